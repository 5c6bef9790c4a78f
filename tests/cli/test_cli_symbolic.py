"""The derive and singular commands."""

from __future__ import annotations

import importlib.util
import json

import numpy as np
import pytest
from typer.testing import CliRunner

import armkit
from armkit.cli import app

pytest.importorskip("sympy")
runner = CliRunner()


def test_derive_planar2_prints_shorthand_and_both_branches():
    res = runner.invoke(app, ["derive", "planar2"])
    assert res.exit_code == 0, res.output
    out = res.output
    assert "a1*c1 + a2*c12" in out and "c12 = cos(q1 + q2)" in out
    assert "elbow down" in out and "elbow up" in out and "Example: armkit" not in out


def test_derive_help_has_examples():
    for cmd in ("derive", "singular", "velocity", "traj"):
        res = runner.invoke(app, [cmd, "--help"])
        assert res.exit_code == 0 and "Example: armkit" in res.output


def test_derive_latex_and_python(tmp_path):
    res = runner.invoke(app, ["derive", "fighter", "--latex"])
    assert res.exit_code == 0 and "\\begin{document}" in res.output and "c_{23}" in res.output
    res = runner.invoke(app, ["derive", "fighter", "--python"])
    assert res.exit_code == 0
    path = tmp_path / "fighter_fk.py"
    path.write_text(res.output)
    spec = importlib.util.spec_from_file_location("fighter_fk", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    q = np.radians([30, 45, 60])
    np.testing.assert_allclose(mod.fk(q), armkit.fk(armkit.load("fighter"), q), atol=1e-9)
    res = runner.invoke(app, ["derive", "fighter", "--latex", "--python"])
    assert res.exit_code == 2


def test_derive_json_and_bad_robot():
    res = runner.invoke(app, ["derive", "planar2", "--json"])
    data = json.loads(res.output)
    assert data["T"][0][3] == "a1*c1 + a2*c12" and data["parameters"] == {"a1": 1.0, "a2": 0.5}
    res = runner.invoke(app, ["derive", "no_such_robot"])
    assert res.exit_code != 0


def test_singular_fighter_names_the_sets(tmp_path):
    res = runner.invoke(app, ["singular", "fighter"])
    assert res.exit_code == 0, res.output
    out = " ".join(res.output.split())
    assert "stretched" in out and "folded" in out and "yaw axis" in out
    res = runner.invoke(app, ["singular", "planar2", "--json", "-o", str(tmp_path / "m.png")])
    data = json.loads(res.output)
    assert data["determinant"] == "a1*a2*sin(q2)" and (tmp_path / "m.png").exists()


def test_singular_stops_at_its_budget_with_exit_2(monkeypatch):
    """`armkit singular so101` ran for more than 15 minutes without a word (a CAD export's offsets); with --budget
    (CPU seconds for the derivation and for the determinant) it stops and says why, in Korean too, exit 2; the
    budget's own rule is derive's (a number of seconds >= 0)."""
    monkeypatch.setenv("ARMKIT_CACHE_DIR", str(__import__("tempfile").mkdtemp()))
    res = runner.invoke(app, ["singular", "so101", "--budget", "1"])
    assert res.exit_code == 2, res.output
    assert "not factored within 1 s of CPU time" in res.output and "--budget" in res.output
    assert "Traceback" not in res.output
    res = runner.invoke(app, ["singular", "so101", "--budget", "1", "--lang", "ko"])
    assert res.exit_code == 2 and "인수분해하지 못했습니다" in res.output
    for bad in ("-1", "inf", "nan"):
        res = runner.invoke(app, ["singular", "planar2", "--budget", bad])
        assert res.exit_code == 2 and "--budget must be a number of seconds >= 0" in res.output, res.output
    res = runner.invoke(app, ["singular", "planar2", "--budget", "0"])          # 0: no limit
    assert res.exit_code == 0 and "= a1*a2*s2" in res.output, res.output
