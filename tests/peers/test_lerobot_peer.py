"""armkit.lerobot.RobotKinematics against LeRobot's own class (issue 20), where LeRobot is importable.

LeRobot is not one of armkit's extras (it brings torch, datasets and its own placo); this file
skips without it. ``make bench-so101`` runs it in ``.venv-placo`` (placo, then
``pip install --no-deps lerobot``: ``lerobot.model.kinematics`` imports only NumPy and placo, so
no torch is needed). Both classes are built on the same URDF (armkit's bundled
``so101_new_calib.urdf``) with LeRobot's arguments. LeRobot's ``inverse_kinematics`` takes one
placo step per call, so it is called again from its own answer (as a control loop does) until
it stops moving. From a start 2 deg (per joint) off a reachable pose, placo's first steps
sometimes overshoot far (tens of cm) and it settles elsewhere or on a joint limit: so the
agreement is checked where LeRobot's class converges (to 1e-6 m), and armkit must solve
every target, those included.
"""

from __future__ import annotations

import os

import numpy as np
import pytest

pytest.importorskip("placo")
lerobot_kinematics = pytest.importorskip("lerobot.model.kinematics")

import armkit  # noqa: E402
from armkit.lerobot import RobotKinematics  # noqa: E402
from armkit.model.files import BUNDLED_DIR  # noqa: E402

URDF = os.path.join(BUNDLED_DIR, "so101.urdf")
JOINTS = ["shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex", "wrist_roll", "gripper"]


@pytest.fixture(scope="module")
def pair():
    theirs = lerobot_kinematics.RobotKinematics(urdf_path=URDF, target_frame_name="gripper_frame_link",
                                                joint_names=JOINTS)
    ours = RobotKinematics(URDF, target_frame_name="gripper_frame_link", joint_names=JOINTS)
    return theirs, ours


def test_forward_kinematics_agree(pair):
    theirs, ours = pair
    arm = armkit.load("so101")
    for q in arm.random_q(50, rng=41):
        deg = np.append(np.degrees(q), 10.0)
        assert np.allclose(ours.forward_kinematics(deg), theirs.forward_kinematics(deg), atol=1e-9)


def test_inverse_kinematics_agree_on_reachable_targets(pair):
    theirs, ours = pair
    arm = armkit.load("so101")
    rng = np.random.default_rng(42)
    converged = 0
    for q in arm.random_q(40, rng=43):
        goal = np.append(np.degrees(q), 10.0)
        T = ours.forward_kinematics(goal)
        start = goal + np.append(rng.normal(0, 2.0, 5), 0.0)
        mine = ours.inverse_kinematics(start, T)
        assert ours.last_stage == "pose" and bool(ours.last_result.success)     # armkit: every target, whole pose
        p_mine = ours.forward_kinematics(mine)[:3, 3]
        assert np.linalg.norm(p_mine - T[:3, 3]) < 1e-6
        assert mine[5] == 10.0                                                  # the jaw carried through
        cur = start.copy()
        for _ in range(300):                                    # LeRobot's one step per call, called again
            nxt = np.asarray(theirs.inverse_kinematics(cur, T), dtype=float)
            if np.abs(nxt - cur).max() < 1e-9:
                break
            cur = nxt
        p_theirs = np.asarray(theirs.forward_kinematics(cur))[:3, 3]
        if np.linalg.norm(p_theirs - T[:3, 3]) < 1e-6:          # where LeRobot's class reaches the target
            converged += 1
            assert np.linalg.norm(p_mine - p_theirs) < 1e-6
            assert np.allclose(np.asarray(theirs.forward_kinematics(mine)), T, atol=1e-6)   # their FK of our joints
    assert converged >= 20                                      # most targets compared (34 of 40 when written)
