"""The cores of the classes solved by a 1-D search (:mod:`.solvers`): the search of :mod:`.search`, completed by
subproblems into whole solutions.

Plain functions; :func:`.solvers.kernels` compiles them with the other cores.
"""

from __future__ import annotations

import math

import numpy as np

from .search import MAXROOT, SM, TI, TP, _search
from .solvers_wrist import _mm, _mtm, _mtv, _mv, _perp, _wrist
from .subproblems import _dot, _wrap, rot, rotm, sp1


# ------------------------------------------------------- 1-D searches of :mod:`.search`, completed
def _target_rows(R06, p):
    """``C (4, 3)`` of the searches TP and SM: the rows of ``R_06``, then ``p``."""
    C = np.zeros((4, 3))
    for i in range(3):
        for j in range(3):
            C[i, j] = R06[i, j]
        C[3, i] = p[i]
    return C


def _core_two_intersecting_end(kind, H, P, RnT, prism, R, p, qref, N, Q, LS, SG):
    """6R, axes 5 and 6 meet (P[5] = 0): q1..q4 by the search TI (q1 searched, SP5 inside), q5 and q6 by SP1."""
    R06 = _mm(R, RnT.T.copy())
    p0w = p - P[0] - _mv(R06, P[6])
    e6 = _mv(R06, H[5])
    C = np.zeros((4, 3))
    for k in range(3):
        C[0, k] = e6[k]
        C[1, k] = p0w[k]
    Qp = np.zeros((MAXROOT, 4))
    mp = _search(TI, H, P, C, N, Qp)
    x = _perp(H[5])
    y = _mv(R06, x)
    m = 0
    for i in range(mp):
        R04 = _mm(_mm(rotm(H[0], Qp[i, 0]), rotm(H[1], Qp[i, 1])), _mm(rotm(H[2], Qp[i, 2]), rotm(H[3], Qp[i, 3])))
        q4, l4 = sp1(H[5], _mtv(R04, e6), H[4])
        R05 = _mm(R04, rotm(H[4], q4))
        q5, l5 = sp1(x, _mtv(R05, y), H[5])
        if m >= Q.shape[0]:
            break
        for k in range(4):
            Q[m, k] = Qp[i, k]
        Q[m, 4] = q4
        Q[m, 5] = q5
        LS[m] = False
        SG[m] = False
        m += 1
    return m


def _core_two_parallel(kind, H, P, RnT, prism, R, p, qref, N, Q, LS, SG):
    """6R, axes 2 ∥ 3: ``(q6, q1, q4, θ = q2 ± q3)`` by the search TP (q6 searched, SP6 inside), then q2 by SP1
    (``rot(h2, q2) P3 = d``), q3 from θ, q5 by SP1."""
    R06 = _mm(R, RnT.T.copy())
    C = _target_rows(R06, p)
    roots = np.zeros((MAXROOT, 4))
    nr = _search(TP, H, P, C, N, roots)
    sgn = 1.0 if _dot(H[1], H[2]) > 0.0 else -1.0
    y = _perp(H[4])
    m = 0
    for r in range(nr):
        x = roots[r, 0]
        q0 = roots[r, 1]
        q3 = roots[r, 2]
        th = roots[r, 3]
        R05 = _mm(R06, rotm(H[5], -x))
        w = p - P[0] - _mv(R05, P[5]) - _mv(R06, P[6])
        R0t = rotm(H[0], -q0)
        d = _mv(R0t, w) - P[1] - rot(H[1], th, P[3] + rot(H[3], q3, P[4]))
        q1, l1 = sp1(P[2], d, H[1])
        M = _mtm(_mm(rotm(H[1], th), rotm(H[3], q3)), _mm(R0t, R05))     # rot(h5, q5)
        q4, l4 = sp1(y, _mv(M, y), H[4])
        if m >= Q.shape[0]:
            break
        Q[m, 0] = q0
        Q[m, 1] = q1
        Q[m, 2] = _wrap(sgn * (th - q1))
        Q[m, 3] = q3
        Q[m, 4] = q4
        Q[m, 5] = _wrap(x)
        LS[m] = False
        SG[m] = False
        m += 1
    return m


def _core_spherical_middle(kind, H, P, RnT, prism, R, p, qref, N, Q, LS, SG):
    """6R, axes 2, 3, 4 meet (P[2] = P[3] = 0): ``(q6, q1)`` by the search SM (q6 searched, SP3 inside), q5 by
    SP1, then the spherical joint (q2, q3, q4) as a wrist (SP2, SP1)."""
    R06 = _mm(R, RnT.T.copy())
    C = _target_rows(R06, p)
    roots = np.zeros((MAXROOT, 4))
    nr = _search(SM, H, P, C, N, roots)
    W = np.zeros((2, 3))
    S = np.empty((5, 3))          # the wrist's work space (_wrist)
    M = np.empty((3, 3, 3))
    m = 0
    for r in range(nr):
        x = roots[r, 0]
        q0 = roots[r, 1]
        R05 = _mm(R06, rotm(H[5], -x))
        u = p - P[0] - _mv(R05, P[5]) - _mv(R06, P[6])
        d = u - rot(H[0], q0, P[1])
        phi, l4 = sp1(P[4], _mtv(R05, d), H[4])          # rot(h5, −q5) P5 = R_05ᵀ d
        R14 = _mtm(rotm(H[0], q0), _mm(R05, rotm(H[4], phi)))
        mw, lsw, sing = _wrist(H[1], H[2], H[3], R14, qref[1], W, S, M)
        for j in range(mw):
            if m >= Q.shape[0]:
                break
            Q[m, 0] = q0
            Q[m, 1] = W[j, 0]
            Q[m, 2] = W[j, 1]
            Q[m, 3] = W[j, 2]
            Q[m, 4] = _wrap(-phi)
            Q[m, 5] = _wrap(x)
            LS[m] = lsw
            SG[m] = sing
            m += 1
    return m
