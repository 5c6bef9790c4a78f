"""One collision rule (issue 22, item 2): a robot's own surroundings belong to the robot.

``scene=None`` (the default) is the robot's own surroundings (the fighter's torso and ground)
in ``armkit.ik``, ``armkit.ik_all``, the workspace, the CLI, the shell and the view;
``scene=False`` / ``--no-scene`` turns them off; every checked answer says what it was checked
against. The target below puts the fighter's upper arm into its torso on both elbow-down
branches (46.8 mm), while both elbow-up branches are clear.
"""

from __future__ import annotations

import io
import json

import numpy as np
import pytest
from rich.console import Console
from typer.testing import CliRunner

import armkit
from armkit.analysis.workspace import workspace
from armkit.cli import app
from armkit.cli.shell import Shell
from armkit.collision import checked_against, resolve_scene

TARGET = [100.0, 0.0, 20.0]
DOWN = "front/elbow-down"
CHECKED = ("ground", "torso")
CLEAR = {"front/elbow-up", "back/elbow-up"}
COLLIDE = {"front/elbow-down", "back/elbow-down"}

runner = CliRunner()


@pytest.fixture(scope="module")
def arm():
    return armkit.load("fighter")


def _verdicts(res):
    return {str(b): bool(s) for b, s in zip(np.asarray(res.branch), np.asarray(res.success))}


# ------------------------------------------------------------------ the rule itself
def test_rule_none_is_the_robots_own_false_is_none(arm):
    own = resolve_scene(arm, None)
    assert [s.name for s in own] == ["ground"]
    assert checked_against(arm, own) == CHECKED
    assert resolve_scene(arm, False) is None and checked_against(arm, None) == ()
    planar = armkit.load("planar2")
    assert resolve_scene(planar, None) is None                  # no collision keys: nothing to check
    assert checked_against(planar, resolve_scene(planar, "robot")) == ("itself",)
    replaced = resolve_scene(arm, armkit.Scene([armkit.Scene.plane([0, 0, 1], -40, name="floor")]))
    assert checked_against(arm, replaced) == ("floor", "torso")   # an explicit scene replaces the ground


# ------------------------------------------------------------------ the API
def test_ik_all_default_honours_the_torso_and_says_so(arm):
    res = armkit.ik_all(arm, TARGET)
    v = _verdicts(res)
    assert {b for b, ok in v.items() if ok} == CLEAR and {b for b, ok in v.items() if not ok} == COLLIDE
    reasons = {str(b): str(r) for b, r in zip(res.branch, res.reason)}
    assert all(reasons[b] == "collision" for b in COLLIDE)
    assert res.checked_against == CHECKED and res[0].checked_against == CHECKED
    old = armkit.ik_all(arm, TARGET, scene=False)               # the old answer: every branch solves
    assert all(_verdicts(old).values()) and old.checked_against == ()


def test_ik_default_honours_the_torso_and_says_so(arm):
    down = armkit.ik(arm, TARGET, branch=DOWN)
    assert not bool(down.success) and str(down.reason) == "collision" and "torso" in down.message
    assert down.checked_against == CHECKED
    q_down = armkit.ik(arm, TARGET, branch=DOWN, scene=False).q
    near = armkit.ik(arm, TARGET, q0=q_down)                     # nearest branch that does not collide
    assert bool(near.success) and str(near.branch) in CLEAR and near.checked_against == CHECKED
    old = armkit.ik(arm, TARGET, branch=DOWN, scene=False)
    assert bool(old.success) and old.checked_against == ()
    assert str(armkit.ik(arm, TARGET, q0=q_down, scene=False).branch) == DOWN
    # IKResult's fields are unchanged: checked_against is an attribute, not a field
    from dataclasses import fields

    assert "checked_against" not in {f.name for f in fields(armkit.IKResult)}


def test_arm_without_surroundings_is_not_checked():
    planar = armkit.load("planar2")
    res = armkit.ik(planar, [1.2, 0.3])
    assert bool(res.success) and res.checked_against == ()
    assert armkit.ik_all(planar, [1.2, 0.3]).checked_against == ()


# ------------------------------------------------------------------ the CLI
def test_cli_ik_same_verdict_and_checked_against(arm):
    out = runner.invoke(app, ["ik", "fighter", *map(str, TARGET), "--json"])
    assert out.exit_code == 0, out.output
    data = json.loads(out.output)
    assert {s["branch"]: s["success"] for s in data["solutions"]} == _verdicts(armkit.ik_all(arm, TARGET))
    assert data["checked_against"] == list(CHECKED)
    text = runner.invoke(app, ["ik", "fighter", *map(str, TARGET)]).output
    assert "checked against: ground, torso" in text
    one = runner.invoke(app, ["ik", "fighter", *map(str, TARGET), "--branch", DOWN])
    assert one.exit_code == 1 and "collision" in one.output and "checked against: ground, torso" in one.output
    off = runner.invoke(app, ["ik", "fighter", *map(str, TARGET), "--json", "--no-scene"])
    assert off.exit_code == 0
    data = json.loads(off.output)
    assert all(s["success"] for s in data["solutions"]) and data["checked_against"] == []
    off = runner.invoke(app, ["ik", "fighter", *map(str, TARGET), "--branch", DOWN, "--no-scene"])
    assert off.exit_code == 0 and "checked against" not in off.output


def test_cli_plot_all_branches_draws_only_the_clear_ones(tmp_path):
    out = runner.invoke(app, ["plot", "fighter", "--all-branches", "100,0,20", "-o", str(tmp_path / "b.png")])
    assert out.exit_code == 0, out.output
    assert "2 branch(es)" in out.output and "checked against: ground, torso" in out.output
    off = runner.invoke(app, ["plot", "fighter", "--all-branches", "100,0,20", "--no-scene",
                              "-o", str(tmp_path / "c.png")])
    assert off.exit_code == 0 and "4 branch(es)" in off.output


# ------------------------------------------------------------------ the shell
def _shell(arm):
    return Shell(arm, lang="en", plot="none", console=Console(file=io.StringIO(), width=120))


def test_shell_same_verdict_and_checked_against(arm):
    sh = _shell(arm)
    sh.execute(f"branch {DOWN}")                                   # prefer elbow-down ...
    out = sh.execute("goto " + " ".join(map(str, TARGET)))
    assert out.status == "ok" and sh.branch in CLEAR                # ... which collides here: not taken
    assert "checked against: ground, torso" in out.text
    np.testing.assert_allclose(armkit.fk(arm, sh.q)[:3, 3], TARGET, atol=1e-6)
    assert _verdicts(armkit.ik_all(arm, TARGET))[sh.branch]         # the API's verdict for that branch
    out = sh.execute("branch")                                     # the branches of the current end point
    assert out.status == "info" and "checked against: ground, torso" in out.text
    rows = {line.split("│")[1].strip().rstrip("*"): line.split("│")[-2].strip()
            for line in out.text.splitlines() if line.count("│") > 3 and "/" in line}
    assert {b: v == "yes" for b, v in rows.items()} == _verdicts(armkit.ik_all(arm, TARGET))
    assert all(rows[b] == "collision" for b in COLLIDE)


def test_shell_without_surroundings_gives_the_old_answer(arm):
    sh = _shell(arm)
    sh.scene = None                                                # what `--no-scene` would be: no check
    sh.execute(f"branch {DOWN}")
    out = sh.execute("goto " + " ".join(map(str, TARGET)))
    assert out.status == "ok" and sh.branch == DOWN and "checked against" not in out.text


# ------------------------------------------------------------------ the view (no browser: its IK API)
def test_view_same_verdict_and_checked_against():
    pytest.importorskip("viser")
    from armkit.viz.view import View

    with View("fighter", lang="en") as v:
        assert v.checked_against == CHECKED
        res = v.set_target(np.array(TARGET))
        assert bool(res.success) and str(res.branch) in CLEAR and res.checked_against == CHECKED
        assert set(v.branches) == CLEAR                              # the branch menu lists the clear ones
        assert "checked against: ground, torso" in v.panels.ik_html.content
    with View("fighter", lang="en", scene=False) as v:
        v.set_target(np.array(TARGET))
        assert set(v.branches) == CLEAR | COLLIDE and v.checked_against == ()


# ------------------------------------------------------------------ the workspace
def test_workspace_default_is_the_robots_own_and_equals_the_cli(arm):
    n = 4000
    own = workspace(arm, samples=n, seed=0)
    off = workspace(arm, samples=n, seed=0, scene=False)
    assert own.checked_against == CHECKED and off.checked_against == ()
    assert own.excluded > 0 and off.excluded == 0 and own.volume != off.volume
    assert "checked against: ground, torso" in own.summary()
    out = runner.invoke(app, ["workspace", "fighter", "-n", str(n), "--json"])
    assert out.exit_code == 0, out.output
    data = json.loads(out.output)
    assert data["volume"] == pytest.approx(own.volume, rel=1e-12) and data["checked_against"] == list(CHECKED)
    out = runner.invoke(app, ["workspace", "fighter", "-n", str(n), "--json", "--no-scene"])
    assert json.loads(out.output)["volume"] == pytest.approx(off.volume, rel=1e-12)
    text = runner.invoke(app, ["workspace", "fighter", "-n", str(n)]).output
    assert "checked against: ground, torso" in text


def test_track_default_is_the_robots_own():
    from armkit.viz.tracking import track

    fighter = armkit.load("fighter")
    tr = track(fighter, path="circle", method="analytic", frames=30)
    assert tr.checked_against == CHECKED and tr.colliding is not None and not tr.colliding.any()
    off = track(fighter, path="circle", method="analytic", frames=30, scene=False)
    assert off.colliding is None and off.checked_against == ()
