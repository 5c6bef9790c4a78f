"""Issue 10, item 8: a 2R arm whose axes are antiparallel (alpha = 180 deg) has its closed form too."""

from __future__ import annotations

import math

import numpy as np
import pytest

import armkit
from armkit.ik.analytic import closed_form
from armkit.model import Joint, Robot


@pytest.mark.parametrize("tool", [None, [[1, 0, 0, 0.2], [0, 1, 0, 0.1], [0, 0, 1, 0.05], [0, 0, 0, 1]]])
@pytest.mark.parametrize("alpha", [math.pi, -math.pi])
def test_antiparallel_2r_closed_form(tool, alpha):
    arm = Robot([Joint(a=1.0, alpha=alpha), Joint(a=0.5)], name="anti", tool=tool)
    assert closed_form(arm) is not None and closed_form(arm).family == "planar-2r"
    q = arm.random_q(300, rng=5)
    p = armkit.fk(arm, q)[:, :3, 3]
    every = armkit.ik_all(arm, p)
    assert np.asarray(every.success).all()
    np.testing.assert_allclose(armkit.fk(arm, every.q)[..., :3, 3], np.repeat(p[:, None], 2, axis=1), atol=1e-9)
    one = armkit.ik(arm, p, q0=q)
    np.testing.assert_allclose(np.asarray(one.q), q, atol=1e-7)     # the branch nearest q0 is q itself


def test_planar_target_off_the_plane_says_so():
    res = armkit.ik(armkit.load("planar2"), [1.0, 2.0, 3.0])
    assert not bool(res.success)
    assert "3 m off the arm's plane" in str(res.message)
    res = armkit.ik(armkit.load("planar2"), [1.0, 2.0, 0.0])
    assert "off the arm's plane" not in str(res.message)
