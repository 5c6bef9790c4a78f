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

Compiled on first use with the solvers' kernels (:func:`.solvers.kernels`); ``njit(cache=True)``, and its
``parallel=True`` twin for batches of :data:`PARALLEL_MIN` targets or more.
"""

from __future__ import annotations

import types
from typing import Any, Optional

import numpy as np
from numpy.typing import NDArray

from . import solvers as _solvers

__all__ = ["solve", "kernels", "PARALLEL_MIN"]

PARALLEL_MIN = 32
"""Batches from this many targets run on the threaded kernel (below it a thread-pool launch costs more than it
saves)."""
MAXSOL = 32
"""Rows of the solvers' candidate buffers (:data:`.solvers.MAXSOL`)."""


def _layout(which, kind, inverted, exact, Hi, Pi, RnT, prism, Ht, Pt, T, q0phi, N, tol_p, tol_r, reach_p, reach_r,
            q, unreach, sing, found, redo):
    """Solve and lay out every target of ``T (B, 4, 4)`` (``q0phi (B, 6)``: the start plus the DH offsets) into
    ``q (B, m, 6)``, ``unreach (B, m)``, ``sing (B, m)`` (a singular wrist's branch), ``found (B,)`` (solutions
    the target has) and ``redo (B,)`` (left to the Python polish; the other outputs of that target untouched).
    Compiled by :func:`kernels` in a namespace that binds the solvers' compiled kernels; never run as Python."""
    B = T.shape[0]
    m = q.shape[1]
    n = 6
    for b in prange(B):  # noqa: F821
        R = np.empty((3, 3))
        p = np.empty(3)
        qref = np.empty(n)
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
        Q = np.zeros((MAXSOL, n))
        LS = np.zeros(MAXSOL, np.bool_)
        SG = np.zeros(MAXSOL, np.bool_)
        ST = np.zeros(MAXSOL, np.int64)
        if which == 0:
            ng, nf = _solve_spherical(kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p, tol_r,  # noqa: F821
                                      Q, LS, SG, ST)
        elif which == 1:
            ng, nf = _solve_three_parallel(kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, qref, N, tol_p,  # noqa: F821
                                           tol_r, Q, LS, SG, ST)
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
            "_solve_spherical", "_solve_three_parallel", "_solve_two_intersecting_end", "_solve_two_parallel",
            "_solve_spherical_middle", "_polish_wanted")}
        extra["prange"] = prange
        ns = jit_namespace(globals(), ("_layout",), extra=extra)
        py = _layout
        twin = types.FunctionType(py.__code__, ns, "_layout_parallel", py.__defaults__, py.__closure__)
        twin.__qualname__ = "_layout_parallel"
        ns["_layout_parallel"] = njit(cache=True, parallel=True)(twin)
        from ... import _jit_loader

        _jit_loader.forget_stale_cache({"__file__": __file__, "_layout": ns["_layout"],
                                        "_layout_parallel": ns["_layout_parallel"]}, SOURCES)
        _KERNELS = types.SimpleNamespace(serial=ns["_layout"], parallel=ns["_layout_parallel"])
    return _KERNELS


def solve(prep: Any, inverted: bool, m: int, target: NDArray[np.float64], q0phi: NDArray[np.float64], N: int,
          tol_p: float, tol_r: float) -> Optional[tuple]:
    """Every target of ``target (B, 4, 4)`` by the prepared solver ``prep`` (:func:`.solvers._prepare`) in one
    compiled call: ``(q (B, m, 6), unreachable (B, m), singular (B, m), found (B,), redo (B,))`` (see
    :func:`_layout`), or None without Numba."""
    K = kernels()
    if K is None:
        return None
    from . import solvers
    from ... import _jit_loader

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
       q, unreach, sing, found, redo)
    return q, unreach, sing, found, redo


SOURCES = _solvers.SOURCES
"""The files whose compiled functions the kernel contains: a change to any of them compiles it anew."""
