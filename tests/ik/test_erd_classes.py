"""Every arm of example-robot-data that armkit knows by name gets a geometric class with a solver, and
`ik_all` answers a pose it reached itself (the arm's own FK, a random configuration inside its limits)."""

from __future__ import annotations

import numpy as np
import pytest

import armkit
from armkit.ik.geometric.classify import classify
from armkit.model.erd import ROBOTS, robots_folder

pytestmark = pytest.mark.skipif(robots_folder() is None, reason="example-robot-data is not installed")

# the class each arm must get, from its axes (read off the URDFs: which joint axes meet or are parallel)
EXPECTED = {
    "ur3": "6R-three-parallel-two-intersecting", "ur5": "6R-three-parallel-two-intersecting",
    "ur10": "6R-three-parallel-two-intersecting", "kinova": "6R-spherical-wrist-two-intersecting",
}


@pytest.mark.parametrize("name", sorted(ROBOTS))
def test_every_named_arm_has_a_class_and_a_solver(name):
    robot = armkit.load(f"example-robot-data:{name}")
    cls = classify(robot)
    if name in EXPECTED:
        assert cls.name == EXPECTED[name]
    if robot.n >= 6:
        assert cls.solver in ("closed form", "1-D search", "2-D search") or cls.solver.startswith("sweep joint"), \
            (name, cls.name, cls.solver)


@pytest.mark.parametrize("name", ["talos", "tiago", "panda", "kinova", "ur5"])
def test_ik_all_on_the_arm_reaches_its_own_pose(name):
    """Every branch called a success is checked here by FK again; a 6R arm also finds the start q
    (up to whole turns); a 7R arm's sweep finds at least one branch (the swept joint need not hit q's value)."""
    robot = armkit.load(f"example-robot-data:{name}")
    rng = np.random.default_rng(7)
    for _ in range(3):
        q = rng.uniform(np.maximum(robot.lower, -3), np.minimum(robot.upper, 3))
        T = armkit.fk(robot, q)
        res = armkit.ik_all(robot, T)
        ok = np.asarray(res.success)
        assert ok.any(), name
        Tb = armkit.fk(robot, res.q[ok])
        np.testing.assert_allclose(Tb, np.broadcast_to(T, Tb.shape), atol=1e-9)
        if robot.n == 6:
            d = np.angle(np.exp(1j * (res.q[ok] - q)))
            assert np.min(np.max(np.abs(d), axis=-1)) < 1e-6
