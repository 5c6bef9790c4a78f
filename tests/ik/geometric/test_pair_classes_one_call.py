"""The one-call kernel's shortcut where some candidates are least-squares ones (issue 19, item 5).

Random arms of the closed-form classes with a meeting or a parallel pair have 4-6 branches of 8 on most targets: the
others are least-squares candidates (a position or a wrist out of reach). On a chain whose ideal form is the true
one, the kernel takes the shortcut past the check with the others where the check fails each least-squares
candidate (:func:`armkit.ik.geometric.solvers_check._apart`; where one passes, the check keeps it and the kernel
goes the long way: ``tests/ik/geometric/test_apart.py``). Either way the answer is the batched path's, to the bit,
and every branch is FK-checked.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from test_family import _random_arm   # same folder, on pytest's path

import armkit
from armkit.ik.analytic import closed_form

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))   # tests/ik: the one-call path against the batched one
from test_single_call import _assert_same, _both, compiled  # noqa: E402, F401 (the fixture: the Numba back end)

KINDS = ("spherical-wrist-meet", "spherical-wrist-parallel", "three-parallel-meet")


@pytest.mark.usefixtures("compiled")
@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_random_pair_arms_equal_the_batched_path(kind, seed):
    rng = np.random.default_rng(seed)
    robot = _random_arm(rng, kind)
    cf = closed_form(robot)
    if cf is None or cf.family != "geometric":
        pytest.skip("a degenerate draw")
    T = armkit.fk(robot, rng.uniform(-np.pi, np.pi, (40, 6)))
    fewer = 0
    for t in T:
        fast, slow = _both(lambda: armkit.ik_all(robot, t))
        _assert_same(fast, slow)
        fewer += int(fast.success.sum()) < fast.success.size
        ok = fast.success
        np.testing.assert_allclose(armkit.fk(robot, fast.q[ok]), np.broadcast_to(t, (int(ok.sum()), 4, 4)),
                                   atol=1e-9)
        _assert_same(*_both(lambda: armkit.ik(robot, t)))
    assert fewer > 0   # targets with least-squares candidates: the case this covers
