"""The interactive shell driven by scripts of lines (no terminal, no eval)."""

from __future__ import annotations

import io
import math
import re

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from rich.console import Console

import armkit
from armkit.cli.shell import EXIT_WORDS, Shell

END = re.compile(r"(?:end point|끝점) \([^)]*\)\s*│\s*([-\d.e+]+)\s*│\s*([-\d.e+]+)\s*│\s*([-\d.e+]+)")


def make(name="fighter", lang="en", **kw):
    return Shell(armkit.load(name), lang=lang, plot="none", console=Console(file=io.StringIO(), width=100), **kw)


def printed_end(out):
    m = END.findall(out.text)
    assert m, out.text
    return np.array([float(v) for v in m[-1]])


def test_club_report_syntax_and_short_forms_match_fk():
    sh = make()
    r = sh.robot
    out = sh.execute("theta1 = 30; theta2 = 45; theta3 = 60")
    assert out.status == "ok"
    np.testing.assert_allclose(printed_end(out), armkit.fk(r, np.radians([30, 45, 60]))[:3, 3], atol=1e-6)
    out = sh.execute("q 10 -20 35.5")
    np.testing.assert_allclose(printed_end(out), armkit.fk(r, np.radians([10, -20, 35.5]))[:3, 3], atol=1e-6)
    out = sh.execute("q1 = 0.5rad; shoulder = 15; elbow = 20deg")
    np.testing.assert_allclose(sh.q, [0.5, math.radians(15), math.radians(20)])
    np.testing.assert_allclose(printed_end(out), armkit.fk(r, sh.q)[:3, 3], atol=1e-6)
    sh.execute("units rad")
    sh.execute("q 0.1 0.2 0.3")
    np.testing.assert_allclose(sh.q, [0.1, 0.2, 0.3])


def test_goto_and_brackets_reach_the_target_and_branch_switches():
    sh = make()
    for line in ("goto 100 50 80", "[100, 50, 80]", "(100 50 80)"):
        out = sh.execute(line)
        assert out.status == "ok", out.text
        np.testing.assert_allclose(printed_end(out), [100, 50, 80], atol=1e-6)
        np.testing.assert_allclose(armkit.fk(sh.robot, sh.q)[:3, 3], [100, 50, 80], atol=1e-6)
    before = sh.q.copy()
    out = sh.execute("branch")
    assert out.status == "info" and "elbow-up" in out.text
    # (100, 50, 80): both elbow-down branches put the upper arm into the torso (the robot's own surroundings)
    other = "front/elbow-up" if sh.branch != "front/elbow-up" else "back/elbow-up"
    out = sh.execute(f"branch {other}")
    assert out.status == "ok" and sh.branch == other
    assert not np.allclose(sh.q, before)
    np.testing.assert_allclose(printed_end(out), [100, 50, 80], atol=1e-6)
    out = sh.execute("goto 300 0 0")                      # outside the 177.2 mm reach
    assert out.status == "error" and "177.2" in out.text
    np.testing.assert_allclose(armkit.fk(sh.robot, sh.q)[:3, 3], [100, 50, 80], atol=1e-6)


def test_mistakes_get_one_line_and_change_nothing():
    sh = make()
    sh.execute("q 10 20 30")
    q = sh.q.copy()
    for line in ("theta4 = 3", "yaw = 400", "q 1 2", "1000 50 80", "__import__('os').system('echo hi')",
                 "theta1 = 1e999", "goto 1 2", "branch nowhere", "units furlongs", "q nan 1 2",
                 "theta1 = 30; theta9 = 1", "exit; q 1 2 3"):
        out = sh.execute(line)
        assert out.status == "error", line
        assert len(out.text.strip().splitlines()) == 1, (line, out.text)
        np.testing.assert_array_equal(sh.q, q)
    assert sh.execute("theta2 = 90/0").status == "error" and sh.execute("theta2 = 2**9").status == "error"
    np.testing.assert_array_equal(sh.q, q)
    assert sh.execute("").status == "empty" and sh.execute("   # comment").status == "empty"


def test_korean_messages():
    sh = make(lang="ko")
    assert "관절" in sh.execute("wrist = 3").text
    assert "명령" in sh.execute("help").text
    sh.execute("lang en")
    assert "no joint named" in sh.execute("wrist = 3").text


def test_exit_words_and_eof_end_the_loop():
    for word in ("exit", "quit", "EXIT"):
        sh = make()
        assert sh.run(io.StringIO(f"q 1 2 3\n{word}\nq 4 5 6\n")) == 0
        np.testing.assert_allclose(sh.q, np.radians([1, 2, 3]))
    sh = make()
    assert sh.run(io.StringIO("q 1 2 3\n")) == 0            # EOF


def test_png_each_step(tmp_path):
    sh = Shell(armkit.load("planar2"), lang="en", plot="png", out_dir=tmp_path,
               console=Console(file=io.StringIO()))
    out = sh.execute("q 30 45")
    assert out.picture == tmp_path / "step_001.png" and out.picture.is_file()
    assert str(out.picture) in out.text
    assert sh.execute("goto 1.2 0.3").picture == tmp_path / "step_002.png"
    assert sh.execute("limits").picture is None


_TOKENS = st.sampled_from(["q", "theta1", "theta2", "theta3", "yaw", "=", ";", "[", "]", "(", ")", ",", "goto",
                           "branch", "units", "deg", "rad", "lang", "ko", "limits", "help", "home", "show", "1e308",
                           "-1e-308", "nan", "inf", "0", "30", "-45.5", ".5", "1e999", "\t", "°", "eval(", "'",
                           "front/elbow-up", "auto", "#", "\\", "\x00", "print"])
_LINE = st.one_of(st.text(max_size=40),
                  st.lists(_TOKENS, max_size=12).map(" ".join),
                  st.lists(st.one_of(_TOKENS, st.floats(allow_nan=True).map(repr)), max_size=8).map("".join))


def _is_exit(line: str) -> bool:
    return any(s.strip().lower() in EXIT_WORDS for s in line.split(";"))


_SEEN = []


@settings(max_examples=12, deadline=None, suppress_health_check=list(HealthCheck))
@given(st.lists(_LINE, min_size=100, max_size=100))
def test_a_thousand_garbage_lines_never_raise_never_exit(lines):
    """Hypothesis' buffer holds about 100 such lines per example; 12 examples feed the shell > 1,000 lines."""
    _SEEN.append(len(lines))
    sh = make()
    r = sh.robot
    for line in lines:
        if _is_exit(line):
            continue
        out = sh.execute(line)
        assert out.status in ("ok", "info", "error", "empty")
        assert np.all(r.within_limits(sh.q))
        if out.status == "ok":
            np.testing.assert_allclose(printed_end(out), armkit.fk(r, sh.q)[:3, 3], atol=1e-5)
    # after all that the shell still works (a garbage line may have switched to radians: "units rad")
    sh.execute("units deg")
    out = sh.execute("theta1 = 30; theta2 = 45; theta3 = 60")
    np.testing.assert_allclose(printed_end(out), [24.860765, 14.353369, 187.181226], atol=1e-5)
    assert sh.execute("quit").status == "exit"


def test_the_garbage_test_saw_a_thousand_lines():
    if not _SEEN:
        pytest.skip("runs after the garbage-line test")
    assert sum(_SEEN) >= 1000


def test_run_loop_survives_garbage_through_stdin():
    sh = make()
    script = "\n".join(["q 1 2 3", "}{", "goto 1e308 0 0", "branch", "q 10 20 30", "exit", "q 4 5 6"]) + "\n"
    assert sh.run(io.StringIO(script)) == 0
    np.testing.assert_allclose(sh.q, np.radians([10, 20, 30]))


# ---- issue 11: one end point per step, branch names, the yaw-is-free note, modes -------------------------------

def test_end_point_once_per_step_and_the_first_show_names_the_branch():
    sh = make()
    out = sh.execute("show")
    assert len(END.findall(out.text)) == 1
    assert "IK branch: front/elbow-down" in out.text and "IK branch: —" not in out.text
    shown = sh.branch
    out = sh.execute("home")                          # the same pose: the same name
    assert sh.branch == shown and f"IK branch: {shown}" in out.text
    out = sh.execute("theta1 = 30; theta2 = 45; theta3 = 60")
    assert len(END.findall(out.text)) == 1 and len(re.findall(r"end point", out.text)) == 1
    # the name show gives is the one goto gives for the same pose, and ik_all's for it
    res = armkit.ik_all(sh.robot, armkit.fk(sh.robot, sh.q)[:3, 3], q0=sh.q)
    ok = np.asarray(res.success) & np.all(np.abs(np.asarray(res.q) - sh.q) < 1e-6, axis=-1)
    assert sh.branch == str(np.asarray(res.branch)[int(np.argmax(ok))])


def test_goto_on_the_yaw_axis_prints_the_clis_note():
    sh = make()
    out = sh.execute("goto 0 0 213.2")
    assert out.status == "ok"
    assert "yaw is free" in out.text
    np.testing.assert_allclose(armkit.fk(sh.robot, sh.q)[:3, 3], [0, 0, 213.2], atol=1e-6)


def test_branch_angles_are_wrapped():
    sh = make()
    w = sh._wrapped(np.radians([214.4, -190.0, 540.0]))
    np.testing.assert_allclose(np.degrees(w), [-145.6, 170.0, 180.0], atol=1e-9)
    sh.execute("goto 100 50 80")
    out = sh.execute("branch")
    for v in re.findall(r"│\s+(-?\d+\.\d{4})\s", out.text):
        assert -180 < float(v) <= 180, out.text


def test_modes_ik_and_fk():
    sh = make()
    assert sh.mode == "ik"
    out = sh.execute("100 50 80")                     # ik: numbers alone are a target
    np.testing.assert_allclose(printed_end(out), [100, 50, 80], atol=1e-6)
    assert sh.execute("mode fk").status == "info" and sh.mode == "fk"
    out = sh.execute("30 45 60")                      # fk: numbers alone are joint values
    np.testing.assert_allclose(sh.q, np.radians([30, 45, 60]))
    np.testing.assert_allclose(printed_end(out), armkit.fk(sh.robot, sh.q)[:3, 3], atol=1e-6)
    assert sh.execute("30 45").status == "error" and sh.mode == "fk"
    assert sh.execute("mode sideways").status == "error"
    sh.execute("mode ik")
    assert sh.mode == "ik"
    fk_shell = make(mode="fk")
    fk_shell.execute("10 20 30")
    np.testing.assert_allclose(fk_shell.q, np.radians([10, 20, 30]))


def test_cli_shell_ik_and_fk_flags():
    from typer.testing import CliRunner

    from armkit.cli import app

    res = CliRunner().invoke(app, ["shell", "fighter", "--no-plot", "--fk", "--lang", "en"], input="10 20 30\nexit\n")
    assert res.exit_code == 0, res.output
    T = armkit.fk(armkit.load("fighter"), np.radians([10, 20, 30]))[:3, 3]
    assert f"{T[0]:.6f}" in res.output
    res = CliRunner().invoke(app, ["shell", "fighter", "--no-plot", "--ik", "--lang", "en"],
                             input="100 50 80\nexit\n")
    assert res.exit_code == 0 and "100.000000" in res.output and "80.000000" in res.output


@pytest.mark.parametrize("cols", [60, 80, 120])
def test_shell_tables_fit_narrow_terminals(cols):
    """Tables wider than the terminal come as one record per row: nothing cut, every number whole."""
    buf = io.StringIO()
    sh = Shell(armkit.load("fighter"), lang="en", plot="none", console=Console(file=buf, width=cols))
    sh.execute("goto 100 50 80")
    sh.execute("branch")
    text = buf.getvalue()
    assert "…" not in text
    assert all(len(line) <= cols for line in text.splitlines()), text
    for name in ("front/elbow-up", "front/elbow-down", "back/elbow-up", "back/elbow-down"):
        assert name in text
    res = armkit.ik_all(sh.robot, [100, 50, 80])
    for q in np.degrees(np.asarray(res.q)):
        for v in q:
            assert f"{v:.4f}" in text
    assert "IK branch: " in text
