"""The packed collision items are remembered per robot under the scene shapes' contents (collision/query.py
``_packed``): a repeated check reuses them, and a moved shape or another scene is packed anew (a shape's
pose is read-only, so a remembered pack cannot go stale under it)."""

from __future__ import annotations

import numpy as np
import pytest

import armkit
from armkit.collision import Scene, clearance, in_collision


@pytest.fixture
def compiled():
    before = armkit.get_backend()
    armkit.set_backend("numba")
    yield
    armkit.set_backend(before)


def arm_radius(arm) -> float:
    """The capsule radius of planar2's links (its file's collision radius), read from the arm's solids."""
    from armkit.collision import arm_geometry

    return float(arm_geometry(arm).solids[-1].size[0])


def test_a_moved_shape_is_packed_anew(compiled):
    arm = armkit.load("planar2")
    q = np.array([[0.0, 0.0]])                        # the arm along +x: link 2 ends at x = 1.5 m
    ball = Scene.sphere([1.0, 0.0, 0.0], 0.1, name="ball")
    scene = Scene([ball])
    assert in_collision(arm, q, scene).tolist() == [True]
    assert in_collision(arm, q, scene).tolist() == [True]   # the same pack again
    with pytest.raises(ValueError):
        ball.pose[:3, 3] = [1.0, 1.0, 0.0]            # a shape cannot change under a remembered pack
    moved = Scene([Scene.sphere([1.0, 1.0, 0.0], 0.1, name="ball")])   # the same name, 1 m off the arm
    assert in_collision(arm, q, moved).tolist() == [False]
    assert clearance(arm, q, moved)[0] == pytest.approx(1.0 - 0.1 - arm_radius(arm), abs=1e-9)
    far = Scene([Scene.sphere([5.0, 0.0, 0.0], 0.1)])
    assert in_collision(arm, q, far).tolist() == [False]
    assert len(arm.cache["collision_packs"]) >= 2     # one pack per scene content


def test_packs_kept_are_bounded(compiled):
    from armkit.collision import query

    arm = armkit.load("planar2")
    q = np.zeros((1, 2))
    for k in range(query.PACKS_KEPT + 5):
        in_collision(arm, q, Scene([Scene.sphere([3.0 + k, 0.0, 0.0], 0.1)]))
        assert len(arm.cache["collision_packs"]) <= query.PACKS_KEPT
