"""Numba kernel for :func:`armkit.ik.result.verify`: pose errors and limit checks in one pass.

The NumPy version costs ~20 µs for one target (a dozen small array operations); this one
costs well under a microsecond per candidate, which matters because every IK answer is
checked. :func:`check_pose` and :func:`check_point` do one candidate and return scalars
(the single-call path of ``verify``); :func:`errors` does a batch. Imported lazily, only
when the Numba back end is in use.
"""

from __future__ import annotations

import math

import numpy as np

from .. import _jit_loader

_jit_loader.install_cache_fallback()  # before the first cache=True: read-only installs cache elsewhere

from numba import njit, prange  # noqa: E402
from .._jit_twins import parallel_twin  # noqa: E402


@njit(cache=True, inline="always")
def _within(q, lower, upper, tol):
    ok = True
    for k in range(q.shape[0]):
        if q[k] < lower[k] - tol or q[k] > upper[k] + tol:
            ok = False
    return ok


@njit(cache=True, inline="always")
def _angle_of(s, cth):
    """The angle of a rotation whose sine is ``s`` and cosine ``cth`` (:func:`_check`'s halves of ``|vee(E - Eᵀ)|``
    and of ``trace E - 1``).

    A verified candidate's angle is tiny: atan2(s, c) is then s / c to the bit (atan(x) = x (1 - x² / 3 ...),
    x² / 3 < 1e-24 below 1e-12; equal on 10 million pairs), a division instead of an atan2 call (~20 ns; the
    Puma's ik_all checks 8 branches a target)."""
    return s / cth if cth > 0.0 and s <= 1e-12 * cth else math.atan2(s, cth)


@njit(cache=True, inline="always")
def _check(T, tgt, pose, q, lower, upper, tol):
    """(position error, rotation angle, within limits) of one candidate: T, tgt (4, 4), q (n,)."""
    ex = T[0, 3] - tgt[0, 3]
    ey = T[1, 3] - tgt[1, 3]
    ez = T[2, 3] - tgt[2, 3]
    dp = math.sqrt(ex * ex + ey * ey + ez * ez)
    dr = 0.0
    if pose:
        # E = Ra^T Rb; angle = atan2(|vee(E - E^T)| / 2, (trace E - 1) / 2)
        e00 = T[0, 0] * tgt[0, 0] + T[1, 0] * tgt[1, 0] + T[2, 0] * tgt[2, 0]
        e01 = T[0, 0] * tgt[0, 1] + T[1, 0] * tgt[1, 1] + T[2, 0] * tgt[2, 1]
        e02 = T[0, 0] * tgt[0, 2] + T[1, 0] * tgt[1, 2] + T[2, 0] * tgt[2, 2]
        e10 = T[0, 1] * tgt[0, 0] + T[1, 1] * tgt[1, 0] + T[2, 1] * tgt[2, 0]
        e11 = T[0, 1] * tgt[0, 1] + T[1, 1] * tgt[1, 1] + T[2, 1] * tgt[2, 1]
        e12 = T[0, 1] * tgt[0, 2] + T[1, 1] * tgt[1, 2] + T[2, 1] * tgt[2, 2]
        e20 = T[0, 2] * tgt[0, 0] + T[1, 2] * tgt[1, 0] + T[2, 2] * tgt[2, 0]
        e21 = T[0, 2] * tgt[0, 1] + T[1, 2] * tgt[1, 1] + T[2, 2] * tgt[2, 1]
        e22 = T[0, 2] * tgt[0, 2] + T[1, 2] * tgt[1, 2] + T[2, 2] * tgt[2, 2]
        s = 0.5 * math.sqrt((e21 - e12) ** 2 + (e02 - e20) ** 2 + (e10 - e01) ** 2)
        cth = 0.5 * (e00 + e11 + e22 - 1.0)
        dr = _angle_of(s, cth)
    return dp, dr, _within(q, lower, upper, tol)


@njit(cache=True, inline="always")  # outputs: one array per argument, never a tuple (Numba 0.68's parfors loses writes through tuples)
def _one(T, tgt, q, limits, opts, dp, dr, within, i):
    """Candidate ``i`` into ``dp[i], dr[i], within[i]``, against target ``tgt[i // per]``; ``opts = (pose, tol,
    per)``, ``limits`` (2, n)."""
    dp[i], dr[i], within[i] = _check(T[i], tgt[i // opts[2]], opts[0], q[i], limits[0], limits[1], opts[1])


@njit(cache=True)
def check_pose(T, tgt, pose, q, lower, upper, tol):
    """One candidate: ``T``, ``tgt`` (4, 4) (only column 3 of ``tgt`` read unless ``pose``), ``q`` (n,).

    Returns ``(position error, rotation angle, within limits)``.
    """
    return _check(T, tgt, pose, q, lower, upper, tol)


@njit(cache=True)
def check_point(T, p, q, lower, upper, tol):
    """As :func:`check_pose` for a target position ``p`` (3,); the rotation angle is 0."""
    ex = T[0, 3] - p[0]
    ey = T[1, 3] - p[1]
    ez = T[2, 3] - p[2]
    return math.sqrt(ex * ex + ey * ey + ez * ez), 0.0, _within(q, lower, upper, tol)


@njit(cache=True)
def _serial(T, tgt, q, limits, opts, dp, dr, within):
    for i in prange(T.shape[0]):
        _one(T, tgt, q, limits, opts, dp, dr, within, i)


_parallel = parallel_twin(_serial)


PARALLEL_MIN = 512
"""Candidates from this many on are checked on all threads. Measured on the project's 2-core machine (``ik_all``,
8 candidates a target, the closed-form passes already on two threads): 64 targets took 4.3 instead of 4.5 µs a
target on the UR5 and 4.6 instead of 5.0 on the Puma 560, 128 targets 3.0 instead of 3.1 and 3.4 instead of 3.8
(docs/performance.md)."""


def errors(T, tgt, pose, q, limits, tol=1e-12, per=1):
    """``T`` (B, 4, 4) actual, ``tgt`` (B // per, 4, 4) targets, candidate ``i`` checked against ``tgt[i // per]``
    (only column 3 read unless ``pose``), ``q`` (B, n), ``limits`` (2, n) lower and upper: position errors,
    rotation angles and within-limits flags ``(B,)``."""
    B = T.shape[0]
    outs = (np.empty(B), np.empty(B), np.empty(B, dtype=np.bool_))
    kernel = _parallel if B >= PARALLEL_MIN and _jit_loader.parallel_ok() else _serial
    kernel(T, tgt, q, limits, (pose, tol, int(per)), *outs)
    return outs


def parallel_twins():
    """``(one-thread kernel, multi-threaded kernel)`` pairs taking the same arguments (for the warm-up)."""
    return [(_serial, _parallel)]
