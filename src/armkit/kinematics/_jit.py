"""Numba kernels over the uniform chain: the fast path for single calls and big batches.

How they are fast (numbers in ``docs/performance.md``):

* A pose is twelve scalar locals (the 3x4 affine part, row-major); a joint costs one
  in-place rotation (or translation) of two columns and one affine product with the
  constant ``fixed[k]`` of the chain, all in registers. Nothing is allocated per joint.
* Batches run in blocks of :data:`BLOCK` configurations. For each block the sines and
  cosines of all its joint values are computed first in one straight, branch-free loop
  that LLVM turns into SIMD code (:func:`_sincos_poly`: Cody-Waite reduction by pi/2 and
  Taylor polynomials of degree 17/18 on [-pi/4, pi/4] evaluated by Estrin's scheme; error below 2 ulp, checked against
  ``numpy.sin``/``numpy.cos`` in the tests). Values that are too big for the short
  reduction (:data:`_SINCOS_MAX`) or not finite fall back to ``math.sin``/``math.cos``
  and are counted, so the caller can reject NaN/inf without a separate pass.
* Blocks are spread over threads with ``prange`` from :data:`PARALLEL_MIN` configurations
  on; below that one thread does it (starting threads costs more than it saves).
* The single-configuration entry points write into an output array allocated by the
  caller (a NumPy allocation is cheaper than a Numba-boxed one) and raise ``ValueError``
  for a wrong length or a non-finite value; :mod:`armkit.kinematics` catches it and lets
  :meth:`Robot.check_q` produce the real message. Each is compiled for one signature on
  first use (module ``__getattr__``), after which any other argument type fails at once
  with ``TypeError`` instead of compiling anew. ``armkit.fk`` and ``armkit.jacobian`` call
  the compiled function itself (``fk_one_entry``, ``jacobian_one_entry``), skipping the
  dispatcher's typing of every argument (a third of their single-call time), once their own
  checks have made sure of the types.

No ``fastmath``: results agree with the NumPy back end to about 1e-15.
Compiled functions are cached on disk (``cache=True``). Importing this module compiles
nothing (it costs Numba's import, ~0.2 s); each kernel compiles, or loads from the cache,
on its first call. On a fresh install a background process compiles them all while the
NumPy kernels answer (:mod:`armkit._jit_loader`, docs/performance.md "First use").
"""

from __future__ import annotations

import math
import threading

import numpy as np

from .. import _jit_loader

_jit_loader.install_cache_fallback()  # before the first cache=True: read-only installs cache elsewhere

from numba import njit, prange, types  # noqa: E402

from .._jit_shaped import shaped  # noqa: E402
from .._jit_twins import parallel_twin  # noqa: E402

BLOCK = 128
"""Configurations per block of the batched kernels (sin/cos scratch: 2 x BLOCK x n doubles)."""

PARALLEL_MIN = 256
"""Batches from this size on use all threads. Measured on the project's 2-core machine (puma560, 2026-12-06, also
with a busy loop on the other core): 128 configurations take 10-11 µs on one thread and 11 on two, 256 take 17
and 11, 2,048 take 115 and 60 (FK; the Jacobian alike). docs/performance.md."""



ROW = 13
"""Length of one row of the packed chain constants: a constant affine transform and a joint flag."""
AFFINE = slice(0, 12)
"""``row[AFFINE]``: the 3x4 affine part of a constant transform, row by row (the bottom row of a
rigid transform, (0, 0, 0, 1), is implied)."""
PRISMATIC = 12
"""``row[PRISMATIC]``: 1.0 where the joint that moves *before* this row's transform is prismatic, else 0.0."""


def pack(fixed, prismatic, base, pre, post, tool):
    """The chain's constants in the two packed layouts the kernels take: ``(F, P)``, float64, read-only.

    Every row holds one constant transform (``row[AFFINE]``, 12 values) and the joint flag
    ``row[PRISMATIC]``:

    * ``F`` (n + 1, ROW): row 0 is ``fixed[0]``; row ``k + 1`` is ``fixed[k + 1]``, applied after joint
      ``k``'s motion, with joint ``k``'s flag (what plain FK and the Jacobian need);
    * ``P`` (2n + 2, ROW): ``base, pre_1..pre_n, post_1..post_n, tool``; row ``1 + k`` (``pre`` of joint
      ``k``) carries joint ``k``'s flag (what all frames and the LM solver need).

    Parameters
    ----------
    fixed : ndarray, shape (n + 1, 4, 4)
    prismatic : ndarray of bool, shape (n,)
    base, tool : ndarray, shape (4, 4)
    pre, post : ndarray, shape (n, 4, 4)
    """
    n = prismatic.shape[0]
    flags = np.asarray(prismatic, dtype=np.float64)
    F = np.zeros((n + 1, ROW))
    F[:, AFFINE] = np.asarray(fixed, dtype=np.float64)[:, :3, :].reshape(n + 1, 12)
    F[1:, PRISMATIC] = flags
    mats = np.concatenate([base[None], pre, post, tool[None]]).astype(np.float64)
    P = np.zeros((2 * n + 2, ROW))
    P[:, AFFINE] = mats[:, :3, :].reshape(2 * n + 2, 12)
    P[1:n + 1, PRISMATIC] = flags
    F.setflags(write=False)
    P.setflags(write=False)
    return F, P


# --------------------------------------------------------------------------- sin/cos
# pi/2 split so that n * _PIO2_HI is exact for |n| < 2**20: _PIO2_HI keeps the first 33 bits.
_PIO2_HI = 1.5707963267341256
_PIO2_LO = 6.077100506506192e-11
_TWO_OVER_PI = 0.6366197723675814
_SINCOS_MAX = 1.0e5  # |x| up to here: the two-part reduction is exact to ~1e-20 absolute

# Taylor coefficients (-1)^k / (2k+1)! and (-1)^k / (2k)!
_S3, _S5, _S7, _S9 = -1.0 / 6.0, 1.0 / 120.0, -1.0 / 5040.0, 1.0 / 362880.0
_S11, _S13, _S15, _S17 = -1.0 / 39916800.0, 1.0 / 6227020800.0, -1.0 / 1307674368000.0, 1.0 / 355687428096000.0
_C4, _C6, _C8, _C10 = 1.0 / 24.0, -1.0 / 720.0, 1.0 / 40320.0, -1.0 / 3628800.0
_C12, _C14, _C16, _C18 = 1.0 / 479001600.0, -1.0 / 87178291200.0, 1.0 / 20922789888000.0, -1.0 / 6402373705728000.0


@njit(cache=True, inline="always")
def _sincos_poly(x):
    """(sin x, cos x) for |x| <= _SINCOS_MAX, branch-free so that loops over it vectorise."""
    k = np.floor(x * _TWO_OVER_PI + 0.5)   # a float (math.floor's integer costs two conversions), the same value
    r = (x - k * _PIO2_HI) - k * _PIO2_LO
    z = r * r
    z2 = z * z
    z4 = z2 * z2
    # Estrin's scheme: half the dependent steps of Horner's (single calls are latency-bound)
    ps = (_S3 + z * _S5) + z2 * (_S7 + z * _S9) + z4 * ((_S11 + z * _S13) + z2 * (_S15 + z * _S17))
    pc = (_C4 + z * _C6) + z2 * (_C8 + z * _C10) + z4 * ((_C12 + z * _C14) + z2 * (_C16 + z * _C18))
    s = r + r * z * ps
    c = (1.0 - 0.5 * z) + z2 * pc
    m = k - 4.0 * np.floor(k * 0.25)  # quadrant 0..3
    odd = (m == 1.0) | (m == 3.0)
    sa = c if odd else s
    ca = s if odd else c
    sin_x = -sa if m >= 2.0 else sa
    cos_x = -ca if (m == 1.0) | (m == 2.0) else ca
    return sin_x, cos_x


@njit(cache=True, inline="always")
def _sincos(x):
    if abs(x) <= _SINCOS_MAX:
        return _sincos_poly(x)
    return math.sin(x), math.cos(x)


# --------------------------------------------------------------------------- atan2
# atan(u) = u + u z P(z), z = u², |u| <= tan(pi/8): P's coefficients a0..a10 (z^0 first) are the Chebyshev fit of
# degree 10 to (atan(√z) - √z) / z^(3/2) on [0, tan²(pi/8)] (mpmath.chebyfit at 50 digits, rounded to doubles;
# tests/kinematics/test_atan2.py fits them again and checks them); its error there is 5e-18 relative to atan(u)
_A0, _A1, _A2, _A3 = -0.3333333333333333, 0.1999999999999552, -0.14285714284666542, 0.11111111015256361
_A4, _A5, _A6, _A7 = -0.09090904578123903, 0.07692183190826087, -0.06664511447381948, 0.0585814891280221
_A8, _A9, _A10 = -0.0508544973794026, 0.03923165829558719, -0.01917688711906226
_TAN_PI8 = 0.41421356237309503
# pi/4, pi/2, pi as a double and the rest (the sum of the two is the constant to ~1e-33)
_PI4_HI, _PI4_LO = 0.7853981633974483, 3.061616997868383e-17
_PI2_HI, _PI2_LO = 1.5707963267948966, 6.123233995736766e-17
_PI_HI, _PI_LO = 3.141592653589793, 1.2246467991473532e-16


@njit(cache=True, inline="always")
def _atan2(y, x):
    """``atan2(y, x)`` within 1.5 ulp (libm's: within 0.5; 2,000,000 random pairs differ from it by at most 2 ulp
    and are equal in 81 %), ~2.6x faster than libm's in a loop of independent calls (9 against 23 ns; where each
    result feeds the next step, as in the Kinova's kernel, the two take about as long).
    The quotient of the smaller by the larger of ``|x|``, ``|y|`` (one division), above tan(pi/8) taken as
    ``pi/4 + atan(u)`` with ``u = (t - 1) / (t + 1)`` (the same one division), then the polynomial above, placed in
    its octant. The signs as libm's: odd in ``y`` to the bit (zeros' signs too), ``atan2(±0, -0.0) = ±pi``,
    ``atan2(±0, +0.0) = ±0``. For finite arguments (the kernels' are); not finite: not libm's answer."""
    ax = abs(x)
    ay = abs(y)
    swap = ay > ax
    num = ax if swap else ay
    den = ay if swap else ax
    half = num > _TAN_PI8 * den
    u = (num - den) / (num + den) if half else (num / den if den != 0.0 else 0.0)
    z = u * u
    z2 = z * z
    z4 = z2 * z2
    # Estrin's scheme, as _sincos_poly
    p = (_A0 + _A1 * z) + z2 * (_A2 + _A3 * z) + z4 * ((_A4 + _A5 * z) + z2 * (_A6 + _A7 * z)) \
        + (z4 * z4) * ((_A8 + _A9 * z) + z2 * _A10)
    a = (_PI4_HI + (u + (u * z * p + _PI4_LO))) if half else u + u * z * p
    if swap:
        a = _PI2_HI - (a - _PI2_LO)
    if math.copysign(1.0, x) < 0.0:
        a = _PI_HI - (a - _PI_LO)
    return math.copysign(a, y)


@njit(cache=True)
def sincos_block(x, s, c):
    """Fill ``s``, ``c`` with sin/cos of the flat array ``x``; return how many were not finite."""
    bad = 0
    for j in range(x.shape[0]):
        sj, cj = _sincos_poly(x[j])
        s[j] = sj
        c[j] = cj
        if not abs(x[j]) <= _SINCOS_MAX:
            bad += 1
    if bad:
        bad = 0
        for j in range(x.shape[0]):
            if not math.isfinite(x[j]):
                bad += 1
            elif abs(x[j]) > _SINCOS_MAX:
                s[j] = math.sin(x[j])
                c[j] = math.cos(x[j])
    return bad


# ------------------------------------------------------------------ 12-scalar poses
@njit(cache=True, inline="always")
def _load(F, k):
    """Row ``k`` of packed constants (see :func:`pack`) as a 12-scalar pose."""
    return (F[k, 0], F[k, 1], F[k, 2], F[k, 3], F[k, 4], F[k, 5], F[k, 6], F[k, 7],
            F[k, 8], F[k, 9], F[k, 10], F[k, 11])


@njit(cache=True, inline="always")
def _mul(X, F, k):
    """X · F[k] for a 12-scalar pose X and row ``k`` of packed constants (see :func:`pack`)."""
    a00, a01, a02, a03, a10, a11, a12, a13, a20, a21, a22, a23 = X
    f00, f01, f02, f03 = F[k, 0], F[k, 1], F[k, 2], F[k, 3]
    f10, f11, f12, f13 = F[k, 4], F[k, 5], F[k, 6], F[k, 7]
    f20, f21, f22, f23 = F[k, 8], F[k, 9], F[k, 10], F[k, 11]
    return (a00 * f00 + a01 * f10 + a02 * f20,
            a00 * f01 + a01 * f11 + a02 * f21,
            a00 * f02 + a01 * f12 + a02 * f22,
            a00 * f03 + a01 * f13 + a02 * f23 + a03,
            a10 * f00 + a11 * f10 + a12 * f20,
            a10 * f01 + a11 * f11 + a12 * f21,
            a10 * f02 + a11 * f12 + a12 * f22,
            a10 * f03 + a11 * f13 + a12 * f23 + a13,
            a20 * f00 + a21 * f10 + a22 * f20,
            a20 * f01 + a21 * f11 + a22 * f21,
            a20 * f02 + a21 * f12 + a22 * f22,
            a20 * f03 + a21 * f13 + a22 * f23 + a23)


@njit(cache=True, inline="always")
def _move(X, t, s, c, prismatic):
    """X · Rz(t) (given s = sin t, c = cos t) or X · Tz(t)."""
    a00, a01, a02, a03, a10, a11, a12, a13, a20, a21, a22, a23 = X
    if prismatic:
        return (a00, a01, a02, a03 + t * a02, a10, a11, a12, a13 + t * a12, a20, a21, a22, a23 + t * a22)
    return (c * a00 + s * a01, c * a01 - s * a00, a02, a03,
            c * a10 + s * a11, c * a11 - s * a10, a12, a13,
            c * a20 + s * a21, c * a21 - s * a20, a22, a23)


@njit(cache=True, inline="always")
def _store(X, out, i):
    out[i, 0, 0], out[i, 0, 1], out[i, 0, 2], out[i, 0, 3] = X[0], X[1], X[2], X[3]
    out[i, 1, 0], out[i, 1, 1], out[i, 1, 2], out[i, 1, 3] = X[4], X[5], X[6], X[7]
    out[i, 2, 0], out[i, 2, 1], out[i, 2, 2], out[i, 2, 3] = X[8], X[9], X[10], X[11]
    out[i, 3, 0], out[i, 3, 1], out[i, 3, 2], out[i, 3, 3] = 0.0, 0.0, 0.0, 1.0


@njit(cache=True, inline="always")
def _store2(X, out):
    out[0, 0], out[0, 1], out[0, 2], out[0, 3] = X[0], X[1], X[2], X[3]
    out[1, 0], out[1, 1], out[1, 2], out[1, 3] = X[4], X[5], X[6], X[7]
    out[2, 0], out[2, 1], out[2, 2], out[2, 3] = X[8], X[9], X[10], X[11]
    out[3, 0], out[3, 1], out[3, 2], out[3, 3] = 0.0, 0.0, 0.0, 1.0


@njit(cache=True, inline="always")
def _store3(X, out, i, f):
    out[i, f, 0, 0], out[i, f, 0, 1], out[i, f, 0, 2], out[i, f, 0, 3] = X[0], X[1], X[2], X[3]
    out[i, f, 1, 0], out[i, f, 1, 1], out[i, f, 1, 2], out[i, f, 1, 3] = X[4], X[5], X[6], X[7]
    out[i, f, 2, 0], out[i, f, 2, 1], out[i, f, 2, 2], out[i, f, 2, 3] = X[8], X[9], X[10], X[11]
    out[i, f, 3, 0], out[i, f, 3, 1], out[i, f, 3, 2], out[i, f, 3, 3] = 0.0, 0.0, 0.0, 1.0


# --------------------------------------------------------------- single configuration
_RO2 = types.Array(types.float64, 2, "C", readonly=True)  # packed constants
_OUT2 = types.Array(types.float64, 2, "C")
# q: float64, 1-D, any strides. One signature only (each costs ~1 s to compile on first use); Numba's dispatcher
# converts a read-only or C-contiguous q to it (the kernels never write q).
_Q1 = types.Array(types.float64, 1, "A", readonly=True)


@njit(cache=True)  # compiled for one signature only, on first use: see __getattr__
def fk_one(F, q, out):
    """FK of one configuration into ``out`` (4, 4); ValueError for a wrong length or NaN/inf."""
    _fk_one(F, q, out)


@njit(cache=True)  # compiled for one signature only, on first use: see __getattr__
def fk_one_w(F, q, out):
    """:func:`fk_one` for a *writable* ``F`` (a private copy of the packed constants): the types Numba's
    dispatcher resolves fastest (a read-only array leaves its cached-typecode path), for ``armkit.fk``."""
    _fk_one(F, q, out)


@njit(cache=True, inline="always")
def _fk_one(F, q, out):
    n = F.shape[0] - 1
    if q.shape[0] != n:
        raise ValueError("q has the wrong length")
    if n <= 8:
        # all sines/cosines first (independent, so they overlap in the CPU), parked in out
        for k in range(n):
            t = q[k]
            if not math.isfinite(t):
                raise ValueError("q is not finite")
            s, c = _sincos(t)
            out[k >> 2, k & 3] = s
            out[2 + (k >> 2), k & 3] = c
        X = _load(F, 0)
        for k in range(n):
            X = _mul(_move(X, q[k], out[k >> 2, k & 3], out[2 + (k >> 2), k & 3], F[k + 1, PRISMATIC] != 0.0), F, k + 1)
    else:
        X = _load(F, 0)
        for k in range(n):
            t = q[k]
            if not math.isfinite(t):
                raise ValueError("q is not finite")
            s, c = _sincos(t)
            X = _mul(_move(X, t, s, c, F[k + 1, PRISMATIC] != 0.0), F, k + 1)
    _store2(X, out)


@njit(cache=True, inline="always")
def _jacobian_cols(F, q, qo, sc, o, tool_frame, J, i):
    """Geometric Jacobian of the configuration q[qo:qo+n] (q flat) into J[i].

    Walking the FK chain ``F``, the pose before joint ``k``'s motion is the frame whose z
    axis is joint ``k``'s axis, so one affine product per joint gives every axis.
    Sines/cosines come from sc[0, o:o+n], sc[1, o:o+n] when ``o >= 0``, else are computed here.
    Returns the end pose (12 scalars, the bits of :func:`_fk_one` for the same sines and cosines).
    """
    n = F.shape[0] - 1
    # first pass: J[i, 0:3, k] <- axis origin p_k, J[i, 3:6, k] <- axis direction z_k
    X = _load(F, 0)
    for k in range(n):
        t = q[qo + k]
        if o >= 0:  # read before J[i, :, k] is written: s and c may be rows of J itself
            sk, ck = sc[0, o + k], sc[1, o + k]
        else:
            sk, ck = _sincos(t)
        J[i, 0, k], J[i, 1, k], J[i, 2, k] = X[3], X[7], X[11]
        J[i, 3, k], J[i, 4, k], J[i, 5, k] = X[2], X[6], X[10]
        X = _mul(_move(X, t, sk, ck, F[k + 1, PRISMATIC] != 0.0), F, k + 1)
    ex, ey, ez = X[3], X[7], X[11]
    for k in range(n):
        zx, zy, zz = J[i, 3, k], J[i, 4, k], J[i, 5, k]
        if F[k + 1, PRISMATIC] != 0.0:
            J[i, 0, k], J[i, 1, k], J[i, 2, k] = zx, zy, zz
            J[i, 3, k], J[i, 4, k], J[i, 5, k] = 0.0, 0.0, 0.0
        else:
            rx, ry, rz = ex - J[i, 0, k], ey - J[i, 1, k], ez - J[i, 2, k]
            J[i, 0, k] = zy * rz - zz * ry
            J[i, 1, k] = zz * rx - zx * rz
            J[i, 2, k] = zx * ry - zy * rx
    if tool_frame:  # rows become R^T v and R^T w
        r00, r01, r02, r10, r11, r12, r20, r21, r22 = X[0], X[1], X[2], X[4], X[5], X[6], X[8], X[9], X[10]
        for k in range(n):
            for o3 in (0, 3):
                a, b, cc = J[i, o3, k], J[i, o3 + 1, k], J[i, o3 + 2, k]
                J[i, o3, k] = r00 * a + r10 * b + r20 * cc
                J[i, o3 + 1, k] = r01 * a + r11 * b + r21 * cc
                J[i, o3 + 2, k] = r02 * a + r12 * b + r22 * cc
    return X


@njit(cache=True)  # compiled for one signature only, on first use: see __getattr__
def jacobian_one(F, q, tool_frame, out):
    """Jacobian of one configuration into ``out`` (6, n); ValueError for a wrong length or NaN/inf."""
    _jacobian_one(F, q, tool_frame, out)


@njit(cache=True)  # compiled for one signature only, on first use: see __getattr__
def jacobian_one_w(F, q, tool_frame, out):
    """:func:`jacobian_one` for a writable ``F`` and an integer ``tool_frame`` (0 or 1): a Python bool leaves the
    dispatcher's fast typecode path too. For ``armkit.jacobian``."""
    _jacobian_one(F, q, tool_frame != 0, out)


@njit(cache=True, inline="always")
def _jacobian_one(F, q, tool_frame, out):
    n = F.shape[0] - 1
    if q.shape[0] != n or out.shape[1] != n:
        raise ValueError("q has the wrong length")
    for k in range(n):  # all sines/cosines first, parked in the first two rows of out
        if not math.isfinite(q[k]):
            raise ValueError("q is not finite")
        out[0, k], out[1, k] = _sincos(q[k])
    _jacobian_cols(F, q, 0, out[0:2], 0, tool_frame, shaped(out, (1, 6, n)), 0)


# armkit.fk / armkit.jacobian's q: as _Q1 but not assumed aligned: their entry points (below) take any float64
# 1-D ndarray, a view at an odd byte offset included (numba.typeof calls even that one aligned)
_Q1U = types.Array(types.float64, 1, "A", readonly=True, aligned=False)
_SIGNATURES = {"fk_one_float64": (fk_one, types.void(_RO2, _Q1, _OUT2).args),
               "jacobian_one_float64": (jacobian_one, types.void(_RO2, _Q1, types.boolean, _OUT2).args),
               # armkit.fk / armkit.jacobian: F a writable copy (_OUT2's type), the frame flag an int64
               "fk_one_fast": (fk_one_w, types.void(_OUT2, _Q1U, _OUT2).args),
               "jacobian_one_fast": (jacobian_one_w, types.void(_OUT2, _Q1U, types.int64, _OUT2).args)}
_ENTRIES = {"fk_one_entry": "fk_one_fast", "jacobian_one_entry": "jacobian_one_fast"}
"""The compiled functions of ``fk_one_fast`` and ``jacobian_one_fast`` themselves, called without the dispatcher."""
_compile_lock = threading.Lock()


def __getattr__(name):
    """``fk_one_float64``, ``jacobian_one_float64`` (read-only ``F``, a bool flag), ``fk_one_fast``,
    ``jacobian_one_fast`` (writable ``F``, an int flag): the kernels, each compiled (or loaded from the cache)
    for its one signature on first use, so that the first ``fk`` does not also pay for the Jacobian kernel.

    Only Numba's public API: ``dispatcher.compile(signature)`` then ``disable_compile()``, so any other
    argument types raise ``TypeError`` at once instead of compiling anew.

    ``fk_one_entry`` and ``jacobian_one_entry`` are what ``compile`` returns for ``fk_one_fast`` and
    ``jacobian_one_fast``: the compiled function, callable without the dispatcher's typing of every argument
    (a third of a single ``armkit.fk``'s time). It checks nothing but each array's item size, so the caller
    guarantees the types of the signature: ``F`` and ``out`` C-contiguous 2-D float64, ``q`` an exact
    ``numpy.ndarray``, 1-D, dtype ``numpy.dtype(numpy.float64)`` (native byte order), the flag an ``int``.
    Lengths and NaN are checked by the kernel (``ValueError``), as through the dispatcher.
    """
    fast = _ENTRIES.get(name, name)
    if fast not in _SIGNATURES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    with _compile_lock:   # two threads asking at once: the second finds the globals set
        if name not in globals():
            dispatcher, signature = _SIGNATURES[fast]
            entry = dispatcher.compile(signature)
            dispatcher.disable_compile()
            globals()[fast] = dispatcher
            for alias, kernel in _ENTRIES.items():
                if kernel == fast:
                    globals()[alias] = entry
    return globals()[name]


# ---------------------------------------------------------------------------- batches
LANES = 8
"""Configurations :func:`_fk_lanes` takes side by side: the batches' groups (:func:`_fk_block`), and the closed
forms' branches (a 6R arm's closed form gives at most 8; :func:`armkit.ik.analytic._single._finish`)."""


@njit(cache=True, inline="always")
def _fk_lanes(F, qt, s, c, m, n, X):
    """FK of ``m`` (at most :data:`LANES`) configurations side by side: ``qt`` ((n * m), joint ``k`` of
    configuration ``i`` at ``k * m + i``) their joint values, ``s``, ``c`` their sines and cosines (the same
    layout), ``X`` (12 * LANES) their 12-scalar poses, entry ``j`` of configuration ``i`` at ``LANES * j + i``.

    The operations of :func:`_fk_one` for each configuration (``_move``, then ``_mul`` by the joint's constants,
    joint by joint), in the same order (the same bits), written as loops over the configurations with a fixed
    stride between a pose's entries, so that the compiler turns each joint's step into vector instructions, four
    configurations an instruction: a Puma's 8 closed-form branches 0.50 -> 0.26 µs with their sines and cosines
    (against :func:`armkit.ik.analytic._single._fk_rows_shared`, which takes each branch after the joints it
    shares with the one before), ``armkit.fk`` of 100,000 configurations on one thread 14-17 -> 19-22 million a
    second (2026-12-07)."""
    L = LANES
    for j in range(12):
        f = F[0, j]
        for i in range(m):
            X[L * j + i] = f
    for k in range(n):
        f00, f01, f02, f03 = F[k + 1, 0], F[k + 1, 1], F[k + 1, 2], F[k + 1, 3]
        f10, f11, f12, f13 = F[k + 1, 4], F[k + 1, 5], F[k + 1, 6], F[k + 1, 7]
        f20, f21, f22, f23 = F[k + 1, 8], F[k + 1, 9], F[k + 1, 10], F[k + 1, 11]
        o = m * k
        if F[k + 1, PRISMATIC] != 0.0:    # _move's X · Tz(t)
            for i in range(m):
                t = qt[o + i]
                X[3 * L + i] = X[3 * L + i] + t * X[2 * L + i]
                X[7 * L + i] = X[7 * L + i] + t * X[6 * L + i]
                X[11 * L + i] = X[11 * L + i] + t * X[10 * L + i]
        else:                              # _move's X · Rz(t)
            for i in range(m):
                sk, ck = s[o + i], c[o + i]
                a00, a01 = X[i], X[L + i]
                a10, a11 = X[4 * L + i], X[5 * L + i]
                a20, a21 = X[8 * L + i], X[9 * L + i]
                X[i], X[L + i] = ck * a00 + sk * a01, ck * a01 - sk * a00
                X[4 * L + i], X[5 * L + i] = ck * a10 + sk * a11, ck * a11 - sk * a10
                X[8 * L + i], X[9 * L + i] = ck * a20 + sk * a21, ck * a21 - sk * a20
        for i in range(m):                 # _mul: X · F[k + 1]
            a00, a01, a02, a03 = X[i], X[L + i], X[2 * L + i], X[3 * L + i]
            a10, a11, a12, a13 = X[4 * L + i], X[5 * L + i], X[6 * L + i], X[7 * L + i]
            a20, a21, a22, a23 = X[8 * L + i], X[9 * L + i], X[10 * L + i], X[11 * L + i]
            X[i] = a00 * f00 + a01 * f10 + a02 * f20
            X[L + i] = a00 * f01 + a01 * f11 + a02 * f21
            X[2 * L + i] = a00 * f02 + a01 * f12 + a02 * f22
            X[3 * L + i] = a00 * f03 + a01 * f13 + a02 * f23 + a03
            X[4 * L + i] = a10 * f00 + a11 * f10 + a12 * f20
            X[5 * L + i] = a10 * f01 + a11 * f11 + a12 * f21
            X[6 * L + i] = a10 * f02 + a11 * f12 + a12 * f22
            X[7 * L + i] = a10 * f03 + a11 * f13 + a12 * f23 + a13
            X[8 * L + i] = a20 * f00 + a21 * f10 + a22 * f20
            X[9 * L + i] = a20 * f01 + a21 * f11 + a22 * f21
            X[10 * L + i] = a20 * f02 + a21 * f12 + a22 * f22
            X[11 * L + i] = a20 * f03 + a21 * f13 + a22 * f23 + a23


@njit(cache=True, inline="always")
def _sincos_of_block(q, qflat, b):
    B, n = q.shape
    i0 = b * BLOCK
    i1 = min(i0 + BLOCK, B)
    sc = np.empty((2, (i1 - i0) * n))
    bad = sincos_block(qflat[i0 * n:i1 * n], sc[0], sc[1])
    return i0, i1, sc, bad


@njit(cache=True, inline="always")
def _fk_block(F, q, out, b):
    """FK of block ``b`` of ``q`` (B, n) into ``out`` (B, 4, 4), :data:`LANES` configurations at a time
    (:func:`_fk_lanes`); returns how many of its values are not finite (:func:`sincos_block`)."""
    B, n = q.shape
    i0 = b * BLOCK
    i1 = min(i0 + BLOCK, B)
    w = np.empty(LANES * (3 * n + 12))
    qt, s, c, X = w[:LANES * n], w[LANES * n:2 * LANES * n], w[2 * LANES * n:3 * LANES * n], w[3 * LANES * n:]
    bad = 0
    for g in range(i0, i1, LANES):
        m = min(LANES, i1 - g)
        for k in range(n):
            for i in range(m):
                qt[k * m + i] = q[g + i, k]
        bad += sincos_block(qt[:m * n], s, c)
        _fk_lanes(F, qt, s, c, m, n, X)
        for i in range(m):
            out[g + i, 0, 0], out[g + i, 0, 1], out[g + i, 0, 2], out[g + i, 0, 3] = \
                X[i], X[LANES + i], X[2 * LANES + i], X[3 * LANES + i]
            out[g + i, 1, 0], out[g + i, 1, 1], out[g + i, 1, 2], out[g + i, 1, 3] = \
                X[4 * LANES + i], X[5 * LANES + i], X[6 * LANES + i], X[7 * LANES + i]
            out[g + i, 2, 0], out[g + i, 2, 1], out[g + i, 2, 2], out[g + i, 2, 3] = \
                X[8 * LANES + i], X[9 * LANES + i], X[10 * LANES + i], X[11 * LANES + i]
            out[g + i, 3, 0], out[g + i, 3, 1], out[g + i, 3, 2], out[g + i, 3, 3] = 0.0, 0.0, 0.0, 1.0
    return bad


@njit(cache=True)
def _fk_serial(F, q, out):
    bad = 0
    for b in prange((q.shape[0] + BLOCK - 1) // BLOCK):
        bad += _fk_block(F, q, out, b)
    return bad


_fk_parallel = parallel_twin(_fk_serial)


def fk_batch(F, q):
    """FK of ``q`` (B, n), C-contiguous: ``(out (B, 4, 4), number of non-finite values in q)``."""
    out = np.empty((q.shape[0], 4, 4))
    bad = (_fk_parallel if q.shape[0] >= PARALLEL_MIN and _jit_loader.parallel_ok() else _fk_serial)(F, q, out)
    return out, bad


@njit(cache=True, inline="always")
def _jacobian_block(F, q, qflat, tool_frame, out, b):
    n = q.shape[1]
    i0, i1, sc, bad = _sincos_of_block(q, qflat, b)
    for i in range(i0, i1):
        _jacobian_cols(F, qflat, i * n, sc, (i - i0) * n, tool_frame, out, i)
    return bad


@njit(cache=True)
def _jacobian_serial(F, q, tool_frame, out):
    bad = 0
    qflat = q.reshape(q.size)
    for b in prange((q.shape[0] + BLOCK - 1) // BLOCK):
        bad += _jacobian_block(F, q, qflat, tool_frame, out, b)
    return bad


_jacobian_parallel = parallel_twin(_jacobian_serial)


def jacobian_batch(F, q, tool_frame):
    """Jacobians of ``q`` (B, n), C-contiguous: ``(out (B, 6, n), number of non-finite values in q)``."""
    out = np.empty((q.shape[0], 6, q.shape[1]))
    kernel = _jacobian_parallel if q.shape[0] >= PARALLEL_MIN and _jit_loader.parallel_ok() else _jacobian_serial
    return out, kernel(F, q, tool_frame, out)


@njit(cache=True, inline="always")
def _frames_block(P, q, qflat, out, b):
    n = q.shape[1]
    i0, i1, sc, bad = _sincos_of_block(q, qflat, b)
    for i in range(i0, i1):
        o = (i - i0) * n
        X = _load(P, 0)
        _store3(X, out, i, 0)
        for k in range(n):
            X = _mul(_move(_mul(X, P, 1 + k), q[i, k], sc[0, o + k], sc[1, o + k], P[1 + k, PRISMATIC] != 0.0), P, 1 + n + k)
            if k == n - 1:
                X = _mul(X, P, 2 * n + 1)
            _store3(X, out, i, k + 1)
    return bad


@njit(cache=True)
def _frames_serial(P, q, out):
    bad = 0
    qflat = q.reshape(q.size)
    for b in prange((q.shape[0] + BLOCK - 1) // BLOCK):
        bad += _frames_block(P, q, qflat, out, b)
    return bad


_frames_parallel = parallel_twin(_frames_serial)


def frames_batch(P, q):
    """Every link frame of ``q`` (B, n): ``(out (B, n + 1, 4, 4), number of non-finite values in q)``."""
    out = np.empty((q.shape[0], q.shape[1] + 1, 4, 4))
    kernel = _frames_parallel if q.shape[0] >= PARALLEL_MIN and _jit_loader.parallel_ok() else _frames_serial
    return out, kernel(P, q, out)



@njit(cache=True)
def rigidity(T, orth, det, last_ok):
    """:func:`armkit.spatial.check_transform`'s measures of every pose of ``T`` (B, 4, 4) in one pass: the
    largest ``|(R^T R - I)_ij|`` into ``orth``, ``det R`` into ``det``, last row exactly (0, 0, 0, 1) into
    ``last_ok`` (the formula of ``spatial._rigidity``, written out for the compiler)."""
    for i in range(T.shape[0]):
        a, b, c = T[i, 0, 0], T[i, 0, 1], T[i, 0, 2]
        d, e, f = T[i, 1, 0], T[i, 1, 1], T[i, 1, 2]
        g, h, k = T[i, 2, 0], T[i, 2, 1], T[i, 2, 2]
        o = max(abs(a * a + d * d + g * g - 1.0), abs(b * b + e * e + h * h - 1.0),
                abs(c * c + f * f + k * k - 1.0), abs(a * b + d * e + g * h), abs(a * c + d * f + g * k),
                abs(b * c + e * f + h * k))
        orth[i] = o if o == o else np.inf
        det[i] = a * (e * k - f * h) - b * (d * k - f * g) + c * (d * h - e * g)
        last_ok[i] = T[i, 3, 0] == 0.0 and T[i, 3, 1] == 0.0 and T[i, 3, 2] == 0.0 and T[i, 3, 3] == 1.0


def parallel_twins():
    """``(one-thread kernel, multi-threaded kernel)`` pairs taking the same arguments (for the warm-up)."""
    return [(_fk_serial, _fk_parallel), (_jacobian_serial, _jacobian_parallel), (_frames_serial, _frames_parallel)]


# the single Jacobian inlines armkit._jit_shaped's view: compiled anew when that file changes
_jit_loader.forget_stale_cache(globals(), ("_jit_shaped.py",))
