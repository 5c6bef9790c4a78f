"""``with_axes_reversed``: the same arm with some joints turning the other way.

The law: with joint k reversed, ``fk(new, q')`` equals ``fk(robot, q)`` where ``q'`` negates the reversed entries
(the geometry is the same; only the sign of the joint variable changes), and the limits follow the sign:
``[-upper, -lower]``. Random DH arms (standard and modified, with prismatic joints) and real files.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit.errors import ShapeError
from armkit.model.axes import joint_axes, with_axes_reversed
from armkit.model.robot import Joint, Robot


@st.composite
def arm_and_flips(draw):
    n = draw(st.integers(1, 7))
    joints = []
    for _ in range(n):
        kind = draw(st.sampled_from(["revolute", "revolute", "prismatic"]))
        theta, d, a, alpha = (draw(st.floats(-1.5, 1.5)) for _ in range(4))
        lo = draw(st.floats(-3.0, -0.1))
        hi = draw(st.floats(0.2, 3.0))
        joints.append(Joint(kind, theta, d, a, alpha, lo, hi))
    robot = Robot(joints, draw(st.sampled_from(["standard", "modified"])))
    flips = draw(st.sets(st.integers(0, n - 1), min_size=1))
    return robot, sorted(flips)


@given(arm_and_flips(), st.integers(0, 2**32 - 1))
@settings(max_examples=60, deadline=None)
def test_same_pose_with_the_reversed_joint_values_negated(case, seed):
    robot, flips = case
    new = with_axes_reversed(robot, flips)
    sign = np.ones(robot.n)
    sign[flips] = -1.0
    q = robot.random_q(5, rng=seed)
    assert np.allclose(armkit.fk(new, q * sign), armkit.fk(robot, q), atol=1e-11)
    # the limits follow the sign, the other joints keep theirs
    assert np.array_equal(np.where(sign < 0, -robot.upper, robot.lower), new.lower)
    assert np.array_equal(np.where(sign < 0, -robot.lower, robot.upper), new.upper)
    # the axes are the same lines, pointing the other way where reversed
    p0, d0 = joint_axes(robot)
    p1, d1 = joint_axes(new)
    assert np.allclose(p0, p1, atol=1e-12)
    assert np.allclose(d1, d0 * sign[:, None], atol=1e-12)


def test_urdf_arm_and_bad_index():
    ur5 = armkit.load("ur5")
    new = with_axes_reversed(ur5, [0, 3])
    q = np.array([0.3, -1.0, 0.5, 0.2, 1.1, -0.4])
    assert np.allclose(armkit.fk(new, q * [-1, 1, 1, -1, 1, 1]), armkit.fk(ur5, q), atol=1e-12)
    assert new.name == "ur5-flipped" and new.joint_names == ur5.joint_names
    with pytest.raises(ShapeError, match="numbered from 0 to 5"):
        with_axes_reversed(ur5, [6])
