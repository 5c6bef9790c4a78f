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
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...model.robot import Robot
from ..result import IKResult, default_tolerance, verify
from ._common import (LENGTH_TOL, Array, Raw, StandardForm, add_messages, elbow_edge, elbow_up, forward_sign,
                      keep_better, out_of_reach, two_link)

__all__ = ["YawPitch3", "pitch_of", "shoulder_reach", "solve_pitch"]

_LABELS = np.array(["back/elbow-down", "back/elbow-up", "front/elbow-down", "front/elbow-up"], dtype=object)
_FRONT = np.array([1.0, 1.0, -1.0, -1.0])    # branch order: (front, e0), (front, e1), (back, e0), (back, e1)
_ELBOW = np.array([0, 1, 0, 1])
_REASON_TEXT = np.array(["converged", "unreachable", "joint limits"])
_APPROACH_TOL = 1e-9    # four joints: the tool's z axis must lie in the arm's plane this closely
_LATERAL_SLACK = 1e-5   # relative to the reach: a target this much inside the sideways offset is on it


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

    def lateral(self, pts: Array, q0phi: Array) -> tuple[Array, Array]:
        """The distance of world points ``(B, 3)`` from the yaw axis and the arm's sideways offset ``L`` (with
        the roll of ``q0phi``), both ``(B,)``: a point nearer the axis than ``|L|`` is out of reach."""
        p = self.sf.point_to_chain(pts)
        phi5 = q0phi[:, 4] if self.roll else np.zeros(len(pts))
        return np.hypot(p[:, 0], p[:, 1]), self.lateral0 + self._tool_point(phi5)[2]

    def solve(self, target: Array, q0phi: Array, x_min: Array | None = None) -> Raw:
        """Every branch for rows ``(x, y, z, pitch)`` ``(B, 4)``; ``q0phi`` ``(B, n)`` DH angles (roll kept).

        ``x_min`` ``(B,)``: the smallest distance ``|a_1 + X|`` of the arm's plane foot to use (a start for the
        polish on the far side of the lateral fold, where the true arm's solution lies)."""
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
        # closer to the yaw axis than the sideways offset; within _LATERAL_SLACK of it (the file's rounding) the
        # target counts as on the boundary (X = 0) and the polish on the true model decides (issue 20)
        lateral_out = rho < np.abs(L) - _LATERAL_SLACK * sf.scale
        Xf = np.sqrt(np.maximum(h2, 0.0) if x_min is None else np.maximum(h2, x_min * x_min))
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


def shoulder_reach(robot: Robot) -> tuple | None:
    """Where the reach of a yaw-pitch3 arm is measured from, and the reach; ``None`` for other arms.

    The shoulder (joint 2's axis, where the arm's plane starts) runs on a circle about the yaw
    axis as the yaw joint turns: centre ``c`` (world), unit axis ``u``, radius ``r_s``. From the
    shoulder the tool point is ``P`` in the arm's plane plus the sideways offset ``L``, so it is
    at most ``R = max over the roll of sqrt((|a_2| + |a_3| + |g|)^2 + L^2)`` away (``g`` the
    in-plane wrist-to-tool offset); a target farther than ``R`` from every point of the circle is
    out of reach whatever the joints (a little more, :data:`_LATERAL_SLACK` of the reach, for the
    rounding of a real file). Returns ``(c, u, r_s, packed, R)``, ``packed`` the eight floats
    ``(cx, cy, cz, ux, uy, uz, r_s, R)`` (the single-target fast path of :mod:`armkit.ik.numeric`).
    """
    solver = _solver_of(robot)
    if solver is None:
        return None
    sf = solver.sf
    u = sf.base[:3, 2].copy()
    c = sf.base[:3, :3] @ np.array([0.0, 0.0, float(sf.d[0])]) + sf.base[:3, 3]
    rs = abs(float(sf.a[0]))
    phi5 = np.linspace(-math.pi, math.pi, 7201)
    gx, gy, gz = solver._tool_point(phi5)
    L = solver.lateral0 + gz
    R = float(np.max(np.hypot(abs(float(sf.a[1])) + abs(float(sf.a[2])) + np.hypot(gx, gy), L)))
    # the grid's step (5e-2 deg) moves g by at most |g| * 1e-6; the slack covers it and the file's rounding
    R += _LATERAL_SLACK * sf.scale
    return c, u, rs, (*c.tolist(), *u.tolist(), rs, R), R


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


_SWEEP = 720            # pitches tried per target by reachable_pitches (every 0.5 deg), then each edge bisected
_SWEEP_CHUNK = 50       # targets per sweep batch (memory: chunk * _SWEEP * 4 branches)


def _pitch_ok(robot: Robot, solver: YawPitch3, pts: Array, psi: Array, q0: Array, enforce_limits: bool) -> NDArray:
    """Whether some branch of the closed form (the ideal arm) reaches ``(pts, psi)`` rows, within the limits."""
    from . import wrap_to_limits

    theta = solver.sf.theta
    raw = solver.solve(np.concatenate([pts, psi[:, None]], axis=1), q0 + theta)
    good = ~raw.unreachable
    if enforce_limits:
        q = wrap_to_limits(raw.q - theta, q0[:, None, :], robot.lower, robot.upper, ~robot.prismatic)
        good &= np.all((q >= robot.lower - 1e-9) & (q <= robot.upper + 1e-9), axis=-1)
    return good.any(axis=1)  # type: ignore[return-value]


def reachable_pitches(robot: Robot, solver: YawPitch3, pts: Array, q0: Array,
                      enforce_limits: bool = True) -> list[list[tuple[float, float]]]:
    """The pitches (rad) the arm reaches at each point ``pts`` ``(B, 3)`` with the roll of ``q0`` ``(B, n)``.

    A 1-D sweep of the closed form over the pitch (every 0.5 deg, the edges then bisected to
    ~1e-4 deg) on the ideal arm (a real file's rounding moves an edge by ~1e-6 rad). Per
    target a list of intervals ``(lo, hi)``, ``lo`` in ``[-pi, pi)`` and ``hi`` possibly past
    ``pi`` for an interval through 180 deg; ``[(-pi, pi)]`` when every pitch is reachable.
    """
    grid = -math.pi + 2 * math.pi * np.arange(_SWEEP) / _SWEEP
    step = 2 * math.pi / _SWEEP
    out: list[list[tuple[float, float]]] = []
    for start in range(0, len(pts), _SWEEP_CHUNK):
        p, q = pts[start:start + _SWEEP_CHUNK], q0[start:start + _SWEEP_CHUNK]
        nb = len(p)
        ok = _pitch_ok(robot, solver, np.repeat(p, _SWEEP, axis=0), np.tile(grid, nb), np.repeat(q, _SWEEP, axis=0),
                       enforce_limits).reshape(nb, _SWEEP)
        nxt = np.roll(ok, -1, axis=1)
        rise = np.argwhere(~ok & nxt)         # (b, k): k fails, k + 1 reaches: a lower edge in (k, k + 1)
        fall = np.argwhere(ok & ~nxt)         # k reaches, k + 1 fails: an upper edge
        edges = np.concatenate([rise, fall])
        lo_in = np.concatenate([np.zeros(len(rise), bool), np.ones(len(fall), bool)])   # the lower end reaches
        a = grid[edges[:, 1]] if len(edges) else np.zeros(0)
        b = a + step
        for _ in range(13):
            mid = 0.5 * (a + b)
            hit = _pitch_ok(robot, solver, p[edges[:, 0]], mid, q[edges[:, 0]], enforce_limits) if len(edges) \
                else np.zeros(0, bool)
            inside = hit == lo_in             # mid on the same side as a
            a, b = np.where(inside, mid, a), np.where(inside, b, mid)
        where = 0.5 * (a + b)
        for j in range(nb):
            if ok[j].all():
                out.append([(-math.pi, math.pi)])
                continue
            lows = np.sort(where[: len(rise)][rise[:, 0] == j])
            highs = np.sort(where[len(rise):][fall[:, 0] == j])
            spans = []
            for lo in lows:
                later = highs[highs > lo]
                hi = later[0] if len(later) else highs[0] + 2 * math.pi     # through 180 deg
                spans.append((float(lo), float(hi)))
            out.append(spans)
    return out


def _deg_text(v: float) -> str:
    return f"{v:.1f}".rstrip("0").rstrip(".").replace("-0", "-0") if v != 0 else "0"


def pitch_range_text(spans: list[tuple[float, float]]) -> str:
    """``"-35 to 60 deg"`` (several joined by ``", "``): the intervals of :func:`reachable_pitches`, in degrees
    rounded inwards to 0.1 deg (every pitch named is reachable)."""
    parts = []
    for lo, hi in spans:
        a, b = math.ceil(math.degrees(lo) * 10 - 1e-9) / 10, math.floor(math.degrees(hi) * 10 + 1e-9) / 10
        if b < a:
            continue
        if b > 180:
            parts.append(f"{_deg_text(a)} to {_deg_text(b - 360)} deg (through 180)")
        else:
            parts.append(f"{_deg_text(a)} to {_deg_text(b)} deg")
    return ", ".join(parts)


def _pitch_messages(robot: Robot, solver: YawPitch3, pts: Array, psi: Array, q0: Array, enforce_limits: bool,
                    message: NDArray[np.object_], rows: NDArray[np.intp]) -> None:
    """Prefix the failed targets' ``rows`` messages with the range of pitches reachable there."""
    spans = reachable_pitches(robot, solver, pts[rows], q0[rows], enforce_limits)
    roll = ""
    for j, i in enumerate(rows):
        if solver.roll:
            roll = f" (with {robot.joint_names[4]} at {math.degrees(float(q0[i, 4])):.4g} deg)"
        want = math.degrees(float(psi[i]))
        text = pitch_range_text(spans[j])
        if spans[j] == [(-math.pi, math.pi)]:
            continue                                   # every pitch reaches it on the ideal arm: no range to give
        w = math.radians(math.remainder(want, 360.0))
        if any(lo <= w <= hi or lo <= w + 2 * math.pi <= hi for lo, hi in spans[j]):
            continue                                   # a pitch at an edge that the ideal arm reaches: no range
        head = (f"pitch {want:.4g} deg is not reachable at this point; reachable pitches here: {text}{roll}" if text
                else f"no pitch reaches this point{' within the joint limits' if enforce_limits else ''}{roll}")
        for k in range(message.shape[1]):
            message[i, k] = f"{head}; {message[i, k]}"


def solve_pitch(robot: Robot, solver: YawPitch3, pts: Array, psi: Array, q0: Array,
                tol: tuple[float, float] | None = None, enforce_limits: bool = True, sweep: bool = True) -> IKResult:
    """Every branch for positions ``pts`` ``(B, 3)`` and pitches ``psi`` ``(B,)``; ``q0`` ``(B, n)``.

    Like :func:`~armkit.ik.analytic.solve_all`: joint values wrapped into the limits nearest
    ``q0``, every branch checked by FK of the true model (position within ``tol[0]``, pitch
    within ``tol[1]`` rad: ``rotation_error`` is the pitch error), branches of a real file's
    ideal arm polished by Newton steps on (position, pitch), successful branches first, each
    group sorted by distance to ``q0``. Fields ``(B, 4)``, ``q`` ``(B, 4, n)``. A target no branch
    reaches gets, in every branch's message, the pitches that are reachable there
    (:func:`reachable_pitches`; ``sweep=False`` skips it), or, beyond the reach at any pitch,
    its distance from the shoulder and the reach (:func:`shoulder_reach`).
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
    # On the lateral fold (a target as far from the yaw axis as the sideways offset) the ideal arm's answer has
    # the arm's plane through the target (X = 0), where Newton cannot move sideways; the true arm's solution
    # lies a little off it: start from X on each side (front and back branches).
    todo = ~ok.any(axis=1)
    if todo.any():
        rho, L = solver.lateral(pts[todo], q0[todo] + theta)
        near = np.abs(rho - np.abs(L)) <= 10 * _LATERAL_SLACK * solver.sf.scale
        if near.any():
            rows = np.flatnonzero(todo)[near]
            x0 = np.sqrt(2.0 * np.abs(L[near]) * _LATERAL_SLACK * solver.sf.scale)
            raw2 = solver.solve(np.concatenate([pts[rows], psi[rows, None]], axis=1), q0[rows] + theta, x_min=x0)
            start = q.copy()
            start[rows] = wrap_to_limits(raw2.q - theta, q0[rows, None, :], robot.lower, robot.upper,
                                         ~robot.prismatic)
            cand = np.zeros(ok.shape, dtype=bool)
            cand[rows] = ~ok[rows]
            q, dp, dr, ok, within = _polish(robot, (q, dp, dr, ok, within), (pts, psi), tol, enforce_limits, 16,
                                            cand=cand, start=start)
    dist = np.linalg.norm(q - q0[:, None, :], axis=-1)
    fk_ok = (dp <= tol[0]) & (dr <= tol[1])
    code = np.where(ok, 0, np.where(fk_ok & ~within, 2, 1))
    message = np.where(ok, raw.note, "").astype(object, copy=False)
    _failure_messages(robot, message, code, raw, q, dp, dr, tol)
    for i in np.flatnonzero(((code == 1) & ~raw.unreachable & (dp <= tol[0])).ravel()):   # pitch, not orientation
        message.flat[i] = str(message.flat[i]).replace("this arm cannot turn to that orientation there",
                                                       "this branch cannot reach that pitch there")
    failed = np.flatnonzero(~ok.any(axis=1))
    if len(failed):
        from ..numeric import shoulder_distance

        sh = shoulder_reach(robot)
        far = shoulder_distance(sh, pts[failed]) > sh[-1] + tol[0]  # type: ignore[arg-type, index]
        for i in failed[far]:   # beyond the reach at any pitch: say so, measured from the shoulder (issue 20)
            d = float(shoulder_distance(sh, pts[i:i + 1])[0])  # type: ignore[arg-type]
            message[i] = (f"unreachable: target is {d:.6g} {robot.unit} from the shoulder; the arm reaches at most "
                          f"{sh[-1]:.6g} {robot.unit} (at any pitch).")  # type: ignore[index]
        if (~far).any() and sweep:
            _pitch_messages(robot, solver, pts, psi, q0, enforce_limits, message, failed[~far])
    order = np.argsort(np.where(ok, 0.0, 1e9) + dist, axis=-1, kind="stable")
    take = lambda a: np.take_along_axis(a, order, axis=1)  # noqa: E731
    return IKResult(q=np.take_along_axis(q, order[..., None], axis=1), success=take(ok), position_error=take(dp),
                    rotation_error=take(dr), iterations=np.zeros(ok.shape, dtype=np.int64), branch=take(raw.label),
                    within_limits=take(within), reason=_REASON_TEXT[take(code)], message=take(message))


# ------------------------------------------------------------------------ position + pointing direction
_VERTICAL = 1e-6    # a direction whose horizontal part is below this points straight up or down


def _direction_check(robot: Robot, q: Array, pts: Array, dirs: Array, tol: tuple[float, float],
                     enforce_limits: bool):
    """Position error, angle (rad) between the tool's z axis and ``dirs``, ok, within limits; ``q`` (..., n)."""
    from ...kinematics import fk

    T = fk(robot, q)
    dp = np.linalg.norm(T[..., :3, 3] - pts, axis=-1)
    z = T[..., :3, 2]
    ang = np.arctan2(np.linalg.norm(_cross(z, dirs), axis=-1), np.einsum("...i,...i->...", z, dirs))
    within = np.all((q >= robot.lower - 1e-12) & (q <= robot.upper + 1e-12), axis=-1)
    ok = (dp <= tol[0]) & (ang <= tol[1]) & (within | (not enforce_limits))
    return dp, ang, ok, within


def _direction_residual(robot: Robot, q: Array, pts: Array, dirs: Array) -> tuple[Array, Array]:
    from ...kinematics import fk

    T = fk(robot, q)
    return np.concatenate([pts - T[:, :3, 3], dirs - T[:, :3, 2]], axis=1), T[:, :3, 2]


def _polish_direction(robot: Robot, q: Array, pts: Array, dirs: Array, steps: int = 12) -> Array:
    """Gauss-Newton on (position, tool z axis along ``dirs``) over every joint, rows ``q`` ``(R, n)``.

    Near straight up or down the roll moves the tool's z axis by micro-radians only: a step is
    cut to 0.3 rad at most and halved until it lowers the error (up to 8 times)."""
    from ...kinematics import jacobian

    q = q.copy()
    n = robot.n
    eye = np.eye(n)
    w = np.array([1.0, 1.0, 1.0, 0, 0, 0]) / robot.reach + np.array([0, 0, 0, 1.0, 1.0, 1.0])
    active = np.arange(len(q))
    for _ in range(steps):
        if len(active) == 0:
            break
        e, z = _direction_residual(robot, q[active], pts[active], dirs[active])
        cost = np.sum((e * w) ** 2, axis=1)
        still = cost > 1e-32
        active, e, z, cost = active[still], e[still], z[still], cost[still]
        if len(active) == 0:
            break
        Jf = jacobian(robot, q[active])
        J = np.empty((len(active), 6, n))
        J[:, :3] = Jf[:, :3]
        zz = np.broadcast_to(z[:, None, :], (len(active), n, 3))
        J[:, 3:] = -np.swapaxes(_cross(zz, np.swapaxes(Jf[:, 3:], 1, 2)), 1, 2)     # dz = w x z = -z x w
        Jw, ew = J * w[None, :, None], e * w
        JT = np.swapaxes(Jw, 1, 2)
        dq = np.linalg.solve(JT @ Jw + 1e-14 * eye, JT @ ew[..., None])[..., 0]
        big = np.abs(dq).max(axis=1)
        dq *= np.minimum(1.0, 0.3 / np.maximum(big, 1e-300))[:, None]
        todo = np.arange(len(active))
        for _half in range(8):
            qn = q[active[todo]] + dq[todo]
            en, _ = _direction_residual(robot, qn, pts[active[todo]], dirs[active[todo]])
            better = np.sum((en * w) ** 2, axis=1) < cost[todo]
            q[active[todo[better]]] = qn[better]
            todo = todo[~better]
            if len(todo) == 0:
                break
            dq[todo] *= 0.5
        active = np.setdiff1d(active, active[todo]) if len(todo) else active
    return q


def direction_to_pitch(robot: Robot, pts: Array, dirs: Array) -> tuple[Array, Array]:
    """The pitch (rad) of pointing directions ``dirs`` ``(B, 3)`` at points ``pts``, and how far (rad) each
    direction leaves the vertical plane through the yaw axis and the point (0 for straight up or down)."""
    u, o, _ = _geometry(robot)
    w = pts - o
    up = dirs @ u
    dh = dirs - up[:, None] * u
    nh = np.linalg.norm(dh, axis=-1)
    wh = w - (w @ u)[:, None] * u
    nw = np.linalg.norm(wh, axis=-1)
    outward = np.where((np.einsum("bi,bi->b", dh, wh) < 0), -1.0, 1.0)
    psi = np.where(nh > _VERTICAL, np.arctan2(up, outward * nh), np.where(up < 0, -0.5 * math.pi, 0.5 * math.pi))
    radial = wh / np.maximum(nw, 1e-300)[:, None]
    side = np.abs(np.einsum("bi,bi->b", dh, _cross(u[None, :], radial)))
    off = np.where((nh > _VERTICAL) & (nw > 1e-12 * robot.reach), np.arcsin(np.clip(side, 0.0, 1.0)), 0.0)
    return psi, off


_NEAR_VERTICAL = 1e-4   # below this horizontal part (chain frame) the roll is found by a sweep on the true model
_ROLL_SWEEP = 24


def _roll_candidates(robot: Robot, solver: YawPitch3, pts: Array, dirs: Array, q0: Array
                     ) -> tuple[Array, NDArray[np.bool_]]:
    """Roll joint values ``(B, K)`` to start from (and which are valid).

    A direction with a horizontal part fixes the arm's plane (front or back); the roll's
    sideways offset must then put that plane through the target: two rolls each way. Nearly
    straight up or down, the plane is free and the roll is set by micro-radian effects (the
    tool's z axis leaves the roll axis by the file's rounding): a sweep of rolls over the
    limits, each then polished on the true model.
    """
    sf = solver.sf
    B = len(pts)
    if not solver.roll:
        return np.zeros((B, 1)), np.ones((B, 1), dtype=bool)
    theta5 = float(sf.theta[4])
    p0 = sf.point_to_chain(pts)
    d0 = dirs @ sf.base_inv[:3, :3].T
    vertical = np.hypot(d0[:, 0], d0[:, 1]) <= _NEAR_VERTICAL
    K = _ROLL_SWEEP if vertical.any() else 4
    cand = np.repeat(q0[:, -1:], K, axis=1)
    valid = np.zeros((B, K), dtype=bool)
    if vertical.any():
        lo, hi = float(robot.lower[4]), float(robot.upper[4])
        lo, hi = (lo, hi) if math.isfinite(lo) and math.isfinite(hi) else (-math.pi, math.pi)
        cand[vertical] = lo + (hi - lo) * (np.arange(K) + 0.5) / K
        valid[vertical] = True
    s4 = float(solver.sf.twist(3) or 1)
    t = sf.tool[:3, 3]
    A, t_ang = math.hypot(t[0], t[1]), math.atan2(t[1], t[0])
    gamma = np.arctan2(d0[:, 1], d0[:, 0])
    for k, turn in enumerate((0.0, math.pi)):            # the arm's plane along the direction, either way
        phi1 = gamma + turn
        z1 = solver.s1 * np.stack([np.sin(phi1), -np.cos(phi1)], axis=1)
        L = np.einsum("bi,bi->b", p0[:, :2], z1)
        if A < 1e-12 * sf.scale:
            ok = ~vertical & (np.abs(L - solver.lateral0) <= _LATERAL_SLACK * sf.scale)
            valid[ok, 2 * k] = True
            continue
        r = s4 * (L - solver.lateral0) / A
        ok = ~vertical & (np.abs(r) <= 1.0 + 1e-3)      # the file's rounding moves L by ~1e-6 m
        a = np.arcsin(np.clip(r, -1.0, 1.0))
        cand[ok, 2 * k] = (a - t_ang - theta5)[ok]
        cand[ok, 2 * k + 1] = (math.pi - a - t_ang - theta5)[ok]
        valid[ok, 2 * k:2 * k + 2] = True
    cand = np.remainder(cand + math.pi, 2 * math.pi) - math.pi
    return cand, valid


def solve_direction(robot: Robot, solver: YawPitch3, pts: Array, dirs: Array, q0: Array,
                    tol: tuple[float, float] | None = None, enforce_limits: bool = True) -> IKResult:
    """Every branch for positions ``pts`` ``(B, 3)`` with the tool's z axis along unit ``dirs`` ``(B, 3)``.

    A yaw + three pitch joints + roll arm points its approach axis only within its vertical
    plane, so a direction is a pitch (:func:`direction_to_pitch`) and the plane's yaw: the
    closed form :func:`solve_pitch` for that pitch, with the roll that makes it exact (the
    tool's z axis leaves the roll axis by the file's rounding, and the roll moves the tool
    point sideways: :func:`_roll_candidates`), then Gauss-Newton on (position, direction)
    over all the joints of the true model. Per branch label (front/back x elbow) the
    solution nearest ``q0`` that succeeds; ``rotation_error`` is the angle between the
    tool's z axis and the direction. Fields ``(B, 4)``, ``q`` ``(B, 4, n)``, sorted like
    :func:`solve_pitch`.
    """
    if tol is None:
        tol = default_tolerance(robot)
    B, n = len(pts), robot.n
    psi, off = direction_to_pitch(robot, pts, dirs)
    rolls, valid = _roll_candidates(robot, solver, pts, dirs, q0)
    K = rolls.shape[1]
    q0k = np.repeat(q0[:, None, :], K, axis=1)
    if solver.roll:
        q0k[..., 4] = rolls
    flat = q0k.reshape(-1, n)
    rep = lambda a: np.repeat(a, K, axis=0)  # noqa: E731
    res = solve_pitch(robot, solver, rep(pts), rep(psi), flat, tol, enforce_limits=False, sweep=False)
    q = np.asarray(res.q).reshape(B * K * 4, n)
    pk, dk = np.repeat(rep(pts), 4, axis=0), np.repeat(rep(dirs), 4, axis=0)
    close = (np.asarray(res.position_error).reshape(-1) <= 6e-3 * robot.reach) & np.repeat(valid.reshape(-1), 4)
    if close.any():
        q[close] = _polish_direction(robot, q[close], pk[close], dk[close], 40)
        from . import wrap_to_limits

        q[close] = wrap_to_limits(q[close][:, None, :], np.repeat(rep(q0), 4, axis=0)[close][:, None, :],
                                  robot.lower, robot.upper, ~robot.prismatic)[:, 0]
    dp, ang, ok, within = _direction_check(robot, q, pk, dk, tol, enforce_limits)
    ok &= close
    labels = np.asarray(res.branch).reshape(B, K * 4)
    q = q.reshape(B, K * 4, n)  # type: ignore[assignment]
    dp, ang, ok, within, close = (a.reshape(B, K * 4) for a in (dp, ang, ok, within, close))
    msg_pitch = np.asarray(res.message, dtype=object).reshape(B, K * 4)
    dist = np.linalg.norm(q - q0[:, None, :], axis=-1)
    fk_ok = (dp <= tol[0]) & (ang <= tol[1]) & close
    # per label: success, then right but outside the limits, then the nearest miss; nearest q0 among equals
    rank = np.where(ok, 0.0, np.where(fk_ok, 1e6, 2e6 + 1e3 * dp / robot.reach)) + dist
    out_q = np.empty((B, 4, n))
    fields = {k: np.empty((B, 4), dtype=t) for k, t in (("dp", float), ("ang", float), ("ok", bool),
                                                         ("within", bool), ("fk", bool), ("msg", object))}
    for j, lab in enumerate(_LABELS):
        r = np.where(labels == lab, rank, np.inf)
        pick = np.argmin(r, axis=1)
        rows = np.arange(B)
        out_q[:, j] = q[rows, pick]
        for key, src in (("dp", dp), ("ang", ang), ("ok", ok), ("within", within), ("fk", fk_ok),
                         ("msg", msg_pitch)):
            fields[key][:, j] = src[rows, pick]
    code = np.where(fields["ok"], 0, np.where(fields["fk"] & ~fields["within"], 2, 1))
    message = np.full((B, 4), "", dtype=object)
    names = robot.joint_names
    none_valid = ~valid.any(axis=1)
    for b in np.flatnonzero(~fields["ok"].any(axis=1)):
        if none_valid[b]:  # type: ignore[index]
            head = (f"this arm points the tool only within its vertical plane through the target (the sideways "
                    f"offset allows a little more); the direction leaves that plane by {math.degrees(off[b]):.3g} deg")
        else:
            head = f"the direction is pitch {math.degrees(psi[b]):.4g} deg at this point"
        for j in range(4):
            if code[b, j] == 2:
                bad = ", ".join(nm for k, nm in enumerate(names)
                                if not robot.lower[k] - 1e-12 <= out_q[b, j, k] <= robot.upper[k] + 1e-12)
                tail = f"outside the joint limits: {bad} (see armkit info for the limits)."
            elif none_valid[b]:  # type: ignore[index]
                tail = "unreachable."
            else:
                tail = str(fields["msg"][b, j]) or (f"unreachable: the closest configuration of this branch misses "
                                                    f"by {fields['dp'][b, j]:.3g} {robot.unit} and "
                                                    f"{math.degrees(fields['ang'][b, j]):.3g} deg.")
            message[b, j] = f"{head}; {tail}"
    # the pitch ranges where the closed form says the pitch is out of reach (sweeps only the failed targets)
    fail_rows = np.flatnonzero(~fields["ok"].any(axis=1))
    if len(fail_rows):
        from ..numeric import shoulder_distance

        sh = shoulder_reach(robot)
        far = shoulder_distance(sh, pts[fail_rows]) > sh[-1] + tol[0]  # type: ignore[arg-type, index]
        code[fail_rows[far]] = 1
        far_rows = fail_rows[far]
        fail_rows, far = fail_rows[~far | none_valid[fail_rows]], far[~far | none_valid[fail_rows]]  # type: ignore[index]
        far = np.isin(fail_rows, far_rows)
        for b in fail_rows[far]:
            d = float(shoulder_distance(sh, pts[b:b + 1])[0])  # type: ignore[arg-type]
            message[b] = (f"unreachable: target is {d:.6g} {robot.unit} from the shoulder; the arm reaches at most "
                          f"{sh[-1]:.6g} {robot.unit} (in any direction).")  # type: ignore[index]
        near = fail_rows[~far & ~none_valid[fail_rows]]  # type: ignore[index]
        if len(near):
            q0r = q0[near].copy()
            if solver.roll:
                q0r[:, 4] = out_q[near, 0, 4]     # the roll the direction needs
            spans = reachable_pitches(robot, solver, pts[near], q0r, enforce_limits)
            for j, b in enumerate(near):
                text = pitch_range_text(spans[j])
                w = float(psi[b])
                if spans[j] == [(-math.pi, math.pi)] or not text \
                        or any(lo <= w <= hi or lo <= w + 2 * math.pi <= hi for lo, hi in spans[j]):
                    inside = code[b] != 2
                    miss = float(np.min(fields["ang"][b][inside] if inside.any() else fields["ang"][b]))
                    for k in range(4):
                        message[b, k] = (f"the direction is pitch {math.degrees(w):.4g} deg, which is reachable here, "
                                         f"but the tool's z axis misses it by {math.degrees(miss):.2g} deg at best (the "
                                         "robot file's rounding tilts the tool's z axis off the roll axis): give the "
                                         f"pitch instead (pitch= / --pitch {math.degrees(w):.4g} --deg); "
                                         f"{str(message[b, k]).split('; ', 1)[1]}")
                    continue
                hint = (f"pitch {math.degrees(psi[b]):.4g} deg is not reachable at this point; reachable pitches "
                        f"here: {text} (give the pitch with pitch= / --pitch)")
                for k in range(4):
                    message[b, k] = (f"the direction is a pitch of {math.degrees(psi[b]):.4g} deg here; {hint}; "
                                     f"{str(message[b, k]).split('; ', 1)[1]}")
    message[fields["ok"]] = ""
    dist = np.linalg.norm(out_q - q0[:, None, :], axis=-1)
    order = np.argsort(np.where(fields["ok"], 0.0, 1e9) + dist, axis=-1, kind="stable")
    take = lambda a: np.take_along_axis(a, order, axis=1)  # noqa: E731
    return IKResult(q=np.take_along_axis(out_q, order[..., None], axis=1), success=take(fields["ok"]),
                    position_error=take(fields["dp"]), rotation_error=take(fields["ang"]),
                    iterations=np.zeros((B, 4), dtype=np.int64),
                    branch=take(np.broadcast_to(_LABELS, (B, 4)).astype(object)),
                    within_limits=take(fields["within"]), reason=_REASON_TEXT[take(code)], message=take(message))


# ------------------------------------------------------------------------ the compiled fast path (issue 20)
_FAST_MODULE = "ik.analytic._yaw_pitch3_jit"


def fast_geometry(robot: Robot) -> Array | None:
    """The packed geometry of the compiled single-target kernels (:mod:`._yaw_pitch3_jit`), or None.

    None when the Numba back end is not in use, or ``robot`` is not a 5-joint revolute yaw-pitch3
    arm with finite limits. Built once per robot (kept in ``robot.cache``).
    """
    from ... import _jit_loader

    kern = _jit_loader.kernels(_FAST_MODULE)
    if kern is None:
        return None
    g = robot.cache.get("yaw_pitch3_fast", False)
    if g is False:
        solver = _solver_of(robot)
        ok = (solver is not None and solver.roll and robot.n == 5 and not robot.prismatic.any()
              and bool(np.all(np.isfinite(robot.lower)) and np.all(np.isfinite(robot.upper))))
        g = kern.pack(robot, solver) if ok else None
        robot.cache["yaw_pitch3_fast"] = g
    return g


def fast_kernels() -> object:
    """The compiled kernel module of this family (None while the Numba back end is not in use)."""
    from ... import _jit_loader

    return _jit_loader.kernels(_FAST_MODULE)


def nearest_pitch(robot: Robot, solver: YawPitch3, pts: Array, psi: Array, q0: Array,
                  tol: tuple[float, float] | None = None, enforce_limits: bool = True) -> IKResult | None:
    """``solve_pitch(...)[rows, 0]`` (the successful branch nearest ``q0``) by the compiled kernels.

    The rows the kernels solve plainly (a success, no note, no straight-elbow retry) come from
    them; the others from :func:`solve_pitch`, which also writes the messages. None when the
    kernels are not in use for ``robot``. Fields ``(B,)``, ``q`` ``(B, n)``.
    """
    g = fast_geometry(robot)
    if g is None:
        return None
    kern: Any = fast_kernels()
    if tol is None:
        tol = default_tolerance(robot)
    B = len(pts)
    Q = np.empty((B, 4, 5))
    DP, DR = np.empty((B, 4)), np.empty((B, 4))
    OK, WI = np.empty((B, 4), dtype=bool), np.empty((B, 4), dtype=bool)
    LAB, best = np.empty((B, 4), dtype=np.int64), np.empty(B, dtype=np.int64)
    kern.nearest_pitch(g, np.ascontiguousarray(pts, dtype=float), np.ascontiguousarray(psi, dtype=float),
                       np.ascontiguousarray(q0, dtype=float), float(tol[0]), float(tol[1]), bool(enforce_limits),
                       Q, DP, DR, OK, WI, LAB, best)
    rows = np.arange(B)
    pick = np.maximum(best, 0)
    q = Q[rows, pick]
    fields: dict[str, Any] = dict(q=q, success=OK[rows, pick], position_error=DP[rows, pick],
                                  rotation_error=DR[rows, pick], iterations=np.zeros(B, dtype=np.int64),
                                  branch=_LABELS[LAB[rows, pick]], within_limits=WI[rows, pick],
                                  reason=np.full(B, "converged", dtype=object), message=np.full(B, "", dtype=object))
    slow = np.flatnonzero(best < 0)
    if len(slow):
        res = solve_pitch(robot, solver, pts[slow], psi[slow], q0[slow], tol, enforce_limits)
        first = res[np.arange(len(slow)), 0]
        for key in fields:
            fields[key] = np.array(fields[key], dtype=object if key in ("branch", "reason", "message") else None)
            fields[key][slow] = np.asarray(getattr(first, key))
    fields["reason"] = np.asarray(fields["reason"]).astype(str)
    return IKResult(**fields)


def branch_label(index: int) -> str:
    """The branch label of a kernel's label index (``""`` for -1: no branch, e.g. the current joints kept)."""
    return str(_LABELS[index]) if 0 <= index < len(_LABELS) else ""
