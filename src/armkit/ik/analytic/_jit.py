"""Numba kernels for the closed forms: the same formulas as the NumPy solvers, one target at a time.

Each kernel fills the arrays the family's NumPy code computes (joint values of every branch
and the flags its labels and messages are made from), for 1 or N targets alike, so that a
single IK call costs a few microseconds instead of a hundred small NumPy operations. The
NumPy code stays the reference and serves ``armkit.set_backend("numpy")``; both give the
same branches, labels and messages, and joint values equal up to the last bits (libm and
NumPy's SIMD ``arctan2``/``arcsin`` may round differently). Imported lazily, only when the
Numba back end is in use.

Each family kernel takes the targets, the family's packed geometry ``g`` (one float64 array per
robot, built by the family's ``geometry`` property; indices named in :mod:`._layout`), what it
needs per target (``q0phi``), then its outputs, one array per argument, and the target range
``lo, hi``. Outputs are never passed in a tuple: Numba 0.68's parfors loses writes to arrays
reached through a tuple inside a ``prange`` loop (the threaded copies are tested against the
one-thread kernels).
"""

from __future__ import annotations

import math

import numpy as np

from ... import _jit_loader

_jit_loader.install_cache_fallback()  # before the first cache=True: read-only installs cache elsewhere

from numba import njit, prange  # noqa: E402

from ..._jit_twins import parallel_twin  # noqa: E402
from ...kinematics._jit import _atan2, _sincos  # noqa: E402  (the FK's sine and cosine: a polynomial, ~40 % faster
# than libm's; atan2 likewise, ~2.6x)

from ._layout import (BASE_INV, JOINT_LOWER, JOINT_PRISMATIC, JOINT_THETA, JOINT_UPPER, P2_BETA,  # noqa: E402
                      P2_ELL, P2_L1, P3_L1, P3_L2, POS_A1, POS_A2, POS_BETA, POS_D1, POS_ELL, POS_S1, POS_TINY,
                      POS_Z, SW_CS, SW_D6, SW_F3, SW_S4, SW_S5, TOOL_INV, UR_A2, UR_A3, UR_D, UR_D1, UR_D4, UR_D5,
                      UR_D6, UR_F3, UR_F4, UR_S1, UR_S4, UR_S5, UR_TINY, YPP_F3)

TWO_PI = 2.0 * math.pi
PAR = 64
"""From this many targets on, the kernels run on all threads. Measured on the project's 2-core machine (``ik_all``,
two threads against one for every pass): 64 targets 4.5 instead of 4.9 µs a target on the UR5, 5.0 instead of 5.6
on the Puma 560; 1,000 targets 2.6 instead of 3.4 and 3.2 instead of 4.3; at 32 targets the two are within the
noise (planar3 from 64-128). docs/performance.md."""


@njit(cache=True, inline="always")
def _rint(x):
    """Round half to even, like ``np.round``: ``np.rint``, one ``roundsd`` instruction (0.5 ns in a loop). The
    version before it (``math.floor``, a test of the remainder) took ~7 ns: a branch that random angles mispredict
    half the time, and ``math.floor`` returns an integer in Numba (two conversions; garbage above 2**63)."""
    return np.rint(x)


@njit(cache=True, inline="always")
def _hypot(x, y):
    """``hypot(x, y)`` as ``sqrt(x² + y²)``: libm's ``hypot`` (scaled against overflow and underflow) took 4-5 % of a
    Puma 560 call; it still answers where the sum of squares could have lost digits to either (below 1e-290,
    above 1e290, not finite). Within an ulp of libm's (each is within an ulp of the true value)."""
    s = x * x + y * y
    if 1e-290 < s < 1e290:
        return math.sqrt(s)
    return math.hypot(x, y)


@njit(cache=True)
def _two_link(x, y, l1, l2):
    """:func:`~._common.two_link` for one point: ``(t1 of branch 0, of branch 1), (t2 ...), c, r``."""
    r2 = x * x + y * y
    c = (r2 - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)
    cc = min(max(c, -1.0), 1.0)
    s = math.sqrt((1.0 - cc) * (1.0 + cc))
    psi = _atan2(y, x)
    # atan2 is odd in y, to the bit (atan2(-y, x) == -atan2(y, x), zeros' signs too; checked on 12 million
    # pairs from 1e-300 to 1e300): each branch pair takes one call, not two (UR5: 8 of its 27 calls a target)
    a = _atan2(l2 * s, l1 + l2 * cc)
    b = _atan2(s, cc)
    return (psi - a, psi + a), (b, -b), c, math.sqrt(r2)


@njit(cache=True, inline="always")
def _fwd(x, default):
    return 1.0 if x > 0 else (-1.0 if x < 0 else default)


@njit(cache=True, inline="always")
def _up(forward, up_sign, l1l2_sign, e):
    return -forward * up_sign * l1l2_sign * e > 0


# ------------------------------------------------------------------------- planar
@njit(cache=True, inline="always")  # outputs: one array per argument, never a tuple (Numba 0.68's parfors loses writes through tuples)
def _planar_one(i, x, y, lengths, q, up, c, r, unreach, edge):
    """2R core for target ``i``, ``lengths = (l1, l2, extra)``: ``q[i, :, 0:2]``, label indices (elbow up)
    ``up[i]``, ``c[i]``, ``r[i]``, ``unreach[i]`` and ``edge[i]`` (stretched or folded)."""
    l1, l2, extra = lengths
    t1, t2, cc, r[i] = _two_link(x, y, l1, l2)
    c[i] = cc
    out = (cc > 1.0) or (cc < -1.0)
    edge[i] = abs(abs(cc) - 1.0) <= 1e-9 and not out
    sg = math.copysign(1.0, l1 * l2)
    f = _fwd(x, 1.0)
    for k in range(2):
        q[i, k, 0] = t1[k]
        q[i, k, 1] = t2[k] - extra
        up[i, k] = 1 if _up(f, 1.0, sg, 1.0 if k == 0 else -1.0) else 0
        unreach[i, k] = out
    return t1, t2


@njit(cache=True, inline="always")
def _point(p, i, g):
    """Point ``p[i]`` (world) in ``B'``: ``B'^-1 p``, with ``B'^-1`` at ``g[BASE_INV]``."""
    b = BASE_INV
    x = g[b + 0] * p[i, 0] + g[b + 1] * p[i, 1] + g[b + 2] * p[i, 2] + g[b + 3]
    y = g[b + 4] * p[i, 0] + g[b + 5] * p[i, 1] + g[b + 6] * p[i, 2] + g[b + 7]
    z = g[b + 8] * p[i, 0] + g[b + 9] * p[i, 1] + g[b + 10] * p[i, 2] + g[b + 11]
    return x, y, z


@njit(cache=True)  # outputs: one array per argument, never a tuple (Numba 0.68's parfors loses writes through tuples)
def _planar2_run(p, g, q, up, c, r, unreach, edge, lo, hi):
    for i in prange(lo, hi):
        x, y, _ = _point(p, i, g)
        _planar_one(i, x, y, (g[P2_L1], g[P2_ELL], g[P2_BETA]), q, up, c, r, unreach, edge)


@njit(cache=True, inline="always")
def _chain(T, i, g, out):
    """``out = B'^-1 @ T[i] @ T'^-1`` (rows 0-2 of 4x4 rigid poses; both frames read from ``g``). Row ``a`` of
    ``B'^-1 @ T[i]`` is held in four scalars, not an array: one array fewer to make per target (~0.1 µs of a
    single call's 3.7)."""
    A, C = BASE_INV, TOOL_INV
    for a in range(3):
        x0, x1, x2, x3 = g[A + 4 * a], g[A + 4 * a + 1], g[A + 4 * a + 2], g[A + 4 * a + 3]
        t0 = x0 * T[i, 0, 0] + x1 * T[i, 1, 0] + x2 * T[i, 2, 0] + x3 * T[i, 3, 0]
        t1 = x0 * T[i, 0, 1] + x1 * T[i, 1, 1] + x2 * T[i, 2, 1] + x3 * T[i, 3, 1]
        t2 = x0 * T[i, 0, 2] + x1 * T[i, 1, 2] + x2 * T[i, 2, 2] + x3 * T[i, 3, 2]
        t3 = x0 * T[i, 0, 3] + x1 * T[i, 1, 3] + x2 * T[i, 2, 3] + x3 * T[i, 3, 3]
        for b in range(4):
            out[a, b] = t0 * g[C + b] + t1 * g[C + 4 + b] + t2 * g[C + 8 + b] + t3 * g[C + 12 + b]


# counted (_nrt=True) said explicitly: it makes an array, and the one-call kernels of _single that call it are not;
# outputs: one array per argument, never a tuple (Numba 0.68's parfors loses writes through tuples)
@njit(cache=True, _nrt=True)
def _planar3_run(T, g, q, up, c, r, unreach, edge, lo, hi):
    for i in prange(lo, hi):
        Tc = np.empty((3, 4))
        _chain(T, i, g, Tc)
        phi = _atan2(Tc[1, 0], Tc[0, 0])
        t1, t2 = _planar_one(i, Tc[0, 3], Tc[1, 3], (g[P3_L1], g[P3_L2], 0.0), q, up, c, r, unreach, edge)
        for k in range(2):
            q[i, k, 2] = phi - t1[k] - t2[k]


def _split(run, B, *args):
    if B >= PAR and _jit_loader.parallel_ok():
        _par(run)(*args, 0, B)
    else:
        run(*args, 0, B)


def _par(run):
    # the multi-threaded twin of a kernel (armkit._jit_twins), made on the first big batch
    fn = _PARALLEL.get(run)
    if fn is None:
        fn = _PARALLEL[run] = parallel_twin(run)
    return fn


_PARALLEL: dict = {}  # one-thread kernel -> its multi-threaded copy: per function, not per robot (robot data: Robot.cache)


def _planar_arrays(B, n):
    return (np.empty((B, 2, n)), np.empty((B, 2), np.int64), np.empty(B), np.empty(B), np.empty((B, 2), np.bool_),
            np.empty(B, np.bool_))


def planar2(p, g):
    """Points ``p`` (B, 3), geometry ``g`` (layout ``P2_*``) -> joint values ``(B, 2, 2)``, label indices
    ``(B, 2)`` (1: elbow up), the two-link cosine and distance ``(B,)``, unreachable ``(B, 2)`` and
    stretched-or-folded ``(B,)``."""
    arrs = _planar_arrays(p.shape[0], 2)
    _split(_planar2_run, p.shape[0], p, g, *arrs)
    return arrs


def planar3(T, g):
    """Poses ``T`` (B, 4, 4), geometry ``g`` (layout ``P3_*``) -> the arrays of :func:`planar2`, joint
    values ``(B, 2, 3)``."""
    arrs = _planar_arrays(T.shape[0], 3)
    _split(_planar3_run, T.shape[0], T, g, *arrs)
    return arrs


# ---------------------------------------------------------------------- positioner
@njit(cache=True, inline="always")  # outputs: one array per argument, never a tuple (Numba 0.68's parfors loses writes through tuples)
def _positioner(i, x, y, z, yaw0, g, phi, up, unreach, c, r, rho, lat, on_axis, edge, lab):
    """:meth:`~.yaw_pitch_pitch.Positioner.solve` for target ``i`` (geometry ``g``, layout ``POS_*``)."""
    s1, d1, a1, a2, Z, ell, beta = g[POS_S1], g[POS_D1], g[POS_A1], g[POS_A2], g[POS_Z], g[POS_ELL], g[POS_BETA]
    tiny = g[POS_TINY]
    rh = _hypot(x, y)
    rho[i] = rh
    h2 = rh * rh - Z * Z
    lat[i] = h2 < 0.0
    Xf = math.sqrt(max(h2, 0.0))
    on_axis[i] = (rh <= tiny) and (abs(Z) <= tiny)
    psi = yaw0 if on_axis[i] else _atan2(y, x)
    sg = math.copysign(1.0, a2 * ell)
    Y = s1 * (z - d1)
    for f in range(2):
        Xs = Xf if f == 0 else -Xf
        p1 = psi - _atan2(-s1 * Z, Xs)
        X = Xs - a1
        t1, t2, cc, rr = _two_link(X, Y, a2, ell)
        c[i, f], r[i, f] = cc, rr
        edge[i, f] = abs(abs(cc) - 1.0) <= 1e-9
        out = (cc > 1.0) or (cc < -1.0) or lat[i]
        fw = _fwd(X, 1.0 if f == 0 else -1.0)
        for e in range(2):
            b = 2 * f + e
            phi[i, b, 0] = p1
            phi[i, b, 1] = t1[e]
            phi[i, b, 2] = t2[e] - beta
            up[i, b] = _up(fw, s1, sg, 1.0 if e == 0 else -1.0)
            unreach[i, b] = out
            lab[i, b] = (2 if f == 0 else 0) + (1 if up[i, b] else 0)


def _pos_arrays(B):
    return (np.empty((B, 4, 3)), np.empty((B, 4), dtype=np.bool_), np.empty((B, 4), dtype=np.bool_),
            np.empty((B, 2)), np.empty((B, 2)), np.empty(B), np.empty(B, dtype=np.bool_),
            np.empty(B, dtype=np.bool_), np.empty((B, 2), dtype=np.bool_), np.empty((B, 4), np.int64))


@njit(cache=True)  # outputs: one array per argument, never a tuple (Numba 0.68's parfors loses writes through tuples)
def _ypp_run(p, g, yaw0, phi, up, unreach, c, r, rho, lat, on_axis, edge, lab, lo, hi):
    f3 = g[YPP_F3]
    for i in prange(lo, hi):
        x, y, z = _point(p, i, g)
        _positioner(i, x, y, z, yaw0[i], g, phi, up, unreach, c, r, rho, lat, on_axis, edge, lab)
        for b in range(4):   # back to the arm as given (a reversed joint 3: f3 = -1)
            phi[i, b, 2] = f3 * phi[i, b, 2]


def yaw_pitch_pitch(p, g, yaw0):
    """Arrays of ``Positioner.solve`` (phi, up, unreachable, c, r, rho, lateral_out, on_axis) and the
    stretched-or-folded flags ``(B, 2)`` and label indices ``(B, 4)`` for points ``p`` (B, 3), geometry
    ``g`` (layout ``POS_*``) and the yaw ``yaw0`` (B,) used on the axis."""
    B = p.shape[0]
    arrs = _pos_arrays(B)
    _split(_ypp_run, B, p, g, yaw0, *arrs)
    return arrs


# ------------------------------------------------------------------ spherical wrist
@njit(cache=True, inline="always")
def _half_turn(x):
    """``x`` turned by pi, kept in ``(-pi, pi]`` where ``x`` is (as atan2 gives it)."""
    return x - math.pi if x > 0.0 else x + math.pi


@njit(cache=True, inline="always")
def _rotate_back(v0, v1, v2, c, s, ca, sa):
    """:func:`~._common.rotate_back` with ``c, s`` the cosine and sine of phi."""
    x = c * v0 + s * v1
    y = -s * v0 + c * v1
    return x, ca * y + sa * v2, -sa * y + ca * v2


# counted (_nrt=True) said explicitly: it makes an array, and the one-call kernels of _single that call it are not;
# outputs: one array per argument, never a tuple (Numba 0.68's parfors loses writes through tuples)
@njit(cache=True, _nrt=True)
def _puma_run(T, g, q0phi, out, lab, singular, phi, up, unreach, c, r, rho, lat, on_axis, edge, lab4, lo, hi):
    d6, s4, s5, cs, f3 = g[SW_D6], g[SW_S4], g[SW_S5], SW_CS, g[SW_F3]
    for i in prange(lo, hi):
        Tc = np.empty((3, 4))
        _chain(T, i, g, Tc)
        x = Tc[0, 3] - d6 * Tc[0, 2]
        y = Tc[1, 3] - d6 * Tc[1, 2]
        z = Tc[2, 3] - d6 * Tc[2, 2]
        _positioner(i, x, y, z, q0phi[i, 0], g, phi, up, unreach, c, r, rho, lat, on_axis, edge, lab4)
        for b in range(4):
            p0, p12 = phi[i, b, 0], phi[i, b, 1] + phi[i, b, 2]
            s0, c0 = _sincos(p0)
            s12, c12 = _sincos(p12)
            m0, m1, m2 = _rotate_back(Tc[0, 2], Tc[1, 2], Tc[2, 2], c0, s0, g[cs], g[cs + 1])
            mz0, mz1, mz2 = _rotate_back(m0, m1, m2, c12, s12, g[cs + 2], g[cs + 3])
            m0, m1, m2 = _rotate_back(Tc[0, 0], Tc[1, 0], Tc[2, 0], c0, s0, g[cs], g[cs + 1])
            mx0, mx1, mx2 = _rotate_back(m0, m1, m2, c12, s12, g[cs + 2], g[cs + 3])
            h = _hypot(mz0, mz1)
            sing = h <= 1e-12
            singular[i, b] = sing
            a5 = _atan2(h, -s4 * s5 * mz2)   # the two wrists' p5: +-a5 (atan2 is odd in y, see _two_link)
            sa5, ca5 = _sincos(a5)                # and their sines and cosines: (+-sin a5, cos a5)
            for k in range(2):
                w = 1.0 if k == 0 else -1.0
                p5 = a5 if k == 0 else -a5
                if k == 1 and not sing:   # the other wrist of the same rotation: (p4 +- pi, -p5, p6 +- pi), as
                    # Rz(p4 + pi) Rx(a4) Rz(-p5) Rx(a5) Rz(p6 + pi) = Rz(p4) Rx(a4) Rz(p5) Rx(a5) Rz(p6) for a4, a5 =
                    # +-90 deg (the family's twists); within 1 ulp of the atan2 of the negated pair, two calls fewer
                    p4, p6 = _half_turn(out[i, b, 0, 3]), _half_turn(out[i, b, 0, 5])
                else:
                    p4 = q0phi[i, 3] if sing else _atan2((w * s5) * mz1, (w * s5) * mz0)
                    s4k, c4k = _sincos(p4)
                    e0, e1, e2 = _rotate_back(mx0, mx1, mx2, c4k, s4k, g[cs + 4], g[cs + 5])
                    f0, f1, f2 = _rotate_back(e0, e1, e2, ca5, sa5 if k == 0 else -sa5, g[cs + 6], g[cs + 7])
                    p6 = _atan2(f1, f0)
                out[i, b, k, 0] = phi[i, b, 0]
                out[i, b, k, 1] = phi[i, b, 1]
                out[i, b, k, 2] = f3 * phi[i, b, 2]   # back to the arm as given (a reversed joint 3: f3 = -1)
                out[i, b, k, 3] = p4
                out[i, b, k, 4] = p5
                out[i, b, k, 5] = p6
                lab[i, b, k] = (4 if b < 2 else 0) + 2 * (1 if up[i, b] else 0) + (1 if k == 0 else 0)


def spherical_wrist(T, g, q0phi):
    """Poses ``T`` (B, 4, 4), geometry ``g`` (layout ``SW_*``), reference joints ``q0phi`` (B, 6) ->
    joint values ``(B, 4, 2, 6)``, label indices ``(B, 4, 2)``, wrist-singular flags ``(B, 4)`` and the
    positioner's arrays."""
    B = T.shape[0]
    arrs = _pos_arrays(B)
    out, lab, singular = np.empty((B, 4, 2, 6)), np.empty((B, 4, 2), np.int64), np.empty((B, 4), dtype=np.bool_)
    _split(_puma_run, B, T, g, q0phi, out, lab, singular, *arrs)
    return out, lab, singular, arrs


# ----------------------------------------------------------------------------- UR
# counted (_nrt=True) said explicitly: it makes an array, and the one-call kernels of _single that call it are not;
# outputs: one array per argument, never a tuple (Numba 0.68's parfors loses writes through tuples)
@njit(cache=True, _nrt=True)
def _ur_run(T, g, q0phi, out, up, lab, unreach, lat, rho, r, on_axis, singular, lo, hi):
    s1, s4, s5, D, tiny = g[UR_S1], g[UR_S4], g[UR_S5], g[UR_D], g[UR_TINY]
    d1, d4, d5, d6, a2, a3 = g[UR_D1], g[UR_D4], g[UR_D5], g[UR_D6], g[UR_A2], g[UR_A3]
    f3, f4 = g[UR_F3], g[UR_F4]
    for i in prange(lo, hi):
        Tc = np.empty((3, 4))
        _chain(T, i, g, Tc)
        p5x = Tc[0, 3] - d6 * Tc[0, 2]
        p5y = Tc[1, 3] - d6 * Tc[1, 2]
        rh = _hypot(p5x, p5y)
        rho[i] = rh
        oa = (rh <= tiny) and (abs(D) <= tiny)
        on_axis[i] = oa
        psi = q0phi[i, 0] if oa else _atan2(p5y, p5x)
        ratio = (s1 * D) / rh if rh > 0 else 0.0
        lat[i] = abs(ratio) > 1.0
        asn = math.asin(min(max(ratio, -1.0), 1.0))
        for sh in range(2):
            p1 = psi + math.pi - asn if sh == 0 else psi + asn
            sin1, cos1 = _sincos(p1)
            z1x, z1y = s1 * sin1, -s1 * cos1
            cos5 = -s4 * s5 * (z1x * Tc[0, 2] + z1y * Tc[1, 2])
            sin5 = _hypot(Tc[2, 2], z1x * Tc[1, 2] - z1y * Tc[0, 2])
            a5 = _atan2(sin5, cos5)
            sa5, ca5 = _sincos(a5)   # the two wrists' p5 = -+a5: sines -+sin a5, cosines cos a5
            wx = Tc[0, 0] * z1x + Tc[1, 0] * z1y
            wy = Tc[0, 1] * z1x + Tc[1, 1] * z1y
            p6 = sn6 = c6 = 0.0   # the first wrist's, for the second
            for wi in range(2):
                ws = -1.0 if wi == 0 else 1.0
                p5 = a5 * ws
                sn5, c5 = sa5 * ws, ca5
                sing = abs(sn5) <= 1e-12
                singular[i, sh, wi] = sing
                k = s4 * ws
                if wi == 1 and not sing:   # the other wrist: p6 turned by pi (its pair (wx, wy) k negated)
                    p6, sn6, c6 = _half_turn(p6), -sn6, -c6
                else:
                    p6 = q0phi[i, 5] if sing else _atan2(-wy * k, wx * k)
                    sn6, c6 = _sincos(p6)
                x40, x41, x42 = c6 * c5, -sn6 * c5, s5 * sn5
                y40, y41, y42 = c6 * sn5, -sn6 * sn5, -s5 * c5
                o0 = -s5 * d5 * sn6 - s4 * d4 * y40
                o1 = -s5 * d5 * c6 - s4 * d4 * y41
                o2 = -d6 - s4 * d4 * y42
                xw0 = Tc[0, 0] * x40 + Tc[0, 1] * x41 + Tc[0, 2] * x42
                xw1 = Tc[1, 0] * x40 + Tc[1, 1] * x41 + Tc[1, 2] * x42
                xw2 = Tc[2, 0] * x40 + Tc[2, 1] * x41 + Tc[2, 2] * x42
                ow0 = Tc[0, 3] + Tc[0, 0] * o0 + Tc[0, 1] * o1 + Tc[0, 2] * o2
                ow1 = Tc[1, 3] + Tc[1, 0] * o0 + Tc[1, 1] * o1 + Tc[1, 2] * o2
                ow2 = Tc[2, 3] + Tc[2, 0] * o0 + Tc[2, 1] * o1 + Tc[2, 2] * o2
                x = cos1 * ow0 + sin1 * ow1
                y = s1 * (ow2 - d1)
                total = _atan2(s1 * xw2, cos1 * xw0 + sin1 * xw1)
                t1, t2, cc, rr = _two_link(x, y, a2, a3)
                r[i, sh, wi] = rr
                out_of = lat[i] or cc > 1.0 or cc < -1.0
                f = _fwd(x, 1.0)
                sg = math.copysign(1.0, a2 * a3)
                for e in range(2):
                    out[i, sh, wi, e, 0] = p1
                    out[i, sh, wi, e, 1] = t1[e]
                    out[i, sh, wi, e, 2] = f3 * t2[e]   # back to the arm as given (reversed joints: -1)
                    out[i, sh, wi, e, 3] = f4 * (total - t1[e] - t2[e])
                    out[i, sh, wi, e, 4] = p5
                    out[i, sh, wi, e, 5] = p6
                    up[i, sh, wi, e] = _up(f, s1, sg, 1.0 if e == 0 else -1.0)
                    lab[i, sh, wi, e] = 4 * sh + 2 * wi + (1 if up[i, sh, wi, e] else 0)
                    unreach[i, sh, wi, e] = out_of



def ur(T, g, q0phi):
    """Poses ``T`` (B, 4, 4), geometry ``g`` (layout ``UR_*``), reference joints ``q0phi`` (B, 6) -> joint
    values ``(B, 2, 2, 2, 6)``, label indices and unreachable ``(B, 2, 2, 2)``, lateral_out, rho ``(B,)``,
    r ``(B, 2, 2)``, on_axis ``(B,)`` and singular ``(B, 2, 2)``."""
    B = T.shape[0]
    out, up, unreach = np.empty((B, 2, 2, 2, 6)), np.empty((B, 2, 2, 2), np.bool_), np.empty((B, 2, 2, 2), np.bool_)
    lab = np.empty((B, 2, 2, 2), np.int64)
    lat, rho, r = np.empty(B, np.bool_), np.empty(B), np.empty((B, 2, 2))
    on_axis, singular = np.empty(B, np.bool_), np.empty((B, 2, 2), np.bool_)
    _split(_ur_run, B, T, g, q0phi, out, up, lab, unreach, lat, rho, r, on_axis, singular)
    return out, lab, unreach, lat, rho, r, on_axis, singular


# ---------------------------------------------------------------- wrap and pick
@njit(cache=True, inline="always")
def _wrap_one(v, q0, lo, hi, revolute):
    """:func:`~armkit.ik.analytic.wrap_to_limits` for one value (``lo, hi``: limits widened by 1e-12)."""
    if not revolute:
        return v
    near = v + TWO_PI * _rint((q0 - v) / TWO_PI)
    if near >= lo and near <= hi:
        return near
    v = near
    if v < lo:
        cand = v + TWO_PI * np.ceil((lo - v) / TWO_PI)    # np.ceil, np.floor: floats, no integer round trip
    else:
        cand = v + TWO_PI * np.floor((hi - v) / TWO_PI)
    if cand >= lo and cand <= hi:
        return cand
    mid = 0.5 * (lo + hi) if (math.isfinite(lo) and math.isfinite(hi)) else v
    return v + TWO_PI * _rint((mid - v) / TWO_PI)


@njit(cache=True, inline="always")
def _widened(joints):
    """``lower - 1e-12, upper + 1e-12, ~prismatic`` of the joint table, as loops. Array expressions and slice
    assignments make Numba compile its shape-mismatch error message (integer-to-string formatting): ~3 s on
    first use."""
    n = joints.shape[1]
    lo, hi, revolute = np.empty(n), np.empty(n), np.empty(n, np.bool_)
    for j in range(n):
        lo[j] = joints[JOINT_LOWER, j] - 1e-12
        hi[j] = joints[JOINT_UPPER, j] + 1e-12
        revolute[j] = joints[JOINT_PRISMATIC, j] == 0.0
    return lo, hi, revolute


@njit(cache=True)  # outputs: one array per argument, never a tuple (Numba 0.68's parfors loses writes through tuples)
def _pick_run(rawq, joints, q0, unreach, enforce, qb, pick, clean, first, last):
    theta = joints[JOINT_THETA]
    m, n = rawq.shape[1], rawq.shape[2]
    lo, hi, revolute = _widened(joints)
    for i in prange(first, last):
        best, bd = 0, np.inf
        dist = np.empty(m)
        cand = np.empty(m, dtype=np.bool_)
        q = np.empty((m, n))
        for b in range(m):
            inside = True
            s = 0.0
            for j in range(n):
                v = _wrap_one(rawq[i, b, j] - theta[j], q0[i, j], lo[j], hi[j], revolute[j])
                q[b, j] = v
                if v < lo[j] or v > hi[j]:
                    inside = False
                if revolute[j]:
                    s += (v - q0[i, j]) ** 2
            dist[b] = math.sqrt(s)
            cand[b] = (not unreach[i, b]) and (inside or not enforce)
            if cand[b] and dist[b] < bd:
                best, bd = b, dist[b]
        pick[i] = best
        for j in range(n):   # not qb[i] = q[best]: see _widened
            qb[i, j] = q[best, j]
        near = False
        for b in range(m):
            if unreach[i, b] and dist[b] <= dist[best]:
                near = True
        clean[i] = cand[best] and not near


def wrap_pick(rawq, joints, q0, unreachable, enforce):
    """Per target, the branch nearest ``q0`` among those not clipped (and inside the limits when ``enforce``):
    its wrapped joint values ``(B, n)``, its index ``(B,)``, and whether it is such a candidate with no clipped
    branch as near ``(B,)``. ``rawq`` (B, m, n) DH angles, ``joints`` the joint table (``_layout.JOINT_*``)."""
    B, m, n = rawq.shape
    outs = (np.empty((B, n)), np.empty(B, np.int64), np.empty(B, np.bool_))
    _split(_pick_run, B, rawq, joints, q0, unreachable, enforce, *outs)
    return outs


@njit(cache=True)
def _wrap_dist_run(rawq, joints, q0, q, dist, first, last):
    theta = joints[JOINT_THETA]
    m, n = rawq.shape[1], rawq.shape[2]
    lo, hi, revolute = _widened(joints)
    for i in prange(first, last):
        for b in range(m):
            s = 0.0
            for j in range(n):
                v = _wrap_one(rawq[i, b, j] - theta[j], q0[i, j], lo[j], hi[j], revolute[j])
                q[i, b, j] = v
                if revolute[j]:
                    s += (v - q0[i, j]) ** 2
            dist[i, b] = math.sqrt(s)


def wrap_dist(rawq, joints, q0):
    """Wrapped joint values ``(B, m, n)`` (:func:`~armkit.ik.analytic.wrap_to_limits`) and their distances
    ``(B, m)`` to ``q0`` (revolute joints); ``joints`` the joint table (``_layout.JOINT_*``)."""
    B, m, n = rawq.shape
    outs = (np.empty((B, m, n)), np.empty((B, m)))
    _split(_wrap_dist_run, B, rawq, joints, q0, *outs)
    return outs


# ------------------------------------------------------------------------- sort
@njit(cache=True, inline="always")
def stable_order(k_of, idx):
    """``idx (m,)`` := the indices that sort ``k_of (m,)`` ascending, ties in index order (an insertion sort:
    ``m`` is a handful of branches). Makes no array (the kernels without reference counts call it)."""
    m = k_of.shape[0]
    for b in range(m):
        k = k_of[b]
        j = b - 1
        while j >= 0 and k_of[idx[j]] > k:
            idx[j + 1] = idx[j]
            j -= 1
        idx[j + 1] = b


@njit(cache=True)  # outputs: one array per argument, never a tuple (Numba 0.68's parfors loses writes through tuples)
def _sort_run(ok, dist, q, dp, dr, within, order, qs, oks, dps, drs, ws, first, last):
    m = ok.shape[1]
    for i in prange(first, last):
        k_of = np.empty(m)
        idx = np.empty(m, np.int64)
        for b in range(m):   # successful branches first, each group by distance (a stable sort)
            k_of[b] = (0.0 if ok[i, b] else 1e9) + dist[i, b]
        stable_order(k_of, idx)
        for b in range(m):
            s = idx[b]
            order[i, b] = s
            for j in range(q.shape[2]):   # not qs[i, b] = q[i, s]: see _widened
                qs[i, b, j] = q[i, s, j]
            oks[i, b], dps[i, b], drs[i, b], ws[i, b] = ok[i, s], dp[i, s], dr[i, s], within[i, s]


def sort_branches(ok, dist, q, dp, dr, within):
    """``np.argsort(where(ok, 0, 1e9) + dist, kind="stable")`` per target ``(B, m)`` and ``q, ok, dp, dr, within``
    in that order."""
    B, m = ok.shape
    out = (np.empty((B, m), np.int64), np.empty_like(q), np.empty((B, m), np.bool_), np.empty((B, m)),
           np.empty((B, m)), np.empty((B, m), np.bool_))
    _split(_sort_run, B, ok, dist, q, dp, dr, within, *out)
    return out


def parallel_twins():
    """``(one-thread kernel, multi-threaded kernel)`` pairs taking the same arguments (for the warm-up)."""
    return [(run, _par(run)) for run in (_planar2_run, _planar3_run, _ypp_run, _puma_run, _ur_run, _pick_run,
                                         _wrap_dist_run, _sort_run)]


# the kernels read the indices of _layout.py as compile-time constants and inline the sine and cosine of
# kinematics/_jit.py: compiled anew when either changes
_jit_loader.forget_stale_cache(globals(), ("ik/analytic/_layout.py", "kinematics/_jit.py"))
