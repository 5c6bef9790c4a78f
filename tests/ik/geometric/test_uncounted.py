"""The search kernels compiled without Numba's reference counts (``UNCOUNTED``, :func:`.subproblems.jit_namespace`).

Such a kernel counts no reference to the arrays it is given or views: safe only while it makes no array and is
handed none by a callee (an array returned to it would never be freed). The searches are run here with Numba's
allocation counters on: every array they make is freed (a leak or a double free changes the counts), and the
answers are those of the same solvers run as Python (the plain functions, every reference counted by Python).
"""

from __future__ import annotations

import numpy as np
import pytest

from armkit.ik.geometric import search as S
from armkit.ik.geometric import search2d as S2
from armkit.ik.geometric import solvers as G

from test_search_speed_free import KINDS   # same folder, on pytest's path
from test_solvers import random_arm

pytest.importorskip("numba")


@pytest.mark.parametrize("module", [S, S2], ids=lambda m: m.__name__.rsplit(".", 1)[-1])
def test_uncounted_names_are_kernels_of_their_module(module) -> None:
    """(``_kernels`` passes its whole ``KERNELS``: nothing to check there.)"""
    assert set(module.UNCOUNTED) <= set(module.KERNELS)
    assert len(set(module.UNCOUNTED)) == len(module.UNCOUNTED)


def _stats():
    from numba.core.runtime import rtsys

    s = rtsys.get_allocation_stats()
    return np.array([s.alloc, s.free, s.mi_alloc, s.mi_free])


def test_the_searches_free_every_array_they_make_and_agree_with_python() -> None:
    from numba.core.runtime import _nrt_python as nrt

    g = np.random.default_rng(20261206)
    cases = []
    for kind, (name, arm) in KINDS.items():
        for _ in range(3):
            form = arm(g)
            R, p = form.fk(g.uniform(-np.pi, np.pi, 6))
            cases.append((getattr(G, name), form, R, p))
    form = random_arm(g, "plain")             # a general 6R: the 2-D search (a coarse grid: this is no speed test)
    R, p = form.fk(g.uniform(-np.pi, np.pi, 6))
    general = (form, R, p)
    for solve, form, R, p in cases:           # compiled (or loaded) before the counts start
        solve(form, R, p, jit=True)
    S2.gen_six_dof(*general, samples=24, jit=True)
    nrt.memsys_enable_stats()
    try:
        before = _stats()
        compiled = [solve(form, R, p, jit=True) for solve, form, R, p in cases]
        grid = S2.gen_six_dof(*general, samples=24, jit=True)
        made = _stats() - before
    finally:
        nrt.memsys_disable_stats()
    assert made[0] > 0                        # the searches make their work arrays ...
    assert made[0] == made[1] and made[2] == made[3]   # ... and free every one
    for (solve, form, R, p), got in zip(cases, compiled):
        ref = solve(form, R, p, jit=False)
        assert got.q.shape == ref.q.shape and np.allclose(got.q, ref.q, rtol=0, atol=1e-9)
        assert np.array_equal(got.ls, ref.ls)
    assert len(grid.q) == len(S2.gen_six_dof(*general, samples=24, jit=False).q)


def test_single_calls_free_every_array_they_make() -> None:
    """The one-call kernels of ``armkit.ik`` / ``armkit.ik_all`` (``_single._nearest_first`` is uncounted too)."""
    import armkit
    from numba.core.runtime import _nrt_python as nrt

    for name in ("ur5", "puma560", "stanford"):
        arm = armkit.load(name)
        T = armkit.fk(arm, arm.random_q(6, rng=5))
        for t in T:
            armkit.ik(arm, t), armkit.ik_all(arm, t)
        nrt.memsys_enable_stats()
        try:
            before = _stats()
            got = [(armkit.ik(arm, t), armkit.ik_all(arm, t)) for t in T]
            made = _stats() - before
        finally:
            nrt.memsys_disable_stats()
        assert made[0] == made[1] and made[2] == made[3], name
        # the hand-written families' kernels make arrays (so the stats count here); the geometric family's one-call
        # kernel (the Stanford arm's) cuts its cores' work arrays from its work vector and makes none
        assert (made[0] == 0) if name == "stanford" else (made[0] > 0), name
        assert all(bool(one.success) and bool(every.success.any()) for one, every in got), name
