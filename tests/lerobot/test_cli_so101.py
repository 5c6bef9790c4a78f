"""``armkit so101 pose``: servo readings through a LeRobot calibration file, exit codes, never a traceback."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import armkit
from armkit.cli import app

runner = CliRunner()
SAMPLE = str(Path(__file__).resolve().parents[2] / "examples" / "so101_calibration.json")
ENV = {"ARMKIT_LANG": "en", "COLUMNS": "200"}


def run(*args: str):
    return runner.invoke(app, ["so101", "pose", "--calibration", SAMPLE, *args], env=ENV)


def test_ticks_table_and_pose():
    res = run("--ticks", "2048", "2048", "2048", "2048", "2048", "2400")
    assert res.exit_code == 0, res.output
    for word in ("shoulder_pan", "wrist_roll", "gripper", "q (deg)", "end point", "T_base_link_gripper_frame_link"):
        assert word in res.output
    assert "0.703" in res.output                  # shoulder_pan: (2048 - 2040) * 360 / 4095 deg
    assert "open: 26.0 %" in res.output            # gripper: (2400 - 2031) / (3452 - 2031) * 100
    assert "warning" not in res.output


def test_json_matches_the_library():
    res = run("--degrees", "10", "-20", "30", "40", "0", "50", "--json")
    assert res.exit_code == 0, res.output
    data = json.loads(res.output)
    assert data["q_deg"] == pytest.approx({"shoulder_pan": 10, "shoulder_lift": -20, "elbow_flex": 30,
                                           "wrist_flex": 40, "wrist_roll": 0})
    assert data["gripper_range_0_100"] == pytest.approx(50.0)
    T = armkit.fk(armkit.load("so101"), np.radians([10, -20, 30, 40, 0]))
    assert np.allclose(data["pose"], T)
    assert data["warnings"] == []


def test_range_mode_and_zero_pose():
    res = run("--range-m100-100", "0", "0", "0", "0", "0", "--json")
    assert res.exit_code == 0, res.output
    data = json.loads(res.output)
    assert data["position"] == pytest.approx([0.3914, 0.0, 0.2265], abs=1e-4)


@pytest.mark.parametrize("args, message", [
    (["--ticks", "2048", "2048", "2048"], "has 6 motors"),
    (["--ticks", "2048", "2048", "2048", "2048", "5000"], "wrist_roll: reading 5000 is outside 0..4095"),
    (["--ticks", "-3", "2048", "2048", "2048", "2048"], "shoulder_pan: reading -3 is outside 0..4095"),
    (["--ticks", "2048", "2048", "x", "2048", "2048"], "is not a number"),
    (["2048", "2048", "2048", "2048", "2048"], "give the unit of the values"),
    (["--ticks", "--degrees", "1", "2", "3", "4", "5"], "give the unit of the values"),
    (["--degrees", "300", "0", "0", "0", "0"], "shoulder_pan: the degrees value would be tick"),
])
def test_bad_input_exits_2_with_one_line(args, message):
    res = run(*args)
    assert res.exit_code == 2, res.output
    assert message in res.output
    assert "Traceback" not in res.output
    assert res.exception is None or isinstance(res.exception, SystemExit)


def test_bad_file_exits_2(tmp_path):
    bad = tmp_path / "cal.json"
    bad.write_text('{"shoulder_pan": {"id": 1}}')
    res = runner.invoke(app, ["so101", "pose", "-c", str(bad), "--ticks", "1", "2", "3", "4", "5"], env=ENV)
    assert res.exit_code == 2 and "missing field 'drive_mode'" in res.output and "Traceback" not in res.output
    res = runner.invoke(app, ["so101", "pose", "-c", str(tmp_path / "no.json"), "--ticks", "1", "2", "3", "4", "5"],
                        env=ENV)
    assert res.exit_code == 2 and "not found" in res.output


def test_outside_calibrated_range_warns_and_still_answers():
    res = run("--ticks", "100", "2048", "2048", "2048", "2048")
    assert res.exit_code == 0, res.output
    assert res.output.count("outside the calibrated range") == 1
    assert "shoulder_pan at tick 100" in res.output and "wrap at 4096" in res.output
    assert "outside the URDF's joint limits: shoulder_pan -170.5" in res.output


def test_help_has_an_example():
    res = runner.invoke(app, ["so101", "pose", "--help"], env=ENV)
    assert res.exit_code == 0 and "Example: armkit so101 pose" in res.output
    res = runner.invoke(app, ["so101", "--help"], env=ENV)
    assert res.exit_code == 0 and "pose" in res.output


def test_korean(tmp_path):
    res = runner.invoke(app, ["so101", "pose", "--calibration", SAMPLE, "--lang", "ko", "--ticks", "2048", "2048",
                              "2048", "2048", "2048", "2400"], env=ENV)
    assert res.exit_code == 0, res.output
    res = runner.invoke(app, ["so101", "pose", "--calibration", SAMPLE, "--lang", "ko", "1", "2", "3", "4", "5"],
                        env=ENV)
    assert res.exit_code == 2


def test_korean_file_errors_and_range_warnings(tmp_path):
    """The calibration file's errors and the range warnings come from their templates, in Korean (issue 20)."""
    def ko(*args: str):
        return runner.invoke(app, ["so101", "pose", "--lang", "ko", *args], env=ENV)

    res = ko("--calibration", str(tmp_path / "missing.json"), "--ticks", "1", "2", "3", "4", "5")
    assert res.exit_code == 2 and "보정 파일" in res.output and "찾을 수 없습니다" in res.output
    assert "not found" not in res.output
    bad = tmp_path / "bad.json"
    bad.write_text('{"shoulder_pan": 3}')
    res = ko("--calibration", str(bad), "--ticks", "1", "2", "3", "4", "5")
    assert res.exit_code == 2 and "필드를 가진 객체여야 합니다" in res.output and "Traceback" not in res.output
    res = ko("--calibration", SAMPLE, "--ticks", "2048", "2048", "2048", "2048", "5000")
    assert res.exit_code == 2 and "5000이 STS3215의 위치 범위 0 ~ 4095를 벗어납니다" in res.output
    res = ko("--calibration", SAMPLE, "--ticks", "100", "2048", "2048", "2048", "2048")
    assert res.exit_code == 0 and "보정 범위 밖" in res.output and "4096에서 한 바퀴" in res.output
    assert "outside the calibrated range" not in res.output
    res = run("--ticks", "100", "2048", "2048", "2048", "2048")        # English stays as it was
    assert "outside the calibrated range of" in res.output and "did the reading wrap at 4096" in res.output
