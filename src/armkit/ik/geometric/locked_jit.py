"""Numba kernel of :mod:`.locked`: the branches of held and swept joints laid out in one compiled call.

After the compiled solvers (:func:`.solvers_check._sweep`) have filled every value's solutions,
:meth:`.locked.Locked.solve` lays them out as branches of the full arm: per target and value the
``m6`` solutions (the rest padded with the first, or the start where there is none), the held
and swept joints put back in their places, the branches the class allows but the target lacks
marked unreachable. :func:`_layout` does that with the arithmetic of the NumPy code it replaces
(the same values to the bit), and counts the candidates that :meth:`.locked.Locked._polish_near`
must touch up first. Imported lazily (:func:`armkit._jit_loader.kernels`), only when the Numba
back end is in use.
"""

from __future__ import annotations

from ... import _jit_loader

_jit_loader.install_cache_fallback()  # before the first cache=True: read-only installs cache elsewhere

from numba import njit  # noqa: E402


@njit(cache=True)
def near_count(LS, good, NF):
    """How many candidates failed the solvers' check while the target is in reach: ``LS (V, B, M)`` false among
    the ``NF (V, B)`` candidates that follow the ``good (V, B)`` solutions (:meth:`.locked.Locked._candidates`)."""
    V, B = good.shape
    c = 0
    for v in range(V):
        for b in range(B):
            for i in range(good[v, b], min(good[v, b] + NF[v, b], LS.shape[2])):
                if not LS[v, b, i]:
                    c += 1
    return c


@njit(cache=True)
def layout(Q, good, cand, m6, inverted, free, held, held_val, swept, values, q0phi, theta, out, unreach, found):
    """The branches of :meth:`.locked.Locked.solve` from the solutions of every value.

    Parameters
    ----------
    Q : ndarray (V, B, M, 6)
        Solutions of the reduced chain (in the order of its form: reversed for an inverted class).
    good, cand : ndarray (V, B) of int64
        Solutions that pass the check (they come first), and else least-squares candidates.
    m6 : int
        Branches of the 6R class.
    inverted : bool
        The reduced chain is the reversed one.
    free : ndarray (6,) of int64
        The full arm's joints of the reduced chain, in order.
    held, held_val : ndarray (H,) of int64, ndarray (H,)
        Held joints and their values.
    swept : int
        The swept joint, or -1.
    values : ndarray (V,)
        Its values (one NaN without a sweep).
    q0phi, theta : ndarray (B, n), ndarray (n,)
        The start plus the DH offsets, and the offsets.
    out : ndarray (B, V * m6, n)
        The branches, plus ``theta`` (written).
    unreach : ndarray (B, V * m6) of bool
        Branches the target lacks (written).
    found : ndarray (B, V) of int64
        Solutions per target and value, at most ``m6`` (written).
    """
    V, B = good.shape
    n = theta.shape[0]
    nf = free.shape[0]
    q0 = q0phi - theta
    for b in range(B):
        for v in range(V):
            g = good[v, b]
            c = cand[v, b]
            count = min(max(g, c), m6)
            fnd = min(g, m6)
            found[b, v] = fnd
            for i in range(m6):
                r = v * m6 + i
                src = i if i < count else 0
                for j in range(n):
                    out[b, r, j] = q0[b, j]
                for k in range(nf):
                    if count > 0:
                        x = Q[v, b, src, nf - 1 - k] if inverted else Q[v, b, src, k]
                    else:
                        x = q0[b, free[k]]
                    out[b, r, free[k]] = x
                for h in range(held.shape[0]):
                    out[b, r, held[h]] = held_val[h]
                if swept >= 0:
                    out[b, r, swept] = values[v]
                for j in range(n):
                    out[b, r, j] = out[b, r, j] + theta[j]
                unreach[b, r] = not i < fnd
