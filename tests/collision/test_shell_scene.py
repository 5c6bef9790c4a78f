"""The shell with surroundings: moves into collision are refused; ground, box, clear, scene edit the scene."""

from __future__ import annotations

import io

import numpy as np
from rich.console import Console

import armkit
from armkit.cli.shell import Shell


def shell(name="fighter", lang="en"):
    return Shell(armkit.load(name), lang=lang, plot="none", console=Console(file=io.StringIO()))


def test_a_move_into_the_ground_is_refused():
    sh = shell()
    out = sh.execute("theta2 = -30")
    assert out.status == "error"
    assert "the forearm would hit the ground by 35.6 mm; the arm did not move" in out.text
    np.testing.assert_array_equal(sh.q, np.zeros(3))
    assert sh.execute("theta2 = 45").status == "ok"


def test_ground_box_clear_scene_commands():
    sh = shell()
    assert "floor at z = -25" in sh.execute("scene").text
    out = sh.execute("clear")
    assert out.status == "info" and "only its own body" in out.text
    assert "would hit the torso by 16.8 mm" in sh.execute("theta2 = -30").text   # the body stays
    assert "floor at z = -40" in sh.execute("ground -40").text
    out = sh.execute("box 50 -50 -40 150 50 50")
    assert "box 1" in out.text
    out = sh.execute("goto 100 0 30")
    assert out.status == "error" and "box 1" in out.text
    assert "ground needs one number" in sh.execute("ground").text
    assert "box needs 6 numbers" in sh.execute("box 1 2").text


def test_goto_picks_a_collision_free_branch():
    sh = shell()
    out = sh.execute("goto 100 0 60")
    assert out.status == "ok"
    assert not armkit.collisions(sh.robot, sh.q).colliding


def test_korean_message():
    out = shell(lang="ko").execute("theta2 = -30")
    assert "부딪힙니다" in out.text and "35.6 mm" in out.text


def test_arms_without_surroundings_are_unchanged_until_asked():
    sh = shell("planar2")
    assert sh.scene is None
    assert sh.execute("q -90 0").status == "ok"
    assert sh.execute("home").status == "ok"
    sh.execute("box -2 -2 -1 2 -0.3 1")          # everything at y < -0.3
    out = sh.execute("q -90 0")
    assert out.status == "error" and "hit the box 1" in out.text


def _cli(*args):
    import subprocess
    import sys

    return subprocess.run([sys.executable, "-c", "from armkit.cli import main; main()", *args], capture_output=True,
                          text=True, timeout=300)


def test_track_and_traj_flag_or_refuse_collisions(tmp_path):
    from armkit.viz.tracking import track

    res = track(armkit.load("fighter"), path="random", method="lm", frames=30, seed=1, scene="robot")
    assert res.colliding is not None and res.colliding.shape == (30,)
    assert res.stats()["frames_in_collision"] == int(res.colliding.sum())
    np.testing.assert_array_equal(res.colliding, armkit.collisions(res.robot, res.q).colliding)
    out = _cli("traj", "fighter", "--joint", "0,0,0", "0,-40,0", "--deg", "--json")
    assert out.returncode == 0 and '"samples_in_collision": 54' in out.stdout
    pic = tmp_path / "t.png"
    out = _cli("traj", "fighter", "--joint", "0,0,0", "0,-40,0", "--deg", "--refuse-collisions", "-o", str(pic))
    assert out.returncode == 1 and "the forearm hits the ground" in out.stderr and not pic.exists()
    out = _cli("traj", "fighter", "--joint", "0,0,0", "0,-40,0", "--deg", "--no-scene", "--json")
    assert out.returncode == 0 and "samples_in_collision" not in out.stdout
