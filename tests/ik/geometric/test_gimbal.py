"""Three revolute axes through one point (class ``3R-spherical``, the ``geometric-gimbal`` family: a camera gimbal,
a spherical wrist on its own) get both branches of an orientation; and over random chains of every kind, the class
line and the solvers agree: ``armkit info`` says "closed form" (or a search) exactly where ``ik_all`` has a solver,
and "degenerate" only where the joints cannot move the tool in every direction (or only by a hair: the classifier
draws the line at 1e-4 of the arm's size, the test checks 1e-2).

References: the Z-Y-X (yaw, pitch, roll) Euler angles of a rotation and their second solution, written here from
the matrix entries; finite differences of FK for the Jacobian's rank; FK of the robot for random gimbals.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import armkit
from armkit import Joint, Robot
from armkit.ik.analytic import closed_form
from armkit.ik.geometric.classify import classify

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "kinematics"))
from test_kinematics import _fd_jacobian as numeric_jacobian  # noqa: E402  (central differences of FK)

HALF = math.pi / 2


def _gimbal(tool_xyz=(0.1, 0.0, 0.0)) -> Robot:
    tool = np.eye(4)
    tool[:3, 3] = tool_xyz
    return Robot([Joint("revolute", axis=(0, 0, 1), name="yaw"), Joint("revolute", axis=(0, 1, 0), name="pitch"),
                  Joint("revolute", axis=(1, 0, 0), name="roll")], "urdf", tool=tool, name="gimbal")


def _same(a: np.ndarray, b: np.ndarray, tol: float) -> bool:
    return bool(np.abs(np.angle(np.exp(1j * (np.asarray(a) - b)))).max() <= tol)


def test_a_yaw_pitch_roll_gimbal_by_hand():
    """R = Rz(a) Ry(b) Rx(c): a = atan2(R10, R00), b = asin(-R20), c = atan2(R21, R22), and (a + pi, pi - b, c + pi)
    gives the same matrix."""
    arm = _gimbal()
    assert classify(arm).name == "3R-spherical" and closed_form(arm).family == "geometric-gimbal"
    for rotvec in Rotation.random(12, random_state=4).as_rotvec():
        T = np.eye(4)
        T[:3, :3] = Rotation.from_rotvec(rotvec).as_matrix()
        T[:3, 3] = T[:3, :3] @ np.array([0.1, 0.0, 0.0])          # where that rotation puts the camera's point
        R = T[:3, :3]
        a, b, c = math.atan2(R[1, 0], R[0, 0]), math.asin(-R[2, 0]), math.atan2(R[2, 1], R[2, 2])
        res = armkit.ik_all(arm, T)
        found = res.q[np.asarray(res.success)]
        assert len(found) == 2
        for hand in ([a, b, c], [a + math.pi, math.pi - b, c + math.pi]):
            assert any(_same(x, hand, 1e-9) for x in found), (found, hand)


def test_a_position_the_rotation_does_not_give_is_unreachable_with_its_distance():
    arm = _gimbal()
    T = armkit.fk(arm, np.array([0.3, -0.5, 1.2]))
    T[:3, 3] += (0.03, 0.0, 0.04)
    res = armkit.ik_all(arm, T)
    assert not np.asarray(res.success).any() and set(res.reason) == {"unreachable"}
    np.testing.assert_allclose(res.position_error, 0.05, atol=1e-12)


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_random_gimbals_every_branch_reaches_the_pose(convention):
    g = np.random.default_rng(7)
    for t in range(25):
        rows = g.uniform(-0.5, 0.5, (3, 4))
        # the three axes meet in one point: standard DH a1 = a2 = d2 = 0 (rows 1, 2); modified DH a_1 = a_2 = 0
        # (on rows 2 and 3) and d2 = 0 (row 2); columns: theta, d, a, alpha
        zero = [(0, 2), (1, 1), (1, 2)] if convention == "standard" else [(1, 2), (1, 1), (2, 2)]
        for i, j in zero:
            rows[i, j] = 0.0
        twist = (0, 1) if convention == "standard" else (1, 2)
        rows[twist, 3] = g.uniform(0.3, 2.8, 2)
        tool = np.eye(4)
        tool[:3, 3] = g.uniform(-0.2, 0.2, 3)
        arm = Robot([Joint("revolute", *row) for row in rows], convention, tool=tool, name="gimbal")
        assert closed_form(arm).family == "geometric-gimbal"
        q = arm.random_q(rng=t)
        T = armkit.fk(arm, q)
        res = armkit.ik_all(arm, T, enforce_limits=False)
        ok = np.asarray(res.success)
        assert ok.any() and np.abs(armkit.fk(arm, res.q[ok]) - T).max() <= 1e-9
        assert any(_same(x, q, 1e-6) for x in res.q[ok])


# ---------------------------------------------------------------- the class line and the solvers agree
def _fd_ranks(robot: Robot, q: np.ndarray) -> tuple[int, int]:
    """Ranks of the tool's full (6, n) and position (3, n) Jacobians by central differences of FK."""
    J = numeric_jacobian(robot, q)
    J[:3] /= max(float(robot.reach), 1e-9)          # lengths in units of the arm's size: columns of about 1

    def rank(M):       # directions the tool moves in by at least 1 % of the arm's size per rad (or per length)
        s = np.linalg.svd(M, compute_uv=False)
        return int((s > 1e-2 * max(s[0], 1.0)).sum())
    return rank(J), rank(J[:3])


def _length(draw, top: float) -> float:
    """0, or a length of 0.05 to ``top`` either way: the structure (which axes meet, which are parallel) is what
    this law is about, not where a classifier's tolerance draws the line for a link of 1e-8."""
    if draw(st.booleans()):
        return 0.0
    return draw(st.sampled_from([1.0, -1.0])) * draw(st.floats(0.05, top))


@st.composite
def chains(draw):
    """1 to 6 joints (some prismatic), random DH rows of either convention with twists of 0 or ±90 deg and zero
    lengths mixed in, so that axes meet and lie parallel often."""
    n = draw(st.integers(1, 6))
    joints = []
    for _ in range(n):
        kind = draw(st.sampled_from(["revolute"] * 5 + ["prismatic"]))
        theta = draw(st.sampled_from([0.0, draw(st.floats(-1.5, 1.5))]))
        d, a = _length(draw, 0.5), _length(draw, 0.5)
        alpha = draw(st.sampled_from([0.0, HALF, -HALF, draw(st.sampled_from([1.0, -1.0])) * draw(st.floats(0.2, 1.4))]))
        joints.append(Joint(kind, theta, d, a, alpha, -3.0, 3.0))
    tool = np.eye(4)
    tool[:3, 3] = [_length(draw, 0.2) for _ in range(3)]
    return Robot(joints, draw(st.sampled_from(["standard", "modified"])), tool=tool, name="chain")


def _in_mm(arm: Robot) -> Robot:
    """The same arm with every length 1000 times larger (written in mm instead of m)."""
    joints = [Joint(j.kind, j.theta, 1000 * j.d, 1000 * j.a, j.alpha, *((1000 * j.lower, 1000 * j.upper)
                    if j.is_prismatic else (j.lower, j.upper))) for j in arm.joints]
    tool = arm.tool.copy()
    tool[:3, 3] *= 1000
    return Robot(joints, arm.convention, tool=tool, name=arm.name, unit="mm")


@settings(max_examples=150, deadline=None)
@given(arm=chains())
def test_the_class_line_and_the_solvers_agree(arm):
    cls = classify(arm)
    assert classify(_in_mm(arm)).name == cls.name            # the unit decides nothing
    claimed = cls.solver in ("closed form", "1-D search", "2-D search")
    assert claimed == (closed_form(arm) is not None), (cls.name, cls.solver, closed_form(arm))
    if cls.degenerate:
        full, position = _fd_ranks(arm, arm.random_q(rng=1))
        assert full < min(arm.n, 6) or position < min(arm.n, 3), (cls.name, full, position)
