"""plot_arm: the drawn joint positions are the FK frame origins (read back from the artists)."""

from __future__ import annotations

import math

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import armkit  # noqa: E402
from armkit.viz import plot_arm  # noqa: E402


def _artist(fig, gid):
    for ax in fig.axes:
        for line in ax.get_lines():
            if line.get_gid() == gid:
                return line
    raise AssertionError(f"no artist with gid {gid!r}")


def _xyz(line):
    if hasattr(line, "get_data_3d"):
        return np.column_stack(line.get_data_3d())
    x, y = line.get_data()
    return np.column_stack([x, y])


@pytest.fixture(autouse=True)
def _close():
    yield
    plt.close("all")


@pytest.mark.parametrize("name, q", [("fighter", [30, 45, 60]), ("puma560", [10, -20, 30, 40, 50, 60]),
                                     ("planar3", [30, 45, 60]), ("planar2", [-20, 110])])
def test_plotted_origins_are_fk_frames(name, q):
    r = armkit.load(name)
    qv = np.radians(q)
    fig = plot_arm(r, qv)
    F = armkit.fk_frames(r, qv)
    got = _xyz(_artist(fig, "origins:0"))
    want = F[:, :3, 3][:, : got.shape[1]]
    np.testing.assert_allclose(got, want, atol=1e-12)
    # the link polyline passes through every frame origin, in order
    poly = _xyz(_artist(fig, "arm:0"))
    idx = [int(np.argmin(np.linalg.norm(poly - p, axis=1))) for p in want]
    assert all(np.linalg.norm(poly[i] - p) < 1e-9 for i, p in zip(idx, want))
    assert idx == sorted(idx)
    ax = fig.axes[0]
    assert ax.get_xlabel() == f"x ({r.unit})" and ax.get_ylabel() == f"y ({r.unit})"
    assert ("3d" == ax.name) == (name not in ("planar2", "planar3"))


def test_fighter_hand_derived_points():
    """The fighting-robot report's geometry: shoulder at (0, 0, 36), elbow at 77.2 (c1 c2, s1 c2, ...) above it."""
    r = armkit.load("fighter")
    t1, t2, t3 = np.radians([30, 45, 60])
    fig = plot_arm(r, [t1, t2, t3])
    pts = _xyz(_artist(fig, "arm:0"))
    elbow = np.array([77.2 * math.cos(t1) * math.cos(t2), 77.2 * math.sin(t1) * math.cos(t2),
                      36 + 77.2 * math.sin(t2)])
    tip = elbow + 100 * np.array([math.cos(t1) * math.cos(t2 + t3), math.sin(t1) * math.cos(t2 + t3),
                                  math.sin(t2 + t3)])
    np.testing.assert_allclose(pts, [[0, 0, 0], [0, 0, 36], elbow, tip], atol=1e-9)
    assert "yaw = 30.0°" in fig.axes[0].get_title() and "mm" in fig.axes[0].get_title()


def test_overlay_of_branches_is_labelled():
    r = armkit.load("planar2")
    qs = np.radians([[30.0, 45.0], [75.0, -45.0]])
    fig = plot_arm(r, qs, labels=["elbow-down", "elbow-up"])
    for i, q in enumerate(qs):
        got = _xyz(_artist(fig, f"origins:{i}"))
        np.testing.assert_allclose(got, armkit.fk_frames(r, q)[:, :2, 3], atol=1e-12)
    texts = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert texts[:2] == ["elbow-down", "elbow-up"]


def test_bad_input_messages():
    r = armkit.load("fighter")
    with pytest.raises(armkit.ShapeError, match=r"shape \(\.\.\., 3\)"):
        plot_arm(r, [1.0, 2.0])
    with pytest.raises(armkit.ShapeError, match="one entry per configuration"):
        plot_arm(r, np.zeros((2, 3)), labels=["only one"])
