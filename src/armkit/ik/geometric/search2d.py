"""A 2-D search for the general 6R chain: no two axes meet or are parallel (IK-Geo's idea, our code).

With q1 and q2 held, the point of axis 6 fixes q3, q4, q5 (the rest of a 3R position problem), and
what is left is whether joint 6's axis then points where the target wants it::

    u = R_02ᵀ (p − p_0 − R_06 p_6T − R_01 p_12) − p_23 = rot(h3, q3) (p_34 + rot(h4, q4) (p_45 + rot(h5, q5) p_56))

Read as ``rot(h3, −q3) u − p_34 = rot(h4, q4) (p_45 + rot(h5, q5) p_56)`` (the two sides agree iff
their components along h4 and their lengths agree), it is two equations linear in ``(cos q3, sin q3)``
and ``(cos q5, sin q5)``; eliminating one pair leaves a trigonometric polynomial of degree 2 in the
other angle, a quartic in the tangent of its half angle (up to 4 real roots: the closed form shared
with the 1-D searches, :func:`._kernels._trig2`, exact solutions only). Then q4 by SP1.
Each of those up to 4 branches leaves the residual

    e(q1, q2) = R_05 h6 − R_06 h6,

two numbers (its components across ``R_06 h6``); a solution of the arm is a zero of e on a branch.

**Resolution.** e is sampled on an :data:`N` × :data:`N` grid over the torus of (q1, q2) (step
360°/N). Each grid cell is walked around on each branch (branches matched corner to corner by their
(q3, q4, q5)); a cell where e winds around 0 holds a zero. Where the branches do not match around a
cell (a branch ends inside, two branches come close), the grid points where ``‖e‖`` is below
:data:`THRESH` and least among their neighbours are taken too, and those next to the end of their
branch where ``‖e‖`` is below :data:`EDGE_THRESH`. Every candidate (for a winding cell: the zero of
e's bilinear interpolation over the cell) is then polished by Newton steps on the whole chain (all six
joints, the true model) and kept only when FK of the chain meets the target to :data:`~.solvers.TOL`
(times the arm's size for the position); duplicates are merged. What the resolution means: a solution
can be missed when another lies within about one grid step of it in (q1, q2) on the same branch (two
zeros of e in one cell: their windings cancel and Newton from there finds one of them). On random
arms that happened for 1 target in 120 (tests/ik/geometric/test_search2d.py); a finer grid
(``samples=``) shrinks it. Since the real solutions of a general 6R come in pairs, an odd count says
that one is missing: Newton steps then start from each solution found, 0.002 to 1 rad along the
direction in which the Jacobian is nearest singular (where such a twin lies), until the count is even
(:func:`_twins`); if it is still odd, a grid twice as fine is searched too, and its solutions merged.
benchmarks/bench_coverage.py's dense check (Levenberg-Marquardt from 200 random starts per target)
found 3 missing of 2,158 on 500 random arms before the Newton steps, and 2 of 2,192 with steps up to
0.2 rad and no finer grid (one twin lay 0.44 rad away; another target had a pair and a twin within a
cell of others). Odd counts on random targets, each on its own random arm: 10 of 3,000 before, 0 of
3,000 and 0 of 5,000 (other seeds) since (2026-12-05).

**Cost.** For a row of the grid (q1 held) the target's vectors are turned by ``R_01ᵀ`` once; each point
turns them by ``R_12ᵀ``, solves its (q3, q4, q5) problem without temporary arrays and keeps, per branch,
the angle and length of e (read by the cell walk instead of recomputed per corner). A point whose two
equations cannot be met (:func:`_reject`: a row of the system, or their sum or difference, asks for more
than its terms can reach, by a margin far above the closed form's tolerance) skips the quartic; a cell
walk is skipped when e stays in one half-plane at all four corners (it cannot wind). Neither shortcut
changes what is found: same candidates, same branches (tests/ik/geometric/test_search2d.py).

The search is compiled with Numba (``njit(cache=True)``, on first use; :func:`kernels`), the whole
grid, the candidates, the Newton polish and the check in one call; without Numba the same functions
run as plain Python (seconds per target).
"""

from __future__ import annotations

import math
import types
from typing import Optional

import numpy as np
from numpy.typing import NDArray

from ... import _jit_loader
from . import _kernels as _kk
from . import subproblems as _sp
from ._kernels import (_add_row, _move, _rmul_rot, _t, _tadd, _tcross, _tdot, _tmtv, _tmul, _tmv, _tnorm,
                       _trig2_rows, _trot_cs, _tsub)
from .poe import POE
from .subproblems import _cross, _dot, _norm, _wrap, rot, rotm

__all__ = ["gen_six_dof", "N", "THRESH", "MAXSOL", "kernels", "resolution"]

Array = NDArray[np.float64]

N = 100
"""Samples of q1 and of q2 over one turn each (3.6° apart): the grid is N × N."""
THRESH = 0.35
"""A grid point of a branch whose ``‖e‖`` (the sine-ish angle between joint 6's axis and the target's) is
below this and least among its neighbours is a candidate, whether or not e winds around its cell."""
EDGE_THRESH = 0.9
"""The same for a grid point next to where its branch ends (a fold of the q3, q4, q5 problem, where e changes
fast): below this, a candidate whether or not it is least among its neighbours."""
MATCH = 1.2
"""Largest change (rad, in q3, q4 or q5) between neighbouring grid points taken as the same branch."""
REJECT = 1e-6
"""Margin of the early rejection of a grid point (:func:`_reject`): a point is skipped without the closed form
only when a combination of its two equations misses what its terms can reach by more than this (relative to the
equations' size; the closed form accepts residuals of 1e-9 of it)."""
THIN = 100
"""Where no solution is found and the (q3, q4, q5) problem has solutions at fewer than one grid point in this many,
the grid twice as fine is searched too, and four times as fine while the count is odd (:func:`_search`):
bench_coverage.py --dense-only --seed=271 found a target whose (q3, q4, q5) problem was solvable at 7 of the 10,000
points and whose 4 solutions the 100 x 100 grid missed (150 x 150 found 2, 200 x 200 3, 400 x 400 all 4). Of 2,000
random targets (each the FK of a random configuration of its own random arm), 21 had fewer, and none of the 49
below one in 50 gained a solution on the finer grid."""
MAX_GRID = 800
"""The finest grid searched, samples a side: its work arrays take 264 bytes a point (169 MB at 800 x 800). The
``samples`` of :func:`gen_six_dof` may not exceed it, and a finer grid of :func:`_search` beyond it is left out."""
MAXCAND = 512
MAXSOL = 32
NEWTON = 60


def resolution(samples: int = N) -> str:
    """The search's resolution in words (for ``armkit info`` and notes)."""
    return f"{samples} x {samples} grid over q1, q2 ({360.0 / samples:.2g} deg)"


# ----------------------------------------------------------------- one grid point: q3, q4, q5
def _lin2(h, k, p):
    """``(a, b, c)`` with ``hᵀ rot(k, θ) p = c + a cos θ + b sin θ``."""
    kp = _dot(k, p)
    c = _dot(h, k) * kp
    b = (h[0] * (k[1] * p[2] - k[2] * p[1]) + h[1] * (k[2] * p[0] - k[0] * p[2])
         + h[2] * (k[0] * p[1] - k[1] * p[0]))
    return _dot(h, p) - c, b, c


def _arm(H, P):
    """What the (q3, q4, q5) problem of every grid point shares, as an array (:func:`_branches` reads it):
    ``h4 × h3``, ``p34 × h3``, ``h4ᵀ h3``, ``p34ᵀ h3``, the coefficients of q5 in both equations, and the
    constant parts of their right-hand sides."""
    h3 = _t(H[2])
    h4 = _t(H[3])
    P34 = _t(P[3])
    P45 = _t(P[4])
    P56 = _t(P[5])
    a_hp, b_hp, c_hp = _lin2(H[3], H[4], P[5])
    a_pp, b_pp, c_pp = _lin2(P[4], H[4], P[5])
    k = np.empty(14)
    x = _tcross(h4, h3)
    y = _tcross(P34, h3)
    for i in range(3):
        k[i] = x[i]
        k[3 + i] = y[i]
    k[6] = _tdot(h4, h3)
    k[7] = _tdot(P34, h3)
    k[8] = -a_hp
    k[9] = -b_hp
    k[10] = -2.0 * a_pp
    k[11] = -2.0 * b_pp
    k[12] = _tdot(h4, P34) + _tdot(h4, P45) + c_hp
    k[13] = _tdot(P45, P45) + _tdot(P56, P56) + 2.0 * c_pp - _tdot(P34, P34)
    return k


def _reject(a00, a01, b00, b01, e0, a10, a11, b10, b11, e1):
    """True when ``a_r· (cos θ1, sin θ1) + b_r· (cos θ2, sin θ2) = e_r`` (r = 0, 1) surely has no solution: for
    λ = (1, 0), (0, 1), (1, 1), (1, −1) on the rows scaled to unit size, ``|λᵀ e|`` exceeds ``‖Aᵀ λ‖ + ‖Bᵀ λ‖``
    (what the left side can reach along λ) by more than :data:`REJECT` ``(2 + |e0| + |e1|) ‖λ‖``."""
    n0 = math.sqrt(a00 * a00 + a01 * a01 + b00 * b00 + b01 * b01)
    n1 = math.sqrt(a10 * a10 + a11 * a11 + b10 * b10 + b11 * b11)
    if n0 <= 0.0 or n1 <= 0.0:
        return False
    a00 /= n0
    a01 /= n0
    b00 /= n0
    b01 /= n0
    e0 /= n0
    a10 /= n1
    a11 /= n1
    b10 /= n1
    b11 /= n1
    e1 /= n1
    m = REJECT * (2.0 + abs(e0) + abs(e1))
    if abs(e0) > math.sqrt(a00 * a00 + a01 * a01) + math.sqrt(b00 * b00 + b01 * b01) + m:
        return True
    if abs(e1) > math.sqrt(a10 * a10 + a11 * a11) + math.sqrt(b10 * b10 + b11 * b11) + m:
        return True
    m *= math.sqrt(2.0)
    if abs(e0 + e1) > (math.sqrt((a00 + a10) ** 2 + (a01 + a11) ** 2) + math.sqrt((b00 + b10) ** 2 + (b01 + b11) ** 2)
                       + m):
        return True
    return abs(e0 - e1) > (math.sqrt((a00 - a10) ** 2 + (a01 - a11) ** 2)
                           + math.sqrt((b00 - b10) ** 2 + (b01 - b11) ** 2) + m)


def _branches(H, P, k, u, T3, T5, out):
    """Up to 4 ``(q3, q4, q5)`` with ``rot(h3, q3) (p_34 + rot(h4, q4) (p_45 + rot(h5, q5) p_56)) = u`` into
    ``out[:, 0:3]``, and for each ``rot(h3, q3) rot(h4, q4) rot(h5, q5) h6`` into ``out[:, 3:6]`` (``out (4, 6)``);
    returns their count. ``k``: :func:`_arm` of the chain; ``T3``, ``T5`` (4,): work space. The closed form of
    :mod:`._kernels` (:func:`._kernels._trig2_rows`, exact solutions only), then q4 by SP1; no temporary arrays."""
    h3 = _t(H[2])
    h4 = _t(H[3])
    h5 = _t(H[4])
    h6 = _t(H[5])
    P34 = _t(P[3])
    P45 = _t(P[4])
    P56 = _t(P[5])
    uu = _t(u)
    # h4ᵀ rot(h3, -θ3) u = c + a cos θ3 - b sin θ3, and p34ᵀ rot(h3, -θ3) u likewise
    h3u = _tdot(h3, uu)
    c_hu = k[6] * h3u
    a_hu = _tdot(h4, uu) - c_hu
    b_hu = k[0] * uu[0] + k[1] * uu[1] + k[2] * uu[2]
    c_pu = k[7] * h3u
    a_pu = _tdot(P34, uu) - c_pu
    b_pu = k[3] * uu[0] + k[4] * uu[1] + k[5] * uu[2]
    e0 = k[12] - c_hu
    e1 = k[13] - _tdot(uu, uu) + 2.0 * c_pu
    # early rejection: A (cos θ3, sin θ3) + B (cos θ5, sin θ5) = e has no solution when for some λ
    # |λᵀ e| > ‖Aᵀ λ‖ + ‖Bᵀ λ‖; λ = each row and their sum and difference (rows scaled to unit size first), with a
    # margin far above the closed form's tolerance, so that nothing it would accept is skipped
    if _reject(a_hu, -b_hu, k[8], k[9], e0, -2.0 * a_pu, 2.0 * b_pu, k[10], k[11], e1):
        return 0
    # the 2 x 2 trigonometric system in (q3, q5), rows scaled alike: the shared closed form (exact solutions)
    n, _ = _trig2_rows(a_hu, -b_hu, k[8], k[9], e0, -2.0 * a_pu, 2.0 * b_pu, k[10], k[11], e1, T3, T5,
                       None)
    for b in range(n):
        q3 = T3[b]
        q5 = T5[b]
        c3 = math.cos(q3)
        s3 = math.sin(q3)
        c5 = math.cos(q5)
        s5 = math.sin(q5)
        v = _tsub(_trot_cs(h3, c3, -s3, uu), P34)
        w = _tadd(P45, _trot_cs(h5, c5, s5, P56))
        # SP1 about h4 from w to v: the parts along h4 drop out of h4ᵀ (w × v)
        y = _tdot(h4, _tcross(w, v))
        x = _tdot(w, v) - _tdot(h4, w) * _tdot(h4, v)
        r = math.sqrt(x * x + y * y)
        c4 = x / r if r > 0.0 else 1.0
        s4 = y / r if r > 0.0 else 0.0
        d = _trot_cs(h3, c3, s3, _trot_cs(h4, c4, s4, _trot_cs(h5, c5, s5, h6)))
        out[b, 0] = q3
        out[b, 1] = _wrap(math.atan2(y, x))
        out[b, 2] = q5
        out[b, 3] = d[0]
        out[b, 4] = d[1]
        out[b, 5] = d[2]
    return n


def _q345(H, P, u, out, W):
    """Up to 4 ``(q3, q4, q5)`` with ``rot(h3, q3) (p_34 + rot(h4, q4) (p_45 + rot(h5, q5) p_56)) = u`` into
    ``out (4, 3)``; returns their count (``W (5, 5)``: work space). :func:`_branches` on its own."""
    full = np.empty((4, 6))
    n = _branches(H, P, _arm(H, P), u, W[0], W[1], full)
    for b in range(n):
        for m in range(3):
            out[b, m] = full[b, m]
    return n


# --------------------------------------------------------------------------- the grid
def _grid(H, P, R06, p, samples, Q, E, C):
    """Every grid point's branches: ``(q3, q4, q5)`` into ``Q (S, S, 4, 3)``; into ``E (S, S, 4, 5)`` the residual
    ``(xᵀ d, yᵀ d, tᵀ d)`` (``d = R_05 h6``, ``t = R_06 h6``, x, y across t), the angle of ``(xᵀ d, yᵀ d)`` and its
    length; counts into ``C (S, S)``. For a row (q1 held) ``R_01ᵀ`` is applied to the target's vectors once; each
    point then turns them by ``R_12ᵀ`` and compares them with its branches' ``R_25 h6``."""
    t = _tmv(R06, _t(H[5]))
    if abs(t[0]) < 0.6:
        x = _tcross(t, (1.0, 0.0, 0.0))
    else:
        x = _tcross(t, (0.0, 1.0, 0.0))
    x = _tmul(x, 1.0 / _tnorm(x))
    y = _tcross(t, x)
    w = _tsub(_tsub(_t(p), _t(P[0])), _tmv(R06, _t(P[6])))      # p − p_0 − R_06 p_6T: the point of axis 6
    P1 = _t(P[1])
    P2 = _t(P[2])
    R1s = np.empty((samples, 3, 3))
    R2s = np.empty((samples, 3, 3))
    for i in range(samples):
        ang = -math.pi + 2.0 * math.pi * i / samples
        R1s[i] = rotm(H[0], ang)
        R2s[i] = rotm(H[1], ang)
    k = _arm(H, P)
    out = np.empty((4, 6))
    T3 = np.empty(4)
    T5 = np.empty(4)
    u = np.empty(3)
    for i in range(samples):
        R1 = R1s[i]
        a1 = _tsub(_tmtv(R1, w), P1)
        x1 = _tmtv(R1, x)
        y1 = _tmtv(R1, y)
        t1 = _tmtv(R1, t)
        for j in range(samples):
            R2 = R2s[j]
            ur = _tsub(_tmtv(R2, a1), P2)
            u[0] = ur[0]
            u[1] = ur[1]
            u[2] = ur[2]
            xr = _tmtv(R2, x1)
            yr = _tmtv(R2, y1)
            tr = _tmtv(R2, t1)
            n = _branches(H, P, k, u, T3, T5, out)
            C[i, j] = n
            for b in range(n):
                d = (out[b, 3], out[b, 4], out[b, 5])
                ex = _tdot(xr, d)
                ey = _tdot(yr, d)
                Q[i, j, b, 0] = out[b, 0]
                Q[i, j, b, 1] = out[b, 1]
                Q[i, j, b, 2] = out[b, 2]
                E[i, j, b, 0] = ex
                E[i, j, b, 1] = ey
                E[i, j, b, 2] = _tdot(tr, d)
                E[i, j, b, 3] = math.atan2(ey, ex)
                E[i, j, b, 4] = math.hypot(ex, ey)


def _adiff(a, b):
    """``|wrap(a − b)|`` for angles in (-π, π] (their difference is within (-2π, 2π))."""
    d = abs(a - b)
    return 2.0 * math.pi - d if d > math.pi else d


def _near(Q, C, i, j, ref):
    """The branch at grid point (i, j) nearest ``ref (3,)`` (q3, q4, q5), -1 if none within :data:`MATCH`."""
    best = -1
    bd = MATCH
    r0 = ref[0]
    r1 = ref[1]
    r2 = ref[2]
    for b in range(C[i, j]):
        d = _adiff(Q[i, j, b, 0], r0)
        if d >= bd:
            continue
        d = max(d, _adiff(Q[i, j, b, 1], r1))
        if d >= bd:
            continue
        d = max(d, _adiff(Q[i, j, b, 2], r2))
        if d < bd:
            bd = d
            best = b
    return best


def _halves(x, y):
    """The open half-planes holding ``(x, y)``: bit 1 ``x > 0``, 2 ``x < 0``, 4 ``y > 0``, 8 ``y < 0``."""
    return (1 if x > 0.0 else (2 if x < 0.0 else 0)) | (4 if y > 0.0 else (8 if y < 0.0 else 0))


def _candidates(Q, E, C, samples, cand):
    """Starts ``(q1, …, q5)`` for Newton into ``cand (MAXCAND, 5)``: in each cell around which e winds, the zero
    of e's bilinear interpolation (q3, q4, q5 interpolated alike); the grid points that are local minima of ‖e‖
    below :data:`THRESH` (or next to their branch's end, below :data:`EDGE_THRESH`). Returns their count."""
    nc = 0
    step = 2.0 * math.pi / samples
    bq = np.empty((4, 3))
    be = np.empty((4, 2))
    ci = np.empty(5, dtype=np.int64)
    cj = np.empty(5, dtype=np.int64)
    # at each grid point, the half-planes (xᵀ d > 0, < 0, yᵀ d > 0, < 0: bits 1, 2, 4, 8) that hold e on every branch
    # with tᵀ d > 0: a cell whose corners share one with the starting branch cannot wind (no atan2 jump)
    half = np.empty((samples, samples), dtype=np.int64)
    for i in range(samples):
        for j in range(samples):
            m = 15
            for b in range(C[i, j]):
                if E[i, j, b, 2] > 0.0:
                    m &= _halves(E[i, j, b, 0], E[i, j, b, 1])
            half[i, j] = m
    for i in range(samples):
        i1 = (i + 1) % samples
        for j in range(samples):
            j1 = (j + 1) % samples
            ci[0] = i
            cj[0] = j
            ci[1] = i1
            cj[1] = j
            ci[2] = i1
            cj[2] = j1
            ci[3] = i
            cj[3] = j1
            ci[4] = i
            cj[4] = j
            for b0 in range(C[i, j]):
                # a local minimum of ‖e‖ on this branch
                r0 = E[i, j, b0, 4]
                if r0 < EDGE_THRESH and E[i, j, b0, 2] > 0.0:
                    low = True
                    edge = False
                    for nb in range(8):           # the 8 neighbours; stop at the first lower one
                        di = nb // 3 - 1 if nb < 4 else (nb + 1) // 3 - 1
                        dj = nb % 3 - 1 if nb < 4 else (nb + 1) % 3 - 1
                        ni = (i + di) % samples
                        nj = (j + dj) % samples
                        k = _near(Q, C, ni, nj, Q[i, j, b0])
                        if k < 0:
                            edge = True
                        elif E[ni, nj, k, 2] > 0.0 and E[ni, nj, k, 4] < r0:
                            low = False
                            break
                    if low and (edge or r0 < THRESH) and nc < cand.shape[0]:
                        cand[nc, 0] = -math.pi + step * i
                        cand[nc, 1] = -math.pi + step * j
                        for k in range(3):
                            cand[nc, 2 + k] = Q[i, j, b0, k]
                        nc += 1
                # the winding of e around the cell on this branch
                b = b0
                total = 0.0
                ok = E[i, j, b0, 2] > 0.0 and (_halves(E[i, j, b0, 0], E[i, j, b0, 1]) & half[i1, j] & half[i1, j1]
                                                & half[i, j1]) == 0
                for k in range(3):
                    bq[0, k] = Q[i, j, b0, k]
                be[0, 0] = E[i, j, b0, 0]
                be[0, 1] = E[i, j, b0, 1]
                for s in range(1, 5):
                    if not ok:
                        break
                    k = _near(Q, C, ci[s], cj[s], Q[ci[s - 1], cj[s - 1], b])
                    if k < 0 or E[ci[s], cj[s], k, 2] <= 0.0:
                        ok = False
                        break
                    total += _wrap(E[ci[s], cj[s], k, 3] - E[ci[s - 1], cj[s - 1], b, 3])
                    b = k
                    if s < 4:
                        for m in range(3):     # unwrapped next to corner 0
                            bq[s, m] = bq[0, m] + _wrap(Q[ci[s], cj[s], k, m] - bq[0, m])
                        be[s, 0] = E[ci[s], cj[s], k, 0]
                        be[s, 1] = E[ci[s], cj[s], k, 1]
                if ok and b == b0 and abs(total) > math.pi and nc < cand.shape[0]:
                    # corners 0 (s, t) = (0, 0), 1 (1, 0), 2 (1, 1), 3 (0, 1): the zero of the bilinear e
                    u = 0.5
                    v = 0.5
                    for _ in range(12):
                        f0 = (1 - u) * (1 - v) * be[0, 0] + u * (1 - v) * be[1, 0] + u * v * be[2, 0] + (1 - u) * v * be[3, 0]
                        f1 = (1 - u) * (1 - v) * be[0, 1] + u * (1 - v) * be[1, 1] + u * v * be[2, 1] + (1 - u) * v * be[3, 1]
                        a00 = -(1 - v) * be[0, 0] + (1 - v) * be[1, 0] + v * be[2, 0] - v * be[3, 0]
                        a10 = -(1 - v) * be[0, 1] + (1 - v) * be[1, 1] + v * be[2, 1] - v * be[3, 1]
                        a01 = -(1 - u) * be[0, 0] - u * be[1, 0] + u * be[2, 0] + (1 - u) * be[3, 0]
                        a11 = -(1 - u) * be[0, 1] - u * be[1, 1] + u * be[2, 1] + (1 - u) * be[3, 1]
                        det = a00 * a11 - a01 * a10
                        if det == 0.0:
                            break
                        u = min(1.0, max(0.0, u - (a11 * f0 - a01 * f1) / det))
                        v = min(1.0, max(0.0, v - (-a10 * f0 + a00 * f1) / det))
                    cand[nc, 0] = -math.pi + step * (i + u)
                    cand[nc, 1] = -math.pi + step * (j + v)
                    for m in range(3):
                        cand[nc, 2 + m] = ((1 - u) * (1 - v) * bq[0, m] + u * (1 - v) * bq[1, m] + u * v * bq[2, m]
                                           + (1 - u) * v * bq[3, m])
                    nc += 1
    return nc


# ---------------------------------------------------------------- Newton on the whole chain
def _fkj(H, P, RnT, q, J, Rout, pout, Wk):
    """FK of the chain at ``q`` (``R`` into ``Rout``, ``p`` into ``pout``) and its world Jacobian ``J (6, 6)``
    (linear rows first); ``Wk (18, 3)`` work space."""
    R = Wk[0:3]
    T = Wk[3:6]
    axes = Wk[6:12]
    orig = Wk[12:18]
    for r in range(3):
        for c in range(3):
            R[r, c] = 1.0 if r == c else 0.0
    p0 = P[0, 0]
    p1 = P[0, 1]
    p2 = P[0, 2]
    for k in range(6):
        h0 = H[k, 0]
        h1 = H[k, 1]
        h2 = H[k, 2]
        for r in range(3):
            axes[k, r] = R[r, 0] * h0 + R[r, 1] * h1 + R[r, 2] * h2
        orig[k, 0] = p0
        orig[k, 1] = p1
        orig[k, 2] = p2
        _rmul_rot(R, T, h0, h1, h2, q[k])
        p0, p1, p2 = _move(R, P, k + 1, p0, p1, p2)
    for k in range(6):
        d0 = p0 - orig[k, 0]
        d1 = p1 - orig[k, 1]
        d2 = p2 - orig[k, 2]
        J[0, k] = axes[k, 1] * d2 - axes[k, 2] * d1
        J[1, k] = axes[k, 2] * d0 - axes[k, 0] * d2
        J[2, k] = axes[k, 0] * d1 - axes[k, 1] * d0
        J[3, k] = axes[k, 0]
        J[4, k] = axes[k, 1]
        J[5, k] = axes[k, 2]
    for r in range(3):
        for c in range(3):
            Rout[r, c] = R[r, 0] * RnT[0, c] + R[r, 1] * RnT[1, c] + R[r, 2] * RnT[2, c]
    pout[0] = p0
    pout[1] = p1
    pout[2] = p2


def _err(Rq, pq, Rt, pt, scale):
    """``(position error / scale, rotation error)`` (the rotation error as the solvers' check: ‖ΔR‖_F / √2)."""
    dp = math.sqrt((pq[0] - pt[0]) ** 2 + (pq[1] - pt[1]) ** 2 + (pq[2] - pt[2]) ** 2)
    e = 0.0
    for r in range(3):
        for c in range(3):
            e += (Rq[r, c] - Rt[r, c]) ** 2
    return dp / scale, math.sqrt(0.5 * e)


def _solve6(A, b, x, M, v):
    """``A x = b`` (6 × 6) by Gaussian elimination with partial pivoting; False when singular (``M (6, 6)``,
    ``v (6,)``: work space)."""
    for r in range(6):
        v[r] = b[r]
        for c in range(6):
            M[r, c] = A[r, c]
    for c in range(6):
        piv = c
        for r in range(c + 1, 6):
            if abs(M[r, c]) > abs(M[piv, c]):
                piv = r
        if abs(M[piv, c]) < 1e-14:
            return False
        if piv != c:
            for k in range(6):
                tmp = M[c, k]
                M[c, k] = M[piv, k]
                M[piv, k] = tmp
            tmp = v[c]
            v[c] = v[piv]
            v[piv] = tmp
        for r in range(c + 1, 6):
            f = M[r, c] / M[c, c]
            for k in range(c, 6):
                M[r, k] -= f * M[c, k]
            v[r] -= f * v[c]
    for c in range(5, -1, -1):
        s = v[c]
        for k in range(c + 1, 6):
            s -= M[c, k] * x[k]
        x[c] = s / M[c, c]
    return True


def _newton(H, P, RnT, Rt, pt, scale, q):
    """Newton (Levenberg-Marquardt when the Jacobian is singular) steps on the whole chain from ``q`` (changed in
    place) towards ``(Rt, pt)``; returns the final ``max(position error / scale, rotation error)``."""
    J = np.empty((6, 6))
    Rq = np.empty((3, 3))
    pq = np.empty(3)
    ev = np.empty(6)
    dq = np.zeros(6)
    JtJ = np.empty((6, 6))
    Jte = np.empty(6)
    Wk = np.empty((18, 3))
    Ms = np.empty((6, 6))
    vs = np.empty(6)
    M = np.empty((3, 3))
    err = 1e300
    for it in range(NEWTON):
        _fkj(H, P, RnT, q, J, Rq, pq, Wk)
        ep, er = _err(Rq, pq, Rt, pt, scale)
        err = max(ep, er)
        if err < 1e-15 or (it >= 25 and err > 1e-6):    # met, or not converging
            break
        for r in range(3):
            ev[r] = (pt[r] - pq[r]) / scale
            for k in range(6):
                J[r, k] /= scale
        # rotation error: vee of the skew part of Rt Rqᵀ (≈ the rotation vector for small errors)
        for r in range(3):
            for c in range(3):
                M[r, c] = Rt[r, 0] * Rq[c, 0] + Rt[r, 1] * Rq[c, 1] + Rt[r, 2] * Rq[c, 2]
        ev[3] = 0.5 * (M[2, 1] - M[1, 2])
        ev[4] = 0.5 * (M[0, 2] - M[2, 0])
        ev[5] = 0.5 * (M[1, 0] - M[0, 1])
        if not _solve6(J, ev, dq, Ms, vs):
            for r in range(6):
                Jte[r] = 0.0
                for c in range(6):
                    JtJ[r, c] = 0.0
                    for k in range(6):
                        JtJ[r, c] += J[k, r] * J[k, c]
                    Jte[r] += J[c, r] * ev[c]
                JtJ[r, r] += 1e-6
            if not _solve6(JtJ, Jte, dq, Ms, vs):
                break
        big = 0.0
        for k in range(6):
            big = max(big, abs(dq[k]))
        f = 1.0 if big < 0.3 else 0.3 / big
        for k in range(6):
            q[k] += f * dq[k]
        if big < 1e-14:
            _fkj(H, P, RnT, q, J, Rq, pq, Wk)
            ep, er = _err(Rq, pq, Rt, pt, scale)
            err = max(ep, er)
            break
    return err


def _pass(H, P, RnT, R, R06, p, samples, tol, scale, Qout, m, best, bestq):
    """One grid of ``samples`` × ``samples`` for the target ``(R, p)`` (``R06`` its orientation times ``R_6T``ᵀ):
    every candidate polished by Newton steps, and those that meet ``tol`` added to ``Qout[:m]`` (duplicates
    merged). Returns ``(new count, candidates, grid points where the (q3, q4, q5) problem has a solution)``; while no
    solution is known, ``best[0]`` and ``bestq`` keep the least error reached and its configuration (a least-squares
    answer)."""
    Q = np.empty((samples, samples, 4, 3))          # only the first C[i, j] branches of a point are written and read
    E = np.empty((samples, samples, 4, 5))
    C = np.zeros((samples, samples), dtype=np.int64)
    _grid(H, P, R06, p, samples, Q, E, C)
    cand = np.zeros((MAXCAND, 5))
    nc = _candidates(Q, E, C, samples, cand)
    q = np.empty(6)
    x = _cross(H[5], H[4])
    x = x / _norm(x)
    y0 = np.empty(3)
    for r in range(3):
        y0[r] = R06[r, 0] * x[0] + R06[r, 1] * x[1] + R06[r, 2] * x[2]
    for c in range(nc):
        for k in range(5):
            q[k] = cand[c, k]
        # q6 from the target's orientation (SP1 about h6 on a vector across it)
        y = y0.copy()
        for k in range(5):               # R_05ᵀ R_06 x
            y = rot(H[k], -q[k], y)
        yp = y - H[5] * _dot(H[5], y)
        q[5] = math.atan2(_dot(H[5], _cross(x, yp)), _dot(x, yp))
        err = _newton(H, P, RnT, R, p, scale, q)
        for k in range(6):
            q[k] = _wrap(q[k])
        if err <= tol:
            m = _add_row(Qout, m, q, 1e-7)
        elif m == 0 and err < best[0]:
            best[0] = err
            bestq[:] = q
    filled = 0
    for i in range(samples):
        for j in range(samples):
            if C[i, j] > 0:
                filled += 1
    return m, nc, filled


def _search(H, P, RnT, R, p, samples, tol, Qout, errs):
    """The whole search for one target ``(R, p)``: verified solutions into ``Qout (MAXSOL, 6)``. Returns
    ``(solutions, candidates)``; ``errs[0]`` gets the least error reached when there is no solution, and
    ``Qout[0]`` that configuration (a least-squares answer).

    An odd count means a solution is missing (a general 6R's real solutions come in pairs): first Newton steps
    from the solutions found (:func:`_twins`), then, if the count is still odd, a grid twice as fine (each cell a
    quarter of the size) and its twins, all merged. The finer grid is searched too where no solution was found
    but the (q3, q4, q5) problem has solutions at fewer than one grid point in :data:`THIN`: it is solvable only in
    bands of (q1, q2) that the grid barely touches, and solutions can lie in them between its points; a count still
    odd after that sends a grid four times as fine."""
    R06 = np.empty((3, 3))
    for r in range(3):
        for c in range(3):
            R06[r, c] = R[r, 0] * RnT[c, 0] + R[r, 1] * RnT[c, 1] + R[r, 2] * RnT[c, 2]
    scale = 0.0
    for k in range(7):
        scale += _norm(P[k])
    scale = max(scale, 1e-12)
    best = np.full(1, 1e300)
    bestq = np.zeros(6)
    m, nc, filled = _pass(H, P, RnT, R, R06, p, samples, tol, scale, Qout, 0, best, bestq)
    thin = m == 0 and 0 < filled and filled * THIN < samples * samples
    if m % 2 == 1:
        m = _twins(H, P, RnT, R, p, scale, tol, Qout, m)
    if (m % 2 == 1 or thin) and 2 * samples <= MAX_GRID:
        m, nc2, _ = _pass(H, P, RnT, R, R06, p, 2 * samples, tol, scale, Qout, m, best, bestq)
        nc += nc2
        if m % 2 == 1:
            m = _twins(H, P, RnT, R, p, scale, tol, Qout, m)
        if thin and m % 2 == 1 and 4 * samples <= MAX_GRID:   # thin bands, a solution still missing: 4x as fine
            m, nc2, _ = _pass(H, P, RnT, R, R06, p, 4 * samples, tol, scale, Qout, m, best, bestq)
            nc += nc2
            if m % 2 == 1:
                m = _twins(H, P, RnT, R, p, scale, tol, Qout, m)
    if m == 0:
        errs[0] = best[0]
        if nc:
            for k in range(6):
                Qout[0, k] = bestq[k]
    return m, nc


def _twins(H, P, RnT, R, p, scale, tol, Qout, m):
    """An odd count of solutions means one is missing (a general 6R's real solutions come in pairs: its other
    solutions are complex and come in conjugate pairs), most likely the twin of a solution found, which lay within
    a grid cell of it (the two windings cancel, and Newton from the cell finds one). So from each solution found,
    Newton steps start a little way along the direction in which the chain's Jacobian is nearest singular (its
    smallest singular vector, by inverse iteration), both ways, at distances 0.002-1 rad, until a new solution
    makes the count even. Returns the new count (unchanged if none is found: a target on a singularity can have
    an odd count of distinct solutions)."""
    J = np.empty((6, 6))
    JtJ = np.empty((6, 6))
    Rq = np.empty((3, 3))
    pq = np.empty(3)
    Wk = np.empty((18, 3))
    Ms = np.empty((6, 6))
    vs = np.empty(6)
    v = np.empty(6)
    w = np.empty(6)
    q = np.empty(6)
    m0 = m
    for o in range(m0):
        _fkj(H, P, RnT, Qout[o], J, Rq, pq, Wk)
        for r in range(3):
            for k in range(6):
                J[r, k] /= scale
        for r in range(6):
            for c in range(6):
                t = 0.0
                for k in range(6):
                    t += J[k, r] * J[k, c]
                JtJ[r, c] = t
            JtJ[r, r] += 1e-12
            v[r] = 1.0 / math.sqrt(6.0) if r % 2 == 0 else -1.0 / math.sqrt(6.0)
        for _ in range(8):          # inverse iteration: v -> the eigenvector of JᵀJ of its least eigenvalue
            if not _solve6(JtJ, v, w, Ms, vs):
                break
            n = 0.0
            for r in range(6):
                n += w[r] * w[r]
            n = math.sqrt(n)
            if not n > 0.0:
                break
            for r in range(6):
                v[r] = w[r] / n
        for step in (0.002, 0.006, 0.02, 0.06, 0.2, 0.4, 0.7, 1.0):
            for sign in (1.0, -1.0):
                for k in range(6):
                    q[k] = Qout[o, k] + sign * step * v[k]
                if _newton(H, P, RnT, R, p, scale, q) > tol:
                    continue
                for k in range(6):
                    q[k] = _wrap(q[k])
                found = _add_row(Qout, m, q, 1e-7)
                if found > m:
                    return found
    return m


KERNELS = ("_lin2", "_arm", "_reject", "_branches", "_q345", "_grid",
           "_adiff", "_near", "_halves", "_candidates", "_fkj", "_err", "_solve6", "_newton", "_pass", "_twins",
           "_search")
UNCOUNTED = ("_lin2", "_reject", "_branches", "_adiff", "_near", "_halves", "_fkj", "_err", "_solve6")
"""The kernels compiled without reference counts (:func:`.subproblems.jit_namespace`): they make no array."""
_KERNELS: Optional[types.SimpleNamespace] = None


def kernels() -> Optional[types.SimpleNamespace]:
    """The compiled search (attributes named as its functions), or None without Numba; compiled on first use."""
    global _KERNELS
    if _KERNELS is None:
        sk = _sp.kernels()
        if sk is None:
            return None
        try:
            extra = _kk.extra()
        except ImportError:
            return None
        extra.update({name: sk.namespace[name] for name in _sp.KERNELS})
        ns = _sp.jit_namespace(globals(), KERNELS, extra=extra, uncounted=UNCOUNTED)

        _jit_loader.forget_stale_cache(ns, ("ik/geometric/subproblems.py", "ik/geometric/_kernels.py",
                                                 "kinematics/_jit.py"))
        _KERNELS = types.SimpleNamespace(**{name: ns[name] for name in KERNELS})
    return _KERNELS


def gen_six_dof(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *, samples: int = N,
                jit: Optional[bool] = None):  # type: ignore[no-untyped-def]
    """Every solution of a general 6R chain (all revolute; no relation between its axes is assumed) by the 2-D
    search over q1, q2 described in the module docstring (``samples`` × ``samples`` grid, :func:`resolution`;
    ``samples`` from 4 to :data:`MAX_GRID`).

    Returns :class:`~.solvers.Solutions`: the solutions found, each verified by FK of ``form`` to
    :data:`~.solvers.TOL`; when none is found, the closest configuration reached (``ls`` True) or nothing.
    ``jit``: the compiled search (default: when armkit's back end is Numba), or the plain functions.

    Examples
    --------
    >>> import numpy as np
    >>> from armkit.ik.geometric.poe import POE
    >>> g = np.random.default_rng(7)
    >>> H = g.normal(size=(6, 3)); H /= np.linalg.norm(H, axis=1, keepdims=True)
    >>> P = g.normal(size=(7, 3)) * 0.4
    >>> form = POE(H, P, np.eye(3), np.zeros(6, dtype=bool))
    >>> q = np.array([0.3, -1.0, 0.5, 2.0, -0.4, 1.1])
    >>> R, p = form.fk(q)
    >>> sol = gen_six_dof(form, R, p)
    >>> bool(any(np.abs(s - q).max() < 1e-9 for s in sol.q))
    True
    """
    from .solvers import TOL, Solutions, _use_jit

    if form.n != 6 or np.any(form.prismatic):
        raise ValueError("gen_six_dof: for 6R chains (every joint revolute)")
    samples = int(samples)
    if not 4 <= samples <= MAX_GRID:
        raise ValueError(f"gen_six_dof: samples must be from 4 to {MAX_GRID} (a grid of {MAX_GRID} x {MAX_GRID} "
                         f"points takes {MAX_GRID ** 2 * 264 / 1e6:.0f} MB), got {samples}")
    K = kernels() if _use_jit(jit) else None
    search = K._search if K is not None else _search
    c = np.ascontiguousarray
    H = c(form.H, dtype=float)
    P = c(form.P, dtype=float)
    RnT = c(form.R_nT, dtype=float)
    Qout = np.zeros((MAXSOL, 6))
    errs = np.zeros(1)
    m, nc = search(H, P, RnT, c(R, dtype=float), c(p, dtype=float), samples, TOL, Qout, errs)
    m = int(m)
    if m:
        return Solutions(Qout[:m].copy(), np.zeros(m, dtype=bool), np.zeros(m, dtype=bool))
    if nc:
        return Solutions(Qout[:1].copy(), np.ones(1, dtype=bool), np.zeros(1, dtype=bool))
    return Solutions(np.zeros((0, 6)), np.zeros(0, dtype=bool), np.zeros(0, dtype=bool))
