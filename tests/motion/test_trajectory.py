"""Trajectories: boundary conditions, limits, waypoints, Cartesian deviation, CSV, plots, CLI."""

from __future__ import annotations

import math

import numpy as np
import pytest
from typer.testing import CliRunner

import armkit
from armkit.cli import app
from armkit.motion.trajectory import cartesian_arc, cartesian_line, joint_trajectory, profile, segment_duration
from armkit.viz.trajectory import plot_trajectory

runner = CliRunner()
A = np.radians([[0, 0, 0], [30, 45, 60]])


def test_quintic_boundary_conditions():
    tr = joint_trajectory(A, "quintic", duration=2.0, dt=0.01)
    np.testing.assert_allclose(tr.q[0], A[0], atol=1e-15)
    np.testing.assert_allclose(tr.q[-1], A[1], atol=1e-15)
    np.testing.assert_allclose(tr.qd[[0, -1]], 0.0, atol=1e-15)
    np.testing.assert_allclose(tr.qdd[[0, -1]], 0.0, atol=1e-12)
    assert tr.t[-1] == pytest.approx(2.0)
    # textbook: q(T/2) = midpoint, peak speed 15/8 * delta / T
    np.testing.assert_allclose(tr.q[100], A.mean(axis=0), atol=1e-15)
    np.testing.assert_allclose(np.abs(tr.qd).max(axis=0), 15 / 8 * A[1] / 2.0, rtol=1e-12)


def test_cubic_ends_at_rest_and_rates_are_derivatives():
    tr = joint_trajectory(A, "cubic", duration=1.0, dt=0.001)
    np.testing.assert_allclose(tr.qd[[0, -1]], 0.0, atol=1e-15)
    np.testing.assert_allclose(np.gradient(tr.q, tr.t, axis=0)[1:-1], tr.qd[1:-1], atol=2e-5)
    np.testing.assert_allclose(np.gradient(tr.qd, tr.t, axis=0)[1:-1], tr.qdd[1:-1], atol=2e-2)


@pytest.mark.parametrize("kind", ["cubic", "quintic", "trapezoid"])
def test_limits_honoured_and_reached(kind):
    vmax, amax = 0.8, 2.0
    tr = joint_trajectory(A, kind, qd_max=vmax, qdd_max=amax, dt=0.0005)
    assert np.abs(tr.qd).max() <= vmax * (1 + 1e-9)
    assert np.abs(tr.qdd).max() <= amax * (1 + 1e-9)
    # the time is the shortest such: one of the limits is met (up to the sampling)
    assert max(np.abs(tr.qd).max() / vmax, np.abs(tr.qdd).max() / amax) > 0.99


def test_trapezoid_hand_example():
    # delta = 1 rad, v = 1 rad/s, a = 2 rad/s^2: blends of 0.5 s, total 1/1 + 1/2 = 1.5 s
    T, b = segment_duration("trapezoid", [1.0], qd_max=1.0, qdd_max=2.0)
    assert T == pytest.approx(1.5) and b == pytest.approx(0.5 / 1.5)
    s, sd, sdd = profile("trapezoid", [0.0, 1 / 3, 0.5, 1.0], blend=1 / 3)
    np.testing.assert_allclose(s, [0.0, 0.25, 0.5, 1.0])


def test_waypoints_are_passed_and_durations_lengthened():
    W = np.radians([[0, 0, 0], [30, 45, 60], [0, 10, 0]])
    tr = joint_trajectory(W, "quintic", durations=[1.0, 0.01], qd_max=1.0, dt=0.01)
    hits = [np.min(np.linalg.norm(tr.q - w, axis=1)) for w in W]
    assert max(hits) < 1e-12
    assert any("lengthened" in n for n in tr.notes)
    with pytest.raises(armkit.ArmkitError, match="durations needs 2"):
        joint_trajectory(W, "quintic", durations=[1.0])
    with pytest.raises(armkit.ArmkitError, match="profile must be"):
        joint_trajectory(W, "septic", duration=1.0)
    with pytest.raises(armkit.ArmkitError, match="outside the joint limits"):
        joint_trajectory([[0.0, 0.0], [0.0, 4.0]], duration=1.0, robot=armkit.load("planar2"))


def _dist_to_segment(P, a, b):
    d = b - a
    t = np.clip(((P - a) @ d) / (d @ d), 0, 1)
    return np.linalg.norm(P - (a + t[:, None] * d), axis=1)


def test_cartesian_line_via_ik_stays_on_the_line_and_on_one_branch():
    r = armkit.load("planar2")
    a, b = np.array([1.2, 0.2]), np.array([0.6, 0.9])
    tr = cartesian_line(r, a, b, steps=100)
    p = armkit.fk(r, tr.q)[:, :2, 3]                      # independent: FK of the joint path
    assert _dist_to_segment(p, a, b).max() < 1e-9
    np.testing.assert_allclose(p[[0, -1]], [a, b], atol=1e-9)
    assert np.abs(np.diff(tr.q, axis=0)).max() < 0.05        # no branch jump between samples
    assert np.all(np.sign(tr.q[:, 1]) == np.sign(tr.q[0, 1]))
    assert np.all(r.within_limits(tr.q))


def test_cartesian_line_3d_and_resolved_rate():
    r = armkit.load("fighter")
    a, b = np.array([120.0, 30.0, 80.0]), np.array([60.0, -40.0, 140.0])
    tr = cartesian_line(r, a, b, steps=60)
    assert _dist_to_segment(armkit.fk(r, tr.q)[:, :3, 3], a, b).max() < 1e-6     # mm
    rr = cartesian_line(r, a, b, steps=60, method="rate")
    assert _dist_to_segment(armkit.fk(r, rr.q)[:, :3, 3], a, b).max() < 1e-3 * r.reach


def test_arc_keeps_its_radius():
    r = armkit.load("planar2")
    tr = cartesian_arc(r, [0.8, 0.0], [1.1, 0.0], math.pi / 2, steps=50)
    p = armkit.fk(r, tr.q)[:, :2, 3]
    np.testing.assert_allclose(np.linalg.norm(p - [0.8, 0.0], axis=1), 0.3, atol=1e-9)
    np.testing.assert_allclose(p[-1], [0.8, 0.3], atol=1e-9)


def test_unreachable_line_raises_with_the_sample():
    with pytest.raises(armkit.UnreachableError, match="sample .* of 11"):
        cartesian_line(armkit.load("planar2"), [1.2, 0.2], [3.0, 0.9], steps=10)


def test_csv_and_plot(tmp_path):
    r = armkit.load("fighter")
    tr = joint_trajectory(A, "quintic", duration=1.0, dt=0.1, robot=r)
    path = tr.to_csv(tmp_path / "t.csv", r.joint_names)
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    assert data.shape == (11, 1 + 3 * 3 + 3)
    np.testing.assert_allclose(data[:, 1:4], tr.q, atol=1e-9)
    assert path.read_text().splitlines()[0].startswith("t,yaw,shoulder,elbow,yaw_rate")
    plot_trajectory(tr, r, tmp_path / "t.png")
    assert (tmp_path / "t.png").stat().st_size > 1000


def test_the_plots_moved_to_viz_and_motion_says_where():
    import armkit.motion
    import armkit.viz

    assert armkit.viz.plot_trajectory is plot_trajectory
    assert armkit.viz.animate_trajectory.__module__ == "armkit.viz.trajectory"
    for name in ("plot_trajectory", "animate_trajectory"):
        with pytest.raises(AttributeError, match=f"moved to armkit.viz.{name}"):
            getattr(armkit.motion, name)


def test_cli_traj(tmp_path):
    out = tmp_path / "traj.png"
    res = runner.invoke(app, ["traj", "fighter", "--joint", "0,0,0", "30,45,60", "--deg", "--profile", "quintic",
                              "--duration", "2", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert out.stat().st_size > 1000
    res = runner.invoke(app, ["traj", "planar2", "--line", "1.2,0.2", "0.6,0.9", "--steps", "20", "--json"])
    assert res.exit_code == 0 and '"max_deviation"' in res.output
    res = runner.invoke(app, ["traj", "planar2", "--line", "1.2,0.2", "3,0.9"])
    assert res.exit_code == 1 and "unreachable" in res.output
    res = runner.invoke(app, ["traj", "fighter", "--joint", "0,0", "30,45", "--deg"])
    assert res.exit_code == 2 and "3 values each" in res.output
    res = runner.invoke(app, ["traj", "fighter", "0,0,0", "1,1,1"])
    assert res.exit_code == 2 and "exactly one" in res.output


def test_cli_traj_animation(tmp_path):
    pytest.importorskip("armkit.viz.animation")
    out = tmp_path / "line.gif"
    res = runner.invoke(app, ["traj", "planar2", "--line", "1.2,0.2", "0.6,0.9", "--steps", "8", "-o", str(out)])
    assert res.exit_code == 0, res.output
    assert out.read_bytes()[:6] in (b"GIF89a", b"GIF87a")


# ---- Cartesian paths through any number of waypoints, with blends (issue 11) -------------------------------------
from hypothesis import given, settings, strategies as st  # noqa: E402

from armkit.motion import blended_polyline, cartesian_waypoints  # noqa: E402


def _min_dist(P: np.ndarray, w: np.ndarray) -> float:
    return float(np.linalg.norm(P - w, axis=1).min())


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(*[st.floats(-2, 2)] * 3), min_size=3, max_size=7),
       st.floats(0.01, 0.5), st.sampled_from(["circular", "parabolic"]))
def test_blended_path_ends_exactly_and_passes_within_the_radius(pts, radius, shape):
    W = np.array(pts)
    if np.linalg.norm(np.diff(W, axis=0), axis=1).min() < 1e-3:
        return
    P = blended_polyline(W, radius, shape, steps=2000)
    assert np.array_equal(P[0], W[0]) and np.array_equal(P[-1], W[-1])       # exactly through start and end
    step = np.linalg.norm(np.diff(P, axis=0), axis=1)
    # equal arc-length samples: no chord longer than its share of the path (one across a tight bend is shorter)
    assert step.max() <= np.median(step) * (1 + 1e-6) + 1e-12
    for w in W[1:-1]:
        assert _min_dist(P, w) <= radius + step.max()                         # within the blend radius


def test_circular_blend_hand_values():
    """A right-angle corner, radius r: the arc (tangent length r, circle radius r) comes to r (sqrt 2 - 1) of the
    corner (r tan(pi/8)); the parabola (Bezier through the corner's control point) to r sqrt(2)/4 (r sin(pi/4)/2)."""
    W = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    r = 0.2
    arc = blended_polyline(W, r, "circular", steps=20000)
    par = blended_polyline(W, r, "parabolic", steps=20000)
    assert abs(_min_dist(arc, W[1]) - r * (np.sqrt(2) - 1)) < 1e-4
    assert abs(_min_dist(par, W[1]) - r * np.sqrt(2) / 4) < 1e-4
    # the arc's points off the straight parts lie on the circle of radius r around (1 - r, r)
    on_arc = (arc[:, 0] > 1 - r + 1e-9) & (arc[:, 1] < r - 1e-9)
    np.testing.assert_allclose(np.linalg.norm(arc[on_arc] - [1 - r, r], axis=1), r, atol=1e-6)
    # radius 0: a sharp corner, and the corner is a sample
    assert _min_dist(blended_polyline(W, 0.0, steps=7), W[1]) == 0.0


def test_blend_radius_clipped_to_half_a_segment():
    W = np.array([[0.0, 0.0], [0.1, 0.0], [0.1, 1.0]])
    P = blended_polyline(W, 0.5, steps=4000)            # 0.5 > half of the first segment (0.05)
    assert _min_dist(P, W[1]) <= 0.05 + 1e-3
    assert np.all(P[:, 1] >= -1e-12)                    # the arc stays inside the corner


def test_waypoints_via_ik_speed_and_joint_limits_kept():
    r = armkit.load("planar2")
    W = np.array([[1.2, 0.2], [1.0, 0.8], [0.4, 1.0], [0.3, 0.6]])
    tr = cartesian_waypoints(r, W, blend=0.1, steps=200, speed=0.3)
    L = np.linalg.norm(np.diff(tr.targets, axis=0), axis=1).sum()
    assert abs(tr.duration - 1.875 * L / 0.3) < 1e-9
    v = np.linalg.norm(np.diff(tr.positions, axis=0), axis=1) / np.diff(tr.t)
    assert v.max() <= 0.3 * 1.001 and v.max() > 0.3 * 0.97       # the limit is kept and used
    np.testing.assert_allclose(tr.positions[[0, -1], :2], W[[0, -1]], atol=1e-9)
    for w in W[1:-1]:
        assert _min_dist(tr.positions[:, :2], w) <= 0.1
    assert tr.deviation.max() < 1e-9
    slow = cartesian_waypoints(r, W, blend=0.1, steps=200, qd_max=0.5)
    assert np.abs(slow.qd).max() <= 0.5 + 1e-12 and np.abs(slow.qd).max() > 0.49
    assert slow.duration > 2.0 and slow.notes


def test_cli_traj_waypoints_with_blends(tmp_path):
    import json

    res = runner.invoke(app, ["traj", "planar2", "--line", "1.2,0.2", "1.0,0.8", "0.4,1.0", "--blend", "0.1",
                              "--steps", "60", "--json"])
    assert res.exit_code == 0, res.output
    d = json.loads(res.stdout)
    assert d["samples"] == 61 and "3 waypoints, circular blends of 0.1" in d["label"]
    out = tmp_path / "t.csv"               # the old spelling --out still works (hidden)
    res = runner.invoke(app, ["traj", "planar2", "--line", "1.2,0.2", "0.6,0.9", "--steps", "5", "--out", str(out)])
    assert res.exit_code == 0 and out.exists(), res.output
    for bad in (["--blend", "-1"], ["--blend-shape", "square"], ["--speed", "0"]):
        res = runner.invoke(app, ["traj", "planar2", "--line", "1.2,0.2", "1.0,0.8", "0.4,1.0", *bad])
        assert res.exit_code == 2 and "Traceback" not in res.output, res.output
