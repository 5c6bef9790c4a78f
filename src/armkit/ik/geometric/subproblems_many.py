"""SP1, SP3 and ``rot`` of :mod:`.subproblems` on many instances at once, in NumPy.

The functions of :mod:`.subproblems` take one instance (vectors ``(3,)``, scalars) and are compiled
by Numba for the kernels. A family that solves in Python (:class:`armkit.ik.analytic.
geometric_prismatic.GeometricScara`) loops over its targets; called once per target, each
subproblem costs microseconds of Python. These take the varying part as arrays with a leading
batch axis ``(B, 3)`` or ``(B,)`` (the rest broadcasts: a fixed axis ``k (3,)``) and do the same
arithmetic, term by term in the same order, on whole arrays. The results equal the scalar
functions' to the last bit wherever NumPy's ``cos``, ``sin``, ``arctan2`` and ``arccos`` equal
``math``'s (tests/ik/geometric/test_subproblems.py checks them against the scalar ones: the same
counts and flags, angles to 1e-14; SP3's to 1e-12, its ``arccos`` near ±1 amplifies a last bit).

Same conventions as the scalar functions: angles in (-π, π], ``count`` and ``ls`` per instance.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from .subproblems import _TINY, TOL

__all__ = ["rot_many", "sp1_many", "sp3_many"]

Array = NDArray[np.float64]


def _dot(a: Array, b: Array) -> Array:
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1] + a[..., 2] * b[..., 2]


def _cross(a: Array, b: Array) -> Array:
    a, b = np.broadcast_arrays(a, b)
    out = np.empty(a.shape)
    out[..., 0] = a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1]
    out[..., 1] = a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2]
    out[..., 2] = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    return out


def _wrap(x: Array) -> Array:
    """``x`` in (-π, π] (:func:`.subproblems._wrap` on each entry)."""
    inside = (x > -np.pi) & (x <= np.pi)
    y = x - 2.0 * np.pi * np.floor((x + np.pi) / (2.0 * np.pi))
    y = np.where(y <= -np.pi, y + 2.0 * np.pi, np.where(y > np.pi, y - 2.0 * np.pi, y))
    return np.where(inside, x, y)


def rot_many(k: Array, theta: Array, p: Array) -> Array:
    """``rot(k, θ) p`` for angles ``theta (B,)``: ``(B, 3)`` (``k``, ``p``: ``(3,)`` or ``(B, 3)``)."""
    c = np.cos(theta)
    s = np.sin(theta)
    kp = _dot(k, p) * (1.0 - c)
    k, p = np.broadcast_to(k, np.shape(theta) + (3,)), np.broadcast_to(p, np.shape(theta) + (3,))
    out = np.empty(np.shape(theta) + (3,))
    out[..., 0] = p[..., 0] * c + (k[..., 1] * p[..., 2] - k[..., 2] * p[..., 1]) * s + k[..., 0] * kp
    out[..., 1] = p[..., 1] * c + (k[..., 2] * p[..., 0] - k[..., 0] * p[..., 2]) * s + k[..., 1] * kp
    out[..., 2] = p[..., 2] * c + (k[..., 0] * p[..., 1] - k[..., 1] * p[..., 0]) * s + k[..., 2] * kp
    return out


def sp1_many(p1: Array, p2: Array, k: Array) -> tuple[Array, NDArray[np.bool_]]:
    """:func:`.subproblems.sp1` on each row: ``(theta (B,), ls (B,))``."""
    kp1 = _dot(k, p1)
    kp2 = _dot(k, p2)
    x = _cross(k, p1)
    y0 = p1[..., 0] - k[..., 0] * kp1
    y1 = p1[..., 1] - k[..., 1] * kp1
    y2 = p1[..., 2] - k[..., 2] * kp1
    s = _dot(x, p2)
    c = y0 * p2[..., 0] + y1 * p2[..., 1] + y2 * p2[..., 2]
    theta = np.arctan2(s, c)
    n1 = np.sqrt(y0 * y0 + y1 * y1 + y2 * y2)
    q0 = p2[..., 0] - k[..., 0] * kp2
    q1 = p2[..., 1] - k[..., 1] * kp2
    q2 = p2[..., 2] - k[..., 2] * kp2
    n2 = np.sqrt(q0 * q0 + q1 * q1 + q2 * q2)
    scale = np.maximum(np.maximum(np.sqrt(_dot(p1, p1)), np.sqrt(_dot(p2, p2))), _TINY)
    ls = (np.abs(n1 - n2) > TOL * scale) | (np.abs(kp1 - kp2) > TOL * scale)
    return np.broadcast_to(theta, ls.shape).copy(), ls


def _trig1(a: float, b: float, c: Array, scale: Array) -> tuple[Array, NDArray[np.int64], NDArray[np.bool_]]:
    """:func:`.subproblems._trig1` for fixed ``a``, ``b`` and many ``c``: ``(θ (B, 2), count (B,), ls (B,))``."""
    B = len(c)
    t = np.zeros((B, 2))
    r = np.sqrt(a * a + b * b)
    flat = r <= TOL * scale                       # no dependence on θ: any θ (c ≈ 0) or none
    phi = np.arctan2(b, a)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = c / r
    inside = np.abs(x) <= 1.0
    w = np.arccos(np.clip(x, -1.0, 1.0))
    one = inside & ((w == 0.0) | (w == np.pi))
    t[:, 0] = np.where(inside, _wrap(phi + w), _wrap(np.where(x > 0.0, phi, phi + np.pi)))
    t[:, 1] = np.where(inside & ~one, _wrap(phi - w), 0.0)
    count = np.where(inside & ~one, 2, 1).astype(np.int64)
    ls = ~inside & (np.abs(np.abs(c) - r) > TOL * scale)
    t[flat] = 0.0
    count[flat] = 1
    ls = np.where(flat, np.abs(c) > TOL * scale, ls)
    return t, count, ls


def sp3_many(p1: Array, p2: Array, k: Array, d: Array) -> tuple[Array, NDArray[np.int64], NDArray[np.bool_]]:
    """:func:`.subproblems.sp3` for fixed ``p1``, ``p2``, ``k`` (each ``(3,)``) and many distances ``d (B,)``:
    ``(theta (B, 2), count (B,), ls (B,))``."""
    kp = _dot(k, p1)
    c = _dot(p2, k) * kp
    a = _dot(p2, p1) - c
    b = _dot(p2, _cross(k, p1))
    target = 0.5 * (_dot(p1, p1) + _dot(p2, p2) - d * d)
    scale = np.maximum(_dot(p1, p1) + _dot(p2, p2) + d * d, _TINY)
    return _trig1(float(a), float(b), target - c, scale)
