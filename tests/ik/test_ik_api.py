"""armkit.ik / armkit.ik_all: target forms, dispatch, branch choice, errors and shapes."""

from __future__ import annotations

import math

import numpy as np
import pytest

import armkit
from armkit.ik import IKInputError, closed_form_family
from armkit.spatial import make_pose, rotx, rotz, transl


@pytest.fixture(scope="module")
def fighter():
    return armkit.load("fighter")


@pytest.fixture(scope="module")
def planar2():
    return armkit.load("planar2")


@pytest.fixture(scope="module")
def planar3():
    return armkit.load("planar3")


def test_public_names():
    assert callable(armkit.ik) and callable(armkit.ik_all)
    assert {"ik", "ik_all", "IKResult"} <= set(armkit.__all__)


def test_auto_uses_the_closed_form_when_the_structure_has_one(fighter):
    res = armkit.ik(fighter, [80.0, 40.0, 120.0])
    assert bool(res.success) and int(res.iterations) == 0 and "/" in str(res.branch)
    assert closed_form_family(fighter) == "yaw-pitch-pitch"


def test_ik_returns_the_branch_nearest_q0(fighter):
    every = armkit.ik_all(fighter, [80.0, 40.0, 120.0])
    for k in range(4):
        res = armkit.ik(fighter, [80.0, 40.0, 120.0], q0=every.q[k] + 0.02)
        assert res.branch == every.branch[k] and np.allclose(res.q, every.q[k])


def test_branch_by_label(planar2):
    up = armkit.ik(planar2, [1.2, 0.3], branch="elbow-up")
    down = armkit.ik(planar2, [1.2, 0.3], branch="elbow-down")
    assert up.q[1] < 0 < down.q[1]                           # target at x > 0: elbow-up is q2 < 0
    with pytest.raises(IKInputError, match="unknown branch 'sideways'.*valid branches: elbow-down, elbow-up"):
        armkit.ik(planar2, [1.2, 0.3], branch="sideways")


def test_branch_is_only_for_the_closed_form(planar2):
    with pytest.raises(IKInputError, match="branch= picks a closed-form solution"):
        armkit.ik(planar2, [1.2, 0.3], method="lm", branch="elbow-up")


def test_planar3_with_phi_and_as_a_pose(planar3):
    phi = 0.4
    a = armkit.ik_all(planar3, [1.0, 0.5], phi=phi)
    T = make_pose(rotz(phi)[:3, :3], [1.0, 0.5, 0.0])
    b = armkit.ik_all(planar3, T)
    assert np.allclose(a.q, b.q) and a.success.all()
    # the end angle is q1 + q2 + q3 (no tool rotation) and the tool tip is at the target
    assert np.allclose(a.q.sum(axis=-1), phi)
    assert np.allclose(armkit.fk(planar3, a.q)[:, :2, 3], [1.0, 0.5], atol=1e-14)
    # batched phi
    many = armkit.ik_all(planar3, [[1.0, 0.5], [0.8, -0.9]], phi=[0.4, -1.0])
    assert many.q.shape == (2, 2, 3) and many.success.all()


def test_planar_2d_target_without_phi_is_position_only(planar3, planar2):
    res = armkit.ik(planar2, [0.9, 0.6])
    assert bool(res.success) and np.allclose(armkit.fk(planar2, res.q)[:2, 3], [0.9, 0.6])
    with pytest.raises(IKInputError, match="give the end angle with phi="):
        armkit.ik_all(planar3, [1.0, 0.5])


@pytest.mark.parametrize("call, match", [
    (lambda r: armkit.ik(r, [1.0, 2.0, 3.0, 4.0]), r"target must be a pose \(\.\.\., 4, 4\)"),
    (lambda r: armkit.ik(r, [np.nan, 0.0, 0.0]), "NaN or infinite"),
    (lambda r: armkit.ik(r, 3.0), "got a scalar"),
    (lambda r: armkit.ik(r, np.full((4, 4), 2.0)), "not a rigid transform"),
    (lambda r: armkit.ik(r, np.eye(4), phi=0.3), "phi= is only for planar"),
    (lambda r: armkit.ik(r, [10.0, 20.0]), "2-D targets .* are for planar arms"),
    (lambda r: armkit.ik(r, [10.0, 20.0, 30.0], q0=[1.0, 2.0]), r"q0 must have shape \(\.\.\., 3\)"),
])
def test_bad_targets_raise_shape_errors(fighter, call, match):
    with pytest.raises(armkit.ShapeError, match=match):
        call(fighter)


def test_phi_on_a_2dof_arm_is_refused(planar2):
    with pytest.raises(armkit.ShapeError, match="cannot also choose the end angle"):
        armkit.ik(planar2, [1.0, 0.2], phi=0.3)


def test_bad_method_and_missing_closed_form():
    with pytest.raises(IKInputError, match="method must be one of auto, analytic, lm"):
        armkit.ik(armkit.load("planar2"), [1.0, 0.2], method="magic")
    with pytest.raises(IKInputError, match="'panda' .* has no closed form in armkit"):
        armkit.ik(armkit.load("panda"), np.eye(4), method="analytic")
    skew = armkit.Robot([armkit.Joint(a=0.3, alpha=0.4), armkit.Joint(a=0.2, alpha=-0.7), armkit.Joint(a=0.25, alpha=1.1),
                         armkit.Joint(a=0.1)], name="skew4")      # (a 7-joint arm is swept: tests/ik/geometric/test_locked.py)
    with pytest.raises(IKInputError, match="no closed form"):
        armkit.ik_all(skew, np.eye(4))
    with pytest.raises(IKInputError, match="needs a pose target"):
        armkit.ik_all(armkit.load("ur5"), [0.3, 0.2, 0.4])


def test_raise_unreachable(fighter):
    with pytest.raises(armkit.UnreachableError, match=r"501\.294 mm from the shoulder.*177\.2 mm \(outer\)"):
        armkit.ik(fighter, [500.0, 0.0, 0.0], raise_unreachable=True)
    res = armkit.ik(fighter, [500.0, 0.0, 0.0])
    assert not res.success and res.reason == "unreachable"
    # the closest configuration: the stretched arm points at the target
    p = armkit.fk(fighter, res.q)[:3, 3]
    shoulder = np.array([0.0, 0.0, 36.0])
    assert math.isclose(np.linalg.norm(p - shoulder), 177.2, rel_tol=1e-12)
    assert np.allclose(np.cross(p - shoulder, [500.0, 0.0, -36.0]), 0.0, atol=1e-9)


def test_shapes_of_batched_results(fighter):
    targets = armkit.fk(fighter, fighter.random_q(6, rng=2))[:, :3, 3].reshape(2, 3, 3)
    one = armkit.ik(fighter, targets)
    assert one.q.shape == (2, 3, 3) and one.success.shape == (2, 3) and one.branch.shape == (2, 3)
    every = armkit.ik_all(fighter, targets)
    assert every.q.shape == (2, 3, 4, 3) and every.reason.shape == (2, 3, 4)
    single = armkit.ik(fighter, targets[1, 2])
    assert single.q.shape == (3,) and single.success.shape == ()
    assert np.allclose(single.q, one.q[1, 2])


def test_tolerance_argument(fighter):
    res = armkit.ik(fighter, [80.0, 40.0, 120.0], tol=(1e-3, 1e-3))
    assert bool(res.success)


def test_dispatch_to_lm_for_arms_without_a_closed_form():
    panda = armkit.load("panda")
    q = np.array([0.1, -0.3, 0.2, -2.0, 0.1, 1.8, 0.5])
    T = armkit.fk(panda, q)
    res = armkit.ik(panda, T, seed=1)
    assert str(res.branch) == "lm" and bool(res.success)
    assert np.allclose(armkit.fk(panda, res.q), T, atol=1e-8)


@pytest.mark.parametrize("method", ["lm", "newton", "ccd", "fabrik"])
def test_dispatch_to_numeric_methods_keeps_the_honest_check(method, planar3):
    target = armkit.fk(planar3, [0.3, 0.6, -0.4])[:3, 3]
    res = armkit.ik(planar3, target, method=method, seed=0)
    assert str(res.branch) == method
    p = armkit.fk(planar3, res.q)[:3, 3]
    assert bool(res.success) == bool(np.linalg.norm(p - target) <= 1e-9 and planar3.within_limits(res.q))


def test_auto_with_a_position_target_on_a_6r_arm_goes_numeric():
    ur = armkit.load("ur5")
    target = armkit.fk(ur, [0.3, -1.0, 1.2, 0.4, 0.5, 2.0])[:3, 3]
    res = armkit.ik(ur, target, seed=0)
    assert str(res.branch) == "lm" and bool(res.success)
    assert np.linalg.norm(armkit.fk(ur, res.q)[:3, 3] - target) <= 1e-9


def test_closed_form_with_base_and_tool_through_the_api():
    puma = armkit.load("puma560")
    moved = armkit.Robot(puma.joints, "standard", "puma on a table", "m", transl(0.2, 0.1, 0.7) @ rotz(0.5),
                         transl(0.0, 0.0, 0.12) @ rotx(0.2))
    q = np.radians([10.0, 40.0, -80.0, 20.0, 60.0, -30.0])
    res = armkit.ik(moved, armkit.fk(moved, q), q0=q + 0.05)
    assert bool(res.success) and np.allclose(res.q, q, atol=1e-9)


@pytest.mark.parametrize("name", ["planar2", "planar3", "fighter", "puma560", "ur5"])
def test_ik_is_the_first_branch_of_ik_all(name):
    """ik checks only the branch it returns when it can; the answer must equal ik_all's first."""
    r = armkit.load(name)
    rng = np.random.default_rng(4)
    q = r.random_q(200, rng=rng)
    T = armkit.fk(r, q)
    T[:20, :3, 3] *= 4.0                                   # some out of reach
    target = T if name in ("planar3", "puma560", "ur5") else T[:, :3, 3]
    q0 = r.random_q(200, rng=rng)
    for limits in (True, False):
        one = armkit.ik(r, target, q0=q0, enforce_limits=limits)
        every = armkit.ik_all(r, target, q0=q0, enforce_limits=limits)
        assert np.array_equal(one.success, every.success[:, 0])
        assert np.allclose(one.q, every.q[:, 0], atol=1e-12)
        assert list(one.branch) == list(every.branch[:, 0])
        assert list(one.reason) == list(every.reason[:, 0])
        assert list(one.message) == list(every.message[:, 0])


def test_trace_follows_the_target_shape(planar3):
    targets = armkit.fk(planar3, planar3.random_q(6, rng=1))[:, :3, 3].reshape(2, 3, 3)
    res = armkit.ik(planar3, targets, method="ccd", trace=True)
    assert res.trace.shape[:2] == (2, 3)
    one = armkit.ik(planar3, targets[0, 0], method="ccd", trace=True)
    assert one.trace.ndim == 1 and len(one.trace) >= 1
    assert armkit.ik(planar3, targets[0, 0], method="lm").trace is None


@pytest.mark.parametrize("bad", [
    lambda T: T @ np.diag([1.0, 1.0, 1.0 + 1e-5, 1.0]),     # axis stretched beyond 1e-6
    lambda T: T @ np.diag([1.0, 1.0, -1.0, 1.0]),            # a reflection: det -1
    lambda T: T + np.outer([0, 0, 0, 1.0], [0, 1e-12, 0, 0]),  # last row not exactly (0, 0, 0, 1)
])
def test_single_pose_rigidity_check_agrees_with_batched_one(bad):
    arm = armkit.load("ur5")
    T = bad(armkit.fk(arm, arm.random_q(rng=2)))
    for target in (T, T[None]):
        with pytest.raises(armkit.ShapeError, match="not a rigid transform"):
            armkit.ik(arm, target)
    ok = armkit.fk(arm, arm.random_q(rng=2)) @ np.diag([1.0, 1.0, 1.0 + 1e-8, 1.0])   # within 1e-6: accepted
    assert armkit.ik(arm, ok).q.shape == (6,)


def test_many_poses_rigidity_check_finds_one_bad_pose():
    arm = armkit.load("ur5")
    T = armkit.fk(arm, arm.random_q(300, rng=4))
    assert armkit.ik(arm, T).q.shape == (300, 6)                    # all rigid: accepted
    for bad in (np.diag([1.0, 1.0, 1.0 + 1e-5, 1.0]), np.diag([1.0, 1.0, -1.0, 1.0])):
        T2 = T.copy()
        T2[123] = T2[123] @ bad
        with pytest.raises(armkit.ShapeError, match="not a rigid transform"):
            armkit.ik(arm, T2)
    T2 = T.copy()
    T2[7, 3, 0] = 1e-12
    with pytest.raises(armkit.ShapeError, match="not a rigid transform"):
        armkit.ik(arm, T2)


def test_check_false_skips_the_pose_check_and_only_it():
    arm = armkit.load("ur5")
    T = armkit.fk(arm, arm.random_q(3, rng=5))
    bad = T @ np.diag([1.0, 1.0, 1.0 + 1e-5, 1.0])         # not rigid: 2e-5 off
    for f in (armkit.ik, armkit.ik_all):
        with pytest.raises(armkit.NotRigidError, match=r"target\[0\] is not a rigid transform"):
            f(arm, bad)
        assert f(arm, bad, check=False).q.shape[0] == 3     # the caller vouches for its poses
        assert np.array_equal(f(arm, T, check=False).q, f(arm, T).q)
        with pytest.raises(armkit.ShapeError, match="NaN"):   # shape and finiteness are still checked
            f(arm, np.full((4, 4), np.nan), check=False)
