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

The engine (:func:`_search`) samples ``x`` at :data:`N` points over a turn (compiled, the closed-form
quartic of :mod:`._kernels` inside SP5/SP6, no Python and no temporary arrays per sample) and pairs the branches of neighbouring
samples by distance (a step where they do not pair up one to one, each within 0.25 rad and three times nearer
than any other, is sampled :data:`SUB_N` times finer). Then, along each branch:

* a sign change between two samples is refined by false position (Illinois) that follows the
  branch, to 1e-14 rad;
* a local extremum of the residual on the side away from 0 whose parabola through three samples
  comes within one second difference of 0 is searched by golden section (stopping as soon as the
  residual changes sign): two roots within one step, or a double root (kept when its residual is
  below 1e-12); where a step sampled finer meets a plain one, the three samples about the seam are
  unequally spaced and looked at the same way (:func:`_seam`: a branch that moves more than 0.5 rad
  in the plain step is not matched across it, and two roots beside it were missed);
* a step across which the residual keeps its sign, where the cubic through the four samples about it has a
  minimum (of the residual's distance from 0) inside the step beyond 0, is searched
  the same way (:func:`_wiggle`: an S-shaped stretch, a root just before the step and two inside it, rises
  through the samples without an extremum at any of them);
* a branch that ends between two samples (two subproblem solutions meet, the residual changes
  like the square root of the distance there) has its end found by bisection (to 3e-10 rad, or
  until the branch and the one it meets there have residuals of one sign that differ by under a
  quarter of the smaller: the rest of that fold cannot reach 0, :func:`_settled`) and is sampled
  :data:`EDGE_N` more times towards it, quadratically spaced (from at least one step back), then as above
  (sign changes, and extrema turning back towards 0); the two branches that meet there are one curve
  through the end, evenly sampled in the square root of the distance to it, and a dip of that curve between
  the last samples is searched too (:func:`_fold_dip`); where the residual of the branch nearest to the
  ending one changes sign between two of those samples, that root is followed by bisection
  (:func:`_fold_root`: a partner that swings more than 0.5 rad between two samples stops its own trace short);
* a pair of branches that is born and dies between two samples (an *island*: SW, SM, SP3 has solutions
  only on an interval of the searched joint narrower than a step; TI, TP, two roots of SP6's quartic turn
  real there and back) is looked for where the subproblem's margin (how far it is from giving two more
  solutions: SP3's, or how near SP6's complex roots are to real, :func:`._kernels._trig2m`) peaks between
  samples with as many branches: its maximum by Brent's method (parabolas, golden section where they fail; to
  :data:`ISLAND_TOL`), the island's ends by bisection, then
  :data:`SUB_N` samples between them (sign changes, and dips turning back towards 0), and the same in the other
  step beside that sample, which can sit in the gap between two islands (:func:`_islands`). benchmarks/bench_coverage.py found such targets
  (tests/ik/geometric/test_search_found_cases.py): an SM search had answered "unreachable" where four
  solutions exist, and a TP search had missed the two solutions of an island 0.02 rad wide.

The turn is closed: its last sample is its first (copied; evaluated again at ``−π + N step`` ≈ π, rounding could
give the two copies residuals of opposite signs around a root at ±π, which then fell between them). A residual
within :data:`ZERO` of 0 at a sample is a root there (a joint value such as 0 or ±π puts one exactly on a
sample), and the sign changes of the steps beside it are tested :data:`NUDGE` of a step inside (a second root
can share the step: its sign at the sample is rounding).

Resolution: :data:`N` = 240 samples (1.5° apart), :data:`SUB_N` × finer in ambiguous steps. A root
can be missed only when three or more roots of one branch lie within one step, two within 3e-10
rad of a branch end, or a double root's residual stays above 1e-12, or two roots crowd within one
step next to a branch end, or an island lies where the three samples about it differ in count, or the parabola
of its margin through them peaks more than one second difference below 0 while the margin at the middle sample
is at most :data:`STEEP` and (TI, TP) the parabola of ``1 / (1 + margin)`` stays above :data:`SHARP_U`
(:func:`_sharp_peak`), or an island is narrower than :data:`ISLAND_TOL` (measured against a dense scan of 20,000 samples on 200 random targets
of each class, tests/ik/geometric/test_search_speed_free.py: 0 missing for all four; TI lost one target's
near-double root, residual peak 2e-6, beside a step sampled finer, until the seams of those steps were looked at,
:func:`_seam`). The
solvers of :mod:`.solvers` complete each root to the six joints and check every solution by FK of
the true chain (TOL 1e-9), polishing by Newton steps where the chain's axes only nearly meet.

:func:`kernels` compiles the engine with Numba like :mod:`.solvers`; the plain functions run
without it (slowly: about a second a target).
"""

from __future__ import annotations

import math
import types
from typing import Any, Optional

import numpy as np
from numpy.typing import NDArray

from ... import _jit_loader
from . import _kernels as _kk
from . import subproblems as _sp
from ._kernels import (_PI, _add_row, _sp3, _sp3_cos, _sp6, _t, _tadd, _tdot, _tlin, _tmul, _tmv, _tnorm,
                       _trig2_rows, _trot, _trot_cs, _tsp1_cs, _tsub, _wrap)
from .poe import POE

__all__ = ["two_parallel", "N", "SUB_N", "EDGE_N", "MAXROOT", "WIDTH", "kernels", "TI", "TP", "SW", "SM"]

Array = NDArray[np.float64]

N = 240
"""Samples of the searched joint over one turn (1.5° apart)."""
SUB_N = 16
"""Sub-samples of a step where the branches of its two ends do not pair up one to one within 0.1 rad."""
EDGE_N = 6
"""Samples (quadratically spaced) between the last sample of a branch and where it ends (was 10; with the end
bracketed by :func:`_settled`, 6 lose nothing against the dense scan of the tests)."""
WIDTH = 7
"""Columns of a branch row ``S[i]``: the branch (three joints), then for TI and TP the cosines and sines of the two
joints SP6 gives (:func:`._kernels._trig2m`), which the residual rotates by (no ``cos``/``sin`` calls for them)."""
MAXROOT = 64
MEMO = 64
"""Evaluations :func:`_edges` remembers (:func:`_eval_memo`): the two branches that meet where they end between two
samples are each traced to that end by :func:`_edge`, at the same points (half of its evaluations, counted)."""
MEMO_COLS = 6 + 4 * WIDTH
"""A remembered evaluation's row: ``x``, the branch count, the four residuals, then the branch rows ``S``."""
FOLD_IT = 48
"""Bisection steps of :func:`_fold_root` (in the square-root parameter: the last step is under 1e-14 of the
distance from the end to the last sample)."""
FOLD_TOL = 1e-9
"""The largest residual :func:`_fold_root` keeps as a root (its bisection ends at a sign change: a root, or a jump
from one branch to another, whose residual stays large)."""
ZERO = 1e-12
"""A residual at a sample within this of 0 is a root on the sample (its sign is rounding)."""
NUDGE = 1e-6
"""Where a step with such a sample at an end is tested for a sign change instead (fraction of the step)."""
STEEP = -0.9
"""A margin peak at a sample above this is searched for an island even where the parabola through the three
samples stays far below 0: the margin of SP5/SP6 lies near -1 away from an island and rises to 0 within a few
thousandths of a radian of it (bench_coverage found islands 0.009-0.01 rad wide whose samples read -0.99, -0.77,
-0.89), steeper than any parabola through the samples."""
ISLAND_TOL = 1e-9
"""How closely (rad) :func:`_island` locates a maximum of the margin that stays below 0 before it gives up (an
island narrower than this can be missed; its solutions lie within it, a near double root, as at a branch end's
3e-10). Golden section to 1e-12 took ~55 evaluations a peak; Brent's method to 1e-9, 13-18 at a smooth peak and
~37 where the margin peaks at a jump (the nearest complex root changes)."""
SHARP_U = 2.0
"""The level of ``1 / (1 + margin)`` below which :func:`_sharp_peak` sends a peak of SP6's margin to the island
search (2: the margin's peak predicted above -0.5; an island is where it reaches 0, level 1)."""
_YES, _NO = np.True_, np.False_
"""True and False that Numba types as ``bool``, not as the literals (which would compile a copy of the callee for
each)."""
TI, TP, SW, SM = np.int64(0), np.int64(1), np.int64(2), np.int64(3)
"""The kinds of search (see the table above): NumPy integers, which Numba types as ``int64`` (a Python int
constant would be a literal, and each kind would compile its own copy of every function of the engine)."""

# ------------------------------------------------------------------------------ the branches
def _eval(kind, H, P, C, x, S, E):
    """The branches at ``x`` into ``S (4, WIDTH)``, their residuals into ``E (4,)``; returns their count.
    ``C (4, 3)``: the target, per kind (TI: ``e6``, ``p0w``; TP, SM: the rows of ``R_06``, then ``p``;
    SW: ``p0W``); TP's in :func:`_search` has three rows more (:func:`_with_terms`)."""
    if kind == TI:
        return _eval_ti(H, P, C, x, S, E)
    if kind == TP:
        return _eval_tp(H, P, C, x, S, E)
    if kind == SW:
        return _eval_sw(H, P, C, x, S, E)
    return _eval_sm(H, P, C, x, S, E)


def _eval_ti(H, P, C, x, S, E):
    """Axes 5, 6 meet (P[5] = 0), q1 = ``x``: SP5 ``−P2 + rot(−h2, q2) v = rot(h3, q3) (P3 + rot(h4, q4) P4)``
    for ``v = rot(h1, −x) p0w − P1``; residual ``(R_04 h5)ᵀ e6 − h5ᵀ h6``. With fewer than 4 branches, ``E[3]`` is
    SP6's margin, squared and negated (:func:`._kernels._trig2m`, :func:`_margin`)."""
    h0 = _t(H[0])
    k1 = _tmul(_t(H[1]), -1.0)
    k2 = _t(H[2])
    k3 = _t(H[3])
    p0 = _tmul(_t(P[2]), -1.0)
    cx = math.cos(x)
    sx = math.sin(x)
    p1 = _tsub(_trot_cs(h0, cx, -sx, _t(C[1])), _t(P[1]))
    p2 = _t(P[3])
    p3 = _t(P[4])
    n, mg = _sp6(k2, k1, p1, _tmul(k2, -1.0), k3, p3, _tmul(p0, 2.0), k1, p1, _tmul(p2, -2.0), k3, p3,
             _tdot(k2, p2) - _tdot(k2, p0), _tdot(p2, p2) + _tdot(p3, p3) - _tdot(p0, p0) - _tdot(p1, p1),
             S[:, 0], S[:, 2], S[:, 3:])    # q2, q4 and their cosines, sines straight into the branch rows
    c = _tdot(_t(H[4]), _t(H[5]))
    e6 = _t(C[0])
    h4 = _t(H[4])
    for i in range(n):
        c1 = S[i, 3]
        s1 = S[i, 4]
        c3 = S[i, 5]
        s3 = S[i, 6]
        v = _tadd(p0, _trot_cs(k1, c1, s1, p1))
        w = _tadd(p2, _trot_cs(k3, c3, s3, p3))
        t2, c2, s2 = _tsp1_cs(w, v, k2)
        S[i, 1] = t2
        a = _trot_cs(k3, c3, s3, h4)
        a = _trot_cs(k2, c2, s2, a)
        a = _trot_cs(k1, c1, -s1, a)      # rot(−h2, −q2) = rot(h2, q2)
        a = _trot_cs(h0, cx, sx, a)
        E[i] = _tdot(a, e6) - c
    if n < 4:      # how near SP6 is to two more branches, kept for the island check (_islands)
        E[3] = -mg * mg
    return n


def _point5(H, P, C, x):
    """With q6 = ``x`` (``C``: the rows of ``R_06``, then ``p``): ``(p − P0 − R_05 P5 − R_06 P6, R_05 h5)``, the point
    of axis 5 seen from axis 1's point and axis 5's direction, for ``R_05 = R_06 rot(h6, −x)``."""
    cx = math.cos(x)
    sx = -math.sin(x)                     # rot(h6, −x)
    h6 = _t(H[5])
    R = C[0:3]
    # R_05 u = R_06 (rot(h6, −x) u): two vectors rotated, not the three columns of R_05
    R05p5 = _tmv(R, _trot_cs(h6, cx, sx, _t(P[5])))
    w = _tsub(_tsub(_tsub(_t(C[3]), _t(P[0])), R05p5), _tmv(R, _t(P[6])))
    v = _tmv(R, _trot_cs(h6, cx, sx, _t(H[4])))
    return w, v


def _tp_terms(H, P):
    """The terms of :func:`_eval_tp`'s SP6 that do not depend on the searched joint: ``(b00, b01, c1)`` and
    ``(b10, b11, c3)`` of :func:`._kernels._tlin` for ``(−h2)ᵀ rot(h4, q4) P4`` and ``(−h2)ᵀ rot(h4, q4) h5``, and
    ``d1 = h2ᵀ (P1 + P2 + P3)``."""
    h1 = _t(H[1])
    h3 = _t(H[3])
    mh1 = _tmul(h1, -1.0)
    b00, b01, c1 = _tlin(mh1, h3, _t(P[4]))
    b10, b11, c3 = _tlin(mh1, h3, _t(H[4]))
    return b00, b01, c1, b10, b11, c3, _tdot(h1, _tadd(_tadd(_t(P[1]), _t(P[2])), _t(P[3])))


def _with_terms(kind, H, P, C):
    """``C`` of the search ``kind``, for TP with three rows more: :func:`_tp_terms`, made once for the whole search
    (``C (7, 3)``; :func:`_eval_tp` reads them there)."""
    if kind != TP:
        return C
    C2 = np.zeros((7, 3))
    for i in range(4):
        for j in range(3):
            C2[i, j] = C[i, j]
    b00, b01, c1, b10, b11, c3, d1 = _tp_terms(H, P)
    C2[4, 0], C2[4, 1], C2[4, 2] = b00, b01, c1
    C2[5, 0], C2[5, 1], C2[5, 2] = b10, b11, c3
    C2[6, 0] = d1
    return C2


def _eval_tp(H, P, C, x, S, E):
    """Axes 2 ∥ 3, q6 = ``x``: SP6 in (q1, q4), θ = q2 ± q3 by SP1; residual ``|d| − |P3|`` (see :func:`two_parallel`).
    With fewer than 4 branches, ``E[3]`` is SP6's margin, squared and negated (:func:`_margin`)."""
    h0 = _t(H[0])
    h1 = _t(H[1])
    h3 = _t(H[3])
    h4 = _t(H[4])
    w, v = _point5(H, P, C, x)
    mh0 = _tmul(h0, -1.0)
    if C.shape[0] >= 7:                   # SP6's terms that do not depend on x, made once (_tp_terms)
        b00, b01, c1 = C[4, 0], C[4, 1], C[4, 2]
        b10, b11, c3 = C[5, 0], C[5, 1], C[5, 2]
        d1 = C[6, 0]
    else:
        b00, b01, c1, b10, b11, c3, d1 = _tp_terms(H, P)
    # SP6 (as _kernels._sp6): h1ᵀ rot(−h0, q1) w + (−h1)ᵀ rot(h3, q4) P4 = d1, the same with v and h4 = 0
    a00, a01, c0 = _tlin(h1, mh0, w)
    a10, a11, c2 = _tlin(h1, mh0, v)
    n, mg = _trig2_rows(a00, a01, b00, b01, d1 - c0 - c1, a10, a11, b10, b11, 0.0 - c2 - c3, S[:, 0], S[:, 1],
                        S[:, 3:])
    n2 = _tnorm(_t(P[2]))
    for i in range(n):
        c0 = S[i, 3]
        s0 = -S[i, 4]                    # rot(h1, −q1)
        c3 = S[i, 5]
        s3 = S[i, 6]
        u = _trot_cs(h3, c3, s3, h4)
        th, ct, st = _tsp1_cs(u, _trot_cs(h0, c0, s0, v), h1)
        d = _tsub(_tsub(_trot_cs(h0, c0, s0, w), _t(P[1])),
                  _trot_cs(h1, ct, st, _tadd(_t(P[3]), _trot_cs(h3, c3, s3, _t(P[4])))))
        S[i, 2] = th
        E[i] = _tnorm(d) - n2
    if n < 4:      # how near SP6 is to two more branches, kept for the island check (_islands)
        E[3] = -mg * mg
    return n


def _eval_sw(H, P, C, x, S, E):
    """Axes 4, 5, 6 meet, q1 = ``x``: q3 by SP3 ``‖rot(h3, q3) P3 + P2‖ = ‖v‖`` for ``v = rot(h1, −x) p0W − P1``;
    residual ``h2ᵀ v − h2ᵀ (P2 + rot(h3, q3) P3)``. Without branches, ``E[0]`` is SP3's margin (:func:`_margin`)."""
    v = _tsub(_trot(_t(H[0]), -x, _t(C[0])), _t(P[1]))
    n = _sp3(_t(P[3]), _tmul(_t(P[2]), -1.0), _t(H[2]), _tnorm(v), S[:, 0])
    if n == 0:   # how far from having branches: kept for the island check (_islands)
        E[0] = 1.0 - abs(_sp3_cos(_t(P[3]), _tmul(_t(P[2]), -1.0), _t(H[2]), _tnorm(v))[0])
        return 0
    h1 = _t(H[1])
    hv = _tdot(h1, v) - _tdot(h1, _t(P[2]))
    for i in range(n):
        S[i, 1] = 0.0
        S[i, 2] = 0.0
        E[i] = hv - _tdot(h1, _trot(_t(H[2]), S[i, 0], _t(P[3])))
    return n


def _eval_sm(H, P, C, x, S, E):
    """Axes 2, 3, 4 meet (P[2] = P[3] = 0), q6 = ``x``: q1 by SP3 ``‖rot(h1, q1) P1 − u‖ = ‖P4‖`` for
    ``u = p − P0 − R_05 P5 − R_06 P6``; residual ``(R_05 h5)ᵀ (u − rot(h1, q1) P1) − h5ᵀ P4``. Without branches,
    ``E[0]`` is SP3's margin (:func:`_margin`)."""
    h4 = _t(H[4])
    u, z = _point5(H, P, C, x)
    p1 = _t(P[1])
    n = _sp3(p1, u, _t(H[0]), _tnorm(_t(P[4])), S[:, 0])
    if n == 0:   # how far from having branches: kept for the island check (_islands)
        E[0] = 1.0 - abs(_sp3_cos(p1, u, _t(H[0]), _tnorm(_t(P[4])))[0])
        return 0
    c = _tdot(h4, _t(P[4]))
    for i in range(n):
        S[i, 1] = 0.0
        S[i, 2] = 0.0
        E[i] = _tdot(z, _tsub(u, _trot(_t(H[0]), S[i, 0], p1))) - c
    return n


def _margin(kind, H, P, C, x, S, E, base):
    """1 where there are more than ``base`` branches at ``x``; else how far the subproblem is from giving two more
    (< 0; -inf where it cannot): for SP3 (SW, SM, ``base`` 0) ``1 − |x|`` of :func:`._kernels._sp3_cos`, which
    :func:`_eval` leaves in ``E[0]``; for SP6 (TI, TP) minus the square of :func:`._kernels._trig2m`'s margin (it
    changes like the distance to where a complex pair of the quartic turns real), left in ``E[3]``. ``S (4, WIDTH)``,
    ``E (4,)``: work space."""
    c = _eval(kind, H, P, C, x, S, E)
    if c > base:
        return 1.0
    if kind == SW or kind == SM:
        return E[0]
    return E[3] if c < 4 else -np.inf


def _island(kind, H, P, C, a, b, base):
    """A point of ``[a, b]`` where the margin (:func:`_margin`) is >= 0, by Brent's method towards its maximum
    (the margin is below 0 at ``a``, at ``b`` and at their midpoint, and the midpoint's is the largest of the
    three): a parabola through the three best points so far where it moves inside the bracket and by less than
    half the step before last, a golden-section step into the larger part otherwise; stopped as soon as the
    margin is >= 0, or when the maximum is known to :data:`ISLAND_TOL`; ``nan`` if it stays below 0.

    Near a maximum below 0 the margin is smooth (a complex pair of the quartic that comes near the real axis and
    leaves it), where parabolas converge in a few steps; golden section alone took ~55 (to 1e-12 rad) on each of the
    ~40 % of targets that look for an island and have none."""
    S = np.empty((4, WIDTH))
    E = np.empty(4)
    g = 0.3819660112501051                  # 1 - 1/φ: the golden-section step, as a fraction of the part
    x = 0.5 * (a + b)
    fx = -_margin(kind, H, P, C, x, S, E, base)   # minimised
    if fx <= 0.0:
        return x
    w = x
    v = x
    fw = fx
    fv = fx
    d = 0.0
    e = 0.0                                  # the step before last
    for _ in range(100):
        m = 0.5 * (a + b)
        tol = ISLAND_TOL
        if abs(x - m) <= 2.0 * tol - 0.5 * (b - a):
            break
        golden = True
        if abs(e) > tol and math.isfinite(fx) and math.isfinite(fw) and math.isfinite(fv):
            r = (x - w) * (fx - fv)
            q = (x - v) * (fx - fw)
            p = (x - v) * q - (x - w) * r
            q = 2.0 * (q - r)
            if q > 0.0:
                p = -p
            q = abs(q)
            last = e
            if abs(p) < abs(0.5 * q * last) and q * (a - x) < p < q * (b - x):
                e = d
                d = p / q                    # the parabola's vertex
                u = x + d
                if u - a < 2.0 * tol or b - u < 2.0 * tol:
                    d = tol if m > x else -tol
                golden = False
        if golden:
            e = a - x if x >= m else b - x
            d = g * e
        u = x + (d if abs(d) >= tol else (tol if d > 0.0 else -tol))
        fu = -_margin(kind, H, P, C, u, S, E, base)
        if fu <= 0.0:
            return u
        if fu <= fx:
            if u >= x:
                a = x
            else:
                b = x
            v, fv = w, fw
            w, fw = x, fx
            x, fx = u, fu
        else:
            if u < x:
                a = u
            else:
                b = u
            if fu <= fw or w == x:
                v, fv = w, fw
                w, fw = u, fu
            elif fu <= fv or v == x or v == w:
                v, fv = u, fu
    return np.nan


def _rim(kind, H, P, C, inside, outside, base):
    """The end of an island (:func:`_islands`) between ``inside`` (margin >= 0) and ``outside`` (< 0), by bisection
    of the margin to rounding: the last point found inside."""
    S = np.empty((4, WIDTH))
    E = np.empty(4)
    for _ in range(200):
        x = 0.5 * (inside + outside)
        if x == inside or x == outside:
            break
        if _margin(kind, H, P, C, x, S, E, base) >= 0.0:
            inside = x
        else:
            outside = x
    return inside


def _sharp_peak(ma, mb, mc):
    """Whether SP6's margin (TI, TP), at three neighbouring samples ``ma < mb > mc``, may reach 0 between them by the
    shape of its peaks: near an island it rises like ``-1 + A / ((x - x0)^2 + e)`` (measured on a coverage check's
    miss, A within 15 % of its mean from 0.004 to 0.026 rad off the island's middle), so ``1 / (1 + margin)`` is a
    parabola in ``x``; where the parabola through the samples' values dips below :data:`SHARP_U` (a margin above
    -0.5 at its lowest point), the island is searched."""
    if not (ma > -1.0 and mc > -1.0):
        return False
    ua = 1.0 / (1.0 + ma)
    ub = 1.0 / (1.0 + mb)
    uc = 1.0 / (1.0 + mc)
    e2 = ua - 2.0 * ub + uc
    return e2 > 0.0 and ub - (uc - ua) * (uc - ua) / (8.0 * e2) <= SHARP_U


def _islands(kind, H, P, C, n, step, cnt, E, roots, m, out, pp, wk, mid):
    """A pair of branches that lives only between two samples (an *island*: SW, SM, SP3 has solutions on an
    interval of the searched joint narrower than a step; TI, TP, two roots of SP6's quartic turn real and back
    there): where three neighbouring samples have as many branches and the margin of the subproblem (how near it
    is to two more, :func:`_margin`) peaks in the middle one, and the parabola through them comes within one second
    difference of 0 (as :func:`_extrema` looks at residuals), its maximum is searched (:func:`_island`). An island
    found has its two ends found by bisection of the margin (:func:`_rim`; there its two branches meet) and is
    sampled :data:`SUB_N` times between them, closer towards the ends (cosine spacing: the branches move like
    the square root of the distance to an end), the sign changes refined as between any samples (:func:`_pair`;
    roots found twice are kept once), and dips turning back towards 0 searched as at a seam (:func:`_seam`: a
    coverage check found two roots 0.00013 rad apart inside an island). Where one is found, the other step beside
    the middle sample is searched too: a coverage check found a sample in a gap 0.003 rad wide between two islands,
    the second one holding two solutions. Returns the new count of ``roots``."""
    sp3 = kind == SW or kind == SM
    M = np.full(n, -np.inf)
    for i in range(n):
        if sp3 and cnt[i] == 0:
            M[i] = E[i, 0]   # the margin, left there by _eval_sw / _eval_sm
        elif not sp3 and cnt[i] < 4:
            M[i] = E[i, 3]   # by _eval_ti / _eval_tp
    Ss = np.zeros((SUB_N + 1, 4, WIDTH))
    Es = np.zeros((SUB_N + 1, 4))
    cs = np.zeros(SUB_N + 1, dtype=np.int64)
    xs = np.zeros(SUB_N + 1)
    D = np.zeros((SUB_N, 4, 4))
    for c in range(n):
        a = c - 1 if c > 0 else n - 1
        b = c + 1 if c + 1 < n else 0
        ma = M[a]
        mb = M[c]
        mc = M[b]
        if not (ma < mb and mc < mb and ma > -np.inf and mc > -np.inf and cnt[a] == cnt[c] and cnt[b] == cnt[c]):
            continue
        d2 = ma - 2.0 * mb + mc
        if mb - (mc - ma) * (mc - ma) / (8.0 * d2) < d2 and not mb > STEEP \
                and (sp3 or not _sharp_peak(ma, mb, mc)):   # the parabola's peak below 0 by more than |d2|, the
            continue                                         # peak low, and no sharp one in between
        base = cnt[c]
        xc = -_PI + c * step
        first = _island(kind, H, P, C, xc - step, xc + step, base)
        if first != first:
            continue
        for side in range(2):
            x = first
            if side == 1:   # the other step beside the sample: it can sit in the gap between two islands
                x = _island(kind, H, P, C, xc, xc + step, base) if first < xc else \
                    _island(kind, H, P, C, xc - step, xc, base)
                if x != x:
                    break
            xa = xc - step if x < xc else xc
            lo = _rim(kind, H, P, C, x, xa, base)
            hi = _rim(kind, H, P, C, x, xa + step, base)
            for k in range(SUB_N + 1):
                xs[k] = lo + (hi - lo) * 0.5 * (1.0 - math.cos(_PI * k / SUB_N))
                cs[k] = _eval(kind, H, P, C, xs[k], Ss[k], Es[k])
            for k in range(SUB_N):
                _dists(Ss[k], cs[k], Ss[k + 1], cs[k + 1], D[k])
                m = _pair(kind, H, P, C, xs[k], Ss[k], Es[k], cs[k], xs[k + 1], Ss[k + 1], Es[k + 1], cs[k + 1], D[k],
                          roots, m, out, pp, wk)
            for k in range(SUB_N - 1):   # and the dips between them (unequally spaced: _seam's parabola)
                m = _seam(kind, H, P, C, xs[k], Ss[k], Es[k], cs[k], D[k], xs[k + 1], Ss[k + 1], Es[k + 1], cs[k + 1],
                          D[k + 1], xs[k + 2], Ss[k + 2], Es[k + 2], cs[k + 2], roots, m, out, mid)
    return m


# ---------------------------------------------------------------------------------- the engine
def _adist(a, b):
    d = 0.0
    for k in range(3):
        d = max(d, abs(_wrap(a[k] - b[k])))
    return d


def _pick(kind, H, P, C, x, ref, S, E):
    """The branch at ``x`` nearest to ``ref (3,)``: ``(index, distance)``; index -1 if none."""
    return _nearest(S, _eval(kind, H, P, C, x, S, E), ref)


def _nearest(S, n, ref):
    """The row of ``S[:n]`` nearest to ``ref``: ``(index, distance)``; index -1 if none."""
    best = -1
    bd = 1e300
    for i in range(n):
        d = _adist(S[i], ref)
        if d < bd:
            bd = d
            best = i
    return best, bd


def _owned(row, d, S0, c0, j0):
    """Whether ``row``, at distance ``d`` from the last point of branch ``j0`` of a sample (branches
    ``S0[:c0]``), lies nearer to that point than to every other branch of the sample (:func:`_edge`)."""
    for o in range(c0):
        if o != j0 and _adist(row, S0[o]) < d:
            return False
    return True


def _refine(kind, H, P, C, a, fa, ref, b, fb, out):
    """The zero between ``a`` (branch ``ref``, residual ``fa``) and ``b`` (residual ``fb`` of the same branch,
    opposite sign) by false position (Illinois), following the branch; ``(x, branch)`` into ``out (4,)``.
    False when the branch is lost."""
    S = np.empty((4, WIDTH))
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
    """Append the root ``out`` to ``roots[:m]`` unless there already (to 1e-9, or full); returns the new count."""
    return _add_row(roots, m, out, 1e-9)


def _dip(kind, H, P, C, a, b, ref, sg, out):
    """The minimum of ``sg`` × the residual of the branch through ``ref`` on [a, b] by golden section, stopped
    as soon as it is below 0: ``(x, residual)``, the branch there into ``out (3,)``; ``nan`` if lost."""
    S = np.empty((4, WIDTH))
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


def _nearest_other(S, n, i):
    """The row of ``S[:n]`` other than ``i`` nearest to row ``i``: ``(index, distance)``; index -1 if none."""
    best = -1
    bd = 1e300
    for k in range(n):
        if k != i:
            d = _adist(S[k], S[i])
            if d < bd:
                bd = d
                best = k
    return best, bd


def _settled(S, E, i, n):
    """Near a branch end: whether no root can lie between here and the end on branch ``i`` or on the branch that
    meets it there. Its partner is the nearest other branch (within 0.05 rad); near the end both residuals go
    like ``E0 ± a √(x_end − x)``, so while they have one sign and differ by under a quarter of the smaller
    (the fold's residuals from here to the end lie between them, up to higher-order terms), the rest of the fold
    keeps that sign."""
    j, d = _nearest_other(S, n, i)
    if j < 0 or not d < 0.05:
        return False
    a = E[i]
    b = E[j]
    return a * b > 0.0 and abs(a - b) < 0.25 * min(abs(a), abs(b))


def _eval_memo(kind, H, P, C, x, S, E, MR, MC):
    """:func:`_eval` at ``x`` unless the memo ``MR (MEMO, MEMO_COLS)`` holds that very ``x`` (in its first ``MC[0]``
    rows, a ring of :data:`MEMO`), whose branches and residuals are then copied; a new evaluation is kept there.
    The same answer as :func:`_eval` to the bit (the same ``x`` evaluated again)."""
    k = MC[0]
    cap = MR.shape[0]
    w = S.shape[1]
    for r in range(min(k, cap)):
        if MR[r, 0] == x:
            for i in range(4):
                E[i] = MR[r, 2 + i]
                for j in range(w):
                    S[i, j] = MR[r, 6 + i * w + j]
            return np.int64(MR[r, 1])
    n = _eval(kind, H, P, C, x, S, E)
    r = k % cap
    MR[r, 0] = x
    MR[r, 1] = n
    for i in range(4):
        MR[r, 2 + i] = E[i]
        for j in range(w):
            MR[r, 6 + i * w + j] = S[i, j]
    MC[0] = k + 1
    return n


def _edges(kind, H, P, C, x0, S0, c0, link, x1, roots, m):
    """:func:`_edge` for each branch ``j`` of the sample at ``x0`` with ``link[j] < 0`` (no partner at the
    neighbouring sample ``x1``), sharing one memo of evaluations (:func:`_eval_memo`): the two branches that end
    together are traced to their end at the same points. Returns the new count of ``roots``."""
    MR = np.empty((MEMO, MEMO_COLS))
    MC = np.zeros(1, dtype=np.int64)
    for j in range(c0):
        if link[j] < 0:
            m = _edge(kind, H, P, C, x0, S0, c0, j, x1, roots, m, MR, MC)
    return m


def _edge(kind, H, P, C, x0, S0, c0, j0, x1, roots, m, MR, MC):
    """Branch ``j0`` of the sample at ``x0`` (its branches ``S0[:c0]``) without a match at the neighbouring
    sample ``x1``: find where it ends (bisection), sample it towards the end quadratically spaced (the residual
    changes like a square root there) and refine the sign changes. Returns the new count of ``roots``.

    A branch found while bisecting is taken as this one only if it lies nearer to this one's last point than to
    every other branch of ``x0`` (:func:`_owned`): a pair of branches born just before ``x0`` has one member end
    just after it, and the other member, 0.43 rad away in ``(q1, q4, θ)``, was taken for it by the nearest-branch
    rule alone (bench_coverage found such a target: the root on the ending member was missed). ``MR``, ``MC``: the
    memo of :func:`_eval_memo`, shared with the other branches that end there (:func:`_edges`)."""
    S = np.empty((4, WIDTH))
    E = np.empty(4)
    ref = S0[j0]
    cur = ref.copy()
    good = x0
    bad = x1
    while abs(bad - good) > 3e-10:
        x = 0.5 * (good + bad)
        n = _eval_memo(kind, H, P, C, x, S, E, MR, MC)
        i, d = _nearest(S, n, cur)
        if i >= 0 and d < 0.5 and _owned(S[i], d, S0, c0, j0):
            good = x
            for k in range(3):
                cur[k] = S[i, k]
            if _settled(S, E, i, n):
                break
        else:
            bad = x
    # from as far again beyond x0 (where matching between samples can still confuse the two branches that
    # meet at the end), and at least one step (x0 to x1) back, to the end: where x0 is a sub-sample just before
    # the end, as far again was a sliver, and two roots just before x0 (the residual dipping below 0 and back
    # between the last two sub-samples) were missed (bench_coverage found such a target)
    back = max(abs(x0 - good), abs(x1 - x0))
    far = x0 - back if x1 > x0 else x0 + back
    i, d = _nearest(S, _eval_memo(kind, H, P, C, far, S, E, MR, MC), ref)
    if i < 0 or d > 0.5 or not _owned(S[i], d, S0, c0, j0):
        far = x0
        i, d = _nearest(S, _eval_memo(kind, H, P, C, x0, S, E, MR, MC), ref)
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
    rp = np.empty(3)      # the branch that meets this one at the end, at the last sample before it
    fp = 0.0
    XU = np.empty((EDGE_N + 1, 3))   # this branch at each sample towards the end, and the residual of the branch
    FQ = np.zeros(EDGE_N + 1)        # nearest to it there (at the end: this one's; 0 where none): _fold_root
    reached = False
    for k in range(1, EDGE_N + 1):
        t = 1.0 - k / EDGE_N
        xb = good + (far - good) * t * t
        nb = _eval_memo(kind, H, P, C, xb, S, E, MR, MC)
        i, d = _nearest(S, nb, prev)
        if i < 0 or d > 0.5:
            break
        fb = E[i]
        jp, dp = _nearest_other(S, nb, i)
        FQ[k] = fb if k == EDGE_N else (E[jp] if jp >= 0 else 0.0)
        for j in range(3):
            XU[k, j] = S[i, j]
        if k == EDGE_N - 1:
            if jp >= 0 and dp < 0.5:
                fp = E[jp]
                for j in range(3):
                    rp[j] = S[jp, j]
        reached = k == EDGE_N
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
        elif abs(fb) <= ZERO:
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
    if reached:   # (without a partner fp is 0: _fold_dip looks no further)
        m = _fold_dip(kind, H, P, C, xl, fl, pl, xa, fa, fp, rp, roots, m, out, mid)
        for k in range(EDGE_N - 1, 0, -1):
            if FQ[k] * FQ[k + 1] < 0.0:   # (a sample without a partner, 0, never counts)
                m = _fold_root(kind, H, P, C, good, far, 1.0 - (k + 1) / EDGE_N, XU[k + 1], FQ[k + 1],
                               1.0 - k / EDGE_N, XU[k], FQ[k], roots, m, out, mid)
    return m


def _fold_root(kind, H, P, C, xe, far, ua, ra, fa, ub, rb, fb, roots, m, out, mid):
    """A root on the partner of an ending branch near the end. The ending branch (traced by :func:`_edge` towards
    its end ``xe`` from ``far``, sampled at ``x = xe + (far − xe) u²``) is ``ra`` at ``u = ua`` and ``rb`` at ``ub``;
    the branch nearest to it has residuals ``fa`` and ``fb`` there, of opposite signs (at the end, ``u = 0``, the
    two are one). A branch swinging fast through a subproblem's near-singular configuration can move more than 0.5
    rad between two samples, so that its own trace stops before the end and never sees its sign change:
    bench_coverage found a ``6R-two-parallel`` target whose root lay 1.5e-4 rad from the end of such a branch (q4
    swinging 1 rad within 3e-4 rad), and the partner's residuals at the ending branch's samples were the only sign
    of it. Bisection in ``u``, the partner taken at each ``x`` as the branch nearest to the ending one, itself
    located on its straight path between ``ra`` and ``rb``; a root is kept when the residual there is within
    :data:`FOLD_TOL` of 0 (a jump between branches is not a root). Returns the new count of ``roots``."""
    S = np.empty((4, WIDTH))
    E = np.empty(4)
    lo = ua
    hi = ub
    x = xe
    f = fb
    j = -1
    for _ in range(FOLD_IT):
        u = 0.5 * (lo + hi)
        x = xe + (far - xe) * u * u
        n = _eval(kind, H, P, C, x, S, E)
        w = (u - ua) / (ub - ua)
        for k in range(3):
            mid[k] = ra[k] + w * _wrap(rb[k] - ra[k])
        i, _ = _nearest(S, n, mid)
        if i < 0:
            return m
        j, _ = _nearest_other(S, n, i)
        if j < 0:
            return m
        f = E[j]
        if f * fa > 0.0:
            lo = u
        else:
            hi = u
    if not abs(f) <= FOLD_TOL:
        return m
    out[0] = x
    out[1] = S[j, 0]
    out[2] = S[j, 1]
    out[3] = S[j, 2]
    return _add(roots, m, out)


def _fold_dip(kind, H, P, C, xl, fl, rl, xe, fe, fp, rp, roots, m, out, mid):
    """Two roots crowded between the last sample ``xl`` of an ending branch (residual ``fl``, branch ``rl``) and
    its end ``xe`` (``fe``), where its partner (the branch it meets there) has residual ``fp`` (branch ``rp``) at
    ``xl`` too. The two branches are one curve through the end, smooth in ``s = ±√(x_end − x)``, and the samples
    towards the end are evenly spaced in ``s``: ``fl``, ``fe``, ``fp`` are that curve at ``s = 1, 0, −1``. Where
    they share a sign and their parabola turns back to within one second difference of 0, the dip is searched
    on the side of its vertex (:func:`_dip_roots`). bench_coverage found a target with both its roots 1e-5 and
    5e-5 rad before a branch end, between the last two samples, where the residual of that branch alone showed
    no extremum. Returns the new count of ``roots``."""
    if not (fl * fe > 0.0 and fe * fp > 0.0):
        return m
    sg = 1.0 if fe > 0.0 else -1.0
    b = 0.5 * (fl - fp)
    c = 0.5 * (fl + fp) - fe
    if sg * c <= 0.0:                 # no extremum towards 0
        return m
    v = fe - b * b / (4.0 * c)
    if sg * v > 2.0 * abs(c) + 1e-12:
        return m
    if -b / (2.0 * c) >= 0.0:        # the vertex on the ending branch's side
        return _dip_roots(kind, H, P, C, xl, fl, rl, xe, fe, rl, sg, roots, m, out, mid)
    return _dip_roots(kind, H, P, C, xl, fp, rp, xe, fe, rp, sg, roots, m, out, mid)


def _dists(Sa, ca, Sb, cb, D):
    """``D[j, k]``: the distance of branch ``j`` of one sample to branch ``k`` of the next."""
    for j in range(ca):
        for k in range(cb):
            D[j, k] = _adist(Sa[j], Sb[k])


def _pair(kind, H, P, C, xa, Sa, Ea, ca, xb, Sb, Eb, cb, D, roots, m, out, pp, wk):
    """Roots between two neighbouring samples: their branches paired one to one, nearest pairs first (within
    0.5 rad; ``D`` from :func:`_dists`), sign changes refined; a branch left without a partner ends in between
    (:func:`_edges`). ``out (4,)``, ``pp (2, 4)``: work space."""
    pa = pp[0]
    pb = pp[1]
    for j in range(4):
        pa[j] = -1
        pb[j] = -1
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
            m = _edges(kind, H, P, C, xb, Sb, cb, pb, xa, roots, m)
            break
    for j in range(ca):             # branches that end between the samples
        if pa[j] < 0:
            m = _edges(kind, H, P, C, xa, Sa, ca, pa, xb, roots, m)
            break
    for j in range(ca):
        k = pa[j]
        if k < 0:
            continue
        fa = Ea[j]
        fb = Eb[k]
        a = xa
        b = xb
        ra = Sa[j]
        rb = Sb[k]
        if abs(fa) <= ZERO:          # a root on the sample itself: kept, and the step looked at from just inside
            out[0] = xa
            out[1] = Sa[j, 0]
            out[2] = Sa[j, 1]
            out[3] = Sa[j, 2]
            m = _add(roots, m, out)
            a = xa + NUDGE * (xb - xa)
            fa = _near(kind, H, P, C, a, Sa[j], wk[0])
            ra = wk[0]
        if abs(fb) <= ZERO:          # (its own root is kept from the next step, which begins there)
            b = xb - NUDGE * (xb - xa)
            fb = _near(kind, H, P, C, b, Sb[k], wk[1])
        if fa * fb < 0.0:
            if _refine(kind, H, P, C, a, fa, ra, b, fb, out):
                m = _add(roots, m, out)
    return m


def _near(kind, H, P, C, x, ref, cur):
    """The residual at ``x`` of the branch nearest ``ref`` (within 0.5 rad; that branch into ``cur``), 0 if
    none (no sign change to refine then)."""
    S = np.empty((4, WIDTH))
    E = np.empty(4)
    i, d = _pick(kind, H, P, C, x, ref, S, E)
    if i < 0 or d > 0.5:
        return 0.0
    for k in range(3):
        cur[k] = S[i, k]
    return E[i]


def _ambiguous(D, ca, cb):
    """True unless the branches of two samples pair up clearly (``D`` from :func:`_dists`): each branch's nearest
    on the other side is within 0.25 rad and three times nearer than any other branch of either side; checked
    both ways. (0.5 rad until bench_coverage found two branches that end and begin again 0.003 rad apart within
    one step, paired across the gap 0.47 rad apart: the two solutions at its ends were missed.)"""
    for side in range(2):
        na = ca if side == 0 else cb
        nb = cb if side == 0 else ca
        for j in range(na):
            k = -1
            bd = 1e300
            sd = 1e300
            for kk in range(nb):
                d = D[j, kk] if side == 0 else D[kk, j]
                if d < bd:
                    sd = bd
                    bd = d
                    k = kk
                elif d < sd:
                    sd = d
            if k < 0 or bd >= 0.25:
                return True                 # a branch ends or begins here (or moves fast): a closer look
            if sd < 3.0 * bd:
                return True
            for jj in range(na):
                if jj != j and (D[jj, k] if side == 0 else D[k, jj]) < 3.0 * bd:
                    return True
    return False


def _match(D, cb, j):
    """The branch of the next sample nearest to branch ``j`` (``D`` from :func:`_dists`, ``cb`` branches there;
    -1 if none within 0.5 rad)."""
    best = -1
    bd = 0.5
    for k in range(cb):
        if D[j, k] < bd:
            bd = D[j, k]
            best = k
    return best


def _extrema(kind, H, P, C, x0, h, S, E, cnt, D, i, roots, m, out, mid, cubic):
    """Samples ``i``, ``i + 1``, ``i + 2`` (at ``x0 + k h``; ``D[i]`` the distances of :func:`_dists` from sample
    ``i`` to ``i + 1``) of a branch with an extremum in the middle, on one side of 0 and turning back towards it:
    when the parabola through them comes within one second difference of 0, two close roots (or a double one)
    may hide there: :func:`_dip`, then both roots refined. With ``cubic`` (the plain samples, not those of a step
    sampled finer), where the branch keeps one sign from sample ``i + 1`` to ``i + 2``, the cubic through those and
    the samples either side is looked at too (:func:`_wiggle`).
    ``out (4,)``, ``mid (3,)``: work space."""
    if i + 2 >= S.shape[0]:
        return m
    xa = x0 + i * h
    for j in range(cnt[i]):
        k = _match(D[i], cnt[i + 1], j)
        if k < 0:
            continue
        k2 = _match(D[i + 1], cnt[i + 2], k)
        if k2 < 0:
            continue
        fa = E[i, j]
        fb = E[i + 1, k]
        fc = E[i + 2, k2]
        # the step between, near 0 for its change: a dip the samples do not show (_wiggle)
        if cubic and fb * fc > 0.0 and min(abs(fb), abs(fc)) < abs(fb - fa) + abs(fc - fb) and i + 3 < S.shape[0]:
            k3 = _match(D[i + 2], cnt[i + 3], k2)
            if k3 >= 0:
                m = _wiggle(kind, H, P, C, xa + h, h, fa, fb, fc, E[i + 3, k3], S[i + 1, k], roots, m, out, mid)
        if not ((fb - fa) * (fc - fb) < 0.0 and fa * fb > 0.0 and fb * fc > 0.0):
            continue
        sg = 1.0 if fb > 0.0 else -1.0
        if sg * (fb - fa) > 0.0:     # an extremum away from 0
            continue
        d2 = fa - 2.0 * fb + fc
        est = fb - (fc - fa) * (fc - fa) / (8.0 * d2)
        if sg * est > abs(d2) + 1e-12:
            continue
        m = _dip_roots(kind, H, P, C, xa, fa, S[i, j], xa + 2.0 * h, fc, S[i + 1, k], sg, roots, m, out, mid)
    return m


def _wiggle(kind, H, P, C, xb, h, f0, f1, f2, f3, ref, roots, m, out, mid):
    """Four samples ``f0 .. f3`` (at ``xb - h``, ``xb``, ``xb + h``, ``xb + 2 h``) of the branch through ``ref`` (at
    ``xb``) whose residual keeps one sign over the middle step: where their cubic has a minimum (of the residual's
    distance from 0) inside the middle step beyond 0, two roots may hide there, on an
    S-shaped stretch that rises through the samples without an extremum at any of them (a coverage check found a
    pair 0.022 rad apart, a third root 0.009 rad before them). The middle step is then searched as
    :func:`_extrema` searches a dip (:func:`_dip_roots`). Called by :func:`_extrema`, which has matched the branch
    across the samples. Returns the new count of ``roots``."""
    d1 = f1 - f0
    d2 = f2 - 2.0 * f1 + f0
    d3 = f3 - 3.0 * f2 + 3.0 * f1 - f0
    # p(t) = f0 + d1 t + d2 t(t-1)/2 + d3 t(t-1)(t-2)/6 through the four at t = 0..3; p'(t) = a t² + b t + c
    a = 0.5 * d3
    b = d2 - d3
    c = d1 - 0.5 * d2 + d3 / 3.0
    disc = b * b - 4.0 * a * c
    if a == 0.0 or disc < 0.0:
        return m
    sg = 1.0 if f1 > 0.0 else -1.0
    r = math.sqrt(disc)
    for t in ((-b - r) / (2.0 * a), (-b + r) / (2.0 * a)):
        if 1.0 < t < 2.0 and sg * (2.0 * a * t + b) > 0.0:      # a minimum of sg p inside the middle step
            v = f0 + d1 * t + d2 * t * (t - 1.0) / 2.0 + d3 * t * (t - 1.0) * (t - 2.0) / 6.0
            if sg * v < 0.0:
                return _dip_roots(kind, H, P, C, xb, f1, ref, xb + h, f2, ref, sg, roots, m, out, mid)
    return m


def _dip_roots(kind, H, P, C, xa, fa, ra, xc, fc, ref, sg, roots, m, out, mid):
    """The dip of the branch through ``ref`` between ``xa`` (residual ``fa``, branch ``ra``) and ``xc`` (``fc``),
    both on the side ``sg`` of 0: its minimum by :func:`_dip`; below 0, the two roots either side of it refined,
    at 0 (within 1e-12) a double root kept. Returns the new count of ``roots``."""
    xm, fx = _dip(kind, H, P, C, xa, xc, ref, sg, mid)
    if sg * fx < 0.0:
        if _refine(kind, H, P, C, xa, fa, ra, xm, fx, out):
            m = _add(roots, m, out)
        if _refine(kind, H, P, C, xm, fx, mid, xc, fc, out):
            m = _add(roots, m, out)
    elif abs(fx) <= 1e-12:
        out[0] = xm
        out[1] = mid[0]
        out[2] = mid[1]
        out[3] = mid[2]
        m = _add(roots, m, out)
    return m


def _seam(kind, H, P, C, xa, Sa, Ea, ca, Dab, xb, Sb, Eb, cb, Dbc, xc, Sc, Ec, cc, roots, m, out, mid):
    """:func:`_extrema` for three samples ``xa < xb < xc`` spaced unequally: where a step sampled :data:`SUB_N`
    times finer meets a plain one, the last sub-step, the sample between and the next sample (or the other way
    round). Neither the sub-steps' triples nor the plain ones see an extremum there (a branch that moves more than
    0.5 rad in the plain step is not matched across it), and two roots close together beside such a step were
    missed (a 600-example run found one 0.0017 rad apart). ``Dab``, ``Dbc``: the distances of :func:`_dists`
    between the samples. The parabola through the three points, its vertex within one second difference (at the
    larger spacing) of 0, as :func:`_extrema` asks. Returns the new count of ``roots``."""
    h0 = xb - xa
    h1 = xc - xb
    for j in range(ca):
        k = _match(Dab, cb, j)
        if k < 0:
            continue
        k2 = _match(Dbc, cc, k)
        if k2 < 0:
            continue
        fa = Ea[j]
        fb = Eb[k]
        fc = Ec[k2]
        if not ((fb - fa) * (fc - fb) < 0.0 and fa * fb > 0.0 and fb * fc > 0.0):
            continue
        sg = 1.0 if fb > 0.0 else -1.0
        if sg * (fb - fa) > 0.0:     # an extremum away from 0
            continue
        a = ((fc - fb) / h1 + (fa - fb) / h0) / (h0 + h1)
        b = (fc - fb) / h1 - a * h1
        est = fb - b * b / (4.0 * a)
        if sg * est > 2.0 * abs(a) * max(h0, h1) ** 2 + 1e-12:
            continue
        m = _dip_roots(kind, H, P, C, xa, fa, Sa[j], xc, fc, Sb[k], sg, roots, m, out, mid)
    return m


def _scan(kind, H, P, C, xs, S, E, cnt):
    """The branches at every ``xs[i]`` into ``S[i]``, ``E[i]``, their counts into ``cnt[i]``."""
    for i in range(xs.shape[0]):
        cnt[i] = _eval(kind, H, P, C, xs[i], S[i], E[i])


def _all_dists(S, cnt, n, D):
    """``D[i]``: the distances of :func:`_dists` from sample ``i`` to ``i + 1``, for ``i < n`` (no array made)."""
    for i in range(n):
        _dists(S[i], cnt[i], S[i + 1], cnt[i + 1], D[i])


def _take(Ss, Es, cs, k, S, E, cnt, i):
    """Sample ``i`` (``S[i]``, ``E[i]``, ``cnt[i]``) into row ``k`` of ``Ss``, ``Es``, ``cs`` (element by element:
    an array assigned to a row needs reference counts)."""
    for r in range(S.shape[1]):
        Es[k, r] = E[i, r]
        for c in range(S.shape[2]):
            Ss[k, r, c] = S[i, r, c]
    cs[k] = cnt[i]


def _walk(kind, H, P, C, n, step, S, E, cnt, D, Ss, Es, cs, Ds, roots, m, out, mid, pp, wk):
    """The steps of :func:`_search` one after the other (its arrays; ``D[i]`` the distances of step ``i``): the
    branches paired and sign changes refined (:func:`_pair`), a step whose branches do not pair up clearly sampled
    :data:`SUB_N` times finer (and the seams with the steps beside it, :func:`_seam`), the dips of every three
    samples (:func:`_extrema`). Makes no array (compiled without reference counts: the rows it hands on are
    views, ~7 a step); returns the new count of ``roots``."""
    for i in range(n):
        xa = -_PI + i * step
        if cnt[i] == 0 and cnt[i + 1] == 0:
            continue
        if _ambiguous(D[i], cnt[i], cnt[i + 1]):
            h = step / SUB_N
            for k in range(SUB_N + 1):
                if k == 0:
                    _take(Ss, Es, cs, k, S, E, cnt, i)
                elif k == SUB_N:
                    _take(Ss, Es, cs, k, S, E, cnt, i + 1)
                else:
                    cs[k] = _eval(kind, H, P, C, xa + k * h, Ss[k], Es[k])
            for k in range(SUB_N):
                _dists(Ss[k], cs[k], Ss[k + 1], cs[k + 1], Ds[k])
            for k in range(SUB_N):
                m = _pair(kind, H, P, C, xa + k * h, Ss[k], Es[k], cs[k], xa + (k + 1) * h, Ss[k + 1], Es[k + 1],
                          cs[k + 1], Ds[k], roots, m, out, pp, wk)
                if k + 2 <= SUB_N:
                    m = _extrema(kind, H, P, C, xa, h, Ss, Es, cs, Ds, k, roots, m, out, mid, _NO)
            b = i - 1 if i >= 1 else n - 1   # the seams with the plain steps before and after (_seam), about ±π too
            m = _seam(kind, H, P, C, xa - step, S[b], E[b], cnt[b], D[b], xa, Ss[0], Es[0], cs[0],
                      Ds[0], xa + h, Ss[1], Es[1], cs[1], roots, m, out, mid)
            if i + 2 <= n + 1:
                m = _seam(kind, H, P, C, xa + step - h, Ss[SUB_N - 1], Es[SUB_N - 1], cs[SUB_N - 1], Ds[SUB_N - 1],
                          xa + step, S[i + 1], E[i + 1], cnt[i + 1], D[i + 1], xa + 2.0 * step, S[i + 2], E[i + 2],
                          cnt[i + 2], roots, m, out, mid)
        else:
            m = _pair(kind, H, P, C, xa, S[i], E[i], cnt[i], xa + step, S[i + 1], E[i + 1], cnt[i + 1], D[i], roots,
                      m, out, pp, wk)
        m = _extrema(kind, H, P, C, -_PI, step, S, E, cnt, D, i, roots, m, out, mid, _YES)
    return m


def _search(kind, H, P, C, n, roots):
    """Every root ``(x, branch)`` of the search ``kind`` into ``roots (MAXROOT, 4)``, ``n`` samples over a turn;
    returns their count."""
    C = _with_terms(kind, H, P, C)
    step = 2.0 * _PI / n
    S = np.zeros((n + 2, 4, WIDTH))
    E = np.zeros((n + 2, 4))
    cnt = np.zeros(n + 2, dtype=np.int64)
    xs = np.empty(n)
    for i in range(n):
        xs[i] = -_PI + i * step
    _scan(kind, H, P, C, xs, S, E, cnt)
    # the last two samples are the first two a turn on: the same branches, the same residuals (evaluated again at
    # ``−π + n step`` ≈ π they differ by rounding, and a root at ±π would fall between the two copies); the second
    # gives the triple of samples about ±π to _extrema (a dip there, both roots within one step of −π, was missed)
    for k in range(2):
        S[n + k] = S[k]
        E[n + k] = E[k]
        cnt[n + k] = cnt[k]
    D = np.empty((n + 1, 4, 4))
    _all_dists(S, cnt, n, D)
    D[n] = D[0]                     # the first step a turn on
    m = np.int64(0)   # not the literal 0: the calls in the loop would be compiled for it as well as for int64
    Ss = np.zeros((SUB_N + 1, 4, WIDTH))
    Es = np.zeros((SUB_N + 1, 4))
    cs = np.zeros(SUB_N + 1, dtype=np.int64)
    Ds = np.empty((SUB_N, 4, 4))
    out = np.empty(4)
    mid = np.empty(3)
    pp = np.empty((2, 4), dtype=np.int64)
    wk = np.empty((2, 3))
    m = _walk(kind, H, P, C, n, step, S, E, cnt, D, Ss, Es, cs, Ds, roots, m, out, mid, pp, wk)
    return _islands(kind, H, P, C, n, step, cnt, E, roots, m, out, pp, wk, mid)


KERNELS = ("_eval_ti", "_point5", "_tp_terms", "_with_terms", "_eval_tp", "_eval_sw", "_eval_sm", "_eval", "_margin",
           "_island", "_rim", "_sharp_peak", "_adist", "_nearest", "_owned", "_pick", "_refine", "_add", "_dip",
           "_nearest_other", "_settled", "_dip_roots", "_fold_dip", "_fold_root", "_eval_memo", "_edge", "_edges",
           "_dists", "_near", "_pair", "_ambiguous", "_match", "_wiggle", "_extrema", "_seam", "_islands", "_scan",
           "_take", "_walk", "_all_dists", "_search")
"""The functions :func:`kernels` compiles, callees before callers (the scalar helpers: :mod:`._kernels`)."""
UNCOUNTED = ("_eval_ti", "_point5", "_tp_terms", "_eval_tp", "_eval_sw", "_eval_sm", "_eval", "_margin", "_sharp_peak",
             "_adist", "_nearest", "_owned", "_pick", "_add", "_nearest_other", "_settled", "_fold_dip", "_eval_memo",
             "_dists", "_pair", "_ambiguous", "_match", "_wiggle", "_extrema", "_dip_roots", "_seam", "_scan", "_take",
             "_walk", "_all_dists")
"""The functions of :data:`KERNELS` compiled without reference counts (:func:`.subproblems.jit_namespace`): those
that make no array (the others: ``_with_terms``, ``_island``, ``_rim``, ``_islands``, ``_refine``, ``_dip``,
``_edge``, ``_edges``, ``_fold_root``, ``_near``, ``_search`` make their work arrays). 13 % off the searches' time."""
_KERNELS: Optional[types.SimpleNamespace] = None


def kernels() -> Optional[types.SimpleNamespace]:
    """The compiled engine (attributes named as its functions, and ``namespace``), or None without Numba."""
    global _KERNELS
    if _KERNELS is None:
        try:
            ns = _sp.jit_namespace(globals(), KERNELS, extra=_kk.extra(), uncounted=UNCOUNTED)
        except ImportError:
            return None

        _jit_loader.forget_stale_cache(ns, ("ik/geometric/_kernels.py", "kinematics/_jit.py"))
        _KERNELS = types.SimpleNamespace(**{name: ns[name] for name in KERNELS}, namespace=ns)
    return _KERNELS


def two_parallel(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *, jit: Optional[bool] = None) -> Any:
    """Every solution of a 6R chain whose axes 2 and 3 are parallel (all revolute): :func:`.solvers.two_parallel`."""
    from . import solvers

    return solvers.two_parallel(form, R, p, q_ref, jit=jit)
