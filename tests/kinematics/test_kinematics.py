"""Forward kinematics and Jacobians against independent references.

References used here, none of them armkit's own output:
- the club's fighting-robot report: the fighter arm at (30, 45, 60) deg ends at (24.861, 14.353, 187.181) mm;
- P. Corke, "Robotics, Vision and Control" (2011), sec. 7.1: Puma 560 at qz = 0 has the tool at
  (0.4521, -0.1500, 0.4318) m with identity rotation, at qr = (0, 90, -90, 0, 0, 0) deg at
  (0.0203, -0.1500, 0.8636) m, identity rotation;
- Universal Robots' DH article: at q = 0 the UR5 tool sits at (a2 + a3, -(d4 + d6), d1 - d5), derived by hand below;
- planar arms by hand: x = L1 c1 + L2 c12 (+ L3 c123), y likewise;
- finite differences of FK for every Jacobian.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit import Joint, Robot
from armkit.spatial import rotx, rotz

BUNDLED = armkit.bundled_robots()


@pytest.fixture(params=["numba", "numpy"])
def backend(request):
    armkit.set_backend(request.param)
    yield request.param
    armkit.set_backend("auto")


def test_fighter_point_from_the_club_report_dh_table(backend):
    T = armkit.fk(armkit.load("fighter"), np.radians([30, 45, 60]))
    assert np.allclose(T[:3, 3], [24.861, 14.353, 187.181], atol=5e-4)


def test_fighter_by_hand(backend):
    q1, q2, q3 = 0.4, -0.3, 1.2
    r = 77.2 * math.cos(q2) + 100 * math.cos(q2 + q3)
    z = 36 + 77.2 * math.sin(q2) + 100 * math.sin(q2 + q3)
    T = armkit.fk(armkit.load("fighter"), [q1, q2, q3])
    assert np.allclose(T[:3, 3], [r * math.cos(q1), r * math.sin(q1), z], atol=1e-12)


def test_puma560_published_poses(backend):
    puma = armkit.load("puma560")
    T = armkit.fk(puma, np.zeros(6))
    assert np.allclose(T[:3, 3], [0.4521, -0.15005, 0.4318], atol=1e-12)
    assert np.allclose(T[:3, :3], np.eye(3), atol=1e-12)
    T = armkit.fk(puma, [0, np.pi / 2, -np.pi / 2, 0, 0, 0])
    assert np.allclose(T[:3, 3], [0.0203, -0.15005, 0.8636], atol=1e-12)
    assert np.allclose(T[:3, :3], np.eye(3), atol=1e-12)


def test_ur5_home_by_hand(backend):
    d1, a2, a3, d4, d5, d6 = 0.089159, -0.425, -0.39225, 0.10915, 0.09465, 0.0823
    T = armkit.fk(armkit.load("ur5"), np.zeros(6))
    assert np.allclose(T[:3, 3], [a2 + a3, -(d4 + d6), d1 - d5], atol=1e-12)
    assert np.allclose(T[:3, :3], rotx(np.pi / 2)[:3, :3], atol=1e-12)  # Rx(90) Rx(90) Rx(-90)


@given(st.floats(-3, 3), st.floats(-3, 3), st.floats(-3, 3))
def test_planar_arms_by_hand(q1, q2, q3):
    T = armkit.fk(armkit.load("planar2"), [q1, q2])
    assert np.allclose(T[:2, 3], [math.cos(q1) + 0.5 * math.cos(q1 + q2), math.sin(q1) + 0.5 * math.sin(q1 + q2)],
                       atol=1e-12)
    T = armkit.fk(armkit.load("planar3"), [q1, q2, q3])
    x = math.cos(q1) + 0.8 * math.cos(q1 + q2) + 0.3 * math.cos(q1 + q2 + q3)
    y = math.sin(q1) + 0.8 * math.sin(q1 + q2) + 0.3 * math.sin(q1 + q2 + q3)
    assert np.allclose(T[:3, 3], [x, y, 0], atol=1e-12)
    assert math.isclose(math.atan2(T[1, 0], T[0, 0]), math.remainder(q1 + q2 + q3, 2 * math.pi), abs_tol=1e-9)


def test_stanford_prismatic_joint_moves_along_its_axis(backend):
    st_arm = armkit.load("stanford")
    q = np.radians([20, 30, 0, 10, 40, 50])
    q[2] = 0.5
    F = armkit.fk_frames(st_arm, q)
    z2 = F[2, :3, 2]  # standard DH: joint 3 slides along z of frame 2
    dq = np.zeros(6)
    dq[2] = 0.1
    shift = armkit.fk(st_arm, q + dq)[:3, 3] - armkit.fk(st_arm, q)[:3, 3]
    assert np.allclose(shift, 0.1 * z2, atol=1e-12)
    J = armkit.jacobian(st_arm, q)
    assert np.allclose(J[:3, 2], z2, atol=1e-12) and np.allclose(J[3:, 2], 0, atol=0)


def _standard_to_modified(robot: Robot) -> Robot:
    """Rewrite a standard-DH arm in modified DH, derived by hand:
    Rz(t1)Tz(d1)[Tx(a1)Rx(al1)][Rz(t2)Tz(d2)][Tx(a2)Rx(al2)]... and Tx, Rx commute, so modified row i
    takes (alpha, a) of standard row i-1, and the last (a_n, alpha_n) moves into the tool."""
    js = robot.joints
    rows = []
    for i, j in enumerate(js):
        prev_a, prev_alpha = (js[i - 1].a, js[i - 1].alpha) if i else (0.0, 0.0)
        rows.append(Joint(j.kind, j.theta, j.d, prev_a, prev_alpha, j.lower, j.upper, j.name))
    c, s = math.cos(js[-1].alpha), math.sin(js[-1].alpha)
    last = np.array([[1, 0, 0, js[-1].a], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])
    return Robot(rows, "modified", robot.name + "_mdh", robot.unit, robot.base, last @ robot.tool)


@pytest.mark.parametrize("name", [n for n in BUNDLED if armkit.load(n).convention == "standard"])
def test_standard_and_modified_dh_of_the_same_arm_agree(name):
    std = armkit.load(name)
    mdh = _standard_to_modified(std)
    q = std.random_q(50, rng=7)
    assert np.allclose(armkit.fk(std, q), armkit.fk(mdh, q), atol=1e-12 * max(1.0, std.reach))


def test_planar3_modified_equals_hand_written_standard_table():
    std = Robot([Joint(a=1.0), Joint(a=0.8), Joint()], "standard", tool=np.array(
        [[1, 0, 0, 0.3], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]]))
    q = std.random_q(20, rng=2)
    assert np.allclose(armkit.fk(std, q), armkit.fk(armkit.load("planar3"), q), atol=1e-12)


def random_pose(draw) -> np.ndarray:
    """A random rigid transform: two rotations and a translation."""
    T = rotz(draw(st.floats(-np.pi, np.pi))) @ rotx(draw(st.floats(-np.pi, np.pi)))   # 4x4 rotations
    T[:3, 3] = [draw(st.floats(-2.0, 2.0)) for _ in range(3)]
    return T


@st.composite
def random_arm(draw, max_joints: int = 7, placed: bool = False):
    """1 to ``max_joints`` joints, revolute or prismatic, either DH convention; ``placed``: a random base and tool."""
    n = draw(st.integers(1, max_joints))
    joints = []
    for i in range(n):
        kind = draw(st.sampled_from(["revolute", "revolute", "prismatic"]))
        vals = [draw(st.floats(-1.5, 1.5)) for _ in range(4)]
        lo, hi = (-3.0, 3.0) if kind == "revolute" else (-0.5, 0.5)
        joints.append(Joint(kind, vals[0], vals[1], vals[2], vals[3], lo, hi))
    conv = draw(st.sampled_from(["standard", "modified"]))
    if placed:
        return Robot(joints, conv, base=random_pose(draw), tool=random_pose(draw))
    return Robot(joints, conv)


@given(random_arm(), st.integers(0, 2**32 - 1))
@settings(max_examples=40)
def test_random_standard_arm_equals_its_modified_rewrite(arm, seed):
    if arm.convention != "standard":
        return
    q = arm.random_q(4, rng=seed)
    assert np.allclose(armkit.fk(arm, q), armkit.fk(_standard_to_modified(arm), q), atol=1e-11)


def _fd_jacobian(robot: Robot, q: np.ndarray, h: float = 1e-6) -> np.ndarray:
    J = np.zeros((6, robot.n))
    for i in range(robot.n):
        dq = np.zeros(robot.n)
        dq[i] = h
        Tp, Tm = armkit.fk(robot, q + dq), armkit.fk(robot, q - dq)
        J[:3, i] = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
        dR = (Tp[:3, :3] - Tm[:3, :3]) / (2 * h) @ armkit.fk(robot, q)[:3, :3].T  # = [w]x
        J[3:, i] = [dR[2, 1], dR[0, 2], dR[1, 0]]
    return J


@pytest.mark.parametrize("name", BUNDLED)
@given(seed=st.integers(0, 2**32 - 1))
@settings(max_examples=15)
def test_jacobian_matches_finite_differences(name, seed):
    robot = armkit.load(name)
    q = robot.random_q(rng=seed)
    J = armkit.jacobian(robot, q)
    scale = max(1.0, robot.reach)
    assert np.allclose(J, _fd_jacobian(robot, q), atol=1e-6 * scale)


@given(random_arm(), st.integers(0, 2**32 - 1))
@settings(max_examples=30)
def test_jacobian_of_random_arms_matches_finite_differences(arm, seed):
    q = arm.random_q(rng=seed)
    assert np.allclose(armkit.jacobian(arm, q), _fd_jacobian(arm, q), atol=1e-6)


@pytest.mark.parametrize("name", BUNDLED)
def test_tool_frame_jacobian_is_rotated_base_jacobian(name):
    robot = armkit.load(name)
    q = robot.random_q(rng=5)
    R = armkit.fk(robot, q)[:3, :3]
    Jb, Jt = armkit.jacobian(robot, q, "base"), armkit.jacobian(robot, q, "tool")
    assert np.allclose(Jt[:3], R.T @ Jb[:3], atol=1e-12) and np.allclose(Jt[3:], R.T @ Jb[3:], atol=1e-12)


@pytest.mark.parametrize("name", BUNDLED)
def test_batched_equals_looped(name, backend):
    robot = armkit.load(name)
    q = robot.random_q(24, rng=11).reshape(2, 3, 4, robot.n)
    T, F, J = armkit.fk(robot, q), armkit.fk_frames(robot, q), armkit.jacobian(robot, q)
    assert T.shape == (2, 3, 4, 4, 4) and F.shape == (2, 3, 4, robot.n + 1, 4, 4) and J.shape == (2, 3, 4, 6, robot.n)
    for idx in np.ndindex(2, 3, 4):
        assert np.array_equal(T[idx], armkit.fk(robot, q[idx]))
        assert np.array_equal(F[idx], armkit.fk_frames(robot, q[idx]))
        assert np.allclose(J[idx], armkit.jacobian(robot, q[idx]), atol=1e-15)
    assert np.allclose(F[..., -1, :, :], T, atol=1e-15)  # the last frame carries the tool


def test_backends_agree():
    for name in BUNDLED:
        robot = armkit.load(name)
        q = robot.random_q(10000, rng=1)
        armkit.set_backend("numpy")
        ref = armkit.fk(robot, q), armkit.jacobian(robot, q[:50], "tool"), armkit.fk_frames(robot, q[:50])
        armkit.set_backend("auto")
        got = armkit.fk(robot, q), armkit.jacobian(robot, q[:50], "tool"), armkit.fk_frames(robot, q[:50])
        for a, b in zip(ref, got):
            assert np.allclose(a, b, atol=1e-13 * max(1, robot.reach))


def test_frames_of_fighter_are_the_report_joint_positions():
    F = armkit.fk_frames(armkit.load("fighter"), np.radians([0, 90, 0]))
    assert np.allclose(F[:, :3, 3], [[0, 0, 0], [0, 0, 36], [0, 0, 113.2], [0, 0, 213.2]], atol=1e-12)


def test_manipulability_two_link_by_hand():
    arm = armkit.load("planar2")
    q = np.array([[0.3, 0.2], [1.0, -2.0], [0.0, 0.0]])
    assert np.allclose(armkit.manipulability(arm, q), 1.0 * 0.5 * np.abs(np.sin(q[:, 1])), atol=1e-12)
    assert armkit.is_singular(arm, [0.5, 0.0]) and armkit.is_singular(arm, [0.5, np.pi])
    assert not armkit.is_singular(arm, [0.5, 1.0])
    assert armkit.condition_number(arm, [0.5, 0.0]) > 1e12
    # mm and m arms give the same numbers: the fighter in m vs mm
    fighter = armkit.load("fighter")
    in_m = Robot([Joint(d=0.036, alpha=np.pi / 2), Joint(a=0.0772), Joint(a=0.1)])
    q = np.radians([10, 40, 60])
    assert np.isclose(armkit.manipulability(fighter, q), armkit.manipulability(in_m, q), rtol=1e-12)


def test_fighter_singularities():
    arm = armkit.load("fighter")
    assert armkit.is_singular(arm, np.radians([10, 40, 0]))        # stretched
    assert armkit.is_singular(arm, np.radians([10, 40, 180]))       # folded
    q_axis = np.array([0.3, math.pi / 2, 0.0])                      # straight up: end point on the yaw axis
    assert armkit.is_singular(arm, q_axis)
    assert not armkit.is_singular(arm, np.radians([10, 40, 60]))


def test_puma_wrist_singularity():
    puma = armkit.load("puma560")
    assert armkit.is_singular(puma, [0.1, 0.5, -0.3, 0.7, 0.0, 0.2])
    assert not armkit.is_singular(puma, [0.1, 0.5, -0.3, 0.7, 0.4, 0.2])


def test_bad_frame_argument():
    with pytest.raises(armkit.ArmkitError, match="frame must be 'base' or 'tool'"):
        armkit.jacobian(armkit.load("ur5"), np.zeros(6), frame="world")  # type: ignore[arg-type]


def test_without_numba_the_numpy_kernels_answer():
    """Numba not importable: fk, ik and the pose check fall back to NumPy instead of failing."""
    import os
    import subprocess
    import sys

    code = ("import sys; sys.modules['numba'] = None\n"
            "import armkit, numpy as np\n"
            "arm = armkit.load('ur5'); T = armkit.fk(arm, arm.random_q(2000, rng=0))\n"
            "assert armkit.get_backend() == 'numpy'\n"
            "assert armkit.ik_all(arm, T).success.any() and armkit.ik(arm, T[0], method='lm').success\n"
            "print('ok')\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600,
                         env={**os.environ, "ARMKIT_JIT": "background"})
    assert out.returncode == 0 and out.stdout.strip() == "ok", out.stderr[-2000:]
