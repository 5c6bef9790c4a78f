"""The memo of the 1-D searches' branch ends (armkit.ik.geometric.search._eval_memo, _edges).

The two branches that end together between two samples are traced to their end at the same points; the second
trace reads the first's evaluations from a memo. The law: an evaluation through the memo is the plain evaluation,
to the bit, whether it was remembered or not, and the memo evaluates again only what it does not hold (a ring: the
oldest go first). Checked on the plain functions (counting the evaluations they make) and on the compiled ones.
"""

from __future__ import annotations

import numpy as np
import pytest

from armkit.ik.geometric import search as S

from test_search_speed_free import search_case   # same folder, on pytest's path


def _plain(kind, H, P, C, x, ev=S._eval):
    Sx, E = np.full((4, S.WIDTH), np.nan), np.full(4, np.nan)
    n = ev(getattr(S, kind), H, P, C, x, Sx, E)
    return n, Sx, E


@pytest.mark.parametrize("kind", ["TI", "TP", "SW", "SM"])
def test_the_memo_answers_as_the_evaluation_and_evaluates_only_what_it_lacks(kind, monkeypatch):
    H, P, C, g = search_case(kind, {"TI": 1, "TP": 2, "SW": 3, "SM": 4}[kind])
    xs = g.uniform(-np.pi, np.pi, 5)
    # a ring of 3: x0 x1 x0 (held) x2 x3 (x0 pushed out) x0 (evaluated again) x3 (held)
    order = [0, 1, 0, 2, 3, 0, 3]
    fresh = [True, True, False, True, True, True, False]
    calls = []
    plain = S._eval

    def counted(*args):
        calls.append(args[4])
        return plain(*args)

    monkeypatch.setattr(S, "_eval", counted)    # what _eval_memo calls
    MR, MC = np.full((3, S.MEMO_COLS), np.nan), np.zeros(1, dtype=np.int64)
    for i, new in zip(order, fresh):
        before = len(calls)
        Sm, Em = np.full((4, S.WIDTH), np.nan), np.full(4, np.nan)
        n = S._eval_memo(getattr(S, kind), H, P, C, xs[i], Sm, Em, MR, MC)
        assert (len(calls) - before == 1) == new, (i, new)
        n0, S0, E0 = _plain(kind, H, P, C, xs[i], plain)
        assert n == n0
        assert np.array_equal(Sm[:n], S0[:n], equal_nan=True) and np.array_equal(Em[:n], E0[:n])


@pytest.mark.parametrize("kind", ["TI", "TP"])
def test_the_compiled_memo_answers_as_the_compiled_evaluation(kind):
    pytest.importorskip("numba")
    K = S.kernels()
    H, P, C, g = search_case(kind, 7)
    MR, MC = np.empty((S.MEMO, S.MEMO_COLS)), np.zeros(1, dtype=np.int64)
    xs = g.uniform(-np.pi, np.pi, 40)
    for x in np.concatenate([xs, xs[::-1]]):       # each x twice: once evaluated, once read back
        Sm, Em = np.full((4, S.WIDTH), np.nan), np.full(4, np.nan)
        n = K._eval_memo(getattr(S, kind), H, P, C, x, Sm, Em, MR, MC)
        n0, S0, E0 = _plain(kind, H, P, C, x, K._eval)
        assert n == n0
        assert np.array_equal(Sm[:n], S0[:n], equal_nan=True) and np.array_equal(Em[:n], E0[:n])
    assert MC[0] == len(xs)                          # the second pass evaluated nothing
