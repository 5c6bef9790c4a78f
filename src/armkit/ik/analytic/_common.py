"""Pieces every closed-form solver shares: the model in standard-DH form, the planar
two-link problem, elbow labels and the raw-solution container.

Every closed-form family works on the robot rewritten as

.. math:: T_{world\\_tool} = B' \\, \\prod_i R_z(q_i + \\theta_i) T_z(d_i) T_x(a_i) R_x(\\alpha_i) \\, T'

(standard DH), where a modified-DH model moves its first ``Rx(alpha_0) Tx(a_0)`` into
``B'`` and shifts ``a, alpha`` down one row, and the last row's constant
``Tx(a_n) Rx(alpha_n)`` (it comes after the last joint's motion) moves into ``T'``.
A solver then only ever sees ``B'^{-1} T T'^{-1}``, the pose of the frame that turns
with the last joint, ``R_z(q_n + theta_n) T_z(d_n)`` after link ``n - 1``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np
from numpy.typing import NDArray

from ... import _jit_loader
from ...model.robot import Joint, Robot

Array = NDArray[np.float64]
HALF_PI = 0.5 * math.pi
ANGLE_TOL = 1e-9     # how close a DH twist must be to 0 or +-90 deg to count as one
LENGTH_TOL = 1e-12   # relative to the arm's reach: a DH length this small counts as zero
IDEAL_ANGLE_TOL = 1e-4    # rad: a twist this close to a multiple of 90 deg is rounding in the file (rpy 1.5708)
IDEAL_LENGTH_TOL = 1e-5   # of the reach: a DH length this small is rounding (a 4e-17 offset), not geometry
IDEAL_PARALLEL_TOL = 1e-4  # axes whose angle has a sine below this are taken as parallel for the ideal arm


def jit_kernels():
    """The module of Numba kernels (:mod:`._jit`) while the Numba back end is in use, else ``None``."""
    return _jit_loader.kernels("ik.analytic._jit")


def _rx(t: float) -> Array:
    c, s = math.cos(t), math.sin(t)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def _txyz(x: float = 0.0, y: float = 0.0, z: float = 0.0) -> Array:
    T = np.eye(4)
    T[:3, 3] = (x, y, z)
    return T


def inverse_pose(T: Array) -> Array:
    """Inverse of one rigid 4x4 pose (``R^T``, exact)."""
    out = np.eye(4)
    out[:3, :3] = T[:3, :3].T
    out[:3, 3] = -T[:3, :3].T @ T[:3, 3]
    return out


def _half_turned(angle: float) -> float:
    """``angle + pi`` in ``(-pi, pi]``; exactly ``k pi/2`` where ``angle`` is exactly a multiple of 90 deg."""
    k = round(angle / HALF_PI)
    if angle == k * HALF_PI:
        j = (k + 2) % 4
        return (j if j < 3 else -1) * HALF_PI
    return math.remainder(angle + math.pi, 2 * math.pi)


@dataclass(frozen=True)
class StandardForm:
    """The robot as standard-DH rows with the last row's ``a, alpha`` moved into the tool.

    ``theta, d, a, alpha`` are ``(n,)`` arrays; ``base`` is ``B'`` and ``tool`` is ``T'``
    (see the module docstring); ``scale`` is a length typical of the arm (its reach).
    """

    theta: Array
    d: Array
    a: Array
    alpha: Array
    base: Array
    tool: Array
    base_inv: Array
    tool_inv: Array
    scale: float
    exact: bool = True
    """False when this is the nearby *ideal* arm (values snapped within the IDEAL_* tolerances):
    branches are then polished by Newton steps on the true model (``solve_all``)."""

    def as_robot(self, like: Robot, name: str) -> Robot:
        """This arm as a standard-DH :class:`Robot` with the joint names and limits of ``like`` (the robot it was
        made from, revolute joints): the same joint values, its own FK (the ideal arm's, for a file's)."""
        return Robot([Joint(theta=float(self.theta[k]), d=float(self.d[k]), a=float(self.a[k]),
                            alpha=float(self.alpha[k]), lower=float(like.lower[k]), upper=float(like.upper[k]),
                            name=like.joint_names[k]) for k in range(self.n)],
                     name=name, base=self.base, tool=self.tool)

    @property
    def n(self) -> int:
        return len(self.theta)

    def is_zero(self, length: float) -> bool:
        return abs(length) <= LENGTH_TOL * self.scale

    def twist(self, i: int) -> int | None:
        """``0`` for alpha = 0, ``+1``/``-1`` for alpha = +-90 deg, ``None`` otherwise."""
        al = math.remainder(float(self.alpha[i]), 2 * math.pi)
        if abs(al) < ANGLE_TOL:
            return 0
        if abs(al - HALF_PI) < ANGLE_TOL:
            return 1
        if abs(al + HALF_PI) < ANGLE_TOL:
            return -1
        return None

    def half_turn(self, i: int) -> bool:
        """Whether twist ``i`` is 180 deg: axes ``i`` and ``i + 1`` parallel and opposite (a file that reverses one)."""
        return abs(math.remainder(float(self.alpha[i]) - math.pi, 2 * math.pi)) < ANGLE_TOL

    def reversed_joint(self, i: int) -> "StandardForm":
        """The same arm with joint ``i``'s axis reversed (``0 < i``): its DH angle ``phi_i = q_i + theta_i`` is
        minus the one of this arm, and the twist before it turns by pi. As ``R_x(pi) R_z(phi) = R_z(-phi) R_x(pi)``
        and ``R_x(pi) T_z(d) = T_z(-d) R_x(pi)``,

        ``R_x(alpha_{i-1}) R_z(phi_i) T_z(d_i) T_x(a_i) R_x(alpha_i)
        = R_x(alpha_{i-1} - pi) R_z(-phi_i) T_z(-d_i) T_x(a_i) R_x(alpha_i + pi)``;

        so ``theta_i, d_i`` change sign and ``alpha_{i-1}, alpha_i`` turn by pi (the last joint's ``R_x(pi)``
        goes into the tool). A Kinova Jaco2 (``alpha_2 = 180`` deg) so becomes a Puma-like arm.
        """
        theta, d, alpha = self.theta.copy(), self.d.copy(), self.alpha.copy()
        theta[i], d[i] = -theta[i], -d[i]
        alpha[i - 1] = _half_turned(alpha[i - 1])
        tool, tool_inv = self.tool, self.tool_inv
        if i == self.n - 1:
            tool = _rx(math.pi) @ tool
            tool_inv = inverse_pose(tool)
        else:
            alpha[i] = _half_turned(alpha[i])
        return StandardForm(theta, d, self.a, alpha, self.base, tool, self.base_inv, tool_inv, self.scale, self.exact)

    def turned_back(self, joints: tuple[int, ...]) -> "tuple[StandardForm, tuple[int, ...]] | None":
        """The arm with each of ``joints`` (0-based, in order) whose twist before it is 180 deg turned back
        (:meth:`reversed_joint`), and those joints numbered from 1 (the family's kernel negates their DH angles;
        ``armkit info`` names them); None where none is.

        Exact arms only. On the nearby ideal arm of a file with rounded numbers (the Kinova's URDF, twists 4.9e-12
        off) every branch of a DH family would take the Gauss-Newton touch-up on the true arm (compiled since the
        tenth session of 2026-12-06, ~1 µs a branch: a rounded Puma's ``ik_all`` takes 15-17 µs), where the
        geometric family, which answers such an arm, solves on the file's own axes (5-6 µs).
        """
        if not self.exact:
            return None
        work, back = self, []
        for i in joints:
            if work.half_turn(i - 1):
                work = work.reversed_joint(i)
                back.append(i + 1)
        return (work, tuple(back)) if back else None

    def to_chain(self, T: Array) -> Array:
        """World targets ``(..., 4, 4)`` -> poses of the last turning frame in ``B'``."""
        return self.base_inv @ T @ self.tool_inv

    def point_to_chain(self, p: Array) -> Array:
        """World points ``(..., 3)`` -> the same points in ``B'``."""
        return p @ self.base_inv[:3, :3].T + self.base_inv[:3, 3]


ROUND_OFF = 4.0 * float(np.finfo(float).eps)
"""A twist this close (relative) to a multiple of 90 deg is that multiple up to floating-point round-off: a
URDF axis reversed gives a DH twist of -pi/2 one ulp off. Snapping it does not make the arm an ideal one."""


def _snap(values: Array, step: float, tol: float) -> tuple[Array, bool]:
    """Values within ``tol`` of a multiple of ``step`` (or of 0 when ``step`` is 0) set exactly there, and
    whether any moved (by more than :data:`ROUND_OFF`, relative, for a multiple of a nonzero ``step``)."""
    if step:
        k = np.round(values / step)
        near = np.abs(values - k * step) <= tol
        exact_multiple = np.where(near, k * step, values)   # k * (pi/2) is exact for the k that occur
        moved = np.abs(exact_multiple - values) > ROUND_OFF * np.maximum(np.abs(values), 1.0)
        return exact_multiple, bool(np.any(moved))
    else:
        near = np.abs(values) <= tol
        exact_multiple = np.where(near, 0.0, values)
    changed = bool(np.any(exact_multiple != values))
    return exact_multiple, changed


def standard_form(robot: Robot) -> StandardForm | None:
    """The robot in :class:`StandardForm`, or ``None`` if it has a prismatic joint.

    Real robot files round their numbers (URDF ``rpy="1.5708 0 0"`` for 90 deg, offsets of
    4e-17): twists within :data:`IDEAL_ANGLE_TOL` of a multiple of 90 deg and lengths within
    :data:`IDEAL_LENGTH_TOL` of the reach are snapped, giving the nearby ideal arm
    (``exact=False``) on which the families are detected and solved; every branch is then
    polished on the true model and judged by its FK. A URDF chain goes through its ideal
    DH twin (nearly parallel axes, sine below :data:`IDEAL_PARALLEL_TOL`, taken as parallel).
    """
    if robot.prismatic.any():
        return None
    exact = True
    if not robot.is_dh:
        from ...model.dh_extract import chain_to_dh

        robot_dh = chain_to_dh(robot, "standard", IDEAL_PARALLEL_TOL, IDEAL_LENGTH_TOL, check=False)
        twin = chain_to_dh(robot, "standard", check=False)
        exact = bool(np.array_equal(twin.dh_table(), robot_dh.dh_table()))
        sf = _standard_form_dh(robot_dh, max(robot.reach, 1e-300))
    else:
        sf = _standard_form_dh(robot, max(robot.reach, 1e-300))
    alpha, moved_a = _snap(sf.alpha, HALF_PI, IDEAL_ANGLE_TOL)
    a, moved_l = _snap(sf.a, 0.0, IDEAL_LENGTH_TOL * sf.scale)
    d, moved_d = _snap(sf.d, 0.0, IDEAL_LENGTH_TOL * sf.scale)
    exact = exact and not (moved_a or moved_l or moved_d)
    if exact:
        return sf
    return StandardForm(sf.theta, d, a, alpha, sf.base, sf.tool, sf.base_inv, sf.tool_inv, sf.scale, exact=False)


def _standard_form_dh(robot: Robot, scale: float) -> StandardForm:
    js = robot.joints
    n = len(js)
    theta = np.array([j.theta for j in js])
    d = np.array([j.d for j in js])
    if robot.convention == "standard":
        a = np.array([j.a for j in js])
        alpha = np.array([j.alpha for j in js])
        base = np.asarray(robot.base, dtype=float).copy()
    else:  # modified: Rx(alpha_{i-1}) Tx(a_{i-1}) Rz Tz  ->  prefix, then standard rows
        a = np.array([js[i + 1].a if i + 1 < n else 0.0 for i in range(n)])
        alpha = np.array([js[i + 1].alpha if i + 1 < n else 0.0 for i in range(n)])
        base = np.asarray(robot.base, dtype=float) @ _rx(js[0].alpha) @ _txyz(js[0].a)
    tool = _txyz(a[-1]) @ _rx(alpha[-1]) @ np.asarray(robot.tool, dtype=float)
    a[-1] = 0.0
    alpha[-1] = 0.0
    return StandardForm(theta, d, a, alpha, base, tool, inverse_pose(base), inverse_pose(tool), scale)


def keep_better(branches: tuple[Array, Array, Array, NDArray[np.bool_], NDArray[np.bool_]], bi: NDArray[np.intp],
                mi: NDArray[np.intp], polished: tuple[Array, Array, Array, NDArray[np.bool_], NDArray[np.bool_]],
                scale: float) -> tuple[Array, Array, Array, NDArray[np.bool_], NDArray[np.bool_]]:
    """Put polished branches back where they lower the FK error (position / ``scale`` + rotation).

    ``branches`` is ``(q, dp, dr, ok, within)`` of every branch, ``(B, m, ...)``; ``polished``
    the same fields for the branches ``[bi, mi]`` after Newton steps. Returns new arrays
    (the inputs are not changed).
    """
    q, dp, dr, ok, within = branches
    qc, dpn, drn, okn, wn = polished
    better = dpn / scale + drn < dp[bi, mi] / scale + dr[bi, mi]
    bi, mi = bi[better], mi[better]
    q, dp, dr, ok, within = q.copy(), dp.copy(), dr.copy(), ok.copy(), within.copy()
    q[bi, mi], dp[bi, mi], dr[bi, mi] = qc[better], dpn[better], drn[better]
    ok[bi, mi], within[bi, mi] = okn[better], wn[better]
    return q, dp, dr, ok, within


def two_link(x: Array, y: Array, l1: float, l2: float) -> tuple[Array, Array, Array, Array]:
    """Both solutions of the planar two-link problem ``l1 e(t1) + l2 e(t1 + t2) = (x, y)``.

    Lengths may be signed (the UR arms have negative ``a``). Uses
    ``cos t2 = (x^2 + y^2 - l1^2 - l2^2) / (2 l1 l2)`` and
    ``t1 = atan2(y, x) - atan2(l2 sin t2, l1 + l2 cos t2)`` (the second ``atan2`` takes
    the sine part first: the homogeneous-transform seminar swaps these arguments, which is wrong).

    Returns
    -------
    t1, t2 : ndarray, shape (..., 2)
        Index 0 has ``sin t2 >= 0``, index 1 ``sin t2 <= 0``. Out of reach, ``cos t2`` is
        clipped to +-1, which gives the closest configuration (stretched or folded
        towards the target).
    c : ndarray, shape (...)
        The unclipped ``cos t2``: ``> 1`` outside the outer circle, ``< -1`` inside the inner one.
    r : ndarray, shape (...)
        Distance of the target from the first axis.
    """
    r2 = x * x + y * y
    c = (r2 - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)
    cc = np.clip(c, -1.0, 1.0)
    s = np.sqrt((1.0 - cc) * (1.0 + cc))
    t2 = np.stack([np.arctan2(s, cc), np.arctan2(-s, cc)], axis=-1)
    s2 = np.stack([s, -s], axis=-1)
    t1 = np.arctan2(y, x)[..., None] - np.arctan2(l2 * s2, l1 + l2 * cc[..., None])
    return t1, t2, c, np.sqrt(r2)


def elbow_up(forward: Array, up_sign: float, l1: float, l2: float, elbow_index: NDArray[np.int_]
             ) -> NDArray[np.bool_]:
    """True where the elbow lies above the line from the shoulder to the target.

    ``forward`` (+-1) is the sign of the target's coordinate along the plane's horizontal
    axis, ``up_sign`` (+-1) maps the plane's second axis to "up". With the target
    ``t = l1 e(t1) + l2 e(t1 + t2)`` and the elbow ``e = l1 e(t1)``, the elbow is above the
    line when ``forward * up_sign * (t x e) > 0``, and ``t x e = -l1 l2 sin t2``. The sign of
    ``sin t2`` is taken from the branch index (0: +, 1: -) so that the two branches keep
    different labels even where they coincide (stretched, folded).
    """
    e = np.where(elbow_index == 0, 1.0, -1.0)
    return np.asarray(-forward * up_sign * math.copysign(1.0, l1 * l2) * e > 0)


def forward_sign(x: Array, default: Array | float = 1.0) -> Array:
    """``sign(x)``, with ``default`` where ``x == 0``."""
    return np.where(x > 0, 1.0, np.where(x < 0, -1.0, default))


class Built:
    """The part of :class:`~armkit.ik.analytic.ClosedFormFamily` shared by the solvers built for a call rather than
    detected from a robot's structure (joints held, :mod:`.held` and :mod:`armkit.ik.geometric.locked`; a sweep)."""

    polish_above = math.inf
    """No Gauss-Newton touch-up in :func:`~armkit.ik.analytic.solve_all`: it would move the held joints."""

    @classmethod
    def detect(cls, sf: Any, robot: Any) -> None:
        """Never detected from a robot's structure: built where ``fixed=``, a sweep or a held wrist asks for it."""
        return None

    @property
    def geometry(self) -> None:
        """No one-call kernel of its own."""
        return None


@dataclass
class Raw:
    """What a family solver returns before wrapping, verification and sorting.

    q : (B, m, n) joint values (DH offsets already removed, not yet wrapped)
    label : (B, m) object array of branch labels
    unreachable : (B, m) bool, the geometry had to be clipped (target out of reach)
    why : callable, flat index into (B, m) -> sentence: why that branch is out of reach
        (called only where ``unreachable``, and only for a moderate number of branches)
    note : (B, m) object array: what a user should know about a solution (free yaw, ...)
    missing : (B, m) bool, optional: the branch has no solution for this target at all (a solver whose
        number of solutions varies fills the rest with a copy); failed whatever FK of its q says
    """

    q: Array
    label: NDArray[np.object_]
    unreachable: NDArray[np.bool_]
    why: Callable[[int], str]
    note: NDArray[np.object_]
    missing: NDArray[np.bool_] | None = None


def fmt_len(x: float, unit: str) -> str:
    return f"{x:.6g} {unit}"


def add_messages(message: NDArray[np.object_], where: NDArray[np.bool_], make, first: bool = False) -> None:
    """``message[i] += make(i)`` (or prepend, with ``first``) for the (few) flat indices where ``where`` is true."""
    flat = message.reshape(-1)
    for i in np.flatnonzero(where.reshape(-1)):
        text = make(i)
        flat[i] = text if not flat[i] else (text + " " + flat[i] if first else flat[i] + " " + text)


def out_of_reach(what: str, r: float, unit: str, outer: float, inner: float) -> str:
    """The sentence for a target outside the shoulder's reach shell (2R and yaw-pitch-pitch arms)."""
    return (f"{what} is {r:.6g} {unit} from the shoulder; the arm reaches {outer:.6g} {unit} (outer) "
            f"and {inner:.6g} {unit} (inner).")


def elbow_edge(c: float) -> str:
    """The note for a target on the reach boundary, from the elbow's cosine ``c`` (+1 stretched, -1 folded)."""
    return ("fully stretched: elbow-up and elbow-down coincide." if c > 0
            else "fully folded: elbow-up and elbow-down coincide.")


def rotate_back(v: list, phi: Array, alpha: float) -> list:
    """``Rx(-alpha) Rz(-phi) v`` (the transpose of ``Rz(phi) Rx(alpha)``) for vectors given as a list of
    three component arrays, broadcast with ``phi``."""
    c, s = np.cos(phi), np.sin(phi)
    ca, sa = math.cos(alpha), math.sin(alpha)
    x = c * v[0] + s * v[1]
    y = -s * v[0] + c * v[1]
    return [x, ca * y + sa * v[2], -sa * y + ca * v[2]]
