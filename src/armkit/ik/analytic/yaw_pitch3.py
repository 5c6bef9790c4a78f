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
pointing from the wrist to the tool; for four joints the tool's z axis, or its x axis, along the last
link, where z lies nearer the pitch axis than the plane, as on a DH arm without a tool frame) makes the angle
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
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from ... import _jit_loader
from ...kinematics import fk, jacobian
from ...model.robot import Robot
from ..result import IKResult, default_tolerance, verify
from ._common import (LENGTH_TOL, Array, Raw, StandardForm, add_messages, elbow_edge, elbow_up, forward_sign,
                      keep_better, out_of_reach, two_link)

__all__ = ["YawPitch3", "pitch_of", "shoulder_reach", "solve_pitch"]

_LABELS = np.array(["back/elbow-down", "back/elbow-up", "front/elbow-down", "front/elbow-up"], dtype=object)
_FRONT = np.array([1.0, 1.0, -1.0, -1.0])    # branch order: (front, e0), (front, e1), (back, e0), (back, e1)
_ELBOW = np.array([0, 1, 0, 1])
_REASON_TEXT = np.array(["converged", "unreachable", "joint limits"])
_APPROACH_COS = math.sqrt(0.5)   # four joints: the tool's z axis is the approach unless nearer the pitch axis
_LATERAL_SLACK = 1e-5   # relative to the reach: a target this much inside the sideways offset is on it


def _approach_axis(tool: Array) -> int:
    """Which axis of the tool frame is a four-joint arm's approach axis (2: z, 0: x), from the tool frame in joint
    4's frame ``tool`` (4, 4) (standard DH: the pitch axis is its z). The tool's z axis, unless it lies nearer
    the pitch axis than the arm's plane (a DH arm without a tool frame, whose z is the last pitch axis itself):
    then its x axis, which points along the last link."""
    return 2 if abs(float(tool[2, 2])) <= _APPROACH_COS else 0


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

    def __init__(self, sf: StandardForm, robot: Robot, beta: float, g_fixed: Array | None, approach: int = 2):
        self.sf, self.unit = sf, robot.unit
        self.yaw_name = robot.joint_names[0]
        self.roll = sf.n == 5
        self.s1 = int(sf.twist(0) or 1)
        self.beta = beta                     # angle of the approach axis in joint 4's frame
        self.g_fixed = g_fixed               # four joints: the tool point in joint 4's frame
        self.approach = approach             # four joints: the tool frame's axis that is the approach (2: z, 0: x)
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
        axis = _approach_axis(sf.tool)
        a = sf.tool[:3, axis]           # its angle in the arm's plane (the part along the pitch axes drops out)
        return cls(sf, robot, math.atan2(a[1], a[0]), sf.tool[:3, 3].copy(), axis)

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
            a_tool = np.eye(3)[solver.approach if solver is not None else 2]
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
_DIRECTION_NAMES = frozenset({"_VERTICAL", "_NEAR_VERTICAL", "_ROLL_SWEEP", "_direction_check", "_direction_residual",
                              "_polish_direction", "direction_to_pitch", "_roll_candidates", "solve_direction"})


_POSITION_NAMES = frozenset({"position_ik", "position_route"})
if TYPE_CHECKING:   # the names __getattr__ gives, with their types
    from .yaw_pitch3_position import position_ik, position_route  # noqa: F401


def __getattr__(name: str) -> Any:
    """The direction part lives in :mod:`.yaw_pitch3_direction`, the position alone in :mod:`.yaw_pitch3_position`
    (both use this module): loaded on first use; a position name is then kept here (no second lookup)."""
    if name in _DIRECTION_NAMES:
        from . import yaw_pitch3_direction

        return getattr(yaw_pitch3_direction, name)
    if name in _POSITION_NAMES:
        from . import yaw_pitch3_position

        value = globals()[name] = getattr(yaw_pitch3_position, name)
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


# ------------------------------------------------------------------------ the compiled fast path (issue 20)
_FAST_MODULE = "ik.analytic._yaw_pitch3_jit"


def fast_geometry(robot: Robot) -> Array | None:
    """The packed geometry of the compiled single-target kernels (:mod:`._yaw_pitch3_jit`), or None.

    None when the Numba back end is not in use, or ``robot`` is not a 5-joint revolute yaw-pitch3
    arm with finite limits. Built once per robot (kept in ``robot.cache``).
    """
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
