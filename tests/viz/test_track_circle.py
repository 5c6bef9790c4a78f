"""Target tracking and animation files."""

from __future__ import annotations

import math

import numpy as np
import pytest
from typer.testing import CliRunner

import armkit
from armkit.viz import render_animation, track
from armkit.viz.tracking import target_path


def _wrapped_steps(q):
    return np.abs(np.angle(np.exp(1j * np.diff(q, axis=0))))


@pytest.mark.parametrize("name, method", [("planar2", "analytic"), ("fighter", "analytic"), ("planar3", "ccd"),
                                          ("planar3", "lm")])
def test_reachable_circle_is_tracked_without_branch_flips(name, method):
    r = armkit.load(name)
    res = track(r, path="circle", method=method, frames=60, scene=False)   # the solver alone (no torso, ground)
    # the circle is inside the workspace: every frame reached, within the tolerance (checked by FK here)
    err = np.linalg.norm(armkit.fk(r, res.q)[:, :3, 3] - res.targets, axis=1)
    assert res.reached.all() and not res.out_of_reach.any()
    assert err.max() <= res.tol
    np.testing.assert_allclose(res.error, err, atol=1e-12)
    # no flips: one branch label throughout and small joint steps (a 60-frame circle moves a few degrees a frame)
    assert len(set(res.branch.tolist())) == 1
    assert _wrapped_steps(res.q).max() < math.radians(25)
    st = res.stats()
    assert st["branch_changes"] == 0 and st["frames_reached"] == 60


def test_circle_geometry_stays_between_the_boundaries():
    r = armkit.load("planar2")
    p = target_path(r, "circle", frames=50)
    rad = np.hypot(p[:, 0], p[:, 1])
    assert rad.min() > 0.5 and rad.max() < 1.5 and np.allclose(p[:, 2], 0)


def test_csv_path_and_out_of_reach_frames(tmp_path):
    r = armkit.load("planar2")
    f = tmp_path / "pts.csv"
    f.write_text("x,y\n1.0,0.5\n1.2,0.2\n3.0,0.0\n1.1,0.1\n")
    res = track(r, path=str(f), method="analytic")
    assert len(res.q) == 4 and res.path == "pts.csv"
    np.testing.assert_array_equal(res.out_of_reach, [False, False, True, False])
    assert res.reached.tolist() == [True, True, False, True]
    with pytest.raises(armkit.ArmkitError, match="CSV file"):
        track(r, path=str(tmp_path / "missing.csv"))
    with pytest.raises(armkit.ArmkitError, match="method must be one of"):
        track(r, path="circle", method="magic")


def test_render_gif_and_mp4(tmp_path):
    from PIL import Image

    r = armkit.load("planar3")
    q = np.linspace([0, 0, 0], [1.0, 0.5, -0.5], 6)
    targets = armkit.fk(r, q)[:, :3, 3]
    gif = render_animation(r, q, tmp_path / "a.gif", targets=targets, fps=10, progress=False)
    with Image.open(gif) as im:
        assert im.n_frames == 6
    mp4 = render_animation(r, q, tmp_path / "a.mp4", progress=False)
    assert mp4.stat().st_size > 1000
    with pytest.raises(armkit.ArmkitError, match=r"\.gif or \.mp4"):
        render_animation(r, q, tmp_path / "a.avi")
    with pytest.raises(armkit.ShapeError, match="targets must have shape"):
        render_animation(r, q, tmp_path / "b.gif", targets=targets[:3])


def test_cli_picture_commands(tmp_path):
    from armkit.cli import app

    run = CliRunner().invoke
    res = run(app, ["plot", "fighter", "30", "45", "60", "--deg", "-o", str(tmp_path / "arm.png")])
    assert res.exit_code == 0 and (tmp_path / "arm.png").is_file()
    res = run(app, ["plot", "fighter", "--all-branches", "100,50,80", "-o", str(tmp_path / "b.png")])
    # the robot's own surroundings by default: both elbow-down branches hit the torso (--no-scene: all four)
    assert res.exit_code == 0 and "2 branch" in res.output and "checked against: ground, torso" in res.output
    res = run(app, ["plot", "fighter", "--all-branches", "900,0,0", "-o", str(tmp_path / "c.png")])
    assert res.exit_code == 1
    res = run(app, ["plot", "fighter", "1", "2", "-o", str(tmp_path / "d.png")])
    assert res.exit_code == 2 and "3 joints" in res.output
    res = run(app, ["workspace", "planar2", "-n", "5000", "--json"])
    assert res.exit_code == 0 and '"area"' in res.output
    res = run(app, ["maps", "planar2", "--steps", "21", "-o", str(tmp_path / "m.png")])
    assert res.exit_code == 0 and (tmp_path / "m.png").is_file()
    res = run(app, ["track", "planar3", "--path", "circle", "--frames", "8", "-o", str(tmp_path / "t.gif")])
    assert res.exit_code == 0 and "reached: 8" in res.output and (tmp_path / "t.gif").is_file()
    res = run(app, ["track", "planar3", "--path", "nowhere"])
    assert res.exit_code == 2
    res = run(app, ["shell", "fighter", "--no-plot", "--lang", "en"], input="q 30 45 60\nexit\n")
    assert res.exit_code == 0 and "24.86" in res.output
    for cmd in ("plot", "shell", "workspace", "maps", "track"):
        assert "Example: armkit" in run(app, [cmd, "--help"]).output


@pytest.mark.parametrize("method", ["analytic", "lm", "ccd"])
def test_a_scara_tracks_paths_in_the_middle_of_its_flat_workspace(method):
    """The eCobra 600 reaches a slab 0.21 m high (its quill's stroke) between radii 0.127 m (the elbow at its
    157.5 deg limit: sqrt(a1² + a2² + 2 a1 a2 cos 157.5°)) and a1 + a2 = 0.6 m: its paths lie at mid-stroke,
    z = d1 - 0.105 = 0.282 m, inside that ring, and every frame is reached (the tilted 3D circle of other arms
    left the slab: 69 of 200 frames failed, and 145 of the random path's)."""
    r = armkit.load("cobra600")
    for path in ("circle", "figure8"):
        p = target_path(r, path, frames=60)
        rad = np.hypot(p[:, 0], p[:, 1])
        assert np.allclose(p[:, 2], 0.387 - 0.105, atol=1e-3) and rad.min() > 0.127 and rad.max() < 0.6
        res = track(r, path=path, method=method, frames=60, scene=False)
        assert res.reached.all(), (path, res.stats())
        assert np.linalg.norm(armkit.fk(r, res.q)[:, :3, 3] - res.targets, axis=1).max() <= res.tol


@pytest.mark.parametrize("name, words", [("ur5", "(ur) needs more than a position"), ("panda", "has none")])
def test_analytic_tracking_without_a_position_closed_form_names_the_methods_that_work(name, words):
    with pytest.raises(armkit.ArmkitError, match="track it with method 'lm', 'newton' or 'ccd'") as info:
        track(armkit.load(name), path="circle", method="analytic", frames=5)
    assert words in str(info.value)
    res = track(armkit.load("puma560"), path="circle", method="analytic", frames=20, scene=False)   # wrist held
    assert res.reached.all()


# ---- why a frame was missed: decided by the closed form, the same for every method --------------------------------
@pytest.mark.parametrize("method", ["ccd", "fabrik", "lm", "analytic"])
def test_planar2_frames_out_of_reach_by_the_law_of_cosines_for_every_method(method):
    """planar2 (links 1 and 0.5, joints turning all the way round) reaches exactly the annulus 0.5 <= r <= 1.5. The
    random path leaves it; every method says so for the same frames (CCD, FABRIK and LM said 'not converged' for
    the 79 frames the closed form called out of reach)."""
    r = armkit.load("planar2")
    res = track(r, path="random", method=method, frames=200, scene=False)
    l1, l2 = (j.a for j in r.joints)
    rad = np.hypot(res.targets[:, 0], res.targets[:, 1])
    outside = (rad > l1 + l2 + 1e-9) | (rad < abs(l1 - l2) - 1e-9)
    assert outside.sum() >= 20                               # the path does leave the annulus
    np.testing.assert_array_equal(res.out_of_reach, outside)
    assert not res.reached[outside].any() and res.reached[~outside].all()
    st = res.stats()
    assert st["frames_not_converged"] == 0 and st["frames_outside_limits"] == 0
    assert st["frames_out_of_reach"] == int(outside.sum())


def test_frames_reachable_only_outside_the_limits_are_named_alike_by_every_method():
    """puma560's random path: some frames are reachable only outside its joint limits. CCD, LM and the closed form
    flag the same frames; each such frame is reached by LM with the limits off (an independent numeric check), and
    no frame flagged out of reach is."""
    r = armkit.load("puma560")
    runs = {m: track(r, path="random", method=m, frames=120, seed=3) for m in ("ccd", "lm", "analytic")}
    missed = np.logical_and.reduce([~res.reached for res in runs.values()])
    limits = runs["lm"].outside_limits
    out = runs["lm"].out_of_reach
    assert limits.any() and out.any()
    for res in runs.values():
        np.testing.assert_array_equal(res.outside_limits[missed], limits[missed])
        np.testing.assert_array_equal(res.out_of_reach[missed], out[missed])
    free = armkit.ik(r, runs["lm"].targets[limits], method="lm", enforce_limits=False, restarts=20)
    assert np.all(free.success)
    far = armkit.ik(r, runs["lm"].targets[out], method="lm", enforce_limits=False, restarts=20)
    assert not np.any(far.success)


def test_analytic_frames_where_every_solution_collides():
    """The fighter with its torso and ground, tracked by the closed form: a frame it misses although the point is
    reachable inside the limits is one where every such branch collides (checked here with armkit.collision)."""
    from armkit.collision import in_collision

    r = armkit.load("fighter")
    res = track(r, path="random", method="analytic", frames=120)
    blocked = np.flatnonzero(res.blocked)
    assert blocked.size
    assert res.stats()["frames_every_solution_collides"] == blocked.size
    for k in blocked:
        every = armkit.ik_all(r, res.targets[k], scene=False)
        ok = np.asarray(every.success)
        assert ok.any() and in_collision(r, np.asarray(every.q)[ok], "robot").all()
    # without a scene there is nothing to collide with: no frame is blocked
    assert not track(r, path="random", method="analytic", frames=120, scene=False).blocked.any()


def test_cli_track_line_names_why_frames_were_missed():
    from armkit.cli import app

    out = CliRunner().invoke(app, ["track", "puma560", "--no-animation", "--frames", "120", "--seed", "3"])
    assert out.exit_code == 0, out.output
    line = " ".join(out.output.split())
    assert "only outside the joint limits:" in line and "not converged: 0" in line
    out = CliRunner().invoke(app, ["track", "puma560", "--no-animation", "--frames", "120", "--seed", "3", "--json"])
    import json

    st = json.loads(out.output)
    assert st["frames_reached"] + st["frames_out_of_reach"] + st["frames_outside_limits"] + \
        st["frames_every_solution_collides"] + st["frames_not_converged"] == 120


def test_random_starts_only_where_a_solution_may_exist():
    """A frame the warm start misses gets random starts only where a solution may exist. planar2's frames beyond its
    annulus took LM's 51 starts each (1311 iterations; `armkit track planar2 --method lm` ran 25 s): now one start
    (at most its 100 steps). The fighter's frames that CCD's warm start misses inside its reach still get starts:
    every one is reached (3 were 'not converged' with the warm start alone)."""
    from armkit.ik import DEFAULT_MAX_ITERATIONS

    res = track(armkit.load("planar2"), path="random", method="lm", frames=200, scene=False)
    assert res.out_of_reach.sum() >= 20
    assert res.iterations[res.out_of_reach].max() <= DEFAULT_MAX_ITERATIONS
    fighter = track(armkit.load("fighter"), path="random", method="ccd", frames=200, scene=False)
    st = fighter.stats()
    assert st["frames_not_converged"] == 0 and st["frames_reached"] + st["frames_out_of_reach"] == 200
