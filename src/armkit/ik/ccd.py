r"""Cyclic coordinate descent (CCD) for position targets, batched over targets.

One iteration (a *sweep*) visits the joints from the last to the first. A revolute joint
turns by the angle that brings the tool point closest to the target when both are seen
from the joint axis,

.. math:: \Delta q_i = \operatorname{atan2}\big(z_i \cdot (u \times v),\ u \cdot v\big),

where :math:`u, v` are the projections of :math:`p_{tool} - p_i` and
:math:`p_{target} - p_i` on the plane perpendicular to the axis :math:`z_i`; a prismatic
joint slides by :math:`z_i \cdot (p_{target} - p_{tool})`. Each update is projected into
the joint limits. Joints before joint ``i`` do not move during its update, so one FK of
all frames per sweep suffices: the tool point is turned with each joint.

Unlike the CCD graphics assignment's version this works in radians, stops when the position error is below
the tolerance (not after a fixed number of sweeps), respects joint limits, restarts from
random configurations when it stalls, and records the error after every sweep.

Two back ends give the same answers: the compiled kernel of :mod:`armkit.ik._ccd_jit` (the
whole loop per target, one target per iteration of a ``prange``) while Numba serves, else the
NumPy loop here, batched over targets. Target ``i``'s restart draws come from the splitmix64
generator (:func:`_splitmix64`, the one function both back ends run) started at a state made
of the seed, ``i`` and the attempt only, so a target's answer does not depend on the other
targets of its batch, and a batch needs no more memory than its targets.
"""

from __future__ import annotations

from typing import Any, Optional

import numpy as np
from numpy.typing import ArrayLike

from .. import _jit_loader
from .._text import Fielded
from ..errors import IKInputError
from ..kinematics import fk, fk_frames, packed
from ..model.robot import Robot
from .numeric import _TOL_FACTOR, Problem, _project, _seeds, _trace_array, assemble, unreachable_note
from .result import DEFAULT_MAX_SWEEPS, DEFAULT_SWEEP_RESTARTS, IKResult
from .verdict import settle

__all__ = ["solve_ccd"]

_STALL_SWEEPS = 30
_ON_AXIS = 1e-20   # a point this close to a joint's axis, relative to its distance (squared), lies on it


def _position_problem(robot: Robot, target: ArrayLike, q0: ArrayLike, mask: Optional[ArrayLike],
                      tol: Optional[tuple[float, float]], enforce_limits: bool, what: str) -> tuple[Problem, str]:
    """A position-only :class:`Problem`; a pose target contributes its position (and a note saying so)."""
    t = np.asarray(target, dtype=float)
    note = ""
    if t.ndim == 3 and t.shape[1:] == (4, 4):
        t = t[:, :3, 3]
        note = Fielded.of("({what} matches the position only; the target's orientation was not used.)", what=what)
    if mask is not None:
        m = np.asarray(mask, dtype=float)
        if m.shape != (6,) or np.any(m[3:] != 0) or not np.all(m[:3] > 0):
            raise IKInputError.of("{what} solves position targets only: mask must be None or weight x, y and z with "
                                  "zero rotation weights, got {mask!r}; use method 'lm' for orientation masks",
                                  what=what, mask=mask)
    return Problem(robot, t, q0, None, tol, enforce_limits, what), note


def _rotate(v: np.ndarray, axis: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Rodrigues: rotate vectors v (k, 3) about unit axes (k, 3) by angle (k,)."""
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    return v * c + np.cross(axis, v) * s + axis * np.einsum("bi,bi->b", axis, v)[:, None] * (1.0 - c)


def solve_ccd(robot: Robot, target: ArrayLike, q0: ArrayLike, *, mask: Optional[ArrayLike] = None,
              tol: Optional[tuple[float, float]] = None, max_iterations: Optional[int] = DEFAULT_MAX_SWEEPS,
              restarts: Optional[int] = DEFAULT_SWEEP_RESTARTS, seed: Any = None, enforce_limits: bool = True,
              trace: bool = False, time_limit: Optional[float] = None) -> IKResult:
    """CCD inverse kinematics for position targets.

    Parameters
    ----------
    robot : Robot
        Any serial chain (revolute and prismatic joints).
    target : array_like, shape (B, 3) or (B, 4, 4)
        Target positions (length units); of a pose only the position is used (``message`` says so).
    q0 : array_like, shape (B, n)
        Start configurations.
    mask : None
        Only position targets: None or weights on x, y, z with zero rotation weights.
    tol : (float, float), optional
        Position tolerance (length units) first; default :func:`~armkit.ik.default_tolerance`.
    max_iterations : int, default :data:`~armkit.ik.DEFAULT_MAX_SWEEPS` (2000)
        Sweeps per attempt. CCD converges linearly and slowly near the workspace boundary
        (a nearly stretched arm can need hundreds of sweeps), so it needs far more sweeps than LM needs steps.
    restarts : int, default :data:`~armkit.ik.DEFAULT_SWEEP_RESTARTS` (20)
        Further attempts from random configurations when an attempt stalls.
    seed : int, optional
        Seeds the restarts (default 0: the same call gives the same answer); target ``i``'s restarts depend on
        the seed, ``i`` and the attempt only.
    enforce_limits : bool, default True
    trace : bool, default False
        Position error after every sweep: ``trace`` of shape (B, sweeps).
    time_limit : float, optional
        Unused by CCD's sweeps budget; accepted for a uniform interface.

    Returns
    -------
    IKResult

    Examples
    --------
    >>> import armkit, numpy as np
    >>> from armkit.ik.ccd import solve_ccd
    >>> arm = armkit.load("planar3")
    >>> res = solve_ccd(arm, [[1.0, 0.5, 0.0]], np.zeros((1, 3)), trace=True, seed=0)
    >>> bool(res.success[0]), res.trace.shape[0]
    (True, 1)
    """
    prob, note = _position_problem(robot, target, q0, mask, tol, enforce_limits, "CCD")
    max_iterations = DEFAULT_MAX_SWEEPS if max_iterations is None else int(max_iterations)
    restarts = DEFAULT_SWEEP_RESTARTS if restarts is None else int(restarts)
    seeds = _seeds(seed, prob.B)   # seeded by default: reproducible; target i's draws depend on (seed, i) only
    tol_p = prob.tol[0] * _TOL_FACTOR
    unreachable, dist = prob.unreachable()
    kernels = _jit_loader.kernels("ik._ccd_jit")
    run = _run_numpy if kernels is None else _run_jit
    q, iters, used, best_err, rows = run(prob, tol_p, max_iterations, restarts, seeds, unreachable, trace)
    reasons = _reasons(prob, unreachable, dist, ~unreachable & (best_err > tol_p), iters, used)
    tr = _trace_array(rows) if trace else None
    return assemble(prob, q, iters, "ccd", reasons, tr, note)


def _splitmix64(state: Any) -> tuple[Any, Any]:
    """One step of the splitmix64 generator: ``(next state, uniform float in [0, 1))``.

    ``state`` is uint64: an array here (NumPy wraps array products modulo 2**64 silently), a
    scalar in the compiled kernel (:mod:`armkit.ik._ccd_jit` compiles this very function), so
    both back ends draw the same bits.
    """
    state = state + np.uint64(0x9E3779B97F4A7C15)
    z = (state ^ (state >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    z = z ^ (z >> np.uint64(31))
    return state, (z >> np.uint64(11)) * (1.0 / 9007199254740992.0)


def _start_state(seed: Any, attempt: Any) -> Any:
    """The generator state of restart ``attempt`` (1, 2, ...) of the target with restart seed ``seed`` (both uint64):
    each target's draws depend on (seed, target index, attempt) only, never on the rest of its batch."""
    return seed * np.uint64(1000003) + attempt


def _run_jit(prob: Problem, tol_p: float, max_iterations: int, restarts: int, seeds: np.ndarray,
             unreachable: np.ndarray, trace: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, list]:
    """The compiled back end: ``(q, sweeps, attempts used, best error, trace rows)``."""
    K = _jit_loader.module("ik._ccd_jit")

    B = prob.B
    params = np.empty(K.N_PARAMS)
    params[K.TOL_P], params[K.MAX_SWEEPS], params[K.RESTARTS], params[K.STALL] = \
        tol_p, max_iterations, restarts, _STALL_SWEEPS
    # fresh writable C arrays (a read-only target would be another signature: one more compile)
    args = (packed(prob.robot)[1], np.array(prob.packed_limits, dtype=float, order="C"), params,
            np.array(prob.target, dtype=float, order="C"), seeds, np.array(unreachable, dtype=np.bool_, order="C"))
    # the trace: room for a few hundred sweeps a target (at most ~32 MB); a target that needed more is solved again
    # (the same sweeps, deterministically) with room for them all
    cap = max(max_iterations, 0) * (max(restarts, 0) + 1)      # the most sweeps a target can make
    width = min(cap, max(256, 2 ** 22 // max(B, 1))) if trace else 0
    while True:
        q = np.array(prob.q0, dtype=float, order="C")
        info = np.zeros((B, 3))
        tr = np.empty((B, width))
        K.ccd_batch(*args, q, tr, info)
        iters = info[:, K.ITERATIONS].astype(np.int64)
        if not trace or B == 0 or int(iters.max()) <= width:
            break
        width = int(iters.max())
    rows = [tr[i, :iters[i]].tolist() for i in range(B)] if trace else []
    return q, iters, info[:, K.USED].astype(np.int64), info[:, K.BEST], rows


def _run_numpy(prob: Problem, tol_p: float, max_iterations: int, restarts: int, seeds: np.ndarray,
               unreachable: np.ndarray, trace: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, list]:
    """The NumPy back end, batched over targets: ``(q, sweeps, attempts used, best error, trace rows)``.

    Each target goes through the same steps as in the compiled kernel: its attempt's bookkeeping (best error,
    convergence, stall) runs only after its own sweeps and restarts, so a target's answer does not depend on
    the other targets of its batch.
    """
    robot, goal = prob.robot, prob.target
    n, B = robot.n, prob.B
    q = _project(prob, prob.q0.copy())
    best_q, best_err = q.copy(), np.full(B, np.inf)
    iters = np.zeros(B, np.int64)
    sweeps = np.zeros(B, np.int64)
    used = np.ones(B, np.int64)
    stale = np.zeros(B, np.int64)
    attempt_best = np.full(B, np.inf)
    active = np.ones(B, bool)
    rows: list = [[] for _ in range(B)] if trace else []
    err = np.linalg.norm(fk(robot, q)[:, :3, 3] - goal, axis=-1)
    k = np.arange(B)
    while len(k):
        while len(k):   # the attempt's bookkeeping of the targets in k; restarts, and their bookkeeping in turn
            e = err[k]
            better = e < best_err[k]
            best_err[k[better]] = e[better]
            best_q[k[better]] = q[k[better]]
            active[k] &= e > tol_p
            impr = e < attempt_best[k] * (1.0 - 1e-3)
            attempt_best[k[impr]] = e[impr]
            stale[k] = np.where(impr, 0, stale[k] + 1)
            over = k[active[k] & ((sweeps[k] >= max_iterations) | (stale[k] >= _STALL_SWEEPS))]
            more = (used[over] <= restarts) & ~unreachable[over]
            active[over[~more]] = False
            k = over[more]
            if len(k):
                state = _start_state(seeds[k], used[k].astype(np.uint64))
                draw = np.empty((len(k), n))
                for j in range(n):
                    state, u = _splitmix64(state)
                    draw[:, j] = prob.rand_lo[j] + (prob.rand_hi[j] - prob.rand_lo[j]) * u
                q[k] = _project(prob, draw)
                used[k] += 1
                sweeps[k] = 0
                stale[k] = 0
                attempt_best[k] = np.inf
                err[k] = np.linalg.norm(fk(robot, q[k])[:, :3, 3] - goal[k], axis=-1)
        k = np.flatnonzero(active)
        if len(k) == 0:
            break
        err[k] = np.linalg.norm(_sweep(prob, q, k) - goal[k], axis=-1)
        iters[k] += 1
        sweeps[k] += 1
        if trace:
            for i, v in zip(k.tolist(), err[k].tolist()):
                rows[i].append(v)
    q = np.where((err <= tol_p)[:, None], q, best_q)
    return q, iters, used, best_err, rows


def _sweep(prob: Problem, q: np.ndarray, k: np.ndarray) -> np.ndarray:
    """One CCD sweep (last joint to first) of the configurations ``q[k]``, in place; their tool points ``(len(k), 3)``."""
    robot = prob.robot
    c, n = robot.chain, robot.n

    F = fk_frames(robot, q[k])
    e = F[:, n, :3, 3].copy()
    t = prob.target[k]
    for j in range(n - 1, -1, -1):
        Jf = F[:, j] @ c.pre[j]                     # joint j's frame: its axis is the local z
        z, p = Jf[:, :3, 2], Jf[:, :3, 3]
        if c.prismatic[j]:
            step = np.einsum("bi,bi->b", z, t - e)
        else:
            u, v = e - p, t - p
            u0, v0 = np.einsum("bi,bi->b", u, u), np.einsum("bi,bi->b", v, v)
            u = u - np.einsum("bi,bi->b", u, z)[:, None] * z
            v = v - np.einsum("bi,bi->b", v, z)[:, None] * z
            step = np.arctan2(np.einsum("bi,bi->b", z, np.cross(u, v)), np.einsum("bi,bi->b", u, v))
            # the tool point or the target on the axis (to round-off): no angle is better than another, so none
            on_axis = (np.einsum("bi,bi->b", u, u) <= _ON_AXIS * u0) | (np.einsum("bi,bi->b", v, v) <= _ON_AXIS * v0)
            step = np.where(on_axis, 0.0, step)
        new = q[k].copy()
        new[:, j] += step
        new = _project(prob, new)
        moved = new[:, j] - q[k, j]
        q[k, j] = new[:, j]
        if c.prismatic[j]:
            e = e + moved[:, None] * z
        else:
            e = p + _rotate(e - p, z, moved)
    return e


def _reasons(prob: Problem, unreachable: np.ndarray, dist: np.ndarray, failed: np.ndarray, iters: np.ndarray,
             used: np.ndarray) -> dict[int, tuple[str, str]]:
    """Reason and message of every failed target: out of the arm's reach, or no convergence."""
    unit = prob.robot.unit
    reasons: dict[int, tuple[str, str]] = {}
    for i in np.flatnonzero(unreachable):
        reasons[int(i)] = ("unreachable", unreachable_note(f"{dist[i]:.4g} {unit}", f"{prob.const['reach at most']:.4g} {unit}",
                                                           prob.const["reach from"]))
    for i in np.flatnonzero(failed):
        reasons[int(i)] = ("max iterations", Fielded.of("CCD did not converge in {n} sweeps ({starts} starts)",
                                                        n=int(iters[i]), starts=int(used[i])))
    settle(prob, reasons)   # where a closed form settles it (armkit.ik.verdict)
    return reasons

