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
"""

from __future__ import annotations

from typing import Any, Optional

import numpy as np
from numpy.typing import ArrayLike

from .._text import Fielded
from ..errors import IKInputError
from ..model.robot import Robot
from .numeric import _TOL_FACTOR, Problem, _project, _trace_array, assemble, unreachable_note
from .result import DEFAULT_MAX_SWEEPS, DEFAULT_SWEEP_RESTARTS, IKResult

__all__ = ["solve_ccd"]

_STALL_SWEEPS = 30


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
        Seeds the restarts.
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
    rng = np.random.default_rng(0 if seed is None else seed)   # seeded by default: reproducible
    n, B = robot.n, prob.B
    goal = prob.target
    tol_p = prob.tol[0] * _TOL_FACTOR
    unreachable, dist = prob.unreachable()
    q = _project(prob, prob.q0.copy())
    best_q, best_err = q.copy(), np.full(B, np.inf)
    iters = np.zeros(B, np.int64)
    sweeps = np.zeros(B, np.int64)
    used = np.ones(B, np.int64)
    stale = np.zeros(B, np.int64)
    attempt_best = np.full(B, np.inf)
    active = np.ones(B, bool)
    rows: list = [[] for _ in range(B)] if trace else []
    from ..kinematics import fk

    err = np.linalg.norm(fk(robot, q)[:, :3, 3] - goal, axis=-1)
    while True:
        better = err < best_err
        best_err = np.where(better, err, best_err)
        best_q[better] = q[better]
        active &= err > tol_p
        impr = err < attempt_best * (1.0 - 1e-3)
        attempt_best = np.where(impr, err, attempt_best)
        stale = np.where(impr, 0, stale + 1)
        over = active & ((sweeps >= max_iterations) | (stale >= _STALL_SWEEPS))
        if np.any(over):
            more = over & (used <= restarts) & ~unreachable
            active &= ~(over & ~more)
            k = np.flatnonzero(more)
            if len(k):
                q[k] = _project(prob, rng.uniform(prob.rand_lo[None], prob.rand_hi[None], size=(len(k), n)))
                used[k] += 1
                sweeps[k] = 0
                stale[k] = 0
                attempt_best[k] = np.inf
                err[k] = np.linalg.norm(fk(robot, q[k])[:, :3, 3] - goal[k], axis=-1)
                continue
        k = np.flatnonzero(active)
        if len(k) == 0:
            break
        err[k] = np.linalg.norm(_sweep(prob, q, k) - goal[k], axis=-1)
        iters[k] += 1
        sweeps[k] += 1
        if trace:
            for i, v in zip(k, err[k]):
                rows[i].append(v)
    q = np.where((err <= tol_p)[:, None], q, best_q)
    reasons = _reasons(prob, unreachable, dist, ~unreachable & (best_err > tol_p), iters, used)
    tr = _trace_array(rows) if trace else None
    return assemble(prob, q, iters, "ccd", reasons, tr, note)


def _sweep(prob: Problem, q: np.ndarray, k: np.ndarray) -> np.ndarray:
    """One CCD sweep (last joint to first) of the configurations ``q[k]``, in place; their tool points ``(len(k), 3)``."""
    robot = prob.robot
    c, n = robot.chain, robot.n
    from ..kinematics import fk_frames

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
            u = u - np.einsum("bi,bi->b", u, z)[:, None] * z
            v = v - np.einsum("bi,bi->b", v, z)[:, None] * z
            step = np.arctan2(np.einsum("bi,bi->b", z, np.cross(u, v)), np.einsum("bi,bi->b", u, v))
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
    return reasons

