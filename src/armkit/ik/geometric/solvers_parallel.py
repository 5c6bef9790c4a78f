"""The three-parallel-axes solver's core (:mod:`.solvers`): axes 2 ∥ 3 ∥ 4, with or without axes 5, 6 meeting.

A plain function; :func:`.solvers.kernels` compiles it with the other cores.
"""

from __future__ import annotations

import math

import numpy as np

from ._kernels import _atan2, _sincos, _t, _tcross, _tnorm, _trot_cs
from .solvers_wrist import SING, _mm, _mtm_to, _mtv, _mv, _mv_to, _perp_to, _rotm_to, _sp1s, _sp1s_cs, _turn_to
from .subproblems import TOL as _SP_TOL
from .subproblems import _TINY as _SP_TINY
from .subproblems import NEAR_TANGENT, _dot, _lin, _sp3cs, _sp4cs, _wrap, rotm, sp1, sp6


# ------------------------------------------------------------------------ three parallel axes
def _core_three_parallel(kind, H, P, RnT, prism, R, p, qref, N, Q, LS, SG, v3, m3, t14, ls14):
    """Axes 2 ∥ 3 ∥ 4 (0-based 1, 2, 3; H[2], H[3] = ±H[1]). ``kind``: 3 general (SP6 for q1, q5),
    4 axes 5, 6 meet (P[5] = 0: SP4, SP4).

    Its work arrays come from the caller (:func:`.solvers_check._core_in`, which zeroes them):
    ``v3 (22, 3)`` for the call's small vectors (rows 14-21: the pairs' cosines and sines), ``m3 (4, 3, 3)`` for
    its matrices (R_06, and those of a singular wrist), ``t14 (15, 4)``: rows 0 and 1 and ``ls14 (4,)`` for the
    (q1, q5) pairs, rows 2-14 the pairs side by side (:func:`_pairs_lanes`; written before they are read)
    (each array made and freed costs ~40 ns and is a call the compiler cannot see through); the subproblems as
    scalars, each angle with its cosine and sine (``_sp4cs``, ``_sp3cs``, ``_sp1s_cs``: no sine or cosine called but
    for SP6's case and a singular wrist), the rotations as turns of vectors by those (``_turn_to``). What makes
    arrays of its own, SP6 of the general case (:func:`_pairs_sp6`) and the singular wrist
    (:func:`_singular_wrist`), is a function of its own, so this one makes none and is compiled without reference
    counts (:data:`.solvers.UNCOUNTED`)."""
    h0 = H[0]
    h1 = H[1]
    h4 = H[4]
    h5 = H[5]
    s2 = 1.0 if _dot(H[2], h1) > 0.0 else -1.0
    s3 = 1.0 if _dot(H[3], h1) > 0.0 else -1.0
    p16, e6, sP, mh0, x5, u, a, b, c, d, w, mP2 = (v3[0], v3[1], v3[2], v3[3], v3[4], v3[5], v3[6], v3[7], v3[8],
                                                   v3[9], v3[10], v3[11])
    g6, f = v3[12], v3[13]
    R06, Rt, R16, R45 = m3[0], m3[1], m3[2], m3[3]
    for i in range(3):   # R_06 = R RnTᵀ, p16 = p - P_0 - R_06 P_6, term by term as _mm and _mv
        for j in range(3):
            R06[i, j] = R[i, 0] * RnT[j, 0] + R[i, 1] * RnT[j, 1] + R[i, 2] * RnT[j, 2]
    for i in range(3):
        p16[i] = p[i] - P[0, i] - (R06[i, 0] * P[6, 0] + R06[i, 1] * P[6, 1] + R06[i, 2] * P[6, 2])
        sP[i] = P[1, i] + P[2, i] + P[3, i] + P[4, i]
        mh0[i] = -h0[i]
        mP2[i] = -P[2, i]
    _mv_to(R06, h5, e6)
    d1 = _dot(h1, sP)
    T0, T4 = t14[0], t14[1]   # the (q1, q5) pairs
    CS0, CS4 = v3[14:18], v3[18:22]   # their cosines and sines (columns 0, 1)
    m14 = 0
    if kind == 4:   # each angle with its cosine and sine (_sp4cs: no acos, no sine or cosine called)
        n0, l0, r00, r01 = _sp4cs(h1, p16, mh0, d1 + _dot(h1, P[5]))
        for i in range(n0):
            t0, ct0, st0 = r00 if i == 0 else r01
            # rot(h0, -t0) e6 (t0: the angle about -h0, as SP4 was asked), by t0's cosine and sine (before
            # 2026-12-07: libm's sin and cos of t0)
            _turn_to(h0, -st0, ct0, e6, a)
            n4, l4, r40, r41 = _sp4cs(h1, h5, h4, _dot(h1, a))
            for j in range(n4):
                t4, ct4, st4 = r40 if j == 0 else r41
                T0[m14] = t0
                T4[m14] = t4
                CS0[m14, 0] = ct0
                CS0[m14, 1] = st0
                CS4[m14, 0] = ct4
                CS4[m14, 1] = st4
                ls14[m14] = bool(l0) or bool(l4)
                m14 += 1
    else:
        m14 = _pairs_sp6(h0, h1, h4, h5, p16, P[5], e6, d1, T0, T4, ls14)
        for i in range(m14):
            CS0[i, 1], CS0[i, 0] = _sincos(T0[i])
            CS4[i, 1], CS4[i, 0] = _sincos(T4[i])
    _perp_to(h5, x5)
    _mv_to(R06, x5, g6)
    # SP6 gives the double root of the singular case to ~1e-8 only: a looser test there (Newton polishes)
    sing_tol = SING if kind == 4 else 1e-6
    # the pairs side by side, each taken where the common case holds (the same bits)
    L = t14[2:]
    lanes = m14 > 0
    if lanes:
        for i in range(PAIR_LANES):     # (rows past m14: zeroes, _core_in's)
            L[9, i] = CS0[i, 0]
            L[10, i] = CS0[i, 1]
            L[11, i] = CS4[i, 0]
            L[12, i] = CS4[i, 1]
        _pairs_lanes(H, P, e6, g6, p16, x5, sing_tol, L)
    m = 0
    for i in range(m14):
        q0 = T0[i]
        q4 = T4[i]
        if lanes and i < PAIR_LANES and L[0, i] != 0.0:
            th, q5 = L[3, i], L[4, i]
            for j in range(2):
                if m >= Q.shape[0]:
                    break
                _put_branch(Q, LS, SG, m, q0, L[6 + 2 * j, i], L[5 + 2 * j, i], th, q4, q5, s2, s3,
                            ls14[i] or L[1 + j, i] != 0.0, False)
                m += 1
            continue
        # R_16 = rot(H[0], q0)ᵀ R_06 and R_45 = rot(H[4], q4) act on vectors only: R_16 H[5] (a), R_16 x (f) and
        # rot(H[0], q0)ᵀ p16 (d) turned by -q0, R_45 H[5] (u) and R_45 P5 (c) by q4; the matrices for a singular
        # wrist alone
        c0, s0 = CS0[i, 0], CS0[i, 1]
        c4, s4 = CS4[i, 0], CS4[i, 1]
        _turn_to(h0, -s0, c0, e6, a)
        _turn_to(h0, -s0, c0, g6, f)
        _turn_to(h0, -s0, c0, p16, d)
        _turn_to(h4, s4, c4, h5, u)
        _turn_to(h4, s4, c4, P[5], c)
        sing = _tnorm(_tcross(u, h1)) < sing_tol
        if sing:     # rot(h5, q5) h6 along h2: q6 free, take q_ref's, then the sum of q2..q4 from it
            q5 = qref[5]
            _rotm_to(h0, q0, Rt)
            _mtm_to(Rt, R06, R16)
            _rotm_to(h4, q4, R45)
            th, lt = _singular_wrist(h1, h5, q5, R45, R16, b)
            l5 = False
            sh, ch = _sincos(th)
        else:
            th, ch, sh, lt = _sp1s_cs(u[0], u[1], u[2], a[0], a[1], a[2], h1[0], h1[1], h1[2])
            _turn_to(h1, -sh, ch, f, w)      # (rot(H[1], th) R_45)ᵀ R_16 x, turn by turn
            _turn_to(h4, -s4, c4, w, b)
            q5, l5 = _sp1s(x5[0], x5[1], x5[2], b[0], b[1], b[2], h5[0], h5[1], h5[2])
        # d = rot(H[0], q0)ᵀ p16 - P1 - rot(H[1], th) (P4 + R45 P5)
        for k in range(3):
            b[k] = P[4, k] + c[k]
        _turn_to(h1, sh, ch, b, c)
        for k in range(3):
            d[k] = d[k] - P[1, k] - c[k]
        n2, l2, r20, r21 = _sp3cs(P[3], mP2, H[2], _tnorm(d))
        for j in range(n2):
            t2, ct2, st2 = r20 if j == 0 else r21
            _turn_to(H[2], st2, ct2, P[3], a)
            for k in range(3):
                w[k] = P[2, k] + a[k]
            q1, l1 = _sp1s(w[0], w[1], w[2], d[0], d[1], d[2], h1[0], h1[1], h1[2])
            if m >= Q.shape[0]:
                break
            _put_branch(Q, LS, SG, m, q0, q1, t2, th, q4, q5, s2, s3,
                        ls14[i] or bool(lt) or bool(l5) or bool(l2) or bool(l1), sing)
            m += 1
    return m


def _put_branch(Q, LS, SG, m, q0, q1, t2, th, q4, q5, s2, s3, ls, sing):
    """Candidate ``m`` of :func:`_core_three_parallel`: q1, q2, q3, then q4 from the sum ``th`` of q2, q3, q4 (``s2``,
    ``s3``: axes 3 and 4 along axis 2 or against it), q5, q6 wrapped; its flags."""
    Q[m, 0] = q0
    Q[m, 1] = q1
    Q[m, 2] = t2
    Q[m, 3] = _wrap(s3 * (th - q1 - s2 * t2))
    Q[m, 4] = q4
    Q[m, 5] = _wrap(q5)
    LS[m] = ls
    SG[m] = sing


PAIR_LANES = 4
"""(q1, q5) pairs whose rest :func:`_pairs_lanes` solves side by side (SP6 and two SP4s give at most 4)."""


def _pairs_lanes(H, P, e6, g6, p16, x5, sing_tol, L):
    """The rest of the three-parallel core for the first :data:`PAIR_LANES` (q1, q5) pairs side by side, by its
    common case: a wrist that is not singular and an SP3 for q3 with two exact answers away from its tangent.
    ``L (13, PAIR_LANES)``, pair ``i`` in column ``i``. Rows 9-12 are the caller's: the cosine and sine of q1, then
    of q5. Rows 0-8 are the answers: row 0 whether the common case holds (1.0; 0.0: the caller takes that pair one
    by one), rows 1 and 2 whether an SP1 of the first or second branch is least squares, row 3 the sum of q2..q4
    (``th``), row 4 q6 (not wrapped), rows 5, 6 the first branch's q3, q2 and rows 7, 8 the second's.

    The operations of :func:`_core_three_parallel`'s loop and of ``_sp3cs`` for such a pair, in the same order (the
    same bits), written with no function called but the inline ``atan2``, square roots and ``floor``, so that the
    loop compiles to vector instructions (its caller is compiled with NumPy's error model, as the spherical core:
    :data:`.solvers.VECTOR`). The axes and vectors are tuples, the loop's length ``L.shape[1]`` (see
    :func:`.solvers_wrist._wrist_lanes` for why)."""
    h0, h1, H2, h4, h5 = _t(H[0]), _t(H[1]), _t(H[2]), _t(H[4]), _t(H[5])
    P1, P2, P3, P4, P5 = _t(P[1]), _t(P[2]), _t(P[3]), _t(P[4]), _t(P[5])
    mP2 = (-P2[0], -P2[1], -P2[2])
    e6, g6, p16, x5 = _t(e6), _t(g6), _t(p16), _t(x5)
    pp = _dot(P3, P3) + _dot(mP2, mP2)
    a3, b3, c3 = _lin(mP2, H2, P3)        # (_sp3cs(P[3], -P[2], H[2], ‖d‖): its terms that do not depend on d)
    for i in range(L.shape[1]):
        c0, s0, c4, s4 = L[9, i], L[10, i], L[11, i], L[12, i]
        a = _trot_cs(h0, c0, -s0, e6)
        f = _trot_cs(h0, c0, -s0, g6)
        d = _trot_cs(h0, c0, -s0, p16)
        u = _trot_cs(h4, c4, s4, h5)
        c = _trot_cs(h4, c4, s4, P5)
        sing = _tnorm(_tcross(u, h1)) < sing_tol
        th, ch, sh, lt = _sp1s_cs(u[0], u[1], u[2], a[0], a[1], a[2], h1[0], h1[1], h1[2])
        w = _trot_cs(h1, ch, -sh, f)
        b = _trot_cs(h4, c4, -s4, w)
        q5, l5 = _sp1s(x5[0], x5[1], x5[2], b[0], b[1], b[2], h5[0], h5[1], h5[2])
        c = _trot_cs(h1, ch, sh, (P4[0] + c[0], P4[1] + c[1], P4[2] + c[2]))
        d = (d[0] - P1[0] - c[0], d[1] - P1[1] - c[1], d[2] - P1[2] - c[2])
        nd = _tnorm(d)
        # _sp3cs, then _trig1cs's case of two answers
        target = 0.5 * (pp - nd * nd)
        scale = max(pp + nd * nd, _SP_TINY)
        x = target - c3
        r = math.sqrt(a3 * a3 + b3 * b3)
        good = r > _SP_TOL * scale
        r = r if good else 1.0          # (a lane that is not taken divides by 1: no error raised)
        ca = a3 / r
        sa = b3 / r
        x = x / r
        good = good & (abs(x) <= 1.0)
        good = good & (not 1.0 - x * x < NEAR_TANGENT) & (not sing)
        sw = math.sqrt(1.0 - x * x if good else 1.0)
        ct2 = ca * x - sa * sw
        st2 = sa * x + ca * sw
        t2 = _wrap(_atan2(st2, ct2))
        q1, l1 = _pair_q2(H2, P2, P3, h1, d, ct2, st2)
        ct2 = ca * x + sa * sw
        st2 = sa * x - ca * sw
        u2 = _wrap(_atan2(st2, ct2))
        v1, m1 = _pair_q2(H2, P2, P3, h1, d, ct2, st2)
        L[0, i] = 1.0 if good else 0.0
        L[1, i] = 1.0 if lt | l5 | l1 else 0.0
        L[2, i] = 1.0 if lt | l5 | m1 else 0.0
        L[3, i] = th
        L[4, i] = q5
        L[5, i] = t2
        L[6, i] = q1
        L[7, i] = u2
        L[8, i] = v1


def _pair_q2(H2, P2, P3, h1, d, ct2, st2):
    """q2 of one branch of :func:`_pairs_lanes` (SP1 of ``P2 + rot(h3, q3) P3`` onto ``d``): ``(q2, ls)``."""
    a = _trot_cs(H2, ct2, st2, P3)
    return _sp1s(P2[0] + a[0], P2[1] + a[1], P2[2] + a[2], d[0], d[1], d[2], h1[0], h1[1], h1[2])


def _pairs_sp6(h0, h1, h4, h5, p16, P5, e6, d1, T0, T4, ls14):
    """The (q1, q5) pairs of the general three-parallel case by SP6 into ``T0``, ``T4``, ``ls14``; their count. A
    function of its own (it makes SP6's arrays), counted, called by the uncounted core."""
    Hs = np.empty((4, 3))
    Ks = np.empty((4, 3))
    Ps = np.empty((4, 3))
    Hs[0] = h1
    Hs[1] = -h1
    Hs[2] = h1
    Hs[3] = -h1
    Ks[0] = -h0
    Ks[1] = h4
    Ks[2] = -h0
    Ks[3] = h4
    Ps[0] = p16
    Ps[1] = P5
    Ps[2] = e6
    Ps[3] = h5
    t0s, t4s, n, l6 = sp6(Hs, Ks, Ps, d1, 0.0)
    for i in range(n):
        T0[i] = t0s[i]
        T4[i] = t4s[i]
        ls14[i] = l6
    return n


def _singular_wrist(h1, h5, q5, R45, R16, b):
    """``(θ, ls)`` of the singular wrist of the three-parallel core (``rot(h5, q5) h6`` along h2, q6 = ``q5`` taken
    from q_ref): ``rot(h2, θ) M y' = R16 y'`` for ``y' = Mᵀ y`` with ``M = R45 rot(h5, q5)`` and ``y = b``, a vector
    across h2 (written into ``b``). A function of its own (it makes arrays), counted, called by the uncounted
    core."""
    M = _mm(R45, rotm(h5, q5))
    _perp_to(h1, b)
    return sp1(b, _mv(R16, _mtv(M, b)), h1)   # rot(h2, th) M y' = R16 y' for y' = Mᵀ y
