"""Issue 22, items 3 and 4: one vector rule, one set of branch names, messages that wrap at the terminal's width,
the closed-form IK as text and LaTeX (a fragment too), Craig's column order, numeric A_i, frames labelled {0}..{n}.

References are independent of the code under test: DH link matrices written out here from the textbooks'
formulas (Spong's standard, Craig's modified), FK of a 2R/yaw-pitch-pitch arm by hand, and the solver's own
answers compared with the printed equations evaluated by SymPy.
"""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest
from typer.testing import CliRunner

import armkit
from armkit.cli import app
from armkit.cli.common import join_vector_words

runner = CliRunner()


def run(*args: str, columns: str | None = "200"):
    return runner.invoke(app, list(args), env={"COLUMNS": columns, "ARMKIT_LANG": "en"})


def out_json(*args: str) -> dict:
    res = run(*args)
    assert res.exit_code in (0, 1), res.output
    return json.loads(res.stdout)


# ------------------------------------------------------------------ 1. one vector rule
@pytest.mark.parametrize("spelling", [["180", "0", "0"], ["180,0,0"], ["180, 0, 0"], ["180 0 0"]])
def test_rpy_is_read_the_same_in_every_spelling(spelling):
    base = out_json("ik", "puma560", "0.4", "0.1", "0.5", "--rpy", "180,0,0", "--deg", "--json")
    got = out_json("ik", "puma560", "0.4", "0.1", "0.5", "--rpy", *spelling, "--deg", "--json")
    assert got["solutions"] == base["solutions"]
    R = np.array(armkit.fk(armkit.load("puma560"), base["solutions"][0]["q_rad"]))[:3, :3]
    assert np.allclose(R, np.diag([1.0, -1.0, -1.0]), atol=1e-9)          # roll 180 deg by hand: diag(1, -1, -1)


def test_rpy_before_the_target_and_with_equals_sign():
    a = out_json("ik", "puma560", "--rpy", "180", "0", "0", "0.4", "0.1", "0.5", "--deg", "--json")
    b = out_json("ik", "puma560", "0.4", "0.1", "0.5", "--rpy=180,0,0", "--deg", "--json")
    assert a["solutions"] == b["solutions"] and a["target"] == b["target"]


@pytest.mark.parametrize("args", [
    ("ik", "so101", "0.25", "0", "0.1", "--direction", "{v}", "--json"),
    ("plot", "fighter", "--all-branches", "{v}", "-o", "{tmp}/b.png"),
])
def test_other_vector_options_take_both_spellings(args, tmp_path):
    vec = ("1", "0", "-1") if "--direction" in args else ("100", "50", "80")
    spaced = [w for a in args for w in (vec if a == "{v}" else [a.replace("{tmp}", str(tmp_path))])]
    commas = [",".join(vec) if a == "{v}" else a.replace("{tmp}", str(tmp_path)) for a in args]
    a, b = run(*spaced), run(*commas)
    assert a.exit_code == b.exit_code and a.exit_code in (0, 1), a.output
    assert a.stdout == b.stdout


def test_workspace_box_takes_both_spellings():
    common = ("workspace", "planar2", "--samples", "2000", "--json")
    a = out_json(*common, "--box", "0.5", "0.5", "-1", "2", "2", "1")
    b = out_json(*common, "--box", "0.5,0.5,-1,2,2,1")
    assert a == b and a["excluded"] > 0


@pytest.mark.parametrize("args, what", [(("ik", "puma560", "0.4", "0.1", "0.5", "--rpy", "180", "0"), "--rpy"),
                                        (("ik", "puma560", "0.4", "0.1", "0.5", "--quat", "0,0,1"), "--quat"),
                                        (("plot", "fighter", "--all-branches", "1,x,2"), "--all-branches")])
def test_a_wrong_vector_is_one_line_and_exit_2(args, what):
    res = run(*args)
    assert res.exit_code == 2 and "Traceback" not in res.output
    assert res.output.strip().startswith("error: " + what) and len(res.output.strip().splitlines()) == 1


def test_join_vector_words_leaves_other_words_alone():
    assert join_vector_words(["fk", "fighter", "1", "2", "3"]) == ["fk", "fighter", "1", "2", "3"]
    assert join_vector_words(["ik", "x", "--", "--rpy", "1", "2", "3"]) == ["ik", "x", "--", "--rpy", "1", "2", "3"]
    assert join_vector_words(["ik", "r", "1", "2", "3", "--rpy", "1", "2", "3", "4"]) == \
        ["ik", "r", "1", "2", "3", "--rpy", "1,2,3", "4"]


def test_the_shell_reads_vectors_by_the_same_rule():
    import io

    from rich.console import Console

    from armkit.cli.common import VECTOR_SPLIT
    from armkit.cli.shell import Shell

    sh = Shell(armkit.load("fighter"), lang="en", plot="none", console=Console(file=io.StringIO()))
    for line in ("goto 24.861 14.353 187.181", "goto 24.861,14.353,187.181", "[24.861, 14.353, 187.181]"):
        assert sh.execute(line).status == "ok"
        assert np.allclose(sh.end_point, [24.861, 14.353, 187.181], atol=1e-3)
    assert VECTOR_SPLIT.split("1, 2 ,3") == ["1", "2", "3"]


# ------------------------------------------------------------------ 2. one set of branch names
def _ik_names(robot: str, *target: str) -> set[str]:
    return {s["branch"] for s in out_json("ik", robot, *target, "--json")["solutions"]}


@pytest.mark.parametrize("robot, target", [("planar2", ("1.2", "0.3")), ("fighter", ("24.861", "14.353", "187.181"))])
def test_maps_offer_the_names_ik_gives(robot, target, tmp_path):
    res = run("maps", robot, "--steps", "9", "--branch", "nosuch", "-o", str(tmp_path / "m.png"))
    assert res.exit_code == 2
    listed = re.search(r"one of (.*), got 'nosuch'", res.output.replace("\n", " ")).group(1)
    assert {n.strip() for n in listed.split(",")} == _ik_names(robot, *target)


def test_plot_and_the_shell_use_the_same_names(tmp_path):
    import io

    from rich.console import Console

    from armkit.cli.shell import Shell

    names = _ik_names("planar2", "1.2", "0.3")
    res = run("plot", "planar2", "--all-branches", "1.2", "0.3", "-o", str(tmp_path / "p.png"))
    assert res.exit_code == 0
    assert set(re.search(r"branch\(es\): (.*)", res.stdout).group(1).split(", ")) == names
    buf = io.StringIO()
    sh = Shell(armkit.load("planar2"), lang="en", plot="none", console=Console(file=buf, width=200))
    sh.execute("goto 1.2 0.3")
    sh.execute("branch")
    assert all(n in buf.getvalue() for n in names)


def test_the_old_map_names_still_work_with_a_note(tmp_path):
    res = run("maps", "planar2", "--steps", "9", "--branch", "q2+", "-o", str(tmp_path / "m.png"))
    assert res.exit_code == 0 and "note: --branch q2+ is the old name" in res.output
    assert "--branch elbow-down" in res.output and "warning" not in res.output


# ------------------------------------------------------------------ 3. messages wrap at the terminal's width
def test_messages_wrap_at_the_width_and_stay_whole_in_a_pipe(monkeypatch):
    from armkit.cli import common

    args = ("derive", "puma560", "--ik")
    whole = run(*args)
    assert whole.exit_code == 2
    line = whole.output.strip()
    assert "\n" not in line and len(line) > 100        # a pipe: one line that grep finds whole
    monkeypatch.setattr(common, "wraps", lambda out, columns=True: True)            # as on a terminal
    for cols in (60, 80):
        narrow = run(*args, columns=str(cols))
        lines = narrow.output.strip().splitlines()
        assert len(lines) > 1 and all(len(x) <= cols for x in lines), lines
        assert " ".join(x.strip() for x in lines) == line                       # wrapped between words, nothing lost


def test_wrapping_follows_the_terminal():
    import io

    from rich.console import Console

    from armkit.cli.common import wraps

    assert wraps(Console(file=io.StringIO(), force_terminal=True), columns=False)
    assert not wraps(Console(file=io.StringIO()), columns=False)


def test_collision_lines_wrap_at_the_width():
    res = run("ik", "fighter", "100", "50", "80", columns="60")
    assert "checked against" in res.stdout
    assert all(len(x) <= 60 for x in res.stdout.splitlines()), res.stdout


# ------------------------------------------------------------------ 4. derive --ik: text, LaTeX, fragment
def _evaluate(text: str, values: dict) -> dict:
    """The printed ``name = expression`` lines evaluated in order with SymPy (the test's reading of the text)."""
    import sympy as sp

    env = dict(values)
    for raw in text.splitlines():
        m = re.match(r"^  (\w+) = (.*)$", raw)
        if m is None or "±" in m.group(2) or "(front)" in m.group(2):
            continue
        env[m.group(1)] = float(sp.sympify(m.group(2), locals={"atan2": sp.atan2}).subs(env).evalf())
    return env


def test_derive_ik_text_planar2_gives_both_branches_of_ik():
    res = run("derive", "planar2", "--ik")
    assert res.exit_code == 0, res.output
    text = res.stdout
    a1, a2 = (float(v) for v in re.search(r"a1 = ([\d.]+) m, a2 = ([\d.]+) m", text).groups())
    x, y = 1.2, 0.3
    solved = {s["branch"]: s["q_rad"] for s in out_json("ik", "planar2", str(x), str(y), "--json")["solutions"]}
    c2 = (x * x + y * y - a1 * a1 - a2 * a2) / (2 * a1 * a2)
    for name, sign in (("elbow-down", 1), ("elbow-up", -1)):          # x >= 0: elbow-down is s2 >= 0 (the text)
        assert re.search(rf"{name}: s2 = {'[+]' if sign > 0 else '-'}sqrt", text)
        env = _evaluate(text, {"x": x, "y": y, "a1": a1, "a2": a2, "s2": sign * math.sqrt(1 - c2 * c2)})
        q1, q2 = env["q1"], env["q2"]
        assert np.allclose([q1, q2], solved[name], atol=1e-9)
        # FK by hand
        assert np.allclose([a1 * math.cos(q1) + a2 * math.cos(q1 + q2), a1 * math.sin(q1) + a2 * math.sin(q1 + q2)],
                           [x, y], atol=1e-12)


@pytest.mark.parametrize("robot", ["fighter", "examples/my_arm.toml"])
def test_derive_ik_text_yaw_pitch_pitch_matches_every_branch(robot):
    from pathlib import Path

    path = str(Path(__file__).resolve().parents[2] / robot) if robot.endswith(".toml") else robot
    res = run("derive", path, "--ik")
    assert res.exit_code == 0, res.output
    text = res.stdout
    unit = armkit.load(path).unit
    d1, a2, a3 = (float(v) for v in re.search(rf"d1 = ([\d.]+) {unit}, a2 = ([\d.]+) {unit}, a3 = ([\d.]+) {unit}",
                                              text).groups())
    target = (24.861, 14.353, 50.0) if unit == "mm" else (20.0, 10.0, 30.0)
    x, y, z = target
    got = out_json("ik", path, *map(str, target), "--no-scene", "--json")["solutions"]
    for name, side, sign in (("front/elbow-down", 1, 1), ("front/elbow-up", 1, -1), ("back/elbow-up", -1, 1),
                             ("back/elbow-down", -1, -1)):
        line = re.search(rf"  {name}: (front|back), s3 = ([+-])sqrt", text)
        assert line and (line.group(1) == "front") == (side > 0) and (line.group(2) == "+") == (sign > 0)
        r, s = side * math.hypot(x, y), z - d1
        c3 = (r * r + s * s - a2 * a2 - a3 * a3) / (2 * a2 * a3)
        env = _evaluate(text, {"x": x, "y": y, "z": z, "d1": d1, "a2": a2, "a3": a3, "r": r,
                               "s3": sign * math.sqrt(1 - c3 * c3)})
        q1 = math.atan2(y, x) + (0 if side > 0 else math.pi)
        q = np.array([q1, env["q2"], env["q3"]])
        # the hand FK of a yaw-pitch-pitch arm: the point at distance r along the yaw, height d1 + ...
        reach = a2 * math.cos(q[1]) + a3 * math.cos(q[1] + q[2])
        p = [reach * math.cos(q1), reach * math.sin(q1), d1 + a2 * math.sin(q[1]) + a3 * math.sin(q[1] + q[2])]
        assert np.allclose(p, target, atol=1e-9)
        mine = next(s for s in got if s["branch"] == name)
        wrap = np.angle(np.exp(1j * (np.array(mine["q_rad"]) - q)))     # the same angles, up to whole turns
        assert np.allclose(wrap, 0, atol=1e-8), (name, mine["q_rad"], q)


def test_derive_ik_latex_and_fragment():
    full = run("derive", "fighter", "--ik", "--latex")
    frag = run("derive", "fighter", "--ik", "--latex", "--fragment")
    assert full.exit_code == frag.exit_code == 0
    assert full.stdout.startswith("\\documentclass") and "\\end{document}" in full.stdout
    assert "\\documentclass" not in frag.stdout and "\\begin{document}" not in frag.stdout
    assert frag.stdout.count("\\begin{align*}") == frag.stdout.count("\\end{align*}") == 1
    for lhs in ("q_{1}", "q_{2}", "q_{3}", "c_{3}", "s_{3}"):
        assert re.search(rf"^\s*{re.escape(lhs)} &= ", frag.stdout, re.M), lhs
    assert frag.stdout.count("{") == frag.stdout.count("}")                      # balanced braces
    assert frag.stdout.strip() in full.stdout                                    # the fragment is the body


def test_derive_fk_latex_fragment_and_option_errors(tmp_path):
    frag = run("derive", "planar2", "--latex", "--fragment")
    assert frag.exit_code == 0 and "\\documentclass" not in frag.stdout and "\\[" in frag.stdout
    assert run("derive", "planar2", "--fragment").exit_code == 2 and "add --latex" in run("derive", "planar2", "--fragment").output
    bad = run("derive", "puma560", "--ik")
    assert bad.exit_code == 2 and "planar 2R" in bad.output
    out = tmp_path / "ik.txt"
    assert run("derive", "planar2", "--ik", "-o", str(out)).exit_code == 0
    assert "q1 = atan2(" in out.read_text()


# ------------------------------------------------------------------ 5. Craig's column order
def _header(output: str) -> str:
    return next(line for line in output.splitlines() if "theta" in line and "┃" in line)


def _columns(output: str) -> list[str]:
    return [c.strip() for c in _header(output).strip("┃").split("┃")]


def test_modified_tables_print_in_craigs_order():
    craig = ["alpha_{i-1}", "a_{i-1}", "d_i", "theta_i"]
    for args in (("info", "planar3"), ("info", "fighter", "--dh", "--convention", "modified")):
        cols = _columns(run(*args).stdout)
        assert cols[cols.index(craig[0]):cols.index(craig[0]) + 4] == craig
    cols = _columns(run("info", "fighter").stdout)                    # standard: theta d a alpha
    assert cols[cols.index("theta_i"):cols.index("theta_i") + 4] == ["theta_i", "d_i", "a_i", "alpha_i"]
    narrow = run("info", "planar3", columns="50").stdout              # one record per joint
    first = re.search(r"alpha_\{i-1\}.*?theta_i", narrow, re.S).group(0)
    assert first.index("a_{i-1}") < first.index("d_i")


def test_modified_row_values_sit_under_craigs_headers():
    out = run("info", "fighter", "--dh", "--convention", "modified").stdout
    rows = [[c.strip() for c in line.strip("│").split("│")] for line in out.splitlines() if line.startswith("│")]
    cols = _columns(out)
    craig = armkit.load("fighter").to_dh("modified")
    for row, j in zip(rows, craig.joints):
        assert float(row[cols.index("alpha_{i-1}")]) == pytest.approx(math.degrees(j.alpha), abs=1e-6)
        assert float(row[cols.index("a_{i-1}")]) == pytest.approx(j.a, abs=1e-6)


# ------------------------------------------------------------------ 6. fk --links: each A_i numerically
def _standard_dh(theta, d, a, alpha):   # Spong: Rz(theta) Tz(d) Tx(a) Rx(alpha)
    ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
    return np.array([[ct, -st * ca, st * sa, a * ct], [st, ct * ca, -ct * sa, a * st], [0, sa, ca, d], [0, 0, 0, 1]])


def _craig_dh(alpha_prev, a_prev, d, theta):   # Craig (3.6): Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta) Tz(d)
    ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha_prev), math.sin(alpha_prev)
    return np.array([[ct, -st, 0, a_prev], [st * ca, ct * ca, -sa, -sa * d], [st * sa, ct * sa, ca, ca * d],
                     [0, 0, 0, 1]])


def test_fk_links_fighter_matches_the_standard_dh_formula():
    q = np.radians([30.0, 45.0, 60.0])
    data = out_json("fk", "fighter", "30", "45", "60", "--deg", "--links", "--json")
    params = [(0.0, 36.0, 0.0, math.pi / 2), (0.0, 0.0, 77.2, 0.0), (0.0, 0.0, 100.0, 0.0)]   # the fighter's table
    for Ai, qi, (th, d, a, al) in zip(data["links"], q, params):
        assert np.allclose(Ai, _standard_dh(qi + th, d, a, al), atol=1e-12)
    assert np.allclose(np.linalg.multi_dot(data["links"]), data["pose"], atol=1e-9)


def test_fk_links_planar3_matches_craigs_formula_and_prints_units():
    q = np.radians([30.0, 45.0, 60.0])
    data = out_json("fk", "planar3", "30", "45", "60", "--deg", "--links", "--json")
    r = armkit.load("planar3")
    for Ai, qi, j in zip(data["links"], q, r.joints):
        assert np.allclose(Ai, _craig_dh(j.alpha, j.a, j.d, qi + j.theta), atol=1e-12)
    T = np.asarray(data["base"]) @ np.linalg.multi_dot(data["links"]) @ np.asarray(data["tool"])
    assert np.allclose(T, data["pose"], atol=1e-12)
    text = run("fk", "planar3", "30", "45", "60", "--deg", "--links").stdout
    assert "A1 = T_0_1" in text and "A3 = T_2_3" in text and "p (m)" in text and "Craig" in text
    assert "0.866025" in text                               # cos 30 deg, rounded, no noise
    assert not re.search(r"-0\.0+\b(?!\d*[1-9])", text)


# ------------------------------------------------------------------ 7. frames labelled {0}..{n}
@pytest.mark.parametrize("robot", ["fighter", "planar3"])
def test_plot_labels_frames_by_number_and_joint(robot):
    from armkit.viz import plot_arm

    r = armkit.load(robot)
    fig = plot_arm(r, np.radians([30.0, 45.0, 60.0]))
    labels = {t.get_gid(): t.get_text() for t in fig.axes[0].texts if str(t.get_gid()).startswith("frame-label:")}
    shown = " ".join(labels.values())
    for k in range(r.n + 1):
        assert f"{{{k}}}" in shown, shown
    for name in r.joint_names:
        assert name in shown
    first = [v for v in labels.values() if "{1}" in v][0]
    assert first.splitlines()[1].split(" / ")[-1] == r.joint_names[0]     # second line: the joint that moves it
    import matplotlib.pyplot as plt

    plt.close(fig)


# ------------------------------------------------------------------ 8. the checks
def test_a_missing_mesh_is_one_warning_line(tmp_path):
    urdf = tmp_path / "arm.urdf"
    urdf.write_text('<robot name="m"><link name="base"><visual><geometry><mesh filename="missing.stl"/></geometry>'
                    '</visual></link><link name="l1"/><joint name="j1" type="revolute"><parent link="base"/>'
                    '<child link="l1"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>'
                    '</joint></robot>')
    res = run("fk", str(urdf), "0", columns=None)
    assert res.exit_code == 0
    warned = [line for line in res.stderr.splitlines() if line.strip()]
    assert len(warned) == 1 and warned[0].startswith("warning: ") and "missing.stl" in warned[0]
    assert "UserWarning" not in res.output and "warnings.warn" not in res.output


def test_manipulability_of_a_mm_arm_says_its_unit():
    res = run("jacobian", "fighter", "30", "45", "60", "--deg")
    assert "both with lengths in m" in res.stdout and "divided by 1000" in res.stdout
    w = float(re.search(r"sqrt\(det\(J J\^T\)\) = ([\d.e-]+)", res.stdout).group(1))
    J = armkit.jacobian(armkit.load("fighter"), np.radians([30, 45, 60]))
    J[:3] *= 1e-3                                           # mm -> m
    rows = [0, 1, 2]                                        # 3 joints: the position rows
    assert w == pytest.approx(math.sqrt(np.linalg.det(J[rows] @ J[rows].T)), rel=1e-5)


def test_help_shows_vector_metavars_not_typer_types():
    res = run("ik", "--help")
    assert "R,P,Y" in res.stdout and "X,Y,Z,W" in res.stdout and "DX,DY,DZ" in res.stdout
    assert "FLOAT FLOAT FLOAT" not in res.stdout and "<float" not in res.stdout
    assert "--links" in run("fk", "--help").stdout and "--fragment" in run("derive", "--help").stdout


def test_help_text_is_not_hard_wrapped():
    res = run("ik", "--help", columns="200")
    assert ("gives a class with a solver: every arm of 1-3 joints (planar3 with --phi), 6-joint arms in closed "
            "form") in res.stdout                                 # three lines of the docstring, one line here
    assert all(len(line) <= 200 for line in res.stdout.splitlines())
    narrow = run("ik", "--help", columns="70")
    assert all(len(line) <= 70 for line in narrow.stdout.splitlines())
