"""Numba kernels of the yaw-pitch3 family (the SO-101): :meth:`armkit.lerobot.RobotKinematics.inverse_kinematics`
in one compiled call.

:func:`teleop` tries, nearest the current joints, the desired pose, else the position and pointing
direction, else the position and the pitch (the kernels of :mod:`._yaw_pitch3_jit`); :func:`teleop_call`
adds LeRobot's units (degrees, extra joints) and the input checks, :func:`teleop_ctx` takes its constants
in one array (:func:`pack_context`). Every name here is also importable from :mod:`._yaw_pitch3_jit`
(``_jit_loader.module("ik.analytic._yaw_pitch3_jit").teleop_ctx``), where these kernels used to live.
"""

from __future__ import annotations

import math

import numpy as np

from ... import _jit_loader

_jit_loader.install_cache_fallback()  # before the first cache=True: read-only installs cache elsewhere

from numba import njit  # noqa: E402

from ._yaw_pitch3_jit import (DIRECTION, FRONT, G_A1, G_A2, G_A3, G_A4, G_BASE_INV, G_BETA, G_D1,  # noqa: E402
                              G_D5, G_LAT0, G_LOWER, G_PAN, G_S1, G_S4, G_SCALE, G_SIZE, G_T, G_THETA, G_UP,
                              G_UPPER, LATERAL_SLACK, LM, NUMPY, PITCH, POSE, POSITION, TWO_PI, _closed_form, _cross,
                              _fk, _nearest, _pitch, _polish_branch, _rotation_angle, _solve4, _within, _wrap_pi,
                              _inside, _wrap_joint, direction_branches)

__all__ = ["teleop", "teleop_call", "teleop_ctx", "pack_context", "position_nearest", "position_rows", "position_one",
           "pack_position", "INVALID", "UNREACHABLE", "C_TOL", "C_INDEX", "C_REACH", "C_SIZE", "P_SIZE"]


@njit(cache=True)
def _position_newton(g, q, p, tol0, X, Z, P):
    """The position ``p`` alone from ``q`` (in place, inside the limits): minimum-norm Newton steps on the five
    joints, a joint that would leave its limits held at the limit from then on. Returns the position error (``X``
    holds the FK of ``q``); more than ``tol0`` where it did not converge (the caller takes LM)."""
    J = np.empty((3, 5))
    free = np.ones(5, dtype=np.bool_)
    A = np.empty((3, 3))
    y = np.empty(3)
    e = np.empty(3)
    dp = np.inf
    for _ in range(30):
        _fk(g, q, X, Z, P)
        for i in range(3):
            e[i] = p[i] - X[i, 3]
        dp = math.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2])
        if dp <= 1e-3 * tol0:
            return dp
        for j in range(5):
            v = _cross(Z[j, 0], Z[j, 1], Z[j, 2], X[0, 3] - P[j, 0], X[1, 3] - P[j, 1], X[2, 3] - P[j, 2])
            f = 1.0 if free[j] else 0.0
            J[0, j], J[1, j], J[2, j] = v[0] * f, v[1] * f, v[2] * f
        for i in range(3):
            for k in range(3):
                s = 0.0
                for j in range(5):
                    s += J[i, j] * J[k, j]
                A[i, k] = s + (1e-12 if i == k else 0.0)
            y[i] = e[i]
        _solve4(A, y, 3)
        big = 0.0
        for j in range(5):
            dq = J[0, j] * y[0] + J[1, j] * y[1] + J[2, j] * y[2]
            big = max(big, abs(dq))
            q[j] += dq
            lo, hi = g[G_LOWER + j], g[G_UPPER + j]
            if q[j] < lo or q[j] > hi:
                q[j] = min(max(q[j], lo), hi)
                free[j] = False
        if big > 0.5:
            return np.inf        # a long way from the current joints: LM decides
    _fk(g, q, X, Z, P)
    dx, dy, dz = p[0] - X[0, 3], p[1] - X[1, 3], p[2] - X[2, 3]
    return math.sqrt(dx * dx + dy * dy + dz * dz)


@njit(cache=True)
def teleop(g, T, q0, orient, tol0, tol1, q_out, info):
    """:meth:`armkit.lerobot.RobotKinematics.inverse_kinematics` of a 5-joint yaw-pitch3 arm, in one call.

    ``T`` (4, 4) the desired pose, ``q0`` (5,) the current joints (rad, inside the limits),
    ``orient``: whether orientation counts. Tries, nearest ``q0``: the whole pose (a direction
    solution whose tool x axis matches too), the position and the pointing direction (the
    target's z axis), the position and that direction's pitch (the roll of ``q0``); with
    ``orient`` False the position with the current tool pitch (the roll of ``q0``). Writes the
    answer to ``q_out`` (5,) and ``info`` = (position error, angle to the whole pose, the stage's
    own error (pitch or direction, rad), the label index); returns the stage code
    (:data:`POSE` ... :data:`POSITION`), :data:`LM` (neither the pose, nor the direction, nor the
    pitch is reachable from here: solve the position alone, numerically) or :data:`NUMPY` (a case
    the NumPy path handles: a vertical direction, a target on the yaw axis, a stretched elbow).
    """
    p = np.empty(3)
    d = np.empty(3)
    for i in range(3):
        p[i] = T[i, 3]
        d[i] = T[i, 2]
    X = np.empty((3, 4))
    Z = np.empty((5, 3))
    P = np.empty((5, 3))
    ah = np.empty(6)
    _fk(g, q0, X, Z, P)
    dx, dy, dz = p[0] - X[0, 3], p[1] - X[1, 3], p[2] - X[2, 3]
    dp0 = math.sqrt(dx * dx + dy * dy + dz * dz)
    if orient and dp0 <= tol0 and _within(g, q0):   # holding still: the current joints are the nearest answer
        ang = _rotation_angle(X, T)
        if ang <= tol1:
            for k in range(5):
                q_out[k] = q0[k]
            info[0], info[1], info[2], info[3] = dp0, ang, ang, -1.0
            return POSE
    if orient:
        Qd = np.empty((16, 5))
        DPd = np.empty(16)
        DAd = np.empty(16)
        OKd = np.empty(16, dtype=np.bool_)
        LABd = np.empty(16, dtype=np.int64)
        ROLLd = np.empty(16)
        STd = np.empty(16, dtype=np.bool_)
        ANGd = np.empty(16)
        m = direction_branches(g, p, d, T, q0, tol0, tol1, Qd, DPd, DAd, OKd, LABd, ROLLd, STd, ANGd)
        if m < 0:
            return NUMPY
        if m > 0:
            POKd = np.zeros(16, dtype=np.bool_)
            for i in range(m):
                POKd[i] = OKd[i] and ANGd[i] <= tol1   # ANGd: measured by FK of the polished candidate
            stage = POSE
            best = _nearest(Qd, POKd, m, q0)
            if best < 0:
                stage = DIRECTION
                best = _nearest(Qd, OKd, m, q0)
            if best >= 0:
                for k in range(5):
                    q_out[k] = Qd[best, k]
                info[0], info[1], info[2], info[3] = DPd[best], ANGd[best], DAd[best], float(LABd[best])
                return stage
        # the pitch of the direction, measured as RobotKinematics._pitch_of does (about the pan point)
        ox, oy = p[0] - g[G_PAN], p[1] - g[G_PAN + 1]
        r = math.hypot(ox, oy)
        if r < 1e-9:
            return NUMPY
        psi = math.atan2(d[2], (d[0] * ox + d[1] * oy) / r)
        stage = PITCH
    else:
        _fk(g, q0, X, Z, P)
        psi, _, _ = _pitch(g, q0, X, p[0], p[1], p[2], ah)
        stage = POSITION
    Qp = np.empty((4, 5))
    DPp = np.empty(4)
    DRp = np.empty(4)
    OKp = np.empty(4, dtype=np.bool_)
    WIp = np.empty(4, dtype=np.bool_)
    LABp = np.empty(4, dtype=np.int64)
    # pitch_branches(..., enforce=True, margin=1e-6) but for the FK of a branch outside the limits by more than
    # 1e-6 rad: it is not polished, so it cannot succeed
    flags = _closed_form(g, p, psi, q0, Qp, LABp)
    if flags != 0:
        return NUMPY
    keep = np.empty(5)
    for j in range(4):
        OKp[j] = False
        if _within(g, Qp[j], 1e-6):
            DPp[j], DRp[j], WIp[j], OKp[j] = _polish_branch(g, Qp[j], p, psi, j, tol0, tol1, True, 1e-6, True,
                                                            X, Z, P, ah, keep)
    best = _nearest(Qp, OKp, 4, q0)
    if best < 0:
        # the position alone, from the current joints (the NumPy path's last stage): LM where this fails
        for k in range(5):
            q_out[k] = q0[k]
        dp = _position_newton(g, q_out, p, tol0, X, Z, P)
        if dp > tol0 or not _within(g, q_out):
            return LM
        info[0], info[1], info[2], info[3] = dp, _rotation_angle(X, T), 0.0, -1.0
        return POSITION
    for k in range(5):
        q_out[k] = Qp[best, k]
    _fk(g, q_out, X, Z, P)
    info[0], info[1], info[2], info[3] = DPp[best], _rotation_angle(X, T), DRp[best], float(LABp[best])
    return stage


# ------------------------------------------------------------------ the position alone (armkit.ik(so101, xyz))
UNREACHABLE = -4     # position_nearest: beyond the reach measured from the shoulder (q: the arm stretched towards it)
_SWEEP = 8          # pitches sampled per target (one of them the start's own pitch), then the best refined
_SWEEP_FINE = 128    # pitches sampled where those find no member
_BACK = np.array([0.0, 1e-4, 1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.3, 1.0])   # fractions of the way back to the sample
_LOCAL = np.array([0.0, -0.02, 0.02, -0.05, 0.05, -0.1, 0.1])   # offsets from the start's pitch sampled first
_REFINE = 20         # golden-section steps on the best sample's bracket (1.57 rad * 0.618^20: ~1e-4 rad)


_PRE = 16            # size of _family_parts' output


@njit(cache=True)
def _family_parts(g, p, q0, pre):
    """What the members of the position's 1-D family share (the roll kept at ``q0[4]``), into ``pre``
    (:data:`_PRE`,): the height term, the wrist-to-tool offset in the arm's plane (2), per half (front, back) the
    pan angle and the in-plane distance from the shoulder, cos and sin of ``beta``; then, the same for every
    pitch, the pan joint's value wrapped into its limits nearest ``q0`` per half (2), the roll joint's (1), and
    per half the squared joint distance of these two from ``q0`` (2, ``inf`` where either leaves its limits:
    no member of that half), and the sum of ``q0``'s three pitch joints with their offsets (1, for
    :func:`_lower_bound`). Returns False where the position-only answer is left to LM (a target inside the
    sideways offset, or on the pan axis)."""
    B = G_BASE_INV
    x = g[B] * p[0] + g[B + 1] * p[1] + g[B + 2] * p[2] + g[B + 3]
    y = g[B + 4] * p[0] + g[B + 5] * p[1] + g[B + 6] * p[2] + g[B + 7]
    z = g[B + 8] * p[0] + g[B + 9] * p[1] + g[B + 10] * p[2] + g[B + 11]
    scale = g[G_SCALE]
    phi5 = q0[4] + g[G_THETA + 4]
    c5, s5 = math.cos(phi5), math.sin(phi5)
    t0, t1, t2 = g[G_T], g[G_T + 1], g[G_T + 2]
    vx, vy, vz = c5 * t0 - s5 * t1, s5 * t0 + c5 * t1, t2 + g[G_D5]
    s4 = g[G_S4]
    L = g[G_LAT0] + s4 * vy
    rho = math.hypot(x, y)
    if rho < abs(L) + LATERAL_SLACK * scale or rho <= 1e-9 * scale:
        return False
    Xf = math.sqrt(rho * rho - L * L)
    yaw = math.atan2(y, x)
    s1 = g[G_S1]
    pre[0], pre[1], pre[2] = s1 * (z - g[G_D1]), g[G_A4] + vx, -s4 * vz
    pre[7], pre[8] = math.cos(g[G_BETA]), math.sin(g[G_BETA])
    roll = _wrap_joint(g, 4, q0[4], q0[4])
    pre[11] = roll
    for jf in range(2):
        Xs = Xf * FRONT[2 * jf]
        pre[3 + jf] = yaw - math.atan2(-s1 * L, Xs)
        pre[5 + jf] = Xs - g[G_A1]
        pan = _wrap_joint(g, 0, pre[3 + jf] - g[G_THETA], q0[0])
        pre[9 + jf] = pan
        pre[12 + jf] = (pan - q0[0]) ** 2 if _inside(g, 0, pan) and _inside(g, 4, roll) else np.inf
    pre[14] = (roll - q0[4]) ** 2
    pre[15] = q0[1] + q0[2] + q0[3] + g[G_THETA + 1] + g[G_THETA + 2] + g[G_THETA + 3]
    return True


@njit(cache=True, inline="always")
def _half(g, pre, psi, sp, cp, jf):
    """The wrist of half ``jf`` (0 front, 1 back) of the family at pitch ``psi`` (``sp``, ``cp``: its sine and
    cosine; the closed form of :func:`._yaw_pitch3_jit._closed_form_at` on the ideal arm):
    ``(reached, Theta, ang, d1, t2, Wx)``, the tool's in-plane angle (``up * psi - beta`` front,
    ``pi - up * psi - beta`` back), the wrist's direction and the two-link angles both elbows share; ``reached``
    False where the wrist is out of reach at ``psi``."""
    a2, a3 = g[G_A2], g[G_A3]
    up, cb, sb = g[G_UP], pre[7], pre[8]
    f = FRONT[2 * jf]
    Theta = (up * psi if jf == 0 else math.pi - up * psi) - g[G_BETA]
    ct, st = f * cp * cb + up * sp * sb, up * sp * cb - f * cp * sb
    Wx, Wy = pre[5 + jf] - (ct * pre[1] - st * pre[2]), pre[0] - (st * pre[1] + ct * pre[2])
    c = (Wx * Wx + Wy * Wy - a2 * a2 - a3 * a3) / (2.0 * a2 * a3)
    if c > 1.0 or c < -1.0:
        return False, Theta, 0.0, 0.0, 0.0, Wx
    sn0 = math.sqrt((1.0 - c) * (1.0 + c))
    return True, Theta, math.atan2(Wy, Wx), math.atan2(a3 * sn0, a2 + a3 * c), math.atan2(sn0, c), Wx


@njit(cache=True, inline="always")
def _lower_bound(g, pre, psi, jf):
    """A lower bound of the squared joint distance from ``q0`` of every member of half ``jf`` at pitch ``psi``:
    the pan and roll terms (the same for all, :func:`_family_parts`) plus ``delta**2 / 3``, where the three pitch
    joints' sum differs from ``q0``'s by ``delta`` at least (it equals the tool's in-plane angle less the joints'
    offsets, modulo 2 pi: ``pre[15]`` holds ``q0``'s side of it), and ``a**2 + b**2 + c**2 >= (a + b + c)**2 / 3``.
    Shrunk by 1e-9 (relative) for rounding: a member it rules out is farther than the bound by more than that."""
    Theta = (g[G_UP] * psi if jf == 0 else math.pi - g[G_UP] * psi) - g[G_BETA]
    delta = _wrap_pi(Theta - pre[15])
    return (pre[12 + jf] + pre[14] + delta * delta / 3.0) * (1.0 - 1e-9)


@njit(cache=True, inline="always")
def _branch(g, pre, q0, jf, e, Theta, ang, d1, t2):
    """Elbow ``e`` (+-1) of half ``jf`` from :func:`_half`'s angles, wrapped into the limits nearest ``q0``:
    ``(D, q1, q2, q3)``, ``D`` the squared joint distance from ``q0`` (``inf`` where a joint leaves its limits;
    the pan and roll joints are :func:`_family_parts`')."""
    th1, th2 = ang - e * d1, e * t2
    v2 = _wrap_joint(g, 2, th2 - g[G_THETA + 2], q0[2])     # the elbow first: the joint most often out
    if not _inside(g, 2, v2):
        return np.inf, 0.0, v2, 0.0
    v1 = _wrap_joint(g, 1, th1 - g[G_THETA + 1], q0[1])
    if not _inside(g, 1, v1):
        return np.inf, v1, v2, 0.0
    v3 = _wrap_joint(g, 3, Theta - th1 - th2 - g[G_THETA + 3], q0[3])
    if not _inside(g, 3, v3):
        return np.inf, v1, v2, v3
    s = pre[12 + jf]
    s += (v1 - q0[1]) ** 2
    s += (v2 - q0[2]) ** 2
    s += (v3 - q0[3]) ** 2
    return s + pre[14], v1, v2, v3


@njit(cache=True)
def _distance(g, pre, psi, q0, j):
    """Branch ``j``'s member at pitch ``psi``: its squared joint distance from ``q0`` alone (:func:`_members`'
    ``D[j]``, the same number)."""
    jf = j // 2
    if pre[12 + jf] == np.inf:
        return np.inf
    reached, Theta, ang, d1, t2, _ = _half(g, pre, psi, math.sin(psi), math.cos(psi), jf)
    if not reached:
        return np.inf
    return _branch(g, pre, q0, jf, 1.0 if j % 2 == 0 else -1.0, Theta, ang, d1, t2)[0]


@njit(cache=True)
def _members(g, pre, psi, q0, only, Q, LAB, D, bound=np.inf):
    """The members of the family at pitch ``psi`` (the closed form of :func:`._yaw_pitch3_jit._closed_form_at` on
    the ideal arm, wrapped into the limits nearest ``q0``): all four (``only`` -1) or branch ``only`` alone.
    ``D`` (4,): each one's squared joint distance from ``q0``, ``inf`` where the wrist is out of reach at
    ``psi`` or a joint leaves its limits; ``Q`` (4, 5) and ``LAB`` (4,) hold the members of finite ``D`` (the
    rows of the others are left part-written). The second elbow mirrors the first: the pitch's sine and cosine,
    then four transcendental calls per half; none for a half whose pan joint (the same at every pitch) is outside
    its limits, nor for a half
    whose members cannot be nearer ``q0`` than ``bound`` (:func:`_lower_bound`; their ``D``: ``inf``)."""
    sg = math.copysign(1.0, g[G_A2] * g[G_A3])
    up = g[G_UP]
    sp, cp = math.sin(psi), math.cos(psi)
    for jf in range(2):
        if only >= 0 and only // 2 != jf:
            continue
        if pre[12 + jf] == np.inf:   # the pan (or the roll) outside its limits: no member of this half
            D[2 * jf] = D[2 * jf + 1] = np.inf
            continue
        if bound < np.inf and _lower_bound(g, pre, psi, jf) >= bound:   # none nearer than the best so far
            D[2 * jf] = D[2 * jf + 1] = np.inf
            continue
        reached, Theta, ang, d1, t2, Wx = _half(g, pre, psi, sp, cp, jf)
        if not reached:              # the wrist out of reach at this pitch
            D[2 * jf] = D[2 * jf + 1] = np.inf
            continue
        f = FRONT[2 * jf]
        fwd = 1.0 if Wx > 0 else (-1.0 if Wx < 0 else f)
        for k in range(2):
            j = 2 * jf + k
            if only >= 0 and only != j:
                continue
            e = 1.0 if k == 0 else -1.0
            D[j], v1, v2, v3 = _branch(g, pre, q0, jf, e, Theta, ang, d1, t2)
            if D[j] < np.inf:
                qb = Q[j]
                qb[0], qb[1], qb[2], qb[3], qb[4] = pre[9 + jf], v1, v2, v3, pre[11]
                LAB[j] = 2 * (1 if f > 0 else 0) + (1 if -fwd * up * sg * e > 0 else 0)


@njit(cache=True)
def _stretch(g, q, p, X, Z, P):
    """Levenberg-Marquardt steps on the position alone from ``q`` (in place, held inside the limits; a step that
    does not bring the tool closer is undone and the damping raised): the configuration closest to an unreachable
    ``p`` (the arm stretched towards it) that these steps find. Returns its position error."""
    J = np.empty((3, 5))
    A = np.empty((3, 3))
    y = np.empty(3)
    old = np.empty(5)
    s2 = g[G_SCALE] * g[G_SCALE]
    lam = 1e-3 * s2
    _fk(g, q, X, Z, P)
    ex, ey, ez = p[0] - X[0, 3], p[1] - X[1, 3], p[2] - X[2, 3]
    dp = math.sqrt(ex * ex + ey * ey + ez * ez)
    for _ in range(40):
        for j in range(5):
            v = _cross(Z[j, 0], Z[j, 1], Z[j, 2], X[0, 3] - P[j, 0], X[1, 3] - P[j, 1], X[2, 3] - P[j, 2])
            J[0, j], J[1, j], J[2, j] = v[0], v[1], v[2]
        for i in range(3):
            for k in range(3):
                s = 0.0
                for j in range(5):
                    s += J[i, j] * J[k, j]
                A[i, k] = s + (lam if i == k else 0.0)
        y[0], y[1], y[2] = ex, ey, ez
        _solve4(A, y, 3)
        for j in range(5):
            old[j] = q[j]
            q[j] = min(max(q[j] + J[0, j] * y[0] + J[1, j] * y[1] + J[2, j] * y[2], g[G_LOWER + j]), g[G_UPPER + j])
        _fk(g, q, X, Z, P)
        nx, ny, nz = p[0] - X[0, 3], p[1] - X[1, 3], p[2] - X[2, 3]
        dn = math.sqrt(nx * nx + ny * ny + nz * nz)
        if dn < dp:
            gain = dp - dn
            ex, ey, ez, dp = nx, ny, nz, dn
            lam = max(lam * 0.3, 1e-9 * s2)
            if gain <= 1e-12 * g[G_SCALE]:
                break
        else:
            for j in range(5):
                q[j] = old[j]
            lam *= 10.0
            if lam > 1e3 * s2:
                break
            _fk(g, q, X, Z, P)
    return dp


@njit(cache=True)
def _newton_answer(g, qn, p, dn, q_out, info, X, Z, P):
    """:func:`position_nearest`'s answer by the Newton steps ``qn`` (label index 4: ``"newton"``)."""
    _fk(g, qn, X, Z, P)
    dx, dy, dz = p[0] - X[0, 3], p[1] - X[1, 3], p[2] - X[2, 3]
    for k in range(5):
        q_out[k] = qn[k]
    info[0], info[1], info[2], info[3] = math.sqrt(dx * dx + dy * dy + dz * dz), np.nan, dn, 4.0
    return POSITION


@njit(cache=True)
def position_nearest(g, p, q0, tol0, tol1, reach, q_out, info):
    """``armkit.ik(arm, p, q0)`` of a 5-joint yaw-pitch3 arm (position only) in closed form: the member of the
    position's 1-D family of solutions (the tool pitch free, the roll kept at ``q0[4]``) nearest ``q0``.

    The pitch is sampled at :data:`_SWEEP` values starting at ``q0``'s own pitch (:data:`_SWEEP_FINE` where
    none has a member), each of the four branches
    scored by its squared joint distance from ``q0`` (inside the limits), the best refined by golden-section
    steps, then polished on the true model (Newton on position and pitch) and checked by FK. ``reach``: the
    reach measured from the shoulder (:func:`.yaw_pitch3.shoulder_reach`). Writes ``q_out`` (5,) and ``info``
    (4,) = (position error, pitch, squared distance from ``q0``, label index); returns :data:`POSITION`,
    :data:`UNREACHABLE` (beyond ``reach`` from the shoulder: ``q_out`` is the arm stretched towards ``p``,
    ``info[1]`` the distance from the shoulder) or :data:`LM` (not settled here: LM answers).
    """
    X = np.empty((3, 4))
    Z = np.empty((5, 3))
    P = np.empty((5, 3))
    B = G_BASE_INV
    x = g[B] * p[0] + g[B + 1] * p[1] + g[B + 2] * p[2] + g[B + 3]
    y = g[B + 4] * p[0] + g[B + 5] * p[1] + g[B + 6] * p[2] + g[B + 7]
    z = g[B + 8] * p[0] + g[B + 9] * p[1] + g[B + 10] * p[2] + g[B + 11]
    dist = math.hypot(math.hypot(x, y) - abs(g[G_A1]), z - g[G_D1])
    if dist > reach * (1.0 + 1e-9) + tol0:
        for k in range(5):
            q_out[k] = q0[k]
        info[0], info[1], info[2], info[3] = _stretch(g, q_out, p, X, Z, P), dist, 0.0, -1.0
        return UNREACHABLE
    qn = np.empty(5)              # minimum-norm Newton steps from q0 (all five joints, as LM moves them): the
    for k in range(5):            # nearest solution where q0 lies close to the family; the pitch search covers
        qn[k] = q0[k]             # the rest, and the nearer of the two is the answer
    dn = np.inf
    if _within(g, qn) and _position_newton(g, qn, p, tol0, X, Z, P) <= tol0 and _within(g, qn):
        dn = 0.0
        for k in range(5):
            dn += (qn[k] - q0[k]) ** 2
    pre = np.empty(_PRE)
    if not _family_parts(g, p, q0, pre):
        if dn < np.inf:
            return _newton_answer(g, qn, p, dn, q_out, info, X, Z, P)
        return LM
    ah = np.empty(6)
    _fk(g, q0, X, Z, P)
    psi0, _, _ = _pitch(g, q0, X, p[0], p[1], p[2], ah)
    Q = np.empty((4, 5))
    LAB = np.empty(4, dtype=np.int64)
    D = np.empty(4)
    every = np.int64(-1)   # "all four branches" as a typed value, not a constant: a constant argument compiles
    bd, bj, bpsi, spsi, h = np.inf, every, psi0, psi0, 0.0   # its own signature of _members and _distance
    for i in range(_LOCAL.shape[0]):      # near the start's pitch first: windows there can be narrow (a joint
        psi = psi0 + _LOCAL[i]            # near its limit, a wrist near the edge of reach at that pitch)
        _members(g, pre, psi, q0, every, Q, LAB, D, bd)
        for j in range(4):
            if D[j] < bd:
                bd, bj, bpsi, spsi, h = D[j], j, psi, psi, 0.05
    for n in (_SWEEP, _SWEEP_FINE):      # a finer sweep where no sample has a member
        for i in range(1, n):
            psi = psi0 + TWO_PI / n * (i if i <= n // 2 else i - n)
            _members(g, pre, psi, q0, every, Q, LAB, D, bd)
            for j in range(4):
                if D[j] < bd:
                    bd, bj, bpsi, spsi, h = D[j], j, psi, psi, TWO_PI / n
        if bj >= 0:
            break
    if bj < 0:
        if dn < np.inf:
            return _newton_answer(g, qn, p, dn, q_out, info, X, Z, P)
        return LM            # no member at the sampled pitches (a target at the edge of reach): LM decides
    if bd > 0.0:             # golden section on the best branch about the best sample (outside: inf)
        r = 0.5 * (math.sqrt(5.0) - 1.0)
        a, b = bpsi - h, bpsi + h
        c1, c2 = b - r * (b - a), a + r * (b - a)
        f1 = _distance(g, pre, c1, q0, bj)
        f2 = _distance(g, pre, c2, q0, bj)
        for _ in range(_REFINE):
            if f1 <= f2:
                b, c2, f2 = c2, c1, f1
                c1 = b - r * (b - a)
                f1 = _distance(g, pre, c1, q0, bj)
            else:
                a, c1, f1 = c1, c2, f2
                c2 = a + r * (b - a)
                f2 = _distance(g, pre, c2, q0, bj)
            if f1 < bd:
                bd, bpsi = f1, c1
            if f2 < bd:
                bd, bpsi = f2, c2
    keep = np.empty(5)
    qb = Q[bj]
    bpsi0 = bpsi
    ok = False
    dp = 0.0
    for t in range(_BACK.shape[0]):   # the best member, else nearer the sample's pitch (a member at a joint limit
        bpsi = bpsi0 + (spsi - bpsi0) * _BACK[t]   # or at the edge of reach, which the true model's polish would
        _members(g, pre, bpsi, q0, bj, Q, LAB, D, np.inf)  # push past)
        if D[bj] < np.inf:
            dp, _, wi, ok = _polish_branch(g, qb, p, bpsi, bj, tol0, tol1, True, 1e-6, True, X, Z, P, ah, keep)
            if ok:
                break
    s = 0.0
    for k in range(5):
        s += (qb[k] - q0[k]) ** 2
    if not ok or dn < s:
        if dn < np.inf:
            return _newton_answer(g, qn, p, dn, q_out, info, X, Z, P)
        return LM
    for k in range(5):
        q_out[k] = qb[k]
    info[0], info[1], info[2], info[3] = dp, bpsi, s, float(LAB[bj])
    return POSITION


@njit(cache=True)
def position_rows(g, p, q0, tol0, tol1, reach, q_out, info, code):
    """:func:`position_nearest` for rows ``p`` (B, 3), ``q0`` (B, 5) into ``q_out`` (B, 5), ``info`` (B, 4),
    ``code`` (B,)."""
    for i in range(p.shape[0]):
        code[i] = position_nearest(g, p[i], q0[i], tol0, tol1, reach, q_out[i], info[i])


INVALID = -2

P_TOL = G_SIZE          # context of position_one: the geometry, the tolerances (2), the reach from the shoulder
P_REACH = G_SIZE + 2
P_SIZE = G_SIZE + 3


def pack_position(g: np.ndarray, tol: tuple[float, float], reach: float) -> np.ndarray:
    """The one array :func:`position_one` reads: geometry ``g`` (:func:`._yaw_pitch3_jit.pack`), ``tol`` and the
    reach measured from the shoulder (:func:`.yaw_pitch3.shoulder_reach`)."""
    ctx = np.empty(P_SIZE)
    ctx[:G_SIZE] = g
    ctx[P_TOL], ctx[P_TOL + 1] = tol
    ctx[P_REACH] = reach
    ctx.setflags(write=False)
    return ctx


@njit(cache=True)
def position_one(ctx, p, q0, out):
    """:func:`position_nearest` for one target ``p`` (3,) from ``q0`` (5,) with its constants in one array
    (:func:`pack_position`): ``out`` (9,) = ``q_out`` (5,), then ``info`` (4,). Returns its code, or
    :data:`INVALID` for input the general path must check (a coordinate of ``p`` not finite; a value of ``q0``
    NaN or beyond 1e6 rad, which :func:`armkit.ik` takes modulo 2 pi)."""
    for i in range(3):
        if not math.isfinite(p[i]):
            return INVALID
    for k in range(5):
        if not abs(q0[k]) <= 1e6:
            return INVALID
    return position_nearest(ctx, p, q0, ctx[P_TOL], ctx[P_TOL + 1], ctx[P_REACH], out[:5], out[5:])


@njit(cache=True)
def teleop_call(g, cur_deg, index, T, orient, tol0, tol1, out_deg, info):
    """:func:`teleop` from LeRobot's units: ``cur_deg`` (k,) the current joint values in degrees (the
    chain's at ``index`` (5,)), ``T`` (4, 4) the desired pose; writes ``out_deg`` (k,) (``cur_deg`` with
    the chain's joints replaced) and ``info`` (9,): :func:`teleop`'s four values, then ``q`` (5,) rad.

    Returns :func:`teleop`'s code, or :data:`INVALID` for input the NumPy path must reject with its
    message (NaN or infinite values; ``T`` not a rigid transform to 1e-6, or its last row not
    exactly 0, 0, 0, 1).
    """
    for i in range(cur_deg.shape[0]):
        if not math.isfinite(cur_deg[i]):
            return INVALID
    for i in range(4):
        for j in range(4):
            if not math.isfinite(T[i, j]):
                return INVALID
    if T[3, 0] != 0.0 or T[3, 1] != 0.0 or T[3, 2] != 0.0 or T[3, 3] != 1.0:
        return INVALID
    for i in range(3):
        for j in range(3):
            s = T[0, i] * T[0, j] + T[1, i] * T[1, j] + T[2, i] * T[2, j]
            if abs(s - (1.0 if i == j else 0.0)) > 1e-6:
                return INVALID
    det = (T[0, 0] * (T[1, 1] * T[2, 2] - T[1, 2] * T[2, 1]) - T[0, 1] * (T[1, 0] * T[2, 2] - T[1, 2] * T[2, 0])
           + T[0, 2] * (T[1, 0] * T[2, 1] - T[1, 1] * T[2, 0]))
    if abs(det - 1.0) > 1e-6:
        return INVALID
    q0 = np.empty(5)
    for k in range(5):
        q0[k] = min(max(math.radians(cur_deg[index[k]]), g[G_LOWER + k]), g[G_UPPER + k])
    q = np.empty(5)
    code = teleop(g, T, q0, orient, tol0, tol1, q, info)
    if code >= 0:
        for i in range(cur_deg.shape[0]):
            out_deg[i] = cur_deg[i]
        for k in range(5):
            if q[k] != math.radians(cur_deg[index[k]]):   # a joint left where it was keeps its value exactly
                out_deg[index[k]] = math.degrees(q[k])
            info[4 + k] = q[k]
    return code


C_TOL = G_SIZE          # context of teleop_ctx: the geometry, the tolerances (2), the chain's indices (5), the reach
C_INDEX = G_SIZE + 2
C_REACH = G_SIZE + 7
C_SIZE = G_SIZE + 8


def pack_context(g: np.ndarray, tol: tuple[float, float], index: np.ndarray, reach: float = math.inf) -> np.ndarray:
    """The one array :func:`teleop_ctx` reads: geometry ``g`` (:func:`pack`), ``tol``, the chain's ``index`` (5,)
    and the reach measured from the shoulder (:func:`.yaw_pitch3.shoulder_reach`; inf: not checked)."""
    ctx = np.empty(C_SIZE)
    ctx[:G_SIZE] = g
    ctx[C_TOL], ctx[C_TOL + 1] = tol
    ctx[C_INDEX:C_INDEX + 5] = index
    ctx[C_REACH] = reach
    ctx.setflags(write=False)
    return ctx


@njit(cache=True)
def teleop_ctx(ctx, cur_deg, T, orient, out_deg, info):
    """:func:`teleop_call` with its constant arguments in one array (:func:`pack_context`): fewer arguments
    for the dispatcher to check on every call of ``RobotKinematics.inverse_kinematics``. A desired position
    beyond the reach from the shoulder returns :data:`LM` at once (no stage can meet it; the caller's
    position stage reports the failure)."""
    B = G_BASE_INV
    x = ctx[B] * T[0, 3] + ctx[B + 1] * T[1, 3] + ctx[B + 2] * T[2, 3] + ctx[B + 3]
    y = ctx[B + 4] * T[0, 3] + ctx[B + 5] * T[1, 3] + ctx[B + 6] * T[2, 3] + ctx[B + 7]
    z = ctx[B + 8] * T[0, 3] + ctx[B + 9] * T[1, 3] + ctx[B + 10] * T[2, 3] + ctx[B + 11]
    if math.hypot(math.hypot(x, y) - abs(ctx[G_A1]), z - ctx[G_D1]) > ctx[C_REACH] * (1.0 + 1e-9) + ctx[C_TOL]:
        ok = True           # (NaN compares False above; teleop_call rejects it)
        for i in range(cur_deg.shape[0]):
            ok = ok and math.isfinite(cur_deg[i])
        if ok and T[3, 0] == 0.0 and T[3, 1] == 0.0 and T[3, 2] == 0.0 and T[3, 3] == 1.0:
            return LM
    index = np.empty(5, dtype=np.int64)
    for k in range(5):
        index[k] = int(ctx[C_INDEX + k])
    return teleop_call(ctx, cur_deg, index, T, orient, ctx[C_TOL], ctx[C_TOL + 1], out_deg, info)


# the kernels above inline helpers of these files: their cache follows them
_jit_loader.forget_stale_cache(globals(), ("ik/analytic/_yaw_pitch3_jit.py", "ik/analytic/_jit.py"))
