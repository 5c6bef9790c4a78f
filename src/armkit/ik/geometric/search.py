"""The 1-D searches of the 6R classes without a closed form but with one special pair (IK-Geo's idea), in one engine.

Each class fixes one joint ``x`` (sampled over a turn); at each sample a subproblem gives up to 4
*branches* (values of other joints, the row ``S (3,)``) that satisfy all the equations but one, and
that one's error is the branch's residual ``E``. A solution of the IK is a zero of a branch's residual.

====== ====================== ====================== ============================================= ========
kind   class (0-based axes)   searched joint         branch (subproblem)                           residual
====== ====================== ====================== ============================================= ========
``TI`` 4, 5 meet              q1                     (q2, q3, q4) by SP5: the axis-5/6 point       angle of axes 5, 6
``TP`` 1 ∥ 2                  q6                     (q1, q4, q2 ± q3) by SP6, SP1                 distance
``SW`` 3, 4, 5 meet           q1                     q3 by SP3: the wrist centre's distance        along axis 2
``SM`` 1, 2, 3 meet           q6                     q1 by SP3: the distance of axis 5 to the      along axis 5
                                                     centre of the spherical joint
====== ====================== ====================== ============================================= ========

The engine (:func:`_search`) samples ``x`` at :data:`N` points over a turn (compiled, a fast
closed-form quartic inside SP5/SP6, no Python per sample) and pairs the branches of neighbouring
samples by distance (a step where they do not pair up one to one within 0.1 rad is sampled
:data:`SUB_N` times finer). Then, along each branch:

* a sign change between two samples is refined by false position (Illinois) that follows the
  branch, to 1e-14 rad;
* a local extremum of the residual on the side away from 0 whose parabola through three samples
  comes within one second difference of 0 is searched by golden section (stopping as soon as the
  residual changes sign): two roots within one step, or a double root (kept when its residual is
  below 1e-12);
* a branch that ends between two samples (two subproblem solutions meet, the residual changes
  like the square root of the distance there) has its end found by bisection (to 3e-10 rad) and
  is sampled :data:`EDGE_N` more times towards it, quadratically spaced, then as above (sign
  changes, and extrema turning back towards 0).

Resolution: :data:`N` = 240 samples (1.5° apart), :data:`SUB_N` × finer in ambiguous steps. A root
can be missed only when three or more roots of one branch lie within one step, two within 3e-10
rad of a branch end, or a double root's residual stays above 1e-12, or two roots crowd within one
step next to a branch end (measured against a dense scan of 20,000 samples on 200 random targets
of each class, tests/ik/geometric/test_search_speed_free.py: 0 missing for TP, SW, SM; for TI one
target lost both roots of a near-double root, residual peak 2e-6, 4e-3 rad from a branch end). The
solvers of :mod:`.solvers` complete each root to the six joints and check every solution by FK of
the true chain (TOL 1e-9), polishing by Newton steps where the chain's axes only nearly meet.

:func:`kernels` compiles the engine with Numba like :mod:`.solvers`; the plain functions run
without it (slowly: about a second a target).
"""

from __future__ import annotations

import cmath
import math
import types
from typing import Any, Optional

import numpy as np
from numpy.typing import NDArray

from . import subproblems as _sp
from .poe import POE

__all__ = ["two_parallel", "N", "SUB_N", "EDGE_N", "MAXROOT", "kernels", "TI", "TP", "SW", "SM"]

Array = NDArray[np.float64]

N = 240
"""Samples of the searched joint over one turn (1.5° apart)."""
SUB_N = 16
"""Sub-samples of a step where the branches of its two ends do not pair up one to one within 0.1 rad."""
EDGE_N = 10
"""Samples (quadratically spaced) between the last sample of a branch and where it ends."""
MAXROOT = 64
TI, TP, SW, SM = 0, 1, 2, 3
"""The kinds of search (see the table above)."""

_PI = math.pi
_R2 = math.sqrt(0.5)
_C8 = (1.0, _R2, 0.0, -_R2, -1.0, -_R2, 0.0, _R2)
_S8 = (0.0, _R2, 1.0, _R2, 0.0, -_R2, -1.0, -_R2)
"""cos and sin of k π / 4."""


# ------------------------------------------------------------------------------------- scalar vectors
def _t(a):
    return (a[0], a[1], a[2])


def _tdot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _tcross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _tadd(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def _tsub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def _tmul(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def _tnorm(a):
    return math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])


def _trot(k, th, p):
    """``rot(k, th) p`` (Rodrigues)."""
    c = math.cos(th)
    s = math.sin(th)
    kp = (k[0] * p[0] + k[1] * p[1] + k[2] * p[2]) * (1.0 - c)
    return (p[0] * c + (k[1] * p[2] - k[2] * p[1]) * s + k[0] * kp,
            p[1] * c + (k[2] * p[0] - k[0] * p[2]) * s + k[1] * kp,
            p[2] * c + (k[0] * p[1] - k[1] * p[0]) * s + k[2] * kp)


def _tmv(M, v):
    return (M[0, 0] * v[0] + M[0, 1] * v[1] + M[0, 2] * v[2],
            M[1, 0] * v[0] + M[1, 1] * v[1] + M[1, 2] * v[2],
            M[2, 0] * v[0] + M[2, 1] * v[1] + M[2, 2] * v[2])


def _tmtv(M, v):
    return (M[0, 0] * v[0] + M[1, 0] * v[1] + M[2, 0] * v[2],
            M[0, 1] * v[0] + M[1, 1] * v[1] + M[2, 1] * v[2],
            M[0, 2] * v[0] + M[1, 2] * v[1] + M[2, 2] * v[2])


def _tlin(h, k, p):
    """``(a, b, c)`` with ``hᵀ rot(k, θ) p = a cos θ + b sin θ + c``."""
    c = _tdot(h, k) * _tdot(k, p)
    return _tdot(h, p) - c, _tdot(h, _tcross(k, p)), c


def _tsp1(p1, p2, k):
    """θ with ``rot(k, θ) p1`` nearest ``p2`` (SP1)."""
    kp1 = _tdot(k, p1)
    y = (p1[0] - k[0] * kp1, p1[1] - k[1] * kp1, p1[2] - k[2] * kp1)
    return math.atan2(_tdot(_tcross(k, p1), p2), _tdot(y, p2))


def _wrap(x):
    if -_PI < x <= _PI:
        return x
    y = x - 2.0 * _PI * math.floor((x + _PI) / (2.0 * _PI))
    if y <= -_PI:
        y += 2.0 * _PI
    return y


# -------------------------------------------------------------------------------- the quartic
def _cubic_max(a2, a1, a0):
    """The largest real root of ``z³ + a2 z² + a1 z + a0`` (trigonometric or Cardano form, then Newton)."""
    p = a1 - a2 * a2 / 3.0
    q = 2.0 * a2 * a2 * a2 / 27.0 - a2 * a1 / 3.0 + a0
    disc = 0.25 * q * q + p * p * p / 27.0
    if disc > 0.0:
        sd = math.sqrt(disc)
        u = -0.5 * q + sd
        v = -0.5 * q - sd
        w = math.copysign(abs(u) ** (1.0 / 3.0), u) + math.copysign(abs(v) ** (1.0 / 3.0), v)
    elif p < 0.0:
        m = math.sqrt(-p / 3.0)
        arg = -0.5 * q / (m * m * m)
        arg = min(1.0, max(-1.0, arg))
        w = 2.0 * m * math.cos(math.acos(arg) / 3.0)
    else:
        w = 0.0
    z = w - a2 / 3.0
    for _ in range(3):
        f = ((z + a2) * z + a1) * z + a0
        d = (3.0 * z + 2.0 * a2) * z + a1
        if d == 0.0:
            break
        dz = f / d
        z -= dz
        if abs(dz) <= 1e-16 * (1.0 + abs(z)):
            break
    return z


def _quartic(c4, c3, c2, c1, c0, re, im):
    """The 4 complex roots of ``c4 t⁴ + c3 t³ + c2 t² + c1 t + c0`` (``c4`` the largest coefficient in size or
    near it) into ``re``, ``im``: Ferrari's factorisation into two quadratics, each root polished by Newton
    steps on the quartic."""
    b = c3 / c4
    c = c2 / c4
    d = c1 / c4
    e = c0 / c4
    s = 0.25 * b
    p = c - 6.0 * s * s
    q = d - 2.0 * c * s + 8.0 * s * s * s
    r = e - d * s + c * s * s - 3.0 * s * s * s * s
    big = 1.0 + abs(p) + abs(r)
    z0 = 0.0
    if abs(q) > 1e-14 * big * math.sqrt(big):
        z0 = _cubic_max(2.0 * p, p * p - 4.0 * r, -q * q)
    if z0 > 1e-14 * big:
        u = math.sqrt(z0)
        v = 0.5 * (p + z0 - q / u)
        w = 0.5 * (p + z0 + q / u)
        _quad(u, v, re, im, 0)
        _quad(-u, w, re, im, 2)
    else:                                 # biquadratic: y² = z, z² + p z + r = 0
        dz = p * p - 4.0 * r
        if dz >= 0.0:
            sq = math.sqrt(dz)
            za = complex(0.5 * (-p + sq), 0.0)
            zb = complex(0.5 * (-p - sq), 0.0)
        else:
            sq = math.sqrt(-dz)
            za = complex(-0.5 * p, 0.5 * sq)
            zb = complex(-0.5 * p, -0.5 * sq)
        ya = cmath.sqrt(za)
        yb = cmath.sqrt(zb)
        re[0] = ya.real
        im[0] = ya.imag
        re[1] = -ya.real
        im[1] = -ya.imag
        re[2] = yb.real
        im[2] = yb.imag
        re[3] = -yb.real
        im[3] = -yb.imag
    for i in range(4):
        t = complex(re[i] - s, im[i])
        f = (((t + b) * t + c) * t + d) * t + e
        for _ in range(3):
            df = ((4.0 * t + 3.0 * b) * t + 2.0 * c) * t + d
            if df == 0.0:
                break
            tn = t - f / df
            fn = (((tn + b) * tn + c) * tn + d) * tn + e
            if abs(fn) >= abs(f):
                break
            t = tn
            f = fn
        re[i] = t.real
        im[i] = t.imag


def _quad(u, v, re, im, k):
    """The roots of ``y² + u y + v`` into ``re[k:k+2]``, ``im[k:k+2]``."""
    disc = u * u - 4.0 * v
    if disc >= 0.0:
        sq = math.sqrt(disc)
        y1 = -0.5 * (u + math.copysign(sq, u))
        y2 = v / y1 if y1 != 0.0 else 0.0
        re[k] = y1
        im[k] = 0.0
        re[k + 1] = y2
        im[k + 1] = 0.0
    else:
        sq = math.sqrt(-disc)
        re[k] = -0.5 * u
        im[k] = 0.5 * sq
        re[k + 1] = -0.5 * u
        im[k + 1] = -0.5 * sq


def _res2(a00, a01, a10, a11, b00, b01, b10, b11, e0, e1, t1, t2):
    c1 = math.cos(t1)
    s1 = math.sin(t1)
    c2 = math.cos(t2)
    s2 = math.sin(t2)
    return a00 * c1 + a01 * s1 + b00 * c2 + b01 * s2 - e0, a10 * c1 + a11 * s1 + b10 * c2 + b11 * s2 - e1


def _trig2(a00, a01, a10, a11, b00, b01, b10, b11, e0, e1, T1, T2):
    """θ1, θ2 with ``A (cos θ1, sin θ1) + B (cos θ2, sin θ2) = e`` (rows of equal scale) into ``T1``, ``T2``;
    returns their count (0 when no exact solution). As :func:`.subproblems._trig2` (eliminate the better
    conditioned unknown, a quartic in the other), the quartic in closed form and shifted so that its root at
    infinity is far from every solution."""
    na = math.sqrt(a00 * a00 + a01 * a01 + a10 * a10 + a11 * a11)
    nb = math.sqrt(b00 * b00 + b01 * b01 + b10 * b10 + b11 * b11)
    scale = max(na, nb, math.sqrt(e0 * e0 + e1 * e1), 1e-300)
    da = abs(a00 * a11 - a01 * a10) / max(na * na, 1e-300)
    db = abs(b00 * b11 - b01 * b10) / max(nb * nb, 1e-300)
    swap = db > da
    if swap:
        x00, x01, x10, x11, y00, y01, y10, y11 = b00, b01, b10, b11, a00, a01, a10, a11
    else:
        x00, x01, x10, x11, y00, y01, y10, y11 = a00, a01, a10, a11, b00, b01, b10, b11
    det = x00 * x11 - x01 * x10
    if abs(det) <= 1e-14 * max(na, nb) ** 2:
        return 0
    i00 = x11 / det
    i01 = -x01 / det
    i10 = -x10 / det
    i11 = x00 / det
    f0 = i00 * e0 + i01 * e1
    f1 = i10 * e0 + i11 * e1
    m00 = i00 * y00 + i01 * y10
    m01 = i00 * y01 + i01 * y11
    m10 = i10 * y00 + i11 * y10
    m11 = i10 * y01 + i11 * y11
    # ‖f − M (cos θ, sin θ)‖² − 1 = a0 + a1 cos θ + b1 sin θ + a2 cos 2θ + b2 sin 2θ
    q11 = m00 * m00 + m10 * m10
    q12 = m00 * m01 + m10 * m11
    q22 = m01 * m01 + m11 * m11
    a0 = f0 * f0 + f1 * f1 - 1.0 + 0.5 * (q11 + q22)
    a1 = -2.0 * (m00 * f0 + m10 * f1)
    b1 = -2.0 * (m01 * f0 + m11 * f1)
    a2 = 0.5 * (q11 - q22)
    b2 = q12
    # θ = φ + α with g(α + π) largest of 8 (the quartic in tan(φ / 2) then has its largest leading coefficient)
    best = -1.0
    kb = 0
    for k in range(8):
        g = abs(a0 - a1 * _C8[k] - b1 * _S8[k] + a2 * _C8[(2 * k) % 8] + b2 * _S8[(2 * k) % 8])
        if g > best:
            best = g
            kb = k
    if best <= 1e-300:
        return 0
    alpha = 0.25 * _PI * kb
    ca = _C8[kb]
    sa = _S8[kb]
    c2a = _C8[(2 * kb) % 8]
    s2a = _S8[(2 * kb) % 8]
    A1 = a1 * ca + b1 * sa
    B1 = b1 * ca - a1 * sa
    A2 = a2 * c2a + b2 * s2a
    B2 = b2 * c2a - a2 * s2a
    re = np.empty(4)
    im = np.empty(4)
    _quartic(a0 - A1 + A2, 2.0 * B1 - 4.0 * B2, 2.0 * a0 - 6.0 * A2, 2.0 * B1 + 4.0 * B2, a0 + A1 + A2, re, im)
    count = 0
    for i in range(4):
        if abs(im[i]) > 1e-5 * (1.0 + math.sqrt(re[i] * re[i] + im[i] * im[i])):
            continue
        t = re[i]
        cf = (1.0 - t * t) / (1.0 + t * t)
        sf = 2.0 * t / (1.0 + t * t)
        cy = cf * ca - sf * sa
        sy = sf * ca + cf * sa
        x0 = f0 - (m00 * cy + m01 * sy)
        x1 = f1 - (m10 * cy + m11 * sy)
        nx = math.sqrt(x0 * x0 + x1 * x1)
        if nx <= 0.0:
            continue
        cx = x0 / nx
        sx = x1 / nx
        if swap:
            c1, s1, c2, s2 = cy, sy, cx, sx
        else:
            c1, s1, c2, s2 = cx, sx, cy, sy
        r0 = a00 * c1 + a01 * s1 + b00 * c2 + b01 * s2 - e0
        r1 = a10 * c1 + a11 * s1 + b10 * c2 + b11 * s2 - e1
        t1 = math.atan2(s1, c1)
        t2 = math.atan2(s2, c2)
        for _ in range(6 if math.sqrt(r0 * r0 + r1 * r1) > 1e-12 * scale else 0):   # Newton on the 2 x 2 system
            j00 = -a00 * s1 + a01 * c1
            j10 = -a10 * s1 + a11 * c1
            j01 = -b00 * s2 + b01 * c2
            j11 = -b10 * s2 + b11 * c2
            dj = j00 * j11 - j01 * j10
            if abs(dj) < 1e-300:
                break
            d1 = (j11 * r0 - j01 * r1) / dj
            d2 = (-j10 * r0 + j00 * r1) / dj
            if abs(d1) > 0.5 or abs(d2) > 0.5:
                break
            t1 -= d1
            t2 -= d2
            c1 = math.cos(t1)
            s1 = math.sin(t1)
            c2 = math.cos(t2)
            s2 = math.sin(t2)
            r0 = a00 * c1 + a01 * s1 + b00 * c2 + b01 * s2 - e0
            r1 = a10 * c1 + a11 * s1 + b10 * c2 + b11 * s2 - e1
            if abs(d1) + abs(d2) < 1e-15 or math.sqrt(r0 * r0 + r1 * r1) <= 1e-14 * scale:
                break
        if math.sqrt(r0 * r0 + r1 * r1) > 1e-9 * scale:
            continue
        t1 = _wrap(t1)
        t2 = _wrap(t2)
        dup = False
        for j in range(count):
            if abs(_wrap(T1[j] - t1)) < 1e-7 and abs(_wrap(T2[j] - t2)) < 1e-7:
                dup = True
        if not dup:
            T1[count] = t1
            T2[count] = t2
            count += 1
    return count


def _sp6(h0, k0, p0, h1, k1, p1, h2, k2, p2, h3, k3, p3, d1, d2, T1, T2):
    """SP6 (as :func:`.subproblems.sp6`, exact solutions only) on scalar vectors: the count into ``T1``, ``T2``."""
    a00, a01, c0 = _tlin(h0, k0, p0)
    b00, b01, c1 = _tlin(h1, k1, p1)
    a10, a11, c2 = _tlin(h2, k2, p2)
    b10, b11, c3 = _tlin(h3, k3, p3)
    e0 = d1 - c0 - c1
    e1 = d2 - c2 - c3
    s = math.sqrt(a00 * a00 + a01 * a01 + b00 * b00 + b01 * b01)
    if s > 0.0:
        a00 /= s
        a01 /= s
        b00 /= s
        b01 /= s
        e0 /= s
    s = math.sqrt(a10 * a10 + a11 * a11 + b10 * b10 + b11 * b11)
    if s > 0.0:
        a10 /= s
        a11 /= s
        b10 /= s
        b11 /= s
        e1 /= s
    return _trig2(a00, a01, a10, a11, b00, b01, b10, b11, e0, e1, T1, T2)


def _sp3(p1, p2, k, d, T):
    """θ with ``‖rot(k, θ) p1 − p2‖ = d`` into ``T``: the count (0 when none; a double root counts twice)."""
    a, b, c = _tlin(p2, k, p1)
    rhs = 0.5 * (_tdot(p1, p1) + _tdot(p2, p2) - d * d) - c
    r = math.sqrt(a * a + b * b)
    if r <= 1e-14 * (_tdot(p1, p1) + _tdot(p2, p2) + d * d):
        return 0
    x = rhs / r
    if abs(x) > 1.0:
        return 0
    phi = math.atan2(b, a)
    w = math.acos(x)
    T[0] = _wrap(phi + w)
    T[1] = _wrap(phi - w)
    return 2


# ------------------------------------------------------------------------------ the branches
def _eval(kind, H, P, C, x, S, E):
    """The branches at ``x`` into ``S (4, 3)``, their residuals into ``E (4,)``; returns their count.
    ``C (4, 3)``: the target, per kind (TI: ``e6``, ``p0w``; TP, SM: the rows of ``R_06``, then ``p``;
    SW: ``p0W``)."""
    if kind == TI:
        return _eval_ti(H, P, C, x, S, E)
    if kind == TP:
        return _eval_tp(H, P, C, x, S, E)
    if kind == SW:
        return _eval_sw(H, P, C, x, S, E)
    return _eval_sm(H, P, C, x, S, E)


def _eval_ti(H, P, C, x, S, E):
    """Axes 5, 6 meet (P[5] = 0), q1 = ``x``: SP5 ``−P2 + rot(−h2, q2) v = rot(h3, q3) (P3 + rot(h4, q4) P4)``
    for ``v = rot(h1, −x) p0w − P1``; residual ``(R_04 h5)ᵀ e6 − h5ᵀ h6``."""
    h0 = _t(H[0])
    k1 = _tmul(_t(H[1]), -1.0)
    k2 = _t(H[2])
    k3 = _t(H[3])
    p0 = _tmul(_t(P[2]), -1.0)
    p1 = _tsub(_trot(h0, -x, _t(C[1])), _t(P[1]))
    p2 = _t(P[3])
    p3 = _t(P[4])
    T1 = np.empty(4)
    T3 = np.empty(4)
    n = _sp6(k2, k1, p1, _tmul(k2, -1.0), k3, p3, _tmul(p0, 2.0), k1, p1, _tmul(p2, -2.0), k3, p3,
             _tdot(k2, p2) - _tdot(k2, p0), _tdot(p2, p2) + _tdot(p3, p3) - _tdot(p0, p0) - _tdot(p1, p1), T1, T3)
    c = _tdot(_t(H[4]), _t(H[5]))
    e6 = _t(C[0])
    h4 = _t(H[4])
    for i in range(n):
        v = _tadd(p0, _trot(k1, T1[i], p1))
        w = _tadd(p2, _trot(k3, T3[i], p3))
        t2 = _tsp1(w, v, k2)
        S[i, 0] = T1[i]
        S[i, 1] = t2
        S[i, 2] = T3[i]
        a = _trot(k3, T3[i], h4)
        a = _trot(k2, t2, a)
        a = _trot(k1, -T1[i], a)      # rot(−h2, −q2) = rot(h2, q2)
        a = _trot(h0, x, a)
        E[i] = _tdot(a, e6) - c
    return n


def _eval_tp(H, P, C, x, S, E):
    """Axes 2 ∥ 3, q6 = ``x``: SP6 in (q1, q4), θ = q2 ± q3 by SP1; residual ``|d| − |P3|`` (see :func:`two_parallel`)."""
    h0 = _t(H[0])
    h1 = _t(H[1])
    h3 = _t(H[3])
    h4 = _t(H[4])
    c0 = _tmv(C[0:3], _trot(_t(H[5]), -x, (1.0, 0.0, 0.0)))
    c1 = _tmv(C[0:3], _trot(_t(H[5]), -x, (0.0, 1.0, 0.0)))
    c2 = _tmv(C[0:3], _trot(_t(H[5]), -x, (0.0, 0.0, 1.0)))
    # R05 = R06 rot(h6, −x): columns c0, c1, c2
    p5 = _t(P[5])
    R05p5 = (c0[0] * p5[0] + c1[0] * p5[1] + c2[0] * p5[2], c0[1] * p5[0] + c1[1] * p5[1] + c2[1] * p5[2],
             c0[2] * p5[0] + c1[2] * p5[1] + c2[2] * p5[2])
    w = _tsub(_tsub(_tsub(_t(C[3]), _t(P[0])), R05p5), _tmv(C[0:3], _t(P[6])))
    v = (c0[0] * h4[0] + c1[0] * h4[1] + c2[0] * h4[2], c0[1] * h4[0] + c1[1] * h4[1] + c2[1] * h4[2],
         c0[2] * h4[0] + c1[2] * h4[1] + c2[2] * h4[2])
    mh1 = _tmul(h1, -1.0)
    T0 = np.empty(4)
    T3 = np.empty(4)
    mh0 = _tmul(h0, -1.0)
    n = _sp6(h1, mh0, w, mh1, h3, _t(P[4]), h1, mh0, v, mh1, h3, h4,
             _tdot(h1, _tadd(_tadd(_t(P[1]), _t(P[2])), _t(P[3]))), 0.0, T0, T3)
    n2 = _tnorm(_t(P[2]))
    for i in range(n):
        u = _trot(h3, T3[i], h4)
        th = _tsp1(u, _trot(h0, -T0[i], v), h1)
        d = _tsub(_tsub(_trot(h0, -T0[i], w), _t(P[1])), _trot(h1, th, _tadd(_t(P[3]), _trot(h3, T3[i], _t(P[4])))))
        S[i, 0] = T0[i]
        S[i, 1] = T3[i]
        S[i, 2] = th
        E[i] = _tnorm(d) - n2
    return n


def _eval_sw(H, P, C, x, S, E):
    """Axes 4, 5, 6 meet, q1 = ``x``: q3 by SP3 ``‖rot(h3, q3) P3 + P2‖ = ‖v‖`` for ``v = rot(h1, −x) p0W − P1``;
    residual ``h2ᵀ v − h2ᵀ (P2 + rot(h3, q3) P3)``."""
    v = _tsub(_trot(_t(H[0]), -x, _t(C[0])), _t(P[1]))
    T = np.empty(2)
    n = _sp3(_t(P[3]), _tmul(_t(P[2]), -1.0), _t(H[2]), _tnorm(v), T)
    h1 = _t(H[1])
    hv = _tdot(h1, v) - _tdot(h1, _t(P[2]))
    for i in range(n):
        S[i, 0] = T[i]
        S[i, 1] = 0.0
        S[i, 2] = 0.0
        E[i] = hv - _tdot(h1, _trot(_t(H[2]), T[i], _t(P[3])))
    return n


def _eval_sm(H, P, C, x, S, E):
    """Axes 2, 3, 4 meet (P[2] = P[3] = 0), q6 = ``x``: q1 by SP3 ``‖rot(h1, q1) P1 − u‖ = ‖P4‖`` for
    ``u = p − P0 − R_05 P5 − R_06 P6``; residual ``(R_05 h5)ᵀ (u − rot(h1, q1) P1) − h5ᵀ P4``."""
    c0 = _tmv(C[0:3], _trot(_t(H[5]), -x, (1.0, 0.0, 0.0)))
    c1 = _tmv(C[0:3], _trot(_t(H[5]), -x, (0.0, 1.0, 0.0)))
    c2 = _tmv(C[0:3], _trot(_t(H[5]), -x, (0.0, 0.0, 1.0)))
    p5 = _t(P[5])
    h4 = _t(H[4])
    R05p5 = (c0[0] * p5[0] + c1[0] * p5[1] + c2[0] * p5[2], c0[1] * p5[0] + c1[1] * p5[1] + c2[1] * p5[2],
             c0[2] * p5[0] + c1[2] * p5[1] + c2[2] * p5[2])
    z = (c0[0] * h4[0] + c1[0] * h4[1] + c2[0] * h4[2], c0[1] * h4[0] + c1[1] * h4[1] + c2[1] * h4[2],
         c0[2] * h4[0] + c1[2] * h4[1] + c2[2] * h4[2])
    u = _tsub(_tsub(_tsub(_t(C[3]), _t(P[0])), R05p5), _tmv(C[0:3], _t(P[6])))
    T = np.empty(2)
    p1 = _t(P[1])
    n = _sp3(p1, u, _t(H[0]), _tnorm(_t(P[4])), T)
    c = _tdot(h4, _t(P[4]))
    for i in range(n):
        S[i, 0] = T[i]
        S[i, 1] = 0.0
        S[i, 2] = 0.0
        E[i] = _tdot(z, _tsub(u, _trot(_t(H[0]), T[i], p1))) - c
    return n


# ---------------------------------------------------------------------------------- the engine
def _adist(a, b):
    d = 0.0
    for k in range(3):
        d = max(d, abs(_wrap(a[k] - b[k])))
    return d


def _pick(kind, H, P, C, x, ref, S, E):
    """The branch at ``x`` nearest to ``ref (3,)``: ``(index, distance)``; index -1 if none."""
    n = _eval(kind, H, P, C, x, S, E)
    best = -1
    bd = 1e300
    for i in range(n):
        d = _adist(S[i], ref)
        if d < bd:
            bd = d
            best = i
    return best, bd


def _refine(kind, H, P, C, a, fa, ref, b, fb, out):
    """The zero between ``a`` (branch ``ref``, residual ``fa``) and ``b`` (residual ``fb`` of the same branch,
    opposite sign) by false position (Illinois), following the branch; ``(x, branch)`` into ``out (4,)``.
    False when the branch is lost."""
    S = np.empty((4, 3))
    E = np.empty(4)
    cur = ref.copy()
    x = a
    side = 0
    for it in range(100):
        x = (a * fb - b * fa) / (fb - fa)
        if not (min(a, b) < x < max(a, b)) or it % 8 == 7:
            x = 0.5 * (a + b)
        i, d = _pick(kind, H, P, C, x, cur, S, E)
        if i < 0 or d > 0.5:
            return False
        for k in range(3):
            cur[k] = S[i, k]
        fx = E[i]
        if fx == 0.0:
            break
        if (fx > 0.0) == (fa > 0.0):
            a = x
            fa = fx
            if side == 1:
                fb *= 0.5
            side = 1
        else:
            b = x
            fb = fx
            if side == -1:
                fa *= 0.5
            side = -1
        if abs(b - a) < 1e-14:
            break
    out[0] = x
    out[1] = cur[0]
    out[2] = cur[1]
    out[3] = cur[2]
    return True


def _add(roots, m, out):
    """Append ``out`` to ``roots[:m]`` unless there already (or full); returns the new count."""
    for j in range(m):
        same = True
        for k in range(4):
            if abs(_wrap(roots[j, k] - out[k])) > 1e-9:
                same = False
                break
        if same:
            return m
    if m < roots.shape[0]:
        for k in range(4):
            roots[m, k] = out[k]
        return m + 1
    return m


def _dip(kind, H, P, C, a, b, ref, sg, out):
    """The minimum of ``sg`` × the residual of the branch through ``ref`` on [a, b] by golden section, stopped
    as soon as it is below 0: ``(x, residual)``, the branch there into ``out (3,)``; ``nan`` if lost."""
    S = np.empty((4, 3))
    E = np.empty(4)
    r = 0.6180339887498949
    cur = ref.copy()
    c = b - r * (b - a)
    d = a + r * (b - a)
    i, dd = _pick(kind, H, P, C, c, cur, S, E)
    if i < 0 or dd > 0.5:
        return 0.0, np.nan
    fc = sg * E[i]
    for k in range(3):
        out[k] = S[i, k]
    if fc < 0.0:
        return c, E[i]
    i, dd = _pick(kind, H, P, C, d, cur, S, E)
    if i < 0 or dd > 0.5:
        return 0.0, np.nan
    fd = sg * E[i]
    if fd < 0.0:
        for k in range(3):
            out[k] = S[i, k]
        return d, E[i]
    x = c
    for _ in range(60):
        if fc < fd:
            b, d, fd = d, c, fc
            x = b - r * (b - a)
            c = x
        else:
            a, c, fc = c, d, fd
            x = a + r * (b - a)
            d = x
        i, dd = _pick(kind, H, P, C, x, cur, S, E)
        if i < 0 or dd > 0.5:
            return 0.0, np.nan
        f = sg * E[i]
        if x == c:
            fc = f
        else:
            fd = f
        if f < 0.0 or b - a < 1e-13:
            for k in range(3):
                out[k] = S[i, k]
            return x, E[i]
    for k in range(3):
        out[k] = S[i, k]
    return x, E[i]


def _edge(kind, H, P, C, x0, ref, x1, roots, m):
    """A branch at ``x0`` (``ref``) without a match at the neighbouring sample ``x1``: find where it ends
    (bisection), sample it towards the end quadratically spaced (the residual changes like a square root
    there) and refine the sign changes. Returns the new count of ``roots``."""
    S = np.empty((4, 3))
    E = np.empty(4)
    cur = ref.copy()
    good = x0
    bad = x1
    while abs(bad - good) > 3e-10:
        x = 0.5 * (good + bad)
        i, d = _pick(kind, H, P, C, x, cur, S, E)
        if i >= 0 and d < 0.5:
            good = x
            for k in range(3):
                cur[k] = S[i, k]
        else:
            bad = x
    # from as far again beyond x0 (where matching between samples can still confuse the two branches that
    # meet at the end) to the end
    far = x0 + (x0 - good)
    i, d = _pick(kind, H, P, C, far, ref, S, E)
    if i < 0 or d > 0.5:
        far = x0
        i, d = _pick(kind, H, P, C, x0, ref, S, E)
        if i < 0:
            return m
    xa = far
    fa = E[i]
    xl = far
    fl = fa
    prev = S[i].copy()
    pl = prev.copy()
    out = np.empty(4)
    mid = np.empty(3)
    for k in range(1, EDGE_N + 1):
        t = 1.0 - k / EDGE_N
        xb = good + (far - good) * t * t
        i, d = _pick(kind, H, P, C, xb, prev, S, E)
        if i < 0 or d > 0.5:
            break
        fb = E[i]
        if k >= 2 and (fa - fl) * (fb - fa) < 0.0 and fl * fa > 0.0 and fa * fb > 0.0 and \
                (fa > 0.0) == (fa - fl < 0.0):      # an extremum turning back towards 0: two close roots?
            sg = 1.0 if fa > 0.0 else -1.0
            xm, fx = _dip(kind, H, P, C, xl, xb, prev, sg, mid)
            if sg * fx < 0.0:
                if _refine(kind, H, P, C, xl, fl, pl, xm, fx, out):
                    m = _add(roots, m, out)
                if _refine(kind, H, P, C, xm, fx, mid, xb, fb, out):
                    m = _add(roots, m, out)
        if fa * fb < 0.0:
            if _refine(kind, H, P, C, xa, fa, prev, xb, fb, out):
                m = _add(roots, m, out)
        elif fb == 0.0:
            out[0] = xb
            out[1] = S[i, 0]
            out[2] = S[i, 1]
            out[3] = S[i, 2]
            m = _add(roots, m, out)
        xl = xa
        fl = fa
        xa = xb
        fa = fb
        for j in range(3):
            pl[j] = prev[j]
            prev[j] = S[i, j]
    return m


def _pair(kind, H, P, C, xa, Sa, Ea, ca, xb, Sb, Eb, cb, roots, m):
    """Roots between two neighbouring samples: their branches paired one to one, nearest pairs first (within
    0.5 rad), sign changes refined; a branch left without a partner ends in between (:func:`_edge`)."""
    out = np.empty(4)
    D = np.empty((4, 4))
    for j in range(ca):
        for k in range(cb):
            D[j, k] = _adist(Sa[j], Sb[k])
    pa = np.full(4, -1, dtype=np.int64)
    pb = np.full(4, -1, dtype=np.int64)
    for _ in range(min(ca, cb)):
        bj = -1
        bk = -1
        bd = 0.5
        for j in range(ca):
            if pa[j] >= 0:
                continue
            for k in range(cb):
                if pb[k] < 0 and D[j, k] < bd:
                    bd = D[j, k]
                    bj = j
                    bk = k
        if bj < 0:
            break
        pa[bj] = bk
        pb[bk] = bj
    for k in range(cb):             # branches that begin between the samples
        if pb[k] < 0:
            m = _edge(kind, H, P, C, xb, Sb[k], xa, roots, m)
    for j in range(ca):
        k = pa[j]
        if k < 0:                   # the branch ends between the samples
            m = _edge(kind, H, P, C, xa, Sa[j], xb, roots, m)
            continue
        fa = Ea[j]
        fb = Eb[k]
        if fa == 0.0:
            out[0] = xa
            out[1] = Sa[j, 0]
            out[2] = Sa[j, 1]
            out[3] = Sa[j, 2]
            m = _add(roots, m, out)
        elif fa * fb < 0.0:
            if _refine(kind, H, P, C, xa, fa, Sa[j], xb, fb, out):
                m = _add(roots, m, out)
    return m


def _ambiguous(Sa, ca, Sb, cb):
    """True unless the branches of two samples pair up clearly: each branch's nearest on the other side is
    within 0.5 rad and three times nearer than any other branch of either side; checked both ways."""
    for side in range(2):
        A = Sa if side == 0 else Sb
        B = Sb if side == 0 else Sa
        na = ca if side == 0 else cb
        nb = cb if side == 0 else ca
        for j in range(na):
            k = -1
            bd = 1e300
            sd = 1e300
            for kk in range(nb):
                d = _adist(A[j], B[kk])
                if d < bd:
                    sd = bd
                    bd = d
                    k = kk
                elif d < sd:
                    sd = d
            if k < 0 or bd >= 0.5:
                return True                 # a branch ends or begins here (or moves fast): a closer look
            if sd < 3.0 * bd:
                return True
            for jj in range(na):
                if jj != j and _adist(A[jj], B[k]) < 3.0 * bd:
                    return True
    return False


def _match(S, cnt, i, j):
    """The branch at sample i + 1 nearest to branch j at sample i (-1 if none within 0.5 rad)."""
    best = -1
    bd = 0.5
    for k in range(cnt[i + 1]):
        d = _adist(S[i, j], S[i + 1, k])
        if d < bd:
            bd = d
            best = k
    return best


def _extrema(kind, H, P, C, x0, h, S, E, cnt, i, roots, m):
    """Samples ``i``, ``i + 1``, ``i + 2`` (at ``x0 + k h``) of a branch with an extremum in the middle, on one
    side of 0 and turning back towards it: when the parabola through them comes within one second difference
    of 0, two close roots (or a double one) may hide there: :func:`_dip`, then both roots refined."""
    if i + 2 >= S.shape[0]:
        return m
    out = np.empty(4)
    mid = np.empty(3)
    xa = x0 + i * h
    for j in range(cnt[i]):
        k = _match(S, cnt, i, j)
        if k < 0:
            continue
        k2 = _match(S, cnt, i + 1, k)
        if k2 < 0:
            continue
        fa = E[i, j]
        fb = E[i + 1, k]
        fc = E[i + 2, k2]
        if not ((fb - fa) * (fc - fb) < 0.0 and fa * fb > 0.0 and fb * fc > 0.0):
            continue
        sg = 1.0 if fb > 0.0 else -1.0
        if sg * (fb - fa) > 0.0:     # an extremum away from 0
            continue
        d2 = fa - 2.0 * fb + fc
        est = fb - (fc - fa) * (fc - fa) / (8.0 * d2)
        if sg * est > abs(d2) + 1e-12:
            continue
        xm, fx = _dip(kind, H, P, C, xa, xa + 2.0 * h, S[i + 1, k], sg, mid)
        if sg * fx < 0.0:
            if _refine(kind, H, P, C, xa, fa, S[i, j], xm, fx, out):
                m = _add(roots, m, out)
            if _refine(kind, H, P, C, xm, fx, mid, xa + 2.0 * h, fc, out):
                m = _add(roots, m, out)
        elif abs(fx) <= 1e-12:
            out[0] = xm
            out[1] = mid[0]
            out[2] = mid[1]
            out[3] = mid[2]
            m = _add(roots, m, out)
    return m


def _scan(kind, H, P, C, xs, S, E, cnt):
    """The branches at every ``xs[i]`` into ``S[i]``, ``E[i]``, their counts into ``cnt[i]``."""
    for i in range(xs.shape[0]):
        cnt[i] = _eval(kind, H, P, C, xs[i], S[i], E[i])


def _search(kind, H, P, C, n, roots):
    """Every root ``(x, branch)`` of the search ``kind`` into ``roots (MAXROOT, 4)``, ``n`` samples over a turn;
    returns their count."""
    step = 2.0 * _PI / n
    S = np.zeros((n + 1, 4, 3))
    E = np.zeros((n + 1, 4))
    cnt = np.zeros(n + 1, dtype=np.int64)
    xs = np.empty(n + 1)
    for i in range(n + 1):
        xs[i] = -_PI + i * step
    _scan(kind, H, P, C, xs, S, E, cnt)
    m = 0
    Ss = np.zeros((SUB_N + 1, 4, 3))
    Es = np.zeros((SUB_N + 1, 4))
    cs = np.zeros(SUB_N + 1, dtype=np.int64)
    for i in range(n):
        xa = -_PI + i * step
        if cnt[i] == 0 and cnt[i + 1] == 0:
            continue
        if _ambiguous(S[i], cnt[i], S[i + 1], cnt[i + 1]):
            h = step / SUB_N
            for k in range(SUB_N + 1):
                if k == 0:
                    Ss[0] = S[i]
                    Es[0] = E[i]
                    cs[0] = cnt[i]
                elif k == SUB_N:
                    Ss[k] = S[i + 1]
                    Es[k] = E[i + 1]
                    cs[k] = cnt[i + 1]
                else:
                    cs[k] = _eval(kind, H, P, C, xa + k * h, Ss[k], Es[k])
            for k in range(SUB_N):
                m = _pair(kind, H, P, C, xa + k * h, Ss[k], Es[k], cs[k], xa + (k + 1) * h, Ss[k + 1], Es[k + 1],
                          cs[k + 1], roots, m)
                if k + 2 <= SUB_N:
                    m = _extrema(kind, H, P, C, xa, h, Ss, Es, cs, k, roots, m)
        else:
            m = _pair(kind, H, P, C, xa, S[i], E[i], cnt[i], xa + step, S[i + 1], E[i + 1], cnt[i + 1], roots, m)
        m = _extrema(kind, H, P, C, -_PI, step, S, E, cnt, i, roots, m)
    return m


KERNELS = ("_t", "_tdot", "_tcross", "_tadd", "_tsub", "_tmul", "_tnorm", "_trot", "_tmv", "_tmtv", "_tlin", "_tsp1",
           "_wrap", "_cubic_max", "_quad", "_quartic", "_res2", "_trig2", "_sp6", "_sp3", "_eval_ti", "_eval_tp",
           "_eval_sw", "_eval_sm", "_eval", "_adist", "_pick", "_refine", "_add", "_dip", "_edge", "_pair",
           "_ambiguous", "_match", "_extrema", "_scan", "_search")
"""The functions :func:`kernels` compiles, callees before callers."""
_KERNELS: Optional[types.SimpleNamespace] = None


def kernels() -> Optional[types.SimpleNamespace]:
    """The compiled engine (attributes named as its functions, and ``namespace``), or None without Numba."""
    global _KERNELS
    if _KERNELS is None:
        try:
            ns = _sp.jit_namespace(globals(), KERNELS)
        except ImportError:
            return None
        _KERNELS = types.SimpleNamespace(**{name: ns[name] for name in KERNELS}, namespace=ns)
    return _KERNELS


def two_parallel(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *, jit: Optional[bool] = None) -> Any:
    """Every solution of a 6R chain whose axes 2 and 3 are parallel (all revolute): :func:`.solvers.two_parallel`."""
    from . import solvers

    return solvers.two_parallel(form, R, p, q_ref, jit=jit)
