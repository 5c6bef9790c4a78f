"""The geometric family in ``armkit.ik_all``: arms the DH-pattern families miss get every branch.

References are independent of the solver: the configuration the target was made from must be
among the branches (up to whole turns), every successful branch must reproduce the target by
FK of the true model, and an arm written two ways (an axis reversed in the file: the same
geometry) must give the same solution set as the hand-written family of the original.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import armkit
from armkit.ik.analytic import closed_form
from armkit.model.robot import Joint, Robot

ERD = Path(sys.prefix) / "lib" / f"python{sys.version_info[0]}.{sys.version_info[1]}" / "site-packages" / \
    "cmeel.prefix" / "share" / "example-robot-data" / "robots"
KINOVA = ERD / "kinova_description/robots/kinova.urdf"


def _wrapped(a: np.ndarray) -> np.ndarray:
    return (a + np.pi) % (2 * np.pi) - np.pi


def _check_every_branch(robot: Robot, q: np.ndarray) -> None:
    """The arm's own q is among the branches, and every solved branch reproduces the target."""
    T = armkit.fk(robot, q)
    res = armkit.ik_all(robot, T, enforce_limits=False)
    assert res.q.shape[:2] == (len(q), closed_form(robot).m)
    gap = np.abs(np.where(robot.prismatic, res.q - q[:, None], _wrapped(res.q - q[:, None]))).max(axis=-1)
    assert (gap.min(axis=1) < 1e-7).all(), gap.min(axis=1)
    ok = res.success
    back = armkit.fk(robot, res.q[ok])
    Tb = np.broadcast_to(T[:, None], res.q.shape[:2] + (4, 4))[ok]
    assert np.abs(back - Tb).max() < 1e-9 * max(1.0, robot.reach)


def _tup(M: np.ndarray) -> tuple:
    return tuple(tuple(float(x) for x in row) for row in M)


def _urdf_twin(robot: Robot, flip: tuple[int, ...]) -> Robot:
    """The same arm as a URDF-convention robot, with the axes of joints ``flip`` reversed (q -> -q)."""
    c = robot.chain
    joints, X = [], c.base.copy()
    prev = np.eye(4)
    for k in range(robot.n):
        A = X @ c.pre[k]
        origin = np.linalg.inv(prev) @ A
        axis = np.array([0.0, 0.0, -1.0 if k in flip else 1.0])
        j = robot.joints[k]
        lo, hi = (-j.upper, -j.lower) if k in flip else (j.lower, j.upper)
        joints.append(Joint(name=j.name, kind=j.kind, lower=lo, upper=hi, origin=_tup(origin), axis=tuple(axis)))
        X = A @ c.post[k]
        prev = A
    tool = np.linalg.inv(prev) @ X @ c.tool
    return Robot(joints, convention="urdf", name=f"{robot.name}-flipped", unit=robot.unit, tool=tool)


def test_kinova_jaco_gets_every_branch() -> None:
    if not KINOVA.is_file():
        pytest.skip("example-robot-data is not installed (test extra)")
    r = armkit.load(str(KINOVA), tip="j2s6s200_end_effector")
    cf = closed_form(r)
    assert cf is not None and cf.family == "geometric"
    rng = np.random.default_rng(5)
    _check_every_branch(r, rng.uniform(-np.pi, np.pi, (40, 6)))


@pytest.mark.parametrize("name, flip", [("puma560", (0,)), ("puma560", (1, 4)), ("ur5", (2,)), ("ur5", (0, 5))])
def test_a_reversed_axis_keeps_the_closed_form_and_its_solutions(name: str, flip: tuple[int, ...]) -> None:
    """Reversing an axis in the file (same geometry) used to lose the closed form (the DH pattern broke)."""
    r = armkit.load(name)
    twin = _urdf_twin(r, flip)
    q = r.random_q(30, rng=2)
    qt = q.copy()
    qt[:, list(flip)] *= -1
    assert np.allclose(armkit.fk(twin, qt), armkit.fk(r, q), atol=1e-12)
    assert closed_form(twin) is not None
    _check_every_branch(twin, qt)
    # the same solution set as the hand-written family of the original arm (mapped through the flip)
    T = armkit.fk(r, q)
    a = armkit.ik_all(r, T, enforce_limits=False)
    b = armkit.ik_all(twin, T, enforce_limits=False)
    for i in range(len(q)):
        qa = a.q[i][a.success[i]]
        qb = b.q[i][b.success[i]].copy()
        qb[:, list(flip)] *= -1
        assert len(qa) == len(qb)
        d = np.abs(_wrapped(qa[:, None] - qb[None])).max(axis=-1)
        assert (d.min(axis=1) < 1e-7).all() and (d.min(axis=0) < 1e-7).all()


def _random_arm(rng: np.random.Generator, kind: str) -> Robot:
    """A random 6R arm of a class, in URDF form: axes and offsets random where the class leaves them free."""
    def unit(v):
        return v / np.linalg.norm(v)

    H = np.array([unit(rng.normal(size=3)) for _ in range(6)])
    pts = rng.normal(size=(6, 3)) * 0.3
    if kind == "spherical-general":            # 4, 5, 6 meet in one point, nothing else
        pts[4] = pts[3] + 0.0
        pts[5] = pts[3] + 0.0
    elif kind == "three-parallel":             # 2 || 3 || 4, nothing else
        H[2] = H[1]
        H[3] = -H[1]
    elif kind == "spherical-base":             # 1, 2, 3 meet
        pts[1] = pts[0]
        pts[2] = pts[0]
    joints = []
    prev = np.eye(4)
    for k in range(6):
        A = np.eye(4)
        z = H[k]
        x = unit(np.cross(z, [0.3, 0.5, 0.8]))
        A[:3, :3] = np.column_stack([x, np.cross(z, x), z])
        A[:3, 3] = pts[k]
        joints.append(Joint(name=f"j{k + 1}", kind="revolute", lower=-np.inf, upper=np.inf,
                            origin=_tup(np.linalg.inv(prev) @ A), axis=(0.0, 0.0, 1.0)))
        prev = A
    tool = np.eye(4)
    tool[:3, 3] = rng.normal(size=3) * 0.1
    return Robot(joints, convention="urdf", name=f"random-{kind}", tool=tool)


@pytest.mark.parametrize("kind", ["spherical-general", "three-parallel", "spherical-base"])
@settings(max_examples=12, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**31 - 1))
def test_random_arms_of_each_class(kind: str, seed: int) -> None:
    rng = np.random.default_rng(seed)
    r = _random_arm(rng, kind)
    if closed_form(r) is None:       # a degenerate draw (e.g. axes that happen to line up)
        pytest.skip("degenerate random arm")
    _check_every_branch(r, rng.uniform(-np.pi, np.pi, (4, 6)))


def test_unreachable_target_is_reported_not_invented() -> None:
    r = _urdf_twin(armkit.load("puma560"), (0,))
    T = np.eye(4)
    T[:3, 3] = [5.0, 0.0, 0.0]          # far beyond the Puma's reach
    res = armkit.ik_all(r, T)
    assert not res.success.any()
    assert all(str(m).startswith("unreachable") for m in res.message)


def test_stanford_arm_prismatic_joint_gets_every_branch() -> None:
    """The Stanford arm (RRPRRR: joint 3 slides) had no closed form; axes 1, 2 meet and 4, 5, 6 meet."""
    r = armkit.load("stanford")
    cf = closed_form(r)
    assert cf is not None and cf.family == "geometric"
    rng = np.random.default_rng(11)
    q = r.random_q(25, rng=rng)
    _check_every_branch(r, q)
