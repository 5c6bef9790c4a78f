"""Targets that fix less than a full pose, for arms with fewer than six joints.

- position + tool pitch (``pitch=``): closed form, every branch, for the yaw + three parallel
  pitch axes (+ roll) family (the SO-101); see :mod:`armkit.ik.analytic.yaw_pitch3`.
- position + pointing direction (``direction=``): the tool's z axis (the approach axis) along
  a given direction, rotation about it free; Levenberg-Marquardt with the weights
  ``(1, 1, 1, 1, 1, 0)`` over ``(x, y, z, rx, ry, rz)`` (:mod:`armkit.ik.numeric`).

Both are reached through :func:`armkit.ik` and (pitch) :func:`armkit.ik_all`.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._text import Fielded
from ..errors import ShapeError
from ..kinematics import fk
from ..model.robot import Robot
from .api import IKInputError, _analytic_solver, _normalise_q0, _numeric, _reshape, _tolerance
from .result import IKResult, default_tolerance, verify

Array = NDArray[np.float64]
DIRECTION_MASK = (1.0, 1.0, 1.0, 1.0, 1.0, 0.0)
"""Weights over (x, y, z, rx, ry, rz) for a position and a pointing direction (rz: about the tool's z axis)."""


def _values(value: ArrayLike, name: str, lead: tuple[int, ...], tail: tuple[int, ...] = ()) -> Array:
    try:
        v = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ShapeError.of("{name} must be numeric, got {got}", name=name, got=f"{value!r}"[:250]) from exc
    try:
        v = np.broadcast_to(v, lead + tail)
    except ValueError as exc:
        raise (ShapeError.of("{name} must be a number or broadcast to the target's leading shape {lead}, got shape "
                             "{shape}", name=name, lead=lead, shape=v.shape) if not tail else
               ShapeError.of("{name} must be shape {tail} or broadcast to the target's leading shape {lead}, got shape "
                             "{shape}", name=name, tail=tail, lead=lead, shape=v.shape)) from exc
    if not np.all(np.isfinite(v)):
        raise ShapeError.of("{what} contains NaN or infinite values", what=name)
    return v


def _positions(target: ArrayLike, what: str) -> tuple[Array, tuple[int, ...]]:
    try:
        t = np.asarray(target, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ShapeError.of("{name} must be numeric, got {got}", name="target", got=f"{target!r}"[:250]) from exc
    if t.ndim == 0 or t.shape[-1] != 3:
        raise ShapeError.of("{what} goes with a position target (..., 3); got shape {shape}", what=what,
                            shape=t.shape)
    if not np.all(np.isfinite(t)):
        raise ShapeError.of("{what} contains NaN or infinite values", what="target")
    return t.reshape(-1, 3), t.shape[:-1]


def _frames(robot: Robot, p: Array, z: Array, q: Array) -> Array:
    """Target poses ``(B, 4, 4)`` at ``p`` with z axis ``z`` and x as near as possible to the tool's x at ``q``.

    The rotation about z is free (masked), but the rotation-vector error the solvers use is
    well-behaved only while that rotation stays below ~90 deg; starting it at 0 keeps it so.
    """
    x = fk(robot, q)[:, :3, 0]
    x = x - np.einsum("bi,bi->b", x, z)[:, None] * z
    norm = np.linalg.norm(x, axis=-1)
    helper = np.eye(3)[np.argmin(np.abs(z), axis=-1)]        # the tool's x along z: any perpendicular
    alt = helper - np.einsum("bi,bi->b", helper, z)[:, None] * z
    x = np.where((norm > 1e-6)[:, None], x, alt)
    x /= np.linalg.norm(x, axis=-1, keepdims=True)
    T = np.zeros((len(p), 4, 4))
    T[:, :3, 0], T[:, :3, 1], T[:, :3, 2], T[:, :3, 3], T[:, 3, 3] = x, np.cross(z, x), z, p, 1.0
    return T


def ik_direction(robot: Robot, target: ArrayLike, q0: ArrayLike | None, direction: Any, *,
                 method: str = "auto", mask: Any = None, phi: Any = None, branch: Any = None, scene: Any = None,
                 **numeric: Any) -> IKResult:
    """:func:`armkit.ik` for a position and a pointing direction of the tool's z axis (numeric).

    Levenberg-Marquardt (or Newton) on the target frame with z along ``direction`` and the
    weights :data:`DIRECTION_MASK`. The frame's free x axis starts at the tool's x of ``q0``;
    targets that fail are tried again from the configuration found, with the frame's x
    turned to that configuration's tool x (twice at most), so the free rotation never
    reaches the far side of the rotation-vector error.
    """
    if method not in ("auto", "analytic", "lm", "newton"):
        raise IKInputError.of("direction= is solved in closed form ('analytic', for a yaw + three pitch joints arm "
                              "such as the SO-101) or by the numeric methods 'lm' and 'newton' (or 'auto'); got method "
                              "{method!r}", method=method)
    for value, text in ((mask, "mask= does not go with direction=: direction= uses the mask (1, 1, 1, 1, 1, 0)"),
                        (phi, "phi= does not go with direction=: phi= is for planar (x, y) targets"),
                        (branch, "branch= does not go with direction=: branch= picks a closed-form solution; "
                                 "direction= is numeric"),
                        (scene, "scene= does not go with direction=: scene= is not available with direction= yet")):
        if value is not None:
            raise IKInputError.of(text)
    if method in ("auto", "analytic") and not numeric.get("trace"):   # one target: one compiled call
        one = _direction_one(robot, target, q0, direction, numeric.get("tol"),
                             bool(numeric.get("enforce_limits", True)))
        if one is not None:
            return one
    p, lead = _positions(target, "direction=")
    d = _values(direction, "direction", lead, (3,)).reshape(-1, 3)
    norm = np.linalg.norm(d, axis=-1)
    if np.any(norm < 1e-12):
        raise ShapeError.of("direction must be a non-zero 3-vector (the way the tool's z axis should point)")
    z = d / norm[:, None]
    q = _normalise_q0(robot, q0, lead)
    solver = None
    if method in ("auto", "analytic"):   # a yaw-pitch3 arm: the direction is a pitch (closed form, issue 20)
        solver = _pitch_solver(robot)
        if solver is None and method == "analytic":
            raise IKInputError.of("robot {robot!r} has no closed form for a position and a pointing direction (that "
                                  "is for arms with a yaw joint and three parallel pitch joints, like the SO-101); use "
                                  "method='lm'", robot=robot.name)
    if solver is not None and not numeric.get("trace"):   # the compiled kernels first (issue 20)
        fast, solved = nearest_direction(robot, p, z, q, _direction_tol(robot, numeric.get("tol")),
                                         bool(numeric.get("enforce_limits", True)))
        if fast is not None and solved.any():
            if solved.all():
                return _reshape(fast, lead)
            rest = np.flatnonzero(~solved)
            slow = _direction_flat(robot, p[rest], z[rest], q[rest], method, solver, numeric)
            return _reshape(_scatter(fast, slow, rest), lead)
    return _reshape(_direction_flat(robot, p, z, q, method, solver, numeric), lead)


def _direction_flat(robot: Robot, p: Array, z: Array, q: Array, method: str, solver: Any,
                    numeric: dict[str, Any]) -> IKResult:
    """:func:`ik_direction` on flat rows ``p``, ``z`` (B, 3), ``q`` (B, n) by NumPy: the closed form of
    ``solver`` (None: none), then Levenberg-Marquardt where it fails (``method`` 'auto'); fields (B, ...)."""
    closed = None
    if method in ("auto", "analytic"):
        if solver is not None:
            from .analytic.yaw_pitch3_direction import solve_direction

            every = solve_direction(robot, solver, p, z, q, _direction_tol(robot, numeric.get("tol")),
                                    bool(numeric.get("enforce_limits", True)))
            closed = every[np.arange(len(p)), 0]
            if method == "analytic" or bool(np.all(closed.success)):
                return closed
    name = "lm" if method in ("auto", "analytic") else method
    frames = _frames(robot, p, z, q)
    budget = numeric.get("restarts")
    # a short first try (3 restarts); the turned frames get the full budget
    quick = dict(numeric, restarts=min(3, 50 if budget is None else budget))
    res = _numeric(name, robot, frames, q, mask=DIRECTION_MASK, **quick)
    # the free rotation of a solution is unknown: frames turned by 180, 90 and 270 deg put every solution
    # within 45 deg of one of them; then the frame of the configuration found
    for turn in (math.pi, 0.5 * math.pi, 1.5 * math.pi, None):
        redo = np.flatnonzero(~np.asarray(res.success) & ((np.asarray(res.reason) != "unreachable") | (turn is None)))
        if len(redo) == 0:
            break
        if turn is None:
            start, T = res.q[redo].copy(), _frames(robot, p[redo], z[redo], res.q[redo])
        else:
            c, s_ = math.cos(turn), math.sin(turn)
            start, T = q[redo], frames[redo].copy()
            T[:, :3, 0], T[:, :3, 1] = c * frames[redo, :3, 0] + s_ * frames[redo, :3, 1], \
                -s_ * frames[redo, :3, 0] + c * frames[redo, :3, 1]
        again = _numeric(name, robot, T, start, mask=DIRECTION_MASK, **numeric)
        good = np.asarray(again.success)
        take = redo[good]
        if len(take) == 0:
            continue
        fields = {f: np.array(getattr(res, f), dtype=object if f in ("reason", "message", "branch") else None)
                  for f in ("q", "success", "position_error", "rotation_error", "iterations", "branch",
                            "within_limits", "reason", "message")}
        for f in fields:
            src = np.asarray(getattr(again, f))[good]
            fields[f][take] = src + fields[f][take] if f == "iterations" else src
        fields["reason"] = fields["reason"].astype(str)
        res = IKResult(**fields, trace=res.trace)
    if closed is not None:   # the closed form's answer where it solved, or where LM failed too (its reason is exact)
        take = np.asarray(closed.success) | ~np.asarray(res.success)  # type: ignore[assignment]
        if take.any():
            res = _merge(res, closed, take)  # type: ignore[arg-type]
    return res


def nearest_direction(robot: Robot, p: Array, z: Array, q0: Array, tol: tuple[float, float],
                      enforce_limits: bool) -> tuple[IKResult | None, NDArray[np.bool_]]:
    """The successful configuration nearest ``q0`` for positions ``p`` and unit directions ``z`` (B, 3), by the
    compiled kernels of :mod:`armkit.ik.analytic._yaw_pitch3_jit`, all rows in one call (``nearest_direction_rows``).

    Returns ``(result, solved)``: ``result`` fields (B, ...) (``q`` (B, n)), valid on the rows ``solved`` (B,).
    The other rows (a direction within 1e-4 of vertical, where the NumPy path sweeps the roll; no success,
    whose reason and message the NumPy path writes) are for :func:`_direction_flat`. ``(None, all False)``
    when the kernels are not in use for ``robot`` (the NumPy back end, not a 5-joint yaw-pitch3 arm), or
    with ``enforce_limits=False`` (the kernels always keep to the limits).
    """
    from .analytic.yaw_pitch3 import _LABELS, fast_geometry, fast_kernels

    B = len(p)
    solved = np.zeros(B, dtype=bool)
    g = fast_geometry(robot) if enforce_limits else None
    if g is None:
        return None, solved
    kern: Any = fast_kernels()
    q, dp, da = np.empty((B, 5)), np.full(B, np.inf), np.full(B, np.inf)
    lab = np.zeros(B, dtype=np.int64)
    pc, zc, qc = (np.ascontiguousarray(a, dtype=float) for a in (p, z, q0))
    kern.nearest_direction_rows(g, pc, zc, qc, float(tol[0]), float(tol[1]), q, dp, da, lab, solved)
    q[~solved] = q0[~solved]
    res = IKResult(q=q, success=solved.copy(), position_error=dp, rotation_error=da,
                   iterations=np.zeros(B, dtype=np.int64), branch=_LABELS[lab], within_limits=solved.copy(),
                   reason=np.where(solved, "converged", "unreachable"), message=np.full(B, "", dtype=object))
    return res, solved


def _scatter(res: IKResult, part: IKResult, rows: NDArray[np.intp]) -> IKResult:
    """``res`` (B rows) with ``rows`` replaced by the rows of ``part`` (len(rows) rows), the trace of ``part``."""
    fields = {}
    for f in ("q", "success", "position_error", "rotation_error", "iterations", "branch", "within_limits", "reason",
              "message"):
        a = np.array(getattr(res, f), dtype=object if f in ("reason", "message", "branch") else None)
        a[rows] = np.asarray(getattr(part, f))
        fields[f] = a.astype(str) if f == "reason" else a
    return IKResult(**fields, trace=part.trace)


def _pitch_solver(robot: Robot) -> Any:
    """The yaw-pitch3 closed form of ``robot``, or None."""
    from .analytic import closed_form

    solver = closed_form(robot)
    return solver if getattr(solver, "target_kind", None) == "pitch" else None


def _direction_tol(robot: Robot, tol: Any) -> tuple[float, float]:
    return default_tolerance(robot) if tol is None else (float(tol[0]), float(tol[1]))


def _merge(res: IKResult, other: IKResult, take: NDArray[np.bool_]) -> IKResult:
    """``res`` with the rows ``take`` from ``other`` (both flat, one answer per target)."""
    fields = {}
    for f in ("q", "success", "position_error", "rotation_error", "iterations", "branch", "within_limits", "reason",
              "message"):
        a = np.array(getattr(res, f), dtype=object if f in ("reason", "message", "branch") else None)
        a[take] = np.asarray(getattr(other, f))[take]
        fields[f] = a.astype(str) if f == "reason" else a
    return IKResult(**fields, trace=res.trace)


def ik_direction_all(robot: Robot, target: ArrayLike, q0: ArrayLike | None, direction: Any, *, tol: Any = None,
                     enforce_limits: bool = True, scene: Any = None, phi: Any = None) -> IKResult:
    """:func:`armkit.ik_all` with ``direction=``: every closed-form branch of a yaw-pitch3 arm (front/back x
    elbow), the tool's z axis along ``direction`` (:func:`armkit.ik.analytic.yaw_pitch3.solve_direction`)."""
    from .analytic.yaw_pitch3_direction import solve_direction

    if phi is not None:
        raise IKInputError.of("phi= is for planar (x, y) targets; it does not go with direction=")
    solver = _pitch_solver(robot)
    if solver is None:
        raise IKInputError.of("robot {robot!r} has no closed form for a position and a pointing direction (ik_all "
                              "with direction= is for arms with a yaw joint and three parallel pitch joints, like the "
                              "SO-101); use armkit.ik(..., direction=...) (numeric)", robot=robot.name)
    p, lead = _positions(target, "direction=")
    d = _values(direction, "direction", lead, (3,)).reshape(-1, 3)
    norm = np.linalg.norm(d, axis=-1)
    if np.any(norm < 1e-12):
        raise ShapeError.of("direction must be a non-zero 3-vector (the way the tool's z axis should point)")
    q = _normalise_q0(robot, q0, lead)
    res = solve_direction(robot, solver, p, d / norm[:, None], q, _tolerance(robot, tol), enforce_limits)
    if scene is not None:   # success also means collision-free (armkit.collision)
        from .scene import mark, scene_or_none, sort_branches

        res = sort_branches(mark(robot, res, scene_or_none(robot, scene)))  # type: ignore[arg-type]
    return _reshape(res, lead)


def ik_pitch(robot: Robot, target: ArrayLike, q0: ArrayLike | None, pitch: ArrayLike, *, method: str = "auto",
             branch: str | None = None, phi: Any = None, mask: Any = None, tol: Any = None,
             enforce_limits: bool = True, scene: Any = None, every: bool = False) -> IKResult:
    """:func:`armkit.ik` / :func:`armkit.ik_all` (``every``) for a position and the tool pitch (closed form)."""
    from .analytic.yaw_pitch3 import solve_pitch

    if method not in ("auto", "analytic"):
        raise IKInputError.of("pitch= is solved in closed form (method 'auto' or 'analytic'), got method {method!r}; "
                              "for a numeric solve give the pointing direction instead (direction=)", method=method)
    if mask is not None:
        raise IKInputError.of("mask= is for the numeric methods; pitch= is solved in closed form")
    if phi is not None:
        raise IKInputError.of("phi= is for planar (x, y) targets; it does not go with pitch=")
    if not every and branch is None and scene is None:   # one target: one compiled call, its result built here
        one = _pitch_one(robot, target, q0, pitch, tol, enforce_limits)
        if one is not None:
            return one
    p, lead = _positions(target, "pitch=")
    psi = _values(pitch, "pitch", lead).reshape(-1)
    why: list[str] = []
    solver = _analytic_solver(robot, True, why, pitch=True)
    if solver is None:
        raise IKInputError(why[0])
    q0f = _normalise_q0(robot, q0, lead)
    if not every and branch is None and scene is None:   # the nearest branch by the compiled kernels (issue 20)
        from .analytic.yaw_pitch3 import nearest_pitch

        fast = nearest_pitch(robot, solver, p, psi, q0f, _tolerance(robot, tol), enforce_limits)  # type: ignore[arg-type]
        if fast is not None:
            return _reshape(fast, lead)
    res = solve_pitch(robot, solver, p, psi, q0f, _tolerance(robot, tol), enforce_limits)  # type: ignore[arg-type]
    if scene is not None:   # success also means collision-free (armkit.collision)
        from .scene import mark, scene_or_none, sort_branches

        res = sort_branches(mark(robot, res, scene_or_none(robot, scene)))  # type: ignore[arg-type]
    if every:
        return _reshape(res, lead)
    rows = np.arange(len(p))
    if branch is None:
        return _reshape(res[rows, 0], lead)
    hit = res.branch == branch
    if not hit.any(axis=1).all():
        valid = sorted(set(np.asarray(res.branch).ravel().tolist()))
        raise IKInputError.of("unknown branch {name!r} for robot {robot!r}; valid branches: {names}", name=branch,
                              robot=robot.name, names=", ".join(valid))
    return _reshape(res[rows, np.argmax(hit, axis=1)], lead)


# ------------------------------------------------------------------ one target, one compiled call
_F64 = np.dtype(np.float64)
_NUMBER = (float, np.float64)
_PITCH_REASON = np.full(1, "converged", dtype=object).astype(str).reshape(())      # the dtypes the batched
_DIRECTION_REASON = np.where(np.ones(1, dtype=bool), "converged", "unreachable").reshape(())   # paths give


_LABELS_0D: list[Any] = []    # per label index: the 0-d object array a batched result's branch becomes


def _label(index: int) -> Any:
    """A fresh 0-d object array of the branch label ``index`` (as ``_LABELS[idx].reshape(())`` gives it)."""
    if not _LABELS_0D:
        from .analytic.yaw_pitch3 import _LABELS

        _LABELS_0D.extend(_LABELS[i:i + 1].reshape(()) for i in range(len(_LABELS)))
    return _LABELS_0D[index].copy()


def _kernels_for(robot: Robot) -> tuple[Any, Any]:
    """``(kernel module, packed geometry)`` of the yaw-pitch3 kernels for ``robot``; the geometry None when they do
    not serve it (:func:`armkit.ik.analytic.yaw_pitch3.fast_geometry`)."""
    from .analytic.yaw_pitch3 import fast_geometry, fast_kernels

    kern = fast_kernels()
    if kern is None:
        return None, None
    g = robot.cache.get("yaw_pitch3_fast", False)     # fast_geometry's record, kept per robot
    return kern, (fast_geometry(robot) if g is False else g)


def _one_start(robot: Robot, target: Any, q0: Any) -> Array | None:
    """The start ``(1, n)`` of one plain target: ``target`` a finite float64 ``(3,)`` and ``q0`` None or a finite
    float64 ``(n,)`` within 1e6 rad (what ``_normalise_q0`` keeps as it is); None for anything else (the batched
    path checks it, says what is wrong, or wraps the start)."""
    if type(target) is not np.ndarray or target.dtype != _F64 or target.shape != (3,):
        return None
    if not math.isfinite(target @ target):   # finite values (one that overflows the sum goes the batched way too)
        return None
    if q0 is None:
        return _normalise_q0(robot, None, ())
    if type(q0) is not np.ndarray or q0.dtype != _F64 or q0.shape != (robot.n,):
        return None
    if not q0 @ q0 <= 1e12:   # so every |q0_i| <= 1e6 (NaN fails too); a larger start goes the batched way
        return None
    return q0.reshape(1, -1).copy()


def _pitch_one(robot: Robot, target: Any, q0: Any, pitch: Any, tol: Any, enforce_limits: bool) -> IKResult | None:
    """:func:`ik_pitch` for one position ``(3,)`` and one pitch (a float) where the compiled kernel solves it plainly
    (the nearest branch succeeds, no note): the same result as the batched path, shaped for one target; None
    for anything else (the batched path answers, with its checks and messages)."""
    if type(pitch) not in _NUMBER or not math.isfinite(pitch):
        return None
    q = _one_start(robot, target, q0)
    if q is None:
        return None
    kern, g = _kernels_for(robot)
    if g is None:
        return None
    if tol is None:
        t = default_tolerance(robot)
    else:
        t = _tolerance(robot, tol)
    Q, DP, DR = np.empty((1, 4, 5)), np.empty((1, 4)), np.empty((1, 4))
    OK, WI = np.empty((1, 4), dtype=bool), np.empty((1, 4), dtype=bool)
    LAB, best = np.empty((1, 4), dtype=np.int64), np.empty(1, dtype=np.int64)
    p = np.ascontiguousarray(target.reshape(1, 3))      # a strided (3,) view: copied, one compiled signature
    kern.nearest_pitch(g, p, np.array([float(pitch)]), q, float(t[0]), float(t[1]), bool(enforce_limits), Q, DP, DR,
                       OK, WI, LAB, best)
    b = int(best[0])
    if b < 0:
        return None
    return IKResult._later((Q[0, b], OK[0, b, ...], DP[0, b, ...], DR[0, b, ...], np.zeros((), dtype=np.int64),
                            _label(int(LAB[0, b])), WI[0, b, ...], _PITCH_REASON.copy(), ""))


def _direction_one(robot: Robot, target: Any, q0: Any, direction: Any, tol: Any,
                   enforce_limits: bool) -> IKResult | None:
    """:func:`ik_direction` for one position and one direction (float64 ``(3,)`` each) that the compiled kernel
    solves (:func:`nearest_direction` for one row): the same result as the batched path, shaped for one target;
    None for anything else (the batched path answers, with its checks and messages)."""
    if type(direction) is not np.ndarray or direction.dtype != _F64 or direction.shape != (3,) \
            or not enforce_limits:
        return None
    q = _one_start(robot, target, q0)
    if q is None:
        return None
    d = direction.reshape(1, 3)
    norm = np.linalg.norm(d, axis=-1)       # as the batched path normalises it, to the last bit
    if not (norm[0] >= 1e-12 and math.isfinite(norm[0])):
        return None
    kern, g = _kernels_for(robot)
    if g is None or _pitch_solver(robot) is None:
        return None
    t = _direction_tol(robot, tol)
    qo, dp, da = np.empty((1, 5)), np.full(1, np.inf), np.full(1, np.inf)
    lab, solved = np.zeros(1, dtype=np.int64), np.zeros(1, dtype=bool)
    p = np.ascontiguousarray(target.reshape(1, 3))
    kern.nearest_direction_rows(g, p, d / norm[:, None], q, float(t[0]), float(t[1]), qo, dp, da, lab, solved)
    if not solved[0]:
        return None
    yes = np.ones((), dtype=bool)
    return IKResult._later((qo[0], yes, dp[0, ...], da[0, ...], np.zeros((), dtype=np.int64), _label(int(lab[0])),
                            yes.copy(), _DIRECTION_REASON.copy(), ""))


def too_few_joints(prob: Any, res: IKResult, failed: NDArray[np.intp], seed: Any) -> list[str]:
    """Sentences for targets that ask more (``weights``) than the arm's joints can give, one per ``failed``.

    The nearest reachable pose is searched with the position first: Levenberg-Marquardt with
    the rotation weights cut to 1e-6 (the orientation then only moves where the position
    leaves freedom), from the configurations found, then position-only steps from there to
    meet the position exactly; the rotation error against the target is the miss. Where that
    search does not meet the position, the sentence gives the best compromise found (``res``).
    """
    from .numeric import _solve, _subproblem

    robot = prob.robot
    n, weights = robot.n, int(np.count_nonzero(prob.w > 0))
    what = "an arbitrary orientation" if weights == 6 else "this position and pointing direction"   # terms
    sub = _subproblem(prob, failed)
    sub.q0 = np.asarray(res.q, dtype=float)[failed].copy()
    sub.w = np.where(np.arange(6) < 3, prob.w, prob.w * 1e-6)
    sub.full_pose = sub.position_only = False
    near = _solve(sub, "lm", 100, 20, seed, False, None, diagnose=False)
    sub.q0, sub.w = np.asarray(near.q, dtype=float).copy(), np.where(np.arange(6) < 3, prob.w, 0.0)
    sub.position_only = True   # then the position exactly, from there (the orientation moves ~1e-6 rad)
    met = _solve(sub, "lm", 100, 0, seed, False, None, diagnose=False)
    dp, dr, _, _ = verify(robot, met.q, prob.target[failed], False, prob.tol, prob.enforce_limits)
    out: list[str] = []
    for j, i in enumerate(failed):
        if dp[j] <= prob.tol[0]:
            out.append(Fielded.of("{n} joints cannot reach {what}; the nearest reachable pose (with the position met) "
                                  "misses by {angle}; q is the least-squares compromise found (1 m weighs as 1 rad)",
                                  terms=("what",), n=n, what=what, angle=f"{math.degrees(float(dr[j])):.3g} deg"))
        else:
            out.append(Fielded.of("{n} joints cannot reach {what}; the nearest pose found misses by {angle} and "
                                  "{distance}", terms=("what",), n=n, what=what,
                                  angle=f"{math.degrees(float(res.rotation_error[i])):.3g} deg",
                                  distance=f"{float(res.position_error[i]):.3g} {robot.unit}"))
    return out
