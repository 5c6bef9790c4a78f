"""`armkit ik` for 7-joint arms (--sweep, --fixed) and a 6-joint URDF with every branch (issue 19), via CliRunner.

Every branch printed is put through :func:`armkit.fk` here and must reproduce the target pose to 1e-6.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

import armkit
from armkit.cli import app
from armkit.spatial import make_pose, rpy_to_rotation, rotation_to_rpy

runner = CliRunner()
PANDA_Q = np.array([0.3, -0.5, 0.2, -2.0, 0.4, 1.6, 0.7])


def run(*args: str, env: dict | None = None):
    return runner.invoke(app, ["ik", *args], env={"COLUMNS": "200", **(env or {})})


def words(robot, q) -> tuple[list[str], np.ndarray]:
    """The command-line words of the pose at ``q`` (full precision, rpy in deg) and the pose they mean."""
    T = armkit.fk(robot, q)
    p, rpy = T[:3, 3], np.degrees(rotation_to_rpy(T[:3, :3]))
    target = make_pose(rpy_to_rotation(rpy, degrees=True), p)
    return [*(repr(float(v)) for v in p), "--rpy", ",".join(repr(float(v)) for v in rpy), "--deg"], target


def assert_reproduce(robot, solutions, target):
    q = np.array([s["q_rad"] for s in solutions])
    T = armkit.fk(robot, q)
    assert np.max(np.abs(T - target)) <= 1e-6, np.max(np.abs(T - target))


@pytest.fixture(scope="module")
def panda():
    return armkit.load("panda")


def test_sweep_json_every_branch_reaches_the_target(panda):
    args, target = words(panda, PANDA_Q)
    res = run("panda", *args, "--all", "--sweep", "40", "--json")
    assert res.exit_code == 0, res.output
    data = json.loads(res.stdout)
    swept = data["swept"]
    assert swept["joint"] == "panda_joint6" and swept["values"] == 40
    assert swept["from_rad"] == pytest.approx(panda.lower[5]) and swept["to_rad"] == pytest.approx(panda.upper[5])
    assert data["solved"] and data["branches_found"] == len(data["solutions"]) >= 8
    assert_reproduce(panda, data["solutions"], target)
    values = np.linspace(panda.lower[5], panda.upper[5], 40)   # the sweep's values: evenly spaced, ends included
    held = np.array([s["q_rad"][5] for s in data["solutions"]])
    assert np.min(np.abs(held[:, None] - values[None, :]), axis=1).max() < 1e-12
    assert all(s["success"] for s in data["solutions"])


def test_all_on_a_7_joint_arm_sweeps_32_and_prints_a_table(panda):
    args, target = words(panda, PANDA_Q)
    res = run("panda", *args, "--all")
    assert res.exit_code == 0, res.output
    assert "swept panda_joint6" in res.stdout                    # the swept joint's column comes first
    assert "panda_joint6 swept over 32 values from -1.003 to 215 deg; branches found: " in " ".join(res.stdout.split())
    n = int(res.stdout.split("branches found: ")[1].split()[0].replace(",", ""))
    data = json.loads(run("panda", *args, "--all", "--json").stdout)
    assert n == data["branches_found"] > 0
    assert_reproduce(panda, data["solutions"], target)


def test_fixed_in_degrees_holds_the_joint_exactly(panda):
    args, target = words(panda, PANDA_Q)
    res = run("panda", *args, "--fixed", f"panda_joint7={math.degrees(PANDA_Q[6])!r}", "--json")
    assert res.exit_code == 0, res.output
    data = json.loads(res.stdout)
    assert data["swept"] is None and data["fixed_rad"] == {"panda_joint7": pytest.approx(PANDA_Q[6], abs=1e-15)}
    assert_reproduce(panda, data["solutions"], target)
    assert any(np.allclose(s["q_rad"], PANDA_Q, atol=1e-6) for s in data["solutions"])   # the q we started from


def test_no_branch_is_said_and_exits_1():
    res = run("panda", "2", "2", "2", "--rpy", "0,0,0", "--all")
    assert res.exit_code == 1
    assert "no branch found" in res.output and "Traceback" not in res.output


@pytest.mark.parametrize("extra, text", [
    (("--fixed", "panda_joint7"), "NAME=VALUE"),
    (("--fixed", "bogus=1"), "no joint named 'bogus'"),
    (("--fixed", "panda_joint7=abc"), "--fixed value"),
    (("--fixed", "panda_joint7=1", "--fixed", "panda_joint7=2"), "twice"),
    (("--sweep", "0"), "sweep must be an integer"),
    (("--sweep", "8", "--method", "lm"), "do not go with"),
])
def test_bad_input_exits_2_with_a_message(extra, text):
    res = run("panda", "0.3", "0.2", "0.5", "--rpy", "180,0,0", "--deg", *extra)
    assert res.exit_code == 2, res.output
    assert text in " ".join(res.output.split()) and "Traceback" not in res.output


def test_a_position_alone_cannot_be_swept():
    res = run("panda", "0.3", "0.2", "0.5", "--all")
    text = " ".join(res.output.split())
    assert res.exit_code == 2 and "sweep a joint for a pose" in text and "--fixed NAME=VALUE" in text


def test_korean(panda):
    args, _ = words(panda, PANDA_Q)
    res = runner.invoke(app, ["--lang", "ko", "ik", "panda", *args, "--sweep", "16"], env={"COLUMNS": "200"})
    assert res.exit_code == 0, res.output
    assert "찾은 해" in res.output and "훑은 관절 panda_joint6" in res.output


def test_kinova_urdf_lists_every_branch():
    from armkit.model.erd import robots_folder

    if robots_folder() is None:
        pytest.skip("example-robot-data is not installed")
    kinova = armkit.load("example-robot-data:kinova")
    args, target = words(kinova, np.array([0.3, 3.0, 1.5, 0.4, 2.0, 0.7]))
    res = run("example-robot-data:kinova", *args, "--all", "--json")
    assert res.exit_code == 0, res.output
    data = json.loads(res.stdout)
    ok = [s for s in data["solutions"] if s["success"]]
    assert len(ok) == 8                                        # a spherical wrist + two parallel axes: 8 branches here
    assert_reproduce(kinova, ok, target)
