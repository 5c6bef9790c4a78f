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
    """The arm's own q is among the branches, every solved branch reproduces the target, and no two solved branches
    of a target are the same configuration."""
    T = armkit.fk(robot, q)
    res = armkit.ik_all(robot, T, enforce_limits=False)
    assert res.q.shape[:2] == (len(q), closed_form(robot).m)
    gap = np.abs(np.where(robot.prismatic, res.q - q[:, None], _wrapped(res.q - q[:, None]))).max(axis=-1)
    assert (gap.min(axis=1) < 1e-7).all(), gap.min(axis=1)
    ok = res.success
    back = armkit.fk(robot, res.q[ok])
    Tb = np.broadcast_to(T[:, None], res.q.shape[:2] + (4, 4))[ok]
    assert np.abs(back - Tb).max() < 1e-9 * max(1.0, robot.reach)
    for b in range(len(q)):
        Q = res.q[b][ok[b]]
        d = np.abs(np.where(robot.prismatic, Q[:, None] - Q[None], _wrapped(Q[:, None] - Q[None]))).max(axis=-1)
        assert (d + np.eye(len(Q)) > 1e-6).all(), d


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
    elif kind == "spherical-wrist-meet":       # 4, 5, 6 meet and 1, 2 meet
        pts[1] = pts[0]
        pts[4] = pts[5] = pts[3]
    elif kind == "spherical-wrist-parallel":   # 4, 5, 6 meet and 2 || 3
        H[2] = H[1]
        pts[4] = pts[5] = pts[3]
    elif kind == "three-parallel-meet":        # 2 || 3 || 4 and 5, 6 meet
        H[2] = H[3] = H[1]
        pts[5] = pts[4]
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


# bench_coverage's random three-parallel arm 12 (numpy generator started from 123) and its target 54, as its URDF
# has them: joint origins (m, rpy 0; the last is the tool's, with the rpy below) and axes, i.e. the POE form's P and H
DOUBLE_ROOT_ORIGINS = [(0.06549154387744684, -0.19678750167327294, -0.0071141969382871335),
                       (0.7043953014196311, -0.3884680076945015, 0.07319130309125338),
                       (-0.9466951217193871, 0.8923898884071841, 0.315207274940723),
                       (0.8107030752420095, -0.36689443974576313, -0.06777999214771968),
                       (-1.5202826899430195, 0.16593705222312713, -1.530806775582887),
                       (1.517133998185967, 0.28671748677391434, 1.1392034787459253),
                       (0.4828898299144101, 0.39316040567486316, 0.21977781492770826)]
DOUBLE_ROOT_TOOL_RPY = (0.11928260354432921, 0.3905083938142133, 0.13898772773342447)
DOUBLE_ROOT_AXES = [(0.8220860803847644, 0.32361945385681523, 0.46844949089846544),
                    (-0.7726851139092753, -0.5510371592048341, -0.31514403678076575),
                    (0.7726851139092753, 0.5510371592048341, 0.31514403678076575),
                    (-0.7726851139092753, -0.5510371592048341, -0.31514403678076575),
                    (-0.28374603588382047, 0.9282273730013382, -0.24058705520300214),
                    (-0.798558610392446, -0.2662411629971941, 0.5398331120763037)]
DOUBLE_ROOT_Q = np.array([2.577075716684246, -0.22077885584382528, -0.15782423988104233, -0.00623834214332053,
                          -2.871485443111667, 0.2011016757447881])


def test_a_double_root_is_one_branch_not_two() -> None:
    """SP6 (q1, q5 of a three-parallel arm) has a double root at this target. The quartic's companion matrix gave
    it twice, 1e-7 rad apart, each passing the FK check; the polish then put both on one configuration, and
    ``ik_all`` listed 4 branches where 2 exist, each twice. Every configuration Levenberg-Marquardt reaches from
    300 random starts is among the branches, and no two branches are the same configuration."""
    from test_dense_check import dense_solutions, robot_of

    from armkit.ik.geometric.poe import POE
    from armkit.spatial import rpy_to_rotation

    robot = robot_of(POE(np.array(DOUBLE_ROOT_AXES), np.array(DOUBLE_ROOT_ORIGINS),
                         rpy_to_rotation(np.array(DOUBLE_ROOT_TOOL_RPY)), np.zeros(6, dtype=bool)))
    assert closed_form(robot).solver == "three_parallel"
    T = armkit.fk(robot, DOUBLE_ROOT_Q)
    res = armkit.ik_all(robot, T, enforce_limits=False)
    found = res.q[res.success]
    assert np.abs(armkit.fk(robot, found) - T).max() < 1e-9 * robot.reach
    gaps = np.abs(_wrapped(found[:, None] - found[None])).max(axis=-1) + np.eye(len(found))
    assert gaps.min() > 1e-6, gaps
    reference = dense_solutions(robot, T, 0)
    assert [u for u in reference if not (np.abs(_wrapped(found - u)).max(axis=-1) < 1e-6).any()] == []
    assert len(found) == len(reference)
