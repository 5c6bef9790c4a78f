"""The spherical-wrist solvers' cores (:mod:`.solvers`): the wrist, the 3R position, and the small 3 x 3 helpers
the other cores share.

Plain functions of scalars and small arrays; :func:`.solvers.kernels` compiles them with Numba in one
namespace with the other cores (see :mod:`.solvers` for the classes and the calling convention).
"""

from __future__ import annotations

import math

import numpy as np

from ._kernels import _atan2, _cs_from, _sincos, _t, _tcross, _tnorm, _trot_cs, _tsp1_abr
from .search import MAXROOT, SW, _search
from .subproblems import TOL as _SP_TOL
from .subproblems import _TINY as _SP_TINY
from .subproblems import NEAR_TANGENT
from .subproblems import _cross, _dot, _norm, _sp3cs, _sp3s, _sp4cs, _wrap, rot, sp1, sp5

SING = 1e-10
"""``‖h4 × R_36 h6‖`` below this: the wrist is singular (axes 4 and 6 in line)."""


# ------------------------------------------------------------------------------ small helpers
def _mv(M, v):
    out = np.empty(3)
    for i in range(3):
        out[i] = M[i, 0] * v[0] + M[i, 1] * v[1] + M[i, 2] * v[2]
    return out


def _mtv(M, v):
    out = np.empty(3)
    for i in range(3):
        out[i] = M[0, i] * v[0] + M[1, i] * v[1] + M[2, i] * v[2]
    return out


def _mm(A, B):
    C = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            C[i, j] = A[i, 0] * B[0, j] + A[i, 1] * B[1, j] + A[i, 2] * B[2, j]
    return C


def _mtm(A, B):
    """``Aᵀ B``."""
    C = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            C[i, j] = A[0, i] * B[0, j] + A[1, i] * B[1, j] + A[2, i] * B[2, j]
    return C


def _perp(h):
    """A unit vector perpendicular to the unit vector ``h``."""
    e = np.zeros(3)
    a0 = abs(h[0])
    a1 = abs(h[1])
    a2 = abs(h[2])
    if a0 <= a1 and a0 <= a2:
        e[0] = 1.0
    elif a1 <= a2:
        e[1] = 1.0
    else:
        e[2] = 1.0
    x = _cross(h, e)
    return x / _norm(x)


# the same products into buffers the caller owns (no allocation; the same arithmetic, with the sine and cosine of
# _kernels._sincos, the FK's polynomial, 1 ulp from libm's that .subproblems.rot and rotm take)
def _rotm_to(k, theta, R):
    """:func:`.subproblems.rotm` into ``R`` (3, 3)."""
    s, c = _sincos(theta)
    v = 1.0 - c
    R[0, 0] = c + k[0] * k[0] * v
    R[0, 1] = k[0] * k[1] * v - k[2] * s
    R[0, 2] = k[0] * k[2] * v + k[1] * s
    R[1, 0] = k[1] * k[0] * v + k[2] * s
    R[1, 1] = c + k[1] * k[1] * v
    R[1, 2] = k[1] * k[2] * v - k[0] * s
    R[2, 0] = k[2] * k[0] * v - k[1] * s
    R[2, 1] = k[2] * k[1] * v + k[0] * s
    R[2, 2] = c + k[2] * k[2] * v


def _rot_to(k, theta, p, out):
    """:func:`.subproblems.rot` into ``out`` (3,)."""
    s, c = _sincos(theta)
    kp = (k[0] * p[0] + k[1] * p[1] + k[2] * p[2]) * (1.0 - c)
    out[0] = p[0] * c + (k[1] * p[2] - k[2] * p[1]) * s + k[0] * kp
    out[1] = p[1] * c + (k[2] * p[0] - k[0] * p[2]) * s + k[1] * kp
    out[2] = p[2] * c + (k[0] * p[1] - k[1] * p[0]) * s + k[2] * kp


def _turn_to(k, s, c, a, oa):
    """:func:`_rot_to` of ``a`` into ``oa`` (not ``a``) by the angle whose sine and cosine are ``s``, ``c``."""
    ka = (k[0] * a[0] + k[1] * a[1] + k[2] * a[2]) * (1.0 - c)
    oa[0] = a[0] * c + (k[1] * a[2] - k[2] * a[1]) * s + k[0] * ka
    oa[1] = a[1] * c + (k[2] * a[0] - k[0] * a[2]) * s + k[1] * ka
    oa[2] = a[2] * c + (k[0] * a[1] - k[1] * a[0]) * s + k[2] * ka


def _mm_to(A, B, C):
    """:func:`_mm` into ``C`` (not ``A`` or ``B``)."""
    for i in range(3):
        for j in range(3):
            C[i, j] = A[i, 0] * B[0, j] + A[i, 1] * B[1, j] + A[i, 2] * B[2, j]


def _mtm_to(A, B, C):
    """:func:`_mtm` into ``C`` (not ``A`` or ``B``)."""
    for i in range(3):
        for j in range(3):
            C[i, j] = A[0, i] * B[0, j] + A[1, i] * B[1, j] + A[2, i] * B[2, j]


def _mv_to(M, v, out):
    """:func:`_mv` into ``out``."""
    for i in range(3):
        out[i] = M[i, 0] * v[0] + M[i, 1] * v[1] + M[i, 2] * v[2]


def _mtv_to(M, v, out):
    """:func:`_mtv` into ``out``."""
    for i in range(3):
        out[i] = M[0, i] * v[0] + M[1, i] * v[1] + M[2, i] * v[2]


def _perp_to(h, out):
    """:func:`_perp` into ``out``."""
    e0 = 0.0
    e1 = 0.0
    e2 = 0.0
    a0 = abs(h[0])
    a1 = abs(h[1])
    a2 = abs(h[2])
    if a0 <= a1 and a0 <= a2:
        e0 = 1.0
    elif a1 <= a2:
        e1 = 1.0
    else:
        e2 = 1.0
    x0 = h[1] * e2 - h[2] * e1
    x1 = h[2] * e0 - h[0] * e2
    x2 = h[0] * e1 - h[1] * e0
    n = math.sqrt(x0 * x0 + x1 * x1 + x2 * x2)
    out[0] = x0 / n
    out[1] = x1 / n
    out[2] = x2 / n



# SP1 and SP2 on scalars (no temporary arrays: the wrist and the position of the sweep call them ~10 times per
# chain); the arithmetic of :func:`.subproblems.sp1` and :func:`.subproblems.sp2`, so the same bits
def _sp1s(p0, p1, p2, q0, q1, q2, k0, k1, k2):
    """:func:`.subproblems.sp1` of ``p1 = (p0, p1, p2)``, ``p2 = (q0, q1, q2)``, ``k = (k0, k1, k2)``: ``(θ, ls)``
    (:func:`_sp1s_cs` without the cosine and sine, which the compiler then drops)."""
    theta, _, _, ls = _sp1s_cs(p0, p1, p2, q0, q1, q2, k0, k1, k2)
    return theta, ls


def _sp1s_cs(p0, p1, p2, q0, q1, q2, k0, k1, k2):
    """:func:`_sp1s` with the angle's cosine and sine from the pair ``atan2`` took (as :func:`._kernels._tsp1_cs`):
    ``(θ, cos θ, sin θ, ls)``."""
    kp1 = k0 * p0 + k1 * p1 + k2 * p2
    kp2 = k0 * q0 + k1 * q1 + k2 * q2
    x0 = k1 * p2 - k2 * p1               # k × p1
    x1 = k2 * p0 - k0 * p2
    x2 = k0 * p1 - k1 * p0
    y0 = p0 - k0 * kp1                   # p1 ⊥ k
    y1 = p1 - k1 * kp1
    y2 = p2 - k2 * kp1
    s = x0 * q0 + x1 * q1 + x2 * q2
    c = y0 * q0 + y1 * q1 + y2 * q2
    theta = _atan2(s, c)
    n1 = math.sqrt(y0 * y0 + y1 * y1 + y2 * y2)
    r0 = q0 - k0 * kp2
    r1 = q1 - k1 * kp2
    r2 = q2 - k2 * kp2
    n2 = math.sqrt(r0 * r0 + r1 * r1 + r2 * r2)
    scale = max(math.sqrt(p0 * p0 + p1 * p1 + p2 * p2), math.sqrt(q0 * q0 + q1 * q1 + q2 * q2), _SP_TINY)
    ls = abs(n1 - n2) > _SP_TOL * scale or abs(kp1 - kp2) > _SP_TOL * scale
    r = math.sqrt(s * s + c * c)
    if r > 0.0:
        return theta, c / r, s / r, ls
    return theta, 1.0, 0.0, ls


def _sp2s(a0, a1, a2, b0, b1, b2, k0, k1, k2, l0, l1, l2):
    """:func:`.subproblems.sp2` of ``p1 = (a0, a1, a2)``, ``p2 = (b0, b1, b2)``, ``k1 = (k0, k1, k2)``,
    ``k2 = (l0, l1, l2)``: ``(θ1[0], θ1[1], θ2[0], θ2[1], count, ls)`` (0.0 past ``count``)."""
    n1 = math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
    n2 = math.sqrt(b0 * b0 + b1 * b1 + b2 * b2)
    if n1 <= _SP_TINY or n2 <= _SP_TINY:
        return 0.0, 0.0, 0.0, 0.0, 1, n1 + n2 > _SP_TOL
    ls = abs(n1 - n2) > _SP_TOL * max(n1, n2)
    u0 = a0 / n1
    u1 = a1 / n1
    u2 = a2 / n1
    w0 = b0 / n2
    w1 = b1 / n2
    w2 = b2 / n2
    c = k0 * l0 + k1 * l1 + k2 * l2
    den = 1.0 - c * c
    if den < 1e-14:                      # parallel axes: a family of solutions, give θ1 = 0
        th, lb = _sp1s(w0, w1, w2, u0, u1, u2, l0, l1, l2)
        return 0.0, 0.0, th, 0.0, 1, bool(ls) or bool(lb)
    d1 = k0 * u0 + k1 * u1 + k2 * u2
    d2 = l0 * w0 + l1 * w1 + l2 * w2
    alpha = (d1 - c * d2) / den
    beta = (d2 - c * d1) / den
    x0 = k1 * l2 - k2 * l1
    x1 = k2 * l0 - k0 * l2
    x2 = k0 * l1 - k1 * l0
    v0 = alpha * k0 + beta * l0
    v1 = alpha * k1 + beta * l1
    v2 = alpha * k2 + beta * l2
    g2 = (1.0 - (v0 * v0 + v1 * v1 + v2 * v2)) / den
    if g2 > 0.0:
        g = math.sqrt(g2)
        e0 = v0 + g * x0
        e1 = v1 + g * x1
        e2 = v2 + g * x2
        s10 = _sp1s(u0, u1, u2, e0, e1, e2, k0, k1, k2)[0]
        s20 = _sp1s(w0, w1, w2, e0, e1, e2, l0, l1, l2)[0]
        ng = -g
        e0 = v0 + ng * x0
        e1 = v1 + ng * x1
        e2 = v2 + ng * x2
        s11 = _sp1s(u0, u1, u2, e0, e1, e2, k0, k1, k2)[0]
        s21 = _sp1s(w0, w1, w2, e0, e1, e2, l0, l1, l2)[0]
        return s10, s11, s20, s21, 2, bool(ls)
    # tangent (one solution, up to rounding) or none (least squares: the points of both circles nearest v0)
    s10 = _sp1s(u0, u1, u2, v0, v1, v2, k0, k1, k2)[0]
    s20 = _sp1s(w0, w1, w2, v0, v1, v2, l0, l1, l2)[0]
    return s10, 0.0, s20, 0.0, 1, bool(ls) or g2 < -1e-14


# ------------------------------------------------------------------------------------ the wrist
def _wrist(h3, h4, h5, R36, q3ref, W, S, M):
    """q4, q5, q6 (0-based 3, 4, 5) with ``rot(h4, q4) rot(h5, q5) rot(h6, q6) = R36``, into ``W (2, 3)``:
    ``(count, ls, singular)``. Its vectors and matrices live in the caller's work space ``S (5, 3)`` and
    ``M (3, 3, 3)``. :func:`_wrist_from` with ``R36 h6`` and ``R36 x`` (``x`` across axis 6) made here."""
    _mv_to(R36, h5, S[0])
    _perp_to(h5, S[1])
    _mv_to(R36, S[1], S[2])
    return _wrist_from(h3, h4, h5, q3ref, W, S, M)


def _wrist_from(h3, h4, h5, q3ref, W, S, M):
    """:func:`_wrist` from the rows of ``S (5, 3)``: ``v = R36 h6``, ``x`` a unit vector across axis 6
    (:func:`_perp_to`) and ``y = R36 x`` (rows 3 and 4: its work). Where R36 is ``R03ᵀ R06``, the spherical core
    takes ``v`` and ``y`` from ``R06 h6`` and ``R06 x`` (made once a target), turned by -q1, -q2, -q3 for each
    position, not from R03 and R36 (:func:`_core_spherical`). It makes no array, in none of its calls, so it is
    compiled without reference counts (:data:`.solvers.UNCOUNTED`)."""
    v = S[0]
    x = S[1]
    y = S[2]
    w = S[3]
    if _tnorm(_tcross(h3, v)) < SING:     # axes 4 and 6 in line: q4 free
        q3 = q3ref
        u = S[4]
        _rot_to(h3, -q3, v, u)
        q4, l1 = _sp1s(h5[0], h5[1], h5[2], u[0], u[1], u[2], h4[0], h4[1], h4[2])
        _rotm_to(h3, q3, M[0])
        _rotm_to(h4, q4, M[1])
        _mm_to(M[0], M[1], M[2])
        _mtv_to(M[2], y, w)
        q5, l2 = _sp1s(x[0], x[1], x[2], w[0], w[1], w[2], h5[0], h5[1], h5[2])
        W[0, 0] = _wrap(q3)
        W[0, 1] = q4
        W[0, 2] = q5
        return 1, bool(l1) or bool(l2), True
    # q4, q5 (0-based t3, t4) by :func:`_sp2cs` (no sine or cosine called), q6 by SP1 of x onto
    # rot(h5, -t4) rot(h4, -t3) y, turned by the cosines and sines the two angles came from: each answer carries the
    # rounding of the one before, so the three make R36 to rounding also near the singular wrist, as the SP2 form did
    # (:func:`_wrist_sp2`, which still answers where this has not two exact answers, a tangent, none, axes in line,
    # and near the tangent: a wrist near its singularity, :data:`NEAR_TANGENT`).
    # That form's four SP1s and two turns by sine and cosine a branch took 172 ns a call, this 164; the Kinova's
    # spherical core 1.37 -> 1.25 µs a target, 2026-12-07; the answers within 6e-12 of that form's.
    ok, r0, r1 = _sp2cs(v[0], v[1], v[2], h5[0], h5[1], h5[2], h3, h4)
    if not ok:
        return _wrist_sp2(h3, h4, h5, W, S)
    ls = False
    w = S[3]
    for i in range(2):
        t3, c3, s3, t4, c4, s4 = r0 if i == 0 else r1
        _turn_to(h3, -s3, c3, y, w)            # rot(h4, -t3) y
        _turn_to(h4, -s4, c4, w, S[4])         # then rot(h5, -t4)
        u = S[4]
        q5, l2 = _sp1s(x[0], x[1], x[2], u[0], u[1], u[2], h5[0], h5[1], h5[2])
        W[i, 0] = t3
        W[i, 1] = t4
        W[i, 2] = q5
        ls = ls or bool(l2)
    return 2, ls, False


def _wrist_sp2(h3, h4, h5, W, S):
    """The non-singular wrist of :func:`_wrist_from` by SP2 of ``h6`` onto ``v`` (t3, t4: :func:`_sp2s`), then SP1
    for t5: where :func:`_sp2cs` has not two exact answers (a tangent, none: its least-squares answers; axes in
    line) or is near the tangent (:data:`NEAR_TANGENT`)."""
    v = S[0]
    x = S[1]
    y = S[2]
    w = S[3]
    a0, a1, b0, b1, m, ls = _sp2s(v[0], v[1], v[2], h5[0], h5[1], h5[2], -h3[0], -h3[1], -h3[2], h4[0], h4[1], h4[2])
    u = S[4]
    for i in range(m):
        t3 = a0 if i == 0 else a1
        t4 = b0 if i == 0 else b1
        _rot_to(h3, -t3, y, u)    # w = (rot(h4, t3) rot(h5, t4))ᵀ y: the two turns undone, vector by vector
        _rot_to(h4, -t4, u, w)
        q5, l2 = _sp1s(x[0], x[1], x[2], w[0], w[1], w[2], h5[0], h5[1], h5[2])
        W[i, 0] = t3
        W[i, 1] = t4
        W[i, 2] = q5
        ls = bool(ls) or bool(l2)
    return m, ls, False


def _sp2cs(v0, v1, v2, c0, c1, c2, A, B):
    """``rot(A, a) rot(B, b) c = v`` for unit ``v``, ``c`` (SP2 in the form of :func:`.subproblems.sp2`):
    ``(True, s0, s1)``, its two solutions ``s = (a, cos a, sin a, b, cos b, sin b)`` in ``sp2``'s order, or
    ``(False, ...)`` where it has not two exact ones or is near the tangent (:data:`NEAR_TANGENT`; a tangent, none,
    ``A ∥ B`` or ``B ∥ c``): the caller then takes ``sp2`` itself, whose least-squares answers stay as they were.

    ``b`` first, from the one equation it meets alone, ``Aᵀ rot(B, b) c = Aᵀ v`` (``rot(A, a)`` keeps A):
    ``α cos b + β sin b = e``, its cosine and sine in closed form; then ``a`` by SP1 of ``rot(B, b) c`` onto
    ``v``, turned by that cosine and sine. No sine or cosine called (``sp2``: four SP1s, and the callers' turns a
    sine and cosine each). Compiled inline into its callers (:data:`.solvers.INLINE`)."""
    al, be, e, r2, disc = _sp2cs_disc(v0, v1, v2, c0, c1, c2, A, B)
    if not (r2 >= 1e-20 and disc > NEAR_TANGENT * r2):
        z = (0.0, 1.0, 0.0, 0.0, 1.0, 0.0)
        return False, z, z
    sq = math.sqrt(disc)
    return True, _sp2cs_one(v0, v1, v2, c0, c1, c2, A, B, al, be, e, r2, sq), \
        _sp2cs_one(v0, v1, v2, c0, c1, c2, A, B, al, be, e, r2, -sq)


def _sp2cs_disc(v0, v1, v2, c0, c1, c2, A, B):
    """:func:`_sp2cs`'s equation for ``b``, ``α cos b + β sin b = e``: ``(α, β, e, α² + β², α² + β² -
    e²)``."""
    bc0 = B[1] * c2 - B[2] * c1          # B × c
    bc1 = B[2] * c0 - B[0] * c2
    bc2 = B[0] * c1 - B[1] * c0
    ab = A[0] * B[0] + A[1] * B[1] + A[2] * B[2]
    gam = ab * (B[0] * c0 + B[1] * c1 + B[2] * c2)
    al = A[0] * c0 + A[1] * c1 + A[2] * c2 - gam
    be = A[0] * bc0 + A[1] * bc1 + A[2] * bc2
    r2 = al * al + be * be
    e = A[0] * v0 + A[1] * v1 + A[2] * v2 - gam
    return al, be, e, r2, r2 - e * e


def _sp2cs_one(v0, v1, v2, c0, c1, c2, A, B, al, be, e, r2, sg):
    """One solution of :func:`_sp2cs` (``sg``: ± the root of its discriminant)."""
    ta, xa, ya, ra, tb, cb, sb = _sp2cs_abr(v0, v1, v2, c0, c1, c2, A, B, al, be, e, r2, sg)
    ta, ca, sa = _cs_from(ta, xa, ya, ra)
    return ta, ca, sa, tb, cb, sb


def _sp2cs_abr(v0, v1, v2, c0, c1, c2, A, B, al, be, e, r2, sg):
    """:func:`_sp2cs_one` before ``a``'s cosine and sine: ``(a, x, y, r, b, cos b, sin b)`` with ``a = atan2(y, x)``,
    ``r = |(x, y)|`` (:func:`._kernels._tsp1_abr`). No function called but the inline ``atan2``."""
    cb = (al * e - be * sg) / r2
    sb = (be * e + al * sg) / r2
    u = _trot_cs(B, cb, sb, (c0, c1, c2))        # rot(B, b) c
    ta, xa, ya, ra = _tsp1_abr(u, (v0, v1, v2), A)
    return ta, xa, ya, ra, _atan2(sb, cb), cb, sb


WRIST_LANES = 4
"""Positions whose wrists :func:`_wrist_lanes` solves side by side (a closed-form 3R position has at most 4)."""


def _wrist_lanes(H, a, b, x, L):
    """The wrists of the first :data:`WRIST_LANES` positions side by side, by :func:`_wrist_from`'s common case:
    ``a = R_06 h6`` and ``b = R_06 x`` turned by -q1, -q2, -q3, then :func:`_sp2cs` and the SP1 for q6.
    ``L (14, WRIST_LANES)``, position ``i`` in column ``i``. Rows 8-13 are the caller's: the cosine and sine of q1,
    then of q2, then of q3. Rows 0-7 are the answers: row 0 whether that case holds (1.0; 0.0: the wrist is
    singular, or ``_sp2cs`` has not two exact answers, or an SP1 pair has no length; the caller then takes
    :func:`_wrist_from` for that position), row 1 whether an SP1 is least squares, rows 2-4 and 5-7 the two
    solutions' q4, q5, q6.

    The operations of :func:`_core_spherical`'s turns and of :func:`_wrist_from`, in the same order (the same
    bits), with no function called but the inline ``atan2`` and square roots: the loop over the positions compiles
    to vector instructions, four positions an instruction (for a revolute joint 3; the caller turns by two joints
    where it is prismatic). Its caller is compiled with NumPy's error model (a division by zero gives infinity, as
    in C, not an exception): a division that may raise is a branch out of the loop, and such a loop stays scalar."""
    # the axes and vectors as tuples of numbers, not rows of arrays: values the compiler knows that no store to L
    # changes (else it must test at run time that L overlaps none of them, and that is too many tests for it)
    h0, h1, h2, h3, h4, h5 = _t(H[0]), _t(H[1]), _t(H[2]), _t(H[3]), _t(H[4]), _t(H[5])
    a, b, x = _t(a), _t(b), _t(x)
    # (L.shape[1], not the constant WRIST_LANES: a loop the compiler knows to be that short it leaves scalar, where
    # it would have to test at run time that its stores do not overlap its loads. Each row's lanes are next to each
    # other, as the vector loads take them: read from Cp[i, k], three apart, the vector loop would never run)
    for i in range(L.shape[1]):
        c, s = L[8, i], -L[9, i]
        ua = _trot_cs(h0, c, s, a)
        ub = _trot_cs(h0, c, s, b)
        c, s = L[10, i], -L[11, i]
        ua = _trot_cs(h1, c, s, ua)
        ub = _trot_cs(h1, c, s, ub)
        c, s = L[12, i], -L[13, i]
        v = _trot_cs(h2, c, s, ua)
        y = _trot_cs(h2, c, s, ub)
        free = _tnorm(_tcross(h3, v)) < SING     # as _wrist_from
        al, be, e, r2, disc = _sp2cs_disc(v[0], v[1], v[2], h5[0], h5[1], h5[2], h3, h4)
        good = (not free) & (r2 >= 1e-20) & (disc > NEAR_TANGENT * r2)
        # (a lane that is not taken divides by 1 and takes the root of 0: the same flags, no error raised)
        sq = math.sqrt(disc if good else 0.0)
        d = r2 if good else 1.0
        t3, t4, t5, g0, l0 = _wrist_half(v, x, y, h3, h4, h5, al, be, e, d, sq)
        u3, u4, u5, g1, l1 = _wrist_half(v, x, y, h3, h4, h5, al, be, e, d, -sq)
        good = good & g0 & g1
        L[0, i] = 1.0 if good else 0.0
        L[1, i] = 1.0 if l0 | l1 else 0.0
        L[2, i] = t3
        L[3, i] = t4
        L[4, i] = t5
        L[5, i] = u3
        L[6, i] = u4
        L[7, i] = u5


def _wrist_half(v, x, y, h3, h4, h5, al, be, e, r2, sg):
    """One of the two wrist solutions of :func:`_wrist_lanes` (``sg``: ± the discriminant's root): ``(q4, q5, q6,
    its SP1 pair has a length, q6's SP1 is least squares)``, as :func:`_wrist_from` makes them."""
    t3, x3, y3, r3, t4, c4, s4 = _sp2cs_abr(v[0], v[1], v[2], h5[0], h5[1], h5[2], h3, h4, al, be, e, r2, sg)
    d = r3 if r3 > 0.0 else 1.0
    w = _trot_cs(h3, x3 / d, -(y3 / d), y)       # rot(h4, -t3) y
    u = _trot_cs(h4, c4, -s4, w)                 # then rot(h5, -t4)
    t5, ls = _sp1s(x[0], x[1], x[2], u[0], u[1], u[2], h5[0], h5[1], h5[2])
    return t3, t4, t5, r3 > 0.0, ls


# ------------------------------------------------------------------ spherical wrist: position
def _put_position(Qp, Cp, Sp, LSp, m, q1, c1, s1, q2, c2, s2, q3, c3, s3, ls):
    """Row ``m`` of a 3R position's solutions: the angles into ``Qp``, their cosines and sines into ``Cp``, ``Sp``,
    the least-squares flag into ``LSp`` (compiled inline into the positions, :data:`.solvers.INLINE`)."""
    Qp[m, 0] = q1
    Qp[m, 1] = q2
    Qp[m, 2] = q3
    Cp[m, 0] = c1
    Sp[m, 0] = s1
    Cp[m, 1] = c2
    Sp[m, 1] = s2
    Cp[m, 2] = c3
    Sp[m, 2] = s3
    LSp[m] = ls


def _pos_two_intersecting(H, P, prism2, p0W, Qp, LSp, V, Cp, Sp):
    """Axes 1, 2 meet (P[1] = 0): ``p0W = rot(h1, q1) rot(h2, q2) (P2 + rot(h3, q3) P3)``
    (joint 3 prismatic: ``P2 + q3 h3 + P3``). ``V (3, 3)``: work rows (-P2, rot(h3, q3) P3, the point ``w``).
    ``Cp``, ``Sp`` (8, 3): the cosines and sines of each solution's angles, for the spherical core's turns (q1, q2
    from :func:`_sp2cs`'s algebra; q3's from the one sine and cosine its own turn takes). Makes no array (SP3 as
    scalars, :func:`.subproblems._sp3s`): compiled without reference counts."""
    h0 = H[0]
    h1 = H[1]
    h2 = H[2]
    d = _norm(p0W)
    mP2, r3, w = V[0], V[1], V[2]
    if prism2:
        a0, a1, a2 = P[2, 0] + P[3, 0], P[2, 1] + P[3, 1], P[2, 2] + P[3, 2]
        b = h2[0] * a0 + h2[1] * a1 + h2[2] * a2
        aa = a0 * a0 + a1 * a1 + a2 * a2
        c = aa - d * d
        disc = b * b - c
        scale = max(aa + d * d, 1e-300)
        t21 = 0.0
        if disc > 1e-12 * scale:
            s = math.sqrt(disc)
            t20 = -b + s
            t21 = -b - s
            n2 = 2
        else:
            t20 = -b
            n2 = 1
        ls2 = disc < -1e-12 * scale
    else:
        for i in range(3):
            mP2[i] = -P[2, i]
        t20, t21, n2, ls2 = _sp3s(P[3], mP2, h2, d)
    m = 0
    for j in range(n2):
        t2j = t20 if j == 0 else t21
        s3 = 0.0
        c3 = 1.0
        if prism2:
            for i in range(3):
                w[i] = P[2, i] + t2j * h2[i] + P[3, i]
        else:
            s3, c3 = _sincos(t2j)
            _turn_to(h2, s3, c3, P[3], r3)
            for i in range(3):
                w[i] = P[2, i] + r3[i]
        # (q1, q2) by SP2 of w onto p0W: _sp2cs where it has two exact answers and the lengths agree, else sp2's
        # scalar form (its least-squares answers as they were), the cosines and sines then by _sincos
        n1 = d
        nw = _norm(w)
        ok = n1 > _SP_TINY and nw > _SP_TINY and not abs(n1 - nw) > _SP_TOL * max(n1, nw)
        if ok:
            ok, r0, r1 = _sp2cs(p0W[0] / n1, p0W[1] / n1, p0W[2] / n1, w[0] / nw, w[1] / nw, w[2] / nw, h0, h1)
        if ok:
            for i in range(2):
                a, ca, sa, b, cb, sb = r0 if i == 0 else r1
                _put_position(Qp, Cp, Sp, LSp, m, a, ca, sa, b, cb, sb, t2j, c3, s3, bool(ls2))
                m += 1
            continue
        a0, a1, b0, b1, n, ls = _sp2s(p0W[0], p0W[1], p0W[2], w[0], w[1], w[2], -h0[0], -h0[1], -h0[2],
                                      h1[0], h1[1], h1[2])
        for i in range(n):
            a = a0 if i == 0 else a1
            b = b0 if i == 0 else b1
            sa, ca = _sincos(a)
            sb, cb = _sincos(b)
            _put_position(Qp, Cp, Sp, LSp, m, a, ca, sa, b, cb, sb, t2j, c3, s3, bool(ls) or bool(ls2))
            m += 1
    return m


def _pos_two_parallel(H, P, p0W, Qp, LSp, V, Cp, Sp):
    """Axes 2 ∥ 3: the axis-2 component of ``rot(h1, q1)ᵀ p0W`` fixes q1 (SP4), then SP3, SP1. ``V (5, 3)``: work
    rows (-h1, -P2, the point ``v``, ``rot(h3, q3) P3``, the point ``w``). ``Cp``, ``Sp`` (8, 3): each solution's
    cosines and sines, which the subproblems give with the angles (:func:`.subproblems._sp4cs`, ``_sp3cs``,
    :func:`_sp1s_cs`) and the turns here and in the spherical core take (before 2026-12-07: libm's sine and cosine
    for the turns here, the FK's for the core's). Makes no array: compiled without reference counts."""
    h0 = H[0]
    h1 = H[1]
    h2 = H[2]
    mh0, mP2, v, r3, w = V[0], V[1], V[2], V[3], V[4]
    for k in range(3):
        mh0[k] = -h0[k]
        mP2[k] = -P[2, k]
    d1 = h1[0] * ((P[1, 0] + P[2, 0]) + P[3, 0]) + h1[1] * ((P[1, 1] + P[2, 1]) + P[3, 1]) \
        + h1[2] * ((P[1, 2] + P[2, 2]) + P[3, 2])                      # _dot(h1, P[1] + P[2] + P[3])
    n0, ls0, r00, r01 = _sp4cs(h1, p0W, mh0, d1)
    m = 0
    for i in range(n0):
        t0, c0, s0 = r00 if i == 0 else r01
        _turn_to(h0, -s0, c0, p0W, v)       # rot(h1, -q1) p0W
        for k in range(3):
            v[k] = v[k] - P[1, k]
        n2, ls2, r20, r21 = _sp3cs(P[3], mP2, h2, _norm(v))
        for j in range(n2):
            t2, c2, s2 = r20 if j == 0 else r21
            _turn_to(h2, s2, c2, P[3], r3)
            for k in range(3):
                w[k] = P[2, k] + r3[k]
            t1, c1, s1, ls1 = _sp1s_cs(w[0], w[1], w[2], v[0], v[1], v[2], h1[0], h1[1], h1[2])
            _put_position(Qp, Cp, Sp, LSp, m, t0, c0, s0, t1, c1, s1, t2, c2, s2, bool(ls0) or bool(ls2) or bool(ls1))
            m += 1
    return m


def _pos_general(H, P, p0W, N, Qp, LSp, V):
    """General 3R position ``p0W = rot(h1, q1) (P1 + rot(h2, q2) (P2 + rot(h3, q3) P3))`` in closed form:
    moved to ``-P1 + rot(h1, -q1) p0W = rot(h2, q2) (P2 + rot(h3, q3) P3)``, which is SP5 (a quartic; up to
    4 solutions, least-squares ones flagged). SP5's length equation depends on q1 only through the distance of
    the point chosen on axis 2 from axis 1, so that point is slid along axis 2 (``P1 + s h2``, ``P2 - s h2``: the
    same chain) until that distance is about the arm's size; where axes 1 and 2 meet it would be 0 and the
    system singular. Axes 2 ∥ 3 make its component equation independent of q3: :func:`_pos_two_parallel`
    answers (``V (5, 3)``: its work rows). Axes 1 ∥ 2 make it independent of q1: that chain takes the 1-D search
    (:func:`_pos_search`)."""
    h0 = H[0]
    h1 = H[1]
    if _norm(_cross(h1, H[2])) < 1e-9:   # (the cosines and sines: rows this caller does not read)
        return _pos_two_parallel(H, P, p0W, Qp, LSp, V, np.empty((8, 3)), np.empty((8, 3)))
    if _norm(_cross(h0, h1)) < 1e-9:
        return _pos_search(H, P, p0W, N, Qp, LSp)
    size = _norm(P[1]) + _norm(P[2]) + _norm(P[3]) + _norm(p0W) + 1e-300
    h1p = h1 - _dot(h1, h0) * h0                        # axis 2's direction away from axis 1
    v = P[1] - _dot(P[1], h0) * h0                      # the axis-2 point's offset from axis 1
    sign = 1.0 if _dot(v, h1p) >= 0.0 else -1.0
    s = sign * size / _norm(h1p)
    t1, t2, t3, count, ls = sp5(-(P[1] + s * h1), p0W, P[2] - s * h1, P[3], h0, h1, H[2])
    for i in range(count):
        Qp[i, 0] = _wrap(-t1[i])
        Qp[i, 1] = t2[i]
        Qp[i, 2] = t3[i]
        LSp[i] = bool(ls)
    return count


def _pos_search(H, P, p0W, N, Qp, LSp):
    """General 3R position by the 1-D search over q1 of :mod:`.search` (kind SW: q3 by SP3, the residual along
    axis 2), then q2 by SP1 (the chains with axes 1 ∥ 2, where SP5 does not apply)."""
    C = np.zeros((4, 3))
    for k in range(3):
        C[0, k] = p0W[k]
    roots = np.zeros((MAXROOT, 4))
    nroot = _search(SW, H, P, C, N, roots)
    m = 0
    for r in range(nroot):
        q0 = roots[r, 0]
        q2 = roots[r, 1]
        v = rot(H[0], -q0, p0W) - P[1]
        w = P[2] + rot(H[2], q2, P[3])
        q1, ls1 = sp1(w, v, H[1])
        q0w = _wrap(q0)
        dup = False
        for j in range(m):
            if abs(_wrap(Qp[j, 0] - q0w)) < 1e-9 and abs(_wrap(Qp[j, 2] - q2)) < 1e-9:
                dup = True
        if dup or m >= Qp.shape[0]:
            continue
        Qp[m, 0] = q0w
        Qp[m, 1] = q1
        Qp[m, 2] = q2
        LSp[m] = False
        m += 1
    return m


def _core_spherical(kind, H, P, RnT, prism, R, p, qref, N, Q, LS, SG, v3, m3, LSp, L):
    """Spherical wrist at the end (P[4] = P[5] = 0): candidates into Q, LS, SG; returns their count.
    ``kind``: 0 axes 1, 2 meet; 1 axes 2 ∥ 3; 2 general (SP5).

    Its work arrays come from the caller (:func:`.solvers_check._core_in`, which zeroes them), zeros:
    ``v3 (41, 3)`` for the small vectors (rows of a 2-D or 3-D array, not reshaped slices of one vector, whose
    reshape is a call of its own: the position solutions Qp (8, 3), the wrist's W (2, 3) and its work S (5, 3), p_0W
    (3), the 3R position's work rows V (5, 3), R_06 h6 and R_06 x and their turns (4, 3), the cosines and sines of
    the positions' angles Cp, Sp (8, 3)), ``m3 (4, 3, 3)`` for the
    matrices (the wrist's work M (3, 3, 3), R_06 (3, 3)), ``LSp (8,)`` the positions' least-squares flags, ``L (14, 4)``
    the wrists side by side (:func:`_wrist_lanes`; written before they are read, not zeroes). It makes
    no array itself (the general position's SP5 makes its own, in a function of its own), so it is compiled without
    reference counts: every row it takes of these arrays, ~40 a target, was counted up and down with an atomic
    instruction."""
    Qp, W, S, p0W, V = v3[0:8], v3[8:10], v3[10:15], v3[15], v3[16:21]
    a, b, ta, tb = v3[21], v3[22], v3[23], v3[24]
    Cp, Sp = v3[25:33], v3[33:41]
    M, R06 = m3[0:3], m3[3]
    for i in range(3):   # R_06 = R RnTᵀ and p_0W = p - P_0 - R_06 P_6, term by term as _mm and _mv
        for j in range(3):
            R06[i, j] = R[i, 0] * RnT[j, 0] + R[i, 1] * RnT[j, 1] + R[i, 2] * RnT[j, 2]
    for i in range(3):
        p0W[i] = p[i] - P[0, i] - (R06[i, 0] * P[6, 0] + R06[i, 1] * P[6, 1] + R06[i, 2] * P[6, 2])
    # the wrist's v = R36 h6 and y = R36 x (R36 = R03ᵀ R06): R03ᵀ applied to R06 h6 and R06 x for each position,
    # a turn by -q1, then -q2, then -q3 (two vectors, one sine and cosine a joint, where R03 and R36 took three 3 x 3
    # products)
    _perp_to(H[5], S[1])
    _mv_to(R06, H[5], a)
    _mv_to(R06, S[1], b)
    if kind == 0:   # (the cosines and sines of the angles come with them)
        mp = _pos_two_intersecting(H, P, prism[2], p0W, Qp, LSp, V, Cp, Sp)
    elif kind == 1:
        mp = _pos_two_parallel(H, P, p0W, Qp, LSp, V, Cp, Sp)
    else:
        mp = _pos_general(H, P, p0W, N, Qp, LSp, V)
        for i in range(mp):
            for k in range(3):
                Sp[i, k], Cp[i, k] = _sincos(Qp[i, k])
    # the wrists of the first four positions side by side, each taken where _wrist_from's common case holds (the
    # same bits). The core a target, 2026-12-07: the Kinova's URDF 0.89 -> 0.52 µs, the rounded Puma's 0.94 -> 0.52,
    # random arms with axes 2 ∥ 3 0.97 -> 0.59 (four wrists one by one took 0.67 µs, side by side 0.18)
    lanes = not prism[2] and mp > 0
    if lanes:
        for i in range(WRIST_LANES):     # (rows past mp: zeroes, _core_in's)
            for k in range(3):
                L[8 + 2 * k, i] = Cp[i, k]
                L[9 + 2 * k, i] = Sp[i, k]
        _wrist_lanes(H, a, b, S[1], L)
    m = 0
    for i in range(mp):
        if lanes and i < WRIST_LANES and L[0, i] != 0.0:
            mw, lsw, sing = 2, L[1, i] != 0.0, False
            for j in range(2):
                W[j, 0] = L[2 + 3 * j, i]
                W[j, 1] = L[3 + 3 * j, i]
                W[j, 2] = L[4 + 3 * j, i]
        else:
            # R03ᵀ = rot(h3, -q3) rot(h2, -q2) rot(h1, -q1), each turn of the two vectors by the angle's cosine
            # and sine
            _turn_to(H[0], -Sp[i, 0], Cp[i, 0], a, ta)
            _turn_to(H[0], -Sp[i, 0], Cp[i, 0], b, tb)
            if prism[2]:
                _turn_to(H[1], -Sp[i, 1], Cp[i, 1], ta, S[0])
                _turn_to(H[1], -Sp[i, 1], Cp[i, 1], tb, S[2])
            else:
                _turn_to(H[1], -Sp[i, 1], Cp[i, 1], ta, S[3])
                _turn_to(H[1], -Sp[i, 1], Cp[i, 1], tb, S[4])
                _turn_to(H[2], -Sp[i, 2], Cp[i, 2], S[3], S[0])
                _turn_to(H[2], -Sp[i, 2], Cp[i, 2], S[4], S[2])
            mw, lsw, sing = _wrist_from(H[3], H[4], H[5], qref[3], W, S, M)
        for j in range(mw):
            if m >= Q.shape[0]:
                break
            Q[m, 0] = Qp[i, 0]
            Q[m, 1] = Qp[i, 1]
            Q[m, 2] = Qp[i, 2]
            Q[m, 3] = W[j, 0]
            Q[m, 4] = W[j, 1]
            Q[m, 5] = W[j, 2]
            LS[m] = LSp[i] or lsw
            SG[m] = sing
            m += 1
    return m
