"""The scalar SP1 and SP2 of the wrist and the sweep (:func:`armkit.ik.geometric.solvers_wrist._sp1s`,
``_sp2s``) against :func:`armkit.ik.geometric.subproblems.sp1` and ``sp2``, whose arithmetic they repeat
without temporary arrays: the same angles to the bit, the same count and least-squares flag, for random
inputs and the special cases (parallel axes, a zero vector, equal lengths, no intersection), both as
plain Python and compiled.
"""

from __future__ import annotations

import numpy as np
import pytest

from armkit.ik.geometric import solvers, solvers_wrist, subproblems


def _cases(count: int):
    rng = np.random.default_rng(7)
    unit = lambda v: v / np.linalg.norm(v)  # noqa: E731
    for i in range(count):
        a, b = rng.normal(size=3), rng.normal(size=3)
        k1, k2 = unit(rng.normal(size=3)), unit(rng.normal(size=3))
        mode = i % 5
        if mode == 1:
            k2 = k1.copy()                                   # parallel axes
        elif mode == 2:
            a = np.zeros(3)                                  # a zero vector
        elif mode == 3:
            b = unit(b) * np.linalg.norm(a)                  # equal lengths: the circles meet (or touch)
        elif mode == 4:
            b = a * (1.0 + 1e-12 * rng.normal())             # nearly the same vector
        yield a, b, k1, k2


def _same(sp1, sp2, sp1s, sp2s):
    for a, b, k1, k2 in _cases(2000):
        t1, t2, m, ls = sp2(a, b, k1, k2)
        r = sp2s(*a, *b, *k1, *k2)
        assert r[4] == m and bool(r[5]) == bool(ls)
        for i in range(m):
            assert r[i] == t1[i] and r[2 + i] == t2[i]
        th, l1 = sp1(a, b, k1)
        s = sp1s(*a, *b, *k1)
        assert s[0] == th and bool(s[1]) == bool(l1)


def test_plain():
    _same(subproblems.sp1, subproblems.sp2, solvers_wrist._sp1s, solvers_wrist._sp2s)


def test_compiled():
    pytest.importorskip("numba")
    sk, k = subproblems.kernels(), solvers.kernels()
    if sk is None or k is None:
        pytest.skip("no compiled kernels")
    _same(sk.sp1, sk.sp2, k._sp1s, k._sp2s)
