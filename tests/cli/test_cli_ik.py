"""`armkit ik` through Typer's test runner: tables, notes, JSON and exit codes 0 / 1 / 2."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

import armkit
from armkit.cli import app

runner = CliRunner()


def run(*args: str):
    return runner.invoke(app, ["ik", *args])


def test_help_has_an_example():
    res = run("--help")
    assert res.exit_code == 0 and "Example: armkit ik" in res.output


def test_fighter_lists_all_four_branches():
    res = run("fighter", "24.861", "14.353", "187.181")
    assert res.exit_code == 0, res.output
    for label in ("front/elbow-up", "front/elbow-down", "back/elbow-up", "back/elbow-down"):
        assert label in res.output
    assert "29.9991" in res.output and "44.9998" in res.output     # (30, 45, 60) deg up to the rounded target
    assert "4 of 4 branches" in res.output


def test_a_scara_lists_both_branches_of_a_pose_and_of_a_position_and_a_ur5_needs_the_turn():
    res = run("cobra600", "0.4", "0.2", "0.25", "--rpy", "180", "0", "30", "--deg", "--all")
    assert res.exit_code == 0, res.output
    # the elbow by the law of cosines (a1 = 0.325 m, a2 = 0.275 m): both signs of acos((x² + y² - a1² - a2²) / 2 a1 a2)
    elbow = math.degrees(math.acos((0.4**2 + 0.2**2 - 0.325**2 - 0.275**2) / (2 * 0.325 * 0.275)))
    assert "2 of 2 branches" in res.output and f"{elbow:.4f}" in res.output and f"-{elbow:.4f}" in res.output
    res = run("cobra600", "0.4", "0.2", "0.25", "--all")   # a position: the wrist never moves the point, held at q0
    assert res.exit_code == 0 and "2 of 2 branches" in res.output and "wrist held at the start q0" in res.output
    assert f"{elbow:.4f}" in res.output and f"-{elbow:.4f}" in res.output
    res = run("ur5", "0.4", "0.2", "0.25", "--all")        # five joints move the point: the closed form needs the turn
    assert res.exit_code == 2 and "is for a pose" in res.output and "--rpy" in res.output


def test_fighter_on_the_yaw_axis_explains_the_free_yaw():
    res = run("fighter", "0", "0", "213.2")
    assert res.exit_code == 0
    assert "any yaw angle works" in res.output and "fully stretched" in res.output


def test_fighter_out_of_reach_exits_1_with_the_distances():
    res = run("fighter", "500", "0", "0")
    assert res.exit_code == 1
    assert "unreachable" in res.output and "177.2 mm (outer)" in res.output and "22.8 mm (inner)" in res.output


def test_planar2_one_branch_and_negative_numbers():
    res = run("planar2", "1.2", "0.3", "--branch", "elbow-up")
    assert res.exit_code == 0 and "elbow-up" in res.output and "elbow-down" not in res.output
    q2 = -math.degrees(math.acos(0.28))                              # law of cosines by hand
    assert f"{q2:.4f}" in res.output
    res = run("planar2", "-1.2", "-0.3")
    assert res.exit_code == 0 and "2 of 2 branches" in res.output


def test_planar3_with_phi_in_degrees():
    res = run("planar3", "1.0", "0.5", "--phi", "30", "--deg", "--json")
    assert res.exit_code == 0
    data = json.loads(res.output)
    assert data["solved"] and len(data["solutions"]) == 2
    r = armkit.load("planar3")
    for sol in data["solutions"]:
        T = armkit.fk(r, sol["q_rad"])
        assert np.allclose(T[:2, 3], [1.0, 0.5], atol=1e-12)
        assert math.isclose(math.atan2(T[1, 0], T[0, 0]), math.radians(30), abs_tol=1e-12)


def test_json_of_a_pose_target_matches_fk():
    res = run("ur5", "0.3", "-0.2", "0.4", "--rpy", "180", "-90", "0", "--deg", "--json")
    assert res.exit_code == 0
    data = json.loads(res.output)
    assert data["method"] == "closed form (ur)" and len(data["solutions"]) == 8
    target = np.array(data["target"])
    for sol in data["solutions"]:
        assert sol["success"]
        assert np.allclose(armkit.fk(armkit.load("ur5"), sol["q_rad"]), target, atol=1e-12)


def test_quaternion_target():
    res = run("puma560", "0.5", "0.2", "0.1", "--quat", "1", "0", "0", "0", "--json")
    assert res.exit_code in (0, 1)
    data = json.loads(res.output)
    R = np.array(data["target"])[:3, :3]
    assert np.allclose(R, np.diag([1.0, -1.0, -1.0]))               # 180 deg about x


def test_numeric_method_with_seed():
    res = run("panda", "0.4", "0.1", "0.5", "--rpy", "180", "0", "0", "--deg", "--method", "lm", "--seed", "3",
              "--json")
    assert res.exit_code == 0, res.output
    data = json.loads(res.output)
    sol = data["solutions"][0]
    assert data["method"] == "lm" and sol["success"]
    T = armkit.fk(armkit.load("panda"), sol["q_rad"])
    assert np.allclose(T[:3, 3], [0.4, 0.1, 0.5], atol=1e-9)
    assert np.allclose(T[:3, :3], np.diag([1.0, -1.0, -1.0]), atol=1e-9)


def test_ccd_trace_prints_the_iterations():
    res = run("planar3", "1.0", "0.5", "--method", "ccd", "--trace")
    assert res.exit_code == 0, res.output
    assert "iteration" in res.output and "error" in res.output


@pytest.mark.parametrize("args, message", [
    (("planar2", "1.2", "0.3", "--branch", "sideways"), "valid branches: elbow-down, elbow-up"),
    (("fighter", "1", "2"), "planar arms"),
    (("fighter", "1"), "got 1 number"),
    (("fighter", "1", "x", "3"), "'x' is not a number"),
    (("ur5", "0.3", "0.2", "0.4", "--rpy", "0", "0", "0", "--quat", "0", "0", "0", "1"), "not both"),
    (("fighter", "10", "20", "30", "--method", "magic"), "--method must be one of"),
    (("fighter", "10", "20", "30", "--all", "--method", "lm"), "--all lists the closed-form branches"),
    (("panda", "0.4", "0.1", "0.5", "--all"), "sweep a joint for a pose"),   # 7 joints: --all sweeps (issue 19)
    (("planar2", "1.0", "0.2", "--phi", "10"), "cannot also choose the end angle"),
    (("nosuchrobot", "1", "2", "3"), "unknown robot"),
])
def test_bad_input_exits_2(args, message):
    res = run(*args)
    assert res.exit_code == 2, res.output
    assert message in res.output


def test_info_names_the_closed_form_of_a_position_with_the_wrist_held():
    res = runner.invoke(app, ["info", "puma560"])
    assert res.exit_code == 0
    text = " ".join(res.output.split())
    assert "a position alone: closed form (yaw-pitch-pitch) with wrist_roll, wrist_bend, wrist_swivel held at q0" in text
    assert "up to 4 solutions" in text
    data = json.loads(runner.invoke(app, ["info", "cobra600", "--json"]).output)
    assert data["position_held"] == {"held": ["wrist"], "family": "geometric-prismatic", "max_solutions": 2}
    assert json.loads(runner.invoke(app, ["info", "ur5", "--json"]).output)["position_held"] is None
    assert "a position alone" not in runner.invoke(app, ["info", "ur5"]).output


def test_a_position_with_fixed_joints_on_the_command_line():
    """The UR5 with its wrist held: the four shoulder/elbow branches, each reaching the point (FK of the printed q)."""
    res = run("ur5", "0.3", "0.2", "0.25", "--fixed", "wrist_1=0", "--fixed", "wrist_2=0", "--fixed", "wrist_3=0",
              "--json")
    assert res.exit_code == 0, res.output
    data = json.loads(res.output)
    assert data["branches_found"] == 4
    ur5 = armkit.load("ur5")
    for row in data["solutions"]:
        assert row["q_rad"][3:] == [0.0, 0.0, 0.0]
        assert np.allclose(armkit.fk(ur5, np.array(row["q_rad"]))[:3, 3], [0.3, 0.2, 0.25], atol=1e-12)
    res = run("ur5", "0.3", "0.2", "0.25", "--fixed", "wrist_3=0")
    assert res.exit_code == 2 and "without a closed form for a position" in " ".join(res.output.split())


def test_a_position_on_a_seven_joint_arm_with_all_names_the_options_of_the_command_line():
    res = run("panda", "0.4", "0.1", "0.5", "--all")
    text = " ".join(res.output.split())
    assert res.exit_code == 2 and "--fixed NAME=VALUE" in text and "--method lm" in text and "fixed=" not in text
    res = run("panda", "0.4", "0.1", "0.5", "--fixed", "panda_joint3=0", "--fixed", "panda_joint5=0", "--fixed",
              "panda_joint6=90", "--fixed", "panda_joint7=0", "--deg", "--json")
    assert res.exit_code == 0, res.output
    panda = armkit.load("panda")
    rows = json.loads(res.output)["solutions"]
    assert rows and all(np.allclose(armkit.fk(panda, np.array(r["q_rad"]))[:3, 3], [0.4, 0.1, 0.5], atol=1e-12)
                        for r in rows)
