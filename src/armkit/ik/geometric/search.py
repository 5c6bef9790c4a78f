"""A 1-D search for the 6R class with one parallel pair: axes 2 ∥ 3 and nothing else (IK-Geo's idea).

With q6 sampled, ``R_05 = R_06 rot(h6, q6)ᵀ`` is known and the wrist point of axis 5,
``w = p − p_0 − R_05 p_56 − R_06 p_6T = R_01 p_12 + R_02 p_23 + R_03 p_34 + R_04 p_45``, too.
Because ``h3 = ±h2``, ``rot(h2, q2) rot(h3, q3) = rot(h2, θ)`` with ``θ = q2 ± q3``, and two
scalar equations hold without θ (``h2ᵀ rot(h2, θ) = h2ᵀ``)::

    h2ᵀ rot(h1, −q1) w        − h2ᵀ rot(h4, q4) p_45 = h2ᵀ (p_12 + p_23 + p_34)     (position along h2)
    h2ᵀ rot(h1, −q1) R_05 h5  − h2ᵀ rot(h4, q4) h5   = 0                          (orientation)

which is SP6 in (q1, q4): up to 4 solutions. Then θ by SP1 (``rot(h2, θ) rot(h4, q4) h5 =
rot(h1, −q1) R_05 h5``), q5 by SP1, and what is left of the position,
``d = rot(h1, −q1) w − p_12 − rot(h2, θ) (p_34 + rot(h4, q4) p_45) = rot(h2, q2) p_23``, asks
``|d| = |p_23|``: the residual ``|d| − |p_23|`` of each of the (up to 4) branches is a function of
q6 alone. Its sign changes between samples (branches matched from sample to sample by their
(q1, q4)) are refined by bisection along the branch; where a branch ends between two samples
(two SP6 solutions meet), the end is found by bisection and the branch sampled towards it
(:data:`EDGE_N` samples, quadratically spaced); then q2 by SP1, q3 = ±(θ − q2).

Resolution: :data:`N` samples of q6 over a turn. A root is missed when a branch's residual
touches zero without changing sign (a double root) or changes sign twice within one step (or
within one of the finer steps next to a branch end); every solution returned is checked
by FK of the true chain (after Newton steps where the chain's axes are only nearly parallel).
The search is compiled with Numba like :mod:`.solvers` (:func:`kernels`; the plain functions
without it). Not yet registered for ``armkit.ik_all``; call :func:`two_parallel` on a
:class:`~.poe.POE`.
"""

from __future__ import annotations

import math
import types
from typing import Any, Optional

import numpy as np
from numpy.typing import NDArray

from . import subproblems as _sp
from .poe import POE
from .solvers import _mm, _mv
from .subproblems import _dot, _norm, _wrap, rot, rotm, sp1, sp6

__all__ = ["two_parallel", "N", "EDGE_N", "kernels"]

Array = NDArray[np.float64]

N = 720
"""Samples of q6 over one turn (0.5° apart)."""
EDGE_N = 32
"""Samples (quadratically spaced) between the last sample of a branch and where it ends."""
MAXROOT = 64


def _tp_eval(H, P, R06, p, x, S, E):
    """At q6 = ``x``: each SP6 solution's (q1, q4, θ) into ``S (4, 3)`` and its residual into ``E (4,)``;
    returns their count."""
    R05 = _mm(R06, rotm(H[5], -x))
    w = p - P[0] - _mv(R05, P[5]) - _mv(R06, P[6])
    v = _mv(R05, H[4])
    Hs = np.empty((4, 3))
    Ks = np.empty((4, 3))
    Ps = np.empty((4, 3))
    for j in range(3):
        Hs[0, j] = H[1, j]
        Hs[1, j] = -H[1, j]
        Hs[2, j] = H[1, j]
        Hs[3, j] = -H[1, j]
        Ks[0, j] = -H[0, j]
        Ks[1, j] = H[3, j]
        Ks[2, j] = -H[0, j]
        Ks[3, j] = H[3, j]
        Ps[0, j] = w[j]
        Ps[1, j] = P[4, j]
        Ps[2, j] = v[j]
        Ps[3, j] = H[4, j]
    t0, t3, n, ls = sp6(Hs, Ks, Ps, _dot(H[1], P[1] + P[2] + P[3]), 0.0)
    if ls:
        return 0
    n2 = _norm(P[2])
    for i in range(n):
        R0t = rotm(H[0], -t0[i])
        u = rot(H[3], t3[i], H[4])
        th, _l = sp1(u, _mv(R0t, v), H[1])
        d = _mv(R0t, w) - P[1] - rot(H[1], th, P[3] + rot(H[3], t3[i], P[4]))
        S[i, 0] = t0[i]
        S[i, 1] = t3[i]
        S[i, 2] = th
        E[i] = _norm(d) - n2
    return n


def _tp_dist(a, b):
    return max(abs(_wrap(a[0] - b[0])), abs(_wrap(a[1] - b[1])))


def _tp_pick(S, n, ref, limit):
    """The index of the solution in ``S[:n]`` nearest ``ref`` (by q1, q4), -1 if none within ``limit``."""
    best = -1
    bd = limit
    for i in range(n):
        d = _tp_dist(S[i], ref)
        if d < bd:
            bd = d
            best = i
    return best


def _tp_refine(H, P, R06, p, a, fa, ref, b, out):
    """Bisection for the zero between ``a`` (branch ``ref``, residual ``fa``) and ``b``, following the branch;
    ``(x, q1, q4, θ)`` into ``out``. False when the branch is lost."""
    S = np.zeros((4, 3))
    E = np.zeros(4)
    cur = ref.copy()
    x = a
    for _ in range(60):
        x = 0.5 * (a + b)
        n = _tp_eval(H, P, R06, p, x, S, E)
        i = _tp_pick(S, n, cur, 0.5)
        if i < 0:
            return False
        cur[:] = S[i]
        if (E[i] > 0.0) == (fa > 0.0):
            a = x
            fa = E[i]
        else:
            b = x
        if abs(b - a) < 1e-14:
            break
    out[0] = x
    out[1] = cur[0]
    out[2] = cur[1]
    out[3] = cur[2]
    return True


def _tp_add(roots, nroot, out):
    if nroot < roots.shape[0]:
        for k in range(4):
            roots[nroot, k] = out[k]
        return nroot + 1
    return nroot


def _tp_edge(H, P, R06, p, x0, ref, f0, x1, roots, nroot):
    """Branch ``ref`` (residual ``f0``) at ``x0`` has no match at ``x1``: find where it ends (bisection), sample
    it towards the end quadratically spaced (the residual changes like a square root there), refine the sign
    changes. Returns the new count of ``roots``."""
    S = np.zeros((4, 3))
    E = np.zeros(4)
    out = np.zeros(4)
    good = x0
    bad = x1
    cur = ref.copy()
    for _ in range(40):
        mid = 0.5 * (good + bad)
        n = _tp_eval(H, P, R06, p, mid, S, E)
        i = _tp_pick(S, n, cur, 0.2)
        if i >= 0:
            good = mid
            cur[:] = S[i]
        else:
            bad = mid
    xa = x0
    fa = f0
    prev = ref.copy()
    for k in range(1, EDGE_N + 1):
        t = 1.0 - k / EDGE_N
        xb = good + (x0 - good) * t * t
        n = _tp_eval(H, P, R06, p, xb, S, E)
        i = _tp_pick(S, n, prev, 0.5)
        if i < 0:
            break
        if E[i] == 0.0:
            out[0] = xb
            out[1] = S[i, 0]
            out[2] = S[i, 1]
            out[3] = S[i, 2]
            nroot = _tp_add(roots, nroot, out)
        elif fa * E[i] < 0.0:
            if _tp_refine(H, P, R06, p, xa, fa, prev, xb, out):
                nroot = _tp_add(roots, nroot, out)
        xa = xb
        fa = E[i]
        prev[:] = S[i]
    return nroot


def _tp_search(H, P, R06, p, samples, roots):
    """The roots ``(q6, q1, q4, θ)`` into ``roots (MAXROOT, 4)``; returns their count."""
    Sa = np.zeros((samples + 1, 4, 3))
    Ea = np.zeros((samples + 1, 4))
    cnt = np.zeros(samples + 1, dtype=np.int64)
    xs = np.empty(samples + 1)
    for i in range(samples + 1):
        xs[i] = -math.pi + 2.0 * math.pi * i / samples
        cnt[i] = _tp_eval(H, P, R06, p, xs[i], Sa[i], Ea[i])
    out = np.zeros(4)
    nroot = 0
    for i in range(samples):
        for j in range(cnt[i + 1]):            # branches that begin between the samples
            if _tp_pick(Sa[i], cnt[i], Sa[i + 1, j], 0.5) < 0:
                nroot = _tp_edge(H, P, R06, p, xs[i + 1], Sa[i + 1, j].copy(), Ea[i + 1, j], xs[i], roots, nroot)
        for j in range(cnt[i]):
            k = _tp_pick(Sa[i + 1], cnt[i + 1], Sa[i, j], 0.5)
            if k < 0:                          # the branch ends between the samples
                nroot = _tp_edge(H, P, R06, p, xs[i], Sa[i, j].copy(), Ea[i, j], xs[i + 1], roots, nroot)
                continue
            if Ea[i, j] == 0.0:
                out[0] = xs[i]
                out[1] = Sa[i, j, 0]
                out[2] = Sa[i, j, 1]
                out[3] = Sa[i, j, 2]
                nroot = _tp_add(roots, nroot, out)
            elif Ea[i, j] * Ea[i + 1, k] < 0.0:
                if _tp_refine(H, P, R06, p, xs[i], Ea[i, j], Sa[i, j].copy(), xs[i + 1], out):
                    nroot = _tp_add(roots, nroot, out)
    return nroot


KERNELS = ("_tp_eval", "_tp_dist", "_tp_pick", "_tp_refine", "_tp_add", "_tp_edge", "_tp_search")
_KERNELS: Optional[types.SimpleNamespace] = None


def kernels() -> Optional[types.SimpleNamespace]:
    """The compiled search (attributes named as its functions), or None without Numba; compiled on first use."""
    global _KERNELS
    if _KERNELS is None:
        from . import solvers

        sk = _sp.kernels()
        gk = solvers.kernels()
        if sk is None or gk is None:
            return None
        extra = {name: sk.namespace[name] for name in _sp.KERNELS}
        extra.update({"_mm": gk._mm, "_mv": gk._mv})
        ns = _sp.jit_namespace(globals(), KERNELS, extra=extra)
        _KERNELS = types.SimpleNamespace(**{name: ns[name] for name in KERNELS})
    return _KERNELS


def _complete(H: Array, P: Array, R06: Array, p: Array, root: Array, sgn: float) -> Array:
    """The full q (6,) of a root ``(q6, q1, q4, θ)``."""
    x, q0, q3, th = (float(v) for v in root)
    R05 = R06 @ rotm(H[5], -x)
    w = p - P[0] - R05 @ P[5] - R06 @ P[6]
    R0t = rotm(H[0], -q0)
    d = R0t @ w - P[1] - rot(H[1], th, P[3] + rot(H[3], q3, P[4]))
    q1, _l1 = sp1(P[2], d, H[1])
    q2 = _wrap(sgn * (th - q1))
    M = rotm(H[3], q3).T @ rotm(H[1], th).T @ R0t @ R05     # rot(h5, q5)
    y = np.cross(H[4], np.array([1.0, 0.0, 0.0]) if abs(H[4][0]) < 0.9 else np.array([0.0, 1.0, 0.0]))
    y /= np.linalg.norm(y)
    q4, _l4 = sp1(y, M @ y, H[4])
    return np.array([q0, q1, q2, q3, q4, _wrap(x)])


def two_parallel(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *, samples: int = N,
                 jit: Optional[bool] = None) -> Any:
    """Every solution of a 6R chain whose axes 2 and 3 are parallel (all revolute), by a 1-D search over q6.

    Returns :class:`~.solvers.Solutions` (``ls`` all False; no candidates for an unreachable target).
    ``jit``: the compiled search (default: when armkit's back end is Numba), or the plain functions.
    """
    from .solvers import TOL, Solutions, _size, _use_jit, align, polish

    if form.n != 6 or np.any(form.prismatic):
        raise ValueError("two_parallel: for 6R chains")
    if float(np.linalg.norm(np.cross(form.H[1], form.H[2]))) > 1e-6:
        raise ValueError("two_parallel: axes 2 and 3 must be parallel")
    ideal, _dev = align(form, (), ((1, 2),))
    H = np.ascontiguousarray(ideal.H, dtype=float)
    P = np.ascontiguousarray(ideal.P, dtype=float)
    sgn = 1.0 if float(H[1] @ H[2]) > 0.0 else -1.0
    R = np.asarray(R, dtype=float)
    p = np.ascontiguousarray(p, dtype=float)
    R06 = np.ascontiguousarray(R @ np.asarray(form.R_nT, dtype=float).T)
    K = kernels() if _use_jit(jit) else None
    search = K._tp_search if K is not None else _tp_search
    roots = np.zeros((MAXROOT, 4))
    nroot = int(search(H, P, R06, p, int(samples), roots))
    scale = _size(form)
    out: list[Array] = []
    for r in range(nroot):
        q = _complete(H, P, R06, p, roots[r], sgn)
        Rq, pq = form.fk(q)
        if not (np.linalg.norm(pq - p) <= TOL * scale and np.linalg.norm(Rq - R) / math.sqrt(2.0) <= TOL):
            q = polish(form, q, R, p)
            q = (q + math.pi) % (2 * math.pi) - math.pi
            Rq, pq = form.fk(q)
            if not (np.linalg.norm(pq - p) <= TOL * scale and np.linalg.norm(Rq - R) / math.sqrt(2.0) <= TOL):
                continue
        if not any(np.abs((q - o + math.pi) % (2 * math.pi) - math.pi).max() < 1e-8 for o in out):
            out.append(q)
    Q = np.array(out).reshape(-1, 6)
    return Solutions(Q, np.zeros(len(Q), dtype=bool), np.zeros(len(Q), dtype=bool))
