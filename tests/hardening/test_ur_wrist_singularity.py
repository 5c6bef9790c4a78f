"""Issue 10, item 6: the UR closed form solves targets at the exact wrist singularity (q5 = 0 or pi)."""

from __future__ import annotations

import numpy as np
import pytest

import armkit


@pytest.mark.parametrize("fixed", [{4: 0.0}, {4: np.pi}, {2: 0.0, 4: 0.0}, {4: 0.0, 3: 0.0}],
                         ids=["q5=0", "q5=pi", "q3=q5=0", "q4=q5=0"])
def test_ur5_wrist_singular_targets_are_solved(fixed):
    arm = armkit.load("ur5")
    q = arm.random_q(300, rng=11)
    for k, v in fixed.items():
        q[:, k] = v
    T = armkit.fk(arm, q)
    every = armkit.ik_all(arm, T)
    assert np.asarray(every.success).any(axis=-1).all()
    one = armkit.ik(arm, T)
    assert np.asarray(one.success).all()
    np.testing.assert_allclose(armkit.fk(arm, one.q), T, atol=1e-9)
    for k in range(5):                                 # single calls take the same route
        res = armkit.ik(arm, T[k], q0=np.zeros(6))
        assert bool(res.success)


def test_puma560_wrist_singular_targets_are_solved():
    arm = armkit.load("puma560")
    q = arm.random_q(300, rng=12)
    q[:, 4] = 0.0
    T = armkit.fk(arm, q)
    assert np.asarray(armkit.ik(arm, T).success).all()
