"""The prepared check (collision/query.py ``_prepared``/``_evaluate_prepared``, ``colliding_rows``) against the
general path (``_evaluate`` with the pairs and chain frames rebuilt on every call): the same distances, the
same colliding rows, the same messages, on random configurations."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit.collision import Scene, collisions, in_collision, query
from armkit.collision.geometry import arm_geometry


@pytest.fixture(scope="module")
def compiled():
    before = armkit.get_backend()
    armkit.set_backend("numba")
    yield
    armkit.set_backend(before)


def _general(robot, q, scene, only_min=False, stop=-np.inf):
    geo = arm_geometry(robot)
    scene_pairs, self_pairs = query._pairs(geo, scene, True)
    return query._evaluate(robot, geo, q, scene_pairs, self_pairs, only_min=only_min, stop=stop)


def _robot_and_scene(name):
    robot = armkit.load(name)
    if name == "fighter":
        return robot, query.resolve_scene(robot, None)   # its ground and torso
    return robot, Scene([Scene.plane([0, 1, 0], -0.2, name="floor"), Scene.sphere([0.8, 0.3, 0], 0.2, name="ball")],
                        robot.unit)


@settings(max_examples=25, deadline=None)
@given(name=st.sampled_from(["fighter", "planar2"]), n=st.integers(1, 8), key=st.integers(0, 2**32 - 1))
def test_prepared_equals_general(compiled, name, n, key):
    robot, scene = _robot_and_scene(name)
    q = robot.random_q(n, rng=np.random.default_rng(key)).reshape(n, robot.n)
    d_gen, dist_gen, arg_gen = _general(robot, q, scene)
    res = collisions(robot, q, scene)
    np.testing.assert_array_equal(res.distances, d_gen)
    np.testing.assert_array_equal(res.distance, dist_gen)
    np.testing.assert_array_equal(res.closest, arg_gen)
    _, yes_no_dist, _ = _general(robot, q, scene, only_min=True, stop=0.0)
    expected_rows = np.flatnonzero(yes_no_dist < 0)
    np.testing.assert_array_equal(in_collision(robot, q, scene), yes_no_dist < 0)
    rows, messages = query.colliding_rows(robot, q, scene)
    np.testing.assert_array_equal(rows, expected_rows)
    # each message as the general path's Collisions of those rows words it (pair names from the geometry)
    if len(expected_rows):
        d_rows = _general(robot, q[expected_rows], scene)[0]
        for m, row in enumerate(d_rows):
            order = np.argsort(row, kind="stable")
            hits = [k for k in order if row[k] < 0]
            assert hits, "a colliding row has a negative pair distance"
            assert res.pairs[hits[0]][0].replace("_", " ") in messages[m]
            assert messages[m] == collisions(robot, q[expected_rows[m]], scene).message()


def test_record_follows_the_scene(compiled):
    robot = armkit.load("planar2")
    q = np.array([[0.0, 0.0]])                        # the arm along +x: link 2 ends at x = 1.5 m
    near = Scene([Scene.sphere([1.0, 0.0, 0.0], 0.1, name="ball")])
    far = Scene([Scene.sphere([1.0, 1.0, 0.0], 0.1, name="ball")])
    assert query.colliding_rows(robot, q, near)[0].tolist() == [0]
    assert query.colliding_rows(robot, q, far)[0].tolist() == []
    assert in_collision(robot, q, near).tolist() == [True]
    assert len(robot.cache["collision_prepared"]) == 2
