"""A batch of targets of the geometric family in one compiled call: every target solved and laid out in a
``prange`` loop (two threads on this machine), writing the branch arrays directly.

:meth:`armkit.ik.analytic.geometric.Geometric.solve` answers a batch ``(B, 4, 4)`` of :func:`armkit.ik_all` /
:func:`armkit.ik`: per target, the solver's kernel (:func:`.solvers_check._solve_spherical` and the others,
the core and its FK check on the true chain, the same functions :func:`.solvers_check._sweep` and the one-call
kernel of :mod:`.one_call` call), then the layout of its branches (solutions in the solver's order, padded with
the first and marked unreachable; an unreachable target: the least-squares candidates, or the start). Before
this module the layout ran in Python, one target at a time, after a one-thread compiled loop over the solvers.

:func:`solve` does both in one compiled call over the batch. A target whose failed candidates the Python polish
of :func:`.solvers.solve_batch` would touch up (an ideal chain that is not the true one) is flagged ``redo`` and
left to the caller, which answers it as before (through :func:`.solvers._run`): the results are those of the
former path.

The closed forms take the one-call kernel's shortcut past the check (:mod:`.one_call`): where the core's
candidates are none least-squares or singular and no two alike, the FK of the robot (its packed chain, as the
verification after the solve computes it) in place of the check's FK on the true chain, gated at the one-call
kernel's gate; the same branches, in the same order, as the check would keep. A target whose branches are not all
within the gate is checked. (The FK of the robot is the cheaper of the two: its sines and cosines in one vector
loop, its constant link transforms; the Kinova's batch of 4,000: 3.55 -> 2.85 µs a target on two threads.)

Compiled on first use with the solvers' kernels (:func:`.solvers.kernels`); ``njit(cache=True)``, and its
``parallel=True`` twin for batches of :data:`PARALLEL_MIN` targets or more.
"""

from __future__ import annotations

import types
from typing import Any, Optional

import numpy as np
from numpy.typing import NDArray

from ... import _jit_loader
from . import solvers as _solvers
from .solvers_check import CORE_M, CORE_T, CORE_V

__all__ = ["solve", "kernels", "PARALLEL_MIN"]

PARALLEL_MIN = 32
"""Batches from this many targets run on the threaded kernel (below it a thread-pool launch costs more than it
saves)."""
MAXSOL = 32
"""Rows of the solvers' candidate buffers (:data:`.solvers.MAXSOL`)."""


def _layout(which, kind, inverted, exact, Hi, Pi, RnT, prism, Ht, Pt, T, q0phi, N, tol_p, tol_r, reach_p, reach_r,
            F, theta, q, unreach, sing, found, redo):
    """Solve and lay out every target of ``T (B, 4, 4)`` (``q0phi (B, 6)``: the start plus the DH offsets) into
    ``q (B, m, 6)``, ``unreach (B, m)``, ``sing (B, m)`` (a singular wrist's branch), ``found (B,)`` (solutions
    the target has) and ``redo (B,)`` (left to the Python polish; the other outputs of that target untouched).
    ``F``: the robot's packed chain (:func:`armkit.kinematics.packed`), ``theta (6,)`` its DH offsets, for the
    shortcut past the check (module docstring). Compiled by :func:`kernels` in a namespace that binds the solvers'
    compiled kernels; never run as Python."""
    B = T.shape[0]
    m = q.shape[1]
    n = 6
    chunks = min(B, CHUNKS)
    for c in prange(chunks):  # noqa: F821
        # the work of one chunk of targets, made once for all of them: R, p and the reference qref of the solver's
        # chain; its candidates Q and flags LS, SG, ST; for the shortcut, the branches W in the robot's order,
        # their DH angles D (flat) with sines and cosines S, C, their poses Tm and the FK's poses after each joint X
        R = np.empty((3, 3))
        p = np.empty(3)
        qref = np.empty(n)
        Q = np.empty((MAXSOL, n))
        LS = np.empty(MAXSOL, np.bool_)
        SG = np.empty(MAXSOL, np.bool_)
        ST = np.empty(MAXSOL, np.int64)
        W = np.empty((m, n))
        D = np.empty(m * n)
        S = np.empty(m * n)
        C = np.empty(m * n)
        Tm = np.empty((m, 4, 4))
        X = np.empty(12 * (n + 1))
        # the closed-form cores' work arrays, as _closed_core makes them (made once a chunk; _core_in zeroes them)
        V3 = np.empty((CORE_V, 3))
        M3 = np.empty((CORE_M, 3, 3))
        T14 = np.empty((CORE_T, 4))
        CL = np.empty(8, np.bool_)
        for b in range(c * B // chunks, (c + 1) * B // chunks):
            _one_target(which, kind, inverted, exact, Hi, Pi, RnT, prism, Ht, Pt, T, q0phi, N, tol_p, tol_r,  # noqa
                        reach_p, reach_r, F, theta, q, unreach, sing, found, redo, b, R, p, qref, Q, LS, SG, ST, W,
                        D, S, C, Tm, X, V3, M3, T14, CL)


def _one_target(which, kind, inverted, exact, Hi, Pi, RnT, prism, Ht, Pt, T, q0phi, N, tol_p, tol_r, reach_p,
                reach_r, F, theta, q, unreach, sing, found, redo, b, R, p, qref, Q, LS, SG, ST, W, D, S, C, Tm, X, V3,
                M3, T14, CL):
    """Target ``b`` of :func:`_layout`, in its chunk's work arrays (``R`` ... ``X``; ``V3`` ... ``CL``: a closed-form
    core's, :func:`.solvers_check._core_in`, where ``_closed_core`` made three arrays a target)."""
    m = q.shape[1]
    n = 6
    if inverted:     # the reversed chain, for the inverse target (as Geometric.solve and the one call do it)
        for i in range(3):
            for j in range(3):
                R[i, j] = T[b, j, i]
        for i in range(3):
            p[i] = -(R[i, 0] * T[b, 0, 3] + R[i, 1] * T[b, 1, 3] + R[i, 2] * T[b, 2, 3])
        for k in range(n):
            qref[k] = q0phi[b, n - 1 - k]
    else:
        for i in range(3):
            for j in range(3):
                R[i, j] = T[b, i, j]
            p[i] = T[b, i, 3]
        for k in range(n):
            qref[k] = q0phi[b, k]
    for i in range(MAXSOL):
        for k in range(n):
            Q[i, k] = 0.0
        LS[i] = False
        SG[i] = False
        ST[i] = 0
    if which <= 1:   # a closed form: its core, then the shortcut past the check, or the check
        mc = _core_in(which, kind, Hi, Pi, RnT, prism, R, p, qref, N, Q, LS, SG, V3, M3, T14, CL)  # noqa: F821
        if _shortcut(inverted, prism, T, b, tol_p, tol_r, F, theta, Q, LS, SG, mc, W, D, S, C, Tm, X):
            k = min(mc, m)
            for r in range(m):
                for j in range(n):
                    q[b, r, j] = W[r if r < k else 0, j]
                unreach[b, r] = r >= k
                sing[b, r] = False
            found[b] = k
            redo[b] = False
            return
        ng, nf = _check(mc, Ht, Pt, RnT, prism, R, p, tol_p, tol_r, Q, LS, SG, ST)  # noqa: F821
    elif which == 2:
        ng, nf = _solve_two_intersecting_end(kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N,  # noqa: F821
                                             tol_p, tol_r, Q, LS, SG, ST)
    elif which == 3:
        ng, nf = _solve_two_parallel(kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p,  # noqa: F821
                                     tol_r, Q, LS, SG, ST)
    else:
        ng, nf = _solve_spherical_middle(kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p,  # noqa: F821
                                         tol_r, Q, LS, SG, ST)
    # solve_batch polishes in Python a failed candidate (unless it is a least-squares one of an exact chain)
    # that lies within reach_p, reach_r of the target (solvers.polish_reach)
    again = nf > 0 and _polish_wanted(Ht, Pt, RnT, prism, R, p, Q, LS, ng, nf, exact, reach_p,  # noqa: F821
                                      reach_r)
    redo[b] = again
    if not again:
        count = ng if ng > 0 else nf
        k = min(count, m)
        for r in range(k):
            for j in range(n):
                q[b, r, j] = Q[r, n - 1 - j] if inverted else Q[r, j]
            unreach[b, r] = ng == 0
            sing[b, r] = ng > 0 and SG[r]
        for r in range(k, m):
            for j in range(n):
                q[b, r, j] = q[b, 0, j] if k > 0 else q0phi[b, j]
            unreach[b, r] = True
            sing[b, r] = False
        found[b] = k if ng > 0 else 0


def _shortcut(inverted, prism, T, b, tol_p, tol_r, F, theta, Q, LS, SG, mc, W, D, S, C, Tm, X):
    """Whether the ``mc`` candidates of ``Q`` take the shortcut past the check (module docstring), their angles
    then in ``W`` (m, 6) in the robot's order: none least-squares or singular, no two alike
    (:func:`.solvers_check._distinct`), and the FK of the robot (``F``, DH angles ``W - theta``) puts each within
    the one-call kernel's gate (:func:`.solvers_check._gate`) of target ``T[b]``."""
    m, n = W.shape
    k = min(mc, m)
    if k == 0 or not _distinct(Q, LS, SG, prism, k, W, inverted):  # noqa: F821
        return False
    gate_p, gate_r = _gate(inverted, tol_p, tol_r, T[b, 0, 3], T[b, 1, 3], T[b, 2, 3])  # noqa: F821
    for r in range(k):
        for j in range(n):
            D[r * n + j] = W[r, j] - theta[j]
    _sincos_block(D[:k * n], S[:k * n], C[:k * n])  # noqa: F821
    _fk_rows_shared(F, D[:k * n].reshape((k, n)), S, C, Tm, X)  # noqa: F821
    for r in range(k):
        d = D[r * n:(r + 1) * n]
        e_p, e_r, _ = _verify(Tm[r], T[b], True, d, d, d, 0.0)  # noqa: F821  (the limits: not asked here)
        if not (e_p <= gate_p and e_r <= gate_r):
            return False
    return True


CHUNKS = 64
"""Pieces a batch is cut into, each with its work arrays made once (the threads share them out)."""


_KERNELS: Optional[types.SimpleNamespace] = None
_NO_NUMBA = False


def kernels() -> Optional[types.SimpleNamespace]:
    """The compiled :func:`_layout` (``serial``) and its ``parallel=True`` twin (``parallel``), or None without
    Numba. Compiled on first use (cached on disk)."""
    global _KERNELS, _NO_NUMBA
    if _KERNELS is None and not _NO_NUMBA:
        from . import solvers

        K = solvers.kernels()
        if K is None:
            _NO_NUMBA = True
            return None
        from numba import njit, prange

        from .subproblems import jit_namespace

        extra: dict[str, Any] = {name: getattr(K, name) for name in (
            "_core_in", "_distinct", "_gate", "_check", "_solve_two_intersecting_end", "_solve_two_parallel",
            "_solve_spherical_middle", "_polish_wanted")}
        from .. import _jit_verify
        from ..analytic import _single
        from ...kinematics._jit import sincos_block

        extra.update(prange=prange, _verify=_jit_verify._check, _fk_rows_shared=_single._fk_rows_shared,
                     _sincos_block=sincos_block)
        ns = jit_namespace(globals(), ("_shortcut", "_one_target", "_layout"), extra=extra)
        py = _layout
        twin = types.FunctionType(py.__code__, ns, "_layout_parallel", py.__defaults__, py.__closure__)
        twin.__qualname__ = "_layout_parallel"
        ns["_layout_parallel"] = njit(cache=True, parallel=True)(twin)

        _jit_loader.forget_stale_cache({"__file__": __file__, **{name: ns[name] for name in (
            "_shortcut", "_one_target", "_layout", "_layout_parallel")}}, SOURCES)
        _KERNELS = types.SimpleNamespace(serial=ns["_layout"], parallel=ns["_layout_parallel"])
    return _KERNELS


def solve(prep: Any, inverted: bool, m: int, target: NDArray[np.float64], q0phi: NDArray[np.float64], N: int,
          tol_p: float, tol_r: float, F: NDArray[np.float64], theta: NDArray[np.float64]) -> Optional[tuple]:
    """Every target of ``target (B, 4, 4)`` by the prepared solver ``prep`` (:func:`.solvers._prepare`) in one
    compiled call: ``(q (B, m, 6), unreachable (B, m), singular (B, m), found (B,), redo (B,))`` (see
    :func:`_layout`), or None without Numba."""
    K = kernels()
    if K is None:
        return None
    from . import solvers

    B = len(target)
    q = np.zeros((B, m, 6))
    unreach = np.zeros((B, m), dtype=np.bool_)
    sing = np.zeros((B, m), dtype=np.bool_)
    found = np.zeros(B, dtype=np.int64)
    redo = np.zeros(B, dtype=np.bool_)
    fn = K.parallel if B >= PARALLEL_MIN and _jit_loader.parallel_ok() else K.serial
    c = np.ascontiguousarray
    fn(solvers._WHICH[prep.solve], prep.kind, inverted, prep.exact, prep.Hi, prep.Pi, prep.RnT, prep.prism, prep.Ht,
       prep.Pt, c(target, dtype=float), c(q0phi, dtype=float), N, tol_p, tol_r, prep.reach * prep.scale, prep.reach,
       F, c(theta, dtype=float), q, unreach, sing, found, redo)
    return q, unreach, sing, found, redo


SOURCES = _solvers.SOURCES + ("ik/analytic/_single.py", "ik/_jit_verify.py", "_jit_shaped.py")
"""The files whose compiled functions the kernel contains: a change to any of them compiles it anew."""
