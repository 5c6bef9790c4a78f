r"""Yaw + three parallel pitch axes (+ roll): the SO-101 / SO-100 family, position and tool pitch.

Five joints (or four without the roll) cannot reach an arbitrary pose. What such an arm
controls in closed form is the tool position **and the tool pitch**: the angle of the
approach axis in the arm's vertical plane. The roll joint (when there is one) keeps the
value of ``q0`` (so pass the roll you want in ``q0``).

Geometry (standard DH after :func:`~._common.standard_form`, on the ideal arm): joint 1
turns about the yaw axis ``z0`` with twist +-90 deg (sign ``s1``), joints 2, 3 and 4 are
parallel (``alpha_2 = alpha_3 = 0``), and for five joints the roll axis is perpendicular to
them (``alpha_4 = +-90 deg``). In the plane of joint 2's frame (``x1`` outward, ``y1 = s1
z0``) the tool point is

.. math::

    P = a_2 e(\varphi_2) + a_3 e(\varphi_2 + \varphi_3) + R(\Theta) g,\qquad
    \Theta = \varphi_2 + \varphi_3 + \varphi_4,

with ``g`` the in-plane tool offset in joint 4's frame (it depends on the roll angle) and the
sideways (lateral) offset ``L = d_2 + d_3 + d_4 + g_z``. The approach axis (the roll axis,
pointing from the wrist to the tool; for four joints the tool's z axis) makes the angle
``Phi_a = Theta + beta`` with ``x1``. Then, as for the yaw-pitch-pitch family,
``a_1 + X = +-sqrt(rho^2 - L^2)`` (front/back),
``phi_1 = atan2(p_y, p_x) - atan2(-s1 L, a_1 + X)``, ``Y = s1 (p_z - d_1)``; the pitch fixes
``Phi_a``, the wrist point ``W = P - R(Theta) g`` is a planar two-link problem
(:func:`~._common.two_link`) for ``phi_2, phi_3``, and ``phi_4 = Theta - phi_2 - phi_3``.

The pitch convention
--------------------
``pitch`` is the angle of the approach axis ``a`` in the arm's vertical plane (the plane
perpendicular to the first pitch axis), ``atan2(a . u, a . h)``: ``u`` is the yaw axis
pointing up (the direction with a non-negative world z), ``h`` the plane's horizontal
direction pointing *outward*, the way the target lies from the foot of the plane on the
yaw axis. ``0`` = pointing horizontally outward, ``+90 deg`` = straight up, ``-90 deg`` =
straight down, ``+-180 deg`` = horizontally back towards the base. On a real file whose
roll axis is not exactly perpendicular to the pitch axes (rounding), the part of ``a``
along the pitch axis is left out, so straight down stays reachable. The same pitch means
the same pointing direction on the front and the back branches (exactly so when the arm
has no sideways offset), and :func:`pitch_of` measures it on any configuration.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ...model.robot import Robot
from ..result import IKResult, default_tolerance, verify
from ._common import (LENGTH_TOL, Array, Raw, StandardForm, add_messages, elbow_edge, elbow_up, forward_sign,
                      keep_better, out_of_reach, two_link)

__all__ = ["YawPitch3", "pitch_of", "solve_pitch"]

_LABELS = np.array(["back/elbow-down", "back/elbow-up", "front/elbow-down", "front/elbow-up"], dtype=object)
_FRONT = np.array([1.0, 1.0, -1.0, -1.0])    # branch order: (front, e0), (front, e1), (back, e0), (back, e1)
_ELBOW = np.array([0, 1, 0, 1])
_REASON_TEXT = np.array(["converged", "unreachable", "joint limits"])
_APPROACH_TOL = 1e-9    # four joints: the tool's z axis must lie in the arm's plane this closely


def _cross(a: Array, b: Array) -> Array:
    """``np.cross`` of (..., 3) arrays without its axis handling (a third of the single-call time)."""
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    out[..., 0] = a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1]
    out[..., 1] = a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2]
    out[..., 2] = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    return out


def _rot(ang: Array, v: tuple[Array, Array]) -> tuple[Array, Array]:
    c, s = np.cos(ang), np.sin(ang)
    return c * v[0] - s * v[1], s * v[0] + c * v[1]


class YawPitch3:
    """Closed form for a yaw joint, three parallel pitch joints and an optional roll joint.

    The target is a position and the tool pitch (see the module docstring): :meth:`solve`
    takes ``(B, 4)`` rows ``(x, y, z, pitch)``. Reached through ``armkit.ik(robot, xyz,
    pitch=...)`` and ``armkit.ik_all(robot, xyz, pitch=...)``.
    """

    family = "yaw-pitch3"
    branch_labels = tuple(_LABELS)
    geometry = None         # solved by NumPy only (a few targets at a time: the SO-101's teleoperation)
    pose_only = True        # a position alone leaves the pitch free: LM (or give pitch=)
    target_kind = "pitch"   # the closed form needs pitch= (see armkit.ik.api)
    m = 4

    def __init__(self, sf: StandardForm, robot: Robot, beta: float, g_fixed: Array | None):
        self.sf, self.unit = sf, robot.unit
        self.yaw_name = robot.joint_names[0]
        self.roll = sf.n == 5
        self.s1 = int(sf.twist(0) or 1)
        self.beta = beta                     # angle of the approach axis in joint 4's frame
        self.g_fixed = g_fixed               # four joints: the tool point in joint 4's frame
        self.lateral0 = float(sf.d[1] + sf.d[2] + sf.d[3])
        # "up": the yaw axis' direction with a non-negative world z (its own direction if horizontal)
        zw = float(sf.base[2, 2])
        self.s_up = -1 if zw < 0 else 1
        self.up_sign = self.s1 * self.s_up   # the plane's y1 axis is s1 z0 = s1 s_up up

    @classmethod
    def detect(cls, sf: StandardForm, robot) -> "YawPitch3 | None":
        if sf.n not in (4, 5) or sf.twist(0) not in (1, -1) or sf.twist(1) != 0 or sf.twist(2) != 0:
            return None
        if sf.is_zero(sf.a[1]) or sf.is_zero(sf.a[2]):
            return None
        if sf.n == 5:
            s4 = sf.twist(3)
            if s4 not in (1, -1):
                return None
            # the roll axis in joint 4's frame is Rx(alpha_4) z = (0, -s4, 0); point it towards the tool's z
            sigma = -1.0 if sf.tool[2, 2] < 0 else 1.0
            return cls(sf, robot, math.atan2(-sigma * s4, 0.0), None)
        z = sf.tool[:3, 2]
        if abs(z[2]) > _APPROACH_TOL:   # the tool's z axis leaves the arm's plane: no pitch to control
            return None
        return cls(sf, robot, math.atan2(z[1], z[0]), sf.tool[:3, 3].copy())

    def _tool_point(self, phi5: Array) -> tuple[Array, Array, Array]:
        """The tool point in joint 4's frame ``(gx, gy, gz)`` for roll DH angles ``phi5`` ``(B,)``."""
        if self.g_fixed is not None:
            g = self.g_fixed
            B = len(phi5)
            return np.full(B, g[0]), np.full(B, g[1]), np.full(B, g[2])
        sf = self.sf
        t = sf.tool[:3, 3]
        c, s = np.cos(phi5), np.sin(phi5)
        vx, vy, vz = c * t[0] - s * t[1], s * t[0] + c * t[1], t[2] + sf.d[4]   # Rz(phi5) t + d5 z
        s4 = float(sf.twist(3) or 1)
        # Tx(a4) Rx(s4 90 deg): (x, y, z) -> (a4 + x, -s4 z, s4 y)
        B = len(phi5)
        return sf.a[3] + vx, np.full(B, -s4 * vz), s4 * vy

    def solve(self, target: Array, q0phi: Array) -> Raw:
        """Every branch for rows ``(x, y, z, pitch)`` ``(B, 4)``; ``q0phi`` ``(B, n)`` DH angles (roll kept)."""
        if target.ndim != 2 or target.shape[1] != 4:
            raise ValueError("yaw-pitch3 solves (x, y, z, pitch) rows; use armkit.ik(robot, xyz, pitch=...)")
        sf = self.sf
        B = len(target)
        p = sf.point_to_chain(target[:, :3])
        psi = target[:, 3]
        phi5 = q0phi[:, 4] if self.roll else np.zeros(B)
        gx, gy, gz = self._tool_point(phi5)
        L = self.lateral0 + gz                                              # (B,)
        x, y, z = p[:, 0], p[:, 1], p[:, 2]
        rho = np.hypot(x, y)
        h2 = rho * rho - L * L
        lateral_out = h2 < 0.0
        Xf = np.sqrt(np.maximum(h2, 0.0))
        on_axis = (rho <= LENGTH_TOL * sf.scale) & (np.abs(L) <= LENGTH_TOL * sf.scale)
        yaw = np.where(on_axis, q0phi[:, 0], np.arctan2(y, x))
        f = _FRONT[None, :]                                                 # (1, 4)
        Xs = Xf[:, None] * f                                                # (B, 4)
        phi1 = yaw[:, None] - np.arctan2(-self.s1 * L[:, None], Xs)
        # the approach angle in the plane from the pitch (front: outward is +x1, back: -x1)
        sp, cp = np.sin(psi)[:, None], np.cos(psi)[:, None]
        Phi = np.arctan2(self.up_sign * sp * np.ones_like(f), f * cp)
        Theta = Phi - self.beta
        Px = Xs - float(sf.a[0])
        Py = np.broadcast_to((self.s1 * (z - float(sf.d[0])))[:, None], Px.shape)
        ox, oy = _rot(Theta, (gx[:, None], gy[:, None]))
        Wx, Wy = Px - ox, Py - oy                                           # the wrist (joint 4's axis)
        t1, t2, c, r = two_link(Wx, Wy, float(sf.a[1]), float(sf.a[2]))     # (B, 4, 2)
        k = _ELBOW[None, :]
        rows = np.arange(4)[None, :]
        t1, t2 = t1[:, rows[0], _ELBOW], t2[:, rows[0], _ELBOW]             # (B, 4): branch j uses elbow k_j
        phi = np.empty((B, 4, sf.n))
        phi[..., 0] = phi1
        phi[..., 1] = t1
        phi[..., 2] = t2
        phi[..., 3] = Theta - t1 - t2
        if self.roll:
            phi[..., 4] = phi5[:, None]
        fwd = forward_sign(Wx, f)
        up = elbow_up(fwd, self.up_sign, float(sf.a[1]), float(sf.a[2]), k)
        unreachable = (c > 1.0) | (c < -1.0) | lateral_out[:, None]
        label = _LABELS[2 * (f > 0).astype(int) + up.astype(int)]
        outer, inner = abs(sf.a[1]) + abs(sf.a[2]), abs(abs(sf.a[1]) - abs(sf.a[2]))
        unit = self.unit

        def why(i: int) -> str:
            b, j = divmod(i, 4)
            if lateral_out[b]:
                return (f"target is {rho[b]:.6g} {unit} from the yaw axis, closer than the arm's sideways offset "
                        f"of {abs(L[b]):.6g} {unit} (with this roll).")
            return out_of_reach("for this pitch, the wrist (the target minus the wrist-to-tool offset)",
                                float(r[b, j]), unit, outer, inner)

        note = np.full((B, 4), "", dtype=object)
        edge = (np.abs(np.abs(c) - 1.0) <= 1e-9) & ~unreachable
        if edge.any():
            add_messages(note, edge, lambda i: elbow_edge(float(c.reshape(-1)[i])))
        if on_axis.any():
            yaw_q = phi1 - sf.theta[0]
            add_messages(note, np.repeat(on_axis[:, None], 4, axis=1) & ~unreachable, lambda i: (
                f"on the yaw axis: any yaw angle works ({self.yaw_name} is free); giving {self.yaw_name} = "
                f"{math.degrees(math.remainder(yaw_q.reshape(-1)[i], 2 * math.pi)):.6g} deg (from q0)."), first=True)
        return Raw(phi, label, unreachable, why, note)


# --------------------------------------------------------------------------------- on the true model
def _geometry(robot: Robot) -> tuple[Array, Array, Array]:
    """The true model's yaw axis ``u`` (pointing up), a point on it, and the approach axis in the tool frame."""
    geo = robot.cache.get("yaw_pitch3_geometry")
    if geo is None:
        first = robot.chain.fixed[0]
        u = first[:3, 2].copy()
        if u[2] < 0:
            u = -u
        last = robot.chain.fixed[-1]            # post_n . tool: the last joint's frame -> tool frame
        solver = _solver_of(robot)
        if solver is not None and solver.roll:
            a_tool = last[:3, :3].T @ np.array([0.0, 0.0, 1.0])     # the roll axis, in the tool frame
            if a_tool[2] < 0:                                         # towards the tool's z
                a_tool = -a_tool
        else:
            a_tool = np.array([0.0, 0.0, 1.0])
        geo = (u, first[:3, 3].copy(), a_tool)
        robot.cache["yaw_pitch3_geometry"] = geo
    return geo


def _solver_of(robot: Robot) -> "YawPitch3 | None":
    from . import closed_form

    s = closed_form(robot)
    return s if isinstance(s, YawPitch3) else None


def pitch_of(robot: Robot, q: Array, target_point: Array | None = None) -> Array:
    """The tool pitch (rad) of configurations ``q`` ``(..., n)`` of a yaw-pitch3 arm.

    The angle of the approach axis in the arm's vertical plane (the plane perpendicular to
    the second joint's axis, the first pitch axis): ``atan2(a . up, a . h)`` with ``h`` the
    plane's horizontal direction pointing outward, towards ``target_point`` ``(..., 3)``
    (default: the tool position). See the module docstring.

    Examples
    --------
    >>> import armkit, numpy as np
    >>> arm = armkit.load("so101")
    >>> round(float(np.degrees(pitch_of(arm, np.radians([0, 0, 0, 90, 0])))), 3)   # wrist bent down
    -90.0
    """
    from ...kinematics import fk

    q = np.asarray(q, dtype=float)
    return _pitch_parts(robot, q, fk(robot, q), target_point)[0]


def _pitch_parts(robot: Robot, q: Array, T: Array, target_point: Array | None = None):
    """``pitch, a, u, h, s, c`` for configurations ``q`` with tool poses ``T``: approach axis ``a``,
    up ``u``, outward horizontal ``h`` (perpendicular to the pitch axis), ``s = a.u``, ``c = a.h``."""
    u, o, a_tool = _geometry(robot)
    f0, f1 = robot.chain.fixed[0], robot.chain.fixed[1]
    c1, s1 = np.cos(q[..., 0]), np.sin(q[..., 0])
    k1 = f1[:3, 2]                                    # joint 2's axis in joint 1's turning frame
    k_local = np.stack([c1 * k1[0] - s1 * k1[1], s1 * k1[0] + c1 * k1[1], np.broadcast_to(k1[2], c1.shape)], -1)
    k = k_local @ f0[:3, :3].T                        # joint 2's axis (the pitch axis) in the world
    h = _cross(k, u)
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    p = (T[..., :3, 3] if target_point is None else np.asarray(target_point, dtype=float)) - o
    side = np.where(np.einsum("...i,...i->...", h, p) < 0, -1.0, 1.0)
    h = h * side[..., None]
    a = T[..., :3, :3] @ a_tool
    s, c = a @ u, np.einsum("...i,...i->...", a, h)
    return np.arctan2(s, c), a, u, h, s, c


def _check(robot: Robot, q: Array, pts: Array, psi: Array, tol: tuple[float, float], enforce_limits: bool):
    """Position error (FK of the true model), pitch error (rad), ok, within limits; ``q`` (..., n)."""
    from ...kinematics import fk

    dp, _, ok, within = verify(robot, q, pts, True, tol, enforce_limits)
    dr = np.abs(np.remainder(_pitch_parts(robot, q, fk(robot, q), pts)[0] - psi + math.pi, 2 * math.pi) - math.pi)
    return dp, dr, ok & (dr <= tol[1]), within


def _polish(robot: Robot, branches: tuple, target: tuple[Array, Array], tol: tuple[float, float],
            enforce_limits: bool, steps: int, cand: NDArray[np.bool_] | None = None, start: Array | None = None):
    """Newton steps on (position, pitch) of the true model over the first four joints (the roll stays).

    ``branches`` is ``(q, dp, dr, ok, within)`` ``(B, m, ...)`` (as :func:`._common.keep_better`
    takes it), ``target`` the positions ``(B, 3)`` and pitches ``(B,)``. ``cand`` ``(B, m)``: the
    branches to polish (default: those within 6e-3 of the reach and rad, not already exact);
    ``start``: where to start them (default ``q``). A branch takes the result only where it
    lowers the FK error. Returns new ``(q, dp, dr, ok, within)``.
    """
    from ...kinematics import fk, jacobian

    q, dp, dr, ok, within = branches
    pts, psi = target
    scale = robot.reach
    if cand is None:
        cand = (dp <= 6e-3 * scale) & (dr <= 6e-3) & ((dp > 1e-13 * scale) | (dr > 1e-13))
    if not cand.any():
        return q, dp, dr, ok, within
    bi, mi = np.nonzero(cand)
    qc, tp, tpsi = (q if start is None else start)[bi, mi].copy(), pts[bi], psi[bi]
    k = 4
    eye = np.eye(k)
    active = np.arange(len(qc))
    for _ in range(steps):
        T = fk(robot, qc[active])
        e = np.empty((len(active), 4))
        e[:, :3] = tp[active] - T[:, :3, 3]
        pitch, a, u, h, sa, ca = _pitch_parts(robot, qc[active], T, tp[active])
        e[:, 3] = np.remainder(tpsi[active] - pitch + math.pi, 2 * math.pi) - math.pi
        still = (np.abs(e[:, :3]).max(axis=1) > 1e-15 * scale) | (np.abs(e[:, 3]) > 1e-15)
        active, e = active[still], e[still]
        a, h, sa, ca = a[still], h[still], sa[still], ca[still]
        if len(active) == 0:
            break
        Jfull = jacobian(robot, qc[active])
        J = np.empty((len(active), 4, k))
        J[:, :3] = Jfull[:, :3, :k]
        # d pitch = (c ds - s dc) / (s^2 + c^2), ds = w.(a x u), dc = w.(a x h) (+ w0.(h x a): h turns with the yaw)
        n2 = (sa * sa + ca * ca)[:, None]
        g = (ca[:, None] * _cross(a, u) - sa[:, None] * _cross(a, h)) / n2
        J[:, 3] = np.einsum("bi,bij->bj", g, Jfull[:, 3:, :k])
        J[:, 3, 0] -= sa * np.einsum("bi,bi->b", Jfull[:, 3:, 0], _cross(h, a)) / n2[:, 0]
        JT = np.swapaxes(J, 1, 2)   # damped (1e-14) normal equations: Newton, safe at a fold
        qc[active, :k] += np.linalg.solve(JT @ J + 1e-14 * eye, (JT @ e[..., None]))[..., 0]
    dpn, drn, okn, wn = _check(robot, qc, tp, tpsi, tol, enforce_limits)
    return keep_better((q, dp, dr, ok, within), bi, mi, (qc, dpn, drn, okn, wn), scale)


def solve_pitch(robot: Robot, solver: YawPitch3, pts: Array, psi: Array, q0: Array,
                tol: tuple[float, float] | None = None, enforce_limits: bool = True) -> IKResult:
    """Every branch for positions ``pts`` ``(B, 3)`` and pitches ``psi`` ``(B,)``; ``q0`` ``(B, n)``.

    Like :func:`~armkit.ik.analytic.solve_all`: joint values wrapped into the limits nearest
    ``q0``, every branch checked by FK of the true model (position within ``tol[0]``, pitch
    within ``tol[1]`` rad: ``rotation_error`` is the pitch error), branches of a real file's
    ideal arm polished by Newton steps on (position, pitch), successful branches first, each
    group sorted by distance to ``q0``. Fields ``(B, 4)``, ``q`` ``(B, 4, n)``.
    """
    from . import _failure_messages, wrap_to_limits

    if tol is None:
        tol = default_tolerance(robot)
    theta = solver.sf.theta
    raw = solver.solve(np.concatenate([pts, psi[:, None]], axis=1), q0 + theta)
    q = wrap_to_limits(raw.q - theta, q0[:, None, :], robot.lower, robot.upper, ~robot.prismatic)
    dp, dr, ok, within = _check(robot, q, pts[:, None], psi[:, None], tol, enforce_limits)
    q, dp, dr, ok, within = _polish(robot, (q, dp, dr, ok, within), (pts, psi), tol, enforce_limits,
                                    2 if solver.sf.exact else 8)
    # At a stretched or folded elbow the ideal arm's answer sits on the fold, where Newton cannot move
    # outwards; the true arm may still reach (its solution has the elbow bent by ~sqrt(error)).
    elbow = q[..., 2] + theta[2]
    stuck = ~ok & (dp <= 6e-3 * robot.reach) & (dr <= 6e-3) & (np.abs(np.sin(elbow)) < 1e-2)
    if stuck.any():
        a2, a3 = abs(float(solver.sf.a[1])), abs(float(solver.sf.a[2]))
        bend = np.sqrt(2.0 * dp * (a2 + a3) / (a2 * a3)) + 1e-4
        sign = np.where(_ELBOW == 0, 1.0, -1.0)[None, :]          # branch order of Raw: elbow index
        start = q.copy()
        start[..., 2] = np.where(np.cos(elbow) > 0, sign * bend, math.pi - sign * bend) - theta[2]
        q, dp, dr, ok, within = _polish(robot, (q, dp, dr, ok, within), (pts, psi), tol, enforce_limits, 16,
                                        cand=stuck, start=start)
    dist = np.linalg.norm(q - q0[:, None, :], axis=-1)
    fk_ok = (dp <= tol[0]) & (dr <= tol[1])
    code = np.where(ok, 0, np.where(fk_ok & ~within, 2, 1))
    message = np.where(ok, raw.note, "").astype(object, copy=False)
    _failure_messages(robot, message, code, raw, q, dp, dr, tol)
    for i in np.flatnonzero(((code == 1) & ~raw.unreachable & (dp <= tol[0])).ravel()):   # pitch, not orientation
        message.flat[i] = str(message.flat[i]).replace("this arm cannot turn to that orientation there",
                                                       "this branch cannot reach that pitch there")
    order = np.argsort(np.where(ok, 0.0, 1e9) + dist, axis=-1, kind="stable")
    take = lambda a: np.take_along_axis(a, order, axis=1)  # noqa: E731
    return IKResult(q=np.take_along_axis(q, order[..., None], axis=1), success=take(ok), position_error=take(dp),
                    rotation_error=take(dr), iterations=np.zeros(ok.shape, dtype=np.int64), branch=take(raw.label),
                    within_limits=take(within), reason=_REASON_TEXT[take(code)], message=take(message))
