"""The three-parallel-axes solver's core (:mod:`.solvers`): axes 2 ∥ 3 ∥ 4, with or without axes 5, 6 meeting.

A plain function; :func:`.solvers.kernels` compiles it with the other cores.
"""

from __future__ import annotations

import math

import numpy as np

from .solvers_wrist import SING, _mm, _mtm, _mtv, _mv, _perp
from .subproblems import _cross, _dot, _norm, _wrap, rot, rotm, sp1, sp3, sp4, sp6


# ------------------------------------------------------------------------ three parallel axes
def _core_three_parallel(kind, H, P, RnT, prism, R, p, qref, N, Q, LS, SG):
    """Axes 2 ∥ 3 ∥ 4 (0-based 1, 2, 3; H[2], H[3] = ±H[1]). ``kind``: 3 general (SP6 for q1, q5),
    4 axes 5, 6 meet (P[5] = 0: SP4, SP4)."""
    h0 = H[0]
    h1 = H[1]
    h4 = H[4]
    h5 = H[5]
    s2 = 1.0 if _dot(H[2], h1) > 0.0 else -1.0
    s3 = 1.0 if _dot(H[3], h1) > 0.0 else -1.0
    R06 = _mm(R, RnT.T.copy())
    p16 = p - P[0] - _mv(R06, P[6])
    e6 = _mv(R06, h5)
    d1 = _dot(h1, P[1] + P[2] + P[3] + P[4])
    T0 = np.zeros(4)
    T4 = np.zeros(4)
    ls14 = np.zeros(4, dtype=np.bool_)
    m14 = 0
    if kind == 4:
        t0, n0, l0 = sp4(h1, p16, -h0, d1 + _dot(h1, P[5]))
        for i in range(n0):
            t4, n4, l4 = sp4(h1, h5, h4, _dot(h1, rot(h0, -t0[i], e6)))
            for j in range(n4):
                T0[m14] = t0[i]
                T4[m14] = t4[j]
                ls14[m14] = bool(l0) or bool(l4)
                m14 += 1
    else:
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
        Ps[1] = P[5]
        Ps[2] = e6
        Ps[3] = h5
        t0, t4, n, l6 = sp6(Hs, Ks, Ps, d1, 0.0)
        for i in range(n):
            T0[i] = t0[i]
            T4[i] = t4[i]
            ls14[i] = l6
        m14 = n
    x5 = _perp(h5)
    m = 0
    for i in range(m14):
        q0 = T0[i]
        q4 = T4[i]
        R16 = _mtm(rotm(h0, q0), R06)
        R45 = rotm(h4, q4)
        u = _mv(R45, h5)
        # SP6 gives the double root of the singular case to ~1e-8 only: a looser test there (Newton polishes)
        sing = _norm(_cross(u, h1)) < (SING if kind == 4 else 1e-6)
        if sing:     # rot(h5, q5) h6 along h2: q6 free, take q_ref's, then the sum of q2..q4 from it
            q5 = qref[5]
            M = _mm(R45, rotm(h5, q5))
            y = _perp(h1)
            th, lt = sp1(y, _mv(R16, _mtv(M, y)), h1)   # rot(h2, th) M y' = R16 y' for y' = Mᵀ y
            l5 = False
        else:
            th, lt = sp1(u, _mv(R16, h5), h1)
            R15 = _mm(rotm(h1, th), R45)
            q5, l5 = sp1(x5, _mtv(R15, _mv(R16, x5)), h5)
        d = _mtv(rotm(h0, q0), p16) - P[1] - rot(h1, th, P[4] + _mv(R45, P[5]))
        t2, n2, l2 = sp3(P[3], -P[2], H[2], _norm(d))
        for j in range(n2):
            w = P[2] + rot(H[2], t2[j], P[3])
            q1, l1 = sp1(w, d, h1)
            if m >= Q.shape[0]:
                break
            Q[m, 0] = q0
            Q[m, 1] = q1
            Q[m, 2] = t2[j]
            Q[m, 3] = _wrap(s3 * (th - q1 - s2 * t2[j]))
            Q[m, 4] = q4
            Q[m, 5] = _wrap(q5)
            LS[m] = ls14[i] or bool(lt) or bool(l5) or bool(l2) or bool(l1)
            SG[m] = sing
            m += 1
    return m
