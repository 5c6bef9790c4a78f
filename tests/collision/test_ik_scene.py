"""IK with a scene: success means collision-free; failures say which pair collides and by how much."""

from __future__ import annotations

import importlib
import subprocess
import sys

import numpy as np
import pytest

import armkit
from armkit.collision import Scene, collisions

from test_query import reference


def table_and_wall(robot):
    R = robot.reach
    return Scene([Scene.box([0.45 * R, 0.0, -0.05 * R], [0.5 * R, 0.8 * R, 0.1 * R], name="table"),
                  Scene.box([0.0, -0.55 * R, 0.3 * R], [2 * R, 0.04 * R, 1.2 * R], name="wall")])


def _targets(robot, count, seed):
    q = robot.random_q(count, rng=seed)
    T = armkit.fk(robot, q)
    return T[..., :3, 3] if robot.name in ("fighter", "planar2") else T


@pytest.mark.parametrize("name", ["fighter", "planar2", "puma560", "ur5"])
def test_ik_all_success_means_collision_free(name):
    robot = armkit.load(name)
    scene = table_and_wall(robot)
    target = _targets(robot, 60, 1)
    res = armkit.ik_all(robot, target, scene=scene)
    plain = armkit.ik_all(robot, target, scene=False)   # scene=False: no check (None is the robot's own)
    ok = np.asarray(res.success)
    assert ok.any() and (np.asarray(res.reason) == "collision").any()
    # wrong = a success that collides (checked with coal, built independently) or misses the target
    for b, k in zip(*np.nonzero(ok)):
        assert reference(robot, res.q[b, k], scene).min() >= 0
    assert np.all(res.position_error[ok] <= 1e-9 / robot.unit_scale)
    # a collision failure is a branch that solved without the scene, with the pair and depth in the message
    for b, k in zip(*np.nonzero(np.asarray(res.reason) == "collision")):
        assert reference(robot, res.q[b, k], scene).min() < 0
        assert " hits the " in res.message[b, k] and robot.unit in res.message[b, k]
    assert ok.sum(axis=1).tolist() <= plain.success.sum(axis=1).tolist()
    # successful branches first
    assert np.all(np.diff(ok.astype(int), axis=1) <= 0)


@pytest.mark.parametrize("name", ["fighter", "puma560"])
def test_ik_nearest_branch_is_collision_free(name):
    robot = armkit.load(name)
    scene = table_and_wall(robot)
    target = _targets(robot, 40, 2)
    res = armkit.ik(robot, target, scene=scene)
    every = armkit.ik_all(robot, target, scene=scene)
    np.testing.assert_array_equal(res.success, every.success.any(axis=1))
    for b in np.nonzero(res.success)[0]:
        assert not collisions(robot, res.q[b], scene).colliding


@pytest.mark.parametrize("name", ["fighter", "puma560", "ur5"])
def test_one_target_answer_is_the_first_of_every_branch_marked_and_sorted(name):
    """One target by the one-call path with a scene: the yes/no check picks the first successful branch that does
    not collide, which must be what marking every branch (collisions named) and sorting them puts first, whether
    the nearest branch collides, a farther one does, or all do (then the answer names the collision)."""
    robot = armkit.load(name)
    kinds = set()
    for scene in (table_and_wall(robot), None):      # None: the robot's own surroundings (the fighter's torso)
        for target in _targets(robot, 40, 3):
            res = armkit.ik(robot, target, scene=scene)
            every = armkit.ik_all(robot, target, scene=scene)
            first = every[0]
            plain = armkit.ik_all(robot, target, scene=False)   # no check: the nearest successful branch first
            if plain.success[0]:
                kinds.add("nearest free" if plain.branch[0] == first.branch and first.success else "nearest collides")
            kinds.add("one free" if every.success.any() else "none free")
            assert res.q.shape == (robot.n,) and np.array_equal(res.q, first.q)
            assert (bool(res.success), str(res.branch), str(res.reason), str(res.message)) == \
                (bool(first.success), str(first.branch), str(first.reason), str(first.message))
            assert float(res.position_error) == float(first.position_error)
    assert kinds == {"nearest collides", "nearest free", "one free", "none free"}


@pytest.mark.parametrize("name", ["panda", "iiwa14", "fighter"])
def test_lm_restarts_away_from_collisions(name):
    robot = armkit.load(name)
    scene = table_and_wall(robot)
    target = _targets(robot, 20, 3)
    free = ~collisions(robot, robot.random_q(20, rng=3), scene).colliding   # targets with a known free answer
    res = armkit.ik(robot, target, method="lm", seed=4, scene=scene)
    for b in range(len(target)):
        if res.success[b]:
            assert reference(robot, res.q[b], scene).min() >= 0
        else:
            assert res.reason[b] in ("collision", "max iterations", "unreachable", "joint limits", "singular")
            if res.reason[b] == "collision":
                assert reference(robot, res.q[b], scene).min() < 0
    assert res.success.sum() >= 0.7 * free.sum() and free.sum() >= 5


def test_fighter_under_the_floor():
    arm = armkit.load("fighter")
    every = armkit.ik_all(arm, [100, 0, -30], scene="robot")
    assert not every.success.any() and set(every.reason.tolist()) == {"collision"}
    assert "the forearm hits the ground by 13 mm" in every.message.tolist()
    one = armkit.ik(arm, [100, 0, -30], scene="robot")
    assert not one.success and one.reason == "collision"
    # the default is the robot's own surroundings; scene=False gives the old answer (four branches under the floor)
    assert not armkit.ik_all(arm, [100, 0, -30]).success.any()
    assert armkit.ik_all(arm, [100, 0, -30], scene=False).success.all()


def _cli(*args):
    return subprocess.run([sys.executable, "-c", "from armkit.cli import main; main()", *args], capture_output=True,
                          text=True, timeout=300)


def test_cli_ik_fighter_collides_with_its_ground():
    out = _cli("ik", "fighter", "100", "0", "-30")
    assert out.returncode == 1
    assert "collision: the forearm hits the ground by 13 mm" in " ".join(out.stderr.split())
    assert _cli("ik", "fighter", "100", "0", "-30", "--no-scene").returncode == 0


def test_cli_scene_file_errors_exit_2(tmp_path):
    bad = tmp_path / "scene.toml"
    bad.write_text('unit = "mm"\n\n[[shapes]]\ntype = "box"\ncenter = [0, 0, 0]\nsize = [10, -1, 10]\n')
    out = _cli("ik", "fighter", "100", "0", "60", "--scene", str(bad))
    assert out.returncode == 2
    assert "scene.toml:6: shapes[1].size" in " ".join(out.stderr.split())
    good = tmp_path / "ok.toml"
    good.write_text('unit = "mm"\n\n[[shapes]]\ntype = "plane"\nnormal = [0, 0, 1]\noffset = -30\n')
    out = _cli("ik", "fighter", "100", "0", "60", "--scene", str(good), "--json")
    assert out.returncode == 0


def test_a_chosen_branch_that_collides_has_the_fields_of_one_that_does_not():
    """``branch=`` with a scene: a branch marked as colliding keeps each field's kind (0-d arrays, the message as
    its text), as an unmarked one has them; marking once turned ``success`` into a NumPy scalar."""
    fighter = armkit.load("fighter")
    for seed in range(60):
        p = armkit.fk(fighter, fighter.random_q(rng=seed))[:3, 3]
        every = armkit.ik_all(fighter, p)
        hit = [str(b) for b, r in zip(every.branch, every.reason) if r == "collision"]
        free = [str(b) for b, ok in zip(every.branch, every.success) if ok]
        if hit and free:
            break
    bad, good = armkit.ik(fighter, p, branch=hit[0]), armkit.ik(fighter, p, branch=free[0])
    assert str(bad.reason) == "collision" and not bad.success and good.success
    for f in ("q", "success", "position_error", "rotation_error", "iterations", "branch", "within_limits", "reason",
              "message"):
        assert type(getattr(bad, f)) is type(getattr(good, f)) or f == "message", f
    assert isinstance(bad.message, str) and " hits the " in bad.message


@pytest.mark.parametrize("call", ["ik", "ik_all", "ik_all batch"])
def test_collision_sentences_are_made_when_read_and_name_the_pair(call, monkeypatch):
    """A loop that reads only ``success`` measures no depth: the sentences of the branches that collide are made
    when ``message`` is first read, once, and are then those of ``collisions(...).message()`` (the depth measured
    on its own) for each of them, also after the branches are sorted or the result is indexed."""
    ik_scene = importlib.import_module("armkit.ik.scene")   # (armkit.ik is also the function's name)
    robot = armkit.load("fighter")
    made = []
    real = ik_scene.row_messages

    def counted(*args, **kw):
        made.append(len(args[1]))
        return real(*args, **kw)

    monkeypatch.setattr(ik_scene, "row_messages", counted)
    scene = table_and_wall(robot)
    targets = _targets(robot, 40, 5)
    if call == "ik_all batch":
        res = armkit.ik_all(robot, targets, scene=scene)
    else:   # the first target whose nearest configuration collides
        solve = getattr(armkit, call)
        res = next(r for r in (solve(robot, t, scene=scene) for t in targets)
                   if (np.asarray(r.reason) == "collision").any())
    hit = np.asarray(res.reason) == "collision"
    assert hit.any() and not np.asarray(res.success)[hit].any() and made == []
    picked = res[0] if call == "ik_all batch" else res      # a part of a result made before its sentences
    messages = np.asarray(res.message, dtype=object)
    assert made == [int(hit.sum())]                          # one pass over the colliding branches, when read
    q = np.asarray(res.q)
    for idx in zip(*np.nonzero(hit)) if hit.ndim else [()]:
        assert messages[idx] == collisions(robot, q[idx], scene).message(), idx
        assert " hits the " in messages[idx] and "mm" in messages[idx]
    assert all(m == "" for m in messages[np.asarray(res.success)])   # a success has no sentence
    if call == "ik_all batch":
        assert list(picked.message) == list(messages[0])     # the part's sentences are the whole's
    res.message                                              # noqa: B018 - read again: made once
    assert len(made) == 1
