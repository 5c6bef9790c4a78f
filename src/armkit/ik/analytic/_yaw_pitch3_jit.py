"""Numba kernels of the yaw-pitch3 family (the SO-101): one IK call in microseconds, for teleoperation.

The NumPy code of :mod:`.yaw_pitch3` stays the reference (and serves the NumPy back end, the
batches that fail, and every message); these kernels do, for one target at a time, what it
does for the targets that succeed:

* :func:`pitch_branches`: the closed form of :meth:`.yaw_pitch3.YawPitch3.solve` on the ideal
  arm (four branches), each wrapped into the joint limits nearest ``q0``
  (:func:`~armkit.ik.analytic.wrap_to_limits`), polished by Newton steps on (position, pitch)
  of the true model and checked by FK of the true model, as :func:`.yaw_pitch3.solve_pitch`;
* :func:`direction_branches`: :func:`.yaw_pitch3.solve_direction` for a direction that is not
  vertical: the roll candidates, the pitch branches for each, Gauss-Newton on (position,
  pointing direction) over the five joints, the check;
* :func:`teleop` (in :mod:`._yaw_pitch3_teleop`, importable from here too): the whole
  :meth:`armkit.lerobot.RobotKinematics.inverse_kinematics` for such an arm in one call: the
  desired pose, else the position and pointing direction, else the position and the pitch,
  nearest the current joints; a code asks the caller to take the NumPy path when none of these
  succeeds (an honest failure needs the NumPy path's messages).

Geometry: one float64 array per robot, :func:`pack` (indices ``G_*`` below), kept in the robot's
cache by :func:`.yaw_pitch3.fast_geometry`. Imported lazily (``armkit._jit_loader.module``), only
while the Numba back end is in use.
"""

from __future__ import annotations

import math

import numpy as np

from ... import _jit_loader

_jit_loader.install_cache_fallback()  # before the first cache=True: read-only installs cache elsewhere

from numba import njit  # noqa: E402

from ...kinematics import fk
from ._jit import _rint  # noqa: E402  (round half to even, shared with the closed-form kernels)

TWO_PI = 2.0 * math.pi
# ------------------------------------------------------------------ the packed geometry (see pack)
G_BASE_INV = 0          # 12: B'^-1 rows 0-2 (the ideal arm's chain frame)
G_A1, G_A2, G_A3, G_D1, G_LAT0, G_S1, G_UP, G_BETA = 12, 13, 14, 15, 16, 17, 18, 19
G_T = 20                # 3: the tool point in joint 5's DH frame
G_D5, G_A4, G_S4, G_SCALE, G_REACH = 23, 24, 25, 26, 27
G_THETA, G_LOWER, G_UPPER = 28, 33, 38         # 5 each
G_FIXED = 43            # 6 x 12: the true model's fixed transforms, rows 0-2
G_U, G_O, G_ATOOL, G_K1, G_R0 = 115, 118, 121, 124, 127     # 3, 3, 3, 3, 9
G_PAN = 136             # 3: a point on the pan axis (RobotKinematics' pitch)
G_EXACT = 139           # 1.0 when the file's arm is exactly the ideal one (2 polish steps, else 8)
G_SIZE = 140

FRONT = (1.0, 1.0, -1.0, -1.0)   # branch order of yaw_pitch3: (front, e0), (front, e1), (back, e0), (back, e1)
ELBOW = (0, 1, 0, 1)
LATERAL_SLACK = 1e-5             # yaw_pitch3._LATERAL_SLACK
NEAR_VERTICAL = 1e-4             # yaw_pitch3._NEAR_VERTICAL
VERTICAL = 1e-6                  # yaw_pitch3._VERTICAL
STALL_AFTER = 8                  # _polish_direction: a start that no longer falls 4x a step after this many is no solution

# codes of teleop()
POSE, DIRECTION, PITCH, POSITION, NUMPY, LM = 0, 1, 2, 3, -1, -3
# flags of pitch_branches (per target)
ON_AXIS, NOTE = 1, 2


def pack(robot, solver) -> np.ndarray:
    """The geometry array of a 5-joint yaw-pitch3 ``robot`` (its closed form ``solver``), read-only."""
    from .yaw_pitch3 import _geometry

    sf = solver.sf
    g = np.zeros(G_SIZE)
    g[G_BASE_INV:G_BASE_INV + 12] = sf.base_inv[:3].reshape(12)
    g[G_A1], g[G_A2], g[G_A3], g[G_D1] = sf.a[0], sf.a[1], sf.a[2], sf.d[0]
    g[G_LAT0], g[G_S1], g[G_UP], g[G_BETA] = solver.lateral0, solver.s1, solver.up_sign, solver.beta
    g[G_T:G_T + 3] = sf.tool[:3, 3]
    g[G_D5], g[G_A4], g[G_S4] = sf.d[4], sf.a[3], float(sf.twist(3) or 1)
    g[G_SCALE], g[G_REACH] = sf.scale, robot.reach
    g[G_THETA:G_THETA + 5] = sf.theta
    g[G_LOWER:G_LOWER + 5] = robot.lower
    g[G_UPPER:G_UPPER + 5] = robot.upper
    g[G_FIXED:G_FIXED + 72] = np.asarray(robot.chain.fixed)[:, :3, :].reshape(72)
    u, o, a_tool = _geometry(robot)
    g[G_U:G_U + 3], g[G_O:G_O + 3], g[G_ATOOL:G_ATOOL + 3] = u, o, a_tool
    g[G_K1:G_K1 + 3] = robot.chain.fixed[1][:3, 2]
    g[G_R0:G_R0 + 9] = robot.chain.fixed[0][:3, :3].reshape(9)

    g[G_PAN:G_PAN + 3] = fk(robot, np.zeros(robot.n), link=robot.links[1].name)[:3, 3]
    g[G_EXACT] = 1.0 if sf.exact else 0.0
    g.setflags(write=False)
    return g


# ------------------------------------------------------------------ the true model
@njit(cache=True)
def _fk(g, q, X, Z, P):
    """Tool pose ``X`` (3, 4) of ``q`` (5,); ``Z``, ``P`` (5, 3): each joint's axis and origin (world)."""
    for r in range(3):
        for c in range(4):
            X[r, c] = g[G_FIXED + 4 * r + c]
    for k in range(5):
        for r in range(3):
            Z[k, r] = X[r, 2]
            P[k, r] = X[r, 3]
        c, s = math.cos(q[k]), math.sin(q[k])
        for r in range(3):
            x0, x1 = X[r, 0], X[r, 1]
            X[r, 0] = c * x0 + s * x1
            X[r, 1] = c * x1 - s * x0
        f = G_FIXED + 12 * (k + 1)
        for r in range(3):
            a0, a1, a2, a3 = X[r, 0], X[r, 1], X[r, 2], X[r, 3]
            for c2 in range(4):
                X[r, c2] = a0 * g[f + c2] + a1 * g[f + 4 + c2] + a2 * g[f + 8 + c2] + (a3 if c2 == 3 else 0.0)


@njit(cache=True, inline="always")
def _cross(a0, a1, a2, b0, b1, b2):
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


@njit(cache=True)
def _pitch(g, q, X, tx, ty, tz, out):
    """The pitch of pose ``X`` at ``q`` measured towards the point ``t``: ``out = (a, h)`` (6,); returns
    ``(pitch, s, c)`` as :func:`.yaw_pitch3._pitch_parts`."""
    u0, u1, u2 = g[G_U], g[G_U + 1], g[G_U + 2]
    c1, s1 = math.cos(q[0]), math.sin(q[0])
    k1x, k1y, k1z = g[G_K1], g[G_K1 + 1], g[G_K1 + 2]
    lx, ly, lz = c1 * k1x - s1 * k1y, s1 * k1x + c1 * k1y, k1z
    R = G_R0
    kx = g[R] * lx + g[R + 1] * ly + g[R + 2] * lz
    ky = g[R + 3] * lx + g[R + 4] * ly + g[R + 5] * lz
    kz = g[R + 6] * lx + g[R + 7] * ly + g[R + 8] * lz
    hx, hy, hz = _cross(kx, ky, kz, u0, u1, u2)
    nh = math.sqrt(hx * hx + hy * hy + hz * hz)
    hx, hy, hz = hx / nh, hy / nh, hz / nh
    if hx * (tx - g[G_O]) + hy * (ty - g[G_O + 1]) + hz * (tz - g[G_O + 2]) < 0:
        hx, hy, hz = -hx, -hy, -hz
    at0, at1, at2 = g[G_ATOOL], g[G_ATOOL + 1], g[G_ATOOL + 2]
    ax = X[0, 0] * at0 + X[0, 1] * at1 + X[0, 2] * at2
    ay = X[1, 0] * at0 + X[1, 1] * at1 + X[1, 2] * at2
    az = X[2, 0] * at0 + X[2, 1] * at1 + X[2, 2] * at2
    out[0], out[1], out[2], out[3], out[4], out[5] = ax, ay, az, hx, hy, hz
    s = ax * u0 + ay * u1 + az * u2
    c = ax * hx + ay * hy + az * hz
    return math.atan2(s, c), s, c


@njit(cache=True, inline="always")
def _wrap_pi(x):
    return (x + math.pi) % TWO_PI - math.pi


@njit(cache=True, inline="always")
def _inside(g, k, v, margin=1e-12):
    """Joint ``k``'s value ``v`` inside its limits, widened by ``margin``."""
    return g[G_LOWER + k] - margin <= v <= g[G_UPPER + k] + margin


@njit(cache=True)
def _within(g, q, margin=1e-12):
    for k in range(5):
        if not _inside(g, k, q[k], margin):
            return False
    return True


@njit(cache=True, inline="always")
def _wrap_joint(g, k, x, ref):
    """Joint ``k``'s value ``x`` wrapped by whole turns into its limits nearest ``ref``
    (:func:`~armkit.ik.analytic.wrap_to_limits` for one revolute joint)."""
    v = x + TWO_PI * _rint((ref - x) / TWO_PI)
    lo, hi = g[G_LOWER + k] - 1e-12, g[G_UPPER + k] + 1e-12
    if v < lo or v > hi:
        if v < lo:
            cand = v + TWO_PI * np.ceil((lo - v) / TWO_PI)
        else:
            cand = v + TWO_PI * np.floor((hi - v) / TWO_PI)
        if lo <= cand <= hi:
            v = cand
        else:
            v = v + TWO_PI * _rint((0.5 * (lo + hi) - v) / TWO_PI)
    return v


@njit(cache=True)
def _wrap_limits(g, q, q0):
    """:func:`~armkit.ik.analytic.wrap_to_limits` for one revolute configuration, in place."""
    for k in range(5):
        q[k] = _wrap_joint(g, k, q[k], q0[k])


@njit(cache=True)
def _solve4(A, b, n):
    """Solve the symmetric positive definite ``A x = b`` (n <= 5) by Gaussian elimination, in place in ``b``."""
    for i in range(n):
        piv = A[i, i]
        for j in range(i + 1, n):
            f = A[j, i] / piv
            for k in range(i, n):
                A[j, k] -= f * A[i, k]
            b[j] -= f * b[i]
    for i in range(n - 1, -1, -1):
        s = b[i]
        for k in range(i + 1, n):
            s -= A[i, k] * b[k]
        b[i] = s / A[i, i]


@njit(cache=True)
def _normal_step(J, e, A, b, m, n):
    """The Gauss-Newton step of ``J[:m, :n]`` for the error ``e[:m]``: solves ``(J^T J + 1e-14 I) x = J^T e``
    (into ``b[:n]``, with ``A`` as scratch). ``J^T J`` is summed once per pair: ``A[j, i]`` would take the same
    products (each commutes exactly) in the same order, so the mirror is the same number."""
    for i in range(n):
        s = 0.0
        for r in range(m):
            s += J[r, i] * e[r]
        b[i] = s
        s = 0.0
        for r in range(m):
            s += J[r, i] * J[r, i]
        A[i, i] = s + 1e-14
        for j in range(i + 1, n):
            s = 0.0
            for r in range(m):
                s += J[r, i] * J[r, j]
            s += 0.0            # as before: a -0.0 sum stored as +0.0
            A[i, j] = s
            A[j, i] = s
    _solve4(A, b, n)


@njit(cache=True)
def _pitch_error(g, q, p, psi, X, Z, P, ah):
    """FK of ``q``: position error (m) and pitch error (rad) against ``(p, psi)``."""
    _fk(g, q, X, Z, P)
    dx, dy, dz = p[0] - X[0, 3], p[1] - X[1, 3], p[2] - X[2, 3]
    pit, _, _ = _pitch(g, q, X, p[0], p[1], p[2], ah)
    return math.sqrt(dx * dx + dy * dy + dz * dz), abs(_wrap_pi(pit - psi))


@njit(cache=True)
def _polish_pitch(g, q, p, psi, steps, X, Z, P, ah, first=False):
    """Newton steps on (position, pitch) of the true model over joints 1-4, in place (yaw_pitch3._polish).

    ``first``: ``X``, ``Z``, ``P`` and ``ah`` hold the FK and pitch parts of ``q`` already (the caller's
    :func:`_pitch_error` of it), which the first step uses. Returns ``(position error, pitch error)`` of the final
    ``q`` as :func:`_pitch_error` gives them where the steps converged (its FK was the last computed), else
    ``(-1, -1)``: the caller measures."""
    scale = g[G_SCALE]
    J = np.empty((4, 4))
    A = np.empty((4, 4))
    b = np.empty(4)
    e = np.empty(4)
    u0, u1, u2 = g[G_U], g[G_U + 1], g[G_U + 2]
    for it in range(steps):
        if it > 0 or not first:
            _fk(g, q, X, Z, P)
            pit, sa, ca = _pitch(g, q, X, p[0], p[1], p[2], ah)
        else:     # _pitch's last lines, on the parts it left in ah
            sa = ah[0] * u0 + ah[1] * u1 + ah[2] * u2
            ca = ah[0] * ah[3] + ah[1] * ah[4] + ah[2] * ah[5]
            pit = math.atan2(sa, ca)
        e[0], e[1], e[2] = p[0] - X[0, 3], p[1] - X[1, 3], p[2] - X[2, 3]
        e[3] = _wrap_pi(psi - pit)
        if max(abs(e[0]), abs(e[1]), abs(e[2])) <= 1e-15 * scale and abs(e[3]) <= 1e-15:
            return math.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]), abs(_wrap_pi(pit - psi))
        ax, ay, az, hx, hy, hz = ah[0], ah[1], ah[2], ah[3], ah[4], ah[5]
        n2 = sa * sa + ca * ca
        au = _cross(ax, ay, az, u0, u1, u2)
        ahc = _cross(ax, ay, az, hx, hy, hz)
        gx = (ca * au[0] - sa * ahc[0]) / n2
        gy = (ca * au[1] - sa * ahc[1]) / n2
        gz = (ca * au[2] - sa * ahc[2]) / n2
        for j in range(4):
            zx, zy, zz = Z[j, 0], Z[j, 1], Z[j, 2]
            v = _cross(zx, zy, zz, X[0, 3] - P[j, 0], X[1, 3] - P[j, 1], X[2, 3] - P[j, 2])
            J[0, j], J[1, j], J[2, j] = v[0], v[1], v[2]
            J[3, j] = gx * zx + gy * zy + gz * zz
        ha = _cross(hx, hy, hz, ax, ay, az)
        J[3, 0] -= sa * (Z[0, 0] * ha[0] + Z[0, 1] * ha[1] + Z[0, 2] * ha[2]) / n2
        _normal_step(J, e, A, b, 4, 4)
        for j in range(4):
            q[j] += b[j]
    return -1.0, -1.0


@njit(cache=True)
def _closed_form_parts(g, p, psi, pre):
    """What :func:`_closed_form` computes before the roll enters, into ``pre`` (12,): the target in the chain
    frame (x, y, z), its distance from the yaw axis, its yaw, the height term, then per half (front, back) the
    wrist angle and its cosine and sine. Several rolls at one target and pitch share them
    (:func:`direction_branches`)."""
    B = G_BASE_INV
    x = g[B] * p[0] + g[B + 1] * p[1] + g[B + 2] * p[2] + g[B + 3]
    y = g[B + 4] * p[0] + g[B + 5] * p[1] + g[B + 6] * p[2] + g[B + 7]
    z = g[B + 8] * p[0] + g[B + 9] * p[1] + g[B + 10] * p[2] + g[B + 11]
    pre[0], pre[1], pre[2] = x, y, z
    pre[3] = math.hypot(x, y)
    pre[4] = math.atan2(y, x)
    pre[5] = g[G_S1] * (z - g[G_D1])
    sp, cp = math.sin(psi), math.cos(psi)
    for jf in range(2):
        f = FRONT[2 * jf]
        Theta = math.atan2(g[G_UP] * sp, f * cp) - g[G_BETA]
        pre[6 + 3 * jf], pre[7 + 3 * jf], pre[8 + 3 * jf] = Theta, math.cos(Theta), math.sin(Theta)


@njit(cache=True)
def _closed_form(g, p, psi, q0, Q, LAB):
    """The closed form on the ideal arm for position ``p`` and pitch ``psi``, the roll kept at ``q0[4]``: the four
    branches wrapped into the limits nearest ``q0`` into ``Q`` (4, 5), their label indices into ``LAB`` (4,);
    returns :data:`ON_AXIS` / :data:`NOTE` flags (see :func:`pitch_branches`). No FK: the caller checks."""
    pre = np.empty(12)
    _closed_form_parts(g, p, psi, pre)
    return _closed_form_at(g, pre, q0, Q, LAB)


@njit(cache=True)
def _closed_form_at(g, pre, q0, Q, LAB):
    """:func:`_closed_form` from its roll-free parts ``pre`` (:func:`_closed_form_parts`) at the roll ``q0[4]``."""
    scale = g[G_SCALE]
    x, y = pre[0], pre[1]
    phi5 = q0[4] + g[G_THETA + 4]
    c5, s5 = math.cos(phi5), math.sin(phi5)
    t0, t1, t2 = g[G_T], g[G_T + 1], g[G_T + 2]
    vx, vy, vz = c5 * t0 - s5 * t1, s5 * t0 + c5 * t1, t2 + g[G_D5]
    s4 = g[G_S4]
    gx, gy, gz = g[G_A4] + vx, -s4 * vz, s4 * vy
    L = g[G_LAT0] + gz
    rho = pre[3]
    h2 = rho * rho - L * L
    lateral_out = rho < abs(L) - LATERAL_SLACK * scale
    Xf = math.sqrt(max(h2, 0.0))
    flags = 0
    if rho <= 1e-9 * scale and abs(L) <= 1e-9 * scale:
        flags |= ON_AXIS
    yaw = pre[4] if flags & ON_AXIS == 0 else q0[0] + g[G_THETA]
    s1, up_sign = g[G_S1], g[G_UP]
    a1, a2, a3 = g[G_A1], g[G_A2], g[G_A3]
    sg = math.copysign(1.0, a2 * a3)
    Py = pre[5]
    for jf in range(2):            # the front and back halves share everything but the elbow's sign
        f = FRONT[2 * jf]
        Xs = Xf * f
        phi1 = yaw - math.atan2(-s1 * L, Xs)
        Theta, ct, st = pre[6 + 3 * jf], pre[7 + 3 * jf], pre[8 + 3 * jf]
        Px = Xs - a1
        Wx, Wy = Px - (ct * gx - st * gy), Py - (st * gx + ct * gy)
        r2 = Wx * Wx + Wy * Wy
        c = (r2 - a2 * a2 - a3 * a3) / (2.0 * a2 * a3)
        cc = min(max(c, -1.0), 1.0)
        sn0 = math.sqrt((1.0 - cc) * (1.0 + cc))
        ang = math.atan2(Wy, Wx)
        unreach = c > 1.0 or c < -1.0 or lateral_out
        if abs(abs(c) - 1.0) <= 1e-9 and not unreach:
            flags |= NOTE
        fwd = 1.0 if Wx > 0 else (-1.0 if Wx < 0 else f)
        for k in range(2):
            j = 2 * jf + k
            sn = -sn0 if k == 1 else sn0
            th1 = ang - math.atan2(a3 * sn, a2 + a3 * cc)
            th2 = math.atan2(sn, cc)
            qb = Q[j]
            qb[0] = phi1 - g[G_THETA]
            qb[1] = th1 - g[G_THETA + 1]
            qb[2] = th2 - g[G_THETA + 2]
            qb[3] = Theta - th1 - th2 - g[G_THETA + 3]
            qb[4] = phi5 - g[G_THETA + 4]
            _wrap_limits(g, qb, q0)
            e = 1.0 if k == 0 else -1.0
            up = -fwd * up_sign * sg * e > 0
            LAB[j] = 2 * (1 if f > 0 else 0) + (1 if up else 0)
    return flags


@njit(cache=True)
def _polish_branch(g, qb, p, psi, j, tol0, tol1, enforce, margin, mine, X, Z, P, ah, keep):
    """Branch ``j`` of :func:`pitch_branches` from its closed form ``qb`` (5,), in place: checked by FK and, when
    ``mine``, polished as :func:`pitch_branches` says (``keep`` (5,): scratch). Returns ``(dp, dr, within, ok)``."""
    scale = g[G_SCALE]
    steps = 2 if g[G_EXACT] > 0 else 8
    dp, dr = _pitch_error(g, qb, p, psi, X, Z, P, ah)
    wi = _within(g, qb)
    if mine and dp <= 6e-3 * scale and dr <= 6e-3 and (dp > 1e-13 * scale or dr > 1e-13) \
            and _within(g, qb, margin):
        for m in range(5):
            keep[m] = qb[m]
        dpn, drn = _polish_pitch(g, qb, p, psi, steps, X, Z, P, ah, True)
        if dpn < 0.0:
            dpn, drn = _pitch_error(g, qb, p, psi, X, Z, P, ah)
        if dpn / scale + drn < dp / scale + dr:
            dp, dr = dpn, drn
            wi = _within(g, qb)
        else:
            for m in range(5):
                qb[m] = keep[m]
    ok = dp <= tol0 and dr <= tol1 and (wi or not enforce)
    elbow = qb[2] + g[G_THETA + 2]
    if mine and not ok and dp <= 6e-3 * g[G_REACH] and dr <= 6e-3 and abs(math.sin(elbow)) < 1e-2 \
            and _within(g, qb, margin):
        # at a stretched or folded elbow Newton cannot move outwards: start again from the elbow bent by
        # ~sqrt(error), on this branch's side (yaw_pitch3.solve_pitch)
        l2, l3 = abs(g[G_A2]), abs(g[G_A3])
        bend = math.sqrt(2.0 * dp * (l2 + l3) / (l2 * l3)) + 1e-4
        sign = 1.0 if ELBOW[j] == 0 else -1.0
        for m in range(5):
            keep[m] = qb[m]
        qb[2] = (sign * bend if math.cos(elbow) > 0 else math.pi - sign * bend) - g[G_THETA + 2]
        dpn, drn = _polish_pitch(g, qb, p, psi, 16, X, Z, P, ah, False)
        if dpn < 0.0:
            dpn, drn = _pitch_error(g, qb, p, psi, X, Z, P, ah)
        if dpn / scale + drn < dp / scale + dr:
            dp, dr = dpn, drn
            wi = _within(g, qb)
            ok = dp <= tol0 and dr <= tol1 and (wi or not enforce)
        else:
            for m in range(5):
                qb[m] = keep[m]
    return dp, dr, wi, ok


@njit(cache=True)
def pitch_branches(g, p, psi, q0, tol0, tol1, enforce, margin, Q, DP, DR, OK, WI, LAB, polish=15):
    """The four branches for position ``p`` (3,) and pitch ``psi``, the roll kept at ``q0[4]``.

    Fills ``Q`` (4, 5), ``DP``, ``DR`` (4,), ``OK``, ``WI`` (4,) bool and ``LAB`` (4,) (label index of
    ``yaw_pitch3._LABELS``); returns flags: :data:`ON_AXIS` (the NumPy path gives a note),
    :data:`NOTE` (a stretched/folded elbow: the NumPy path gives a note). A failed branch at a
    straight elbow is polished again from a bent one, as the NumPy path does. ``margin``: polish only the
    branches within the limits to this much (rad; ``inf``: every branch near the target, as the NumPy path).
    ``polish``: a bit mask of the branches to polish (bit ``j``: branch ``j``; default all); a branch left
    out is the closed form's, checked by FK, bit for bit what the polish of it starts from.
    """
    X = np.empty((3, 4))
    Z = np.empty((5, 3))
    P = np.empty((5, 3))
    ah = np.empty(6)
    keep = np.empty(5)
    flags = _closed_form(g, p, psi, q0, Q, LAB)
    for j in range(4):
        DP[j], DR[j], WI[j], OK[j] = _polish_branch(g, Q[j], p, psi, j, tol0, tol1, enforce, margin,
                                                    (polish >> j) & 1 == 1, X, Z, P, ah, keep)
    return flags


# ------------------------------------------------------------------ position + pointing direction
@njit(cache=True)
def _dir_cost(g, q, p, d, X, Z, P, e):
    _fk(g, q, X, Z, P)
    w = 1.0 / g[G_REACH]
    for i in range(3):
        e[i] = (p[i] - X[i, 3]) * w
        e[3 + i] = d[i] - X[i, 2]
    s = 0.0
    for i in range(6):
        s += e[i] * e[i]
    return s


@njit(cache=True)
def _polish_direction(g, q, p, d, steps, X, Z, P):
    """Gauss-Newton on (position, tool z along ``d``) over the five joints, in place
    (yaw_pitch3._polish_direction: steps cut to 0.3 rad, halved up to 8 times until the error drops;
    here it also stops where the error falls by less than 4x a step after the eighth: no solution, and
    where the step is below 1e-14 rad: converged)."""
    w = 1.0 / g[G_REACH]
    e = np.empty(6)
    J = np.empty((6, 5))
    A = np.empty((5, 5))
    b = np.empty(5)
    qn = np.empty(5)
    cost = _dir_cost(g, q, p, d, X, Z, P, e)
    for it in range(steps):
        if cost <= 1e-32:
            return
        before = cost
        zx, zy, zz = X[0, 2], X[1, 2], X[2, 2]
        for j in range(5):
            v = _cross(Z[j, 0], Z[j, 1], Z[j, 2], X[0, 3] - P[j, 0], X[1, 3] - P[j, 1], X[2, 3] - P[j, 2])
            J[0, j], J[1, j], J[2, j] = v[0] * w, v[1] * w, v[2] * w
            t = _cross(Z[j, 0], Z[j, 1], Z[j, 2], zx, zy, zz)
            J[3, j], J[4, j], J[5, j] = t[0], t[1], t[2]
        _normal_step(J, e, A, b, 6, 5)
        big = 0.0
        for j in range(5):
            big = max(big, abs(b[j]))
        if big <= 1e-14:
            return   # converged: the step is a few ulps of the joints (the halvings below would only find noise)
        if big > 0.3:
            for j in range(5):
                b[j] *= 0.3 / big
        moved = False
        for _half in range(8):
            for j in range(5):
                qn[j] = q[j] + b[j]
            cn = _dir_cost(g, qn, p, d, X, Z, P, e)
            if cn < cost:
                for j in range(5):
                    q[j] = qn[j]
                cost = cn
                moved = True
                break
            for j in range(5):
                b[j] *= 0.5
        slow = cost > 0.25 * before
        if not moved or (slow and cost > 1e-24 and it >= STALL_AFTER):
            return   # stalled: a start that is no solution (a solution converges quadratically from ~1e-6)
        # X, Z, P, e hold q's values already: the accepted trial was the last _dir_cost call


@njit(cache=True)
def _direction_polished(g, qb, p, d, q0, X, Z, P):
    """:func:`_polish_direction` (40 steps) of ``qb`` in place, wrapped into the limits nearest ``q0``, and its FK
    (left in ``X``): returns (position error, angle (rad) between the tool's z axis and ``d``)."""
    _polish_direction(g, qb, p, d, 40, X, Z, P)
    _wrap_limits(g, qb, q0)
    _fk(g, qb, X, Z, P)
    dx, dy, dz = p[0] - X[0, 3], p[1] - X[1, 3], p[2] - X[2, 3]
    cx, cy, cz = _cross(X[0, 2], X[1, 2], X[2, 2], d[0], d[1], d[2])
    return (math.sqrt(dx * dx + dy * dy + dz * dz),
            math.atan2(math.sqrt(cx * cx + cy * cy + cz * cz), X[0, 2] * d[0] + X[1, 2] * d[1] + X[2, 2] * d[2]))


@njit(cache=True)
def direction_pitch(g, p, d):
    """yaw_pitch3.direction_to_pitch for one point and unit direction: ``(pitch, vertical)``."""
    u0, u1, u2 = g[G_U], g[G_U + 1], g[G_U + 2]
    up = d[0] * u0 + d[1] * u1 + d[2] * u2
    dhx, dhy, dhz = d[0] - up * u0, d[1] - up * u1, d[2] - up * u2
    nh = math.sqrt(dhx * dhx + dhy * dhy + dhz * dhz)
    wx, wy, wz = p[0] - g[G_O], p[1] - g[G_O + 1], p[2] - g[G_O + 2]
    wu = wx * u0 + wy * u1 + wz * u2
    whx, why, whz = wx - wu * u0, wy - wu * u1, wz - wu * u2
    outward = -1.0 if dhx * whx + dhy * why + dhz * whz < 0 else 1.0
    if nh > VERTICAL:
        return math.atan2(up, outward * nh)
    return -0.5 * math.pi if up < 0 else 0.5 * math.pi


@njit(cache=True)
def _pitch_start(g, p, psi, qb, j, tol0, tol1, X, Z, P, ah, keep):
    """Closed-form candidate ``qb`` (branch ``j`` at its roll, :func:`_closed_form`) polished on (position, pitch) in
    place, as :func:`pitch_branches` polishes branch ``j`` alone: the start of the direction polish. Returns its
    position error and whether it is a start (near enough, and inside the limits to 1e-3)."""
    dp, _, _, _ = _polish_branch(g, qb, p, psi, j, tol0, tol1, False, 1e-3, True, X, Z, P, ah, keep)
    return dp, dp <= 6e-3 * g[G_REACH] and _within(g, qb, 1e-3)


@njit(cache=True)
def direction_branches(g, p, d, T, q0, tol0, tol1, Q, DP, DA, OK, LAB, ROLL, STARTED, ANG):
    """Position ``p`` and the tool's z axis along the unit ``d``: the nearest successful configurations.

    ``T`` (4, 4) is the whole desired pose: candidates are polished nearest ``q0`` first, until the
    nearest direction solution is found and no farther candidate can meet ``T`` too (or one does).
    Fills ``Q`` (16, 5) with every candidate (4 rolls x 4 branches), ``DP`` (16,) position error,
    ``DA`` (16,) angle (rad) between the tool's z axis and ``d``, ``OK`` (16,), ``LAB`` (16,) the
    label index, ``ROLL`` (16,) the roll each came from, ``STARTED`` (16,) whether it was polished on
    (position, pitch) (the others are the closed form's, which is cheap: the polish comes when a candidate's
    turn comes, see :func:`_pitch_start`) and ``ANG`` (16,) the angle (rad) between a polished candidate's
    pose and ``T`` (inf for the others). Returns the number of
    candidates tried, or -1 for a direction within 1e-4 of vertical (the NumPy path sweeps the roll there).
    """
    B = G_BASE_INV
    d0x = g[B] * d[0] + g[B + 1] * d[1] + g[B + 2] * d[2]
    d0y = g[B + 4] * d[0] + g[B + 5] * d[1] + g[B + 6] * d[2]
    if math.hypot(d0x, d0y) <= NEAR_VERTICAL:
        return -1
    x = g[B] * p[0] + g[B + 1] * p[1] + g[B + 2] * p[2] + g[B + 3]
    y = g[B + 4] * p[0] + g[B + 5] * p[1] + g[B + 6] * p[2] + g[B + 7]
    psi = direction_pitch(g, p, d)
    t0, t1 = g[G_T], g[G_T + 1]
    A = math.hypot(t0, t1)
    t_ang = math.atan2(t1, t0)
    theta5 = g[G_THETA + 4]
    s4, s1, lat0, scale = g[G_S4], g[G_S1], g[G_LAT0], g[G_SCALE]
    gamma = math.atan2(d0y, d0x)
    rolls = np.empty(4)
    n = 0
    for turn in range(2):
        phi1 = gamma + turn * math.pi
        L = x * s1 * math.sin(phi1) - y * s1 * math.cos(phi1)
        if A < 1e-12 * scale:
            if abs(L - lat0) <= LATERAL_SLACK * scale:
                rolls[n] = q0[4]
                n += 1
            continue
        r = s4 * (L - lat0) / A
        if abs(r) <= 1.0 + 1e-3:
            a = math.asin(min(max(r, -1.0), 1.0))
            rolls[n] = _wrap_pi(a - t_ang - theta5)
            rolls[n + 1] = _wrap_pi(math.pi - a - t_ang - theta5)
            n += 2
    X = np.empty((3, 4))
    Z = np.empty((5, 3))
    P = np.empty((5, 3))
    ah = np.empty(6)
    keep = np.empty(5)
    q0r = np.empty(5)
    dist = np.full(16, np.inf)
    posey = np.zeros(16, dtype=np.bool_)
    near = 6e-3 * g[G_REACH]
    pre = np.empty(12)
    if n > 0:
        _closed_form_parts(g, p, psi, pre)   # the same target and pitch for every roll
    m = 0
    for i in range(n):
        for k in range(5):
            q0r[k] = q0[k]
        q0r[4] = rolls[i]
        # the closed form only (checked by FK): a start is polished (as the NumPy path polishes them all) when
        # its turn comes
        _closed_form_at(g, pre, q0r, Q[m:m + 4], LAB[m:m + 4])
        for j in range(4):
            qb = Q[m]
            DP[m], DA[m], ANG[m], OK[m] = np.inf, np.inf, np.inf, False
            ROLL[m], STARTED[m] = rolls[i], False
            # the polish moves the joints by ~1e-6 rad: a start outside the limits by more cannot succeed (nor is
            # it worth an FK: its DP stays inf, to be measured by whoever polishes it)
            if not _within(g, qb, 1e-3):
                m += 1
                continue
            _fk(g, qb, X, Z, P)
            dx, dy, dz = p[0] - X[0, 3], p[1] - X[1, 3], p[2] - X[2, 3]
            DP[m] = math.sqrt(dx * dx + dy * dy + dz * dz)
            if DP[m] <= near:
                s = 0.0
                for k in range(5):
                    s += (qb[k] - q0[k]) ** 2
                dist[m] = s
                posey[m] = _rotation_angle(X, T) <= 0.1   # the polish turns the roll by up to ~1e-2 near |r| = 1
            m += 1
    # polish nearest first: the first success is the nearest direction solution; after it only a start that may
    # meet the whole pose is still worth polishing, and the first whole-pose success ends the search
    order = np.argsort(dist[:m])
    found = False
    for r in range(m):
        c = order[r]
        if dist[c] == np.inf:
            break
        if found and not posey[c]:
            continue
        STARTED[c] = True
        qb = Q[c]
        DP[c], start = _pitch_start(g, p, psi, qb, c % 4, tol0, tol1, X, Z, P, ah, keep)
        if not start:
            continue
        DP[c], DA[c] = _direction_polished(g, qb, p, d, q0, X, Z, P)
        ANG[c] = _rotation_angle(X, T)
        OK[c] = DP[c] <= tol0 and DA[c] <= tol1 and _within(g, qb)
        if OK[c]:
            if posey[c] and ANG[c] <= tol1:
                break
            found = True
            more = False
            for r2 in range(r + 1, m):
                if posey[order[r2]] and dist[order[r2]] < np.inf:
                    more = True
            if not more:
                break
    return m


@njit(cache=True)
def nearest_direction_rows(g, P, D, Q0, tol0, tol1, q_out, dp_out, da_out, lab_out, solved):
    """``armkit.ik(arm, P, direction=D, q0=Q0)`` for rows ``P``, ``D``, ``Q0`` in one call: per row the successful
    configuration nearest ``Q0[i]``, as :func:`.yaw_pitch3.solve_direction` finds it.

    :func:`direction_branches` polishes the candidates nearest first and stops at the first success; a farther
    candidate may still polish into a nearer solution, and the NumPy path polishes them all: so every other
    candidate near the target is polished here too (on (position, pitch), then on (position, direction)), and
    one whose polish stopped goes on from where it stopped. Writes ``q_out`` (B, 5), ``dp_out``, ``da_out``
    (B,), ``lab_out`` (B,) (label index) and ``solved`` (B,): False for a direction within 1e-4 of vertical,
    no success, or a polish that stalled next to a solution (slow convergence): the NumPy path answers those.
    """
    Q = np.empty((16, 5))
    DP = np.empty(16)
    DA = np.empty(16)
    OK = np.zeros(16, dtype=np.bool_)
    LAB = np.zeros(16, dtype=np.int64)
    ROLL = np.empty(16)
    STARTED = np.zeros(16, dtype=np.bool_)
    ANG = np.empty(16)
    T = np.zeros((4, 4))   # no whole pose wanted: a zero rotation is never met, so no candidate is preferred
    X = np.empty((3, 4))
    Z = np.empty((5, 3))
    Pf = np.empty((5, 3))
    ah = np.empty(6)
    keep = np.empty(5)
    near = 6e-3 * g[G_REACH]   # yaw_pitch3.solve_direction polishes the candidates this close
    for i in range(P.shape[0]):
        solved[i] = False
        p, d, q0 = P[i], D[i], Q0[i]
        m = direction_branches(g, p, d, T, q0, tol0, tol1, Q, DP, DA, OK, LAB, ROLL, STARTED, ANG)
        if m <= 0:
            continue
        psi = direction_pitch(g, p, d)
        for c in range(m):
            if OK[c]:
                continue
            if not STARTED[c]:       # the closed form's: its (position, pitch) polish first, as the NumPy path
                DP[c], _ = _pitch_start(g, p, psi, Q[c], c % 4, tol0, tol1, X, Z, Pf, ah, keep)
            if DP[c] > near:
                continue
            DP[c], DA[c] = _direction_polished(g, Q[c], p, d, q0, X, Z, Pf)
            OK[c] = DP[c] <= tol0 and DA[c] <= tol1 and _within(g, Q[c])
        best = _nearest(Q, OK, m, q0)
        if best < 0:
            continue
        stalled = False
        for c in range(m):
            if not OK[c] and DP[c] <= 1e-2 * near and DA[c] <= 1e-3 and _within(g, Q[c]):
                stalled = True
        if stalled:
            continue
        solved[i] = True
        for k in range(5):
            q_out[i, k] = Q[best, k]
        dp_out[i], da_out[i], lab_out[i] = DP[best], DA[best], LAB[best]


# ------------------------------------------------------------------ helpers (also of ._yaw_pitch3_teleop)
@njit(cache=True)
def _rotation_angle(X, T):
    """The angle (rad) of ``R_X^T R_T``, precise near 0 and pi."""
    def e(i, j):
        return X[0, i] * T[0, j] + X[1, i] * T[1, j] + X[2, i] * T[2, j]

    vx, vy, vz = e(2, 1) - e(1, 2), e(0, 2) - e(2, 0), e(1, 0) - e(0, 1)
    return math.atan2(0.5 * math.sqrt(vx * vx + vy * vy + vz * vz), 0.5 * (e(0, 0) + e(1, 1) + e(2, 2) - 1.0))


@njit(cache=True)
def _nearest(Q, OK, n, q0):
    best, bd = -1, np.inf
    for i in range(n):
        if OK[i]:
            s = 0.0
            for k in range(5):
                s += (Q[i, k] - q0[k]) ** 2
            if s < bd:
                best, bd = i, s
    return best


@njit(cache=True)
def nearest_pitch(g, p, psi, q0, tol0, tol1, enforce, Q, DP, DR, OK, WI, LAB, best):
    """:func:`pitch_branches` for rows ``p`` (B, 3), ``psi`` (B,), ``q0`` (B, 5) into ``(B, 4, ...)``
    outputs, and per row the index of the successful branch nearest ``q0`` in ``best`` (B,)
    (-1: none, or a flag the NumPy path must see)."""
    for i in range(p.shape[0]):
        flags = pitch_branches(g, p[i], psi[i], q0[i], tol0, tol1, enforce, np.inf, Q[i], DP[i], DR[i], OK[i],
                               WI[i], LAB[i])
        best[i] = -1 if flags != 0 else _nearest(Q[i], OK[i], 4, q0[i])


# RobotKinematics in one call: ._yaw_pitch3_teleop (split off this file); its names are read here as before
_TELEOP_NAMES = frozenset(("teleop", "teleop_call", "teleop_ctx", "pack_context", "_position_newton", "INVALID",
                           "C_TOL", "C_INDEX", "C_SIZE"))


def __getattr__(name: str):
    if name in _TELEOP_NAMES:   # imported on first use: that module imports this one
        from . import _yaw_pitch3_teleop

        return getattr(_yaw_pitch3_teleop, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
