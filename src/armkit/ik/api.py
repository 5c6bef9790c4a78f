"""The public IK entry points :func:`ik` and :func:`ik_all`: target normalisation and dispatch.

``method="auto"`` uses the closed form when the robot's *structure* admits one (found
from the DH model by :func:`armkit.ik.analytic.closed_form`, never from its name) and the
target fits it, otherwise Levenberg-Marquardt. The numeric solvers live in
:mod:`armkit.ik.numeric`, :mod:`armkit.ik.ccd` and :mod:`armkit.ik.fabrik` and are
imported only when asked for.
"""

from __future__ import annotations

import importlib
import math
from typing import Any, Callable, Literal, Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _jit_loader
from .._checks import real_array, short_repr
from .._text import Fielded
from ..errors import IKInputError, ShapeError, UnreachableError
from ..kinematics import fk, jacobian
from ..model.robot import Robot
from ..spatial import check_transform
from .result import IKResult, default_tolerance

__all__ = ["ik", "ik_all", "METHODS", "IKInputError", "closed_form_family"]

Array = NDArray[np.float64]
METHODS = ("auto", "analytic", "lm", "newton", "ccd", "fabrik")
_NUMERIC = {"lm": ("numeric", "solve_lm"), "newton": ("numeric", "solve_newton"),
            "ccd": ("ccd", "solve_ccd"), "fabrik": ("fabrik", "solve_fabrik")}


def closed_form_family(robot: Robot) -> Optional[str]:
    """Name of the closed-form family of ``robot`` (``"ur"``, ``"spherical-wrist"``, ...) or ``None``.

    Examples
    --------
    >>> import armkit
    >>> closed_form_family(armkit.load("puma560")), closed_form_family(armkit.load("iiwa14"))
    ('spherical-wrist', None)
    """
    from .analytic import closed_form

    solver = closed_form(robot)
    return None if solver is None else solver.family


# ----------------------------------------------------------------------------- targets
def _planar_plane(robot: Robot) -> tuple[float, Array, float]:
    """For an arm moving in the world xy plane: its height z, tool rotation at q = 0 and end angle there."""
    J = jacobian(robot, robot.random_q(rng=0))
    # every turn about z and every slide across it (J's z row and its x, y turning rows are 0): a planar arm, its
    # slides included (a polar arm's turn and reach)
    axes_z = np.allclose(J[3:5], 0.0, atol=1e-9) and np.allclose(J[2], 0.0, atol=1e-9 * robot.reach)
    if not axes_z:
        raise ShapeError.of("2-D targets (x, y) are for planar arms moving in the world xy plane; robot "
                            "{robot!r} is not one: give (x, y, z) or a pose", robot=robot.name)
    T0 = fk(robot, np.zeros(robot.n))
    return float(T0[2, 3]), T0[:3, :3], math.atan2(T0[1, 0], T0[0, 0])


def _normalise_target(robot: Robot, target: ArrayLike, phi: ArrayLike | None, check: bool = True
                      ) -> tuple[Array, tuple[int, ...], bool]:
    """``target`` -> ``(flat targets (B, 4, 4) or (B, 3), leading shape, position_only)``; poses are checked
    by :func:`armkit.spatial.check_transform` unless ``check`` is False."""
    t = real_array(target, "target")
    if t.ndim == 0:
        raise ShapeError.of("target must be a pose (..., 4, 4), a position (..., 3) or a planar position (..., 2), "
                            "got a scalar {got}", got=repr(t))
    if not np.all(np.isfinite(t)):
        raise ShapeError.of("{what} contains NaN or infinite values", what="target")
    if t.ndim >= 2 and t.shape[-2:] == (4, 4):
        if phi is not None:
            raise ShapeError.of("phi= is only for planar (..., 2) position targets; a pose already fixes the end "
                                "angle")
        if check:
            check_transform(t, what="target")
        lead = t.shape[:-2]
        return t.reshape(-1, 4, 4), lead, False
    if t.shape[-1] == 3:
        if phi is not None:
            raise ShapeError.of("phi= is only for planar (..., 2) position targets; for a 3-D target give a pose")
        return t.reshape(-1, 3), t.shape[:-1], True
    if t.shape[-1] == 2:
        z, R0, phi0 = _planar_plane(robot)
        lead = t.shape[:-1]
        if phi is None:
            p = np.concatenate([t, np.full(lead + (1,), z)], axis=-1)
            return p.reshape(-1, 3), lead, True
        if robot.n < 3:
            raise ShapeError.of("robot {robot!r} has {n} joints: it cannot also choose the end angle phi; leave phi "
                                "out", robot=robot.name, n=robot.n)
        try:
            ph = np.broadcast_to(real_array(phi, "phi"), lead)
        except ValueError as exc:
            raise ShapeError.of("phi must be a number or broadcast to the target's leading shape {lead}, got shape "
                                "{shape}", lead=lead, shape=np.shape(phi)) from exc
        if not np.all(np.isfinite(ph)):
            raise ShapeError.of("{what} contains NaN or infinite values", what="phi")
        c, s = np.cos(ph - phi0), np.sin(ph - phi0)
        Rz = np.zeros(lead + (3, 3))
        Rz[..., 0, 0], Rz[..., 0, 1], Rz[..., 1, 0], Rz[..., 1, 1], Rz[..., 2, 2] = c, -s, s, c, 1.0
        T = np.zeros(lead + (4, 4))
        T[..., :3, :3] = Rz @ R0
        T[..., :2, 3] = t
        T[..., 2, 3] = z
        T[..., 3, 3] = 1.0
        return T.reshape(-1, 4, 4), lead, False
    raise ShapeError.of("target must be a pose (..., 4, 4), a position (..., 3) or, for planar arms, (..., 2); got "
                        "shape {shape}", shape=t.shape)


def _normalise_q0(robot: Robot, q0: ArrayLike | None, lead: tuple[int, ...]) -> Array:
    if q0 is None:
        base = robot.cache.get("ik_q0")   # a Robot is immutable: its clipped zero vector is kept in its cache
        if base is None:
            base = robot.cache["ik_q0"] = np.clip(np.zeros(robot.n), robot.lower, robot.upper)
        if not lead:
            return base[None].copy()
        return np.broadcast_to(base, (math.prod(lead), robot.n)).copy()
    q = robot.check_q(real_array(q0, "q0"), "q0")
    # A start beyond any meaning (|q| > 1e6 rad) is taken modulo 2 pi for revolute joints and
    # clipped to the limits for prismatic ones: q0 = 1e308 must not turn a reachable target unreachable.
    if np.any(np.abs(q) > 1e6):
        wrapped = np.where(robot.prismatic, np.clip(q, robot.lower, robot.upper), np.remainder(q + math.pi, 2 * math.pi) - math.pi)
        q = np.where(np.abs(q) > 1e6, wrapped, q)
    try:
        q = np.broadcast_to(q, lead + (robot.n,))
    except ValueError as exc:
        raise ShapeError.of("q0 must broadcast to the targets' shape {shape}, got {got}", shape=lead + (robot.n,),
                            got=q.shape) from exc
    return q.reshape(-1, robot.n).copy()


def _targets_and_start(robot: Robot, target: ArrayLike, q0: ArrayLike | None, phi: ArrayLike | None,
                       check: bool) -> tuple[Array, tuple[int, ...], bool, Array]:
    """Flat targets, their leading shape, position-only, flat starts: the leading axes of ``target`` and
    ``q0`` broadcast both ways (a (1, n) start for (B, 4, 4) targets, or (3, n) starts for one target)."""
    flat, lead, position_only = _normalise_target(robot, target, phi, check)
    if q0 is not None and np.ndim(q0) >= 2:
        try:
            full = np.broadcast_shapes(lead, np.shape(q0)[:-1])
        except ValueError as exc:
            raise ShapeError.of("q0 must broadcast to the targets' shape {shape}, got {got}", shape=lead + (robot.n,),
                                got=np.shape(q0)) from exc
        if full != lead:   # more starts than targets: each target is solved from each of its starts
            tail = flat.shape[1:]
            flat = np.broadcast_to(flat.reshape(lead + tail), full + tail).reshape((-1,) + tail)
            lead = full
    return flat, lead, position_only, _normalise_q0(robot, q0, lead)


def _tolerance(robot: Robot, tol: Any) -> tuple[float, float]:
    if tol is None:
        return default_tolerance(robot)
    t = real_array(tol, "tol")
    if t.shape == ():
        p, r = float(t), default_tolerance(robot)[1]
    elif t.shape == (2,):
        p, r = float(t[0]), float(t[1])
    else:
        raise IKInputError.of("tol must be a number or (position, rotation), got {got}", got=short_repr(tol))
    if not (0 < p < math.inf and 0 < r < math.inf):
        raise IKInputError.of("tol must be positive and finite (position in {unit}, rotation in rad), got {got}",
                              unit=robot.unit, got=short_repr(tol))
    return p, r


def _check_call(robot: Any, seed: Any = None, max_iterations: Any = None, restarts: Any = None) -> None:
    """The arguments every IK entry point shares: a Robot, a usable seed and counts."""
    if not isinstance(robot, Robot):
        if isinstance(robot, str):
            raise IKInputError.of("robot must be an armkit.Robot, got the string {got}; load it first: "
                                  "armkit.load({got})", got=short_repr(robot))
        raise IKInputError.of("robot must be an armkit.Robot, got {kind}", kind=type(robot).__name__)
    if seed is not None and not isinstance(seed, np.random.Generator):
        if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
            raise IKInputError.of("seed must be a non-negative integer or a numpy Generator, got {got}",
                                  got=short_repr(seed))
    for name, v in (("max_iterations", max_iterations), ("restarts", restarts)):
        if v is not None and (isinstance(v, bool) or not isinstance(v, (int, np.integer))
                              or not 0 <= v <= 10_000_000 or (name == "max_iterations" and v < 1)):
            raise IKInputError.of("{name} must be an integer between {low} and {high:,}, got {got}", name=name,
                                  low=1 if name == "max_iterations" else 0, high=10_000_000, got=short_repr(v))


def _reshape(res: IKResult, lead: tuple[int, ...]) -> IKResult:
    """Fields ``(B, ...)`` -> ``lead + (...)``."""
    def f(a: Any) -> Any:
        b = a if isinstance(a, np.ndarray) else np.asarray(a)
        return b.reshape(lead + b.shape[1:])

    trace = res.trace
    if trace is not None and np.ndim(trace) >= 1 and np.shape(trace)[0] == math.prod(lead):
        trace = np.asarray(trace).reshape(lead + np.shape(trace)[1:])   # per-target rows, like the other fields
    return res._map(f, trace)


def _one_row(a: Any) -> Any:
    """A field of one target's result with a leading axis of 1 (the ``(B, m)`` rows that
    :func:`.scene.sort_branches` sorts)."""
    return np.asarray(a)[None]


def _scene(robot: Robot, scene: Any) -> Any:
    """``scene=`` by the one collision rule (:func:`armkit.collision.resolve_scene`): a Scene, or None for no check.

    A robot without collision keys and ``scene=None`` is answered here without importing anything
    (the single-call path stays as fast as it was)."""
    if scene is None and robot.__dict__.get("collision") is None:
        return None
    from ..collision.query import resolve_scene

    return resolve_scene(robot, scene)


def _checked(robot: Robot, res: IKResult, scene: Any) -> IKResult:
    """``res`` with ``checked_against`` set: what its successes were checked against (nothing for None)."""
    if scene is not None:
        from ..collision.query import checked_against

        object.__setattr__(res, "checked_against", checked_against(robot, scene))
    return res


def _raise_if_unreachable(res: IKResult) -> None:
    reason = np.asarray(res.reason)
    failed = (reason == "unreachable") & ~np.asarray(res.success)
    if failed.any():
        idx = np.argwhere(failed)[0]
        if failed.ndim == 0:   # the solver's sentence as it is (it keeps its template and fields)
            raise UnreachableError(np.asarray(res.message).item())
        raise UnreachableError.of("{message} (target {index})", message=np.asarray(res.message)[tuple(idx)],
                                  index=tuple(int(i) for i in idx))


# --------------------------------------------------------------------------- solvers
def _refused(why_not: list[str] | None, sentence: Callable[[], str]) -> None:
    """No closed-form solver: the reason ``sentence()`` appended to ``why_not``, made only where one is wanted."""
    if why_not is not None:
        why_not.append(sentence())
    return None


def _analytic_solver(robot: Robot, position_only: bool, why_not: list[str] | None, pitch: bool = False):
    """The closed-form solver that answers ``robot`` for this kind of target, or None with the reason appended to
    ``why_not`` (None: the caller falls back to LM and reads no reason, so none is written)."""
    from .analytic import closed_form


    solver = closed_form(robot)
    if position_only and not pitch and (solver is None or solver.target_kind != "position"):
        from .analytic.held import position_solver   # a wrist that never moves the tool point, held at q0

        held = position_solver(robot)
        if held is not None:
            return held
    if solver is None:
        return _refused(why_not, lambda: Fielded.of(
            "robot {robot!r} ({n} DOF {types}) has no closed form in armkit: it solves 2R and 3R arms (a position; a "
            "planar 3R with the end angle; three axes through one point, an orientation), 1 to 3 joints "
            "with prismatic ones (a position: Cartesian, cylindrical, spherical, SCARA and the rest), a 4-joint SCARA "
            "(position and turn), yaw + three pitch joints (+ roll), 6R arms (by subproblems, or a 1-D or "
            "2-D search where the axes need one; prismatic joints before a spherical wrist, as in the Stanford arm) "
            "and 7-joint arms with a joint held (fixed=) or swept (ik_all); use method='lm'", robot=robot.name,
            n=robot.n, types=robot.joint_types))
    if pitch != (getattr(solver, "target_kind", None) == "pitch"):   # position + tool pitch: armkit.ik.partial
        return _refused(why_not, lambda: Fielded.of(
            "robot {robot!r} ({family}, {n} joints) has a closed form for a position and the tool pitch: give pitch= "
            "(rad); for a position alone, a pointing direction (direction=) or a pose use method='lm' (armkit.ik's "
            "default)" if not pitch else
            "robot {robot!r} ({family}, {n} joints) has no closed form for a position and a pitch (pitch= is for arms "
            "with a yaw joint and three parallel pitch joints, like the SO-101); leave pitch out",
            robot=robot.name, family=solver.family, n=robot.n))
    if pitch:
        return solver
    if position_only and solver.pose_only:
        return _refused(why_not, lambda: Fielded.of(
            "robot {robot!r} ({family}) needs a pose target for its closed form: give the end angle with phi=, or use "
            "method='lm' for position-only IK" if solver.family == "planar-3r" else
            "robot {robot!r} ({family}) needs a pose target for its closed form: give a (4, 4) pose, or use "
            "method='lm' for position-only IK", robot=robot.name, family=solver.family))
    return solver


def _all_branches(robot: Robot, target: Array, q0: Array, position_only: bool, tol: Any,
                  enforce_limits: bool, fixed: Any = None, sweep: Any = None) -> IKResult:
    from .analytic import solve_all

    why: list[str] = []
    solver = None
    if fixed is not None or sweep is not None or robot.n == 7:   # held or swept joints (ik.geometric.locked)
        from .geometric.locked import resolve

        solver = resolve(robot, fixed, sweep, position_only)
    if solver is None:
        solver = _analytic_solver(robot, position_only, why)
    if solver is None:
        raise IKInputError(why[0])
    held = getattr(solver, "held", None) if fixed else None   # fixed={} holds nothing: the arm's own solver
    if held and not getattr(solver, "at_start", False):   # the held joints start at their values: 2 pi wrapping keeps them
        q0 = q0.copy()
        q0[:, list(held)] = list(held.values())
    return solve_all(robot, solver, target, q0, position_only, _tolerance(robot, tol), enforce_limits)


_UNKNOWN = object()
_F64 = np.dtype(np.float64)   # compared as a dtype object: ~0.3 µs less than with the type np.float64
_single_call: Any = None   # analytic.single_call once imported (the one-call path counts microseconds)
ONE_CALL = True
"""Single targets by one compiled call (:func:`_one_target`); False: the batched path (tests compare the two)."""


def _one_target(robot: Robot, target: Any, q0: Any, tol: Any, enforce_limits: bool, check: bool, nearest: bool
                ) -> IKResult | None:
    """One float64 pose ``(4, 4)`` or position ``(3,)`` by the closed form in one compiled call
    (:func:`armkit.ik.analytic.single_call`): the result, shaped as :func:`ik` (``nearest``) or :func:`ik_all`
    give it for one target, or None where the general path answers (any other target or start, no closed form
    for it, a 7-joint arm, the NumPy back end, or a case the compiled call leaves to the batched path). The same
    values either way."""
    global _single_call
    if not ONE_CALL or type(target) is not np.ndarray or target.dtype != _F64:
        return None
    shape = target.shape
    if shape != (4, 4) and shape != (3,):
        return None
    n = len(robot.joints)
    if n == 7:
        return None
    if q0 is not None:
        if type(q0) is not np.ndarray or q0.dtype != _F64 or q0.shape != (n,):
            return None
        q0 = q0.ravel()
    solver = robot.cache.get("closed_form", _UNKNOWN)
    if solver is _UNKNOWN:
        from .analytic import closed_form

        solver = closed_form(robot)
    if solver is None or solver.target_kind == "pitch" or (solver.pose_only and shape == (3,)):
        return None
    if _single_call is None:
        from .analytic import single_call

        _single_call = single_call
    return _single_call(robot, solver, target, q0, None if tol is None else _tolerance(robot, tol), enforce_limits,
                        check, nearest)


_run_one: Any = None   # analytic.run_one once imported
_run_small: Any = None   # analytic.run_small_batch once imported
_NDARRAY = np.ndarray
_POSE = (4, 4)


def _fast_record(robot: Robot) -> Any:
    """What :func:`_fast` needs of ``robot``, made once (``robot.cache["ik_fast"]``): the one-call record of
    :func:`armkit.ik.analytic.one_call_record` (it names the target shapes its family takes); False where
    the defaults of :func:`ik` and :func:`ik_all` never take the one-call path without more checks (no closed
    form, a pitch family, a 7-joint arm, collision keys: the robot's own scene); None while the Numba back
    end does not serve (asked again next time; a pickled record also comes back as None)."""
    global _run_one, _run_small
    rec: Any = False
    if len(robot.joints) != 7 and robot.__dict__.get("collision") is None:
        from .analytic import closed_form, one_call_record, run_one, run_small_batch

        _run_one, _run_small = run_one, run_small_batch
        solver = closed_form(robot)
        if solver is not None and solver.target_kind != "pitch":
            rec = one_call_record(robot, solver)
            if rec is None:
                return None
    robot.cache["ik_fast"] = rec
    return rec


def _fast(robot: Any, target: np.ndarray, q0: Any, enforce_limits: Any, check: Any, nearest: bool
          ) -> IKResult | None:
    """:func:`ik` / :func:`ik_all` with their default options (no ``tol``, ``scene``, ``branch``, ...) for one
    float64 ``target``: the one-call path of :func:`_one_target` with the robot's record looked up once
    (:func:`_fast_record`), or None where the general code answers (it also raises every error). One pose with
    every default does not come here once the record is made: :func:`ik` and :func:`ik_all` call its closure
    (``c.one``) themselves."""
    if not ONE_CALL or type(robot) is not Robot or target.dtype is not _F64:
        return None
    c = robot.cache.get("ik_fast")   # (one pose with every default: the callers take c.one themselves first)
    if c is None:
        c = _fast_record(robot)
    if not c or _jit_loader._ACTIVE is None:
        return None
    shape = target.shape
    if q0 is None and enforce_limits is True and check is True and shape in c.shapes:   # the most common call
        return _run_one(robot, c, target, None, c.ctx_near if nearest else c.ctx, None, True, nearest)
    lead: tuple[int, ...] = ()
    if shape not in c.shapes:   # a few targets (..., 4, 4) or (..., 3): one call each (analytic.run_small_batch)
        lead = shape[:-2] if shape[-2:] == (4, 4) else shape[:-1]
        if not lead or shape[len(lead):] not in c.shapes or not 0 < math.prod(lead) <= (c.small_near if nearest
                                                                                       else c.small):
            return None
    if q0 is not None:
        if type(q0) is not _NDARRAY or q0.dtype is not _F64:
            return None
        if q0.shape == (c.n,):
            q0 = q0.ravel()
        elif not lead or q0.shape != lead + (c.n,):   # one start for all, or one per target
            return None
    if enforce_limits is True and check is True:
        ctx = c.ctx_near if nearest else c.ctx
    elif type(enforce_limits) is bool and type(check) is bool:
        ctx = c.context(None, enforce_limits, check, nearest)
    else:
        return None
    if not lead:
        return _run_one(robot, c, target, q0, ctx, None, check, nearest)
    tail = shape[len(lead):]
    starts = q0 if q0 is None or q0.ndim == 1 else q0.reshape(-1, c.n)
    res = _run_small(robot, c, target.reshape((-1,) + tail), starts, ctx, check, nearest,
                     lambda t, s: _batched(robot, t, s, enforce_limits, check, nearest))
    if res is None or len(lead) == 1:
        return res
    return res._map(lambda a: a.reshape(lead + np.shape(a)[1:]), None)


def _batched(robot: Robot, target: Array, q0: Array | None, enforce_limits: bool, check: bool, nearest: bool
             ) -> IKResult:
    """:func:`ik` (``nearest``) or :func:`ik_all` of float64 targets ``(B, 4, 4)`` or ``(B, 3)`` by the batched
    path, with the default options but ``q0``, ``enforce_limits`` and ``check``: what their general code answers
    (for the targets of a batch whose compiled call asked for it: :func:`armkit.ik.analytic.run_small_batch`)."""
    flat, lead, position_only, q0f = _targets_and_start(robot, target, q0, None, check)
    if nearest:
        return _nearest_branch(robot, flat, q0f, position_only, None, enforce_limits,
                               _analytic_solver(robot, position_only, None), lead)
    return _reshape(_all_branches(robot, flat, q0f, position_only, None, enforce_limits), lead)


def _nearest_branch(robot: Robot, target: Array, q0: Array, position_only: bool, tol: Any,
                    enforce_limits: bool, solver: Any = None, lead: tuple[int, ...] | None = None) -> IKResult:
    from .analytic import solve_nearest

    if solver is None:
        why: list[str] = []
        solver = _analytic_solver(robot, position_only, why)
        if solver is None:
            raise IKInputError(why[0])
    return solve_nearest(robot, solver, target, q0, position_only, _tolerance(robot, tol), enforce_limits, lead)


def _numeric(method: str, robot: Robot, target: Array, q0: Array, **kw: Any) -> IKResult:
    module, func = _NUMERIC[method]
    try:
        mod = importlib.import_module(f"armkit.ik.{module}")
        solve = getattr(mod, func)
    except (ImportError, AttributeError) as exc:
        raise IKInputError.of("method {method!r} is not available in this build of armkit ({reason})", method=method,
                              reason=str(exc)) from exc
    kw = {k: v for k, v in kw.items() if v is not None or k in ("mask", "seed", "tol")}
    return solve(robot, target, q0, **kw)


def ik_all(robot: Robot, target: ArrayLike, q0: ArrayLike | None = None, *, phi: ArrayLike | None = None,
           enforce_limits: bool = True, tol: Any = None, scene: Any = None, pitch: ArrayLike | None = None,
           check: bool = True, direction: ArrayLike | None = None, fixed: Any = None,
           sweep: int | None = None) -> IKResult:
    """Every closed-form solution (branch) for each target.

    Parameters
    ----------
    robot : Robot
        An arm with a closed form (see :mod:`armkit.ik.analytic`); others raise :class:`IKInputError`.
    target : array_like, shape (..., 4, 4), (..., 3) or (..., 2)
        Pose, position (position-only IK: the 2R and yaw-pitch-pitch families) or planar
        position (with ``phi`` for a 3R planar arm). Lengths in the robot's unit.
    q0 : array_like, shape (n,) or (..., n), optional
        Reference configuration: branches are sorted by distance to it, 2 pi turns chosen
        nearest to it, and free joints (singular families) take its values. Zeros if None.
    phi : float or array_like, shape (...), optional
        End angle (rad) of a planar arm for ``(..., 2)`` targets.
    enforce_limits : bool
        Branches outside the joint limits get ``success=False``, reason "joint limits".
    tol : float or (float, float), optional
        Position (robot unit) and rotation (rad) tolerance of the FK check.
    scene : None, False, armkit.Scene, path of a scene file or "robot"
        A branch that collides (with the scene, the robot's body or itself) fails with reason
        "collision" and a message naming the pair and the depth. None (the default): the
        robot's own surroundings from its robot file (the fighter's torso and ground; none for
        arms whose file has no collision keys); False: no check; a scene replaces the robot's
        ground, its body stays (:func:`armkit.collision.resolve_scene`, ``docs/scene.md``).
        ``IKResult.checked_against`` names what was checked.
    pitch : float or array_like, shape (...), optional
        Tool pitch (rad) for ``(..., 3)`` position targets of a yaw + three pitch joints
        (+ roll) arm such as the SO-101 (``docs/so101.md``); the roll joint keeps ``q0``.
        ``rotation_error`` is then the pitch error.
    check : bool
        Check that pose targets are rigid transforms (:func:`armkit.spatial.check_transform`);
        ``False`` skips it for poses a program built itself (hot loops).
    fixed : dict of str to float, optional
        Joints held at these values (rad, or lengths), e.g. ``{"A3": 0.5}`` on a 7-joint arm:
        the joints left are solved in closed form (when their class has one) and every branch
        keeps the held values exactly (:mod:`armkit.ik.geometric.locked`). With a position
        target, 1 to 3 joints left are solved for it (:mod:`armkit.ik.analytic.held`); without
        ``fixed``, a wrist whose axes pass through the tool point is held at ``q0``.
    sweep : int, optional
        7-joint arms without ``fixed``: the number of values (default 32, evenly spaced over
        its limits) of the joint whose locking leaves a closed form (``armkit info`` names it);
        every branch of every value is returned, labelled ``"<joint>=<value>/s<k>"``.

    Returns
    -------
    IKResult
        ``q`` ``(..., m, n)``, other fields ``(..., m)``; successful branches first, each
        group sorted by distance to ``q0``.

    Examples
    --------
    >>> import armkit, numpy as np
    >>> arm = armkit.load("planar2")
    >>> res = armkit.ik_all(arm, [1.2, 0.3])
    >>> res.branch.tolist(), res.success.tolist()
    (['elbow-down', 'elbow-up'], [True, True])
    >>> bool(np.allclose(armkit.fk(arm, res.q)[..., :2, 3], [1.2, 0.3]))
    True
    """
    if type(target) is _NDARRAY and phi is None and tol is None and scene is None and pitch is None \
            and direction is None and fixed is None and sweep is None:   # the common call: the fast path
        if q0 is None and enforce_limits is True and check is True and type(robot) is Robot \
                and (c := robot.cache.get("ik_fast")) and c.one is not None and target.shape == _POSE \
                and target.dtype is _F64 and ONE_CALL and _jit_loader._ACTIVE is not None:
            one = c.one[0](robot, target)   # one pose, every default: the record's closure called here, not by
        else:                               # _fast (0.2-0.3 µs of a 3.5 µs call)
            one = _fast(robot, target, q0, enforce_limits, check, False)
        if one is not None:
            return one
    _check_call(robot)
    if (fixed is not None or sweep is not None) and (pitch is not None or direction is not None):
        raise IKInputError.of("fixed= and sweep= are for pose targets; they do not go with pitch= or direction=")
    scene = _scene(robot, scene)
    if direction is not None:   # issue 20: every branch of a yaw-pitch3 arm for a pointing direction (ik.partial)
        from .partial import ik_direction_all

        return _checked(robot, ik_direction_all(robot, target, q0, direction, phi=phi, tol=tol,
                                                enforce_limits=enforce_limits, scene=scene), scene)
    if pitch is not None:
        from .partial import ik_pitch

        return _checked(robot, ik_pitch(robot, target, q0, pitch, phi=phi, tol=tol, enforce_limits=enforce_limits,
                                        scene=scene, every=True), scene)
    if fixed is None and sweep is None and phi is None:   # one target: one compiled call
        one = _one_target(robot, target, q0, tol, enforce_limits, check, False)
        if one is not None:
            if scene is None:
                return one
            from .scene import mark, sort_branches

            marked = mark(robot, one, scene)
            if marked is one:   # nothing collides: the branches and their order stand
                return _checked(robot, one, scene)
            rows = marked._map(_one_row, None)   # (1, m): the rows sort_branches sorts
            return _checked(robot, _reshape(sort_branches(rows), ()), scene)
    flat, lead, position_only, q0f = _targets_and_start(robot, target, q0, phi, check)
    res = _all_branches(robot, flat, q0f, position_only, tol, enforce_limits, fixed, sweep)
    if scene is not None:   # success also means collision-free (armkit.collision)
        from .scene import mark, sort_branches

        res = sort_branches(mark(robot, res, scene))
    return _checked(robot, _reshape(res, lead), scene)


def ik(robot: Robot, target: ArrayLike, q0: ArrayLike | None = None,
       method: Literal["auto", "analytic", "lm", "newton", "ccd", "fabrik"] = "auto", *,
       branch: str | None = None, phi: ArrayLike | None = None, mask: ArrayLike | None = None, tol: Any = None,
       max_iterations: int | None = None, restarts: int | None = None, seed: Any = None,
       enforce_limits: bool = True, raise_unreachable: bool = False, trace: bool = False,
       scene: Any = None, pitch: ArrayLike | None = None, direction: ArrayLike | None = None,
       check: bool = True, fixed: Any = None) -> IKResult:
    """Inverse kinematics: one solution per target, honest about failure.

    Parameters
    ----------
    robot : Robot
    target : array_like, shape (..., 4, 4), (..., 3) or (..., 2)
        Pose ``T_world_tool``, position (position-only IK) or, for planar arms, ``(x, y)``
        with the end angle ``phi``. Lengths in the robot's unit; batched over ``(...)``.
    q0 : array_like, shape (n,) or (..., n), optional
        Initial guess (numeric methods) or reference (closed form: the branch nearest
        to it is returned). Zeros (clipped into the limits) if None.
    method : {"auto", "analytic", "lm", "newton", "ccd", "fabrik"}
        "auto": the closed form when the robot's structure has one and the target fits it,
        otherwise "lm".
    branch : str, optional
        Closed form only: return this branch (e.g. ``"elbow-up"``, ``"front/elbow-down"``,
        ``"right/elbow-up/noflip"``) instead of the one nearest ``q0``.
    phi : float or array_like, optional
        End angle (rad) for ``(..., 2)`` targets of a 3R planar arm.
    mask : array_like, shape (6,), optional
        Numeric methods: weights of (x, y, z, rx, ry, rz) errors (e.g. a 5-DOF arm).
    tol : float or (float, float), optional
        Position (robot unit) and rotation (rad) tolerance; default
        :func:`~armkit.ik.result.default_tolerance`.
    max_iterations, restarts, seed
        Numeric methods: budget and reproducible random restarts. None: the method's
        default (LM and Newton :data:`~armkit.ik.DEFAULT_MAX_ITERATIONS` steps and
        :data:`~armkit.ik.DEFAULT_RESTARTS` restarts; CCD and FABRIK
        :data:`~armkit.ik.DEFAULT_MAX_SWEEPS` sweeps and :data:`~armkit.ik.DEFAULT_SWEEP_RESTARTS`).
    enforce_limits : bool
        A solution outside the joint limits is not a success.
    raise_unreachable : bool
        Raise :class:`~armkit.UnreachableError` (with the message saying how far out of
        reach) instead of returning ``success=False``.
    trace : bool
        Numeric methods: keep the per-iteration error in ``IKResult.trace``.
    scene : None, False, armkit.Scene, path of a scene file or "robot"
        Success also means collision-free: the closed form returns the nearest branch that
        does not collide, numeric methods restart from random configurations while the answer
        collides; what still collides fails with reason "collision". None (the default): the
        robot's own surroundings (the fighter's torso and ground), False: no check (see
        :func:`ik_all`); ``IKResult.checked_against`` names what was checked.
    pitch : float or array_like, shape (...), optional
        Tool pitch (rad) for a ``(..., 3)`` position: closed form for a yaw + three pitch
        joints (+ roll) arm such as the SO-101 (``docs/so101.md``); ``rotation_error`` is the
        pitch error.
    direction : array_like, shape (..., 3), optional
        For a ``(..., 3)`` position: the direction the tool's z axis should point, rotation
        about it free (numeric, the mask ``(1, 1, 1, 1, 1, 0)``).
    check : bool
        Check that pose targets are rigid transforms (:func:`armkit.spatial.check_transform`);
        ``False`` skips it for poses a program built itself (hot loops).
    fixed : dict of str to float, optional
        Joints held at these values (as in :func:`ik_all`): the nearest of the closed-form
        branches of the joints left (``branch=`` picks one of them instead).

    Returns
    -------
    IKResult
        Fields of shape ``(...)``, ``q`` ``(..., n)``. ``success`` is true only where FK of
        ``q`` meets the tolerance (and the limits, when enforced).

    Examples
    --------
    >>> import armkit, numpy as np
    >>> arm = armkit.load("fighter")
    >>> res = armkit.ik(arm, [24.861, 14.353, 187.181], q0=np.radians([25, 40, 65]))
    >>> bool(res.success), str(res.branch), np.round(np.degrees(res.q), 2).tolist()
    (True, 'front/elbow-down', [30.0, 45.0, 60.0])
    """
    if type(target) is _NDARRAY and type(method) is str and (method == "auto" or method == "analytic") \
            and branch is None and phi is None and mask is None and tol is None and scene is None and pitch is None \
            and direction is None and fixed is None and seed is None and max_iterations is None \
            and restarts is None and raise_unreachable is False:   # the common call: the fast path
        if q0 is None and enforce_limits is True and check is True and type(robot) is Robot \
                and (c := robot.cache.get("ik_fast")) and c.one is not None and target.shape == _POSE \
                and target.dtype is _F64 and ONE_CALL and _jit_loader._ACTIVE is not None:
            one = c.one[1](robot, target)   # as in ik_all
        else:
            one = _fast(robot, target, q0, enforce_limits, check, True)
        if one is not None:
            return one
    if type(robot) is Robot and (pos := robot.cache.get("yaw_pitch3_position")) is not False \
            and type(method) is str and method == "auto" and enforce_limits is True and trace is False \
            and branch is None and phi is None and mask is None and tol is None and scene is None and pitch is None \
            and direction is None and fixed is None and seed is None and max_iterations is None \
            and restarts is None and _jit_loader._ACTIVE is not None:   # the SO-101's position: its closed form
        if pos is None:      # the record is made by the first call (False for every other arm: not asked again)
            from .analytic.yaw_pitch3_position import position_route

            one = position_route(robot, target, q0)
        else:
            one = pos.route(robot, target, q0)   # None: another target, LM's few targets, beyond the reach
        if one is not None:
            if raise_unreachable:
                _raise_if_unreachable(one)
            return one
    if method not in METHODS:
        raise IKInputError.of("method must be one of {names}; got {method}", names=", ".join(METHODS),
                              method=short_repr(method))
    _check_call(robot, seed, max_iterations, restarts)
    scene = _scene(robot, scene)
    one = None
    if (method == "auto" or method == "analytic") and branch is None and mask is None and phi is None \
            and pitch is None and direction is None and fixed is None:   # one target: one compiled call
        one = _one_target(robot, target, q0, tol, enforce_limits, check, scene is None)
        if one is not None and scene is not None:   # the nearest branch that does not collide
            from .scene import nearest_free

            one = nearest_free(robot, one, scene)
    numeric: dict[str, Any] = {} if one is not None else {   # tol checked here (and by _one_target)
        "mask": mask, "tol": None if tol is None else _tolerance(robot, tol), "seed": seed,
        "enforce_limits": enforce_limits, "trace": trace, "max_iterations": max_iterations, "restarts": restarts}
    if one is not None:
        res = one
    elif fixed is not None:   # held joints (ik.geometric.locked): the nearest of every branch
        if method not in ("auto", "analytic") or pitch is not None or direction is not None or mask is not None:
            raise IKInputError.of("fixed= holds joints for the closed form: it goes with method='auto' or "
                                  "'analytic' and a pose target, not with pitch=, direction= or mask=")
        flat, lead, position_only, q0f = _targets_and_start(robot, target, q0, phi, check)
        res = _closed_one(robot, flat, q0f, lead, position_only, tol, enforce_limits, None, branch, scene, fixed)
    elif pitch is not None or direction is not None:   # targets that fix less than a pose (armkit.ik.partial)
        res = _partial(robot, target, q0, method, pitch, direction, branch, phi, tol, scene, numeric)
    else:
        flat, lead, position_only, q0f = _targets_and_start(robot, target, q0, phi, check)
        solver = None
        if method == "auto" and mask is None:   # no reason wanted: LM answers where there is no closed form
            solver = _analytic_solver(robot, position_only, None)
        use_closed = method == "analytic" or solver is not None
        if branch is not None and not use_closed:
            raise IKInputError.of("branch= picks a closed-form solution; method {method!r} is numeric"
                                  if method not in ("auto", "analytic") else
                                  "branch= picks a closed-form solution; robot {robot!r} has no closed form for this "
                                  "target", method=method, robot=robot.name)
        if use_closed:
            if mask is not None:
                raise IKInputError.of("mask= is for the numeric methods; the closed form solves the full target")
            res = _closed_one(robot, flat, q0f, lead, position_only, tol, enforce_limits, solver, branch, scene)
        else:
            res = _numeric_one(robot, "lm" if method == "auto" else method, flat, q0f, lead, scene, numeric)
    if raise_unreachable:
        _raise_if_unreachable(res)
    return _checked(robot, res, scene)


def _partial(robot: Robot, target: ArrayLike, q0: ArrayLike | None, method: str, pitch: Any, direction: Any,
             branch: str | None, phi: Any, tol: Any, scene: Any, numeric: dict[str, Any]) -> IKResult:
    """:func:`ik` for a position with a tool pitch or a pointing direction (:mod:`armkit.ik.partial`)."""
    from .partial import ik_direction, ik_pitch

    if pitch is not None and direction is not None:
        raise IKInputError.of("give pitch= or direction=, not both")
    if pitch is not None:
        return ik_pitch(robot, target, q0, pitch, method=method, branch=branch, phi=phi, mask=numeric["mask"],
                        tol=tol, enforce_limits=numeric["enforce_limits"], scene=scene)
    return ik_direction(robot, target, q0, direction, method=method, phi=phi, branch=branch, scene=scene, **numeric)


def _closed_one(robot: Robot, flat: Array, q0f: Array, lead: tuple[int, ...], position_only: bool, tol: Any,
                enforce_limits: bool, solver: Any, branch: str | None, scene: Any, fixed: Any = None) -> IKResult:
    """:func:`ik` by the closed form: the nearest branch, the nearest that does not collide, or ``branch``;
    with ``fixed``, of the branches of the joints left (:func:`ik_all`'s ``fixed=``)."""
    if branch is None and scene is None and fixed is None:   # shaped lead + (...) already
        return _nearest_branch(robot, flat, q0f, position_only, tol, enforce_limits, solver, lead)
    every = _all_branches(robot, flat, q0f, position_only, tol, enforce_limits, fixed)
    if branch is None:   # the nearest branch (with a scene: the nearest that does not collide)
        from .scene import mark, sort_branches

        every = sort_branches(mark(robot, every, scene) if scene is not None else every)
        return _reshape(every[np.arange(len(flat)), 0], lead)
    hit = every.branch == branch
    if not hit.any(axis=1).all():
        valid = sorted(set(np.asarray(every.branch).ravel().tolist()))
        raise IKInputError.of("unknown branch {name!r} for robot {robot!r}; valid branches: {names}", name=branch,
                              robot=robot.name, names=", ".join(valid))
    res = _reshape(every[np.arange(len(flat)), np.argmax(hit, axis=1)], lead)
    if scene is not None:
        from .scene import mark

        res = mark(robot, res, scene)
    return res


def _numeric_one(robot: Robot, name: str, flat: Array, q0f: Array, lead: tuple[int, ...], scene: Any,
                 kw: dict[str, Any]) -> IKResult:
    """:func:`ik` by a numeric method; with a scene, restarts away from collisions (:mod:`armkit.collision`)."""
    flat_res = _numeric(name, robot, flat, q0f, **kw)
    if scene is not None:
        from .scene import retry_numeric

        flat_res = retry_numeric(robot, flat_res, scene,
                                 lambda q0r, rows: _numeric(name, robot, flat[rows], q0r, **kw), kw["seed"])
    return _reshape(flat_res, lead)
