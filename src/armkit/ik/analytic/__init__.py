"""Closed-form inverse kinematics: every branch, detected from the robot's structure.

One module per family of arms:

================  ===========================================  ========  =====================
family            structure (from the DH model, not the name)  branches  bundled example
================  ===========================================  ========  =====================
planar-2r         2R, parallel axes                            2         planar2
planar-3r         3R, parallel axes, pose target (phi)         2         planar3
yaw-pitch-pitch   3R, vertical axis then two parallel axes     4         fighter
spherical-wrist   6R, Puma-like arm, axes 4-6 meet in a point  8         puma560
ur                6R, axes 2-4 parallel, UR-type offsets       8         ur5
yaw-pitch3        4R/5R: yaw, 3 parallel pitch axes (+ roll),  4         so101
                  target: position + tool pitch (pitch=)
================  ===========================================  ========  =====================

:func:`closed_form` finds the family of a robot; :func:`solve_all` runs it on a batch of
targets and turns its raw output into an :class:`~armkit.ik.result.IKResult` with a
branch axis: joint values wrapped by 2 pi into the limits (the representative nearest
``q0``), every branch checked by forward kinematics (:func:`~armkit.ik.result.verify`),
then sorted: successful branches first, each group by distance to ``q0``.
:func:`single_call` does the same for ONE target in one compiled call (:mod:`._single`),
the path ``armkit.ik_all`` and ``armkit.ik`` take for a single pose or position.
"""

from __future__ import annotations

import math
import sys
import threading
import weakref
from collections import deque
from dataclasses import replace
from typing import Any, Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from ... import _jit_loader
from ..._text import Fielded
from ...errors import ArmkitError
from ...kinematics import fk, jacobian, packed
from ...model.robot import Robot
from ...spatial import inverse
from ..result import IKResult, _message as _message_of, _result_of, default_tolerance, verify
from ._common import Raw, StandardForm, jit_kernels, keep_better, standard_form
from ._layout import LABEL_SHIFT, NEAREST, joint_table
from .geometric import MANY, Geometric, Geometric1R, Geometric2R, Geometric3R, GeometricGimbal, has_batch_form
from .geometric_prismatic import GeometricPrismatic, GeometricPrismaticWrist, GeometricScara
from .planar import Planar2R, Planar3R
from .spherical_wrist import SphericalWrist
from .ur import ParallelAxes
from .yaw_pitch3 import YawPitch3
from .yaw_pitch_pitch import YawPitchPitch

__all__ = ["ClosedFormFamily", "ClosedForm", "closed_form", "solve_all", "wrap_to_limits", "FAMILIES"]

Array = NDArray[np.float64]
TWO_PI = 2.0 * math.pi
_REASON_TEXT = np.array(["converged", "unreachable", "joint limits"])


@runtime_checkable
class ClosedFormFamily(Protocol):
    """The contract of a closed-form family: what :func:`closed_form`, :func:`solve_all` and
    :func:`solve_nearest` use (``docs/ik.md``, "Adding a closed-form family").

    An instance is the solver for one robot (kept in ``robot.cache["closed_form"]``), so what
    it computes once (``geometry``) is computed once per robot.
    """

    family: str
    """The name users see (``"ur"``, ``"planar-2r"``, ...), unique among :data:`FAMILIES`."""
    branch_labels: tuple[str, ...]
    """The one label table: the NumPy and the Numba path both give indices into it (``Raw.label``)."""
    m: int
    """Branches per target, ``len(branch_labels)``."""
    pose_only: bool
    """True when a position alone does not fix the closed form (a pose, ``phi=`` or ``pitch=`` needed)."""
    target_kind: str
    """What a target gives the closed form: ``"position"`` (a position fixes it), ``"pose"`` (a ``(4, 4)`` pose;
    planar-3r also takes ``phi=``) or ``"pitch"`` (a position and the tool pitch, ``pitch=``: :meth:`solve` gets
    ``(B, 4)`` rows ``(x, y, z, pitch)``). ``pose_only`` is ``target_kind != "position"``."""
    sf: StandardForm
    """The robot in standard-DH form (:func:`._common.standard_form`), on which the family was detected."""

    @classmethod
    def detect(cls, sf: StandardForm, robot: Robot) -> "ClosedFormFamily | None":
        """The solver for ``robot`` when its structure is this family's, else None (from the DH model, never the name)."""

    @property
    def geometry(self) -> Array | None:
        """The packed float64 geometry of the family's Numba kernel (layout in :mod:`._layout`), built once;
        None for a family solved by NumPy only."""

    def solve(self, target: Array, q0phi: Array) -> Raw:
        """Every branch for targets ``(B, 4, 4)`` or ``(B, 3)``; ``q0phi`` ``(B, n)`` is ``q0`` plus the DH
        offsets theta (free joints take it). Returns DH angles ``(B, m, n)``, labels, clipped flags, notes."""


ClosedForm = ClosedFormFamily   # the name used before the contract was written down


FAMILIES = (Planar2R, Planar3R, YawPitchPitch, SphericalWrist, ParallelAxes, YawPitch3)


def closed_form(robot: Robot) -> ClosedForm | None:
    """The closed-form solver for ``robot``'s structure, or ``None`` when it has none.

    Examples
    --------
    >>> import armkit
    >>> [getattr(closed_form(armkit.load(n)), "family", None) for n in ("fighter", "puma560", "ur5", "panda")]
    ['yaw-pitch-pitch', 'spherical-wrist', 'ur', None]
    """
    # Detection costs ~40 µs; a Robot is immutable, so the answer is kept in its cache.
    try:
        return robot.cache["closed_form"]  # type: ignore[no-any-return]
    except KeyError:
        pass
    found: ClosedForm | None = None
    sf = standard_form(robot)
    if sf is not None:
        found = _hand_written(sf, robot)
    if found is not None and not found.sf.exact:   # the ideal arm of a file: solved on its own axes where it can be
        exact = _on_own_axes(robot, sf, found)
        found = found if exact is None else exact
    if found is None:      # any other arm whose axes allow it: subproblem decomposition (the geometric family)
        found = (_on_own_axes(robot, sf, None) or Geometric3R.detect(sf, robot)  # type: ignore[assignment]
                 or Geometric2R.detect(sf, robot) or Geometric1R.detect(sf, robot)
                 or GeometricGimbal.detect(sf, robot) or GeometricPrismatic.detect(sf, robot)
                 or GeometricPrismaticWrist.detect(sf, robot) or GeometricScara.detect(sf, robot))
    robot.cache["closed_form"] = found
    return found


def _hand_written(sf: StandardForm, robot: Robot) -> ClosedForm | None:
    """The first of :data:`FAMILIES` whose DH pattern ``sf`` has, or None."""
    for cls in FAMILIES:
        found = cls.detect(sf, robot)
        if found is not None:
            return found  # type: ignore[no-any-return]
    return None


def _on_own_axes(robot: Robot, sf: StandardForm | None, ideal: ClosedForm | None) -> Geometric | None:
    """The geometric family for ``robot`` with the branch names of a hand-written family, or None.

    ``ideal`` given (a hand-written family that matched the nearby ideal arm of a file, ``sf.exact`` False): the
    geometric family where it solves the file's own axes in closed form (a twist written ``rpy="1.5708"`` moves no
    axis off meeting or parallel when the class keeps holding: the Puma's, the UR5's), so that no branch needs the
    Gauss-Newton touch-up (~1 µs a branch: 13-15 µs against 4 µs a call), with ``ideal``'s branch names; else None
    (the hand-written family answers, every branch touched up). ``ideal`` None: the geometric family where it
    answers, named by the hand-written family of the arm's ideal DH twin where one matches it (the Kinova's URDF,
    twists 4.9e-12 off, whose DH table has joint 3 turned back)."""
    g = Geometric.detect(sf, robot)
    if g is None:
        return None
    if ideal is not None:
        if g.m != ideal.m or ideal.target_kind != "pose" or not g.solves_exactly():
            return None
        g.names_from = ideal
    elif sf is not None and not sf.exact:
        named = _hand_written(replace(sf, exact=True), robot)   # (exact: detected as the arm it is, turned back)
        if named is not None and named.m == g.m and named.target_kind == "pose":
            g.names_from = named
    return g


def wrap_to_limits(q: Array, q0: Array, lower: Array, upper: Array, revolute: NDArray[np.bool_]) -> Array:
    """Shift revolute joint values by multiples of 2 pi: inside the limits and nearest ``q0``.

    Where no shift brings a value inside its limits, the one nearest the middle of the
    limits is used (it stays outside; the caller reports "joint limits").

    Parameters
    ----------
    q, q0 : ndarray, shape (..., n), broadcastable
    lower, upper : ndarray, shape (n,)
    revolute : ndarray of bool, shape (n,)
    """
    tol = 1e-12
    q = np.asarray(q, dtype=float)
    near = np.where(revolute, q + TWO_PI * np.round((q0 - q) / TWO_PI), q)   # the turn nearest q0
    lo, hi = lower - tol, upper + tol
    out = (near < lo) | (near > hi)
    if out.any():   # nearest-to-q0 is outside: the in-limit turn nearest q0 is the one just inside
        idx = np.nonzero(out)
        j = idx[-1]
        v, lj, hj = near[idx], lo[j], hi[j]
        with np.errstate(invalid="ignore"):
            cand = v + TWO_PI * np.where(v < lj, np.ceil((lj - v) / TWO_PI), np.floor((hj - v) / TWO_PI))
            finite = np.isfinite(lj) & np.isfinite(hj)
            mid = np.where(finite, 0.5 * (np.where(finite, lj, 0.0) + np.where(finite, hj, 0.0)), v)
        fallback = v + TWO_PI * np.round((mid - v) / TWO_PI)
        near[idx] = np.where(~revolute[j], v, np.where((cand >= lj) & (cand <= hj), cand, fallback))
    return near


def _joint_table(robot: Robot, solver: ClosedForm):
    """The joint table of the wrap/pick kernels (``_layout.JOINT_*``), kept in the robot's cache."""
    table = robot.cache.get("closed_form_joints")
    if table is None:
        table = robot.cache["closed_form_joints"] = joint_table(solver.sf.theta, robot.lower, robot.upper,
                                                                robot.prismatic)
    return table


MAX_DETAILED = 10_000
"""Above this many failed branches in one call, messages name the cause without the distances (speed)."""


def _failure_messages(robot: Robot, message: NDArray[np.object_], code: NDArray[np.int_],
                      raw: Raw, q: Array, dp: Array, dr: Array, tol: tuple[float, float]) -> None:
    """Fill ``message`` in place for the failed branches (``code``: index into ``_REASON_TEXT``; 0 only where
    the branch succeeded). Each message keeps its template and fields (:class:`armkit._text.Fielded`)."""
    if code.size <= FEW:
        _few_failure_messages(robot, message, code, raw, q, dp, dr, tol)
        return
    limits = code == 2
    if limits.any():   # one message per pattern of violated joints, not per branch
        lo, hi = robot.lower - 1e-12, robot.upper + 1e-12
        ql = q[limits]
        bits = ((ql < lo) | (ql > hi)) @ (1 << np.arange(robot.n))
        if robot.n <= 16:   # a table indexed by the pattern (no sorting)
            texts = np.empty(1 << robot.n, dtype=object)
            patterns, inverse = np.flatnonzero(np.bincount(bits, minlength=1 << robot.n)), bits
        else:
            patterns, inverse = np.unique(bits, return_inverse=True)
            texts = np.empty(len(patterns), dtype=object)
        for k, pattern in enumerate(patterns):
            texts[pattern if robot.n <= 16 else k] = _limit_text(robot, [j for j in range(robot.n)
                                                                         if int(pattern) >> j & 1])
        message[limits] = texts[inverse.ravel()]
    unreachable = code == 1
    count = int(unreachable.sum())
    if count == 0:
        return
    if count > MAX_DETAILED:
        message[unreachable & raw.unreachable] = Fielded.of("unreachable: out of this branch's reach.")
        message[unreachable & ~raw.unreachable] = Fielded.of("unreachable: the closest configuration misses the "
                                                             "target.")
        return
    flat_msg, flat_out, flat_dp, flat_dr = message.reshape(-1), raw.unreachable.reshape(-1), dp.reshape(-1), dr.reshape(-1)
    for i in np.flatnonzero(unreachable.reshape(-1)):
        if flat_out[i]:
            flat_msg[i] = Fielded.of("unreachable: {why}", why=raw.why(int(i)))
        else:
            flat_msg[i] = _unreachable_text(robot, flat_dp[i], flat_dr[i], tol)


FEW = 64
"""Up to this many branches in one call, :func:`_failure_messages` loops in Python (a single target: NumPy's
per-call overhead on a few elements cost more than the messages); the same messages either way."""


def _unreachable_text(robot: Robot, dp: float, dr: float, tol: tuple[float, float]):
    return Fielded.of(
        "unreachable: the closest configuration of this branch misses the target by {distance} and {angle} "
        "(this arm cannot turn to that orientation there)." if dp <= tol[0] else
        "unreachable: the closest configuration of this branch misses the target by {distance} and {angle}.",
        distance=f"{dp:.3g} {robot.unit}", angle=f"{math.degrees(dr):.3g} deg")


def _few_failure_messages(robot: Robot, message: NDArray[np.object_], code: NDArray[np.int_],
                          raw: Raw, q: Array, dp: Array, dr: Array, tol: tuple[float, float]) -> None:
    """:func:`_failure_messages` for a few branches, element by element."""
    flat_code = code.reshape(-1).tolist()
    if not any(flat_code):
        return
    n = robot.n
    lo, hi = (robot.lower - 1e-12).tolist(), (robot.upper + 1e-12).tolist()
    flat_msg, flat_q = message.reshape(-1), q.reshape(-1, n)
    flat_dp, flat_dr = dp.reshape(-1), dr.reshape(-1)
    flat_out = None if raw is None else raw.unreachable.reshape(-1)   # (None: only limits asked, _limit_messages)
    limit_texts: dict[tuple[int, ...], Any] = {}
    for i, c in enumerate(flat_code):
        if c == 2:
            row = flat_q[i].tolist()
            key = tuple(j for j in range(n) if row[j] < lo[j] or row[j] > hi[j])
            text = limit_texts.get(key)
            if text is None:
                text = limit_texts[key] = _limit_text(robot, key)
            flat_msg[i] = text
        elif c == 1:
            flat_msg[i] = (Fielded.of("unreachable: {why}", why=raw.why(i)) if flat_out is not None and flat_out[i]
                           else _unreachable_text(robot, flat_dp[i], flat_dr[i], tol))


def _limit_text(robot: Robot, joints) -> Any:
    """The sentence of a branch outside the limits of ``joints`` (indices)."""
    return Fielded.of("outside the joint limits: {names} (see armkit info for the limits).",
                      names=", ".join(robot.joint_names[j] for j in joints))


POLISH_ABOVE = 1e-13
"""Branches whose FK error exceeds this (relative to reach, or rad) get a Gauss-Newton touch-up. A family
may set its own ``polish_above`` (the geometric family polishes on the true chain itself: 1e-12)."""
POLISH_WINDOW = (1e-6, 6e-3)
"""Branches this close (relative to reach, and rad) are polished: exact model, and the ideal arm of a real file."""


POLISH_DONE = 1e-14
"""A Gauss-Newton step of the touch-up no larger than this (rad, or length units) ends it: Newton's steps shrink
quadratically (a branch of the ideal arm of a file with rpy 1.5708: ~1e-5, 1e-10, 1e-15), so the next would move
``q`` by rounding only. A Puma export with its joint origins turned by up to 1e-5 rad took all six: its ``ik_all``
1.3 ms a call, 0.66 ms with this stop (and :func:`_small_log`)."""


def _small_log(R: Array) -> Array:
    """Rotation vectors of rotations ``(k, 3, 3)`` by less than 90 deg (the touch-up's, within its 6e-3 rad window):
    ``(R - R^T) / 2 = sin(t) [u]x`` gives ``u sin t``, and ``t = asin |u sin t|``. Exact to rounding where scipy's
    quaternion route (:func:`armkit.spatial.so3_log`) costs ~0.1 ms a call."""
    v = 0.5 * np.stack([R[:, 2, 1] - R[:, 1, 2], R[:, 0, 2] - R[:, 2, 0], R[:, 1, 0] - R[:, 0, 1]], axis=-1)
    s = np.linalg.norm(v, axis=-1)
    ratio = np.divide(np.arcsin(np.minimum(s, 1.0)), s, out=np.ones_like(s), where=s > 0.0)
    return v * ratio[:, None]


def _steps(ideal: bool) -> int:
    """The most Gauss-Newton steps of the touch-up: six for the branches of a file's ideal arm, two else."""
    return 6 if ideal else 2


def _gauss_newton(robot: Robot, qc: Array, tgt: Array, pose: bool, steps: int) -> Array:
    """The touch-up's steps for the rows ``qc`` (k, n) towards ``tgt`` (k, 4, 4) or (k, 3), in NumPy (the least-
    squares step of ``pinv``), all rows at once until the largest step is :data:`POLISH_DONE` or less."""
    for _ in range(steps):
        T = fk(robot, qc)
        J = jacobian(robot, qc)
        p_t = tgt[:, :3, 3] if tgt.ndim == 3 else tgt
        e = p_t - T[:, :3, 3]
        if pose:
            w = _small_log(tgt[:, :3, :3] @ np.swapaxes(T[:, :3, :3], -1, -2))
            e = np.concatenate([e, w], axis=-1)
        else:
            J = J[:, :3]
        step = np.einsum("bij,bj->bi", np.linalg.pinv(J, rcond=1e-10), e)
        qc = qc + step
        if np.abs(step).max() <= POLISH_DONE:   # converged: a further step would move q by rounding only
            break
    return qc


RETARGET_ROUNDS, RETARGET_WINDOW = 4, 1e-3
"""Rounds of :func:`_retarget` (each moves a branch ~1e-5 times as far as the one before on a file that rounds its
twists by 3.7e-6 rad, so four leave it well inside the touch-up's reach), and the failing branches it takes up: FK
errors within this (of the reach, and rad). On 10,000 targets of files with rounded twists the branches it turned
into solutions missed by up to 2e-6 (the UR5) and 2.9e-4 (the Puma: a fold of the shoulder and the elbow at once);
720 of the UR5's 776 failing branches missed by more than 1e-5 and were out of reach, 580 by more than 1e-3 (the
one-call path leaves only the targets within it to the batched path)."""


def _touch_up(robot: Robot, qc: Array, tgt: Array, pose: bool, steps: int) -> tuple[Array, NDArray[np.bool_]]:
    """At most ``steps`` Gauss-Newton steps for the rows ``qc`` (k, n) towards ``tgt`` (k, 4, 4) or (k, 3), in place:
    compiled row by row with the Numba back end (:func:`._single._touch_up`, the one-call path's bits), by
    :func:`_gauss_newton` for the rows it refuses (every row with the NumPy back end, a system that is not square,
    a value not finite). Returns ``(qc, refused)``, ``refused`` (k,) bool."""
    rest = np.ones(len(qc), dtype=bool)
    one = _jit_loader.kernels("ik.analytic._single")
    if one is not None and robot.n == (6 if pose else 3):
        if tgt.ndim == 3:
            T = np.ascontiguousarray(tgt)
        else:   # a point: column 3 of a pose, as the one-call kernels hold it
            T = np.zeros((len(tgt), 4, 4))
            T[:, :3, 3] = tgt
        rest = one.touch_up_rows(packed(robot)[0], qc, T, pose, steps, POLISH_DONE)
    if rest.any():
        qc[rest] = _gauss_newton(robot, qc[rest], tgt[rest], pose, steps)
    return qc, rest


def _retarget(robot: Robot, branches: tuple, target: Array, position_only: bool, tol: tuple[float, float],
              enforce_limits: bool, solver: ClosedForm, q0: Array, labels: NDArray[np.str_]) -> tuple:
    """Branches of a file's ideal arm that the touch-up left failing (within :data:`RETARGET_WINDOW`), solved again
    in closed form for a target moved by the two arms' difference.

    Where the ideal arm misses a target by a hair (the wrist centre a micrometre inside the shoulder's sideways
    offset on the true arm, outside it on the ideal one), its branches are clipped onto a fold between two
    solutions, where the Jacobian loses rank and Newton's steps cannot choose a side. But where the true arm reaches
    ``T`` at ``q*``, the ideal arm reaches ``T E(q*)``, ``E(q) = FK_true(q)^-1 FK_ideal(q)`` (a point target:
    ``p + p_ideal(q) - p_true(q)``), which the closed form solves, every branch by its name: so each such branch is
    solved for ``T E(q)`` at its latest ``q``, :data:`RETARGET_ROUNDS` rounds (``E`` changes ~1e-5 as fast as
    ``q`` does), then touched up on the true arm and kept where it passes the FK check (a target out of reach stays
    as it was). ``labels`` (B, m): the branches' names as the solve gave them. The one-call path leaves every
    target with such a branch to this path. Returns ``branches`` (``(q, dp, dr, ok, within)``), new arrays where one
    changed. A few targets in a thousand on a Puma of a file with ``rpy="1.5708"``: 50 branches of 80,000 that EAIK
    finds, 0 after."""
    q, dp, dr, ok, within = branches
    scale = robot.reach
    stuck = ~((dp <= tol[0]) & (dr <= tol[1])) & (dp <= RETARGET_WINDOW * scale) & (dr <= RETARGET_WINDOW)
    if not stuck.any():
        return branches

    sf = solver.sf
    ideal = robot.cache.get("ideal_arm")
    if ideal is None:   # the ideal arm as a DH table (the solver's): its FK for the same joint values
        ideal = robot.cache["ideal_arm"] = sf.as_robot(robot, f"{robot.name}, ideal arm")
    bi, mi = np.nonzero(stuck)
    qs, aim, want = q[bi, mi].copy(), target[bi], labels[bi, mi]
    rows = np.arange(len(bi))
    revolute = ~robot.prismatic
    for _ in range(RETARGET_ROUNDS):
        Tt, Ti = fk(robot, qs), fk(ideal, qs)
        moved = aim + Ti[:, :3, 3] - Tt[:, :3, 3] if aim.ndim == 2 else aim @ inverse(Tt) @ Ti
        raw = solver.solve(moved, q0[bi] + sf.theta)
        same = raw.label == want[:, None]
        j = np.argmax(same, axis=1)
        new = raw.q[rows, j] - sf.theta
        new = np.where(revolute, new + 2 * math.pi * np.round((qs - new) / (2 * math.pi)), new)   # the same turn
        qs = np.where(same.any(axis=1)[:, None], new, qs)
    pose = aim.ndim == 3 and not position_only
    qs = _touch_up(robot, qs, aim, pose, _steps(True))[0]
    dpn, drn, okn, wn = verify(robot, qs, aim, position_only, tol, enforce_limits)
    good = (dpn <= tol[0]) & (drn <= tol[1])
    return keep_better((q, dp, dr, ok, within), bi[good], mi[good], (qs[good], dpn[good], drn[good], okn[good],
                                                                       wn[good]), scale)


def _polish(robot: Robot, branches: tuple, target: Array, position_only: bool, tol: tuple[float, float],
            enforce_limits: bool, ideal: bool = False, above: float = POLISH_ABOVE, retarget: tuple | None = None):
    """A few Gauss-Newton steps on the true model for the branches that are close but not exact.

    ``branches`` is ``(q, dp, dr, ok, within)`` ``(B, m, ...)``, returned anew (see :func:`._common.keep_better`).

    Near a singularity (e.g. the UR wrist at ``sin q5 ~ 1e-5``) a joint angle is ill-conditioned
    and the closed form can be ~1e-12 off; two Newton steps from there restore full precision.
    When the closed form was solved on the nearby ideal arm of a real file (``ideal``; see
    :func:`._common.standard_form`), branches within 6e-3 (of the reach, and rad) get up to
    six steps. A step is kept only where it makes the FK error smaller; success is still
    judged by FK of the true model.
    """
    if above == math.inf:     # no branch is above it (a family that polishes itself, e.g. a sweep's 32 x 8 branches)
        return branches

    q, dp, dr, ok, within = branches
    scale = robot.reach
    window = POLISH_WINDOW[ideal]
    cand = (dp <= window * scale) & (dr <= window) & ((dp > above * scale) | (dr > above))
    if not cand.any():
        return q, dp, dr, ok, within
    bi, mi = np.nonzero(cand)
    tgt = target[bi]
    qc = q[bi, mi].copy()
    pose = tgt.ndim == 3 and not position_only
    qc, rest = _touch_up(robot, qc, tgt, pose, _steps(ideal))
    dpn, drn, okn, wn = verify(robot, qc, tgt, position_only, tol, enforce_limits)
    out = keep_better((q, dp, dr, ok, within), bi, mi, (qc, dpn, drn, okn, wn), scale)
    if ideal and retarget is not None:   # (solver, q0, labels): see _retarget
        out = _retarget(robot, out, target, position_only, tol, enforce_limits, *retarget)
    return out


def solve_all(robot: Robot, solver: ClosedForm, target: Array, q0: Array, position_only: bool,
              tol: tuple[float, float] | None = None, enforce_limits: bool = True) -> IKResult:
    """Every branch of the closed form for targets ``(B, 4, 4)`` or ``(B, 3)``; ``q0`` ``(B, n)``.

    Returns an :class:`IKResult` with fields ``(B, m)`` and ``q`` ``(B, m, n)``.
    """
    theta = solver.sf.theta
    target = target.copy()   # the branches' sentences are made later, from this copy (a caller may reuse its array)
    named_later = _names_later(solver)
    raw = _solve_raw(solver, target, q0 + theta)
    jit = jit_kernels()
    dist = None
    if jit is not None:
        q, dist = jit.wrap_dist(raw.q, _joint_table(robot, solver), q0)
    else:
        q = wrap_to_limits(raw.q - theta, q0[:, None, :], robot.lower, robot.upper, ~robot.prismatic)
    if tol is None:
        tol = default_tolerance(robot)
    dp, dr, ok, within = verify(robot, q, target[:, None], position_only, tol, enforce_limits)
    q_before = q
    q, dp, dr, ok, within = _polish(robot, (q, dp, dr, ok, within), target, position_only, tol, enforce_limits,
                                    ideal=not solver.sf.exact, above=getattr(solver, "polish_above", POLISH_ABOVE),
                                    retarget=None if solver.sf.exact else (solver, q0, raw.label))
    if dist is None:
        dist = np.linalg.norm(np.where(robot.prismatic, 0.0, q - q0[:, None, :]), axis=-1)
    elif q is not q_before:   # polished branches: their distances again, summed as the one-call kernels sum them
        bi, mi = np.nonzero((q != q_before).any(axis=-1))
        new = np.empty(len(bi))
        _jit_loader.kernels("ik.analytic._single").row_distances(q[bi, mi], q0[bi], _joint_table(robot, solver), new)
        dist[bi, mi] = new
    fk_ok = (dp <= tol[0]) & (dr <= tol[1])
    if raw.missing is not None:     # a branch that does not exist for this target is never a success
        ok = ok & ~raw.missing
        fk_ok = fk_ok & ~raw.missing
    code = np.where(ok, 0, np.where(fk_ok & ~within, 2, 1))
    unsorted = (q, ok, dp, dr)   # the sort below makes new arrays: these stay the messages' own
    if jit is not None:
        order, q, ok, dp, dr, within = jit.sort_branches(ok, dist, q, dp, dr, within)
    else:
        order = np.argsort(np.where(ok, 0.0, 1e9) + dist, axis=-1, kind="stable")
        q = np.take_along_axis(q, order[..., None], axis=1)
        ok, dp, dr, within = (np.take_along_axis(a, order, axis=1) for a in (ok, dp, dr, within))
    rows = np.arange(order.shape[0])[:, None]
    take = lambda a: a[rows, order]  # noqa: E731  (np.take_along_axis(a, order, axis=1), without its set-up)

    def messages() -> NDArray[np.object_]:
        """The branches' sentences (a sweep has hundreds per target), made when ``message`` is first read."""
        q_, ok_, dp_, dr_ = unsorted
        message = np.where(ok_, raw.note, "").astype(object, copy=False)
        _failure_messages(robot, message, code, raw, q_, dp_, dr_, tol)
        return take(message)

    iterations, reason = np.zeros(ok.shape, dtype=np.int64), _REASON_TEXT[take(code)]
    if named_later:   # the branches' names made when a field but q and success is first read (Geometric.name_branches)
        def make(made: tuple, which: str) -> Any:
            if which == "message":
                return messages
            return {"position_error": dp, "rotation_error": dr, "iterations": iterations,
                    "branch": _name(solver, q, target), "within_limits": within, "reason": reason}
        return IKResult._deferred((make,), q, ok)
    return IKResult._later((q, ok, dp, dr, iterations, take(raw.label), within, reason, None), messages)


def _solve_raw(solver: Any, target: Array, q0phi: Array) -> Raw:
    """``solver.solve``; with its plain labels (``named=False``) where the family names its branches when they are
    read (the geometric family, :func:`_names_later`)."""
    if _names_later(solver):
        return solver.solve(target, q0phi, named=False)  # type: ignore[no-any-return]
    return solver.solve(target, q0phi)  # type: ignore[no-any-return]


def _name(solver: Any, q: Array, target: Array) -> NDArray[np.object_]:
    """``solver.name_branches(q, target)`` (the geometric family, :func:`_names_later`)."""
    return solver.name_branches(q, target)  # type: ignore[no-any-return]


def _names_later(solver: ClosedForm) -> bool:
    """Whether ``solver`` names its branches from their joint values (the geometric family of an arm whose ideal DH
    twin a hand-written family matches: ``Geometric.name_branches``, tens of µs a target): the batched paths then
    solve with its plain labels and make the names when the branch field is first read."""
    return getattr(solver, "names_from", None) is not None


# ------------------------------------------------------------------ one target, one compiled call
class _Single:
    """What the one-call path needs of a robot and its closed form, built once (kept in ``robot.cache``): the
    kernel, its ``ctx`` vectors (one per options: :func:`._single.context`), the buffer sizes and the label table."""

    __slots__ = ("kernels", "kernel", "solver", "geometry", "joints", "F", "labels", "labels0", "blank", "m", "n",
                 "mn", "at", "fsize", "fshape", "isize", "bsize", "wsize", "wk", "one", "q0", "scale", "window",
                 "above", "sign", "default_tol", "ctx", "ctx_near", "ctxs", "converged", "shapes", "entry", "small",
                 "small_near", "address", "pool", "spare", "kept", "namer", "wk_rows")

    def __init__(self, robot: Robot, solver: ClosedForm, kernels) -> None:
        self.kernels = kernels
        self.solver = solver
        self.kernel = kernels.KERNELS.get(solver.family) if solver.geometry is not None else None
        self.geometry = solver.geometry
        self.joints = _joint_table(robot, solver)
        self.F = packed(robot)[0]
        self.labels = np.array(solver.branch_labels, dtype=object)
        self.labels0 = [self.labels[k:k + 1].reshape(()) for k in range(len(self.labels))]   # 0-d, copied per use
        # a family that names its branches from their joint values (the geometric family of a file whose ideal arm
        # a hand-written family matches): its names, made when the branch field is read; else the label table
        self.namer = getattr(solver, "name_branches") if _names_later(solver) else None
        self.m, self.n = solver.m, robot.n
        self.mn = self.m * self.n
        self.blank = np.full(self.m, "", dtype=object)
        self.converged = _REASON_TEXT[np.zeros(self.m, dtype=np.int64)]   # every branch's reason, copied per use
        self.shapes = ((4, 4),) if solver.pose_only else ((4, 4), (3,))   # the targets the family takes
        # the most targets of one call answered target by target (run_small_batch), for ik_all and for ik: more
        # where the family has a kernel (ROWS), fewer where it solves a batch faster as a whole (a whole-batch form,
        # from geometric.MANY targets: the SCARA's)
        small, near = ROWS if self.kernel is not None else (SMALL_BATCH, SMALL_BATCH)
        if has_batch_form(solver):
            small, near = min(small, MANY - 1), min(near, MANY - 1)
        self.small, self.small_near = small, near
        lay = kernels.layout(self.m, self.n)
        self.at = lay
        # the outputs, then the kernel's work space at the ends of ib and bb, and its float work vector wk
        self.wsize, wi, wb = kernels.work(solver.family if self.kernel is not None else None, self.m, self.n)
        self.fsize, self.isize, self.bsize = lay["fb"], lay["ib"] + wi, lay["bb"] + wb
        # fb made as rows of n (its flat layout, rounded up to whole rows): q (m, n) is its first m rows, a view
        # cheaper to make than a reshape (0.1 against 0.2 µs of a 5 µs ik_all)
        self.fshape = (-(-self.fsize // self.n), self.n)
        # the float work vector, one for every call: a kernel holds the GIL from start to end (none is compiled
        # with nogil; a test checks), so two threads never use it at once, and it keeps nothing between calls
        self.wk = np.empty(self.wsize)
        self.wk_rows: list = []   # the batch driver's work vectors on several threads, free (_batch_from_rows)
        self.q0 = np.clip(np.zeros(robot.n), robot.lower, robot.upper)   # armkit.ik's start when none is given
        self.scale = robot.reach
        self.window = POLISH_WINDOW[not solver.sf.exact]
        self.above = getattr(solver, "polish_above", POLISH_ABOVE)
        self.sign = getattr(solver, "sign", 1)
        self.default_tol = default_tolerance(robot)
        self.ctxs: dict = {}
        self.ctx = self.context(None, True, True)
        self.ctx_near = self.context(None, True, True, True)
        self.entry: Any = self.kernel
        self.address = 0
        self.pool: list = []   # the batch driver's buffers, kept for the next batch (_row_buffers)
        self.spare: deque = deque(maxlen=2)   # a single call's buffers, kept for the next call (_one_buffers)
        # the sets of the two closures of _one_target_calls (ik_all, ik: each its own views), the two newest each
        self.kept: tuple[deque, deque] = (deque(maxlen=2), deque(maxlen=2))
        if self.kernel is not None:   # the compiled function itself, called without the dispatcher's typing
            # of seven arrays (~0.35 us of a ~12 us call); see run_one for why it is safe
            sample = (np.empty(16), self.q0, self.ctx, np.empty(self.fshape), np.empty(self.isize, np.int64),
                      np.empty(self.bsize, np.bool_), self.wk)
            self.entry = _jit_loader.compiled_entry(self.kernel, *sample)
            self.address = kernels.kernel_address(self.kernel, sample)   # for the batch driver (_batch_from_rows)
        # the most common call, ik_all(robot, pose) and ik(robot, pose) with their defaults, as two closures
        self.one = _one_target_calls(self) if self.kernel is not None else None

    def __reduce__(self) -> tuple:
        """Pickled as None (a pickled robot's cache holds it): the copy makes its own record when first used,
        since the compiled kernels it refers to are code of this process, not data."""
        return (_no_record, ())

    def context(self, tol: tuple[float, float] | None, enforce_limits: bool, check: bool, nearest: bool = False
                ) -> Array:
        """The kernels' ``ctx`` for these options, made once (``nearest``: for :func:`armkit.ik`, which keeps the
        first branch only)."""
        key = (tol, enforce_limits, check, nearest)
        ctx = self.ctxs.get(key)
        if ctx is None:
            k = self.kernels
            opts = k.options(self.default_tol if tol is None else tol, enforce_limits, self.window, self.above,
                             self.scale, self.sign, check, nearest, _steps(not self.solver.sf.exact), POLISH_DONE,
                             0.0 if self.solver.sf.exact else RETARGET_WINDOW)
            ctx = self.ctxs[key] = k.context(self.geometry, self.joints, self.F, opts)
        return ctx


def _no_record() -> None:
    """What an unpickled :class:`_Single` becomes: no record (made again on first use)."""
    return None


_REASON_0D = [_REASON_TEXT[k:k + 1].reshape(()) for k in range(3)]   # 0-d reasons, copied per use
_CONVERGED = _REASON_0D[0]
_I64, _BOOL = np.dtype(np.int64), np.dtype(np.bool_)   # dtype objects: np.empty takes them faster than types
_NEW = object.__new__


def one_call_record(robot: Robot, solver: ClosedForm) -> "_Single | None":
    """What the one-call path keeps of ``robot`` and ``solver`` (:class:`_Single`, made once and kept in
    ``robot.cache``), or None while the Numba back end does not serve (``set_backend``, or the kernels
    still compiling)."""
    c = robot.cache.get("closed_form_one_call")
    if c is None or c.solver is not solver:
        kernels = _jit_loader.kernels("ik.analytic._single")
        if kernels is None:
            return None
        c = robot.cache["closed_form_one_call"] = _Single(robot, solver, kernels)
    elif _jit_loader._ACTIVE is None and _jit_loader.kernels("ik.analytic._single") is None:
        return None
    return c


def single_call(robot: Robot, solver: ClosedForm, target: Array, q0: Array | None, tol: tuple[float, float] | None,
                enforce_limits: bool = True, check: bool = True, nearest: bool = False) -> IKResult | None:
    """:func:`solve_all` (or with ``nearest``, :func:`solve_nearest`) for ONE target in one compiled call.

    ``target`` is a float64 pose ``(4, 4)`` or position ``(3,)`` the family takes, ``q0`` a float64 ``(n,)``
    (None: zeros clipped into the limits, as :func:`armkit.ik` takes it). Checks what the batched path
    checks (``check``: the pose is rigid). Returns the result with fields ``(m,)`` (``nearest``: ``()``),
    the same values as the batched path, or None where that path must answer
    (the Numba back end is not in use, a branch to polish, a note to give, a target or start to reject):
    the caller then takes it. See :mod:`._single`. The messages of failed branches are made when the
    ``message`` field is first read, its other fields but ``q`` and ``success`` when one of them is
    (:meth:`~armkit.ik.result.IKResult._deferred`).
    """
    c = one_call_record(robot, solver)
    if c is None:
        return None
    if tol is None and enforce_limits and check:
        ctx = c.ctx_near if nearest else c.ctx
    else:
        ctx = c.context(tol, enforce_limits, check, nearest)
    return run_one(robot, c, target, q0, ctx, tol, check, nearest)


def run_one(robot: Robot, c: "_Single", target: Array, q0: Array | None, ctx: Array, tol: tuple[float, float] | None,
            check: bool, nearest: bool, deferred: bool = True) -> IKResult | None:
    """:func:`single_call` once its record ``c`` and options ``ctx`` (:meth:`_Single.context` of ``tol`` and the
    flags) are known: the path :func:`armkit.ik` and :func:`armkit.ik_all` take with their default options.
    With ``deferred``, the result's fields are made from the buffers when one is first read
    (:meth:`IKResult._deferred`; the target is copied where the messages of failed branches need it)."""
    bufs = _one_buffers(c)
    fb, ib, bb = bufs
    if q0 is None:
        q0 = c.q0
    raw = None
    if c.kernel is not None:   # the family's kernel and the rest in one call: its compiled function (c.entry),
        # which trusts the types of its one signature. Both callers hand over what it takes: a native float64
        # target and q0 (armkit.ik.api checks the dtype), each 1-D and C-contiguous (ravel of a (4, 4), a (3,)
        # or an (n,) array); ctx and the buffers are the record's own. The kernel writes only the buffers.
        r = c.entry(target.ravel(), q0, ctx, fb, ib, bb, c.wk)
    else:                      # a family solved in Python (the geometric family): its solve, then one call
        t = target.ravel()
        kernels = c.kernels
        if not kernels.usable(t, q0, check):
            return None
        solver = c.solver
        q0phi = (q0 + solver.sf.theta)[None]   # (a family that names its branches: named when read, _later_fields)
        raw = _solve_raw(solver, target[None], q0phi)
        missing = raw.missing[0] if raw.missing is not None else np.zeros(c.m, dtype=bool)
        r = kernels.post(raw.q[0], raw.unreachable[0], missing, t, q0, ctx, fb, ib, bb, c.wk)
    c.spare.append(bufs)   # for a later call, once no result holds them
    if r & 3:
        return None
    if nearest:   # q and success, which nearly every caller reads: made now, the other fields by _later_fields
        q, ok = fb[0], bb[0, ...]
    else:
        q, ok = fb[:c.m], bb[:c.m]
    if deferred:
        kept = target.copy() if _sentences(r, raw, ib, nearest) else target   # what the sentences will read
        return IKResult._deferred((_later_fields, robot, c, raw, kept, fb, ib, bb, r, tol, nearest), q, ok)
    rest = _later_fields((_later_fields, robot, c, raw, target, fb, ib, bb, r, tol, nearest), "all")
    if callable(rest[-1]):   # the sentences of failed branches: made when first read
        return IKResult._later((q, ok) + rest[:-1] + (None,), rest[-1])
    return _result_of(q, ok, *rest)


def _one_target_calls(c: "_Single") -> tuple[Any, Any]:
    """``(every, nearest)``: :func:`run_one` for ``(robot, pose)`` with the default options (no ``q0``, limits
    enforced, the pose checked; ``nearest``: :func:`armkit.ik`), the record's values bound once (its attribute
    reads and run_one's tests cost ~0.3 µs of a 5 µs call). The same result, to the bit, as run_one's.

    Each keeps the two newest of its own sets (``c.kept``): the buffers ``fb, ib, bb`` and the result that hands
    them out, with its views ``q`` and ``success``. A call takes a set that nothing refers to any more
    (:func:`_free_counts`): the result dropped by the caller (no weak reference to it, its ``__dict__`` not held),
    then, once the fields it made when read are dropped with it, no view of a buffer held elsewhere. It then hands
    out the same result object with the new call's numbers, its fields made again when read: making the result and
    its two views cost ~0.3 µs of a 2-3 µs call (2026-12-07). A set still held stays where it is, and a new one is
    made; a caller that keeps every result makes a new set each call."""
    entry, ctx, ctx_near, q0, wk = c.entry, c.ctx, c.ctx_near, c.q0, c.wk
    refs, weak, later = sys.getrefcount, weakref.getweakrefcount, _later_fields

    def calls(nearest: bool) -> Any:
        spare = c.kept[nearest]
        take, keep = spare.popleft, spare.append
        context = ctx_near if nearest else ctx
        m, fshape, isize, bsize, new, cls = c.m, c.fshape, c.isize, c.bsize, _NEW, IKResult

        def new_set() -> tuple:
            """``(fb, ib, bb, result, q, success, result's __dict__)``: the buffers (:func:`_new_one_buffers`), the
            result made as :meth:`IKResult._deferred` makes it (``_make`` None until a call fills the buffers),
            ``q`` and ``success`` its views of ``fb`` and ``bb`` (``nearest``: the first branch's, ``success``
            0-d). Written out: three calls more cost ~0.2 µs of a call that keeps every result."""
            fb, ib, bb = np.empty(fshape), np.empty(isize, _I64), np.empty(bsize, _BOOL)
            q, ok = (fb[0], bb[0, ...]) if nearest else (fb[:m], bb[:m])
            res = new(cls)
            d = res.__dict__
            d["q"], d["success"], d["trace"], d["_make"] = q, ok, None, None
            return fb, ib, bb, res, q, ok, d

        f_res, f_d, f_fb, f_ib, f_bb, f_q, f_ok = _free_counts(new_set())
        # each count is at least its free one (the set holds each object), so a sum above the sum of the free counts
        # means one of them is above its own: one test for the result and its __dict__, one for the arrays (~40 ns
        # less than a test each, 2026-12-07)
        f_top, f_arrays = f_res + f_d, f_fb + f_ib + f_bb + f_q + f_ok

        def one(robot: Robot, target: Array) -> IKResult | None:
            try:
                s = take()
            except IndexError:
                s = new_set()
            else:
                fb, ib, bb, res, q, ok, d = s   # (unpacked as _free_counts unpacks: the same counts)
                if refs(res) + refs(d) > f_top or weak(res):
                    keep(s)   # a result the caller holds (or its __dict__, vars(result)): kept for later, or dropped
                    # from the deque by newer sets
                    s = new_set()
                else:
                    if len(d) != 4:   # fields made when read: dropped, and made again from this call's numbers
                        d.clear()
                        d["q"], d["success"], d["trace"] = q, ok, None
                    d["_make"] = None
                    if refs(fb) + refs(ib) + refs(bb) + refs(q) + refs(ok) > f_arrays:
                        keep(s)   # a field or a view of one outlives its result
                        s = new_set()
            fb, ib, bb, res, q, ok, d = s
            r = entry(target.ravel(), q0, context, fb, ib, bb, wk)
            keep(s)
            if r & 3:
                return None
            if nearest:
                kept = target if r & NEAREST or ib.item(0) == 0 else None   # (_sentences; None as below)
            else:   # (_sentences, without a note of a Python solve; None: the kernel's copy of the target in fb,
                # read by _later_fields, instead of a copy of the caller's array made now)
                kept = target if r == 0 else None
            d["_make"] = (later, robot, c, None, kept, fb, ib, bb, r, None, nearest)
            return res

        return one

    return calls(False), calls(True)


def _free_counts(s: tuple) -> tuple[int, ...]:
    """``sys.getrefcount`` of the result, its ``__dict__`` and the arrays of a new set ``s`` of
    :func:`_one_target_calls`, where nothing but the set refers to them: the most each may have for a call to take
    the set again. Unpacked as those calls unpack a set they take, so the counts are theirs."""
    fb, ib, bb, res, q, ok, d = s
    return sys.getrefcount(res), sys.getrefcount(d), sys.getrefcount(fb), sys.getrefcount(ib), sys.getrefcount(bb), \
        sys.getrefcount(q), sys.getrefcount(ok)


def _sentences(r: int, raw: Raw | None, ib: NDArray[np.int64], nearest: bool) -> bool:
    """Whether the result of :func:`run_one` (status ``r``) needs sentences made by :class:`_Messages` (a failed
    branch, or a note of the family solved in Python) rather than empty texts."""
    if nearest:
        return not (r & NEAREST or ib.item(0) == 0)
    return r != 0 or (raw is not None and any(raw.note[0]))


def _later_fields(made: tuple, which: str) -> Any:
    """Fields of the result of :func:`run_one` from the buffers its kernel filled, made when first read
    (:meth:`IKResult._deferred`) or all at once. ``made``: the call's tuple (this function, robot, record ``c``,
    ``raw`` (the Python solve of a family without a kernel, or None), target (None: the pose the kernel copied
    into ``fb``), fb, ib, bb, status ``r``, tol, nearest). ``which``: "message" (its text, or where failed
    branches need sentences, the :class:`_Messages` that make them when read: :meth:`IKResult._later`);
    "rest" (a dict of the fields but q, success and message: one read makes them all, cheaper than one by one);
    "all" (a tuple of those fields and then ``message``, in their order; :func:`run_one` makes q and success).
    With ``nearest`` (:func:`armkit.ik`): the first of the sorted branches, as 0-d arrays."""
    _, robot, c, raw, target, fb, ib, bb, r, tol, nearest = made
    m, mn = c.m, c.mn
    fb = fb.reshape(-1)   # (rows, n): the flat layout of _single.layout
    if target is None:    # the pose as the kernel read it (_one_target_calls): its copy in fb
        target = fb[c.at["target"]:c.at["target"] + 16].reshape(4, 4)
    message: Any = None
    if which != "rest":
        if _sentences(r, raw, ib, nearest):
            message = _Messages(robot, c, raw, target, fb, ib, tol, nearest)
        elif nearest:
            message = "" if raw is None else str(raw.note[0][ib[3 * m]])
        else:
            message = c.blank.copy()
        if which == "message":
            return message
    if nearest:   # (a family that names its branches: from the branches as answered, touched up where they were)
        if c.namer is not None:
            branch = np.array(c.namer(fb[:c.n].reshape(1, 1, c.n), target[None])[0, 0], dtype=object)
        elif raw is not None:
            branch = np.array(raw.label[0][ib[3 * m]], dtype=object)
        else:
            branch = c.labels0[r >> LABEL_SHIFT if r & NEAREST else ib.item(m)].copy()
        dp, dr, it, within = fb[mn, ...], fb[mn + m, ...], ib[2 * m, ...], bb[m, ...]
        reason = _CONVERGED.copy() if r & NEAREST else _REASON_0D[ib.item(0)].copy()
    else:
        if c.namer is not None:
            branch = c.namer(fb[:mn].reshape(1, m, c.n), target[None])[0]
        elif raw is not None:
            branch = raw.label[0][ib[3 * m:4 * m]]
        else:
            branch = c.labels[ib[m:2 * m]]
        dp, dr, it, within = fb[mn:mn + m], fb[mn + m:mn + 2 * m], ib[2 * m:3 * m], bb[m:2 * m]
        reason = _REASON_TEXT[ib[:m]] if r else c.converged.copy()
    if which == "rest":
        return {"position_error": dp, "rotation_error": dr, "iterations": it, "branch": branch,
                "within_limits": within, "reason": reason}
    return dp, dr, it, branch, within, reason, message


SMALL_BATCH = 16
"""Batches of at most this many targets of a family solved in Python (the geometric classes of a 1-D search) take
the one-call path target by target (:func:`run_small_batch`): the batched path starts at ~0.3-0.5 ms whatever the
size (then ~0.01 ms a target), the one-call path costs ~0.02 ms a target for ``armkit.ik`` and ~0.03 ms for
``armkit.ik_all`` (UR5, Puma 560: the two are equal near 16-24 targets for ``ik_all`` and 24-32 for ``ik`` on this
project's 2-core machine; benchmarks/bench_analytic.py --small-only)."""
ROWS = (sys.maxsize, sys.maxsize)
"""The same limits, ``(ik_all, ik)``, for a family with a kernel. Its calls write each target's numbers into a row
of one set of buffers, all rows by one compiled driver (:func:`_batch_from_rows`; the family's kernel called
through its address, on every thread from :data:`ROWS_PARALLEL` targets), the fields but ``q`` and ``success`` made
when first read; more than :data:`POOL_ROWS` targets in pieces of that many rows (:func:`_in_pieces`). Against the
batched path (2026-12-06), the UR5's ``ik_all`` of 2 targets 27 -> 10 µs a call, of 8 targets 57 -> 22, of 16
targets 64 -> 38, ``ik`` 20 -> 9, 27 -> 16, 46 -> 29 (CPU time of the thread); the Puma's 1,000 targets of
``ik_all`` 1.9-2.0 -> 1.5-1.6 µs a target (wall clock, two threads, with the buffers the robot keeps between
batches, :func:`_row_buffers`). The limits were 1,024 and 4,096 until the fifth session of 2026-12-07, when the
kernels had become fast enough that the rows beat the batched path at every size (``bench_analytic.py
--big-only``). The buffers of :func:`armkit.ik_all`'s pieces (~1.7 KB a target) stay with the result until its
fields are made (kept: 2.8-3.1 KB a target against the batched path's 2.3-2.4; at their peak the batched path's
arrays took as much, or 8-17 KB a target on the geometric family); :func:`armkit.ik`'s pieces are made compact
as they come (:func:`_compact`), their sets used again by the next piece."""
ROWS_PARALLEL = 32
"""Batches of a family with a kernel from this many targets run on every thread (:func:`_batch_from_rows`; the
Puma's ``ik_all`` of 32 targets 2.7 -> 2.6 µs a target, of 128 targets 2.3 -> 2.0)."""
ROW_CHUNKS = 64
"""The chunks of rows of a threaded batch, each with its own work vector (:func:`._single._rows`)."""


def run_small_batch(robot: Robot, c: "_Single", targets: Array, q0: Array | None, ctx: Array, check: bool,
                    nearest: bool, batched: Any = None) -> IKResult | None:
    """:func:`run_one` for each of a few targets (``targets`` float64 ``(B,) + shape`` the family takes, ``B``
    at most ``c.small``: :data:`SMALL_BATCH`, fewer for a family with a whole-batch form; for a family with a
    kernel any number (:data:`ROWS`), in pieces of :data:`POOL_ROWS` rows above that;
    ``q0`` None, one start ``(n,)`` or one per target ``(B, n)``, float64), the results stacked as the batched path
    gives them: fields
    ``(B,)`` (``(B, m)`` for every branch), the same values and types (tests/ik/test_small_batch.py). None where
    any target needs the batched path (the caller then takes it for all: a branch to polish, a note to give, a
    target or start to reject), except where a family with a kernel is given ``batched``: the batched path for some
    of the targets, ``batched(targets, q0)`` (``q0`` as given here, of those targets), which then answers the
    targets whose kernel call asked for it, alone (:func:`_batch_from_rows`)."""
    B = targets.shape[0]
    if q0 is not None:
        q0 = np.ascontiguousarray(q0)
    if c.kernel is not None:
        if B > POOL_ROWS:
            return _in_pieces(robot, c, targets, q0, ctx, nearest, batched)
        return _batch_from_rows(robot, c, targets, q0, ctx, nearest, batched)
    parts = []
    for i in range(B):
        one = run_one(robot, c, targets[i], q0 if q0 is None or q0.ndim == 1 else q0[i], ctx, None, check, nearest,
                      deferred=False)
        if one is None:
            return None
        parts.append(one)
    values = [_stacked([r.__dict__[f] for r in parts]) for f in _STACKED]
    if all("message" in r.__dict__ for r in parts):   # every target succeeded: no sentence to make
        return IKResult._later((*values, _stacked_messages(parts)))
    return IKResult._later((*values, None), lambda: _stacked_messages(parts))


def _batch_from_rows(robot: Robot, c: "_Single", targets: Array, q0: Array | None, ctx: Array,
                     nearest: bool, batched: Any = None, size: int = 0, out: tuple | None = None) -> IKResult | None:
    """:func:`run_small_batch` for a family with a kernel: each target's kernel call writes into its own row of
    three buffers ``(B, size)`` (:func:`_row_buffers`), all the calls made by one compiled driver
    (:func:`._single._rows`, threaded from :data:`ROWS_PARALLEL` targets), and every field is made once for all the
    rows, ``q`` and ``success`` now, the others when first read (:func:`_rows_fields`, as :func:`_later_fields`
    makes them for one: the label and reason of row ``i`` taken where the kernel wrote them for its first branch,
    which :func:`armkit.ik`'s nearest-first status also names). Making each target's result and then stacking the
    fields cost about as much as the compiled calls (the UR5's ``ik`` of 8 targets: 66 µs, 23 of them in the
    calls), and calling the kernel from Python ~1 µs a target more than from the driver.

    Rows whose kernel call asks for the batched path (a singular wrist's note, a branch to polish further) are
    answered by ``batched`` (:func:`run_small_batch`) for those targets alone and spliced in (:func:`_spliced`):
    one target at the home pose of a wrist among 1,000 made the whole batch take the batched path, 3-4x the
    time. None where a target is to be rejected (the batched path raises its error, naming the target), where
    every row asks for the batched path, or where ``batched`` is None and some row does. ``out``: the arrays
    ``(q, success)`` (float64 ``(B, n)`` and bool ``(B,)`` for ``nearest``, else ``(B, m, n)`` and ``(B, m)``,
    C-contiguous) that the driver writes those fields into (:func:`_in_pieces`' rows of the whole batch's), or None
    for new ones."""
    if not c.address:
        return None
    B, n = targets.shape[0], c.n
    whole = _row_buffers(c, B, size)   # (size: a new set's rows, at least B)
    FB, IB, BB, marks = (a[:B] for a in whole)
    flat = np.ascontiguousarray(targets).reshape(B, -1)
    starts = c.q0 if q0 is None else q0
    each = starts.ndim == 2
    parallel = B >= ROWS_PARALLEL and _jit_loader.parallel_ok()
    # the work vectors: on one thread the record's own (the serial driver, like a kernel, holds the GIL
    # throughout); on several one per chunk of rows, a set the record keeps free between calls (the threaded driver
    # lets the GIL go: two threads' batches take two sets; list.pop and append are each one step under the GIL).
    # Until the tenth session of 2026-12-07 each set of row buffers had its own (0.4-0.7 MB, fresh for each piece of
    # a big batch, whose result holds its pieces' sets)
    if parallel:
        try:
            WK = c.wk_rows.pop()
        except IndexError:
            WK = np.empty((ROW_CHUNKS, c.wsize))
    else:
        WK = c.wk.reshape(1, -1)
    # q and success, which nearly every caller reads, written by the driver as each row is solved (a copy of the
    # rows' views made after it took ~0.09 µs a target of a 50,000-target batch's 1.1, on one thread)
    q, ok = _answer_arrays(c, B, nearest) if out is None else out
    pending = c.kernels.rows_entry(parallel)(c.address, flat, starts.reshape(-1, n), each, ctx, FB, IB, BB, WK, marks,
                                             q.reshape(B, -1), ok.reshape(B, -1))
    _put_back(c, whole)
    if parallel:
        c.wk_rows.append(WK)
    if pending < 0:
        return None
    rows: list = []
    redo = None
    if pending >> 32:   # rows for the batched path (marked 2)
        if batched is None or pending >> 32 == B:
            return None
        redo = np.flatnonzero(marks == 2)
        rows = np.flatnonzero(marks == 1).tolist()
        good = np.flatnonzero(marks != 2)[0]   # a row the kernel answered copied to those rows, so that the fields
        FB[redo], IB[redo], BB[redo] = FB[good], IB[good], BB[good]   # made of the buffers read valid numbers
    elif pending:
        rows = np.flatnonzero(marks).tolist()
    FB = FB.reshape(B, -1)   # each row's flat layout (_single.layout)
    # the other fields when one is first read (_rows_fields); the sentences of the rows with a failed branch (the
    # others stay empty) when the message is read, from a copy of the targets made now (the caller may change its
    # array before then)
    kept = flat.copy() if rows else None
    made: tuple = (_rows_fields, robot, c, FB, IB, BB, rows, kept, targets.shape[1:], nearest)
    if redo is not None:
        try:
            sub = batched(targets[redo], q0[redo] if q0 is not None and q0.ndim == 2 else q0)
        except ArmkitError:   # (none is known) the batched path of the whole batch raises it, naming the target
            return None
        q[redo], ok[redo] = sub.q, sub.success
        made = (_spliced, made, redo, sub)
    return IKResult._deferred(made, q, ok)


def _answer_arrays(c: "_Single", B: int, nearest: bool) -> tuple[Array, NDArray[np.bool_]]:
    """New arrays ``(q, success)`` of ``B`` targets' answers, which the batch driver fills (:func:`._single._rows`):
    float64 ``(B, n)`` and bool ``(B,)`` for ``nearest``, else ``(B, m, n)`` and ``(B, m)``."""
    if nearest:
        return np.empty((B, c.n)), np.empty(B, _BOOL)
    return np.empty((B, c.m, c.n)), np.empty((B, c.m), _BOOL)


def _in_pieces(robot: Robot, c: "_Single", targets: Array, q0: Array | None, ctx: Array, nearest: bool,
               batched: Any) -> IKResult | None:
    """:func:`_batch_from_rows` of more than :data:`POOL_ROWS` targets: pieces of that many, one after the other,
    each writing ``q`` and ``success`` into its rows of the whole batch's arrays; the other fields made when first
    read (:func:`_joined`): :func:`armkit.ik_all`'s from each piece's set of buffers, which the result holds until
    then; :func:`armkit.ik`'s pieces are made compact at once (:func:`_compact`), their sets free for the next piece.
    None where a piece is (the batched path answers every target). Pieces of the size of a kept set: the sets of a
    loop over batches are the process's memory already, where one set of 50,000 rows (~85 MB) came fresh from the
    system in some calls, with a page fault every 4 KB (the UR5's 50,000 targets 2.7-3.1 µs a target in those calls,
    0.96-1.4 in the others; in pieces of 1,024 rows 0.96-1.02 after the first call). Until the tenth session of
    2026-12-07 each piece copied its ``q`` and ``success`` and the pieces' were joined at the end: the Puma's 50,000
    targets of ``ik_all`` took 1.15-1.20 µs a target so, 1.04-1.08 now that the driver writes them into the
    batch's arrays (:func:`_batch_from_rows`) and keeps its work vectors. Making ``ik_all``'s pieces compact too
    gains nothing: 97 % of the Puma's targets have a branch outside the limits, whose sentence needs most of the
    row (copying the rows of the sentences to make took that call to 1.6-2.4 µs a target)."""
    B, step = targets.shape[0], POOL_ROWS
    q, ok = _answer_arrays(c, B, nearest)
    makers = []
    for s in range(0, B, step):
        starts = q0[s:s + step] if q0 is not None and q0.ndim == 2 else q0
        part = _batch_from_rows(robot, c, targets[s:s + step], starts, ctx, nearest, batched, step,
                                (q[s:s + step], ok[s:s + step]))
        if part is None:
            return None
        make = part.__dict__["_make"]
        makers.append(_compact(make) if nearest else make)
        del part
    return IKResult._deferred((_joined, makers), q, ok)


def _compact(made: tuple) -> tuple:
    """The made tuple of a piece of :func:`armkit.ik`'s rows (:func:`_rows_fields`', or :func:`_spliced`'s around
    it) made to hold no buffer of the piece's set: copies of the numbers its fields but q and success are made of
    (:func:`_raw`: 41 bytes a target; with the joint values and the pose that a family naming its branches when
    read names them by), and of the rows of the sentences to make (a target whose branch failed: ~1.7 KB each). The
    set goes back to the pool for the next piece: a batch of any size keeps ~0.1 KB a target besides those rows (and
    ``q``), where the sets took ~1.7 KB."""
    if made[0] is _spliced:
        return (_spliced, _compact(made[1])) + made[2:]
    _, robot, c, FB, IB, BB, rows, kept, shape, nearest = made
    raw = tuple(a.copy() for a in _raw(c, FB, IB, BB, nearest))
    named = None if c.namer is None else tuple(a.copy() for a in _named_by(c, FB, nearest))
    sentences = (FB[rows].copy(), IB[rows].copy(), kept[rows]) if rows else (None, None, None)
    return (_compact_fields, robot, c, len(FB), raw, named, rows, sentences, shape, nearest)


def _compact_fields(made: tuple, which: str) -> Any:
    """:func:`_rows_fields` of a piece made compact by :func:`_compact`: the same fields, the same sentences."""
    _, robot, c, B, raw, named, rows, (FB, IB, kept), shape, nearest = made
    if which == "message":
        return _rows_messages(robot, c, B, rows, range(len(rows)), FB, IB, kept, shape, nearest)
    return _rows_rest(c, raw, named, nearest)


def _joined(made: tuple, which: str) -> Any:
    """The fields of :func:`_in_pieces`'s result but ``q`` and ``success``, made when first read: ``made`` (this
    function, the makers of its pieces' deferred fields, in order: only those are kept of the pieces, so no field
    is held twice); ``which`` as :func:`_rows_fields` takes it (the message made when read)."""
    makers = made[1]
    if which == "rest":
        rests = [make[0](make, "rest") for make in makers]
        return {f: np.concatenate([r[f] for r in rests]) for f in _STACKED[2:]}

    def message() -> NDArray[np.object_]:
        texts = [make[0](make, "message") for make in makers]
        return np.concatenate([t() if callable(t) else t for t in texts])

    return message


def _spliced(made: tuple, which: str) -> Any:
    """The fields of :func:`_batch_from_rows`'s result but ``q`` and ``success`` where the batched path answered
    some rows: ``made`` (this function, the made tuple of :func:`_rows_fields`, those rows, the batched path's
    result for them). ``which`` as :func:`_rows_fields` takes it; its fields with those rows put in (a text array
    widened where the batched path's texts are longer)."""
    _, inner, redo, sub = made
    out = inner[0](inner, which)
    if which == "rest":
        return {k: _put_rows(v, redo, getattr(sub, k)) for k, v in out.items()}
    if callable(out):
        return lambda: _put_rows(out(), redo, sub.message)
    return _put_rows(out, redo, sub.message)


def _put_rows(a: NDArray, rows: NDArray[np.intp], values: NDArray) -> NDArray:
    """``a`` with ``a[rows] = values``, in place where the dtype holds them (a text array widened first)."""
    if a.dtype.kind == "U" and values.dtype.kind == "U" and values.dtype.itemsize > a.dtype.itemsize:
        a = a.astype(values.dtype)
    a[rows] = values
    return a


POOL = 2
"""Sets of the batch driver's buffers a record keeps (:func:`_row_buffers`): two serve a loop that keeps each result
until the next call's returns."""
POOL_ROWS = 1024
"""The largest set kept (~1.7 MB for a 6-joint arm with 8 branches): bigger batches go in pieces of this many rows
(:func:`_in_pieces`)."""


def _row_buffers(c: "_Single", B: int, rows: int = 0) -> tuple:
    """The batch driver's buffers for ``B`` targets (``FB, IB, BB`` and the row marks, at least ``B`` rows; the
    chunks' work vectors are the record's, ``c.wk_rows``): a set of the record's pool that no result holds any more,
    taken out of it, or a new set of ``max(B, rows)`` rows (the pool keeps the :data:`POOL` newest, of at most
    :data:`POOL_ROWS` rows; the last piece of a batch in pieces asks for a whole piece's, so that the next batch's
    pieces can take it). A result holds its set through the views it was given and the fields and sentences it makes
    later. Pages a batch touched before cost less than fresh ones (the kernels touch ~1.7 KB a target; on this
    machine the Puma's 1,000 targets of ``ik_all`` took 2.2 µs a target with new buffers, 1.5-1.6 with kept ones).
    The caller puts the set back after its call (:func:`_put_back`)."""
    pool = c.pool
    if B > POOL_ROWS:
        return _new_row_buffers(c, B)
    with _POOL_LOCK:   # two threads never take one set
        for i, whole in enumerate(pool):
            if len(whole[0]) >= B and _most_refs(whole) <= _FREE:
                return pool.pop(i)
        if len(pool) >= POOL:
            del pool[0]   # the oldest, held by a result: it goes with that result
    return _new_row_buffers(c, max(B, rows))


def _put_back(c: "_Single", whole: tuple) -> None:
    """Return the set ``whole`` of :func:`_row_buffers` to the record's pool after its call, for a later batch once
    no result holds it (a set of more than :data:`POOL_ROWS` rows is not kept)."""
    if len(whole[0]) <= POOL_ROWS:
        with _POOL_LOCK:
            c.pool.append(whole)


def _one_buffers(c: "_Single") -> tuple:
    """The buffers ``fb, ib, bb`` of one call of :func:`run_one` (a record's one-call kernel writes every output
    there): a set the record kept (``c.spare``, the two newest) that no result holds any more, or a new set. A result
    holds its set through the views it was given and the fields and sentences it makes later, so the numbers of a
    result a caller keeps are never written again; a loop ``res = ik_all(arm, T)`` (the previous result alive
    during the call) takes the two kept sets in turn. Taking a set out of the deque and putting it back are each
    one step that holds the GIL, so two threads never take one set. The caller puts the set back after its call."""
    spare = c.spare
    try:
        bufs = spare.popleft()
    except IndexError:
        return _new_one_buffers(c)
    if _held(bufs, _FREE_ONE):
        spare.append(bufs)   # held by a result: kept for later, or dropped from the deque by newer sets
        return _new_one_buffers(c)
    return bufs


def _new_one_buffers(c: "_Single") -> tuple:
    """A new set of :func:`_one_buffers`."""
    return np.empty(c.fshape), np.empty(c.isize, _I64), np.empty(c.bsize, _BOOL)


def _new_row_buffers(c: "_Single", B: int) -> tuple:
    """A new set of :func:`_row_buffers` for ``B`` targets."""
    return np.empty((B,) + c.fshape), np.empty((B, c.isize), _I64), np.empty((B, c.bsize), _BOOL), np.empty(B, _I64)


def _most_refs(whole: tuple) -> int:
    """The most references to one array of the set ``whole`` (``sys.getrefcount``, counting its own argument and
    this loop's name): :data:`_FREE` where nothing but the set refers to any (no view of it, no field made of it
    later, no sentence maker holds it)."""
    most = 0
    for a in whole:
        most = max(most, sys.getrefcount(a))
    return most


_FREE = _most_refs((np.empty(1),))
""":func:`_most_refs` of a set that nothing else refers to, measured so on this Python (3 on CPython 3.11)."""
_POOL_LOCK = threading.Lock()


def _held(bufs: tuple, free: int) -> bool:
    """Whether anything but the set ``bufs`` (three arrays, :func:`_one_buffers`) refers to one of its arrays: more
    than ``free`` references (``sys.getrefcount``, counting its own argument and this function's name)."""
    fb, ib, bb = bufs
    return sys.getrefcount(fb) > free or sys.getrefcount(ib) > free or sys.getrefcount(bb) > free


_FREE_ONE = next(f for f in range(1, 16) if not _held((np.empty(1), np.empty(1), np.empty(1)), f))
""":func:`_held`'s count for a set nothing else refers to, measured with that function on this Python (3 on
CPython 3.11)."""


def _rows_fields(made: tuple, which: str) -> Any:
    """The fields of :func:`_batch_from_rows`'s result but ``q`` and ``success``, made when first read
    (:meth:`IKResult._deferred`) from the rows its driver filled, as :func:`_later_fields` makes them for one
    target. ``made``: (this function, robot, record ``c``, the buffers ``FB (B, size)``, ``IB``, ``BB``, the rows
    whose failed branches need sentences, a copy of the targets (flat) for those, the shape of one target,
    ``nearest``). ``which``: "rest" (a dict of the fields but q, success and message) or "message" (the texts, or
    the function that makes them)."""
    _, robot, c, FB, IB, BB, rows, kept, shape, nearest = made
    if which == "message":
        return _rows_messages(robot, c, FB.shape[0], rows, rows, FB, IB, kept, shape, nearest)
    return _rows_rest(c, _raw(c, FB, IB, BB, nearest), None if c.namer is None else _named_by(c, FB, nearest),
                      nearest)


def _raw(c: "_Single", FB: Array, IB: NDArray[np.int64], BB: NDArray[np.bool_], nearest: bool) -> tuple:
    """Views of the rows' numbers that the fields but q, success, message and a named family's ``branch`` are made
    of (:func:`_rows_rest`), for ``k`` branches a target (1 for ``nearest``, else ``c.m``): the position and rotation
    errors ``(B, 2k)``; the reason codes, the label indices and the iterations ``(B, 3k)``; within the limits
    ``(B, k)`` (:func:`._single.layout`: each field's ``m`` columns, of which ``nearest`` reads the first)."""
    m, mn = c.m, c.mn
    step = m if nearest else 1
    return FB[:, mn:mn + 2 * m:step], IB[:, :3 * m:step], BB[:, m:m + (1 if nearest else m)]


def _named_by(c: "_Single", FB: Array, nearest: bool) -> tuple:
    """Views of what a family that names its branches when read names them by (``c.namer``): the rows' sorted
    joint values ``(B, k n)`` and the poses as the kernel read them ``(B, 16)``."""
    at = c.at["target"]
    return FB[:, :(1 if nearest else c.m) * c.n], FB[:, at:at + 16]


def _rows_rest(c: "_Single", raw: tuple, named: tuple | None, nearest: bool) -> dict:
    """The fields but q, success and message of rows, made of their numbers ``raw`` (:func:`_raw`; copied, the
    rows may be a kept set's) and, for a family that names its branches when read, ``named`` (:func:`_named_by`):
    fields ``(B,)`` for ``nearest``, else ``(B, m)``."""
    E, I, W = raw
    B, k = len(W), W.shape[1]
    namer = c.namer
    if named is None or namer is None:
        branch = c.labels[I[:, k:2 * k]]
    else:
        branch = namer(named[0].reshape(B, k, c.n), named[1].reshape(B, 4, 4))

    def pick(a: NDArray) -> NDArray:   # (the first branch's column for nearest)
        return a[:, 0] if nearest else a

    return {"position_error": pick(E[:, :k]).copy(), "rotation_error": pick(E[:, k:]).copy(),
            "iterations": pick(I[:, 2 * k:]).copy(), "branch": pick(branch), "within_limits": pick(W).copy(),
            "reason": pick(_REASON_TEXT[I[:, :k]])}


def _rows_messages(robot: Robot, c: "_Single", B: int, rows: list, at: Any, FB: Any, IB: Any, kept: Any,
                   shape: tuple, nearest: bool) -> Any:
    """The ``message`` field of ``B`` rows (:func:`_rows_fields`, :func:`_compact_fields`): empty texts, or where
    ``rows`` need sentences the function that makes them when read, each row ``rows[j]``'s from ``FB``, ``IB`` and
    ``kept`` at ``at[j]`` (the rows themselves, or a compact copy of them)."""
    message = np.empty(B, dtype=object) if nearest else np.full((B, c.m), "", dtype=object)
    if nearest:
        message[:] = ""
    if not rows:
        return message

    def messages() -> NDArray[np.object_]:
        for i, j in zip(rows, at):
            message[i] = _Messages(robot, c, None, kept[j].reshape(shape), FB[j], IB[j], None, nearest)()
        return message

    return messages


_STACKED = ("q", "success", "position_error", "rotation_error", "iterations", "branch", "within_limits", "reason")
"""The fields of :class:`IKResult` before ``message``, in order (:meth:`IKResult._later`)."""


def _stacked(arrays: list) -> Any:
    """``np.stack(arrays)`` of one field's arrays, all of one shape and dtype, in ~1 us instead of ~6: 0-d
    object arrays (the labels of :func:`armkit.ik`) item by item, so that the stack holds their objects."""
    first = arrays[0]
    if first.dtype != object or first.ndim:
        return np.array(arrays, dtype=first.dtype)
    out = np.empty(len(arrays), dtype=object)
    for i, a in enumerate(arrays):
        out[i] = a[()]
    return out


def _stacked_messages(parts: list) -> Any:
    """The ``message`` field of a stacked batch: an object array ``(B,)`` of str, or ``(B, m)``."""
    if parts[0].shape == ():
        out = np.empty(len(parts), dtype=object)
        out[:] = [r.message for r in parts]
        return out
    return np.array([r.message for r in parts], dtype=object)


class _Messages:
    """The ``message`` field of a one-call result, made when first read (:meth:`IKResult._later`): the sentences
    :func:`solve_all` gives its failed branches (and the family's notes), from the numbers the kernel left in
    its private part of the buffers. With ``nearest``, the first branch's sentence only."""

    __slots__ = ("robot", "c", "raw", "target", "fb", "ib", "tol", "nearest")

    def __init__(self, robot: Robot, c: _Single, raw: Raw | None, target: Array, fb: Array, ib: NDArray[np.int64],
                 tol: tuple[float, float] | None, nearest: bool) -> None:
        self.robot, self.c, self.raw, self.fb, self.ib = robot, c, raw, fb, ib
        self.target = target.copy()   # the caller may change its array before the message is read
        self.tol = c.default_tol if tol is None else tol
        self.nearest = nearest

    def __call__(self) -> Any:
        raw = self.raw
        if raw is None:
            return self._from_kernel()
        c, fb, ib = self.c, self.fb, self.ib
        m, n, at = c.m, c.n, c.at
        count = 1 if self.nearest else m
        code, order, bits = ib[:count], ib[3 * m:3 * m + count], ib[4 * m:4 * m + count]
        message = np.where(code == 0, raw.note[0][order], "").astype(object, copy=False)
        if (code == 2).any():
            _limit_messages(self.robot, message, code, bits)
        if (code == 1).any():   # why a branch is out of reach: the family's own sentence, in sorted order
            unreachable = raw.unreachable[0][order]
            q = fb[:count * n].reshape(count, n)
            shim = Raw(q, message, unreachable, lambda i: raw.why(int(order[i])), message)
            _failure_messages(self.robot, message, np.where(code == 1, 1, 0), shim, q,
                              fb[at["hdp"]:at["hdp"] + count], fb[at["hdr"]:at["hdr"] + count], self.tol)
        if self.nearest:
            return str(message[0])
        return message

    def _from_kernel(self) -> Any:
        """:meth:`__call__` for a family solved by the kernel: the sentences of :func:`_few_failure_messages`
        (the same objects' values), made in one Python loop from the kernel's numbers."""
        c, fb, ib, robot = self.c, self.fb, self.ib, self.robot
        m, at = c.m, c.at
        count = 1 if self.nearest else m
        codes = ib[:count].tolist()
        texts: list[Any] = [""] * count
        reach = fb[at["reach"]:at["reach"] + 4 * count].tolist()
        dp, dr = fb[at["hdp"]:at["hdp"] + count].tolist(), fb[at["hdr"]:at["hdr"] + count].tolist()
        made: dict = {}
        for b, k in enumerate(codes):
            if k == 2:
                texts[b] = _limit_message(robot, int(ib[4 * m + b]))
            elif k == 1:
                clipped, lat, rho, r = reach[4 * b:4 * b + 4]
                if clipped != 0.0:   # the family's sentence from the kernel's numbers, once per distinct row
                    why = made.get((lat, rho, r))
                    if why is None:
                        why = made[(lat, rho, r)] = getattr(c.solver, "reach_why")(lat != 0.0, rho, r, self.target)
                    texts[b] = Fielded.of("unreachable: {why}", why=why)
                else:
                    texts[b] = _unreachable_text(robot, dp[b], dr[b], self.tol)
        if self.nearest:
            return str(texts[0])
        message = c.blank.copy()
        message[:] = texts
        return message


def _result(values: tuple, later: Any = None) -> IKResult:
    """An :class:`IKResult` of the fields ``values`` (``trace`` None; ``message`` made by ``later()`` when first
    read if given), built without the dataclass's ``__init__`` (:meth:`IKResult._later`)."""
    return IKResult._later(values, later)


def _limit_messages(robot: Robot, message: NDArray[np.object_], code: NDArray[np.int_], bits: NDArray[np.int_]
                    ) -> None:
    """``message`` of the branches outside the limits (``code == 2``): :func:`_failure_messages`' sentence for
    each pattern of joints (``bits``), made once per robot and pattern (``robot.cache["limit_messages"]``)."""
    for b in np.flatnonzero(code == 2).tolist():
        message[b] = _limit_message(robot, int(bits[b]))


def _limit_message(robot: Robot, pattern: int) -> Any:
    """:func:`_limit_text` of the joints whose bits are set in ``pattern``, made once per robot and pattern
    (``robot.cache["limit_messages"]``)."""
    made = robot.cache.get("limit_messages")
    if made is None:
        made = robot.cache["limit_messages"] = {}
    text = made.get(pattern)
    if text is None:
        text = made[pattern] = _limit_text(robot, [j for j in range(robot.n) if pattern >> j & 1])
    return text


def solve_nearest(robot: Robot, solver: ClosedForm, target: Array, q0: Array, position_only: bool,
                  tol: tuple[float, float] | None = None, enforce_limits: bool = True,
                  lead: tuple[int, ...] | None = None) -> IKResult:
    """The first branch of :func:`solve_all` for each target, checking only that branch by FK.

    Same answer as ``solve_all(...)[:, 0]``: where the branch nearest ``q0`` among those the
    geometry and the limits allow passes its FK check, and no clipped (out-of-reach) branch is
    nearer, it is the nearest successful one; every other target goes through :func:`solve_all`.
    Fields ``(B,)``, ``q`` ``(B, n)``; ``lead + (...)`` instead of ``(B, ...)`` when ``lead`` is given.
    """
    if tol is None:
        tol = default_tolerance(robot)
    theta = solver.sf.theta
    named_later = _names_later(solver)
    raw = _solve_raw(solver, target, q0 + theta)
    B = len(target)
    rows = np.arange(B)
    jit = jit_kernels()
    if jit is not None:
        qb, pick, clean = jit.wrap_pick(raw.q, _joint_table(robot, solver), q0, raw.unreachable, enforce_limits)
    else:
        q = wrap_to_limits(raw.q - theta, q0[:, None, :], robot.lower, robot.upper, ~robot.prismatic)
        cand = ~raw.unreachable
        if enforce_limits:
            cand = cand & robot.within_limits(q)
        dist = np.linalg.norm(np.where(robot.prismatic, 0.0, q - q0[:, None, :]), axis=-1)
        pick = np.argmin(np.where(cand, dist, np.inf), axis=1)
        # a clipped (out-of-reach) branch could still pass FK at a boundary: it matters only if it is nearer
        nearer_clipped = (raw.unreachable & (dist <= dist[rows, pick][:, None])).any(axis=1)
        clean = cand[rows, pick] & ~nearer_clipped
        qb = q[rows, pick]
    dp, dr, ok, within = verify(robot, qb, target, position_only, tol, enforce_limits)
    if raw.missing is not None:
        ok = ok & ~raw.missing[rows, pick]
    scale = solver.sf.scale   # robot.reach (computed on every access)
    above = getattr(solver, "polish_above", POLISH_ABOVE)
    fine = ok & clean & (dp <= above * scale) & (dr <= above)
    fields = {"q": qb, "success": ok, "position_error": dp, "rotation_error": dr,   # fresh arrays: redo writes
              "iterations": np.zeros(B, dtype=np.int64), "branch": raw.label[rows, pick], "within_limits": within,
              "reason": _REASON_TEXT[np.zeros(B, dtype=int)], "message": raw.note[rows, pick]}
    if named_later:   # the names of the branches picked, made when read (solve_all's, for the targets it redoes)
        return _nearest_named_later(robot, solver, target, q0, position_only, tol, enforce_limits, lead, fields, fine)
    if fine.all():
        if lead is not None:
            fields = {k: a.reshape(lead + a.shape[1:]) for k, a in fields.items()}
        return IKResult(**fields)
    redo = np.flatnonzero(~fine)
    full = solve_all(robot, solver, target[redo], q0[redo], position_only, tol, enforce_limits)
    for f in ("q", "success", "position_error", "rotation_error", "branch", "within_limits", "reason"):
        fields[f][redo] = getattr(full, f)[:, 0]
    message = fields.pop("message")
    shape = (lambda a: a.reshape(lead + a.shape[1:])) if lead is not None else (lambda a: a)

    def messages() -> NDArray[np.object_]:
        """The redone targets' sentences, made when first read: solve_all makes those of every branch (a few µs
        each; 4 ms of a Kinova's 1,000 targets with 100 out of reach), and most callers never read them."""
        message[redo] = full.message[:, 0]
        out = shape(message)
        return _message_of(out, out.shape)

    return IKResult._later(tuple(shape(fields[f]) for f in _STACKED) + (None,), messages)


def _nearest_named_later(robot: Robot, solver: ClosedForm, target: Array, q0: Array, position_only: bool,
                         tol: tuple[float, float] | None, enforce_limits: bool, lead: tuple[int, ...] | None,
                         fields: dict, fine: NDArray[np.bool_]) -> IKResult:
    """:func:`solve_nearest`'s answer for a family that names its branches from their joint values
    (:func:`_names_later`): the targets it cannot answer by the first branch redone by :func:`solve_all`, then every
    field but ``q`` and ``success`` made when first read, the names among all of each target's branches
    (``Geometric.name_branches``)."""
    redo = np.flatnonzero(~fine)
    full = solve_all(robot, solver, target[redo], q0[redo], position_only, tol, enforce_limits) if len(redo) \
        else None
    if full is not None:
        for f in ("q", "success"):
            fields[f][redo] = getattr(full, f)[:, 0]
    shape = (lambda a: a.reshape(lead + a.shape[1:])) if lead is not None else (lambda a: a)
    kept = target.copy()

    def make(made: tuple, which: str) -> Any:
        if which == "message":   # the redone targets' sentences from solve_all's first branch
            if full is not None:
                fields["message"][redo] = full.message[:, 0]
            return _message_of(shape(fields["message"]), shape(fields["success"]).shape)
        if full is not None:     # the redone targets' other fields (their names below, with every target's)
            for f in ("position_error", "rotation_error", "within_limits", "reason"):
                fields[f][redo] = getattr(full, f)[:, 0]
        named = _name(solver, fields["q"][:, None, :], kept)[:, 0]
        return {"position_error": shape(fields["position_error"]), "rotation_error": shape(fields["rotation_error"]),
                "iterations": shape(fields["iterations"]), "branch": shape(named),
                "within_limits": shape(fields["within_limits"]), "reason": shape(fields["reason"])}

    return IKResult._deferred((make,), shape(fields["q"]), shape(fields["success"]))
