"""The geometric family's single IK call in one compiled call: solve, verify, wrap and sort one target.

:class:`armkit.ik.analytic.geometric.Geometric` answers one target in :func:`armkit.ik` and
:func:`armkit.ik_all` through the one-call path of :func:`armkit.ik.analytic.single_call`, like the
hand-written families: its ``geometry`` is the packed vector of :func:`geometry` and its kernel is
:func:`kernel` (registered under ``"geometric"`` in :data:`armkit.ik.analytic._single.KERNELS`). For one
target the kernel does in one call what :meth:`Geometric.solve` and :func:`armkit.ik.analytic._single.post`
do in several:

1. the target checked and, for a class solved on the reversed chain, inverted;
2. the solver's kernel of :mod:`.solvers` (the core and its FK check on the true chain, the same
   functions :func:`.solvers.solve_batch` loops over; the core run by :func:`.solvers_check._core_in` in work
   arrays cut from the kernel's work vector, :data:`CORE_WORK`, where ``_closed_core`` makes them), for the
   classes solved in closed form (spherical wrist, three parallel axes; :func:`closed_form_only`);
3. the branches laid out as :meth:`Geometric.solve` lays them out (solutions in the solver's order,
   the rest padded with the first and marked unreachable; an unreachable target: the least-squares
   candidates, or the start);
4. the steps of :func:`armkit.ik.analytic._single._finish`: wrap, FK of the robot, check, sort.

The kernel takes a shortcut past the check of step 2, which repeats the FK of step 4 on the same chain in another
form: where the core gives branches, none least-squares or singular and no two alike
(:func:`.solvers_check._distinct`), they go to step 4 unchecked (laid out as step 3 lays out passing ones), with a
gate (every branch checked, also for :func:`armkit.ik`). If the FK of the robot puts each within half the check's
tolerances, the check of step 2 passes them all (the two FKs of one chain differ by rounding, ~1e-15 of the arm's
size, and the check's rotation measure ``‖ΔR‖_F / √2 = 2 sin(θ/2)`` is at most step 4's angle ``θ``), keeping
every branch in its order: the same answer to the bit, with one FK instead of two (the Kinova's ``ik_all``: 7.3 ->
5.9 µs, ``ik`` 7.2 -> 6.1). A branch above the gate sends the target the long way (step 2's check, then step 3).
Where some candidates are least-squares ones (a position or a wrist out of reach: a random arm of a class with a
meeting or parallel pair has 4-6 branches of 8) on a chain whose ideal form is the true one, the shortcut takes the
others where the check would fail each least-squares one (:func:`.solvers_check._apart`, one FK of the check's
for each of those): the check would drop them, and it never polishes them on such a chain.
A class solved on the reversed chain is checked there against the inverse target ``(Rᵀ, -Rᵀp)``, whose position
error is at most ``dp + θ |p|`` (``dp``, ``θ``: step 4's errors, ``p`` the target's position): its gate is a
quarter of the position tolerance for ``dp`` and for ``θ |p|``, and half the rotation tolerance for ``θ``
(:func:`.solvers_check._gate`, which the batch kernel's shortcut shares, :mod:`.batched`).

What the one call does not do the same way returns :data:`FALLBACK` (the caller answers by the
batched path, with the same result): a candidate the Python polish of :func:`.solvers.solve_batch`
would touch up, and a singular wrist (its branch carries a note).

The geometry vector (float64, read by the kernel at the indices below):

==========  =====  =================================================================
index       size   value
==========  =====  =================================================================
``WHICH``   1      the solver kernel (:data:`.solvers._WHICH`: 0 or 1 here)
``KIND``    1      its case (:data:`.solvers._CASES`)
``INV``     1      1.0: solved on the reversed chain for the inverse target
``EXACT``   1      1.0: the ideal chain is the true one (up to rounding)
``TOL_P``   1      the position tolerance of the check (:data:`.solvers.TOL` x arm size)
``TOL_R``   1      the rotation tolerance (:data:`.solvers.TOL`)
``NS``      1      samples of the 1-D searches (:data:`.solvers.SEARCH_N`)
``M``       1      branches of the class
``HI``      18     the ideal chain's axes (6, 3)
``PI``      21     its offsets (7, 3)
``RNT``     9      the tool rotation at q = 0 (3, 3)
``PRISM``   6      1.0 for a prismatic joint
``HT``      18     the true chain's axes
``PT``      21     its offsets
``REACH``   2      how far off a failed candidate is still polished: position, rotation
                   (:func:`.solvers.polish_reach`; the position times the arm size)
==========  =====  =================================================================
"""

from __future__ import annotations

from typing import Any, Optional

import numpy as np
from numpy.typing import NDArray

from ... import _jit_loader
from . import solvers as _solvers
from .solvers_check import CORE_M, CORE_T, CORE_V

__all__ = ["geometry", "kernel", "SIZE"]

WHICH, KIND, INV, EXACT, TOL_P, TOL_R, NS, M = range(8)
HI, PI, RNT, PRISM, HT, PT, REACH, SIZE = 8, 26, 47, 56, 62, 80, 101, 103
DONE, FALLBACK, BAD_TARGET = 0, 1, 2
"""The statuses of :mod:`armkit.ik.analytic._single` (a test checks that they agree)."""
THETA = 0
"""Row of the DH offsets in the joint table (:data:`armkit.ik.analytic._layout.JOINT_THETA`)."""
MAXSOL = 32
"""Rows of the solvers' candidate buffers (:data:`.solvers.MAXSOL`)."""


def geometry(form: Any, solver: str, m: int, inverted: bool) -> Optional[NDArray[np.float64]]:
    """The packed vector of the table above for the chain ``form`` (already reversed for an inverted class) and
    the solver named ``solver`` (:data:`.solvers.SOLVERS`), or None when no compiled kernel serves it."""
    from . import solvers

    name = solvers.case_of(solver, form)
    if name not in solvers._CASES or solvers._WHICH[solvers._CASES[name][0]] > 1:
        return None            # the 1-D searches (and the general 6R's 2-D search): see closed_form_only
    prep = solvers._prepare(form, name)
    if not closed_form_only(prep.Hi, prep.kind):
        return None
    g = np.zeros(SIZE)
    g[WHICH] = solvers._WHICH[prep.solve]
    g[KIND] = prep.kind
    g[INV] = 1.0 if inverted else 0.0
    g[EXACT] = 1.0 if prep.exact else 0.0
    g[TOL_P] = solvers.TOL * prep.scale
    g[TOL_R] = solvers.TOL
    g[NS] = solvers.SEARCH_N
    g[M] = m
    g[HI:PI] = prep.Hi.ravel()
    g[PI:RNT] = prep.Pi.ravel()
    g[RNT:PRISM] = prep.RnT.ravel()
    g[PRISM:HT] = prep.prism
    g[HT:PT] = prep.Ht.ravel()
    g[PT:REACH] = prep.Pt.ravel()
    g[REACH] = prep.reach * prep.scale
    g[REACH + 1] = prep.reach
    g.setflags(write=False)
    return g


def closed_form_only(Hi: NDArray[np.float64], kind: int) -> bool:
    """Whether the spherical-wrist case ``kind`` of the ideal chain's axes ``Hi`` solves the position in closed
    form: the general case (2) searches when axes 1 and 2 are parallel and 2, 3 are not (the test of
    :func:`.solvers_wrist._pos_general`, with its arithmetic).

    Only the closed forms run in the one call. A 1-D search compiled into this kernel rounds differently
    in the last bits (4e-15 rad seen) from the same search compiled into :func:`.solvers_check._sweep`, so
    its branches would not be those of the batched path to the bit; those classes keep the path of
    ``Geometric.solve`` and ``_single.post`` (the search dominates their time anyway)."""
    from .subproblems import _cross, _norm

    if kind != 2:
        return True
    return bool(_norm(_cross(Hi[1], Hi[2])) < 1e-9 or not _norm(_cross(Hi[0], Hi[1])) < 1e-9)


def _geometric(t, q0, ctx, fb, ib, bb, wk):
    """The kernel ``(t, q0, ctx, fb, ib, bb, wk) -> status`` of :mod:`armkit.ik.analytic._single` for the geometric
    family (steps 1-4 of the module docstring). Compiled by :func:`kernel` in a namespace that binds the names
    of the solvers' and ``_single``'s compiled functions; never run as Python. It makes no array (its work space
    is the caller's: :func:`work`), so it is compiled without reference counts."""
    _, g, joints, _, opts = _parts(ctx)  # noqa: F821
    n = 6
    which, kind, inverted, exact = int(g[WHICH]), int(g[KIND]), g[INV] != 0.0, g[EXACT] != 0.0
    tol_p, tol_r, N, m = g[TOL_P], g[TOL_R], int(g[NS]), int(g[M])
    # pieces of the work vectors (rows of 2-D pieces where they can be: a reshape is a call of its own): the
    # target; the chains' writable copies (the solver kernels are compiled for those) and the target's R, p; qref
    # and the empty reach radii of _finish (one zero); the solver's candidates Q (zero) and the branches rawq; the
    # flags prism, LS, SG (false) and unreach; the ints ST (zero) and lab; then _finish's
    _, T, at, usable = _begin(t, q0, opts, wk)  # noqa: F821
    if not usable:
        return BAD_TARGET
    v3 = shaped(wk[at:at + 3 * ROWS3], (ROWS3, 3))  # noqa: F821
    Hi, Pi, RnT, Ht, Pt, R, p = v3[0:6], v3[6:13], v3[13:16], v3[16:22], v3[22:29], v3[29:32], v3[32]
    for i in range(6):
        for j in range(3):
            Hi[i, j] = g[HI + 3 * i + j]
            Ht[i, j] = g[HT + 3 * i + j]
    for i in range(7):
        for j in range(3):
            Pi[i, j] = g[PI + 3 * i + j]
            Pt[i, j] = g[PT + 3 * i + j]
    for i in range(3):
        for j in range(3):
            RnT[i, j] = g[RNT + 3 * i + j]
    at += 3 * ROWS3
    qb = wk[at:at + n + 1]
    at += n + 1
    qq = shaped(wk[at:at + (MAXSOL + m) * n], (MAXSOL + m, n))  # noqa: F821
    at += (MAXSOL + m) * n
    for k in range(n + 1):
        qb[k] = 0.0
    for i in range(MAXSOL + m):
        for k in range(n):
            qq[i, k] = 0.0
    qref, none = qb[:n], qb[n:]
    Q, rawq = qq[:MAXSOL], qq[MAXSOL:]
    # the core's work arrays (what _closed_core makes: three arrays made and freed a call, ~0.1 µs; _core_in zeroes
    # them): vectors, matrices, the three-parallel core's (q1, q5) pairs
    cw = wk[at:at + CORE_WORK]
    cv3 = shaped(cw[:3 * CORE_V], (CORE_V, 3))  # noqa: F821
    cm3 = shaped(cw[3 * CORE_V:3 * CORE_V + 9 * CORE_M], (CORE_M, 3, 3))  # noqa: F821
    t14 = shaped(cw[3 * CORE_V + 9 * CORE_M:], (CORE_T, 4))  # noqa: F821
    at += CORE_WORK
    # _apart's: a candidate's angles with their sines and cosines, the FK's rotations and positions after each joint
    a3 = wk[at:at + 3 * n]
    aR = shaped(wk[at + 3 * n:at + 3 * n + 9 * (n + 1)], (n + 1, 3, 3))  # noqa: F821
    aP = shaped(wk[at + 3 * n + 9 * (n + 1):at + APART_WORK], (n + 1, 3))  # noqa: F821
    at += APART_WORK
    b_at = 2 * m + n + 2 * MAXSOL + m
    wb = bb[2 * m:b_at]
    for k in range(wb.shape[0]):
        wb[k] = False
    prism, LS, SG, unreach = wb[:n], wb[n:n + MAXSOL], wb[n + MAXSOL:n + 2 * MAXSOL], wb[n + 2 * MAXSOL:]
    cls = bb[b_at:b_at + 8]   # the core's least-squares flags of its positions (or pairs)
    b_at += 8
    for k in range(n):
        prism[k] = g[PRISM + k] != 0.0
    i_at = 5 * m + MAXSOL + m
    wi = ib[5 * m:i_at]
    for k in range(wi.shape[0]):
        wi[k] = 0
    ST, lab = wi[:MAXSOL], wi[MAXSOL:]
    if inverted:   # the reversed chain, for the inverse target (Geometric.solve's einsum, term by term)
        for i in range(3):
            for j in range(3):
                R[i, j] = T[j, i]
        for i in range(3):
            p[i] = -(R[i, 0] * T[0, 3] + R[i, 1] * T[1, 3] + R[i, 2] * T[2, 3])
        for k in range(n):
            qref[k] = q0[n - 1 - k] + joints[THETA, n - 1 - k]
    else:
        for i in range(3):
            for j in range(3):
                R[i, j] = T[i, j]
            p[i] = T[i, 3]
        for k in range(n):
            qref[k] = q0[k] + joints[THETA, k]
    mc = _core_in(which, kind, Hi, Pi, RnT, prism, R, p, qref, N, Q, LS, SG, cv3, cm3, t14, cls)  # noqa: F821
    k = min(mc, m)
    if k > 0 and not _distinct(Q, LS, SG, prism, k, rawq, inverted):  # noqa: F821
        # least-squares candidates (or a singular or repeated one) on an exact chain: the others, where the check
        # fails every least-squares one (module docstring)
        k = 0
        if exact and mc <= m:
            k = _apart(Q, LS, SG, prism, mc, rawq, inverted, Ht, Pt, RnT, R, p, tol_p, tol_r,  # noqa: F821
                       a3, aR, aP)
    if k > 0:
        # the shortcut (module docstring): branches found, none least-squares or singular, no two alike; if the FK
        # of the robot puts each within the gate, the check on the true chain passes them all
        gate_p, gate_r = _gate(inverted, tol_p, tol_r, T[0, 3], T[1, 3], T[2, 3])  # noqa: F821
        for b in range(m):
            if b >= k:   # padding, as the long way pads
                for j in range(n):
                    rawq[b, j] = rawq[0, j]
            unreach[b] = b >= k
            lab[b] = b
        status = _finish(rawq, unreach, unreach, lab, ctx, q0, T, _YES, _NO, float(k), none, m + 1,  # noqa: F821
                         gate_p, gate_r, fb, ib, bb, wk[at:], ib[i_at:], bb[b_at:])
        if status != RECHECK:  # noqa: F821
            return status
    ng, nf = _check(mc, Ht, Pt, RnT, prism, R, p, tol_p, tol_r, Q, LS, SG, ST)  # noqa: F821
    if nf > 0 and _polish_wanted(Ht, Pt, RnT, prism, R, p, Q, LS, ng, nf, exact, g[REACH],  # noqa: F821
                                 g[REACH + 1]):   # solve_batch would polish one in Python
        return FALLBACK
    count = ng if ng > 0 else nf
    k = min(count, m)
    for b in range(k):
        if ng > 0 and SG[b]:
            return FALLBACK   # a singular wrist: the branch has a note
        for j in range(n):
            rawq[b, j] = Q[b, n - 1 - j] if inverted else Q[b, j]
        unreach[b] = ng == 0
    for b in range(k, m):
        for j in range(n):
            rawq[b, j] = rawq[0, j] if k > 0 else q0[j] + joints[THETA, j]
        unreach[b] = True
    for b in range(m):
        lab[b] = b
    found = float(k) if ng > 0 else 0.0
    return _finish(rawq, unreach, unreach, lab, ctx, q0, T, _YES, _NO, found, none, m + 1,  # noqa: F821
                   _NO_GATE, _NO_GATE, fb, ib, bb, wk[at:], ib[i_at:], bb[b_at:])


ROWS3 = 6 + 7 + 3 + 6 + 7 + 3 + 1
"""Rows of the kernel's (rows, 3) work piece: Hi, Pi, RnT, Ht, Pt, R, p."""
CORE_WORK = 3 * CORE_V + 9 * CORE_M + 4 * CORE_T
"""Floats of the cores' work: the vectors, the matrices, the rows of 4 (the wrists' lanes, the three-parallel core's
(q1, q5) pairs)."""


APART_WORK = 3 * 6 + 12 * 7
"""Floats of :func:`.solvers_check._apart`'s work: angles, sines, cosines (6 each), rotations (7, 3, 3), positions
(7, 3)."""


def work(m: int, n: int) -> tuple[int, int, int]:
    """The work space :func:`_geometric` cuts for itself (``_single.WORK``): ``(floats, ints, flags)``."""
    return 16 + 3 * ROWS3 + n + 1 + (MAXSOL + m) * n + CORE_WORK + APART_WORK, MAXSOL + m, n + 2 * MAXSOL + m + 8


_KERNEL: Any = None
_YES, _NO = np.True_, np.False_   # typed bool, not literal True/False: one signature of _finish (see _single)


def kernel() -> Any:
    """The compiled :func:`_geometric`, registered in :data:`armkit.ik.analytic._single.KERNELS` under
    ``"geometric"``; None without Numba. Compiled on first use (cached on disk)."""
    global _KERNEL
    if _KERNEL is None:
        from . import solvers

        K = solvers.kernels()
        if K is None:
            _KERNEL = False
            return None
        from .. import _jit_verify  # noqa: F401  (the dependency of _single, imported before it)
        from ..analytic import _single
        from .subproblems import jit_namespace

        assert (_single.DONE, _single.FALLBACK, _single.BAD_TARGET) == (DONE, FALLBACK, BAD_TARGET)
        assert _single.RECHECK not in (DONE, FALLBACK, BAD_TARGET)
        extra = {name: getattr(K, name) for name in ("_core_in", "_distinct", "_apart", "_gate", "_check",
                                                     "_polish_wanted")}
        extra.update({name: getattr(_single, name) for name in ("_parts", "_begin", "_finish", "shaped", "RECHECK",
                                                                "_NO_GATE")})
        ns = jit_namespace(globals(), ("_geometric",), extra=extra, uncounted=("_geometric",))

        _jit_loader.forget_stale_cache({"__file__": __file__, "_geometric": ns["_geometric"]}, SOURCES)
        _KERNEL = ns["_geometric"]
        _single.KERNELS.setdefault("geometric", _KERNEL)
        _single.WORK.setdefault("geometric", work)
    return _KERNEL or None


SOURCES = _solvers.SOURCES + (
    "ik/analytic/_single.py", "ik/analytic/_jit.py", "ik/analytic/_layout.py", "kinematics/_jit.py",
    "ik/_jit_verify.py", "_jit_shaped.py")
"""The files whose compiled functions the kernel contains: a change to any of them compiles it anew."""
