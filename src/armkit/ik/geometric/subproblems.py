"""The Paden-Kahan subproblems and IK-Geo's SP1-SP6, on plain float64 vectors.

The subproblems of Elias and Wen ("IK-Geo: Unified robot inverse kinematics using subproblem
decomposition", 2022), written here from their definitions; ``rot(k, θ)`` is the rotation by
``θ`` about the unit axis ``k`` (right hand), every vector a float64 array of shape (3,):

==== ============================================================================ ==========
SP1  ``rot(k, θ) p1 = p2``                                                         1
SP2  ``rot(k1, θ1) p1 = rot(k2, θ2) p2``                                           0-2
SP3  ``‖rot(k, θ) p1 − p2‖ = d``                                                   0-2
SP4  ``hᵀ rot(k, θ) p = d``                                                        0-2
SP5  ``p0 + rot(k1, θ1) p1 = rot(k2, θ2) (p2 + rot(k3, θ3) p3)``                   0-4
SP6  ``h1ᵀ rot(k1, θ1) p1 + h2ᵀ rot(k2, θ2) p2 = d1`` and                          0-4
     ``h3ᵀ rot(k3, θ1) p3 + h4ᵀ rot(k4, θ2) p4 = d2``
==== ============================================================================ ==========

Output convention (every function returns a tuple, never raises):

* ``sp1(p1, p2, k) -> (theta, ls)``
* ``sp2(p1, p2, k1, k2) -> (theta1 (2,), theta2 (2,), count, ls)``
* ``sp3(p1, p2, k, d) -> (theta (2,), count, ls)``
* ``sp4(h, p, k, d) -> (theta (2,), count, ls)``
* ``sp5(p0, p1, p2, p3, k1, k2, k3) -> (theta1 (4,), theta2 (4,), theta3 (4,), count, ls)``
* ``sp6(H (4, 3), K (4, 3), P (4, 3), d1, d2) -> (theta1 (4,), theta2 (4,), count, ls)``

The solution arrays have a fixed size; only the first ``count`` entries mean something (the
rest are 0). Angles are in (-π, π]. ``ls`` (least squares) is True when the equation has no
exact solution: the ``count`` (then 1) entries are the least-squares (closest) answer, for SP1
the angle that brings ``rot(k, θ) p1`` nearest to ``p2``, for SP2 the angles that bring the two
directions nearest (the lengths of ``p1`` and ``p2`` differing also sets ``ls``), for SP3/SP4 the
θ that makes the left side nearest to ``d``, for SP5/SP6 the point nearest to a solution among
the quartic's (complex) roots, an approximation. A double (tangent) solution is returned once,
``ls`` False. Degenerate instances with infinitely many solutions (``p`` along ``k`` in SP1/SP4,
parallel axes in SP2) return one member of the family. "Exact" means to a relative tolerance
of :data:`TOL` of the lengths involved.

The functions use only scalar math and small arrays, so Numba can compile them unchanged:
:func:`kernels` returns ``njit(cache=True)`` copies, compiled on first use (Numba is imported
only then); the functions of this module stay plain Python, importable and testable without it.
SP5 and SP6 find their exact solutions by the closed-form quartic of :func:`._kernels._trig2`; only
an instance without one takes the companion matrix (``np.linalg.eigvals``, ~5 µs compiled) for its
least-squares answer. A compiled SP5 with solutions takes 1.9 µs (7.4 µs by the companion matrix).
"""

from __future__ import annotations

import math
import types
from typing import Any, Optional

import numpy as np

from ... import _jit_loader
from . import _kernels
from ._kernels import _atan2
from ._kernels import _trig2 as _trig2_exact

__all__ = ["sp1", "sp2", "sp3", "sp4", "sp5", "sp6", "rot", "rotm", "kernels", "jit_namespace", "TOL", "KERNELS"]

TOL = 1e-8
"""Relative tolerance below which an equation counts as met exactly (``ls`` False)."""

_TINY = 1e-300


# ------------------------------------------------------------------------------ vector helpers
def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _cross(a, b):
    out = np.empty(3)
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]
    return out


def _norm(a):
    return math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])


def _wrap(x):
    """``x`` in (-π, π]."""
    if -math.pi < x <= math.pi:
        return x
    y = x - 2.0 * math.pi * math.floor((x + math.pi) / (2.0 * math.pi))
    if y <= -math.pi:
        y += 2.0 * math.pi
    elif y > math.pi:
        y -= 2.0 * math.pi
    return y


def _rot_into(k, theta, p, out):
    """``rot(k, theta) @ p`` (Rodrigues) into ``out`` (3,), without forming the matrix (libm's sine and cosine)."""
    c = math.cos(theta)
    s = math.sin(theta)
    kp = _dot(k, p) * (1.0 - c)
    out[0] = p[0] * c + (k[1] * p[2] - k[2] * p[1]) * s + k[0] * kp
    out[1] = p[1] * c + (k[2] * p[0] - k[0] * p[2]) * s + k[1] * kp
    out[2] = p[2] * c + (k[0] * p[1] - k[1] * p[0]) * s + k[2] * kp


def rot(k, theta, p):
    """``rot(k, theta) @ p`` (Rodrigues), without forming the matrix (:func:`_rot_into`)."""
    out = np.empty(3)
    _rot_into(k, theta, p, out)
    return out


def rotm(k, theta):
    """The rotation matrix ``rot(k, theta)`` (3, 3)."""
    c = math.cos(theta)
    s = math.sin(theta)
    v = 1.0 - c
    R = np.empty((3, 3))
    R[0, 0] = c + k[0] * k[0] * v
    R[0, 1] = k[0] * k[1] * v - k[2] * s
    R[0, 2] = k[0] * k[2] * v + k[1] * s
    R[1, 0] = k[1] * k[0] * v + k[2] * s
    R[1, 1] = c + k[1] * k[1] * v
    R[1, 2] = k[1] * k[2] * v - k[0] * s
    R[2, 0] = k[2] * k[0] * v - k[1] * s
    R[2, 1] = k[2] * k[1] * v + k[0] * s
    R[2, 2] = c + k[2] * k[2] * v
    return R


def _lin(h, k, p):
    """``(a, b, c)`` with ``hᵀ rot(k, θ) p = c + a cos θ + b sin θ`` for every θ (``hᵀ (k × p)`` term by term, as
    ``_dot(h, _cross(k, p))``: no array made)."""
    kp = _dot(k, p)
    c = _dot(h, k) * kp
    a = _dot(h, p) - c
    b = h[0] * (k[1] * p[2] - k[2] * p[1]) + h[1] * (k[2] * p[0] - k[0] * p[2]) + h[2] * (k[0] * p[1] - k[1] * p[0])
    return a, b, c


# ------------------------------------------------------------------------------------ SP1-SP4
def sp1(p1, p2, k):
    """θ with ``rot(k, θ) p1 = p2``; least squares (``ls`` True) when no θ does. Returns ``(θ, ls)``."""
    kp1 = _dot(k, p1)
    kp2 = _dot(k, p2)
    x = _cross(k, p1)                    # k × p1
    y0 = p1[0] - k[0] * kp1              # p1 ⊥ k
    y1 = p1[1] - k[1] * kp1
    y2 = p1[2] - k[2] * kp1
    s = _dot(x, p2)
    c = y0 * p2[0] + y1 * p2[1] + y2 * p2[2]
    theta = _atan2(s, c)
    n1 = math.sqrt(y0 * y0 + y1 * y1 + y2 * y2)
    q0 = p2[0] - k[0] * kp2
    q1 = p2[1] - k[1] * kp2
    q2 = p2[2] - k[2] * kp2
    n2 = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2)
    scale = max(_norm(p1), _norm(p2), _TINY)
    ls = abs(n1 - n2) > TOL * scale or abs(kp1 - kp2) > TOL * scale
    return theta, ls


def _trig1s(a, b, c, scale):
    """θ with ``a cos θ + b sin θ = c`` as scalars ``(θ0, θ1, count, ls)`` (θ1 = 0 where there is one): :func:`_trig1`
    without its array (the compiled solvers' cores call these); least squares past the extremes."""
    r = math.sqrt(a * a + b * b)
    if r <= TOL * scale:                 # no dependence on θ: any θ (c ≈ 0) or none
        return 0.0, 0.0, 1, abs(c) > TOL * scale
    phi = _atan2(b, a)
    x = c / r
    if abs(x) <= 1.0:
        w = math.acos(x)
        if w == 0.0 or w == math.pi:
            return _wrap(phi + w), 0.0, 1, False
        return _wrap(phi + w), _wrap(phi - w), 2, False
    return _wrap(phi if x > 0.0 else phi + math.pi), 0.0, 1, abs(abs(c) - r) > TOL * scale   # the extreme nearest c


NEAR_TANGENT = 1e-4
"""The closed-form cores' SP2 (:func:`.solvers_wrist._sp2cs`) and ``a cos θ + b sin θ = c`` (:func:`_trig1cs`) answer
by their cosines and sines where the answer is farther from the tangent than this share (of ``r²``, of ``1`` for
``1 − (c / r)²``: the sine of the distance above ~0.01); nearer, the angle from ``√(r² − e²)`` takes the rounding of
``e`` times ``1 / sin``, and :func:`sp2` and :func:`_trig1s` answer, as before 2026-12-07. With the bound at 1e-14,
17-20 % of the Kinova's and the rounded Puma's targets with ``|q5| < 1e-3`` gave a branch whose FK error (~1e-12)
asked for the touch-up (6 % with sp2), and a batch holding one such target went the batched path whole (the
Kinova's 1,000 targets: 2.5 -> 3.5 ms)."""


def _trig1cs(a, b, c, scale):
    """:func:`_trig1s` with each angle's cosine and sine: ``(count, ls, (θ0, cos θ0, sin θ0), (θ1, cos θ1, sin θ1))``,
    in its order (θ0 = φ + w, θ1 = φ − w for ``φ = atan2(b, a)``, ``w = acos(c / r)``), the cosines and sines by
    the sum formulas from ``a / r``, ``b / r``, ``c / r`` and ``√(1 − (c / r)²)``, each angle by ``atan2`` of its
    own: no ``acos`` (libm's, ~20 ns) and no sine or cosine for the caller's turns. The angles agree with
    :func:`_trig1s`'s to rounding; one answer where ``c / r`` is ±1 exactly, as there. Near the tangent
    (:data:`NEAR_TANGENT`) it answers by :func:`_trig1s` itself, with libm's cosines and sines. For the closed-form
    cores (:mod:`.solvers_parallel`, :mod:`.solvers_wrist`); the searches keep :func:`_trig1s`."""
    r = math.sqrt(a * a + b * b)
    if r <= TOL * scale:                 # no dependence on θ: any θ (c ≈ 0) or none
        z = (0.0, 1.0, 0.0)
        return 1, abs(c) > TOL * scale, z, z
    ca = a / r
    sa = b / r
    x = c / r
    if abs(x) <= 1.0 and 1.0 - x * x < NEAR_TANGENT:   # near the tangent: _trig1s's angles (by acos, whose rounding
        # there is no worse than √(1 − x²)'s and keeps the answers of before), their cosines and sines by libm
        t0, t1, n, ls = _trig1s(a, b, c, scale)
        return n, ls, (t0, math.cos(t0), math.sin(t0)), (t1, math.cos(t1), math.sin(t1))
    if abs(x) <= 1.0:
        sw = math.sqrt(1.0 - x * x)
        c0 = ca * x - sa * sw
        s0 = sa * x + ca * sw
        t0 = (_wrap(_atan2(s0, c0)), c0, s0)
        if sw == 0.0:
            return 1, False, t0, t0
        c1 = ca * x + sa * sw
        s1 = sa * x - ca * sw
        return 2, False, t0, (_wrap(_atan2(s1, c1)), c1, s1)
    if x < 0.0:                          # the extreme nearest c
        ca = -ca
        sa = -sa
    t0 = (_wrap(_atan2(sa, ca)), ca, sa)
    return 1, abs(abs(c) - r) > TOL * scale, t0, t0


def _sp4cs(h, p, k, d):
    """:func:`_sp4s` by :func:`_trig1cs` (each angle with its cosine and sine)."""
    a, b, c = _lin(h, k, p)
    scale = max(_norm(h) * _norm(p), abs(d), _TINY)
    return _trig1cs(a, b, d - c, scale)


def _sp3cs(p1, p2, k, d):
    """:func:`_sp3s` by :func:`_trig1cs` (each angle with its cosine and sine)."""
    a, b, c = _lin(p2, k, p1)
    target = 0.5 * (_dot(p1, p1) + _dot(p2, p2) - d * d)
    scale = max(_dot(p1, p1) + _dot(p2, p2) + d * d, _TINY)
    return _trig1cs(a, b, target - c, scale)


def _two(t0, t1):
    """The array ``(t0, t1)`` (2,) that :func:`_trig1`, :func:`sp3` and :func:`sp4` return of their scalar forms."""
    t = np.zeros(2)
    t[0] = t0
    t[1] = t1
    return t


def _trig1(a, b, c, scale):
    """θ with ``a cos θ + b sin θ = c``: ``(θ (2,), count, ls)``; least squares past the extremes (:func:`_trig1s`)."""
    t0, t1, n, ls = _trig1s(a, b, c, scale)
    return _two(t0, t1), n, ls


def sp4(h, p, k, d):
    """θ with ``hᵀ rot(k, θ) p = d``: ``(θ (2,), count, ls)``."""
    t0, t1, n, ls = _sp4s(h, p, k, d)
    return _two(t0, t1), n, ls


def _sp4s(h, p, k, d):
    """:func:`sp4` as scalars ``(θ0, θ1, count, ls)`` (:func:`_trig1s`; the same numbers, no array)."""
    a, b, c = _lin(h, k, p)
    scale = max(_norm(h) * _norm(p), abs(d), _TINY)
    return _trig1s(a, b, d - c, scale)


def sp3(p1, p2, k, d):
    """θ with ``‖rot(k, θ) p1 − p2‖ = d``: ``(θ (2,), count, ls)``."""
    t0, t1, n, ls = _sp3s(p1, p2, k, d)
    return _two(t0, t1), n, ls


def _sp3s(p1, p2, k, d):
    """:func:`sp3` as scalars ``(θ0, θ1, count, ls)`` (:func:`_trig1s`; the same numbers, no array)."""
    a, b, c = _lin(p2, k, p1)
    target = 0.5 * (_dot(p1, p1) + _dot(p2, p2) - d * d)
    scale = max(_dot(p1, p1) + _dot(p2, p2) + d * d, _TINY)
    return _trig1s(a, b, target - c, scale)


def sp2(p1, p2, k1, k2):
    """θ1, θ2 with ``rot(k1, θ1) p1 = rot(k2, θ2) p2``: ``(θ1 (2,), θ2 (2,), count, ls)``.

    Works on the directions of ``p1`` and ``p2`` (different lengths set ``ls``); the common
    vector ``v = rot(k1, θ1) p̂1`` is found from its components along ``k1``, ``k2`` and
    ``k1 × k2``, then each angle by SP1.
    """
    t1 = np.zeros(2)
    t2 = np.zeros(2)
    n1 = _norm(p1)
    n2 = _norm(p2)
    if n1 <= _TINY or n2 <= _TINY:
        return t1, t2, 1, n1 + n2 > TOL
    ls = abs(n1 - n2) > TOL * max(n1, n2)
    u1 = p1 / n1
    u2 = p2 / n2
    c = _dot(k1, k2)
    den = 1.0 - c * c
    if den < 1e-14:                      # parallel axes: a family of solutions, give θ1 = 0
        th, l2 = sp1(u2, u1, k2)
        t2[0] = th
        return t1, t2, 1, ls or l2
    a1 = _dot(k1, u1)
    a2 = _dot(k2, u2)
    alpha = (a1 - c * a2) / den
    beta = (a2 - c * a1) / den
    x = _cross(k1, k2)
    v0 = alpha * k1 + beta * k2
    g2 = (1.0 - _dot(v0, v0)) / den
    if g2 > 0.0:
        g = math.sqrt(g2)
        for i in range(2):
            v = v0 + (g if i == 0 else -g) * x
            t1[i] = sp1(u1, v, k1)[0]
            t2[i] = sp1(u2, v, k2)[0]
        return t1, t2, 2, ls
    # tangent (one solution, up to rounding) or none (least squares: the points of both circles nearest v0)
    t1[0] = sp1(u1, v0, k1)[0]
    t2[0] = sp1(u2, v0, k2)[0]
    return t1, t2, 1, ls or g2 < -1e-14


# ------------------------------------------------------------------------------------ SP5, SP6
def _quartic_roots(c4, c3, c2, c1, c0):
    """The (complex) roots of ``c4 t⁴ + c3 t³ + c2 t² + c1 t + c0``, leading zeros dropped
    (eigenvalues of the companion matrix)."""
    cs = np.array([c4, c3, c2, c1, c0])
    big = max(abs(c4), abs(c3), abs(c2), abs(c1), abs(c0))
    if big == 0.0:
        return np.zeros(0, dtype=np.complex128)
    cs = cs / big
    i = 0
    while i < 4 and abs(cs[i]) < 1e-13:
        i += 1
    deg = 4 - i
    if deg == 0:
        return np.zeros(0, dtype=np.complex128)
    C = np.zeros((deg, deg), dtype=np.complex128)
    for j in range(deg):
        C[0, j] = -cs[i + 1 + j] / cs[i]
    for j in range(1, deg):
        C[j, j - 1] = 1.0
    return np.linalg.eigvals(C)


def _res2(A, B, e, t1, t2):
    c1 = math.cos(t1)
    s1 = math.sin(t1)
    c2 = math.cos(t2)
    s2 = math.sin(t2)
    r0 = A[0, 0] * c1 + A[0, 1] * s1 + B[0, 0] * c2 + B[0, 1] * s2 - e[0]
    r1 = A[1, 0] * c1 + A[1, 1] * s1 + B[1, 0] * c2 + B[1, 1] * s2 - e[1]
    return r0, r1


def _newton2(A, B, e, t1, t2, steps, reach=0.5):
    """At most ``steps`` Newton steps on ``A (cos t1, sin t1) + B (cos t2, sin t2) = e``: none that moves an angle
    by more than ``reach`` (farther than that is not this root's convergence: the angles are left as they are),
    the last one below 1e-15 rad (the next would change them by rounding only). The residual is
    :func:`_res2`'s, term by term."""
    for _ in range(steps):
        c1 = math.cos(t1)
        s1 = math.sin(t1)
        c2 = math.cos(t2)
        s2 = math.sin(t2)
        r0 = A[0, 0] * c1 + A[0, 1] * s1 + B[0, 0] * c2 + B[0, 1] * s2 - e[0]
        r1 = A[1, 0] * c1 + A[1, 1] * s1 + B[1, 0] * c2 + B[1, 1] * s2 - e[1]
        j00 = -A[0, 0] * s1 + A[0, 1] * c1
        j10 = -A[1, 0] * s1 + A[1, 1] * c1
        j01 = -B[0, 0] * s2 + B[0, 1] * c2
        j11 = -B[1, 0] * s2 + B[1, 1] * c2
        det = j00 * j11 - j01 * j10
        if abs(det) < 1e-300:
            break
        d1 = (j11 * r0 - j01 * r1) / det
        d2 = (-j10 * r0 + j00 * r1) / det
        if abs(d1) > reach or abs(d2) > reach:
            break
        t1 -= d1
        t2 -= d2
        if abs(d1) + abs(d2) < 1e-15:
            break
    return t1, t2


def _trig2(A, B, e):
    """θ1, θ2 with ``A (cos θ1, sin θ1) + B (cos θ2, sin θ2) = e`` (A, B (2, 2), e (2,)).

    Eliminates the unknown whose matrix is better conditioned, which leaves ``‖f − M x‖ = 1``
    for ``x = (cos θ, sin θ)``: a quartic in ``tan(θ / 2)``. Returns ``(θ1 (4,), θ2 (4,), count, ls)``.

    The exact solutions come from :func:`._kernels._trig2`, the solver of the 1-D and 2-D searches (the
    quartic in closed form, shifted so that no solution lies near its root at infinity), each then taken to
    full precision (:func:`_newton2`). Only when it finds none does the quartic go to its companion matrix
    here: its near-real roots (and θ = π, the root at infinity) are polished by Newton steps on the 2x2 system
    and kept when they meet it (an exact solution the closed form missed), else the nearest candidate is the
    least-squares answer.
    """
    out1 = np.zeros(4)
    out2 = np.zeros(4)
    count = _trig2_exact(A[0, 0], A[0, 1], A[1, 0], A[1, 1], B[0, 0], B[0, 1], B[1, 0], B[1, 1], e[0], e[1], out1,
                         out2)
    if count > 0:
        for i in range(count):   # its roots meet the system to 1e-12, enough for the searches (they polish
            # later); here they are final: to full precision (an ill-conditioned root, 1e-12 in the residual,
            # can be 1e-7 rad off in the angles), by steps of this root's convergence only
            t1, t2 = _newton2(A, B, e, out1[i], out2[i], 6, 1e-4)
            out1[i] = _wrap(t1)
            out2[i] = _wrap(t2)
        return out1, out2, count, False
    na = math.sqrt(A[0, 0] ** 2 + A[0, 1] ** 2 + A[1, 0] ** 2 + A[1, 1] ** 2)
    nb = math.sqrt(B[0, 0] ** 2 + B[0, 1] ** 2 + B[1, 0] ** 2 + B[1, 1] ** 2)
    scale = max(na, nb, math.sqrt(e[0] * e[0] + e[1] * e[1]), _TINY)
    da = abs(A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]) / max(na * na, _TINY)
    db = abs(B[0, 0] * B[1, 1] - B[0, 1] * B[1, 0]) / max(nb * nb, _TINY)
    swap = db > da
    X = B if swap else A        # the eliminated unknown's matrix
    Y = A if swap else B
    det = X[0, 0] * X[1, 1] - X[0, 1] * X[1, 0]
    if abs(det) <= 1e-14 * max(na, nb) ** 2:
        return out1, out2, 0, True
    # X⁻¹
    i00 = X[1, 1] / det
    i01 = -X[0, 1] / det
    i10 = -X[1, 0] / det
    i11 = X[0, 0] / det
    f0 = i00 * e[0] + i01 * e[1]
    f1 = i10 * e[0] + i11 * e[1]
    m00 = i00 * Y[0, 0] + i01 * Y[1, 0]
    m01 = i00 * Y[0, 1] + i01 * Y[1, 1]
    m10 = i10 * Y[0, 0] + i11 * Y[1, 0]
    m11 = i10 * Y[0, 1] + i11 * Y[1, 1]
    q11 = m00 * m00 + m10 * m10
    q12 = m00 * m01 + m10 * m11
    q22 = m01 * m01 + m11 * m11
    g1 = m00 * f0 + m10 * f1
    g2 = m01 * f0 + m11 * f1
    h = f0 * f0 + f1 * f1 - 1.0
    roots = _quartic_roots(q11 + 2.0 * g1 + h, -4.0 * q12 - 4.0 * g2, -2.0 * q11 + 4.0 * q22 + 2.0 * h,
                           4.0 * q12 - 4.0 * g2, q11 - 2.0 * g1 + h)
    nr = roots.shape[0]
    cand_y = np.empty(nr + 1)
    cand_real = np.empty(nr + 1, dtype=np.bool_)
    for i in range(nr):
        cand_y[i] = 2.0 * math.atan(roots[i].real)
        cand_real[i] = abs(roots[i].imag) <= 1e-5 * (1.0 + abs(roots[i]))
    cand_y[nr] = math.pi
    cand_real[nr] = True
    count = 0
    best = np.inf
    best1 = 0.0
    best2 = 0.0
    for i in range(nr + 1):
        ty = cand_y[i]
        cy = math.cos(ty)
        sy = math.sin(ty)
        x0 = f0 - (m00 * cy + m01 * sy)
        x1 = f1 - (m10 * cy + m11 * sy)
        tx = _atan2(x1, x0)
        t1 = ty if swap else tx
        t2 = tx if swap else ty
        r0, r1 = _res2(A, B, e, t1, t2)
        r = math.sqrt(r0 * r0 + r1 * r1)
        if r < best:
            best, best1, best2 = r, t1, t2
        if not cand_real[i]:
            continue
        t1, t2 = _newton2(A, B, e, t1, t2, 6)
        r0, r1 = _res2(A, B, e, t1, t2)
        if math.sqrt(r0 * r0 + r1 * r1) > 1e-9 * scale:
            continue
        t1 = _wrap(t1)
        t2 = _wrap(t2)
        dup = False
        for j in range(count):
            if abs(_wrap(out1[j] - t1)) < 1e-7 and abs(_wrap(out2[j] - t2)) < 1e-7:
                dup = True
        if not dup and count < 4:
            out1[count] = t1
            out2[count] = t2
            count += 1
    if count == 0:
        out1[0] = _wrap(best1)
        out2[0] = _wrap(best2)
        return out1, out2, 1, True
    return out1, out2, count, False


def sp6(H, K, P, d1, d2):
    """θ1, θ2 with ``H[0]ᵀ rot(K[0], θ1) P[0] + H[1]ᵀ rot(K[1], θ2) P[1] = d1`` and
    ``H[2]ᵀ rot(K[2], θ1) P[2] + H[3]ᵀ rot(K[3], θ2) P[3] = d2``: ``(θ1 (4,), θ2 (4,), count, ls)``."""
    A = np.empty((2, 2))
    B = np.empty((2, 2))
    e = np.empty(2)
    a, b, c = _lin(H[0], K[0], P[0])
    A[0, 0] = a
    A[0, 1] = b
    e[0] = d1 - c
    a, b, c = _lin(H[1], K[1], P[1])
    B[0, 0] = a
    B[0, 1] = b
    e[0] -= c
    a, b, c = _lin(H[2], K[2], P[2])
    A[1, 0] = a
    A[1, 1] = b
    e[1] = d2 - c
    a, b, c = _lin(H[3], K[3], P[3])
    B[1, 0] = a
    B[1, 1] = b
    e[1] -= c
    # equal row scales, so that the tolerance means the same in both equations
    for i in range(2):
        s = math.sqrt(A[i, 0] ** 2 + A[i, 1] ** 2 + B[i, 0] ** 2 + B[i, 1] ** 2)
        if s > 0.0:
            A[i, 0] /= s
            A[i, 1] /= s
            B[i, 0] /= s
            B[i, 1] /= s
            e[i] /= s
    return _trig2(A, B, e)


def sp5(p0, p1, p2, p3, k1, k2, k3):
    """θ1, θ2, θ3 with ``p0 + rot(k1, θ1) p1 = rot(k2, θ2) (p2 + rot(k3, θ3) p3)``:
    ``(θ1 (4,), θ2 (4,), θ3 (4,), count, ls)``.

    Both sides are the same vector iff their components along ``k2`` and their lengths agree:
    two equations linear in ``(cos θ1, sin θ1, cos θ3, sin θ3)`` (solved as SP6 is), then θ2 by SP1.
    """
    Hs = np.empty((4, 3))
    Ks = np.empty((4, 3))
    Ps = np.empty((4, 3))
    Hs[0] = k2
    Hs[1] = -k2
    Hs[2] = 2.0 * p0
    Hs[3] = -2.0 * p2
    Ks[0] = k1
    Ks[1] = k3
    Ks[2] = k1
    Ks[3] = k3
    Ps[0] = p1
    Ps[1] = p3
    Ps[2] = p1
    Ps[3] = p3
    d1 = _dot(k2, p2) - _dot(k2, p0)
    d2 = _dot(p2, p2) + _dot(p3, p3) - _dot(p0, p0) - _dot(p1, p1)
    t1, t3, count, ls = sp6(Hs, Ks, Ps, d1, d2)
    t2 = np.zeros(4)
    for i in range(count):
        v = p0 + rot(k1, t1[i], p1)
        w = p2 + rot(k3, t3[i], p3)
        th, l1 = sp1(w, v, k2)
        t2[i] = th
        ls = ls or l1
    return t1, t2, t3, count, ls


# ---------------------------------------------------------------------------------- compiling
KERNELS = ("_dot", "_cross", "_norm", "_wrap", "_rot_into", "rot", "rotm", "_lin", "sp1", "_trig1s", "_trig1cs",
           "_two", "_trig1", "_sp4s", "_sp4cs", "sp4", "_sp3s", "_sp3cs", "sp3", "sp2", "_quartic_roots", "_res2",
           "_newton2", "_trig2", "sp6", "sp5")
"""The functions :func:`kernels` compiles, callees before callers."""


def jit_namespace(namespace: dict[str, Any], names: tuple[str, ...], extra: Optional[dict[str, Any]] = None,
                  uncounted: tuple[str, ...] = (), vector: tuple[str, ...] = ()) -> dict[str, Any]:
    """``njit(cache=True)`` copies of ``namespace[name]`` for each name, compiled on first call.

    The copies share a new globals dict (a copy of ``namespace`` updated with ``extra`` and the
    compiled functions themselves), so that the plain functions keep calling plain functions
    and the compiled ones call compiled ones. Returns that dict.

    The names in ``uncounted`` are compiled without Numba's reference counts (``_nrt=False``): a function that
    takes arrays counts a reference to each up on entry and down on return, and to each view it makes (``S[i]``),
    with an atomic instruction each time. In the 1-D searches, whose small functions are called ~500 times a
    target with 5-12 arrays each, that was 13 % of the time (perf, 2026-12-06). Such a function must allocate
    no array and return none, in its whole call tree; it may call a counted one (every other name is compiled with
    ``_nrt=True`` said explicitly, so it does not take an uncounted caller's setting, as Numba's callees do).

    The names in ``vector`` are compiled with NumPy's error model: a float division by zero gives an infinity or
    not-a-number, as in C, where Python's model raises ``ZeroDivisionError``, a branch out of every loop with a
    division, which keeps the loop from being compiled to vector instructions
    (:func:`.solvers_wrist._wrist_lanes`). Results where no division by zero happens are the same.
    """
    _jit_loader.install_cache_fallback()
    from numba import njit

    ns = dict(namespace)
    if extra:
        ns.update(extra)
    for name in names:
        f = namespace[name]
        copy = types.FunctionType(f.__code__, ns, f.__name__, f.__defaults__, f.__closure__)
        options = {"error_model": "numpy"} if name in vector else {}
        ns[name] = njit(cache=True, _nrt=name not in uncounted, **options)(copy)
    return ns


def compiled(namespace: dict[str, Any], names: tuple[str, ...], extra: Optional[dict[str, Any]] = None,
             uncounted: tuple[str, ...] = ()) -> Optional[types.SimpleNamespace]:
    """:func:`jit_namespace` of ``names`` (and ``extra``, ``uncounted``) as a namespace (attributes named as the
    functions, and ``namespace``: the dict), or None when Numba cannot be imported."""
    try:
        ns = jit_namespace(namespace, names, extra, uncounted)
    except ImportError:
        return None
    return types.SimpleNamespace(**{name: ns[name] for name in names}, namespace=ns)


_KERNELS: Optional[types.SimpleNamespace] = None


def kernels() -> Optional[types.SimpleNamespace]:
    """The compiled subproblems (attributes named as the functions of this module), or None
    when Numba cannot be imported. Compiled on first call of each (cached on disk)."""
    global _KERNELS
    if _KERNELS is None:
        kk = _kernels.kernels()
        if kk is None:
            return None
        _KERNELS = compiled(globals(), KERNELS, {"_trig2_exact": kk._trig2, "_atan2": kk.namespace["_atan2"]})
        if _KERNELS is not None:
            _jit_loader.forget_stale_cache(_KERNELS.namespace, SOURCES)
    return _KERNELS


SOURCES = ("ik/geometric/subproblems.py", "ik/geometric/_kernels.py", "kinematics/_jit.py")
"""The files whose functions the compiled subproblems contain (armkit's atan2 from the last): a change to any
compiles them anew."""
