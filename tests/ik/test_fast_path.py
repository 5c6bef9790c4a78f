"""The short path of ``armkit.ik`` / ``armkit.ik_all`` for one target with default options (issue 19).

``api._fast`` answers the common call (one float64 pose or position, no ``tol``, ``scene``, ``branch``,
...) from the robot's cached one-call record without the general argument handling. It must give what
the batched path gives (``api.ONE_CALL = False``: :func:`armkit.ik.analytic.solve_all` and
``solve_nearest``), field by field and type by type, and every argument it does not take must still be
checked and honoured by the general code. The fighter (a robot with its own collision scene) keeps its
check: the nearest branch that does not collide, on targets where the nearest collides and where it
does not.
"""

from __future__ import annotations

import importlib
import importlib.util

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit.errors import IKInputError
from armkit.ik.analytic import closed_form

from test_single_call import _assert_same as _same   # field by field, type by type

api = importlib.import_module("armkit.ik.api")


@pytest.fixture(scope="module", autouse=True)
def compiled():
    armkit.set_backend("numba")    # the one-call path serves the Numba back end only
    if importlib.util.find_spec("numba") is None or closed_form(armkit.load("ur5")) is None:
        pytest.skip("Numba is not available")
    yield
    armkit.set_backend("auto")


def _batched(fn):
    try:
        api.ONE_CALL = False
        return fn()
    finally:
        api.ONE_CALL = True


def _taken(monkeypatch, fn):
    """``fn()`` with the general one-call entry disabled: only the short path may answer."""
    def refuse(*args, **kwargs):
        raise AssertionError("the general path was taken")

    monkeypatch.setattr(api, "_one_target", refuse)
    monkeypatch.setattr(api, "_targets_and_start", refuse)
    try:
        return fn()
    finally:
        monkeypatch.undo()


@pytest.mark.parametrize("name", ["ur5", "puma560", "planar2", "planar3"])
def test_default_calls_take_the_short_path_and_equal_the_batched_one(name, rng, monkeypatch):
    robot = armkit.load(name)
    for _ in range(5):
        q = robot.random_q(rng=rng)
        T = armkit.fk(robot, q)
        target = T[:3, 3].copy() if name == "planar2" else T
        for fn in (armkit.ik, armkit.ik_all):
            for kw in ({}, {"q0": rng.uniform(-4.0, 4.0, robot.n)}, {"enforce_limits": False}, {"check": False}):
                fast = _taken(monkeypatch, lambda: fn(robot, target, **kw))
                _same(fast, _batched(lambda: fn(robot, target, **kw)))
        assert bool(armkit.ik(robot, target, q0=q).success)     # and it answers: FK of its q is the target


def test_arguments_the_short_path_does_not_take_are_still_checked():
    ur5 = armkit.load("ur5")
    T = armkit.fk(ur5, np.array([0.3, -1.0, 1.2, 0.4, 0.9, -0.2]))
    with pytest.raises(IKInputError):
        armkit.ik(ur5, T, seed=-1)                  # a bad seed is an error even where the closed form answers
    with pytest.raises(IKInputError):
        armkit.ik(ur5, T, max_iterations=0)
    with pytest.raises(IKInputError):
        armkit.ik("ur5", T)                          # a robot's name is not a robot
    with pytest.raises(IKInputError):
        armkit.ik_all("ur5", T)
    with pytest.raises(IKInputError):
        armkit.ik(ur5, T, method="nope")
    with pytest.raises(IKInputError):
        armkit.ik(ur5, T, tol=-1.0)


def test_options_beside_the_defaults_are_honoured():
    """A tolerance, float32 and list targets and a wrong-length start reach the general code and mean there
    what they always meant."""
    ur5 = armkit.load("ur5")
    q = np.array([0.3, -1.0, 1.2, 0.4, 0.9, -0.2])
    T = armkit.fk(ur5, q)
    Tmoved = T.copy()
    Tmoved[0, 3] += 1e-4                            # 0.1 mm beside the reachable target... still reachable
    loose = armkit.ik(ur5, Tmoved, tol=1e-3)
    assert bool(loose.success)
    for target in (T.astype(np.float32), T.tolist()):
        res = armkit.ik(ur5, target, q0=q)
        assert bool(res.success)
        assert np.allclose(armkit.fk(ur5, res.q), T, atol=1e-6)
    with pytest.raises(Exception):
        armkit.ik(ur5, T, q0=np.zeros(5))


def test_a_backend_switch_leaves_the_short_path():
    """With the NumPy back end the short path steps aside: the answer is the NumPy solver's."""
    ur5 = armkit.load("ur5")
    T = armkit.fk(ur5, np.array([0.3, -1.0, 1.2, 0.4, 0.9, -0.2]))
    armkit.ik(ur5, T)                                # the robot's short-path record is made
    armkit.set_backend("numpy")
    try:
        res = armkit.ik_all(ur5, T)
        assert res.success.any()
    finally:
        armkit.set_backend("numba")
    assert armkit.ik_all(ur5, T).shape == res.shape


_FIGHTER: dict = {}


def _fighter():
    if "arm" not in _FIGHTER:
        _FIGHTER["arm"] = armkit.load("fighter")
    return _FIGHTER["arm"]


@settings(max_examples=25, deadline=None)
@given(u=st.lists(st.floats(0.0, 1.0), min_size=3, max_size=3), far=st.sampled_from([1.0, 1.0, 1.0, 1.5]))
def test_fighter_with_its_scene_equals_the_batched_path(u, far):
    fighter = _fighter()
    q = fighter.lower + (fighter.upper - fighter.lower) * np.asarray(u)
    p = armkit.fk(fighter, q)[:3, 3] * far
    for fn in (armkit.ik, armkit.ik_all):
        _same(fn(fighter, p), _batched(lambda: fn(fighter, p)))


def test_fighter_targets_where_the_nearest_collides_and_where_it_does_not(rng):
    """Both cases of the fighter's short cut occur, and each answer is the batched path's."""
    fighter = _fighter()
    seen = set()
    for _ in range(40):
        p = armkit.fk(fighter, fighter.random_q(rng=rng))[:3, 3]
        every = armkit.ik_all(fighter, p)
        seen.add("collision" in set(np.asarray(every.reason).tolist()))
        _same(every, _batched(lambda: armkit.ik_all(fighter, p)))
        _same(armkit.ik(fighter, p), _batched(lambda: armkit.ik(fighter, p)))
        if seen == {True, False}:
            break
    assert seen == {True, False}


def test_a_robot_that_has_solved_pickles_and_its_copy_solves_alike():
    """The one-call records in ``robot.cache`` refer to compiled code: a pickled robot leaves them behind and
    its copy makes its own when first used (the same answer)."""
    import pickle

    ur5 = armkit.load("ur5")
    T = armkit.fk(ur5, np.array([0.3, -1.0, 1.2, 0.4, 0.9, -0.2]))
    before = armkit.ik_all(ur5, T)
    copy = pickle.loads(pickle.dumps(ur5))
    _same(armkit.ik_all(copy, T), before)
    _same(armkit.ik(copy, T), armkit.ik(ur5, T))
