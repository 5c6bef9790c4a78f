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
