"""Workspace sampling against analytic areas/volumes derived here."""

from __future__ import annotations

import math

import numpy as np
import pytest

import armkit
from armkit.analysis import Exclusion, workspace


def test_planar2_annulus_area_within_reported_error():
    # end point at distance |L1 + L2 e^{i q2}| from the base: every radius in [L1 - L2, L1 + L2] for some q2,
    # every direction through q1, so the workspace is the annulus pi ((L1 + L2)^2 - (L1 - L2)^2) = 4 pi L1 L2
    L1, L2 = 1.0, 0.5
    exact = math.pi * ((L1 + L2) ** 2 - (L1 - L2) ** 2)
    ws = workspace(armkit.load("planar2"), samples=60_000, seed=3)
    assert ws.planar and ws.measure_name == "area"
    assert abs(ws.volume - exact) <= ws.volume_error
    assert ws.volume_error < 0.08 * exact           # and the error bar is informative
    assert ws.has_inner_boundary
    assert ws.inner_radius == pytest.approx(L1 - L2, abs=5e-3)
    assert ws.outer_radius == pytest.approx(L1 + L2, abs=5e-3)


def test_fighter_spherical_shell_volume_within_reported_error():
    # the fighting-robot report's arm: yaw about z, then a 77.2/100 mm two-link pitch arm whose shoulder is 36 mm up the yaw axis.
    # From the shoulder the end point reaches every distance in [100 - 77.2, 100 + 77.2] in every direction
    # (pitch over +-180 deg, yaw over +-180 deg): a spherical shell 4/3 pi (R^3 - r^3).
    R, r = 177.2, 22.8
    exact = 4.0 / 3.0 * math.pi * (R ** 3 - r ** 3)
    ws = workspace(armkit.load("fighter"), samples=150_000, seed=5, scene=False)   # the bare shell: no torso, ground
    assert not ws.planar
    np.testing.assert_allclose(ws.centre, [0, 0, 36], atol=1e-9)
    assert abs(ws.volume - exact) <= ws.volume_error
    assert ws.volume_error < 0.3 * exact
    assert ws.has_inner_boundary and ws.inner_radius == pytest.approx(r, abs=0.5)
    assert ws.outer_radius == pytest.approx(R, abs=0.5)


def test_no_inner_boundary_when_the_arm_reaches_its_base():
    ws = workspace(armkit.load("planar3"), samples=20_000, seed=1)   # 1 - 0.8 - 0.3 < 0: reaches the base
    assert not ws.has_inner_boundary


def test_limits_and_ground_exclusion_are_respected():
    r = armkit.load("fighter")
    ex = Exclusion(ground_z=0.0, boxes=[((-60, -60, -100), (60, 60, 20))])
    ws = workspace(r, samples=20_000, seed=2, exclusion=ex)
    assert 0 < len(ws.points) < 20_000 and ws.excluded == 20_000 - len(ws.points)
    assert np.all(r.within_limits(ws.q))
    F = armkit.fk_frames(r, ws.q)
    # the moving joints and the end point stay above the ground and outside the body box
    moving = F[:, 2:, :3, 3]
    assert np.all(moving[..., 2] >= -1e-9)
    lo, hi = np.array([-60, -60, -100]), np.array([60, 60, 20])
    assert not np.any(np.all((moving > lo) & (moving < hi), axis=-1))
    np.testing.assert_allclose(ws.points, F[:, -1, :3, 3], atol=1e-9)


def test_workspace_input_errors():
    r = armkit.load("planar2")
    with pytest.raises(armkit.ArmkitError, match="samples must be an integer >= 100"):
        workspace(r, samples=10)
    with pytest.raises(armkit.ShapeError, match="exclusion box 0"):
        Exclusion(boxes=[((0, 0), (1, 1))])
    with pytest.raises(armkit.ArmkitError, match="nothing is reachable"):
        workspace(r, samples=1000, exclusion=Exclusion(ground_z=10.0))
