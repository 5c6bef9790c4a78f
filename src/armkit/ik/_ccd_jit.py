"""Numba kernel of the CCD loop: one target per call, scalar loops, every sweep in compiled code.

The whole solve (the frames of the joints, the sweeps from the last joint to the first, the
limit projection, the stall test, the random restarts and the trace) runs here, so a sweep
costs well under a microsecond per joint instead of the ~0.3-0.6 ms that NumPy's per-call
overhead imposes on a sweep of a batch. :func:`ccd_batch` runs many targets, one per
iteration of a ``prange`` (threads for big batches). Imported lazily by
:mod:`armkit.ik.ccd` (never at ``import armkit``).

The algorithm and the restart draws are those of the NumPy back end in :mod:`armkit.ik.ccd`
(read it for the mathematics); the splitmix64 step of the draws is the very function
written there, compiled here.
"""

from __future__ import annotations

import math

import numpy as np

from .. import _jit_loader

_jit_loader.install_cache_fallback()  # before the first cache=True: read-only installs cache elsewhere

from numba import njit, prange  # noqa: E402
from .._jit_twins import parallel_twin  # noqa: E402

# the 12-scalar pose helpers of the kinematics kernels and their packed chain layout (see ik/_jit_lm.py)
from ..kinematics._jit import _load, _move, _mul  # noqa: E402
from ._jit_lm import _prismatic, _project, _project1  # noqa: E402  (one rule for the limits, LM's)
from .ccd import _ON_AXIS, _splitmix64, _start_state  # noqa: E402

# The packed arguments of the kernels (built by armkit.ik.ccd):
#   P       (2n + 2, ROW)  the chain (armkit.kinematics.packed(robot)[1])
#   limits  (4, n)         lower, upper, random-start low, random-start high
#   params  (N_PARAMS,)    the solver options, at these indices:
TOL_P = 0            # position tolerance of the iteration (length units)
MAX_SWEEPS = 1       # sweeps per attempt
RESTARTS = 2         # further attempts from random configurations
STALL = 3            # sweeps without a 0.1 % improvement that end an attempt
N_PARAMS = 4
# info (B, 3): sweeps in all, attempts used, the best position error
ITERATIONS, USED, BEST = 0, 1, 2

_next = njit(inline="always")(_splitmix64)
_state = njit(inline="always")(_start_state)


@njit(cache=True)
def _frames(P, q, Z):
    """Joint ``k``'s axis ``Z[k, :3]`` and origin ``Z[k, 3:]`` (its frame is the link frame times ``pre[k]``);
    returns the tool point."""
    n = q.shape[0]
    X = _load(P, 0)
    for k in range(n):
        X = _mul(X, P, 1 + k)
        Z[k, 0], Z[k, 1], Z[k, 2] = X[2], X[6], X[10]
        Z[k, 3], Z[k, 4], Z[k, 5] = X[3], X[7], X[11]
        t = q[k]
        X = _mul(_move(X, t, math.sin(t), math.cos(t), _prismatic(P, k)), P, 1 + n + k)
    X = _mul(X, P, 2 * n + 1)
    return X[3], X[7], X[11]


@njit(cache=True)
def _sweep(P, limits, q, t, Z):
    """One sweep (last joint to first) of ``q`` (n,) in place towards the point ``t`` (3,); the tool point's distance
    from ``t`` afterwards."""
    ex, ey, ez = _frames(P, q, Z)
    tx, ty, tz = t[0], t[1], t[2]
    for j in range(q.shape[0] - 1, -1, -1):
        zx, zy, zz, px, py, pz = Z[j, 0], Z[j, 1], Z[j, 2], Z[j, 3], Z[j, 4], Z[j, 5]
        prismatic = _prismatic(P, j)
        if prismatic:
            step = zx * (tx - ex) + zy * (ty - ey) + zz * (tz - ez)
        else:
            ux, uy, uz = ex - px, ey - py, ez - pz
            vx, vy, vz = tx - px, ty - py, tz - pz
            u0 = ux * ux + uy * uy + uz * uz
            v0 = vx * vx + vy * vy + vz * vz
            a = ux * zx + uy * zy + uz * zz
            ux, uy, uz = ux - a * zx, uy - a * zy, uz - a * zz
            b = vx * zx + vy * zy + vz * zz
            vx, vy, vz = vx - b * zx, vy - b * zy, vz - b * zz
            if ux * ux + uy * uy + uz * uz <= _ON_AXIS * u0 or vx * vx + vy * vy + vz * vz <= _ON_AXIS * v0:
                step = 0.0   # the tool point or the target on the axis: turning cannot help
            else:
                cx, cy, cz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
                step = math.atan2(zx * cx + zy * cy + zz * cz, ux * vx + uy * vy + uz * vz)
        new = _project1(q[j] + step, limits, j, prismatic)
        moved = new - q[j]
        q[j] = new
        if prismatic:
            ex, ey, ez = ex + moved * zx, ey + moved * zy, ez + moved * zz
        else:   # Rodrigues: the tool point turns about the joint's axis
            c, s = math.cos(moved), math.sin(moved)
            wx, wy, wz = ex - px, ey - py, ez - pz
            d = (zx * wx + zy * wy + zz * wz) * (1.0 - c)
            ex = px + (wx * c + (zy * wz - zz * wy) * s + zx * d)
            ey = py + (wy * c + (zz * wx - zx * wz) * s + zy * d)
            ez = pz + (wz * c + (zx * wy - zy * wx) * s + zz * d)
    return math.sqrt((ex - tx) ** 2 + (ey - ty) ** 2 + (ez - tz) ** 2)


@njit(cache=True)
def _distance(P, q, t, Z):
    """The tool point's distance from ``t`` at ``q``."""
    ex, ey, ez = _frames(P, q, Z)
    return math.sqrt((ex - t[0]) ** 2 + (ey - t[1]) ** 2 + (ez - t[2]) ** 2)


@njit(cache=True)
def _ccd_one(P, limits, params, t, seed, unreachable, q, trace, info):
    """Solve the position ``t`` (3,) from ``q`` (n,), in place: the configuration that converged, else the best one.

    ``seed`` (uint64): the target's restart seed; ``unreachable``: no restarts; ``trace[k]`` = the error after
    sweep ``k`` (length 0: none); ``info`` (3,): see the top of this module.
    """
    n = q.shape[0]
    tol_p = params[TOL_P]
    max_sweeps, restarts, stall = int(params[MAX_SWEEPS]), int(params[RESTARTS]), int(params[STALL])
    Z = np.empty((n, 6))
    _project(q, limits, P)
    best_q = q.copy()
    err = _distance(P, q, t, Z)
    best_err = np.inf
    iters = 0
    used = 1
    while True:
        sweeps = 0
        stale = 0
        attempt_best = np.inf
        converged = False
        while True:
            if err < best_err:
                best_err = err
                for j in range(n):
                    best_q[j] = q[j]
            if not err > tol_p:
                converged = True
                break
            if err < attempt_best * (1.0 - 1e-3):
                attempt_best = err
                stale = 0
            else:
                stale += 1
            if sweeps >= max_sweeps or stale >= stall:
                break
            err = _sweep(P, limits, q, t, Z)
            iters += 1
            sweeps += 1
            if iters <= trace.shape[0]:
                trace[iters - 1] = err
        if converged or unreachable or used > restarts:
            break
        state = _state(seed, np.uint64(used))
        for j in range(n):
            state, u = _next(state)
            q[j] = limits[2, j] + (limits[3, j] - limits[2, j]) * u
        _project(q, limits, P)
        used += 1
        err = _distance(P, q, t, Z)
    if not err <= tol_p:
        for j in range(n):
            q[j] = best_q[j]
    info[ITERATIONS] = iters
    info[USED] = used
    info[BEST] = best_err


def ccd_batch(P, limits, params, targets, seeds, unreachable, q, trace, info):
    """Solve every position ``targets[i]`` (B, 3) from ``q[i]``; q, trace, info written in place.

    ``seeds`` (B,) uint64; ``unreachable`` (B,) bool; ``trace`` (B, k) (k = 0: none); ``info`` (B, 3). Threads
    for 8 targets or more (one thread, the same results, while the multi-threaded kernel is not cached yet).
    """
    run = _ccd_parallel if targets.shape[0] >= 8 and _jit_loader.parallel_ok() else ccd_serial
    run(P, limits, params, targets, seeds, unreachable, q, trace, info)


@njit(cache=True)
def ccd_serial(P, limits, params, targets, seeds, unreachable, q, trace, info):
    """As :func:`ccd_batch` without threads (small batches, single targets)."""
    for i in prange(targets.shape[0]):
        _ccd_one(P, limits, params, targets[i], seeds[i], unreachable[i], q[i], trace[i], info[i])


_ccd_parallel = parallel_twin(ccd_serial)


def parallel_twins():
    """``(one-thread kernel, multi-threaded kernel)`` pairs taking the same arguments (for the warm-up)."""
    return [(ccd_serial, _ccd_parallel)]


# the cached kernels inline the pose helpers of kinematics/_jit.py, the limit rule of ik/_jit_lm.py (_project1) and
# the splitmix64 step of ik/ccd.py
_jit_loader.forget_stale_cache(globals(), ("kinematics/_jit.py", "ik/_jit_lm.py", "ik/ccd.py"))
