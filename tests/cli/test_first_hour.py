"""The first hour of a new user (issue 22): names that resolve, paths that say "file not found", ``--version``,
clean ``--help``, numbers without noise, and ``convert --convention``."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import armkit
from armkit.cli import app
from armkit.cli.common import count, fixed
from armkit.model import erd

runner = CliRunner()
MY_ARM = Path(__file__).resolve().parents[2] / "examples" / "my_arm.toml"
needs_erd = pytest.mark.skipif(erd.robots_folder() is None, reason="example-robot-data is not installed (test extra)")


def run(*args: str):
    return runner.invoke(app, list(args))


# ------------------------------------------------------------------ README: names, paths, --version
def test_version():
    res = run("--version")
    assert res.exit_code == 0 and res.output.strip() == f"armkit {armkit.__version__}"


def test_my_arm_example_matches_the_hand_check():
    arm = armkit.load(MY_ARM)
    assert (arm.unit, arm.n, arm.joint_types) == ("cm", 3, "RRR")
    assert np.allclose(armkit.fk(arm, [0, 0, 0])[:3, 3], [50, 0, 12])   # its comment's hand check
    res = run("fk", str(MY_ARM), "10", "20", "30", "--deg")
    assert res.exit_code == 0 and "(38.961, 6.870, 39.702) cm" in res.output   # what the README says


@pytest.mark.parametrize("name", ["no/such/arm.toml", "my_arm.toml", "ur5_robot.urdf", "arm.xml", "./fighter"])
def test_a_missing_path_says_file_not_found(name):
    with pytest.raises(armkit.RobotFileNotFoundError, match="file not found"):
        armkit.load(name)
    with pytest.raises(armkit.UnknownRobotError):       # still an unknown robot for `except UnknownRobotError`
        armkit.load(Path(name))
    res = run("fk", name, "0", "0", "0")
    assert res.exit_code == 2 and f"{name}: file not found" in res.output and "unknown robot" not in res.output
    ko = run("fk", name, "0", "0", "0", "--lang", "ko")
    assert ko.exit_code == 2 and "파일을 찾을 수 없습니다" in ko.output


def test_a_name_that_is_not_a_path_still_lists_the_bundled_robots():
    res = run("fk", "fightr", "0", "0", "0")
    assert res.exit_code == 2 and "unknown robot 'fightr'" in res.output and "fighter" in res.output


@needs_erd
def test_example_robot_data_names_load_with_their_tip():
    ur5 = armkit.load("example-robot-data:ur5")
    by_path = armkit.load(erd.robots_folder() / erd.ROBOTS["ur5"][0], tip="tool0")
    q = ur5.random_q(5, rng=2)
    assert np.allclose(armkit.fk(ur5, q), armkit.fk(by_path, q), atol=1e-12)
    other_tip = armkit.load("example-robot-data:ur5", tip="wrist_3_link")    # tip= overrides the default
    wrist = armkit.load(erd.robots_folder() / erd.ROBOTS["ur5"][0], tip="wrist_3_link")
    assert np.allclose(armkit.fk(other_tip, q), armkit.fk(wrist, q), atol=1e-12)
    assert not np.allclose(armkit.fk(other_tip, q), armkit.fk(ur5, q), atol=1e-6)
    same = armkit.load("example-robot-data:ur_description/urdf/ur5_robot.urdf", tip="tool0")
    assert np.allclose(armkit.fk(same, q), armkit.fk(ur5, q), atol=1e-12)


@needs_erd
@pytest.mark.parametrize("name", sorted(erd.ROBOTS))
def test_every_named_example_robot_data_arm_loads(name):
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")       # no mesh or joint warning for a named arm
        arm = armkit.load(f"example-robot-data:{name}")
    assert arm.n >= 5 and arm.joint_types == "R" * arm.n


@needs_erd
def test_example_robot_data_on_the_command_line():
    res = run("ik", "example-robot-data:ur5", "0.4", "0.1", "0.3", "--rpy", "180", "0", "0", "--deg")
    assert res.exit_code == 0 and "8 of 8 branches" in res.output
    res = run("info", "example-robot-data:ur6")
    assert res.exit_code == 2 and "known arms:" in res.output and "ur5" in res.output
    res = run("info", "example-robot-data:ur_description/urdf/nothing.urdf")
    assert res.exit_code == 2 and "file not found" in res.output


def test_example_robot_data_missing_names_the_extra(monkeypatch):
    monkeypatch.setattr(erd, "robots_folder", lambda: None)
    with pytest.raises(armkit.MissingExtraError, match=r"pip install 'armkit\[robots\]'"):
        armkit.load("example-robot-data:ur5")
    res = run("info", "example-robot-data:ur5")
    assert res.exit_code == 2 and "armkit[robots]" in res.output and "Traceback" not in res.output
    ko = run("info", "example-robot-data:ur5", "--lang", "ko")
    assert ko.exit_code == 2 and "추가 기능이 필요합니다" in ko.output and "armkit[robots]" in ko.output


def test_the_robots_extra_exists():
    import sys

    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover
        import tomli as tomllib
    meta = tomllib.loads((Path(__file__).resolve().parents[2] / "pyproject.toml").read_text())["project"]
    assert any("example-robot-data" in req for req in meta["optional-dependencies"]["robots"])


# ------------------------------------------------------------------ clean --help
def _commands():
    from typer.main import get_command

    out = []

    def walk(command, path):
        subs = getattr(command, "commands", None)
        if subs:
            for name, sub in subs.items():
                walk(sub, path + [name])
        else:
            out.append((path, command))

    walk(get_command(app), [])
    return out


@pytest.mark.parametrize("path, takes_robot", [(p, any(x.name == "robot" for x in c.params)) for p, c in _commands()],
                         ids=[" ".join(p) for p, _ in _commands()])
def test_help_has_no_typer_metavars_and_lists_base_tip(path, takes_robot):
    res = runner.invoke(app, path + ["--help"], env={"COLUMNS": "200"})
    assert res.exit_code == 0, res.output
    assert not re.search(r"<(bool|str|int|float|path|list\[)", res.output), res.output
    if takes_robot:
        assert "--base" in res.output and "--tip" in res.output and "LINK" in res.output


def test_top_level_help_is_clean():
    res = runner.invoke(app, ["--help"], env={"COLUMNS": "120"})
    assert res.exit_code == 0 and "--version" in res.output and "<bool>" not in res.output


def test_base_and_tip_listed_in_help_still_work_anywhere_on_the_line():
    a = run("fk", "so101", "0", "0", "0", "0", "0", "--tip", "gripper_frame_link", "--json")
    b = run("--tip", "gripper_frame_link", "fk", "so101", "0", "0", "0", "0", "0", "--json")
    assert a.exit_code == b.exit_code == 0 and a.stdout == b.stdout


# ------------------------------------------------------------------ numbers: no noise, counts with separators
def test_fixed_never_prints_minus_zero():
    assert fixed(-0.0) == fixed(-1e-17) == fixed(-0.0004) == "0.000"
    assert fixed(-1e-17, 6, " ") == " 0.000000" and fixed(-0.5, 6, " ") == "-0.500000"
    assert count(1_000_000) == "1,000,000" and count(999) == "999"


def test_fk_output_has_no_negative_zero():
    res = run("fk", str(MY_ARM), "0", "0", "0", "--deg")   # rpy (90, -0, 0) and a -0 in T before
    assert res.exit_code == 0 and not re.search(r"-0\.0+(?!\d*[1-9])\b", res.output), res.output
    res = run("info", str(MY_ARM))
    assert res.exit_code == 0 and not re.search(r"-0\.0+(?!\d*[1-9])\b", res.output), res.output


def test_velocity_shows_no_rounding_noise():
    res = runner.invoke(app, ["velocity", "planar2", "30", "45", "--deg", "--ee-vel", "0.1", "0"],
                        env={"COLUMNS": "200"})
    assert res.exit_code == 0 and "achieved: (0.1, 0)," in res.output    # was (0.1, 1.24991e-17)


@needs_erd
def test_dh_table_of_a_urdf_shows_no_rounding_noise():
    res = runner.invoke(app, ["info", "example-robot-data:ur5", "--dh"], env={"COLUMNS": "200"})
    assert res.exit_code == 0
    assert not re.search(r"\d[eE]-\d", res.output), res.output      # was "q2* -2.80553e-10"
    assert "q2* " not in res.output.replace("q2* │", "")


def test_reach_summary_counts_have_separators(tmp_path):
    pytest.importorskip("zarr")
    store = tmp_path / "p2.zarr"
    built = run("reach", "build", "planar2", "-o", str(store), "--samples", "20000", "--workers", "1")
    assert built.exit_code == 0, built.output
    shown = runner.invoke(app, ["reach", "show", str(store)], env={"COLUMNS": "200"})
    assert shown.exit_code == 0 and "20,000" in shown.output


# ------------------------------------------------------------------ convert --convention
def test_convert_writes_the_convention_asked_for(tmp_path):
    out = tmp_path / "fighter_craig.toml"
    res = run("convert", "fighter", str(out), "--convention", "modified")
    assert res.exit_code == 0, res.output
    craig, fighter = armkit.load(out), armkit.load("fighter")
    assert craig.convention == "modified"
    q = fighter.random_q(20, rng=4)
    assert np.allclose(armkit.fk(craig, q), armkit.fk(fighter, q), atol=1e-9)
    back = tmp_path / "back.toml"
    assert run("convert", str(out), str(back), "--convention", "standard").exit_code == 0
    assert armkit.load(back).convention == "standard"
    assert np.allclose(armkit.fk(armkit.load(back), q), armkit.fk(fighter, q), atol=1e-9)


def test_convert_keeps_the_robot_convention_by_default(tmp_path):
    for name, convention in (("planar3", "modified"), ("fighter", "standard"), ("so101", "standard")):
        out = tmp_path / f"{name}.toml"
        assert run("convert", name, str(out)).exit_code == 0
        assert armkit.load(out).convention == convention


def test_convert_refuses_a_convention_for_urdf(tmp_path):
    res = run("convert", "fighter", str(tmp_path / "f.urdf"), "--convention", "modified")
    assert res.exit_code == 2 and "a URDF file has no DH table" in res.output
    assert not (tmp_path / "f.urdf").exists()
