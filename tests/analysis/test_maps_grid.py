"""FK/IK contour-map data for planar2 (the symbolic 2-link tutorial's arm): formulas, NaN exactly outside the annulus."""

from __future__ import annotations

import numpy as np
import pytest

import armkit
from armkit.analysis import fk_maps, ik_maps

L1, L2 = 1.0, 0.5


def test_fk_maps_match_the_planar_formula():
    r = armkit.load("planar2")
    q1 = np.radians(np.linspace(0, 90, 7))
    q2 = np.radians(np.linspace(-180, 180, 9))
    m = fk_maps(r, q1, q2)
    Q1, Q2 = np.meshgrid(q1, q2, indexing="ij")
    np.testing.assert_allclose(m.x, L1 * np.cos(Q1) + L2 * np.cos(Q1 + Q2), atol=1e-12)
    np.testing.assert_allclose(m.y, L1 * np.sin(Q1) + L2 * np.sin(Q1 + Q2), atol=1e-12)


def test_ik_maps_nan_exactly_out_of_reach_and_fk_of_each_branch():
    r = armkit.load("planar2")
    gx = np.linspace(-1.6, 1.6, 41)
    gy = np.linspace(-1.6, 1.6, 37)
    m = ik_maps(r, gx, gy)
    assert m.q.shape == (41, 37, 2, 2) and len(m.branches) == 2
    X, Y = np.meshgrid(gx, gy, indexing="ij")
    rad = np.hypot(X, Y)
    inside = (rad >= L1 - L2) & (rad <= L1 + L2)
    clear = np.abs(rad - (L1 + L2)) > 1e-9
    clear &= np.abs(rad - (L1 - L2)) > 1e-9
    for b in range(2):
        finite = np.isfinite(m.q[:, :, b, :]).all(axis=-1)
        assert np.array_equal(finite[clear], inside[clear])
        assert np.array_equal(np.isnan(m.q[:, :, b, :]).any(axis=-1), ~finite)
        q = m.q[:, :, b, :][finite]
        p = armkit.fk(r, q)[:, :2, 3]
        np.testing.assert_allclose(p, np.column_stack([X[finite], Y[finite]]), atol=1e-9)
    # the two branches are the two signs of the elbow angle where the elbow is bent
    both = np.isfinite(m.q[..., 1]).all(axis=-1) & (rad < 1.49) & (rad > 0.51)
    s = np.sign(m.q[..., 1][both])
    assert np.all(s[:, 0] == -s[:, 1])


def test_map_input_errors():
    r = armkit.load("planar2")
    with pytest.raises(armkit.ShapeError, match="q1_grid must be a 1-D"):
        fk_maps(r, np.zeros((2, 2)), [0.0])
    with pytest.raises(armkit.ArmkitError, match="two different joint indices"):
        fk_maps(r, [0.0], [0.0], joints=(0, 0))


# ---- the CLI draws the symbolic 2-link tutorial's maps (issue 11) -----------------------------------------------

def capture_maps(monkeypatch: pytest.MonkeyPatch, *args: str, code: int = 0) -> tuple:
    """Run ``armkit maps ...`` in-process and keep the map data handed to the plot (the picture is drawn too)."""
    from typer.testing import CliRunner

    import armkit.viz.plots as plots
    from armkit.cli import app

    seen: dict = {}
    real = plots.plot_maps

    def keep(fk=None, ik=None, **kw):
        seen["fk"], seen["ik"] = fk, ik
        fig = real(fk, ik, **kw)
        seen["fig"] = fig
        return fig

    monkeypatch.setattr(plots, "plot_maps", keep)
    res = CliRunner().invoke(app, ["maps", *args])
    assert res.exit_code == code, res.output
    return seen.get("fk"), seen.get("ik"), seen.get("fig"), res.output


def test_cli_maps_are_the_tutorials_formulas(monkeypatch: pytest.MonkeyPatch, tmp_path) -> None:
    out = tmp_path / "m.png"
    fm, im, _fig, _ = capture_maps(monkeypatch, "planar2", "--q1", "0:90", "--x", "0:1.5:0.01", "--y", "0:1.5:0.01",
                                   "-o", str(out))
    assert out.stat().st_size > 10_000
    # FK: theta1 0..90 (the tutorial's first quadrant) x theta2 -180..180 (the default)
    t1, t2 = np.degrees(fm.q1), np.degrees(fm.q2)
    assert t1[0] == 0 and abs(t1[-1] - 90) < 1e-12 and abs(t2[0] + 180) < 1e-12 and abs(t2[-1] - 180) < 1e-12
    Q1, Q2 = np.meshgrid(fm.q1, fm.q2, indexing="ij")
    np.testing.assert_allclose(fm.x, L1 * np.cos(Q1) + L2 * np.cos(Q1 + Q2), atol=1e-12)
    np.testing.assert_allclose(fm.y, L1 * np.sin(Q1) + L2 * np.sin(Q1 + Q2), atol=1e-12)
    # IK: x, y = 0, 0.01, ..., 1.5; one panel row per solution q2 = +-acos(c2)
    assert len(im.x) == len(im.y) == 151
    np.testing.assert_allclose(im.x, np.arange(151) * 0.01, atol=1e-12)
    assert im.branches == ("elbow-down", "elbow-up")    # armkit ik's names (issue 22): q2 >= 0 and q2 <= 0 where x >= 0
    X, Y = np.meshgrid(im.x, im.y, indexing="ij")
    rr = X**2 + Y**2
    inside = (rr >= (L1 - L2) ** 2) & (rr <= (L1 + L2) ** 2)
    clear = (np.abs(rr - (L1 - L2) ** 2) > 1e-9) & (np.abs(rr - (L1 + L2) ** 2) > 1e-9)
    c2 = (rr - L1**2 - L2**2) / (2 * L1 * L2)
    for b, sign in enumerate((+1, -1)):
        q = im.q[:, :, b, :]
        finite = np.isfinite(q).all(axis=-1)
        assert np.array_equal(finite[clear], inside[clear])          # NaN exactly where out of reach
        ok = inside & clear
        q2 = sign * np.arccos(np.clip(c2[ok], -1, 1))
        q1 = np.arctan2(Y[ok], X[ok]) - np.arctan2(L2 * np.sin(q2), L1 + L2 * np.cos(q2))
        np.testing.assert_allclose(q[ok][:, 1], q2, atol=1e-7)
        np.testing.assert_allclose(q[ok][:, 0], q1, atol=1e-7)
        # no seam: neighbours inside the annulus (off its edges, where acos is steep) differ by little
        away = (rr > 0.55**2) & (rr < 1.45**2)
        for axis in (0, 1):
            both = np.logical_and(np.take(away, range(150), axis), np.take(away, range(1, 151), axis))
            step = np.abs(np.diff(q, axis=axis))[both]
            assert step.max() < np.radians(6), np.degrees(step.max())


def test_cli_maps_planar2_default_is_the_tutorial_layout(monkeypatch: pytest.MonkeyPatch, tmp_path) -> None:
    fm, im, fig, _ = capture_maps(monkeypatch, "planar2", "-o", str(tmp_path / "m.png"), "--branch", "q2-")
    assert np.degrees(fm.q1[[0, -1]]).round(9).tolist() == [0, 90]
    assert np.degrees(fm.q2[[0, -1]]).round(9).tolist() == [-180, 180]
    assert im.x[0] == 0 and abs(im.x[-1] - 1.5) < 1e-12 and abs(im.x[1] - 0.01) < 1e-12
    assert im.branches == ("q2-",) and im.q.shape[2] == 1
    ax = fig.axes[0]                            # q1 on the horizontal axis
    assert ax.get_xlabel().startswith("q1") and ax.get_ylabel().startswith("q2")


def test_cli_maps_constant_panel_and_colour_bars_span_the_data(monkeypatch: pytest.MonkeyPatch, tmp_path) -> None:
    fm, im, fig, _ = capture_maps(monkeypatch, "fighter", "--steps", "41", "-o", str(tmp_path / "m.png"))
    assert np.abs(fm.y).max() < 1e-9                 # y(shoulder, elbow) at yaw 0: rounding noise only
    texts = [t.get_text() for ax in fig.axes for t in ax.texts]
    assert "y constant = 0 mm" in texts
    bars = [ax for ax in fig.axes if ax.get_label() == "<colorbar>"]
    assert len(bars) >= 4
    lo, hi = bars[0].get_ylim()                      # FK x: exactly the data's range
    assert abs(lo - fm.x.min()) < 1e-9 and abs(hi - fm.x.max()) < 1e-9


@pytest.mark.parametrize("args,msg", [(("--q1", "90:0"), "stop must be larger"), (("--x", "0:1.5:0"), "step"),
                                      (("--q2", "a:b"), "--q2"), (("--branch", "sideways"), "--branch must name"),
                                      (("--x", "1"), "start:stop")])
def test_cli_maps_bad_ranges_exit_2(monkeypatch: pytest.MonkeyPatch, tmp_path, args, msg) -> None:
    _, _, _, out = capture_maps(monkeypatch, "planar2", *args, "-o", str(tmp_path / "m.png"), code=2)
    assert msg in out and "Traceback" not in out


def test_scara_ik_maps_at_mid_stroke(tmp_path):
    """The eCobra 600's IK maps: targets at the middle of the slab it reaches (z = 0.387 - 0.105 m, the quill at
    mid-stroke) by default, its wrist held at q0; every map value reaches its target (FK), the two branches are
    the two signs of the elbow (a 2R in the plane: q2 = ±acos(...)), and the quill is 0.105 m everywhere."""
    from typer.testing import CliRunner

    from armkit.cli import app

    r = armkit.load("cobra600")
    gx = gy = np.linspace(-0.6, 0.6, 25)
    m = ik_maps(r, gx, gy)
    assert abs(m.z - 0.282) < 1e-3 and m.branches == ("s1", "s2")
    X, Y = np.meshgrid(gx, gy, indexing="ij")
    hits = 0
    for b in range(2):
        ok = np.all(np.isfinite(m.q[:, :, b]), axis=-1)
        hits += ok.sum()
        p = armkit.fk(r, m.q[:, :, b][ok])[:, :3, 3]
        assert np.allclose(p, np.stack([X[ok], Y[ok], np.full(ok.sum(), m.z)], axis=-1), atol=1e-9)
        assert np.allclose(m.q[:, :, b][ok][:, 2], 0.387 - m.z, atol=1e-12)
    both = np.all(np.isfinite(m.q[:, :, 0]), axis=-1) & np.all(np.isfinite(m.q[:, :, 1]), axis=-1)
    assert hits > 200 and np.all(np.sign(m.q[:, :, 0, 1][both]) == -np.sign(m.q[:, :, 1, 1][both]))
    res = CliRunner().invoke(app, ["maps", "cobra600", "-o", str(tmp_path / "maps.png")])
    assert res.exit_code == 0 and "FK maps only" not in res.output


@pytest.mark.parametrize("name, pair", [("cobra600", (0, 1)), ("fighter", (1, 2)), ("puma560", (1, 2)),
                                        ("ur5", (1, 2))])
def test_fk_maps_default_to_the_first_two_parallel_turning_joints(name, pair):
    """The tutorial's maps are of two links turning in one plane: a SCARA's shoulder and elbow (vertical axes 1, 2),
    the fighter's, Puma's and UR's shoulder and elbow (horizontal axes 2, 3)."""
    from armkit.cli.viz import _parallel_pair

    r = armkit.load(name)
    assert _parallel_pair(r) == pair
    a, b = (armkit.kinematics.jacobian(r, r.random_q(rng=1))[3:, k] for k in pair)
    assert np.linalg.norm(np.cross(a, b)) < 1e-9                  # the two axes are parallel (by the Jacobian)


# ---- memory: the maps in chunks, the pictures bounded before anything is computed ----------------------------------

@pytest.mark.parametrize("name,chunk", [("fighter", 37), ("planar2", 5), ("cobra600", 120)])
def test_maps_in_chunks_are_the_maps_in_one_piece(monkeypatch: pytest.MonkeyPatch, name, chunk) -> None:
    """Batched == looped: the maps computed a few grid rows at a time (chunks smaller than a row too) are the maps
    computed in one call, to the bit, with the same branch order."""
    from armkit.analysis import maps as M

    r = armkit.load(name)
    R = r.reach
    gx, gy = np.linspace(-R, R, 23), np.linspace(-R, R, 19)
    whole_ik, whole_fk = ik_maps(r, gx, gy), fk_maps(r, np.linspace(-1, 1, 17), np.linspace(-2, 2, 13))
    monkeypatch.setattr(M, "IK_CHUNK", chunk)
    monkeypatch.setattr(M, "CHUNK", chunk)
    parts_ik, parts_fk = ik_maps(r, gx, gy), fk_maps(r, np.linspace(-1, 1, 17), np.linspace(-2, 2, 13))
    assert parts_ik.branches == whole_ik.branches
    assert np.array_equal(parts_ik.q, whole_ik.q, equal_nan=True)
    assert np.array_equal(parts_ik.reachable, whole_ik.reachable)
    assert whole_ik.reachable.any()
    for a in "xyz":
        assert np.array_equal(getattr(parts_fk, a), getattr(whole_fk, a))


def test_ik_maps_hold_one_chunk_of_results_not_the_grid() -> None:
    """ik_all's full result is 1.6-3.4 kB a target for the fighter; the maps keep 8 bytes a joint of each branch.
    Over 90,601 targets the peak allocation (tracemalloc, numpy's arrays included) stays under 110 MB (74 MB
    measured, most of it one chunk of 20,000 targets): the whole grid's result at once took 174 MB."""
    import tracemalloc

    r = armkit.load("fighter")
    g = np.linspace(-300, 300, 301)
    ik_maps(r, g[:3], g[:3])                  # compiled and the default height known before measuring
    tracemalloc.start()
    try:
        m = ik_maps(r, g, g, z=150.0)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert m.reachable.any()
    assert peak < 110e6, peak


def test_cli_maps_refuses_pictures_beyond_the_memory_limit(monkeypatch: pytest.MonkeyPatch, tmp_path) -> None:
    """2001 x 2001 IK targets (the largest --x/--y grids) for the fighter's 4 branches x 3 joints: refused at once
    with exit 2, the points and the limit said (in Korean too), no picture written; under a raised limit the size
    check lets the same sizes through (the 80 bytes a point are the measured picture cost)."""
    from typer.testing import CliRunner

    from armkit.cli import app

    out = tmp_path / "m.png"
    args = ["maps", "fighter", "--x", "-300:300:0.3", "--y", "-300:300:0.3", "-o", str(out)]
    monkeypatch.setenv("ARMKIT_MEMORY_LIMIT", "2G")
    res = CliRunner().invoke(app, args)
    assert res.exit_code == 2, res.output
    points = 3 * 121 * 121 + 2001 * 2001 * 4 * 3
    assert f"{points:,}" in res.output and "ARMKIT_MEMORY_LIMIT" in res.output and "Traceback" not in res.output
    assert not out.exists()
    res = CliRunner().invoke(app, [*args, "--lang", "ko"])
    assert res.exit_code == 2 and "메모리" in res.output
    monkeypatch.setenv("ARMKIT_MEMORY_LIMIT", "100K")          # a small grid over a tiny limit: the same check
    res = CliRunner().invoke(app, ["maps", "planar2", "--steps", "21", "--no-ik", "-o", str(out)])
    assert res.exit_code == 2 and f"{3 * 21 * 21:,}" in res.output
