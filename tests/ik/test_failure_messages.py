"""The failed branches' messages are the same whether a call had few branches (filled element by element)
or many (filled by array operations): armkit.ik.analytic._failure_messages."""

from __future__ import annotations

import numpy as np
import pytest

import armkit
from armkit.ik import analytic


def _targets(robot, n, seed):
    """FK of random configurations, a third of them pushed out of reach (position doubled)."""
    rng = np.random.default_rng(seed)
    q = rng.uniform(-np.pi, np.pi, (n, robot.n))
    T = armkit.fk(robot, q)
    T[::3, :3, 3] *= 2.0
    return T


@pytest.mark.parametrize("name", ["ur5", "puma560", "planar3", "fighter"])
def test_few_and_many_branches_give_the_same_messages(name):
    robot = armkit.load(name)
    T = _targets(robot, 45, 5)     # 45 targets x 2-8 branches: more than analytic.FEW
    if robot.name == "planar3":
        phi = np.linspace(-3, 3, len(T))
        many = armkit.ik_all(robot, T[:, :2, 3], phi=phi)
        few = [armkit.ik_all(robot, T[k, :2, 3], phi=phi[k]) for k in range(len(T))]
    else:
        target = T[:, :3, 3] if robot.n == 3 else T
        many = armkit.ik_all(robot, target)
        few = [armkit.ik_all(robot, target[k]) for k in range(len(T))]
    assert np.asarray(many.message).size > analytic.FEW     # the array path
    kinds = set()
    for k, one in enumerate(few):
        np.testing.assert_array_equal(one.reason, many.reason[k])
        for a, b in zip(np.asarray(one.message).tolist(), np.asarray(many.message[k]).tolist()):
            assert str(a) == str(b)
            assert getattr(a, "template", None) == getattr(b, "template", None)
            kinds.add(getattr(a, "template", ""))
    if name == "puma560":           # its limits cut some branches: both kinds of message are compared
        assert any(t.startswith("outside the joint limits") for t in kinds)
    assert any(t.startswith("unreachable") for t in kinds)
