r"""Numerical IK on any serial chain: Levenberg-Marquardt (damped least squares) and Newton.

Both solvers iterate every target of a batch together (batched FK, Jacobians and linear
solves; with Numba, one compiled loop per target run in parallel threads) and report
honestly: ``success`` comes only from the FK check :func:`armkit.ik.verify` (or its
masked form, see ``mask``), and a failure says why (``reason``) and by how much
(``message``). A single target with the default mask and tolerance takes a short route
to the same kernel, seeds and check (single-call latency is mostly Python around the
kernel); its result is the same, field by field.

The task error
--------------
For the current tool pose :math:`(R, p)` and the target :math:`(R_t, p_t)`

.. math::

    e = \begin{pmatrix} s\,(p_t - p) \\ \log(R^T R_t)^\vee \end{pmatrix} \in \mathbb{R}^6 ,

the position part in metres (``s`` = metres per length unit, so a mm arm behaves like a
m arm) in the world frame, the rotation part as a rotation vector in the *target* frame
(the rotation still to be done). The solvers model the error as
:math:`e(q + \Delta q) \approx e(q) - J\,\Delta q` with the task Jacobian

.. math::

    J = \begin{pmatrix} s\,J_v \\ R_t^T J_\omega \end{pmatrix}

(:math:`J_v, J_\omega` the rows of the geometric Jacobian in the world frame; prismatic
joints move in metres). The linear rows are exact. The angular rows are the derivative of
the rotation error only at zero error: the exact rows are
:math:`J_r^{-1}(e_r)\,R_t^T J_\omega`, with the inverse right Jacobian of SO(3)

.. math::

    J_r^{-1}(\phi) = I + \tfrac12 [\phi]_\times
        + \Bigl(\frac{1}{\theta^2} - \frac{1 + \cos\theta}{2\theta\sin\theta}\Bigr)[\phi]_\times^2,
    \qquad \theta = \lVert\phi\rVert ,

so the exact rows differ from the rows used by at most
:math:`\lVert J_r^{-1}(e_r) - I\rVert_2 = \sqrt{\theta^2/4 + c^2\theta^4}` relative to them
(:math:`c` the bracket above): 0.51 at 1 rad of rotation error, 0.050 at 0.1 rad, 0.0050 at
0.01 rad (``tests/ik/test_lm_task_jacobian.py`` checks this by finite differences of the
solvers' own error, for both engines). Near a solution this costs nothing: a Jacobian error
of order :math:`\theta` times a step of order :math:`\theta` is of second order, so the
convergence stays quadratic; far from the target the step differs from the Gauss-Newton
step by up to that factor, which the damping and the accept/reject rule below absorb.
The exact rows were tried (NumPy engine, 1,000 random reachable poses per arm, default
restarts) and do not pay: mean iterations 19.3 -> 20.4 (UR5), 28.7 -> 29.0 (Panda),
26.4 -> 27.6 (Puma 560, and one failure more), so the solvers keep the simpler rows.
A weight vector ``w`` (the ``mask``) over ``(x, y, z, rx, ry, rz)`` selects what
matters: position-only is ``(1, 1, 1, 0, 0, 0)``; a 5-DOF arm that cannot choose the
rotation about its tool axis uses ``(1, 1, 1, 1, 1, 0)``. Masked position axes are world
axes; masked rotation axes are axes of the target frame.

Levenberg-Marquardt
-------------------
With :math:`W = \mathrm{diag}(w)` and the cost :math:`E = \tfrac12 e^T W e` one step solves

.. math:: (J^T W J + \lambda I)\,\Delta q = J^T W e, \qquad \lambda = \mu E + 10^{-12},

an error-dependent damping in the spirit of Chan and Lawrence (1988) and Sugihara (2011):
far from the target the step is short and safe, near it :math:`\lambda \to 0` and the
iteration becomes Gauss-Newton with quadratic convergence. Steps that lower the cost are
accepted (and :math:`\mu` shrinks), others are rejected (and :math:`\mu` grows), as in
Marquardt's method. After each step the joints are projected into their limits (revolute
joints by whole turns when that brings them inside, then clamping). An attempt stops when
it converges, after ``max_iterations`` steps, or when its cost has not fallen by 1 % for
8 steps; the next attempt starts from a random configuration inside the limits, up to
``restarts`` times.

Newton
------
:func:`solve_newton` is the textbook iteration :math:`\Delta q = (W^{1/2} J)^+ W^{1/2} e`
with the Moore-Penrose pseudo-inverse, full steps and no damping: fast near a solution,
erratic near singularities. It exists for teaching and comparison; use LM for work.

References
----------
S. K. Chan and P. D. Lawrence, "General inverse kinematics with the error damped
pseudoinverse", ICRA 1988. T. Sugihara, "Solvability-unconcerned
inverse kinematics by the Levenberg-Marquardt method", IEEE T-RO 27(5), 2011.
"""

from __future__ import annotations

import math
import time
from typing import Any, Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _jit_loader
from .. import kinematics as _kinematics
from .._text import Fielded
from ..errors import ShapeError
from ..model.robot import Robot
# the pieces of the solvers, re-exported here: ccd, fabrik, partial, the analytic solvers and the tests import them
# from this module
from ._numeric_inputs import (_TOL_FACTOR, _W_POSE, _W_POSITION, Problem, _constants, _seed_base, _seeds,
                              _subproblem, shoulder_distance)
from ._numeric_numpy import (_STALL_STEPS, _errors, _evaluate, _leaves_range, _project, _rotation_vector,
                             _run_numpy, _smallest_sigma, _step)
from ._numeric_report import _fmt, _trace_array, assemble, check, residual_note, unreachable_note
from .result import (DEFAULT_MAX_ITERATIONS, DEFAULT_NEWTON_RESTARTS, DEFAULT_RESTARTS, IKResult, default_tolerance,
                     verify)
from .verdict import settle

__all__ = ["solve_lm", "solve_newton"]

Array = NDArray[np.float64]

_SINGULAR_SIGMA = 1e-5  # smallest singular value (metres, rad) below which a stalled solve is "singular"


# ------------------------------------------------------------------------------- Numba engine
def _jit():
    """The compiled kernels, or None when Numba is unavailable or the NumPy backend is chosen."""
    return _jit_loader.kernels("ik._jit_lm")


def _kernel_args(const: dict, s: float, tol: tuple[float, float], w: Array, max_iterations: int, attempts: int,
                 first_attempt: int) -> Array:
    """The kernel's packed options ``params`` (layout: :mod:`armkit.ik._jit_lm`), cached per robot (they
    repeat from call to call)."""
    key = ("params", tol, True if w is _W_POSE else False if w is _W_POSITION else w.tobytes(), max_iterations,
           attempts, first_attempt)
    params = const.get(key)
    if params is None:
        k = _jit_loader.module("ik._jit_lm")
        params = np.empty(k.N_PARAMS)
        params[k.SCALE], params[k.TOL_P], params[k.TOL_R] = s, tol[0] * s * _TOL_FACTOR, tol[1] * _TOL_FACTOR
        params[k.W:k.W + 6] = w
        params[k.MAX_ITERATIONS], params[k.FIRST_ATTEMPT], params[k.ATTEMPTS] = max_iterations, first_attempt, attempts
        params.setflags(write=False)
        if len(const) < 64:
            const[key] = params
    return params


def _run_jit(kernels, prob: Problem, q: Array, max_iterations: int, attempts: int, first_attempt: int,
             seeds: NDArray[np.uint64], want_trace: bool):
    B, n = q.shape
    q = np.array(q, dtype=float, order="C")
    info = np.zeros((B, 4))
    cap = max_iterations * attempts if want_trace else 0
    trace = np.full((B, cap), np.nan) if cap else np.empty((B, 0))
    params = _kernel_args(prob.const, prob.s, prob.tol, prob.w, max_iterations, attempts, first_attempt)
    run = kernels.lm_batch if B >= 8 else kernels.lm_serial
    run(_kinematics.packed(prob.robot)[1], prob.packed_limits, params, prob.poses, seeds, q, trace, info)
    iters = info[:, 0].astype(np.int64)
    rows = [trace[i, :iters[i]].tolist() for i in range(B)] if want_trace else []
    return q, iters, info[:, 2].astype(np.int64), info[:, 1] == 0, info[:, 3], rows



# --------------------------------------------------------------------------------- the solvers
def _solve(prob: Problem, method: str, max_iterations: Optional[int], restarts: Optional[int], seed: Any,
           trace: bool, time_limit: Optional[float], diagnose: bool = True) -> IKResult:
    max_iterations = DEFAULT_MAX_ITERATIONS if max_iterations is None else int(max_iterations)
    restarts = DEFAULT_RESTARTS if restarts is None else int(restarts)
    if max_iterations < 0 or restarts < 0:
        raise ShapeError.of("max_iterations and restarts must be >= 0, got {max_iterations} and {restarts}",
                            max_iterations=max_iterations, restarts=restarts)
    newton = method == "newton"
    B = prob.B
    unreachable, dist = prob.unreachable()
    any_unreachable = bool(unreachable.any())
    kernels = None if newton else _jit()
    seeds = _seeds(seed, B)
    total_attempts = restarts + 1
    if kernels is not None and time_limit is None and not any_unreachable:  # the common case, no bookkeeping
        q, iters, used, _, _, rows = _run_jit(kernels, prob, prob.q0, max_iterations, total_attempts, 0, seeds,
                                              trace)
        return _finish(prob, q, iters, used, method, max_iterations, restarts, seed, _trace_array(rows), diagnose)
    rng = np.random.default_rng(0 if seed is None else seed) if kernels is None else None
    q = prob.q0.copy()
    iters = np.zeros(B, np.int64)
    used = np.zeros(B, np.int64)
    done = np.zeros(B, bool)
    rows = [[] for _ in range(B)] if trace else []
    t0 = time.perf_counter()
    if time_limit is None:
        # provably unreachable targets get one attempt (the closest configuration from q0), no restarts
        rounds = [(np.flatnonzero(unreachable), 0, 1), (np.flatnonzero(~unreachable), 0, total_attempts)]
    else:  # attempt by attempt, checking the clock between rounds
        rounds = [(np.flatnonzero(unreachable), 0, 1)] + \
                 [(np.flatnonzero(~unreachable), a, 1) for a in range(total_attempts)]
    for idx, first, count in rounds:
        idx = idx[~done[idx]]
        if len(idx) == 0:
            continue
        if time_limit is not None and first > 0 and time.perf_counter() - t0 > time_limit:
            break
        sub = _subproblem(prob, idx)
        if kernels is not None:
            out = _run_jit(kernels, sub, q[idx], max_iterations, count, first, seeds[idx], trace)
        else:
            out = _run_numpy(sub, q[idx], max_iterations, count, first, rng or np.random.default_rng(0 if seed is None else seed),
                             newton, trace)
        q_i, it_i, used_i, conv_i, _, rows_i = out
        q[idx] = q_i
        iters[idx] += it_i
        used[idx] += used_i
        done[idx] = conv_i | (count == 1 and first == 0 and unreachable[idx[0]])
        if trace:
            for j, r in zip(idx, rows_i):
                rows[j].extend(r)
    reasons: dict[int, tuple[str, str]] = {}
    unit = prob.robot.unit
    for i in (np.flatnonzero(unreachable) if any_unreachable else ()):
        reasons[int(i)] = ("unreachable", unreachable_note(f"{_fmt(dist[i])} {unit}",
                                                           f"{_fmt(prob.const['reach at most'])} {unit}",
                                                           prob.const["reach from"]))
    res = assemble(prob, q, iters, method, reasons, _trace_array(rows))
    if diagnose and not res.success.all() and len(failed := np.flatnonzero(~res.success & ~unreachable)):
        _diagnose(prob, res, failed, reasons, used, method, max_iterations, restarts, seed)
        res = assemble(prob, q, iters, method, reasons, res.trace)
    return res


def _finish(prob: Problem, q: Array, iters: NDArray[np.int64], used: NDArray[np.int64], method: str,
            max_iterations: int, restarts: int, seed: Any, trace: Optional[Array], diagnose: bool) -> IKResult:
    """The result of a solve without provably unreachable targets: checked, and failures diagnosed."""
    res = assemble(prob, q, iters, method, {}, trace)
    if diagnose and not res.success.all():
        failed = np.flatnonzero(~res.success)
        reasons: dict[int, tuple[str, str]] = {}
        _diagnose(prob, res, failed, reasons, used, method, max_iterations, restarts, seed)
        res = assemble(prob, q, iters, method, reasons, res.trace)
    return res


_EYE_1 = np.eye(4)[None]
_LM_BRANCH = np.full(1, "lm", dtype=object)
_CONVERGED = np.array(["converged"])      # the dtype of assemble's reason field: "<U9"
for _a in (_EYE_1, _LM_BRANCH, _CONVERGED):
    _a.setflags(write=False)


def _solve_one(robot: Robot, target: Any, q0: Any, max_iterations: Optional[int], restarts: Optional[int],
               seed: Any, enforce_limits: bool) -> Optional[IKResult]:
    """:func:`solve_lm` of one target with the default mask and tolerance, without the batch machinery.

    Same kernel, same seeds, the same FK check (:func:`~armkit.ik.verify`) and the same
    result as the general path, ~25 µs less Python around the kernel. ``None`` for
    anything else (the general path then handles it and raises the errors): a target
    other than a float64 (1, 4, 4) pose or (1, 3) position, ``q0`` other than float64
    (1, n), non-finite values, a provably unreachable target, no Numba.
    """
    if type(target) is not np.ndarray or type(q0) is not np.ndarray or not isinstance(robot, Robot):
        return None
    point = target.shape == (1, 3)
    if not (point or target.shape == (1, 4, 4)) or q0.shape != (1, robot.n) \
            or target.dtype != np.float64 or q0.dtype != np.float64:
        return None
    max_iterations = DEFAULT_MAX_ITERATIONS if max_iterations is None else max_iterations
    restarts = DEFAULT_RESTARTS if restarts is None else restarts
    if type(max_iterations) is not int or type(restarts) is not int or max_iterations < 0 or restarts < 0:
        return None
    kernels = _jit()
    if kernels is None:
        return None
    tol = default_tolerance(robot)
    c = _constants(robot)
    x, y, z = (target[0] if point else target[0, :3, 3]).tolist()
    sh = c["shoulder"]
    if sh is None:
        ox, oy, oz = c["origin xyz"]
        beyond = math.sqrt((x - ox) ** 2 + (y - oy) ** 2 + (z - oz) ** 2) > c["reach"] * (1.0 + 1e-9) + tol[0]
    else:   # the distance from the shoulder's circle (cx, cy, cz, ux, uy, uz, radius, reach)
        cx, cy, cz, ux, uy, uz, rs, reach = sh[3]
        wx, wy, wz = x - cx, y - cy, z - cz
        h = wx * ux + wy * uy + wz * uz
        rh = math.sqrt(max(wx * wx + wy * wy + wz * wz - h * h, 0.0))
        beyond = math.hypot(rh - rs, h) > reach * (1.0 + 1e-9) + tol[0]
    if beyond:
        return None  # provably unreachable: the general path explains it
    if point:
        poses = _EYE_1.copy()
        poses[0, :3, 3] = target[0]
    else:
        poses = np.ascontiguousarray(target)
    q = np.array(q0, order="C")
    params = _kernel_args(c, robot.unit_scale, tol, _W_POSITION if point else _W_POSE, max_iterations,
                          restarts + 1, 0)
    info = np.zeros((1, 4))
    limits = c["packed limits" if enforce_limits else "packed free"]
    FP = robot.cache.get("packed_chain") or _kinematics.packed(robot)
    if not kernels.lm_single(FP[1], limits, params, poses, _seed_base(seed), q, info):
        return None  # NaN or infinity in the target or q0: the general path says which
    dp, dr, ok, within = verify(robot, q, target, point, tol, enforce_limits)
    iters = int(info[0, 0])
    if not ok[0]:  # a failure: say why, as the general path does
        prob = Problem(robot, target, q0, None, None, enforce_limits)
        return _finish(prob, q, np.array([iters], dtype=np.int64), info[:, 2].astype(np.int64), "lm",
                       max_iterations, restarts, seed, None, True)
    message = Fielded.of("converged in {n} iterations: {residual}.", n=iters,
                         residual=residual_note(float(dp[0]), None if point else float(dr[0]), robot.unit))
    return IKResult._of(q=q, success=ok, position_error=dp, rotation_error=dr, iterations=np.array([iters], np.int64),
                        branch=_LM_BRANCH.copy(), within_limits=within, reason=_CONVERGED.copy(),
                        message=np.array([message], dtype=object))



def _diagnose(prob: Problem, res: IKResult, failed: NDArray[np.intp], reasons: dict, used: NDArray[np.int64],
              method: str, max_iterations: int, restarts: int, seed: Any) -> None:
    """Why did these targets fail? Joint limits (a solution exists without them), singular, or budget."""
    sub = _subproblem(prob, failed)
    if prob.enforce_limits:
        free = object.__new__(Problem)
        free.__dict__.update(sub.__dict__)
        free.enforce_limits = False
        free.lower, free.upper, free.rand_lo, free.rand_hi = prob.const["free"]
        alt = _solve(free, method, max_iterations, min(restarts, 5), seed, False, None, diagnose=False)
    sigma = _smallest_sigma(prob, res.q[failed], failed)
    too_many = int(np.count_nonzero(prob.w > 0)) > prob.robot.n and bool(np.any(prob.w[3:] > 0))
    if too_many:   # more to meet than joints (a pose for a 5-DOF arm): say so, with the nearest pose's miss
        from .partial import too_few_joints

        short = too_few_joints(prob, res, failed, seed)
    for j, i in enumerate(failed):
        i = int(i)
        if prob.enforce_limits and alt.success[j]:
            broken = ", ".join(prob.robot.limit_violations(alt.q[j])) or "limits"
            reasons[i] = ("joint limits", Fielded.of("found solutions only outside the joint limits ({broken}); q is "
                                                     "the best configuration found inside them", broken=broken))
        elif too_many:
            reasons[i] = ("unreachable", short[j])
        elif sigma[j] < _SINGULAR_SIGMA:
            reasons[i] = ("singular", Fielded.of("stalled at a singular configuration (smallest singular value "
                                                 "{sigma}) after {n} iterations and {starts} starts",
                                                 sigma=f"{sigma[j]:.1e}", n=int(res.iterations[i]), starts=int(used[i])))
        else:
            reasons[i] = ("max iterations", Fielded.of("no solution within {n} iterations ({starts} starts of at most "
                                                       "{steps} steps)", n=int(res.iterations[i]), starts=int(used[i]),
                                                       steps=max_iterations))
    settle(prob, reasons)   # where a closed form settles it: out of reach, only outside the limits, or missed


def solve_lm(robot: Robot, target: ArrayLike, q0: ArrayLike, *, mask: Optional[ArrayLike] = None,
             tol: Optional[tuple[float, float]] = None, max_iterations: Optional[int] = DEFAULT_MAX_ITERATIONS,
             restarts: Optional[int] = DEFAULT_RESTARTS, seed: Any = None, enforce_limits: bool = True, trace: bool = False,
             time_limit: Optional[float] = None) -> IKResult:
    r"""Levenberg-Marquardt (damped least squares) IK for a batch of targets.

    Parameters
    ----------
    robot : Robot
    target : array_like, shape (B, 4, 4) or (B, 3)
        Target poses ``T_world_tool`` or positions (position-only IK), length units of the robot.
    q0 : array_like, shape (B, n)
        Initial guesses (warm start); the first attempt starts here.
    mask : array_like, shape (6,), optional
        Weights over ``(x, y, z, rx, ry, rz)``; position axes are world axes, rotation axes
        are axes of the target frame. Default: all ones for a pose, ``(1, 1, 1, 0, 0, 0)``
        for a position. ``(1, 1, 1, 1, 1, 0)`` leaves the rotation about the tool's z axis free.
    tol : (float, float), optional
        Position (length units) and rotation (rad) tolerance; default
        :func:`~armkit.ik.default_tolerance` (1e-9 m or 1e-6 mm, 1e-9 rad).
    max_iterations : int, default :data:`~armkit.ik.DEFAULT_MAX_ITERATIONS` (100)
        Steps per attempt.
    restarts : int, default :data:`~armkit.ik.DEFAULT_RESTARTS` (50)
        Further attempts from random configurations inside the limits.
    seed : int or numpy Generator, optional
        Seeds the restarts: the same seed gives the same answers. The default (None) is
        seed 0, so a call without a seed is reproducible too.
    enforce_limits : bool, default True
        Keep joints inside their limits (projection after each step) and require it for success.
    trace : bool, default False
        Record the error norm (metres and rad combined) after every step: ``trace`` (B, iterations).
    time_limit : float, optional
        Seconds after which no further restart begins (checked between attempts).

    Returns
    -------
    IKResult
        Batched over B. ``reason`` is "converged", "unreachable" (the position lies beyond
        ``robot.reach`` from the base: q is the closest configuration found), "joint limits"
        (the solutions found lie outside the limits), "singular" (stalled where the Jacobian
        lost rank) or "max iterations" (budget spent; the residual is in ``message``). LM is
        local: where the arm has a closed form with every branch for the target, it settles a
        failure (:mod:`armkit.ik.verdict`): "unreachable" or "joint limits" when it finds no
        in-limit solution, else the message says how many in-limit solutions LM missed (a target
        whose only one has a joint within a degree of its limit can be missed).

    Examples
    --------
    >>> import armkit, numpy as np
    >>> from armkit.ik.numeric import solve_lm
    >>> arm = armkit.load("puma560")
    >>> T = armkit.fk(arm, [[0.3, 0.5, -1.0, 0.2, 0.6, -0.4]])
    >>> res = solve_lm(arm, T, np.zeros((1, 6)), seed=1)
    >>> bool(res.success[0]), str(res.reason[0])
    (True, 'converged')
    >>> bool(np.allclose(armkit.fk(arm, res.q), T, atol=1e-9))
    True
    """
    if mask is None and tol is None and not trace and time_limit is None:
        one = _solve_one(robot, target, q0, max_iterations, restarts, seed, enforce_limits)
        if one is not None:
            return one
    prob = Problem(robot, target, q0, mask, tol, enforce_limits, "solve_lm")
    return _solve(prob, "lm", max_iterations, restarts, seed, trace, time_limit)


def solve_newton(robot: Robot, target: ArrayLike, q0: ArrayLike, *, mask: Optional[ArrayLike] = None,
                 tol: Optional[tuple[float, float]] = None, max_iterations: Optional[int] = DEFAULT_MAX_ITERATIONS,
                 restarts: Optional[int] = DEFAULT_NEWTON_RESTARTS, seed: Any = None, enforce_limits: bool = True,
                 trace: bool = False, time_limit: Optional[float] = None) -> IKResult:
    r"""Newton-Raphson IK with the pseudo-inverse: :math:`\Delta q = J^+ e`, full steps, no damping.

    The textbook method, for teaching and for comparison with :func:`solve_lm` (same
    parameters and result). Converges quadratically near a regular solution; near a
    singularity the pseudo-inverse produces huge steps, which the joint-limit projection
    and random restarts have to absorb. Runs on NumPy (batched), never on the JIT kernel.

    Examples
    --------
    >>> import armkit, numpy as np
    >>> from armkit.ik.numeric import solve_newton
    >>> arm = armkit.load("planar2")
    >>> res = solve_newton(arm, [[1.2, 0.3, 0.0]], [[0.1, 0.5]], seed=0)
    >>> bool(res.success[0])
    True
    """
    prob = Problem(robot, target, q0, mask, tol, enforce_limits, "solve_newton")
    return _solve(prob, "newton", max_iterations, restarts, seed, trace, time_limit)
