"""The class pictures (armkit.viz.axes): what is drawn follows the axes, not the robot's name."""

from __future__ import annotations

import numpy as np
import pytest

import armkit
from armkit.ik.geometric.classify import classify
from armkit.ik.geometric.poe import poe
from armkit.viz.axes import GALLERY, class_gallery, plot_axes, random_chain

pytest.importorskip("matplotlib")


def _axis_lines(ax, n):
    return ax.lines[:n]          # plot_axes draws the n joint axes first, then the links


def test_axis_lines_lie_on_the_joint_axes():
    """Each drawn axis line passes through the joint's point at q = 0 along its direction (the POE form)."""
    robot = armkit.load("ur5")
    form = poe(robot)
    pts = np.cumsum(form.P[:-1], axis=0)
    ax = plot_axes(robot)
    for j, line in enumerate(_axis_lines(ax, robot.n)):
        xs, ys, zs = line.get_data_3d()
        a, b = np.array([xs[0], ys[0], zs[0]]), np.array([xs[1], ys[1], zs[1]])
        mid, d = (a + b) / 2, (b - a) / np.linalg.norm(b - a)
        np.testing.assert_allclose(mid, pts[j], atol=1e-12)
        assert abs(abs(d @ form.H[j]) - 1.0) < 1e-12


def test_parallel_axes_share_a_colour_and_meeting_points_get_a_star():
    """UR5: axes 2, 3, 4 parallel (one colour, not the others'); the Puma: two groups meet (1-2, 4-5-6)."""
    ax = plot_axes(armkit.load("ur5"))
    colours = [line.get_color() for line in _axis_lines(ax, 6)]
    assert colours[1] == colours[2] == colours[3]
    assert len({colours[0], colours[1]}) == 2 and colours[0] == colours[4] == colours[5]
    ax = plot_axes(armkit.load("puma560"))
    stars = ax.collections
    assert len(stars) == len([g for g in classify(armkit.load("puma560")).intersecting if len(g) >= 2]) == 2
    centre = np.asarray(stars[-1]._offsets3d).ravel()     # the wrist centre: on axes 4, 5 and 6
    form = poe(armkit.load("puma560"))
    pts = np.cumsum(form.P[:-1], axis=0)
    for j in (3, 4, 5):
        r = centre - pts[j]
        assert np.linalg.norm(r - (r @ form.H[j]) * form.H[j]) < 1e-9


@pytest.mark.parametrize("k", range(len(GALLERY)))
def test_random_chains_have_the_class_their_panel_names(k):
    title, name, meet, par = GALLERY[k]
    if name is not None:
        pytest.skip("a bundled robot")
    expected = {"spherical wrist, generic": "6R-spherical-wrist", "two intersecting": "6R-two-intersecting",
                "two parallel": "6R-two-parallel", "general 6R": "6R-general"}[title]
    assert classify(random_chain(3 + k, meet, par)).name == expected


def test_gallery_is_written(tmp_path):
    fig = class_gallery()
    assert len(fig.axes) == len(GALLERY)
    out = tmp_path / "classes.png"
    fig.savefig(out)
    assert out.stat().st_size > 10_000
