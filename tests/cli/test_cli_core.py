"""The core commands through Typer's test runner: output, JSON and exit codes."""

from __future__ import annotations

import json

import numpy as np
import pytest
from typer.testing import CliRunner

import armkit
from armkit.cli import app

runner = CliRunner()


def run(*args: str):
    return runner.invoke(app, list(args))


def test_help_shows_an_example():
    for cmd in ("robots", "info", "fk", "jacobian"):
        res = run(cmd, "--help")
        assert res.exit_code == 0
        assert "Example: armkit" in res.output


def test_robots_table_and_json():
    res = run("robots")
    assert res.exit_code == 0 and "fighter" in res.output and "puma560" in res.output
    rows = json.loads(run("robots", "--json").stdout)
    by_name = {r["name"]: r for r in rows}
    assert by_name["stanford"]["joints"] == "RRPRRR" and by_name["panda"]["convention"] == "modified"
    assert by_name["fighter"]["unit"] == "mm"


def test_info_fighter_shows_dh_in_degrees():
    res = run("info", "fighter")
    assert res.exit_code == 0
    assert "77.2" in res.output and "90" in res.output and "standard DH" in res.output


def test_fk_fighter_prints_seed_point():
    res = run("fk", "fighter", "30", "45", "60", "--deg")
    assert res.exit_code == 0
    assert "(24.861, 14.353, 187.181) mm" in res.output


def test_fk_json_matches_library():
    res = run("fk", "puma560", "0", "0.78", "3.14", "0", "0.78", "0", "--json")
    assert res.exit_code == 0
    data = json.loads(res.stdout)
    q = [0, 0.78, 3.14, 0, 0.78, 0]
    assert np.allclose(data["pose"], armkit.fk(armkit.load("puma560"), q), atol=1e-12)
    assert len(data["frames"]) == 7


def test_jacobian_with_negative_numbers_and_tool_frame():
    res = run("jacobian", "ur5", "0.1", "-1", "1", "0", "0.5", "0", "--frame", "tool", "--json")
    assert res.exit_code == 0, res.output
    data = json.loads(res.stdout)
    ur5 = armkit.load("ur5")
    assert np.allclose(data["jacobian"], armkit.jacobian(ur5, [0.1, -1, 1, 0, 0.5, 0], "tool"), atol=1e-12)


def test_user_robot_file(tmp_path):
    path = tmp_path / "my_arm.toml"
    armkit.save(armkit.load("fighter"), path)
    res = run("fk", str(path), "30", "45", "60", "--deg")
    assert res.exit_code == 0 and "(24.861, 14.353, 187.181) mm" in res.output


@pytest.mark.parametrize("args, message", [
    (("fk", "fighter", "1", "2"), "has 3 joints"),
    (("fk", "fighter", "1", "x", "2"), "'x' is not a number"),
    (("fk", "fighter", "1", "nan", "2"), "not a finite number"),
    (("fk", "fightr", "1", "2", "3"), "bundled robots are: cobra600, fighter"),
    (("jacobian", "ur5", "0", "0", "0", "0", "0", "0", "--frame", "world"), "--frame must be 'base' or 'tool'"),
    (("fk", "fighter", "0", "0", "270", "--deg", "--strict"), "elbow = 270.000 deg outside"),
])
def test_bad_input_exits_2_with_message(args, message):
    res = run(*args)
    assert res.exit_code == 2
    assert message in res.output
    assert "Traceback" not in res.output


def test_limit_is_a_warning_without_strict():
    res = run("fk", "fighter", "0", "0", "270", "--deg")
    assert res.exit_code == 0
    assert "warning" in res.output and "elbow = 270.000 deg outside [-180.000, 180.000] deg" in res.output


def test_malformed_file_reports_file_line_field(tmp_path):
    import subprocess
    import sys

    bad = tmp_path / "bad.toml"
    bad.write_text('name = "b"\n\n[[joints]]\na = "long"\n')
    proc = subprocess.run([sys.executable, "-c", "from armkit.cli import main; main()", "fk", str(bad), "0"],
                          capture_output=True, text=True)
    assert proc.returncode == 2
    assert "bad.toml:4: joints[1].a: must be a finite number" in proc.stderr
    assert "Traceback" not in proc.stderr
