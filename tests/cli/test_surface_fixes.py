"""Issue 11's small surface fixes: the --deg hint, shell arithmetic and bare targets, IKResult.message as a
str, rotx(..., degrees=True), one end-point line per shell step, traj --output."""

from __future__ import annotations

import io
import math

import numpy as np
import pytest
from rich.console import Console
from typer.testing import CliRunner

import armkit
from armkit._arith import evaluate, looks_arithmetic
from armkit.cli import app
from armkit.cli.shell import Shell
from armkit.spatial import rotx, roty, rotz

runner = CliRunner()


def cli(*args: str):
    return runner.invoke(app, list(args), env={"COLUMNS": "200"})


# ---------------------------------------------------------------- --deg hint
def test_fk_in_radians_with_degree_values_suggests_deg():
    res = cli("fk", "fighter", "30", "45", "60")
    assert res.exit_code == 0
    assert "did you mean --deg?" in res.stderr and "30 45 60 read as degrees are inside the limits" in res.stderr
    strict = cli("fk", "fighter", "30", "45", "60", "--strict")
    assert strict.exit_code == 2 and "did you mean --deg?" in strict.stderr


def test_deg_hint_beyond_a_full_turn_even_inside_the_limits(tmp_path):
    # a continuous joint has no limit to break: values beyond 2 pi still get the hint
    res = cli("fk", "ur5", "7", "-8", "9", "10", "-11", "12")
    assert "did you mean --deg?" in res.stderr


@pytest.mark.parametrize("args", [("fighter", "30", "45", "60", "--deg"), ("fighter", "0.5", "1", "1"),
                                  ("fighter", "0", "0", "0")])
def test_no_deg_hint_for_plausible_values(args):
    res = cli("fk", *args)
    assert res.exit_code == 0 and "--deg" not in res.stderr


# ---------------------------------------------------------------- IKResult.message
def test_single_ik_message_is_a_str_batched_stays_an_array():
    r = armkit.load("fighter")
    for kw in ({}, {"method": "lm"}, {"method": "ccd"}, {"method": "fabrik"}):
        one = armkit.ik(r, [24.861, 14.353, 187.181], **kw)
        assert isinstance(one.message, str) and not isinstance(one.message, np.ndarray), kw   # a str (or a
        # Fielded: a str that keeps its template and fields for the Korean rendering), never a 0-d array
    far = armkit.ik(r, [2400.0, 0.0, 0.0])
    assert isinstance(far.message, str) and far.message.startswith("unreachable")
    batch = armkit.ik(r, [[24.861, 14.353, 187.181], [2400.0, 0.0, 0.0]])
    assert isinstance(batch.message, np.ndarray) and batch.message.shape == (2,)
    assert isinstance(batch[1].message, str) and batch[1].message == str(batch.message[1])
    every = armkit.ik_all(r, [24.861, 14.353, 187.181])
    assert isinstance(every.message, np.ndarray) and every.message.shape == (4,)


# ---------------------------------------------------------------- degrees=True
@pytest.mark.parametrize("rot", [rotx, roty, rotz])
def test_elementary_rotations_take_degrees(rot):
    np.testing.assert_allclose(rot(30, degrees=True), rot(math.pi / 6), atol=1e-15)
    np.testing.assert_allclose(rot([30, -90], degrees=True), rot(np.radians([30, -90])), atol=1e-15)
    np.testing.assert_allclose(rot(0.5), rot(math.degrees(0.5), degrees=True), atol=1e-15)


def test_rotx_by_hand():
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    np.testing.assert_allclose(rotx(30, degrees=True)[:3, :3], [[1, 0, 0], [0, c, -s], [0, s, c]], atol=1e-15)


# ---------------------------------------------------------------- arithmetic
@pytest.mark.parametrize("text, value", [("90/2", 45.0), ("45+15", 60.0), ("-30", -30.0), ("-(10 + 20) * 2", -60.0),
                                         ("pi/4", math.pi / 4), ("1e2/4", 25.0), ("2*-3", -6.0), ("((1))", 1.0)])
def test_arithmetic(text, value):
    assert looks_arithmetic(text)
    assert evaluate(text) == pytest.approx(value, abs=1e-15)


@pytest.mark.parametrize("text", ["", "1/0", "2**10", "1+", "(1", "1)", "__import__('os')", "abs(1)", "1e999",
                                  "9" * 300, "(" * 50 + "1" + ")" * 50, "1 2", "pi pi", "x"])
def test_arithmetic_refuses(text):
    with pytest.raises(ValueError):
        evaluate(text)


def shell(lang: str = "en") -> Shell:
    return Shell(armkit.load("fighter"), lang=lang, plot="none", console=Console(file=io.StringIO(), width=100))


def test_shell_takes_simple_arithmetic():
    sh = shell()
    assert sh.execute("theta2 = 90/2").status == "ok"
    assert sh.q[1] == pytest.approx(math.radians(45))
    assert sh.execute("theta1 = pi/4 rad; theta3 = (10 + 20) * 2 deg").status == "ok"
    np.testing.assert_allclose(sh.q, np.radians([45, 45, 60]))
    assert sh.execute("q 90/2 15+15 0").status == "ok"
    np.testing.assert_allclose(sh.q, np.radians([45, 30, 0]))
    before = sh.q.copy()
    for bad in ("theta2 = 90/0", "theta2 = 2**3", "theta2 = __import__('os')", "theta2 = (1"):
        assert sh.execute(bad).status == "error", bad
    np.testing.assert_array_equal(sh.q, before)


def test_bare_numbers_are_a_target():
    sh = shell()
    out = sh.execute("100 50 80")
    assert out.status == "ok"
    np.testing.assert_allclose(armkit.fk(sh.robot, sh.q)[:3, 3], [100, 50, 80], atol=1e-6)


@pytest.mark.parametrize("lang, label", [("en", "end point"), ("ko", "끝점")])
def test_end_point_printed_once_per_step(lang, label):
    sh = shell(lang)
    for line in ("theta1 = 30; theta2 = 45; theta3 = 60", "goto 100 50 80", "home", "show"):
        out = sh.execute(line)
        assert out.text.count(label) == 1, out.text
        assert "end point:" not in out.text


# ---------------------------------------------------------------- traj --output
def test_traj_takes_output_and_out(tmp_path):
    for flag in ("--output", "--out", "-o"):
        path = tmp_path / f"t{flag.strip('-')}.csv"
        res = cli("traj", "planar2", "--joint", "0,0", "1,1", flag, str(path))
        assert res.exit_code == 0, res.output
        assert path.is_file() and path.stat().st_size > 0


@pytest.mark.parametrize("robot,target", [("fighter", [100, 50, 80]), ("planar2", [1.0, 0.5])])
def test_branch_picture_legend_does_not_cover_the_axes(robot, target):
    """Issue 11: the IK-branch picture's legend sits below the plot, not on it."""
    import matplotlib.pyplot as plt

    from armkit.viz.arm import plot_arm

    r = armkit.load(robot)
    res = armkit.ik_all(r, target)
    tp = np.append(target, 0.0)[:3]
    fig = plot_arm(r, np.asarray(res.q), labels=[str(b) for b in res.branch], targets=[tp])
    fig.canvas.draw()
    ax = fig.axes[0]
    leg = ax.get_legend().get_window_extent()
    box = ax.get_window_extent()
    assert leg.y1 <= box.y0 + 1, (leg, box)            # entirely below the axes
    plt.close(fig)
