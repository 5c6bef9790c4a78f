"""Every IK solution of a 6-joint chain in closed form, by subproblem decomposition (IK-Geo style).

Each solver takes a :class:`~.poe.POE` and one target ``(R (3, 3), p (3,))`` and returns a
:class:`Solutions` ``(q (m, n), ls (m,), singular (m,))``: all solutions, each checked by
:meth:`POE.fk` to :data:`TOL` times the arm's size (position) and :data:`TOL` rad (rotation).
``ls`` is True only when the target is out of reach: then no solution passes the check and the
least-squares candidates are returned instead (``m`` may also be 0). ``singular`` marks a
solution at a singularity that leaves a family of solutions; one member is returned, with the
free joint at ``q_ref`` (0 without it). Revolute angles are in (-π, π]; a prismatic joint's
value is a length. Joints are numbered from 1 in the text below, from 0 in the code.

=================================== ==========================================================
solver                              axes (the classifier checks them; the solvers assume them)
=================================== ==========================================================
``spherical_two_intersecting``      4, 5, 6 meet; 1, 2 meet (Puma, Jaco, Stanford: joint 3 may
                                    be prismatic). SP3 (q3), SP2 (q1, q2).
``spherical_two_parallel``          4, 5, 6 meet; 2 ∥ 3. SP4 (q1), SP3 (q3), SP1 (q2).
``spherical``                       4, 5, 6 meet. 1-D search over q1 (:mod:`.search`, kind SW):
                                    q3 by SP3, the axis-2 component as residual; SP1 (q2).
``three_parallel``                  2 ∥ 3 ∥ 4. SP6 (q1, q5), SP1 (q2+q3+q4, q6), SP3 (q3), SP1 (q2).
``three_parallel_two_intersecting`` 2 ∥ 3 ∥ 4; 5, 6 meet (UR). SP4 (q1), SP4 (q5), then as above.
``spherical_base``                  1, 2, 3 meet (a spherical wrist at the base): the reversed
                                    chain (:func:`reverse`) by ``spherical_wrist``.
``two_intersecting``                5, 6 meet; no two of axes 2, 3, 4 parallel (else SP5
                                    degenerates). 1-D search over q1 (kind TI) with SP5 (q2, q3,
                                    q4) and the axis-5/6 angle as residual; SP1 (q5), SP1 (q6).
``two_parallel``                    2 ∥ 3: 1-D search over q6 (kind TP) with SP6 (q1, q4) and
                                    the distance residual; SP1 (q2, q5).
``spherical_middle``                2, 3, 4 meet: 1-D search over q6 (kind SM) with SP3 (q1) and
                                    the axis-5 component as residual; SP1 (q5), the spherical
                                    joint as a wrist (q2, q3, q4).
=================================== ==========================================================

The 1-D searches share one compiled engine (:mod:`.search`): :data:`SEARCH_N` samples over a
turn, branches followed from sample to sample, sign changes refined by false position, branch
ends and near-zero extrema searched; their resolution is stated there. Up to 16 solutions.

Every spherical-wrist solver ends with the wrist: SP2 (q4, q5) on the axis-6 direction and SP1
(q6); when axes 4 and 6 line up (``R_36 h6 ∥ h4``) q4 is set to ``q_ref[3]`` and ``singular`` set.

Before solving, :func:`align` slides the points of ``P`` along their axes so that axes that
meet share one point (and makes parallel axes exactly parallel): the solvers work on that
*ideal* chain. When the robot's axes only nearly meet or are nearly parallel, the ideal chain
differs from the true one, and each solution is polished by Newton steps on the true chain
(:func:`polish`, Jacobian from the POE) before the check.

The solver cores use only scalar math and small arrays, like :mod:`.subproblems`:
:func:`kernels` compiles them with Numba (``njit(cache=True)``, on first use: about a minute
for all of them, then loaded from Numba's disk cache in about a second). The wrappers use
them when armkit's back end is Numba (:func:`armkit.set_backend`; for ``"auto"`` once armkit's
own kernels are ready), the plain functions otherwise; ``jit=True`` / ``jit=False`` force one.
"""

from __future__ import annotations

import math
import types
import weakref
from typing import Any, Callable, NamedTuple, Optional

import numpy as np
from numpy.typing import NDArray

from . import _kernels as _kk
from . import subproblems as _sp
from .classify import common_point
from . import search2d as _search2d
from ._kernels import _fk_err
from .poe import POE
from .search import MAXROOT, SM, SW, TI, TP, _search
from .search import N as _SEARCH_N
from .search import kernels as _search_kernels
from .subproblems import _cross, _dot, _norm, _wrap, rot, rotm, sp1, sp2, sp3, sp4, sp5, sp6

__all__ = ["Solutions", "solve_batch", "align", "reverse", "polish", "spherical_two_intersecting", "spherical_two_parallel",
           "spherical", "spherical_wrist", "three_parallel", "three_parallel_two_intersecting", "spherical_base",
           "two_intersecting", "two_parallel", "spherical_middle",
           "SOLVERS", "TOL", "SEARCH_N", "kernels"]

Array = NDArray[np.float64]

TOL = 1e-9
"""Check of every returned solution: position error ≤ TOL × arm size, rotation error ≤ TOL rad."""
SEARCH_N = _SEARCH_N
"""Samples of the searched joint over one turn in the 1-D searches (:data:`.search.N`)."""
SING = 1e-10
"""``‖h4 × R_36 h6‖`` below this: the wrist is singular (axes 4 and 6 in line)."""
MAXSOL = 32


class Solutions(NamedTuple):
    """All solutions ``q (m, n)``; ``ls (m,)``: least-squares candidates of an unreachable target;
    ``singular (m,)``: one member of a family of solutions (the free joint at ``q_ref``)."""
    q: Array
    ls: NDArray[np.bool_]
    singular: NDArray[np.bool_]


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


# ------------------------------------------------------------------------------------ the wrist
def _wrist(h3, h4, h5, R36, q3ref, W):
    """q4, q5, q6 (0-based 3, 4, 5) with ``rot(h4, q4) rot(h5, q5) rot(h6, q6) = R36``, into ``W (2, 3)``:
    ``(count, ls, singular)``."""
    v = _mv(R36, h5)
    x = _perp(h5)
    y = _mv(R36, x)
    if _norm(_cross(h3, v)) < SING:     # axes 4 and 6 in line: q4 free
        q3 = q3ref
        u = rot(h3, -q3, v)
        q4, l1 = sp1(h5, u, h4)
        R35 = _mm(rotm(h3, q3), rotm(h4, q4))
        q5, l2 = sp1(x, _mtv(R35, y), h5)
        W[0, 0] = _wrap(q3)
        W[0, 1] = q4
        W[0, 2] = q5
        return 1, bool(l1) or bool(l2), True
    t3, t4, m, ls = sp2(v, h5, -h3, h4)
    for i in range(m):
        R35 = _mm(rotm(h3, t3[i]), rotm(h4, t4[i]))
        q5, l2 = sp1(x, _mtv(R35, y), h5)
        W[i, 0] = t3[i]
        W[i, 1] = t4[i]
        W[i, 2] = q5
        ls = bool(ls) or bool(l2)
    return m, ls, False


# ------------------------------------------------------------------ spherical wrist: position
def _pos_two_intersecting(H, P, prism2, p0W, Qp, LSp):
    """Axes 1, 2 meet (P[1] = 0): ``p0W = rot(h1, q1) rot(h2, q2) (P2 + rot(h3, q3) P3)``
    (joint 3 prismatic: ``P2 + q3 h3 + P3``)."""
    h0 = H[0]
    h1 = H[1]
    h2 = H[2]
    d = _norm(p0W)
    t2 = np.zeros(2)
    if prism2:
        a = P[2] + P[3]
        b = _dot(h2, a)
        c = _dot(a, a) - d * d
        disc = b * b - c
        scale = max(_dot(a, a) + d * d, 1e-300)
        if disc > 1e-12 * scale:
            s = math.sqrt(disc)
            t2[0] = -b + s
            t2[1] = -b - s
            n2 = 2
        else:
            t2[0] = -b
            n2 = 1
        ls2 = disc < -1e-12 * scale
    else:
        t2, n2, ls2 = sp3(P[3], -P[2], h2, d)
    m = 0
    for j in range(n2):
        if prism2:
            w = P[2] + t2[j] * h2 + P[3]
        else:
            w = P[2] + rot(h2, t2[j], P[3])
        t0, t1, n, ls = sp2(p0W, w, -h0, h1)
        for i in range(n):
            Qp[m, 0] = t0[i]
            Qp[m, 1] = t1[i]
            Qp[m, 2] = t2[j]
            LSp[m] = bool(ls) or bool(ls2)
            m += 1
    return m


def _pos_two_parallel(H, P, p0W, Qp, LSp):
    """Axes 2 ∥ 3: the axis-2 component of ``rot(h1, q1)ᵀ p0W`` fixes q1 (SP4), then SP3, SP1."""
    h0 = H[0]
    h1 = H[1]
    h2 = H[2]
    t0, n0, ls0 = sp4(h1, p0W, -h0, _dot(h1, P[1] + P[2] + P[3]))
    m = 0
    for i in range(n0):
        v = rot(h0, -t0[i], p0W) - P[1]
        t2, n2, ls2 = sp3(P[3], -P[2], h2, _norm(v))
        for j in range(n2):
            w = P[2] + rot(h2, t2[j], P[3])
            t1, ls1 = sp1(w, v, h1)
            Qp[m, 0] = t0[i]
            Qp[m, 1] = t1
            Qp[m, 2] = t2[j]
            LSp[m] = bool(ls0) or bool(ls2) or bool(ls1)
            m += 1
    return m


def _pos_general(H, P, p0W, N, Qp, LSp):
    """General 3R position ``p0W = rot(h1, q1) (P1 + rot(h2, q2) (P2 + rot(h3, q3) P3))`` in closed form:
    moved to ``-P1 + rot(h1, -q1) p0W = rot(h2, q2) (P2 + rot(h3, q3) P3)``, which is SP5 (a quartic; up to
    4 solutions, least-squares ones flagged). SP5's length equation depends on q1 only through the distance of
    the point chosen on axis 2 from axis 1, so that point is slid along axis 2 (``P1 + s h2``, ``P2 - s h2``: the
    same chain) until that distance is about the arm's size; where axes 1 and 2 meet it would be 0 and the
    system singular. Axes 2 ∥ 3 make its component equation independent of q3: :func:`_pos_two_parallel`
    answers. Axes 1 ∥ 2 make it independent of q1: that chain takes the 1-D search (:func:`_pos_search`)."""
    h0 = H[0]
    h1 = H[1]
    if _norm(_cross(h1, H[2])) < 1e-9:
        return _pos_two_parallel(H, P, p0W, Qp, LSp)
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


def _core_spherical(kind, H, P, RnT, prism, R, p, qref, N, Q, LS, SG):
    """Spherical wrist at the end (P[4] = P[5] = 0): candidates into Q, LS, SG; returns their count.
    ``kind``: 0 axes 1, 2 meet; 1 axes 2 ∥ 3; 2 general (SP5)."""
    R06 = _mm(R, RnT.T.copy())
    p0W = p - P[0] - _mv(R06, P[6])
    Qp = np.zeros((8, 3))
    LSp = np.zeros(8, dtype=np.bool_)
    if kind == 0:
        mp = _pos_two_intersecting(H, P, prism[2], p0W, Qp, LSp)
    elif kind == 1:
        mp = _pos_two_parallel(H, P, p0W, Qp, LSp)
    else:
        mp = _pos_general(H, P, p0W, N, Qp, LSp)
    W = np.zeros((2, 3))
    m = 0
    for i in range(mp):
        R03 = rotm(H[0], Qp[i, 0])
        R03 = _mm(R03, rotm(H[1], Qp[i, 1]))
        if not prism[2]:
            R03 = _mm(R03, rotm(H[2], Qp[i, 2]))
        R36 = _mtm(R03, R06)
        mw, lsw, sing = _wrist(H[3], H[4], H[5], R36, qref[3], W)
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
    m = 0
    for r in range(nr):
        x = roots[r, 0]
        q0 = roots[r, 1]
        R05 = _mm(R06, rotm(H[5], -x))
        u = p - P[0] - _mv(R05, P[5]) - _mv(R06, P[6])
        d = u - rot(H[0], q0, P[1])
        phi, l4 = sp1(P[4], _mtv(R05, d), H[4])          # rot(h5, −q5) P5 = R_05ᵀ d
        R14 = _mtm(rotm(H[0], q0), _mm(R05, rotm(H[4], phi)))
        mw, lsw, sing = _wrist(H[1], H[2], H[3], R14, qref[1], W)
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


def _solve_two_intersecting_end(kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r, Q, LS, SG, ST):
    m = _core_two_intersecting_end(kind, Hi, Pi, RnT, prism, R, p, qref, N, Q, LS, SG)
    return _check(m, Ht, Pt, RnT, prism, R, p, tol_p, tol_r, Q, LS, SG, ST)


def _solve_two_parallel(kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r, Q, LS, SG, ST):
    m = _core_two_parallel(kind, Hi, Pi, RnT, prism, R, p, qref, N, Q, LS, SG)
    return _check(m, Ht, Pt, RnT, prism, R, p, tol_p, tol_r, Q, LS, SG, ST)


def _solve_spherical_middle(kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r, Q, LS, SG, ST):
    m = _core_spherical_middle(kind, Hi, Pi, RnT, prism, R, p, qref, N, Q, LS, SG)
    return _check(m, Ht, Pt, RnT, prism, R, p, tol_p, tol_r, Q, LS, SG, ST)


def _check(m, H, P, RnT, prism, R, p, tol_p, tol_r, Q, LS, SG, ST):
    """Wrap the angles of the ``m`` candidates and check each on the true chain; then put the ones that
    pass (repeats dropped) first and the ones that fail after them (rows of Q, LS, SG; ``ST`` 1 / 0).
    Returns ``(passing, failing)``."""
    for i in range(m):
        for k in range(Q.shape[1]):
            if not prism[k]:
                Q[i, k] = _wrap(Q[i, k])
        ep, er = _fk_err(H, P, RnT, prism, Q[i], R, p)
        ST[i] = 1 if (ep <= tol_p and er <= tol_r) else 0
        if ST[i] == 1:
            for j in range(i):
                if ST[j] == 1 and _close(Q[i], Q[j], prism):
                    ST[i] = 2
                    break
    Qc = Q[:m].copy()
    LSc = LS[:m].copy()
    SGc = SG[:m].copy()
    STc = ST[:m].copy()
    ng = 0
    for i in range(m):
        if STc[i] == 1:
            Q[ng] = Qc[i]
            LS[ng] = LSc[i]
            SG[ng] = SGc[i]
            ST[ng] = 1
            ng += 1
    nf = 0
    for i in range(m):
        if STc[i] == 0:
            Q[ng + nf] = Qc[i]
            LS[ng + nf] = LSc[i]
            SG[ng + nf] = SGc[i]
            ST[ng + nf] = 0
            nf += 1
    return ng, nf


def _close(a, b, prism):
    for k in range(a.shape[0]):
        d = abs(a[k] - b[k])
        if not prism[k]:
            d = abs(_wrap(a[k] - b[k]))
        if d > 1e-8:
            return False
    return True


def _solve_spherical(kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r, Q, LS, SG, ST):
    m = _core_spherical(kind, Hi, Pi, RnT, prism, R, p, qref, N, Q, LS, SG)
    return _check(m, Ht, Pt, RnT, prism, R, p, tol_p, tol_r, Q, LS, SG, ST)


def _solve_three_parallel(kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r, Q, LS, SG, ST):
    m = _core_three_parallel(kind, Hi, Pi, RnT, prism, R, p, qref, N, Q, LS, SG)
    return _check(m, Ht, Pt, RnT, prism, R, p, tol_p, tol_r, Q, LS, SG, ST)


def _batch(which, kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r, Q, LS, SG, ST, NG, NF):
    """Every target of a batch in one call: ``R (B, 3, 3)``, ``p (B, 3)``, ``qref (B, n)``; per target
    the solutions ``Q[b]`` and flags as one call of the kernel ``which`` (0 spherical, 1 three parallel,
    2 two intersecting, 3 two parallel, 4 spherical middle) would give them, and their counts ``NG`` (good), ``NF`` (failed the check)."""
    for b in range(R.shape[0]):
        if which == 0:
            ng, nf = _solve_spherical(kind, Hi, Pi, RnT, prism, Ht, Pt, R[b], p[b], qref[b], N, tol_p, tol_r,
                                      Q[b], LS[b], SG[b], ST[b])
        elif which == 1:
            ng, nf = _solve_three_parallel(kind, Hi, Pi, RnT, prism, Ht, Pt, R[b], p[b], qref[b], N, tol_p, tol_r,
                                           Q[b], LS[b], SG[b], ST[b])
        elif which == 2:
            ng, nf = _solve_two_intersecting_end(kind, Hi, Pi, RnT, prism, Ht, Pt, R[b], p[b], qref[b], N, tol_p,
                                                 tol_r, Q[b], LS[b], SG[b], ST[b])
        elif which == 3:
            ng, nf = _solve_two_parallel(kind, Hi, Pi, RnT, prism, Ht, Pt, R[b], p[b], qref[b], N, tol_p, tol_r,
                                         Q[b], LS[b], SG[b], ST[b])
        else:
            ng, nf = _solve_spherical_middle(kind, Hi, Pi, RnT, prism, Ht, Pt, R[b], p[b], qref[b], N, tol_p, tol_r,
                                             Q[b], LS[b], SG[b], ST[b])
        NG[b] = ng
        NF[b] = nf


def _sweep(which, kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r, Q, LS, SG, ST, NG, NF):
    """:func:`_batch` for ``V`` chains of one class at once (a joint of a 7-joint arm held at ``V`` values,
    :mod:`.locked`): ``Hi (V, 6, 3)``, ``Pi (V, 7, 3)``, ``RnT (V, 3, 3)``, ``Ht``, ``Pt`` likewise, ``tol_p (V,)``;
    outputs with a leading ``V`` axis."""
    for v in range(Hi.shape[0]):
        _batch(which, kind, Hi[v], Pi[v], RnT[v], prism, Ht[v], Pt[v], R, p, qref, N, tol_p[v], tol_r, Q[v], LS[v],
               SG[v], ST[v], NG[v], NF[v])


# ----------------------------------------------------------------------------- the chain
def _points(P: Array) -> Array:
    """Points on axes 1..n (rows 0..n-1) and the tool origin (row n), world frame, q = 0."""
    return np.cumsum(P, axis=0)


def align(form: POE, meet: tuple[tuple[int, ...], ...] = (), parallel: tuple[tuple[int, ...], ...] = ()
          ) -> tuple[POE, float]:
    """The ideal chain for a solver, and how far it is from ``form``.

    Axes of each group in ``parallel`` (0-based joint indices) get one common direction (the
    mean, signs kept); the points of the axes of each group in ``meet`` are all moved to the
    point nearest to those axes (least squares), so that the P between them is 0. Exact
    robots only slide points along their axes (the same chain); for nearly meeting or
    parallel axes the returned chain is the nearest ideal one.

    Returns
    -------
    (POE, float)
        The ideal chain and the deviation: the largest axis-direction change (rad) or the
        largest distance of a moved point from its axis divided by the arm size.
    """
    H = np.array(form.H, dtype=float)
    pts = _points(np.asarray(form.P, dtype=float))
    n = form.n
    scale = _size(form)
    dev = 0.0
    for group in parallel:
        ref = H[group[0]]
        acc = np.zeros(3)
        for k in group:
            acc += H[k] if H[k] @ ref >= 0 else -H[k]
        acc /= np.linalg.norm(acc)
        for k in group:
            new = acc if H[k] @ ref >= 0 else -acc
            dev = max(dev, float(np.linalg.norm(new - H[k])))
            H[k] = new
    for group in meet:
        c, _ = common_point(H, pts, group)      # the point nearest to all the group's lines (the classifier's)
        for k in group:
            off = c - pts[k]
            dev = max(dev, float(np.linalg.norm(off - H[k] * (H[k] @ off))) / scale)
            pts[k] = c
    P = np.empty_like(form.P, dtype=float)
    P[0] = pts[0]
    P[1:n + 1] = pts[1:n + 1] - pts[:n]
    return POE(H, P, np.array(form.R_nT, dtype=float), np.array(form.prismatic, dtype=bool)), dev


def reverse(form: POE) -> POE:
    """The chain run backwards: from the tool (its frame at q = 0 is the new world) to the base.

    Its joint k is joint n-1-k with the axis reversed, and its FK at the same q (reversed) is
    the inverse of the original's: ``reverse(f).fk(q[::-1]) == inverse of f.fk(q)``.
    """
    Rt = np.asarray(form.R_nT, dtype=float).T
    H = -(np.asarray(form.H)[::-1] @ Rt.T)
    P = -(np.asarray(form.P)[::-1] @ Rt.T)
    return POE(np.ascontiguousarray(H), np.ascontiguousarray(P), np.ascontiguousarray(Rt),
               np.array(form.prismatic[::-1], dtype=bool))


def _size(form: POE) -> float:
    return max(float(np.linalg.norm(form.P, axis=1).sum()), 1e-12)


# --------------------------------------------------------------------------------- polishing
def _jacobian(form: POE, q: Array) -> tuple[Array, Array, Array]:
    """World-frame geometric Jacobian (6, n) (linear rows first) and the pose ``(R, p)`` at ``q``."""
    n = form.n
    R = np.eye(3)
    p = np.array(form.P[0], dtype=float)
    axes = np.empty((n, 3))
    origins = np.empty((n, 3))
    for k in range(n):
        axes[k] = R @ form.H[k]
        origins[k] = p
        if form.prismatic[k]:
            p = p + q[k] * axes[k]
        else:
            R = R @ rotm(form.H[k], float(q[k]))
        p = p + R @ form.P[k + 1]
    J = np.zeros((6, n))
    for k in range(n):
        if form.prismatic[k]:
            J[:3, k] = axes[k]
        else:
            J[:3, k] = np.cross(axes[k], p - origins[k])
            J[3:, k] = axes[k]
    return J, R @ form.R_nT, p


def _log_vec(Re: Array) -> Array:
    """Rotation vector of ``Re`` (small and moderate angles)."""
    w = 0.5 * np.array([Re[2, 1] - Re[1, 2], Re[0, 2] - Re[2, 0], Re[1, 0] - Re[0, 1]])
    s = float(np.linalg.norm(w))
    c = 0.5 * (np.trace(Re) - 1.0)
    th = math.atan2(s, c)
    return w if s < 1e-12 else w * (th / s)


def polish(form: POE, q: Array, R: Array, p: Array, steps: int = 8) -> Array:
    """A few Newton (least-squares) steps on the true chain ``form`` towards the target ``(R, p)``."""
    q = np.array(q, dtype=float)
    scale = _size(form)
    for _ in range(steps):
        J, Rq, pq = _jacobian(form, q)
        e = np.concatenate([p - pq, _log_vec(R @ Rq.T)])
        if np.linalg.norm(e[:3]) < 1e-15 * scale and np.linalg.norm(e[3:]) < 1e-15:
            break
        W = np.array([1.0 / scale] * 3 + [1.0] * 3)
        dq = np.linalg.lstsq(J * W[:, None], e * W, rcond=None)[0]
        q += dq
        if np.abs(dq).max() < 1e-15:
            break
    return q


# ---------------------------------------------------------------------------------- wrappers
KERNELS = ("_mv", "_mtv", "_mm", "_mtm", "_perp", "_wrist", "_pos_two_intersecting", "_pos_two_parallel",
           "_pos_search", "_pos_general", "_core_spherical", "_core_three_parallel", "_close", "_check", "_solve_spherical",
           "_solve_three_parallel", "_target_rows", "_core_two_intersecting_end", "_core_two_parallel",
           "_core_spherical_middle", "_solve_two_intersecting_end", "_solve_two_parallel", "_solve_spherical_middle",
           "_batch", "_sweep")
_KERNELS: Optional[types.SimpleNamespace] = None
_NO_NUMBA = False


def kernels() -> Optional[types.SimpleNamespace]:
    """The compiled solver cores (and subproblems), or None without Numba; compiled on first use."""
    global _KERNELS, _NO_NUMBA
    if _KERNELS is None and not _NO_NUMBA:
        sk = _sp.kernels()
        ek = _search_kernels()
        if sk is None or ek is None:
            _NO_NUMBA = True
            return None
        extra = _kk.extra()                 # the shared helpers (_fk_err), then the subproblems
        extra.update({name: sk.namespace[name] for name in _sp.KERNELS})
        extra["_search"] = ek._search
        ns = _sp.jit_namespace(globals(), KERNELS, extra=extra)
        from ... import _jit_loader

        _jit_loader.forget_stale_cache(ns, ("ik/geometric/subproblems.py", "ik/geometric/search.py",
                                                 "ik/geometric/_kernels.py"))
        _KERNELS = types.SimpleNamespace(**{name: ns[name] for name in KERNELS})
    return _KERNELS


def _use_jit(jit: Optional[bool]) -> bool:
    """``jit`` if given, else armkit's back end (:func:`armkit.set_backend`): the compiled cores when the
    Numba back end serves (for ``"auto"``: once armkit's kernels are ready), the plain functions otherwise."""
    if jit is not None:
        return jit
    from ... import kinematics

    return kinematics._jit_module() is not None


class _Prepared(NamedTuple):
    solve: str          # the kernel
    kind: int           # its case
    Hi: Array           # the ideal chain
    Pi: Array
    RnT: Array
    prism: NDArray[np.bool_]
    Ht: Array           # the true chain
    Pt: Array
    exact: bool         # ideal == true (up to rounding)
    scale: float        # arm size


_PREPARED: dict[tuple[int, str], tuple[Any, Any]] = {}
_CASES = {  # name: (kernel, case, meeting axes, parallel axes, joints that may be prismatic)
    "spherical_two_intersecting": ("_solve_spherical", 0, ((0, 1), (3, 4, 5)), (), (2,)),
    "spherical_two_parallel": ("_solve_spherical", 1, ((3, 4, 5),), ((1, 2),), ()),
    "spherical": ("_solve_spherical", 2, ((3, 4, 5),), (), ()),
    "three_parallel": ("_solve_three_parallel", 3, (), ((1, 2, 3),), ()),
    "three_parallel_two_intersecting": ("_solve_three_parallel", 4, ((4, 5),), ((1, 2, 3),), ()),
    "two_intersecting": ("_solve_two_intersecting_end", 5, ((4, 5),), (), ()),
    "two_parallel": ("_solve_two_parallel", 6, (), ((1, 2),), ()),
    "spherical_middle": ("_solve_spherical_middle", 7, ((1, 2, 3),), (), ()),
}


def _cached(form: POE, key: str, make: Callable[[], Any]) -> Any:
    """``make()``, remembered for this POE object (by identity, while it lives)."""
    hit = _PREPARED.get((id(form), key))
    if hit is not None and hit[0]() is form:
        return hit[1]
    value = make()
    if len(_PREPARED) > 512:
        _PREPARED.clear()
    _PREPARED[(id(form), key)] = (weakref.ref(form), value)
    return value


def _prepare(form: POE, name: str) -> _Prepared:
    def make() -> _Prepared:
        solve, kind, meet, parallel, may_slide = _CASES[name]
        if form.n != 6:
            raise ValueError(f"{name}: for 6-joint chains, got {form.n} joints")
        bad = [k + 1 for k in range(6) if form.prismatic[k] and k not in may_slide]
        if bad:
            raise ValueError(f"{name}: joint(s) {bad} may not be prismatic here")
        if name == "two_intersecting" and (_parallel(form, 1, 2, 1e-6) or _parallel(form, 2, 3, 1e-6)):
            raise ValueError("two_intersecting: axes 2 ∥ 3 or 3 ∥ 4 make its SP5 degenerate; the solvers of "
                             "spherical wrists or three parallel axes answer such arms")
        if name == "two_parallel" and not _parallel(form, 1, 2, 1e-6):
            raise ValueError("two_parallel: axes 2 and 3 must be parallel")
        if name == "spherical_middle" and not (_meets(form, 1, 2, 1e-6) and _meets(form, 2, 3, 1e-6)):
            raise ValueError("spherical_middle: axes 2, 3 and 4 must meet in a point")
        ideal, dev = align(form, meet, parallel)
        c = np.ascontiguousarray
        return _Prepared(solve, kind, c(ideal.H), c(ideal.P), c(np.asarray(form.R_nT, dtype=float)),
                         c(np.asarray(form.prismatic, dtype=np.bool_)), c(np.asarray(form.H, dtype=float)),
                         c(np.asarray(form.P, dtype=float)), dev < 1e-13, _size(form))
    return _cached(form, name, make)


def _run(name: str, form: POE, R: Array, p: Array, q_ref: Optional[Array], jit: Optional[bool]) -> Solutions:
    prep = _prepare(form, name)
    n = 6
    R = np.ascontiguousarray(R, dtype=float)
    p = np.ascontiguousarray(p, dtype=float)
    qref = _ZERO6 if q_ref is None else np.ascontiguousarray(q_ref, dtype=float)
    Q = np.zeros((MAXSOL, n))
    LS = np.zeros(MAXSOL, dtype=np.bool_)
    SG = np.zeros(MAXSOL, dtype=np.bool_)
    ST = np.zeros(MAXSOL, dtype=np.int64)
    K = kernels() if _use_jit(jit) else None
    fn = getattr(K, prep.solve) if K is not None else globals()[prep.solve]
    tol_p = TOL * prep.scale
    ng, nf = fn(prep.kind, prep.Hi, prep.Pi, prep.RnT, prep.prism, prep.Ht, prep.Pt, R, p, qref, SEARCH_N, tol_p,
                TOL, Q, LS, SG, ST)
    if nf and not (prep.exact and LS[ng:ng + nf].all()):
        # polish what the ideal chain got nearly right (nearly meeting / parallel axes, rounding)
        for i in range(ng, ng + nf):
            if LS[i] and prep.exact:
                continue
            qi = polish(form, Q[i], R, p)
            Rq, pq = form.fk(qi)
            if np.linalg.norm(pq - p) <= tol_p and np.linalg.norm(Rq - R) / math.sqrt(2.0) <= TOL:
                qi = np.where(form.prismatic, qi, (qi + math.pi) % (2 * math.pi) - math.pi)
                if not any(_same(qi, Q[j], form.prismatic) for j in range(ng)):
                    Q[ng] = qi
                    SG[ng] = SG[i]
                    ng += 1
    if ng:
        return Solutions(Q[:ng].copy(), np.zeros(ng, dtype=bool), SG[:ng].copy())
    return Solutions(Q[:nf].copy(), np.ones(nf, dtype=bool), SG[:nf].copy())


_ZERO6 = np.zeros(6)
_WHICH = {"_solve_spherical": 0, "_solve_three_parallel": 1, "_solve_two_intersecting_end": 2, "_solve_two_parallel": 3,
          "_solve_spherical_middle": 4}


def solve_batch(name: str, form: POE, R: Array, p: Array, q_ref: Array, *, jit: Optional[bool] = None
                ) -> list[Solutions]:
    """:data:`SOLVERS` ``[name]`` on every target of ``R (B, 3, 3)``, ``p (B, 3)``, ``q_ref (B, n)``, the
    kernel looping over the batch in one compiled call (each target as :func:`_run` would solve it; a target
    whose candidates need the Python polish goes through :func:`_run`)."""
    if name == "spherical_wrist":
        name = _cached(form, "wrist case", lambda: _wrist_case(form))
    if name not in _CASES:
        return [SOLVERS[name](form, R[b], p[b], q_ref[b], jit=jit) for b in range(len(R))]
    prep = _prepare(form, name)
    B, n = len(R), 6
    K = kernels() if jit is not False else None
    if K is None:
        return [_run(name, form, R[b], p[b], q_ref[b], jit) for b in range(B)]
    Q = np.zeros((B, MAXSOL, n))
    LS = np.zeros((B, MAXSOL), dtype=np.bool_)
    SG = np.zeros((B, MAXSOL), dtype=np.bool_)
    ST = np.zeros((B, MAXSOL), dtype=np.int64)
    NG = np.zeros(B, dtype=np.int64)
    NF = np.zeros(B, dtype=np.int64)
    c = np.ascontiguousarray
    K._batch(_WHICH[prep.solve], prep.kind, prep.Hi, prep.Pi, prep.RnT, prep.prism, prep.Ht, prep.Pt,
             c(R, dtype=float), c(p, dtype=float), c(q_ref, dtype=float), SEARCH_N, TOL * prep.scale, TOL,
             Q, LS, SG, ST, NG, NF)
    out: list[Solutions] = []
    for b in range(B):
        ng, nf = int(NG[b]), int(NF[b])
        if nf and not (prep.exact and LS[b, ng:ng + nf].all()):
            out.append(_run(name, form, R[b], p[b], q_ref[b], jit))     # the rare polish: as one call
        elif ng:
            out.append(Solutions(Q[b, :ng], np.zeros(ng, dtype=bool), SG[b, :ng]))
        else:
            out.append(Solutions(Q[b, :nf], np.ones(nf, dtype=bool), SG[b, :nf]))
    return out


def _same(a: Array, b: Array, prismatic: NDArray[np.bool_]) -> bool:
    d = np.abs(a - b)
    d = np.where(prismatic, d, np.minimum(d % (2 * math.pi), 2 * math.pi - d % (2 * math.pi)))
    return bool(d.max() < 1e-8)


def spherical_two_intersecting(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *,
                               jit: Optional[bool] = None) -> Solutions:
    """Axes 4, 5, 6 meet and axes 1, 2 meet (joint 3 revolute or prismatic): up to 8 solutions."""
    return _run("spherical_two_intersecting", form, R, p, q_ref, jit)


def spherical_two_parallel(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *,
                           jit: Optional[bool] = None) -> Solutions:
    """Axes 4, 5, 6 meet and axes 2 ∥ 3 (all revolute): up to 8 solutions."""
    return _run("spherical_two_parallel", form, R, p, q_ref, jit)


def spherical(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *,
              jit: Optional[bool] = None) -> Solutions:
    """Axes 4, 5, 6 meet, nothing else assumed (all revolute): closed form, up to 8 solutions.

    The wrist centre's position fixes q1, q2, q3 by SP5 (a quartic, up to 4), then the wrist gives 2 each.
    Where axes 1 ∥ 2 SP5 does not apply and the 1-D search SW of :mod:`.search` over q1 answers
    (:data:`SEARCH_N` samples a turn; SP3 for q3, the residual along axis 2). Every solution is checked by FK."""
    return _run("spherical", form, R, p, q_ref, jit)


def _meets(form: POE, i: int, j: int, tol: float = 1e-9) -> bool:
    hi, hj = form.H[i], form.H[j]
    c = np.cross(hi, hj)
    s = np.linalg.norm(c)
    pts = _points(np.asarray(form.P, dtype=float))
    if s < 1e-9:
        return False
    return abs(float((pts[j] - pts[i]) @ c)) / s <= tol * _size(form)


def _parallel(form: POE, i: int, j: int, tol: float = 1e-9) -> bool:
    return float(np.linalg.norm(np.cross(form.H[i], form.H[j]))) <= tol


def _wrist_case(form: POE) -> str:
    if _meets(form, 0, 1):
        return "spherical_two_intersecting"
    if _parallel(form, 1, 2) and not np.any(form.prismatic):
        return "spherical_two_parallel"
    return "spherical"


def spherical_wrist(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *,
                    jit: Optional[bool] = None) -> Solutions:
    """Axes 4, 5, 6 meet: :func:`spherical_two_intersecting` when axes 1, 2 meet,
    :func:`spherical_two_parallel` when 2 ∥ 3, :func:`spherical` otherwise."""
    return _run(_cached(form, "wrist case", lambda: _wrist_case(form)), form, R, p, q_ref, jit)


def three_parallel(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *,
                   jit: Optional[bool] = None) -> Solutions:
    """Axes 2 ∥ 3 ∥ 4 (all revolute): SP6 for q1, q5; up to 8 solutions."""
    return _run("three_parallel", form, R, p, q_ref, jit)


def three_parallel_two_intersecting(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *,
                                    jit: Optional[bool] = None) -> Solutions:
    """Axes 2 ∥ 3 ∥ 4 and axes 5, 6 meet (UR arms; all revolute): up to 8 solutions."""
    return _run("three_parallel_two_intersecting", form, R, p, q_ref, jit)


def two_intersecting(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *,
                     jit: Optional[bool] = None) -> Solutions:
    """Axes 5 and 6 meet (all revolute; no two of axes 2, 3, 4 parallel): up to 16 solutions.

    The 1-D search TI of :mod:`.search` over q1 (:data:`SEARCH_N` samples a turn; its resolution is
    stated there): at each q1, SP5 gives up to 4 (q2, q3, q4) that put the axis-5/6 point in place,
    and the residual of each is the angle condition of axes 5 and 6 (``(R_04 h5)ᵀ R_06 h6 = h5ᵀ h6``);
    then q5, q6 by SP1. Every solution is checked by FK."""
    return _run("two_intersecting", form, R, p, q_ref, jit)


def spherical_base(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *,
                   jit: Optional[bool] = None) -> Solutions:
    """Axes 1, 2, 3 meet (a spherical wrist at the base): :func:`spherical_wrist` on the reversed
    chain (:func:`reverse`) for the inverse target, solutions turned back."""
    rev = _cached(form, "reversed", lambda: reverse(form))
    R = np.asarray(R, dtype=float)
    p = np.asarray(p, dtype=float)
    qr = None if q_ref is None else np.asarray(q_ref, dtype=float)[::-1]
    sol = spherical_wrist(rev, R.T, -(R.T @ p), qr, jit=jit)
    return Solutions(np.ascontiguousarray(sol.q[:, ::-1]), sol.ls, sol.singular)


def two_parallel(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *,
                 jit: Optional[bool] = None) -> Solutions:
    """Axes 2 ∥ 3 and no other relation (all revolute): up to 16 solutions.

    The 1-D search TP of :mod:`.search` over q6 (:data:`SEARCH_N` samples, its resolution there): at each
    q6, SP6 gives up to 4 ``(q1, q4)`` from the two equations along axis 2 (position and orientation), SP1
    the sum ``θ = q2 ± q3``, and the residual is ``|d| − |P3|``; then q2, q5 by SP1."""
    return _run("two_parallel", form, R, p, q_ref, jit)


def spherical_middle(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *,
                     jit: Optional[bool] = None) -> Solutions:
    """Axes 2, 3, 4 meet in a point (a spherical joint in the middle; all revolute): up to 16 solutions.

    The 1-D search SM of :mod:`.search` over q6 (:data:`SEARCH_N` samples): at each q6 the point of axis 5
    is at a fixed distance from the centre of the spherical joint (SP3 for q1, up to 2 branches) and its
    component along axis 5 is the residual; then q5 by SP1 and q2, q3, q4 as a wrist (SP2, SP1; at the
    wrist's singularity q2 at ``q_ref``)."""
    return _run("spherical_middle", form, R, p, q_ref, jit)


SOLVERS: dict[str, Callable[..., Solutions]] = {
    "spherical_two_intersecting": spherical_two_intersecting,
    "spherical_two_parallel": spherical_two_parallel,
    "spherical": spherical,
    "spherical_wrist": spherical_wrist,
    "three_parallel": three_parallel,
    "three_parallel_two_intersecting": three_parallel_two_intersecting,
    "spherical_base": spherical_base,
    "two_intersecting": two_intersecting,
    "two_parallel": two_parallel,
    "spherical_middle": spherical_middle,
    "gen_six_dof": _search2d.gen_six_dof,      # the general 6R: 2-D search (search2d.py)
}
"""The solvers by name (IK-Geo's names where it has them)."""
