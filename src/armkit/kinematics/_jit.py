"""Numba kernels over the uniform chain: the fast path for single calls and big batches.

Each pose is kept in twelve scalar locals (the 3x4 affine part), so a joint costs one
in-place rotation/translation of two columns plus one affine product with a constant.
Compiled functions are cached on disk (``cache=True``); importing this module is what
costs time, so :mod:`armkit.kinematics` imports it only on first use.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

_PARALLEL_MIN = 4096  # below this batch size threads cost more than they save (measured, benchmarks/bench_fk.py)


@njit(cache=True, inline="always")
def _load(F):
    return (F[0, 0], F[0, 1], F[0, 2], F[0, 3], F[1, 0], F[1, 1], F[1, 2], F[1, 3],
            F[2, 0], F[2, 1], F[2, 2], F[2, 3])


@njit(cache=True, inline="always")
def _mul(X, F):
    a00, a01, a02, a03, a10, a11, a12, a13, a20, a21, a22, a23 = X
    return (a00 * F[0, 0] + a01 * F[1, 0] + a02 * F[2, 0],
            a00 * F[0, 1] + a01 * F[1, 1] + a02 * F[2, 1],
            a00 * F[0, 2] + a01 * F[1, 2] + a02 * F[2, 2],
            a00 * F[0, 3] + a01 * F[1, 3] + a02 * F[2, 3] + a03,
            a10 * F[0, 0] + a11 * F[1, 0] + a12 * F[2, 0],
            a10 * F[0, 1] + a11 * F[1, 1] + a12 * F[2, 1],
            a10 * F[0, 2] + a11 * F[1, 2] + a12 * F[2, 2],
            a10 * F[0, 3] + a11 * F[1, 3] + a12 * F[2, 3] + a13,
            a20 * F[0, 0] + a21 * F[1, 0] + a22 * F[2, 0],
            a20 * F[0, 1] + a21 * F[1, 1] + a22 * F[2, 1],
            a20 * F[0, 2] + a21 * F[1, 2] + a22 * F[2, 2],
            a20 * F[0, 3] + a21 * F[1, 3] + a22 * F[2, 3] + a23)


@njit(cache=True, inline="always")
def _move(X, t, prismatic):
    a00, a01, a02, a03, a10, a11, a12, a13, a20, a21, a22, a23 = X
    if prismatic:
        return (a00, a01, a02, a03 + t * a02, a10, a11, a12, a13 + t * a12, a20, a21, a22, a23 + t * a22)
    c = math.cos(t)
    s = math.sin(t)
    return (c * a00 + s * a01, c * a01 - s * a00, a02, a03,
            c * a10 + s * a11, c * a11 - s * a10, a12, a13,
            c * a20 + s * a21, c * a21 - s * a20, a22, a23)


@njit(cache=True, inline="always")
def _store(X, out):
    out[0, 0], out[0, 1], out[0, 2], out[0, 3] = X[0], X[1], X[2], X[3]
    out[1, 0], out[1, 1], out[1, 2], out[1, 3] = X[4], X[5], X[6], X[7]
    out[2, 0], out[2, 1], out[2, 2], out[2, 3] = X[8], X[9], X[10], X[11]
    out[3, 0], out[3, 1], out[3, 2], out[3, 3] = 0.0, 0.0, 0.0, 1.0


@njit(cache=True)
def _fk_one(fixed, prismatic, q, out):
    X = _load(fixed[0])
    for k in range(q.shape[0]):
        X = _mul(_move(X, q[k], prismatic[k]), fixed[k + 1])
    _store(X, out)


@njit(cache=True)
def fk_single(fixed, prismatic, q):
    out = np.empty((4, 4))
    _fk_one(fixed, prismatic, q, out)
    return out


@njit(cache=True)
def _fk_serial(fixed, prismatic, q, out):
    for i in range(q.shape[0]):
        _fk_one(fixed, prismatic, q[i], out[i])


@njit(cache=True, parallel=True)
def _fk_parallel(fixed, prismatic, q, out):
    for i in prange(q.shape[0]):
        _fk_one(fixed, prismatic, q[i], out[i])


def fk_batch(fixed, prismatic, q):
    out = np.empty((q.shape[0], 4, 4))
    (_fk_parallel if q.shape[0] >= _PARALLEL_MIN else _fk_serial)(fixed, prismatic, q, out)
    return out


@njit(cache=True)
def _frames_one(base, pre, post, tool, prismatic, q, out):
    X = _load(base)
    _store(X, out[0])
    n = q.shape[0]
    for k in range(n):
        X = _mul(_move(_mul(X, pre[k]), q[k], prismatic[k]), post[k])
        if k == n - 1:
            X = _mul(X, tool)
        _store(X, out[k + 1])


@njit(cache=True, parallel=True)
def _frames_batch(base, pre, post, tool, prismatic, q, out):
    for i in prange(q.shape[0]):
        _frames_one(base, pre, post, tool, prismatic, q[i], out[i])


def frames_batch(base, pre, post, tool, prismatic, q):
    out = np.empty((q.shape[0], q.shape[1] + 1, 4, 4))
    if q.shape[0] == 1:
        _frames_one(base, pre, post, tool, prismatic, q[0], out[0])
    else:
        _frames_batch(base, pre, post, tool, prismatic, q, out)
    return out


@njit(cache=True)
def _jacobian_one(base, pre, post, tool, prismatic, q, tool_frame, J):
    # first pass: J[0:3, k] <- axis origin p_k, J[3:6, k] <- axis direction z_k
    X = _load(base)
    n = q.shape[0]
    for k in range(n):
        X = _mul(X, pre[k])
        J[0, k], J[1, k], J[2, k] = X[3], X[7], X[11]
        J[3, k], J[4, k], J[5, k] = X[2], X[6], X[10]
        X = _mul(_move(X, q[k], prismatic[k]), post[k])
    X = _mul(X, tool)
    ex, ey, ez = X[3], X[7], X[11]
    for k in range(n):
        zx, zy, zz = J[3, k], J[4, k], J[5, k]
        if prismatic[k]:
            J[0, k], J[1, k], J[2, k] = zx, zy, zz
            J[3, k], J[4, k], J[5, k] = 0.0, 0.0, 0.0
        else:
            rx, ry, rz = ex - J[0, k], ey - J[1, k], ez - J[2, k]
            J[0, k] = zy * rz - zz * ry
            J[1, k] = zz * rx - zx * rz
            J[2, k] = zx * ry - zy * rx
    if tool_frame:  # rows become R^T v and R^T w
        r00, r01, r02, r10, r11, r12, r20, r21, r22 = X[0], X[1], X[2], X[4], X[5], X[6], X[8], X[9], X[10]
        for k in range(n):
            for o in (0, 3):
                a, b, c = J[o, k], J[o + 1, k], J[o + 2, k]
                J[o, k] = r00 * a + r10 * b + r20 * c
                J[o + 1, k] = r01 * a + r11 * b + r21 * c
                J[o + 2, k] = r02 * a + r12 * b + r22 * c


@njit(cache=True)
def jacobian_single(base, pre, post, tool, prismatic, q, tool_frame):
    J = np.empty((6, q.shape[0]))
    _jacobian_one(base, pre, post, tool, prismatic, q, tool_frame, J)
    return J


@njit(cache=True, parallel=True)
def _jacobian_batch(base, pre, post, tool, prismatic, q, tool_frame, out):
    for i in prange(q.shape[0]):
        _jacobian_one(base, pre, post, tool, prismatic, q[i], tool_frame, out[i])


def jacobian_batch(base, pre, post, tool, prismatic, q, tool_frame):
    out = np.empty((q.shape[0], 6, q.shape[1]))
    _jacobian_batch(base, pre, post, tool, prismatic, q, tool_frame, out)
    return out
