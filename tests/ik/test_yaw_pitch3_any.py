"""Every arm that ``classify`` calls ``4R-yaw-three-parallel`` or ``5R-yaw-three-parallel-roll`` ("closed form, up to
4 solutions") gets its closed form (the yaw-pitch3 family), whatever its tool frame and DH convention; a yaw axis
that is not perpendicular to the pitch axes is no such class.

References: a four-joint DH arm without a tool frame by hand (its x axis points along the last link, so its
pitch is ``q2 + q3 + q4`` in front of the yaw axis, and the tool point is the planar three-link sum turned by
``q1``), and for random arms FK of the robot and the configuration the target came from.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import armkit
from armkit import Joint, Robot
from armkit.ik.analytic import closed_form
from armkit.ik.analytic.yaw_pitch3 import YawPitch3, pitch_of
from armkit.ik.geometric.classify import classify

HALF = math.pi / 2


def _row(draw, alpha=None):
    theta, d, a, al = (draw(st.floats(-0.5, 0.5)) for _ in range(4))
    return [theta, d, a, al if alpha is None else alpha]


@st.composite
def yaw_pitch3_arms(draw):
    """Yaw, three parallel pitch joints (links of 0.2 to 0.5) and for five joints a roll, in either convention,
    with offsets and a random tool frame (sometimes none)."""
    n = draw(st.sampled_from([4, 5]))
    convention = draw(st.sampled_from(["standard", "modified"]))
    sign = draw(st.sampled_from([HALF, -HALF]))
    roll = draw(st.sampled_from([HALF, -HALF]))
    rows = [_row(draw) for _ in range(n)]
    first = 0 if convention == "standard" else 1          # the row that holds the twist after joint k
    rows[first][3] = sign
    rows[first + 1][3] = rows[first + 2][3] = 0.0
    if n == 5:
        rows[first + 3][3] = roll
    for k in (first + 1, first + 2):                      # the two pitch links (a of the rows after the twist)
        rows[k][2] = draw(st.floats(0.2, 0.5))
    tool = np.eye(4)
    if draw(st.booleans()):
        tool[:3, :3] = Rotation.from_rotvec([draw(st.floats(-3.0, 3.0)) for _ in range(3)]).as_matrix()
    tool[:3, 3] = [draw(st.floats(-0.1, 0.1)) for _ in range(3)]
    return Robot([Joint("revolute", *row) for row in rows], convention, tool=tool, name="arm")


@settings(max_examples=60, deadline=None)
@given(arm=yaw_pitch3_arms(), seed=st.integers(0, 2**31 - 1))
def test_the_class_and_the_solver_agree_and_the_start_is_among_the_branches(arm, seed):
    cls = classify(arm)
    assert cls.name == f"{arm.n}R-yaw-three-parallel{'-roll' if arm.n == 5 else ''}" and cls.solver == "closed form"
    assert isinstance(closed_form(arm), YawPitch3)
    q = arm.random_q(rng=seed)
    T = armkit.fk(arm, q)
    res = armkit.ik_all(arm, T[:3, 3], pitch=float(pitch_of(arm, q)), q0=q, enforce_limits=False)
    ok = np.asarray(res.success)
    ends = armkit.fk(arm, res.q[ok])[:, :3, 3]
    assert ok.any() and np.abs(ends - T[:3, 3]).max() <= 1e-9
    d = np.abs(np.angle(np.exp(1j * (res.q[ok] - q))))[:, :4]      # the roll keeps q0's value
    assert (d.max(axis=1) <= 1e-6).any(), (res.q, q)


def test_four_joints_without_a_tool_frame_by_hand():
    """Standard DH (q1, 0.1, 0, 90 deg), (q2, 0, 0.3, 0), (q3, 0, 0.25, 0), (q4, 0, 0.1, 0): the tool's z axis is the
    last pitch axis, so the approach is its x axis along the last link, at q2 + q3 + q4 above the horizontal; the
    tool point is (X cos q1, X sin q1, 0.1 + Y) with X, Y the planar three-link sums."""
    arm = Robot([Joint("revolute", d=0.1, alpha=HALF), Joint("revolute", a=0.3), Joint("revolute", a=0.25),
                 Joint("revolute", a=0.1)], name="arm4")
    assert classify(arm).name == "4R-yaw-three-parallel" and isinstance(closed_form(arm), YawPitch3)
    g = np.random.default_rng(3)
    for _ in range(10):
        q1, q2, q3, q4 = g.uniform(-1.0, 1.0), g.uniform(0.1, 0.9), g.uniform(-0.6, 0.3), g.uniform(-0.6, 0.6)
        X = 0.3 * math.cos(q2) + 0.25 * math.cos(q2 + q3) + 0.1 * math.cos(q2 + q3 + q4)
        Y = 0.3 * math.sin(q2) + 0.25 * math.sin(q2 + q3) + 0.1 * math.sin(q2 + q3 + q4)
        p = np.array([X * math.cos(q1), X * math.sin(q1), 0.1 + Y])
        np.testing.assert_allclose(armkit.fk(arm, [q1, q2, q3, q4])[:3, 3], p, atol=1e-12)
        assert math.isclose(float(pitch_of(arm, np.array([q1, q2, q3, q4]))), q2 + q3 + q4, abs_tol=1e-12)
        res = armkit.ik_all(arm, p, pitch=q2 + q3 + q4, enforce_limits=False)
        found = res.q[np.asarray(res.success)]
        assert (np.abs(found - [q1, q2, q3, q4]).max(axis=1) <= 1e-9).any(), found


def test_a_yaw_axis_at_another_angle_is_not_the_class():
    arm = Robot([Joint("revolute", d=0.1, alpha=1.2), Joint("revolute", a=0.3), Joint("revolute", a=0.25),
                 Joint("revolute", a=0.1)], name="skew")
    assert classify(arm).name == "4R-general" and classify(arm).solver == "numeric" and closed_form(arm) is None
