"""7-joint arms: ``ik_all(robot, T, fixed={...})`` holds joints, and ``ik_all`` sweeps the lockable joint.

References are independent of the solver: the configuration a target was made from must be among
the successful branches (up to whole turns) when its held (or swept) joint has the value the solver
was given, every successful branch must reproduce the target by ``armkit.fk`` of the full 7-joint
model, and the held value must come back bit for bit. The sweep's values are the ones its docstring
promises (``numpy.linspace`` over the limits, written out here by hand).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import armkit
from armkit.errors import IKInputError
from armkit.ik.geometric.locked import DEFAULT_SWEEP, lock, sweep_values
from armkit.ik.geometric.poe import poe
from armkit.model.robot import Joint, Robot

TOL = 1e-9


def _wrapped(a: np.ndarray) -> np.ndarray:
    return (a + np.pi) % (2 * np.pi) - np.pi


@pytest.fixture(scope="module")
def panda() -> Robot:
    return armkit.load("panda")


@pytest.fixture(scope="module")
def iiwa() -> Robot:
    return armkit.load("iiwa14")


def _random_q(robot: Robot, count: int, seed: int) -> np.ndarray:
    """Configurations well inside the limits (5 % margin), away from the limits' edges."""
    rng = np.random.default_rng(seed)
    lo, hi = robot.lower, robot.upper
    margin = 0.05 * (hi - lo)
    return rng.uniform(lo + margin, hi - margin, size=(count, robot.n))


def _check(robot: Robot, res: armkit.IKResult, T: np.ndarray, q: np.ndarray, held: dict[int, float]) -> None:
    """Every success reproduces T by FK of the full arm, holds the held values exactly; q is among them."""
    ok = np.asarray(res.success)
    assert ok.any()
    good = res.q[ok]
    back = armkit.fk(robot, good)
    assert np.abs(back[:, :3, 3] - T[:3, 3]).max() <= TOL
    assert np.abs(back[:, :3, :3] - T[:3, :3]).max() <= 2 * TOL
    for k, v in held.items():
        assert np.all(good[:, k] == v)                      # exact, not close
    gap = np.abs(_wrapped(good - q)).max(axis=-1)
    assert gap.min() < 1e-7, gap.min()


# ------------------------------------------------------------------------------ the locked chain
@pytest.mark.parametrize("name", ["panda", "iiwa14", "stanford"])
def test_lock_keeps_the_forward_kinematics(name):
    """``lock(f, k, t)`` is the same arm with joint k frozen at t (revolute and prismatic joints)."""
    robot = armkit.load(name)
    form = poe(robot)
    rng = np.random.default_rng(3)
    for q in rng.uniform(-2.5, 2.5, size=(5, robot.n)):
        T = armkit.fk(robot, q)
        for k in range(robot.n):
            R, p = lock(form, k, float(q[k])).fk(np.delete(q, k))
            assert np.allclose(R, T[:3, :3], atol=1e-12) and np.allclose(p, T[:3, 3], atol=1e-12), (k, q)


def test_sweep_values_are_the_documented_grid(panda):
    lo, hi = panda.lower[5], panda.upper[5]
    v = sweep_values(panda, 5, 32)
    assert len(v) == 32 and v[0] == lo and v[-1] == hi
    assert np.allclose(np.diff(v), (hi - lo) / 31)
    free = Robot([Joint(a=0.3, lower=-math.inf, upper=math.inf)], name="free")
    assert np.allclose(sweep_values(free, 0, 4), [-math.pi, -math.pi / 2, 0.0, math.pi / 2])


# ------------------------------------------------------------------------------------- fixed=
@pytest.mark.parametrize("name, joint", [("panda", "panda_joint6"), ("iiwa14", "A3"), ("iiwa14", "A5")])
def test_fixed_every_branch(name, joint):
    robot = armkit.load(name)
    k = robot.joint_names.index(joint)
    for q in _random_q(robot, 6, seed=k):
        T = armkit.fk(robot, q)
        res = armkit.ik_all(robot, T, fixed={joint: q[k]})
        assert res.q.shape == (8, 7)
        _check(robot, res, T, q, {k: q[k]})
        assert all(("held at" in str(m)) for m in np.asarray(res.message)[res.success])


def test_fixed_batched_matches_one_by_one(iiwa):
    qs = _random_q(iiwa, 4, seed=11)
    T = armkit.fk(iiwa, qs)
    many = armkit.ik_all(iiwa, T, fixed={"A3": 0.4})
    assert many.q.shape == (4, 8, 7)
    for b in range(4):
        one = armkit.ik_all(iiwa, T[b], fixed={"A3": 0.4})
        assert np.array_equal(one.success, many.success[b])
        assert np.allclose(one.q, many.q[b], atol=1e-12)
        assert np.all(many.q[b][..., 2] == 0.4)


def test_fixed_value_outside_the_limits_fails_by_limits(iiwa):
    q = _random_q(iiwa, 1, seed=5)[0]
    q[2] = 3.05                                   # beyond A3's limit (2.967)
    T = armkit.fk(iiwa, q)
    res = armkit.ik_all(iiwa, T, fixed={"A3": q[2]})
    assert not res.success.any()
    assert "joint limits" in set(np.asarray(res.reason).tolist())
    free = armkit.ik_all(iiwa, T, fixed={"A3": q[2]}, enforce_limits=False)
    _check(iiwa, free, T, q, {2: q[2]})


# ---------------------------------------------------------------------------------- the sweep
@pytest.mark.parametrize("name, k", [("panda", 5), ("iiwa14", 2)])
def test_sweep_finds_the_generating_configuration(name, k):
    """With the swept joint set to one of the sweep's values, the configuration is among the branches."""
    robot = armkit.load(name)
    values = np.linspace(robot.lower[k], robot.upper[k], DEFAULT_SWEEP)
    for i, q in enumerate(_random_q(robot, 3, seed=20 + k)):
        q[k] = values[7 + 9 * i]
        T = armkit.fk(robot, q)
        res = armkit.ik_all(robot, T)
        assert res.q.shape == (DEFAULT_SWEEP * 8, 7)
        _check(robot, res, T, q, {})
        labels = np.asarray(res.branch)
        swept = {lab.split("/")[0] for lab in labels}
        assert len(swept) == DEFAULT_SWEEP and all(s.startswith(robot.joint_names[k] + "=") for s in swept)
        assert set(np.unique(res.q[:, k])) <= set(values)
        ok = np.asarray(res.success)        # each branch holds the value its label names
        named = np.array([float(lab.split("=")[1].split("/")[0]) for lab in labels[ok]])
        assert np.abs(named - res.q[ok, k]).max() <= 5e-5
        assert all(f"swept over {DEFAULT_SWEEP} values" in m for m in np.asarray(res.message)[ok])


def test_sweep_count_keyword(panda):
    q = _random_q(panda, 1, seed=2)[0]
    res = armkit.ik_all(panda, armkit.fk(panda, q), sweep=5)
    assert res.q.shape == (5 * 8, 7)
    assert np.allclose(np.unique(res.q[:, 5]), np.linspace(panda.lower[5], panda.upper[5], 5))


def test_sweep_on_the_example_robot_data_panda():
    robot = armkit.load("example-robot-data:panda")
    k = robot.joint_names.index("panda_joint6")
    values = sweep_values(robot, k)
    q = _random_q(robot, 1, seed=9)[0]
    q[k] = values[12]
    T = armkit.fk(robot, q)
    _check(robot, armkit.ik_all(robot, T), T, q, {})


# ------------------------------------------------------------------------------------- errors
@pytest.mark.parametrize("kwargs, message", [
    ({"fixed": {"A9": 0.1}}, "no joint named 'A9'.* the joints are A1, A2"),
    ({"fixed": [("A3", 0.1)]}, "fixed must be a dict"),
    ({"fixed": {"A3": float("nan")}}, "finite number"),
    ({"fixed": {"A3": "x"}}, "must be a number"),
    ({"sweep": 0}, "sweep must be an integer between 1 and 10,000"),
    ({"sweep": True}, "sweep must be an integer"),
    ({"sweep": 8, "fixed": {"A3": 0.1}}, "not both"),
    ({"fixed": {"A1": 0.1, "A2": 0.2}}, "leaves a 5-joint chain .* without a closed form"),
    ({"fixed": {f"A{i}": 0.1 for i in range(1, 8)}}, "holds every joint"),
])
def test_bad_arguments(iiwa, kwargs, message):
    with pytest.raises(IKInputError, match=message):
        armkit.ik_all(iiwa, armkit.fk(iiwa, np.full(7, 0.3)), **kwargs)


def test_position_targets_and_six_joint_arms(iiwa):
    with pytest.raises(IKInputError, match="needs a pose target"):
        armkit.ik_all(iiwa, [0.3, 0.2, 0.5])
    with pytest.raises(IKInputError, match="leaves 6 joints .* without a closed form for a position"):
        armkit.ik_all(iiwa, [0.3, 0.2, 0.5], fixed={"A3": 0.2})
    ur5 = armkit.load("ur5")
    with pytest.raises(IKInputError, match="sweep= is for 7-joint arms"):
        armkit.ik_all(ur5, armkit.fk(ur5, np.full(6, 0.3)), sweep=8)
    with pytest.raises(IKInputError, match="do not go with pitch="):
        armkit.ik_all(iiwa, [0.3, 0.2, 0.5], pitch=0.3, fixed={"A3": 0.2})


def test_the_notes_of_held_and_swept_branches_read_in_korean():
    from armkit.locale.library import fielded, localize

    panda = armkit.load("panda")
    T = armkit.fk(panda, np.array([0.3, -0.5, 0.2, -2.0, 0.4, 1.6, 0.7]))
    held = armkit.ik_all(panda, T, fixed={"panda_joint6": 1.6})
    swept = armkit.ik_all(panda, T)
    for res, english, korean in ((held, "panda_joint6 held at 1.6", "1.6에 고정"),
                                 (swept, "panda_joint6 swept over 32 values from", "값 32개로 스윕")):
        note = res.message[res.success][0]
        assert fielded(note) is not None and note.startswith(english)
        assert korean in localize(note, "ko") and "swept" not in localize(note, "ko")
