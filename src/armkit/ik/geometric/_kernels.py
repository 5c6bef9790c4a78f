"""Compiled scalar helpers shared by the searches and solvers of :mod:`armkit.ik.geometric` (one copy each).

* 3-vectors as tuples (no allocation): dot, cross, Rodrigues rotation, ``hᵀ rot(k, θ) p`` as
  ``a cos θ + b sin θ + c``, SP1.
* The closed-form quartic (Ferrari, roots polished by Newton steps), the 2 x 2 trigonometric system
  ``A (cos θ1, sin θ1) + B (cos θ2, sin θ2) = e`` built on it (exact solutions), and SP3 / SP6 on scalars:
  what the 1-D searches (:mod:`.search`) evaluate at every sample and the 2-D search (:mod:`.search2d`) at
  every grid point.
* The forward kinematics of a product-of-exponentials chain and its pose error (the FK check of
  :mod:`.solvers`, and the Newton steps of :mod:`.search2d`).

The plain functions run as Python; :func:`kernels` compiles them with Numba (``cache=True``), and the
modules that call them compile their own functions against these (Numba inlines the calls).
"""

from __future__ import annotations

import cmath
import math
import types
from typing import Any, Optional

import numpy as np
from ... import _jit_loader

__all__ = ["kernels", "KERNELS"]

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


def _sincos(x):
    """``(sin x, cos x)`` by the FK's polynomial (:func:`armkit.kinematics._jit._sincos`, ~40 % faster than libm's
    ``sin`` and ``cos``). The compiled helpers call that kernel itself (:func:`extra`); in plain Python this runs its
    Python function, the same bits."""
    from ...kinematics._jit import _sincos as compiled_sincos

    return compiled_sincos.py_func(x)


def _sincos_block(x, s, c):
    """:func:`armkit.kinematics._jit.sincos_block`: ``s``, ``c`` the sines and cosines of the flat ``x`` (by
    :func:`_sincos`'s polynomial, in one vector loop); returns how many were not finite. The compiled helpers call
    that kernel itself (:func:`extra`); in plain Python this runs its Python function, the same bits."""
    from ...kinematics._jit import sincos_block

    return sincos_block.py_func(x, s, c)


def _atan2(y, x):
    """``atan2(y, x)`` by armkit's polynomial (:func:`armkit.kinematics._jit._atan2`, ~2.6x faster than libm's, within
    1.5 ulp). The compiled helpers call that kernel itself (:func:`extra`); in plain Python this runs its Python
    function, the same bits."""
    from ...kinematics._jit import _atan2 as compiled_atan2

    return compiled_atan2.py_func(y, x)


def _trot(k, th, p):
    """``rot(k, th) p`` (Rodrigues)."""
    s, c = _sincos(th)
    return _trot_cs(k, c, s, p)


def _trot_cs(k, c, s, p):
    """``rot(k, θ) p`` from ``c = cos θ``, ``s = sin θ`` (:func:`_trot` when both are known)."""
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


def _tsp1_cs(p1, p2, k):
    """θ with ``rot(k, θ) p1`` nearest ``p2`` (SP1), and its cosine and sine: ``(θ, cos θ, sin θ)``, the two from
    the same pair that gives θ (no ``sin``/``cos`` calls; they differ from ``cos(θ)``, ``sin(θ)`` by rounding
    only)."""
    th, a, b, r = _tsp1_abr(p1, p2, k)
    return _cs_from(th, a, b, r)


def _cs_from(th, a, b, r):
    """``(θ, cos θ, sin θ)`` of ``θ = atan2(b, a)`` and ``r = |(a, b)|``: the pair divided by its length, or where
    that is 0, the cosine and sine of θ."""
    if r > 0.0:
        return th, a / r, b / r
    return th, math.cos(th), math.sin(th)


def _tsp1_abr(p1, p2, k):
    """:func:`_tsp1_cs` before its division: ``(θ, a, b, r)`` with ``θ = atan2(b, a)``, ``r = |(a, b)|`` (where
    ``r > 0``, ``cos θ = a / r``, ``sin θ = b / r``). It calls no function but armkit's inline ``atan2``, so loops
    of it over lanes compile to vector instructions (:func:`.solvers_wrist._wrist_lanes`)."""
    kp1 = _tdot(k, p1)
    y = (p1[0] - k[0] * kp1, p1[1] - k[1] * kp1, p1[2] - k[2] * kp1)
    b = _tdot(_tcross(k, p1), p2)
    a = _tdot(y, p2)
    return _atan2(b, a), a, b, math.sqrt(a * a + b * b)


def _wrap(x):
    if -_PI < x <= _PI:
        return x
    y = x - 2.0 * _PI * math.floor((x + _PI) / (2.0 * _PI))
    if y <= -_PI:
        y += 2.0 * _PI
    return y


# -------------------------------------------------------------------------------- the quartic
def _cubic_max(a2, a1, a0):
    """The largest real root of ``z³ + a2 z² + a1 z + a0`` (trigonometric or Cardano form, then Newton steps
    that are small and each decrease the cubic's size: a double largest root is kept as the closed form gives it)."""
    p = a1 - a2 * a2 / 3.0
    q = 2.0 * a2 * a2 * a2 / 27.0 - a2 * a1 / 3.0 + a0
    disc = 0.25 * q * q + p * p * p / 27.0
    if disc > 1e-12 * 0.25 * q * q:       # Cardano: ∛u + ∛v with ∛u ∛v = −p / 3 (u the larger, one cube root);
        # below that, a double root where rounding made disc > 0: Cardano would give the simple root, the
        # trigonometric form (its argument clamped to ±1) the double one too
        u = -0.5 * q - math.copysign(math.sqrt(disc), q)
        cu = math.copysign(abs(u) ** (1.0 / 3.0), u)
        w = cu - p / (3.0 * cu)
        wp = -0.5 * w                     # the real part of the complex pair (the three sum to 0)
        if wp > w and abs((wp * wp + p) * wp + q) <= 1e-13 * (abs(a2) ** 3 + abs(a2 * a1) + abs(a0)):
            w = wp                        # a pair real up to the rounding of p, q (a double root above w)
    elif p < 0.0:
        m = math.sqrt(-p / 3.0)
        arg = -0.5 * q / (m * m * m)
        arg = min(1.0, max(-1.0, arg))
        w = 2.0 * m * math.cos(math.acos(arg) / 3.0)
    else:
        w = 0.0
    z = w - a2 / 3.0
    f = ((z + a2) * z + a1) * z + a0
    for _ in range(3):                    # Newton, a step kept only when it is small and decreases |f|: at a
        if f == 0.0:                      # double root f and f' are both rounding, and their ratio would throw
            break                         # z far away (onto another root, even)
        d = (3.0 * z + 2.0 * a2) * z + a1
        if d == 0.0:
            break
        dz = f / d
        if abs(dz) > 1e-4 * (1.0 + abs(z)):
            break
        zn = z - dz
        fn = ((zn + a2) * zn + a1) * zn + a0
        if abs(fn) >= abs(f):
            break
        z = zn
        f = fn
        if abs(dz) <= 1e-16 * (1.0 + abs(z)):
            break
    return z


def _quartic(c4, c3, c2, c1, c0, re, im):
    """The 4 complex roots of ``c4 t⁴ + c3 t³ + c2 t² + c1 t + c0`` (``c4`` the largest coefficient in size or
    near it) into ``re``, ``im`` (:func:`_quartic4`)."""
    r0, i0, r1, i1, r2, i2, r3, i3 = _quartic4(c4, c3, c2, c1, c0)
    re[0] = r0
    im[0] = i0
    re[1] = r1
    im[1] = i1
    re[2] = r2
    im[2] = i2
    re[3] = r3
    im[3] = i3


def _quartic4(c4, c3, c2, c1, c0):
    """The 4 complex roots of ``c4 t⁴ + c3 t³ + c2 t² + c1 t + c0`` (``c4`` the largest coefficient in size or
    near it) as ``(re0, im0, …, re3, im3)``: Ferrari's factorisation into two quadratics, each root polished by
    Newton steps on the quartic (in real arithmetic for the real roots; a complex root only when it is nearly
    real, the others are of no use to the callers)."""
    ic4 = 1.0 / c4
    b = c3 * ic4
    c = c2 * ic4
    d = c1 * ic4
    e = c0 * ic4
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
        qu = q / u
        r0, i0, r1, i1 = _quad(u, 0.5 * (p + z0 - qu))
        r2, i2, r3, i3 = _quad(-u, 0.5 * (p + z0 + qu))
        # each quadratic gives two reals or a conjugate pair: polish one of a pair, conjugate it for the other
        r0, j0 = _polish(r0 - s, i0, b, c, d, e)
        if i0 != 0.0:
            r1, i1 = r0, -j0
        else:
            r1, i1 = _polish(r1 - s, i1, b, c, d, e)
        r2, j2 = _polish(r2 - s, i2, b, c, d, e)
        if i2 != 0.0:
            r3, i3 = r2, -j2
        else:
            r3, i3 = _polish(r3 - s, i3, b, c, d, e)
        return r0, j0, r1, i1, r2, j2, r3, i3
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
        r0, i0, r1, i1 = ya.real, ya.imag, -ya.real, -ya.imag
        r2, i2, r3, i3 = yb.real, yb.imag, -yb.real, -yb.imag
    r0, i0 = _polish(r0 - s, i0, b, c, d, e)
    r1, i1 = _polish(r1 - s, i1, b, c, d, e)
    r2, i2 = _polish(r2 - s, i2, b, c, d, e)
    r3, i3 = _polish(r3 - s, i3, b, c, d, e)
    return r0, i0, r1, i1, r2, i2, r3, i3


def _newton4(t, b, c, d, e):
    """Up to 3 Newton steps on ``t⁴ + b t³ + c t² + d t + e`` from ``t`` (a float or a complex: compiled for
    each), stopped when one does not decrease ``|f|`` (or would leave for ``|t| > 1e60``, where ``f`` overflows: the
    roots of the callers' quartics lie within a few units), when ``f(t)`` is 0, or after a step below
    ``1e-15 (1 + |t|)`` (the next would change ``t`` by rounding only)."""
    f = (((t + b) * t + c) * t + d) * t + e
    for _ in range(3):
        if f == 0.0:
            break
        df = ((4.0 * t + 3.0 * b) * t + 2.0 * c) * t + d
        if df == 0.0:
            break
        dt = f / df
        tn = t - dt
        if not abs(tn) <= 1e60:   # a step off to where the quartic overflows (df nearly 0) cannot decrease |f|
            break
        fn = (((tn + b) * tn + c) * tn + d) * tn + e
        if abs(fn) >= abs(f):
            break
        t = tn
        f = fn
        if abs(dt) <= 1e-15 * (1.0 + abs(t)):
            break
    return t


def _polish(tr, ti, b, c, d, e):
    """:func:`_newton4` from ``tr + i ti``: in real arithmetic for a real start, complex for a nearly real one
    (``|ti| ≤ 1e-2 (1 + |t|)``); a root farther from the real axis is returned as it is."""
    if ti == 0.0:
        return _newton4(tr, b, c, d, e), 0.0
    if abs(ti) > 1e-2 * (1.0 + abs(tr)):
        return tr, ti
    z = _newton4(complex(tr, ti), b, c, d, e)
    return z.real, z.imag


def _quad(u, v):
    """The roots of ``y² + u y + v`` as ``(re, im, re, im)``."""
    disc = u * u - 4.0 * v
    if disc >= 0.0:
        sq = math.sqrt(disc)
        y1 = -0.5 * (u + math.copysign(sq, u))
        y2 = v / y1 if y1 != 0.0 else 0.0
        return y1, 0.0, y2, 0.0
    sq = math.sqrt(-disc)
    return -0.5 * u, 0.5 * sq, -0.5 * u, -0.5 * sq



def _res2(a00, a01, a10, a11, b00, b01, b10, b11, e0, e1, t1, t2):
    c1 = math.cos(t1)
    s1 = math.sin(t1)
    c2 = math.cos(t2)
    s2 = math.sin(t2)
    return a00 * c1 + a01 * s1 + b00 * c2 + b01 * s2 - e0, a10 * c1 + a11 * s1 + b10 * c2 + b11 * s2 - e1


def _angle(c, s):
    """``atan2(s, c)`` for a unit ``(c, s)``, in ``[−π, π]`` as ``atan2`` (−π when ``s`` rounds it there: :func:`_wrap`
    after). (By the half-angle tangent and one ``atan`` while libm's ``atan`` was cheaper than its ``atan2``; armkit's
    own :func:`_atan2` is cheaper than either.)"""
    return _atan2(s, c)


def _trig2(a00, a01, a10, a11, b00, b01, b10, b11, e0, e1, T1, T2):
    """θ1, θ2 with ``A (cos θ1, sin θ1) + B (cos θ2, sin θ2) = e`` (rows of equal scale) into ``T1``, ``T2``;
    returns their count (0 when no exact solution). As :func:`.subproblems._trig2` (eliminate the better
    conditioned unknown, a quartic in the other), the quartic in closed form and shifted so that its root at
    infinity is far from every solution. :func:`_trig2m` with its margin dropped."""
    return _trig2m(a00, a01, a10, a11, b00, b01, b10, b11, e0, e1, T1, T2, None)[0]


def _trig2m(a00, a01, a10, a11, b00, b01, b10, b11, e0, e1, T1, T2, CS):
    """:func:`_trig2`, returning ``(count, margin)``: the margin is how near the quartic's nearest complex root
    is to being real, as an angle, ``2 |Im t| / (1 + |t|²)`` for ``t = tan(φ / 2)``, over the roots that give no
    solution of their own (complex, failing the check, or a repeat of one found: a pair about to turn complex);
    ``inf`` when every root gives one. Two more solutions appear where it reaches 0 (a pair of complex roots
    turning real): the 1-D search looks for pairs of branches born and dying between two of its samples where it
    dips (``search._islands``). ``CS``: None, or rows ``(≥ 4, 4)`` that get each solution's
    ``(cos θ1, sin θ1, cos θ2, sin θ2)`` (equal to the cosines and sines of ``T1``, ``T2`` up to rounding; the 1-D
    searches rotate by them next, without calling ``cos`` and ``sin`` again)."""
    na2 = a00 * a00 + a01 * a01 + a10 * a10 + a11 * a11
    nb2 = b00 * b00 + b01 * b01 + b10 * b10 + b11 * b11
    scale = max(math.sqrt(max(na2, nb2, e0 * e0 + e1 * e1)), 1e-300)
    tol12 = 1e-12 * scale                 # residuals compared in squares (no square roots per root)
    tol12 *= tol12
    tol14 = 1e-14 * scale
    tol14 *= tol14
    tol9 = 1e-9 * scale
    tol9 *= tol9
    da = abs(a00 * a11 - a01 * a10) / max(na2, 1e-300)
    db = abs(b00 * b11 - b01 * b10) / max(nb2, 1e-300)
    swap = db > da
    if swap:
        x00, x01, x10, x11, y00, y01, y10, y11 = b00, b01, b10, b11, a00, a01, a10, a11
    else:
        x00, x01, x10, x11, y00, y01, y10, y11 = a00, a01, a10, a11, b00, b01, b10, b11
    det = x00 * x11 - x01 * x10
    if abs(det) <= 1e-14 * max(na2, nb2):
        return 0, np.inf
    idet = 1.0 / det
    i00 = x11 * idet
    i01 = -x01 * idet
    i10 = -x10 * idet
    i11 = x00 * idet
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
    # (cos 2α, sin 2α) for α = k π / 4 is (1, 0), (0, 1), (−1, 0), (0, −1), repeated: the 8 values unrolled
    ra = _R2 * (a1 + b1)
    rb = _R2 * (b1 - a1)
    gv = (abs(a0 - a1 + a2), abs(a0 - ra + b2), abs(a0 - b1 - a2), abs(a0 - rb - b2),
          abs(a0 + a1 + a2), abs(a0 + ra + b2), abs(a0 + b1 - a2), abs(a0 + rb - b2))
    best = -1.0
    kb = 0
    for k in range(8):
        if gv[k] > best:
            best = gv[k]
            kb = k
    if best <= 1e-300:
        return 0, np.inf
    ca = _C8[kb]
    sa = _S8[kb]
    c2a = _C8[(2 * kb) % 8]
    s2a = _S8[(2 * kb) % 8]
    A1 = a1 * ca + b1 * sa
    B1 = b1 * ca - a1 * sa
    A2 = a2 * c2a + b2 * s2a
    B2 = b2 * c2a - a2 * s2a
    roots = _quartic4(a0 - A1 + A2, 2.0 * B1 - 4.0 * B2, 2.0 * a0 - 6.0 * A2, 2.0 * B1 + 4.0 * B2, a0 + A1 + A2)
    count = 0
    margin = np.inf
    for i in range(4):
        t = roots[2 * i]
        ti = roots[2 * i + 1]
        if abs(ti) > 1e-5 * (1.0 + math.sqrt(t * t + ti * ti)):
            margin = min(margin, 2.0 * abs(ti) / (1.0 + t * t + ti * ti))
            continue
        w = 1.0 / (1.0 + t * t)
        cf = (1.0 - t * t) * w
        sf = 2.0 * t * w
        cy = cf * ca - sf * sa
        sy = sf * ca + cf * sa
        x0 = f0 - (m00 * cy + m01 * sy)
        x1 = f1 - (m10 * cy + m11 * sy)
        nx2 = x0 * x0 + x1 * x1
        if nx2 <= 0.0:
            continue
        inx = 1.0 / math.sqrt(nx2)
        cx = x0 * inx
        sx = x1 * inx
        if swap:
            c1, s1, c2, s2 = cy, sy, cx, sx
        else:
            c1, s1, c2, s2 = cx, sx, cy, sy
        r0 = a00 * c1 + a01 * s1 + b00 * c2 + b01 * s2 - e0
        r1 = a10 * c1 + a11 * s1 + b10 * c2 + b11 * s2 - e1
        # the angles: the quartic's unknown is tan((θ − α) / 2), the other one from its unit (cos, sin)
        ty = 2.0 * _atan2(t, 1.0) + 0.25 * _PI * kb   # atan(t)
        if ty > _PI:
            ty -= 2.0 * _PI
        tx = _angle(cx, sx)
        if swap:
            t1, t2 = ty, tx
        else:
            t1, t2 = tx, ty
        for _ in range(6 if r0 * r0 + r1 * r1 > tol12 else 0):   # Newton on the 2 x 2 system
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
            if abs(d1) + abs(d2) < 1e-15 or r0 * r0 + r1 * r1 <= tol14:
                break
        if r0 * r0 + r1 * r1 > tol9:
            margin = min(margin, 2.0 * abs(ti) / (1.0 + t * t + ti * ti))
            continue
        t1 = _wrap(t1)                    # atan2 is already in (−π, π]: the fast path unless Newton moved it
        t2 = _wrap(t2)
        dup = False
        for j in range(count):            # both in (−π, π]: a difference within 1e-7 of 0 or of ±2π
            d1 = abs(T1[j] - t1)
            d2 = abs(T2[j] - t2)
            if (d1 < 1e-7 or d1 > 2.0 * _PI - 1e-7) and (d2 < 1e-7 or d2 > 2.0 * _PI - 1e-7):
                dup = True
        if not dup:
            T1[count] = t1
            T2[count] = t2
            if CS is not None:            # their cosines and sines, for callers that rotate by them next
                CS[count, 0] = c1
                CS[count, 1] = s1
                CS[count, 2] = c2
                CS[count, 3] = s2
            count += 1
        else:      # a pair that has nearly met (a double root): as near to turning complex as its roots are apart
            margin = min(margin, 2.0 * abs(ti) / (1.0 + t * t + ti * ti))
    return count, margin


def _sp6(h0, k0, p0, h1, k1, p1, h2, k2, p2, h3, k3, p3, d1, d2, T1, T2, CS):
    """SP6 (as :func:`.subproblems.sp6`, exact solutions only) on scalar vectors: the solutions into ``T1``, ``T2``
    (their cosines and sines into ``CS`` unless it is None); returns ``(count, margin)`` (:func:`_trig2m`)."""
    a00, a01, c0 = _tlin(h0, k0, p0)
    b00, b01, c1 = _tlin(h1, k1, p1)
    a10, a11, c2 = _tlin(h2, k2, p2)
    b10, b11, c3 = _tlin(h3, k3, p3)
    return _trig2_rows(a00, a01, b00, b01, d1 - c0 - c1, a10, a11, b10, b11, d2 - c2 - c3, T1, T2, CS)


def _trig2_rows(a00, a01, b00, b01, e0, a10, a11, b10, b11, e1, T1, T2, CS):
    """:func:`_trig2m` on the rows ``a0· (cos θ1, sin θ1) + b0· (cos θ2, sin θ2) = e0`` (and row 1) scaled to unit
    size first, so that its tolerances mean the same in both equations: ``(count, margin)`` (``CS`` as there)."""
    s = math.sqrt(a00 * a00 + a01 * a01 + b00 * b00 + b01 * b01)
    if s > 0.0:
        s = 1.0 / s
        a00 *= s
        a01 *= s
        b00 *= s
        b01 *= s
        e0 *= s
    s = math.sqrt(a10 * a10 + a11 * a11 + b10 * b10 + b11 * b11)
    if s > 0.0:
        s = 1.0 / s
        a10 *= s
        a11 *= s
        b10 *= s
        b11 *= s
        e1 *= s
    return _trig2m(a00, a01, a10, a11, b00, b01, b10, b11, e0, e1, T1, T2, CS)


def _add_row(rows, m, x, tol):
    """Append ``x`` to ``rows[:m]`` unless a row within ``tol`` of it in every column (angles wrapped) is there
    (or ``rows`` is full); returns the new count. The 1-D searches' roots and the 2-D search's solutions."""
    for j in range(m):
        same = True
        for k in range(x.shape[0]):
            if abs(_wrap(rows[j, k] - x[k])) > tol:
                same = False
                break
        if same:
            return m
    if m < rows.shape[0]:
        for k in range(x.shape[0]):
            rows[m, k] = x[k]
        return m + 1
    return m


def _sp3_cos(p1, p2, k, d):
    """SP3 ``‖rot(k, θ) p1 − p2‖ = d`` as ``cos(θ − atan2(b, a)) = x``: ``(x, a, b)``; ``x`` is inf when the
    equation does not depend on θ (degenerate). Solutions exist where ``|x| <= 1`` (:func:`_sp3`; the 1-D
    searches watch ``1 − |x|`` where there are none, :func:`.search._islands`)."""
    a, b, c = _tlin(p2, k, p1)
    rhs = 0.5 * (_tdot(p1, p1) + _tdot(p2, p2) - d * d) - c
    r = math.sqrt(a * a + b * b)
    if r <= 1e-14 * (_tdot(p1, p1) + _tdot(p2, p2) + d * d):
        return math.inf, a, b
    return rhs / r, a, b


def _sp3(p1, p2, k, d, T):
    """θ with ``‖rot(k, θ) p1 − p2‖ = d`` into ``T``: the count (0 when none; a double root counts twice)."""
    x, a, b = _sp3_cos(p1, p2, k, d)
    if abs(x) > 1.0:
        return 0
    phi = _atan2(b, a)
    w = math.acos(x)
    T[0] = _wrap(phi + w)
    T[1] = _wrap(phi - w)
    return 2




# ------------------------------------------------------------------------- forward kinematics
def _rot_entries(h0, h1, h2, q):
    """The nine entries of ``rot(h, q)`` (Rodrigues), row by row."""
    s, c = _sincos(q)
    return _rot_entries_sc(h0, h1, h2, s, c)


def _rot_entries_sc(h0, h1, h2, s, c):
    """:func:`_rot_entries` of the angle whose sine and cosine are ``s``, ``c``."""
    v = 1.0 - c
    return (c + h0 * h0 * v, h0 * h1 * v - h2 * s, h0 * h2 * v + h1 * s,
            h1 * h0 * v + h2 * s, c + h1 * h1 * v, h1 * h2 * v - h0 * s,
            h2 * h0 * v - h1 * s, h2 * h1 * v + h0 * s, c + h2 * h2 * v)


def _rmul_rot(R, T, h0, h1, h2, q):
    """``R ← R rot(h, q)`` in place (``T (3, 3)``: work space)."""
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = _rot_entries(h0, h1, h2, q)
    for i in range(3):
        a0 = R[i, 0]
        a1 = R[i, 1]
        a2 = R[i, 2]
        T[i, 0] = a0 * r00 + a1 * r10 + a2 * r20
        T[i, 1] = a0 * r01 + a1 * r11 + a2 * r21
        T[i, 2] = a0 * r02 + a1 * r12 + a2 * r22
    for i in range(3):
        for j in range(3):
            R[i, j] = T[i, j]


def _move(R, P, k, p0, p1, p2):
    """``p + R P[k]`` for ``p = (p0, p1, p2)`` (one link of the forward kinematics)."""
    x = P[k, 0]
    y = P[k, 1]
    z = P[k, 2]
    return (p0 + (R[0, 0] * x + R[0, 1] * y + R[0, 2] * z), p1 + (R[1, 0] * x + R[1, 1] * y + R[1, 2] * z),
            p2 + (R[2, 0] * x + R[2, 1] * y + R[2, 2] * z))


def _fk_err_from(H, P, RnT, prism, q, Rt, pt, RS, PS, s, SC):
    """``(position error, rotation error)`` of ``q`` for the target ``(Rt, pt)`` on the chain ``(H, P, RnT)`` (the
    formula of :meth:`.poe.POE.fk`, without temporary arrays; the rotation error ``‖ΔR‖_F / √2``).

    The rotation and position after each joint are left in ``RS (n + 1, 3, 3)``, ``PS (n + 1, 3)``, and the chain
    is taken up after joint ``s`` from what the previous call left there (``s = 0``: from the base): a caller
    checking candidates that share their first joints (the branches of a closed form come in pairs that differ
    only in the wrist) skips those joints' work. Each joint's operations are the same whatever ``s``: the same
    bits. ``SC (2, n)``: work space for the sines and cosines of ``q``'s joints from ``s`` on (:func:`_sincos`),
    which :func:`_fk_err_sc` then takes."""
    for k in range(s, H.shape[0]):
        SC[0, k], SC[1, k] = _sincos(q[k])
    return _fk_err_sc(H, P, RnT, prism, q, SC[0], SC[1], Rt, pt, RS, PS, s)


def _fk_err_sc(H, P, RnT, prism, q, S, C, Rt, pt, RS, PS, s):
    """:func:`_fk_err_from` with the sines ``S`` and cosines ``C`` (n,) of ``q``'s revolute joints given (from
    ``s`` on; the prismatic joints' entries are not read): the same operations, so the same bits where they are
    :func:`_sincos`'s. A caller checking many candidates takes them in one vector loop
    (:func:`armkit.kinematics._jit.sincos_block`, the same polynomial)."""
    n = H.shape[0]
    # the rotation in nine scalars and the position in three, stored after each joint for the next call; the
    # operations of _rmul_rot (its _rot_entries) and _move, in their order (the same bits), without reading back
    # what was stored
    if s == 0:
        a00, a01, a02, a10, a11, a12, a20, a21, a22 = 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0
        p0, p1, p2 = P[0, 0], P[0, 1], P[0, 2]
        for i in range(3):
            for j in range(3):
                RS[0, i, j] = 1.0 if i == j else 0.0
            PS[0, i] = P[0, i]
    else:
        a00, a01, a02 = RS[s, 0, 0], RS[s, 0, 1], RS[s, 0, 2]
        a10, a11, a12 = RS[s, 1, 0], RS[s, 1, 1], RS[s, 1, 2]
        a20, a21, a22 = RS[s, 2, 0], RS[s, 2, 1], RS[s, 2, 2]
        p0, p1, p2 = PS[s, 0], PS[s, 1], PS[s, 2]
    for k in range(s, n):
        h0 = H[k, 0]
        h1 = H[k, 1]
        h2 = H[k, 2]
        if prism[k]:
            p0 += q[k] * (a00 * h0 + a01 * h1 + a02 * h2)
            p1 += q[k] * (a10 * h0 + a11 * h1 + a12 * h2)
            p2 += q[k] * (a20 * h0 + a21 * h1 + a22 * h2)
        else:
            r00, r01, r02, r10, r11, r12, r20, r21, r22 = _rot_entries_sc(h0, h1, h2, S[k], C[k])
            a00, a01, a02 = (a00 * r00 + a01 * r10 + a02 * r20, a00 * r01 + a01 * r11 + a02 * r21,
                             a00 * r02 + a01 * r12 + a02 * r22)
            a10, a11, a12 = (a10 * r00 + a11 * r10 + a12 * r20, a10 * r01 + a11 * r11 + a12 * r21,
                             a10 * r02 + a11 * r12 + a12 * r22)
            a20, a21, a22 = (a20 * r00 + a21 * r10 + a22 * r20, a20 * r01 + a21 * r11 + a22 * r21,
                             a20 * r02 + a21 * r12 + a22 * r22)
        x = P[k + 1, 0]
        y = P[k + 1, 1]
        z = P[k + 1, 2]
        p0, p1, p2 = (p0 + (a00 * x + a01 * y + a02 * z), p1 + (a10 * x + a11 * y + a12 * z),
                      p2 + (a20 * x + a21 * y + a22 * z))
        RS[k + 1, 0, 0], RS[k + 1, 0, 1], RS[k + 1, 0, 2] = a00, a01, a02
        RS[k + 1, 1, 0], RS[k + 1, 1, 1], RS[k + 1, 1, 2] = a10, a11, a12
        RS[k + 1, 2, 0], RS[k + 1, 2, 1], RS[k + 1, 2, 2] = a20, a21, a22
        PS[k + 1, 0] = p0
        PS[k + 1, 1] = p1
        PS[k + 1, 2] = p2
    dp = math.sqrt((p0 - pt[0]) ** 2 + (p1 - pt[1]) ** 2 + (p2 - pt[2]) ** 2)
    e = 0.0
    for j in range(3):     # row 0 of R RnT against the target's, then rows 1 and 2 (the order of the sum)
        e += (a00 * RnT[0, j] + a01 * RnT[1, j] + a02 * RnT[2, j] - Rt[0, j]) ** 2
    for j in range(3):
        e += (a10 * RnT[0, j] + a11 * RnT[1, j] + a12 * RnT[2, j] - Rt[1, j]) ** 2
    for j in range(3):
        e += (a20 * RnT[0, j] + a21 * RnT[1, j] + a22 * RnT[2, j] - Rt[2, j]) ** 2
    return dp, math.sqrt(0.5 * e)


# ---------------------------------------------------------------------------------- compiled
KERNELS = ("_t", "_tdot", "_tcross", "_tadd", "_tsub", "_tmul", "_tnorm", "_trot_cs", "_trot", "_tmv", "_tmtv",
           "_tlin", "_tsp1_abr", "_cs_from", "_tsp1_cs", "_wrap", "_cubic_max", "_quad", "_newton4", "_polish",
           "_quartic4", "_quartic",
           "_res2", "_angle", "_trig2m", "_trig2", "_trig2_rows", "_sp6", "_add_row", "_sp3_cos", "_sp3",
           "_rot_entries_sc", "_rot_entries", "_rmul_rot", "_move", "_fk_err_sc", "_fk_err_from")
"""The functions :func:`kernels` compiles, callees before callers."""
_KERNELS: Optional[types.SimpleNamespace] = None


def kernels() -> Optional[types.SimpleNamespace]:
    """The compiled helpers (attributes named as the functions, and ``namespace``: the dict to pass as ``extra``
    to :func:`.subproblems.jit_namespace` by a module that calls them), or None without Numba."""
    global _KERNELS
    if _KERNELS is None:
        from .subproblems import compiled

        # none allocates or returns an array: all compiled without reference counts
        _KERNELS = compiled(globals(), KERNELS, extra=_compiled_sincos(), uncounted=KERNELS)
        if _KERNELS is not None:
            # they inline the FK's sine and cosine and armkit's atan2: compiled anew when kinematics/_jit.py changes
            _jit_loader.forget_stale_cache(_KERNELS.namespace, ("kinematics/_jit.py",))
    return _KERNELS


def _compiled_sincos() -> dict[str, Any]:
    """``{"_sincos": ..., "_atan2": ..., "_sincos_block": ...}``, the compiled kernels, for the compiled namespaces
    ({} without Numba: compiled() says so)."""
    try:
        from ...kinematics._jit import _atan2 as compiled_atan2
        from ...kinematics._jit import _sincos as compiled_sincos
        from ...kinematics._jit import sincos_block
    except ImportError:
        return {}
    return {"_sincos": compiled_sincos, "_atan2": compiled_atan2, "_sincos_block": sincos_block}


def extra() -> dict[str, Any]:
    """``{name: compiled function}`` of :data:`KERNELS` (for ``jit_namespace(..., extra=...)``); raises
    ImportError without Numba."""
    k = kernels()
    if k is None:
        raise ImportError("numba")
    return {name: k.namespace[name] for name in KERNELS + ("_sincos", "_atan2", "_sincos_block")}
