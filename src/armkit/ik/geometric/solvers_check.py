"""The solvers' kernels (:mod:`.solvers`): each core, then the FK check of its candidates on the true chain; one
target, a batch, or a sweep of chains.

Plain functions; :func:`.solvers.kernels` compiles them with the other cores.
"""

from __future__ import annotations

import math

import numpy as np

from ._kernels import _fk_err_from, _fk_err_sc, _sincos_block
from .solvers_parallel import _core_three_parallel
from .solvers_search import _core_spherical_middle, _core_two_intersecting_end, _core_two_parallel
from .solvers_wrist import _core_spherical
from .search2d import _newton, _twins
from .subproblems import _wrap


def _solve_two_intersecting_end(kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r, Q, LS, SG, ST):
    return _solve_searched(_TI_END, kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r, Q, LS, SG, ST)


def _solve_two_parallel(kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r, Q, LS, SG, ST):
    return _solve_searched(_TWO_PAR, kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r, Q, LS, SG, ST)


def _solve_spherical_middle(kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r, Q, LS, SG, ST):
    return _solve_searched(_SPH_MID, kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r, Q, LS, SG, ST)


_TI_END, _TWO_PAR, _SPH_MID = np.int64(2), np.int64(3), np.int64(4)
"""The cores of the 1-D searches (the numbers of :func:`_solve`), typed ``int64``, not as literals (one compiled
copy of :func:`_solve_searched` serves all three)."""


def _searched_core(which, kind, Hi, Pi, RnT, prism, R, p, qref, N, Q, LS, SG):
    if which == _TI_END:
        return _core_two_intersecting_end(kind, Hi, Pi, RnT, prism, R, p, qref, N, Q, LS, SG)
    if which == _TWO_PAR:
        return _core_two_parallel(kind, Hi, Pi, RnT, prism, R, p, qref, N, Q, LS, SG)
    return _core_spherical_middle(kind, Hi, Pi, RnT, prism, R, p, qref, N, Q, LS, SG)


def _solve_searched(which, kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r, Q, LS, SG, ST):
    """A class solved by a 1-D search (the core ``which``): its candidates checked (:func:`_check`), those that fail
    the check brought onto the target by Newton steps where they can be (:func:`_promote`), an odd count made even
    where a twin lies beside a solution (:func:`_paired`). A count still odd, whose missing solution is not beside
    one found (near in the searched joint, it can be far in the others), sends the search again with twice the
    samples, then four times (:data:`RETRIES`), while the count stays odd; the new solutions of each are merged in
    (:func:`_merged`). No solution at all sends it again once with twice the samples (:data:`EMPTY_RETRY`)."""
    m = _searched_core(which, kind, Hi, Pi, RnT, prism, R, p, qref, N, Q, LS, SG)
    ng, nf = _check(m, Ht, Pt, RnT, prism, R, p, tol_p, tol_r, Q, LS, SG, ST)
    ng, nf = _promote(Ht, Pt, RnT, prism, R, p, tol_p, tol_r, Q, LS, SG, ST, ng, nf)
    ng, nf = _paired(Ht, Pt, RnT, R, p, tol_p, tol_r, Q, LS, SG, ST, ng, nf)
    n2 = N
    for r in range(RETRIES):
        if ng % 2 == 0 and not (EMPTY_RETRY and ng == 0 and r == 0 and _within_reach(Pi, p)):
            break
        n2 *= 2
        Q2, LS2, SG2, ST2 = np.zeros_like(Q), np.zeros_like(LS), np.zeros_like(SG), np.zeros_like(ST)
        m2 = _searched_core(which, kind, Hi, Pi, RnT, prism, R, p, qref, n2, Q2, LS2, SG2)
        ng2, nf2 = _check(m2, Ht, Pt, RnT, prism, R, p, tol_p, tol_r, Q2, LS2, SG2, ST2)
        ng2 = _promote(Ht, Pt, RnT, prism, R, p, tol_p, tol_r, Q2, LS2, SG2, ST2, ng2, nf2)[0]
        ng, nf = _merged(Q, LS, SG, ST, ng, nf, Q2, SG2, ng2, prism)
    _sharpen(Ht, Pt, RnT, prism, R, p, tol_p, tol_r, Q, ng)
    return ng, nf


def _within_reach(P, p):
    """Whether the point ``p`` lies within the sum of the chain's link lengths ``|P[1]| + ... + |P[6]|`` of its first
    point ``P[0]`` (beyond it no configuration reaches: rotations keep lengths)."""
    reach = 0.0
    for k in range(1, P.shape[0]):
        reach += math.sqrt(P[k, 0] ** 2 + P[k, 1] ** 2 + P[k, 2] ** 2)
    d = math.sqrt((p[0] - P[0, 0]) ** 2 + (p[1] - P[0, 1]) ** 2 + (p[2] - P[0, 2]) ** 2)
    return d <= reach * (1.0 + 1e-6)


def _sharpen(H, P, RnT, prism, R, p, tol_p, tol_r, Q, ng):
    """Newton steps on the whole chain from each of the ``ng`` passing rows of ``Q`` whose FK error is above
    :data:`SHARP` times the check's tolerances. Near a double root (two solutions that nearly meet, where the
    search's refinement in one joint leaves the others least sure) a solution passed the check 2e-9 from the
    target on an arm 6.7 long; Newton takes it to the last digits. The row keeps the new value only where its error
    is smaller and it repeats no other row."""
    q = np.empty(6)
    F = np.empty((2, 6))
    RS = np.empty((7, 3, 3))
    PS = np.empty((7, 3))
    for i in range(ng):
        ep, er = _fk_err_from(H, P, RnT, prism, Q[i], R, p, RS, PS, 0, F)
        if ep <= SHARP * tol_p and er <= SHARP * tol_r:
            continue
        _, ep2, er2 = _newton_from(H, P, RnT, prism, R, p, tol_p, tol_r, Q[i], q, RS, PS, F)
        if max(ep2 / tol_p, er2 / tol_r) >= max(ep / tol_p, er / tol_r):
            continue
        if not _repeats(q, Q, ng, i, prism):
            for k in range(6):
                Q[i, k] = q[k]


SHARP = 1e-3
"""The FK error, as a fraction of the check's tolerances, above which :func:`_sharpen` polishes a solution of a
1-D search (1e-12 times the arm's size in position, 1e-12 rad in rotation)."""

RETRIES = 2
"""How many times a 1-D search with an odd count of solutions runs again, each time with twice the samples of
the last (2N, then 4N). Found by bench_coverage: a twin 4 rad away in the other joints that 2N finds (seed 31), and
one of a `6R-two-parallel` target that only 4N finds (`--seed=139`)."""
EMPTY_RETRY = True
"""Whether a 1-D search that found no solution runs again once with 2N samples (then as an odd count would). Found by
bench_coverage (`--seed=223`): a `6R-two-intersecting` target whose only two solutions lie 4e-5 rad apart in q1,
within 0.0004 rad of where their branch is born, was answered "out of reach"; 2N samples find both. It costs a
second search (twice the first's) on targets out of reach, except those beyond the sum of the link lengths
(:func:`_within_reach`)."""


def _promote(H, P, RnT, prism, R, p, tol_p, tol_r, Q, LS, SG, ST, ng, nf):
    """Newton steps on the whole chain (:func:`.search2d._newton`; 6R, every joint revolute) from each of the ``nf``
    failing candidates after the ``ng`` passing rows of ``Q`` that is not a least-squares one. Where a branch's
    other joints swing fast with the searched one (1.2 rad within 0.0026 rad of q1 seen, near a branch's birth),
    the searched joint's root can be right and the others a few hundredths off; from there Newton reaches the
    solution. A candidate that then passes the check (:func:`_fk_err_from`, angles wrapped) becomes the last
    passing row, unless it repeats one (then it is dropped); the other failing rows stay, after the passing ones.
    Returns the new ``(passing, failing)``."""
    q = np.empty(6)
    F = np.empty((2, 6))
    RS = np.empty((7, 3, 3))
    PS = np.empty((7, 3))
    i = ng
    while i < ng + nf:
        if LS[i]:
            i += 1
            continue
        err, ep, er = _newton_from(H, P, RnT, prism, R, p, tol_p, tol_r, Q[i], q, RS, PS, F)
        if err > tol_r or not (ep <= tol_p and er <= tol_r):
            i += 1
            continue
        sg = SG[i]
        last = ng + nf - 1
        if not _repeats(q, Q, ng, -1, prism):   # row i takes the first failing row's place, q the last passing one
            _copy_row(Q, LS, SG, ST, ng, i)
            for k in range(6):
                Q[ng, k] = q[k]
            LS[ng] = False
            SG[ng] = sg
            ST[ng] = 1
            ng += 1
            nf -= 1
            i += 1
        else:         # a repeat: the last failing row takes its place
            _copy_row(Q, LS, SG, ST, last, i)
            nf -= 1
    return ng, nf


def _polish_wanted(H, P, RnT, prism, R, p, Q, LS, ng, nf, exact, reach_p, reach_r):
    """Whether :func:`.solvers._run` would polish one of the ``nf`` failing rows after the ``ng`` passing ones of
    ``Q``: a row not both least-squares and of an exact chain, whose FK error on the true chain ``(H, P)`` is
    within ``reach_p`` (position) and ``reach_r`` (rotation; :func:`.solvers.polish_reach`). The one-call and
    batched kernels leave such a target to ``_run``; the others answer it as ``_run`` would."""
    F = np.empty((2, 6))
    RS = np.empty((7, 3, 3))
    PS = np.empty((7, 3))
    for i in range(ng, ng + nf):
        if LS[i] and exact:
            continue
        ep, er = _fk_err_from(H, P, RnT, prism, Q[i], R, p, RS, PS, 0, F)
        if ep <= reach_p and er <= reach_r:
            return True
    return False


def _newton_from(H, P, RnT, prism, R, p, tol_p, tol_r, row, q, RS, PS, F):
    """Newton steps on the whole chain (:func:`.search2d._newton`) from ``row`` into ``q`` (6,), its angles then
    wrapped: ``(Newton's last error, position error, rotation error)``, the last two by the check's FK
    (:func:`_fk_err_from`; ``RS``, ``PS``, ``F (2, 6)`` its work space)."""
    for k in range(6):
        q[k] = row[k]
    err = _newton(H, P, RnT, R, p, tol_p / tol_r, q)
    for k in range(6):
        q[k] = _wrap(q[k])
    ep, er = _fk_err_from(H, P, RnT, prism, q, R, p, RS, PS, 0, F)
    return err, ep, er


def _copy_row(Q, LS, SG, ST, src, dst):
    for k in range(Q.shape[1]):
        Q[dst, k] = Q[src, k]
    LS[dst] = LS[src]
    SG[dst] = SG[src]
    ST[dst] = ST[src]


def _check(m, H, P, RnT, prism, R, p, tol_p, tol_r, Q, LS, SG, ST):
    """Wrap the angles of the ``m`` candidates and check each on the true chain; then put the ones that
    pass (repeats dropped) first and the ones that fail after them (rows of Q, LS, SG; ``ST`` 1 / 0).
    Returns ``(passing, failing)``."""
    n = Q.shape[1]
    # four work arrays, made once for the m candidates (each array made and freed costs ~40 ns): the FK's work
    # space: the rotation RS (n + 1, 3, 3) and position PS (n + 1, 3) after each joint of the last candidate, taken
    # up by the next where their first joints agree (the branches come in pairs that differ in the wrist); the
    # candidates' copy for the reordering, C (m, n + 3): the angles, LS, SG, ST; and the wrapped angles of all m in
    # one flat vector, then their sines and cosines (one vector loop for all, not one call a joint: the same
    # polynomial, the same bits)
    RS = np.empty((n + 1, 3, 3))
    PS = np.empty((n + 1, 3))
    C = np.empty((m, n + 3))
    mn = m * n
    A = np.empty(3 * mn)
    for i in range(m):
        for k in range(n):
            if not prism[k]:
                Q[i, k] = _wrap(Q[i, k])
            A[i * n + k] = Q[i, k]
    _sincos_block(A[:mn], A[mn:2 * mn], A[2 * mn:])
    for i in range(m):
        s = 0
        if i > 0:
            while s < n and Q[i, s] == Q[i - 1, s]:
                s += 1
        a = mn + i * n
        ep, er = _fk_err_sc(H, P, RnT, prism, Q[i], A[a:a + n], A[a + mn:a + mn + n], R, p, RS, PS, s)
        ST[i] = 1 if (ep <= tol_p and er <= tol_r) else 0
        if ST[i] == 1:
            for j in range(i):
                if ST[j] == 1 and _close(Q[i], Q[j], prism):
                    ST[i] = 2
                    break
    for i in range(m):
        for k in range(n):
            C[i, k] = Q[i, k]
        C[i, n] = 1.0 if LS[i] else 0.0
        C[i, n + 1] = 1.0 if SG[i] else 0.0
        C[i, n + 2] = ST[i]
    ng = 0
    for i in range(m):
        if C[i, n + 2] == 1.0:
            for k in range(n):
                Q[ng, k] = C[i, k]
            LS[ng] = C[i, n] != 0.0
            SG[ng] = C[i, n + 1] != 0.0
            ST[ng] = 1
            ng += 1
    nf = 0
    for i in range(m):
        if C[i, n + 2] == 0.0:
            for k in range(n):
                Q[ng + nf, k] = C[i, k]
            LS[ng + nf] = C[i, n] != 0.0
            SG[ng + nf] = C[i, n + 1] != 0.0
            ST[ng + nf] = 0
            nf += 1
    return ng, nf


def _paired(H, P, RnT, R, p, tol_p, tol_r, Q, LS, SG, ST, ng, nf):
    """After a 1-D search (6R, every joint revolute): an odd count ``ng`` of solutions means one is missing (the
    real solutions come in pairs), most likely the twin of one found, within one step of the search; Newton steps
    look for it from each solution along the Jacobian's most singular direction (:func:`.search2d._twins`). A
    twin found goes in as the last passing row (the failing rows move down one; the last drops when full).
    Returns the new ``(passing, failing)``. A count still odd after this sends the caller's search again with twice
    the samples, then four times (:func:`_merged`): a twin near in the searched joint can be far in the others."""
    if ng % 2 == 0:
        return ng, nf
    G = np.empty((ng + 1, 6))
    for i in range(ng):
        for k in range(6):
            G[i, k] = Q[i, k]
    if _twins(H, P, RnT, R, p, tol_p / tol_r, tol_r, G, ng) == ng:
        return ng, nf
    return _put_passing(Q, LS, SG, ST, ng, nf, G[ng], False)


def _put_passing(Q, LS, SG, ST, ng, nf, q, sg):
    """Put the solution ``q`` (its singular flag ``sg``) in as passing row ``ng``: the ``nf`` failing rows after it
    move down one, the last dropping when the buffer is full. Returns the new ``(passing, failing)`` (unchanged when
    every row already passes)."""
    if ng + nf >= Q.shape[0]:
        if nf == 0:
            return ng, nf
        nf -= 1
    for i in range(ng + nf - 1, ng - 1, -1):
        for k in range(Q.shape[1]):
            Q[i + 1, k] = Q[i, k]
        LS[i + 1] = LS[i]
        SG[i + 1] = SG[i]
        ST[i + 1] = ST[i]
    for k in range(Q.shape[1]):
        Q[ng, k] = q[k]
    LS[ng] = False
    SG[ng] = sg
    ST[ng] = 1
    return ng + 1, nf


def _merged(Q, LS, SG, ST, ng, nf, Q2, SG2, ng2, prism):
    """The passing rows of a second search (``Q2``, ``SG2``: its first ``ng2`` rows) that are not among the ``ng``
    passing rows of ``Q``, put in after them (:func:`_put_passing`). Returns the new ``(passing, failing)``."""
    for i in range(ng2):
        if not _repeats(Q2[i], Q, ng, -1, prism):
            ng, nf = _put_passing(Q, LS, SG, ST, ng, nf, Q2[i], SG2[i])
    return ng, nf


def _repeats(q, Q, ng, skip, prism):
    """Whether ``q`` is one of the first ``ng`` rows of ``Q`` other than row ``skip`` (-1: none), up to
    :func:`_close`."""
    for j in range(ng):
        if j != skip and _close(q, Q[j], prism):
            return True
    return False


def _close(a, b, prism):
    for k in range(a.shape[0]):
        d = abs(a[k] - b[k])
        if not prism[k]:
            d = abs(_wrap(a[k] - b[k]))
        if d > 1e-8:
            return False
    return True


CORE_V, CORE_M, CORE_T = 41, 4, 15
"""Rows of a closed-form core's work vectors (rows of 3), matrices and rows of 4 (:func:`_core_in`): the spherical
core's (its wrists side by side, :func:`.solvers_wrist._wrist_lanes`, take 14 rows of 4); the three-parallel core
takes the first :data:`CORE_V_PARALLEL` vectors, two rows of 4 for its (q1, q5) pairs and 13 for those pairs side
by side (:func:`.solvers_parallel._pairs_lanes`)."""
CORE_V_PARALLEL = 22
"""The work vectors the three-parallel core takes (its small vectors, then its pairs' cosines and sines)."""


def _core_in(which, kind, Hi, Pi, RnT, prism, R, p, qref, N, Q, LS, SG, V3, M3, T14, CL):
    """The candidates of a closed-form core (``which`` 0: spherical wrist, 1: three parallel axes) into Q, LS, SG,
    before the check; returns their count. The core's work arrays are the caller's, ``V3 (CORE_V, 3)``,
    ``M3 (CORE_M, 3, 3)``, ``T14 (CORE_T, 4)`` and ``CL (8,)`` flags, zeroed here as the cores take them (the
    rows of ``T14`` after the first two: the lanes, written before they are read): the one-call
    and batch kernels (:mod:`.one_call`, :mod:`.batched`) keep theirs (each array made and freed costs ~40 ns),
    :func:`_closed_core` makes them. It makes no array, so it is compiled without reference counts."""
    for i in range(CORE_V if which == 0 else CORE_V_PARALLEL):
        for j in range(3):
            V3[i, j] = 0.0
    for i in range(CORE_M):
        for j in range(3):
            for k in range(3):
                M3[i, j, k] = 0.0
    for i in range(2):
        for j in range(4):
            T14[i, j] = 0.0
    for i in range(8):
        CL[i] = False
    if which == 0:
        return _core_spherical(kind, Hi, Pi, RnT, prism, R, p, qref, N, Q, LS, SG, V3, M3, CL, T14)
    return _core_three_parallel(kind, Hi, Pi, RnT, prism, R, p, qref, N, Q, LS, SG, V3[:CORE_V_PARALLEL], M3, T14,
                                CL[:4])


def _closed_core(which, kind, Hi, Pi, RnT, prism, R, p, qref, N, Q, LS, SG):
    """:func:`_core_in` in work arrays of its own: its own compiled function, counted (it makes them), for the
    checked solvers (:func:`_solve_spherical`, :func:`_solve_three_parallel`)."""
    return _core_in(which, kind, Hi, Pi, RnT, prism, R, p, qref, N, Q, LS, SG, np.empty((CORE_V, 3)),
                    np.empty((CORE_M, 3, 3)), np.empty((CORE_T, 4)), np.empty(8, dtype=np.bool_))


def _solve_spherical(kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r, Q, LS, SG, ST):
    m = _closed_core(_SPHERICAL, kind, Hi, Pi, RnT, prism, R, p, qref, N, Q, LS, SG)
    return _check(m, Ht, Pt, RnT, prism, R, p, tol_p, tol_r, Q, LS, SG, ST)


def _solve_three_parallel(kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r, Q, LS, SG, ST):
    m = _closed_core(_THREE_PARALLEL, kind, Hi, Pi, RnT, prism, R, p, qref, N, Q, LS, SG)
    return _check(m, Ht, Pt, RnT, prism, R, p, tol_p, tol_r, Q, LS, SG, ST)


_SPHERICAL, _THREE_PARALLEL = np.int64(0), np.int64(1)
"""The closed-form cores of :func:`_closed_core`, typed ``int64`` (one compiled copy serves both)."""


def _distinct(Q, LS, SG, prism, m, W, reverse):
    """Whether none of the ``m`` candidates of ``Q`` is a least-squares one (``LS``: most fail the check, which then
    decides what becomes of them) or singular (``SG``: the long way gives a note) and no two are the same up to
    :func:`_close`, their angles wrapped into ``W (m, n)`` as :func:`_check` wraps them (each row then reversed with
    ``reverse``: a chain solved reversed, in the robot's order). Where they also all pass the check, the check keeps
    them all, in their order: the shortcut past it of the one-call and batch kernels (:mod:`.one_call`,
    :mod:`.batched`). Compiled without reference counts, its pairs compared by :func:`_close_wrapped`: 184 -> 95 ns
    for the Kinova's 8 branches (2026-12-07)."""
    n = Q.shape[1]
    for i in range(m):
        if LS[i] or SG[i]:
            return False
        for k in range(n):
            W[i, k] = Q[i, k] if prism[k] else _wrap(Q[i, k])
        for j in range(i):
            if _close_wrapped(W, i, j, prism):
                return False
    if reverse:
        for i in range(m):
            for k in range(n // 2):
                W[i, k], W[i, n - 1 - k] = W[i, n - 1 - k], W[i, k]
    return True


def _apart(Q, LS, SG, prism, m, W, reverse, H, P, RnT, R, p, tol_p, tol_r, A, RS, PS):
    """:func:`_distinct` where some of the ``m`` candidates are least-squares ones (a position or wrist out of reach)
    on a chain whose ideal form is the true one: the count of the others, none singular and no two alike, their
    angles wrapped into ``W`` in their order (each row reversed with ``reverse``), where every least-squares one
    fails the check of :func:`_check` (its angles wrapped and their sines and cosines taken as that check takes
    them, its FK on the true chain ``(H, P, RnT)`` from the base against ``(R, p)``: the same bits); else -1.

    The check would then drop each least-squares candidate (a failed one of such a chain is not polished:
    :func:`_polish_wanted`) and keep the others in their order where they pass: the shortcut's branches
    (:mod:`.one_call`), with one FK for each least-squares candidate where the check took one for every candidate.
    ``A (3 n)``, ``RS (n + 1, 3, 3)``, ``PS (n + 1, 3)``: work space. Makes no array: compiled without reference
    counts."""
    n = Q.shape[1]
    k = 0
    for i in range(m):
        if LS[i]:
            for j in range(n):
                A[j] = Q[i, j] if prism[j] else _wrap(Q[i, j])
            _sincos_block(A[:n], A[n:2 * n], A[2 * n:3 * n])
            ep, er = _fk_err_sc(H, P, RnT, prism, A[:n], A[n:2 * n], A[2 * n:3 * n], R, p, RS, PS, 0)
            if ep <= tol_p and er <= tol_r:
                return -1   # it passes: the check keeps it in its place
            continue
        if SG[i] or k >= W.shape[0]:
            return -1
        for j in range(n):
            W[k, j] = Q[i, j] if prism[j] else _wrap(Q[i, j])
        for j in range(k):
            if _close_wrapped(W, k, j, prism):
                return -1
        k += 1
    if reverse:
        for i in range(k):
            for j in range(n // 2):
                W[i, j], W[i, n - 1 - j] = W[i, n - 1 - j], W[i, j]
    return k


def _close_wrapped(W, i, j, prism):
    """:func:`_close` of rows ``i`` and ``j`` of ``W``, whose revolute angles are wrapped into (-π, π]: a difference
    ``x`` of two such lies in (-2π, 2π), where ``_wrap(x)`` is ``x ∓ 2π`` past ±π, exactly (the two are within a
    factor 2: Sterbenz), so ``|_wrap(x)|`` is ``min(|x|, 2π - |x|)``, the same bits without ``_wrap``'s floor."""
    for k in range(W.shape[1]):
        d = abs(W[i, k] - W[j, k])
        if not prism[k]:
            d = min(d, 2.0 * math.pi - d)
        if d > 1e-8:
            return False
    return True


def _gate(inverted, tol_p, tol_r, x, y, z):
    """``(position, rotation)``: the FK errors of the robot below which every branch passes the check (tolerances
    ``tol_p``, ``tol_r``) of a target at ``(x, y, z)``: the gate of the shortcut past the check (:mod:`.one_call`).
    Half the check's tolerances (two FKs of one chain differ by rounding, and the check's rotation measure is at
    most the angle); a chain solved reversed is checked against the inverse target, whose position error is at
    most ``dp + θ |p|``: a quarter of the position tolerance for ``dp`` and for ``θ |p|``."""
    if not inverted:
        return 0.5 * tol_p, 0.5 * tol_r
    gate_r = 0.5 * tol_r
    p_norm = math.sqrt(x * x + y * y + z * z)
    if p_norm > 0.0:
        gate_r = min(gate_r, 0.25 * tol_p / p_norm)
    return 0.25 * tol_p, gate_r


def _solve(which, kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r, Q, LS, SG, ST):
    """The solver kernel ``which`` (0 spherical, 1 three parallel, 2 two intersecting, 3 two parallel, 4 spherical
    middle) on one target: ``(passing, failing)`` as that kernel returns them. Compiled inline into its callers
    (:data:`.solvers.INLINE`): one copy of the dispatch per batch loop, no call of its own."""
    if which == 0:
        return _solve_spherical(kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r, Q, LS, SG, ST)
    if which == 1:
        return _solve_three_parallel(kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r, Q, LS, SG, ST)
    if which == 2:
        return _solve_two_intersecting_end(kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r, Q, LS, SG,
                                           ST)
    if which == 3:
        return _solve_two_parallel(kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r, Q, LS, SG, ST)
    return _solve_spherical_middle(kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r, Q, LS, SG, ST)


def _sweep(which, kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r, Q, LS, SG, ST, NG, NF):
    """Every target of a batch for ``V`` chains of one class at once (a joint of a 7-joint arm held at ``V`` values,
    :mod:`.locked`; one chain for :func:`.solvers.solve_batch`): ``Hi (V, 6, 3)``, ``Pi (V, 7, 3)``,
    ``RnT (V, 3, 3)``, ``Ht``, ``Pt`` likewise, ``tol_p (V,)``; ``R (B, 3, 3)``, ``p (B, 3)``, ``qref (B, n)``.
    Per chain and target the solutions ``Q[v, b]`` and flags as one call of the kernel ``which`` (:func:`_solve`)
    would give them, and their counts ``NG`` (good), ``NF`` (failed the check)."""
    for v in range(Hi.shape[0]):
        for b in range(R.shape[0]):
            ng, nf = _solve(which, kind, Hi[v], Pi[v], RnT[v], prism, Ht[v], Pt[v], R[b], p[b], qref[b], N, tol_p[v],
                            tol_r, Q[v, b], LS[v, b], SG[v, b], ST[v, b])
            NG[v, b] = ng
            NF[v, b] = nf
