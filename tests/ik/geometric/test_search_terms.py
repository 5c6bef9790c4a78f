"""The `6R-two-parallel` search's terms made once (armkit.ik.geometric.search._tp_terms, _with_terms).

SP6's two linear terms that do not depend on the searched joint are made once a search and read by every
evaluation from three more rows of ``C``. The law: an evaluation that reads them is the evaluation that makes
them itself, to the bit, plain and compiled; the other kinds' ``C`` is left as it is.
"""

from __future__ import annotations

import numpy as np
import pytest

from armkit.ik.geometric import search as S

from test_search_speed_free import search_case   # same folder, on pytest's path


@pytest.mark.parametrize("compiled", [False, True], ids=["python", "compiled"])
def test_terms_made_once_give_the_same_branches(compiled):
    if compiled:
        pytest.importorskip("numba")
    K = S.kernels() if compiled else S
    for seed in range(5):
        H, P, C, g = search_case("TP", seed)
        C7 = K._with_terms(S.TP, H, P, C)
        assert C7.shape == (7, 3) and np.array_equal(C7[:4], C)
        for x in g.uniform(-np.pi, np.pi, 30):
            S4, E4 = np.full((4, S.WIDTH), np.nan), np.full(4, np.nan)
            S7, E7 = np.full((4, S.WIDTH), np.nan), np.full(4, np.nan)
            n4 = K._eval(S.TP, H, P, C, x, S4, E4)
            n7 = K._eval(S.TP, H, P, C7, x, S7, E7)
            assert n4 == n7
            assert np.array_equal(S4, S7, equal_nan=True) and np.array_equal(E4, E7, equal_nan=True)


@pytest.mark.parametrize("kind", ["TI", "SW", "SM"])
def test_other_kinds_keep_their_target_rows(kind):
    H, P, C, _ = search_case(kind, 1)
    assert S._with_terms(getattr(S, kind), H, P, C) is C
