"""Closed-form IK: fk(ik(T)) == T on every branch, complete and distinct branches, singular and
boundary cases, honest failures, joint limits, batching.

Reference values come from hand derivations written out here (the 2R law of cosines, the
fighter arm's geometry) and from forward kinematics of the joint vectors that generated
the targets, never from armkit's IK itself.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit import Joint, Robot
from armkit.ik.analytic import closed_form, wrap_to_limits
from armkit.spatial import make_pose, rotx, roty, rotz, transl

TWO_PI = 2 * math.pi
FAMILIES = {"planar2": "planar-2r", "planar3": "planar-3r", "fighter": "yaw-pitch-pitch",
            "puma560": "spherical-wrist", "ur5": "ur"}
POSE_TARGETS = {"planar3", "puma560", "ur5"}


def angle_gap(a, b):
    """Largest joint-wise difference of angles, modulo 2 pi."""
    d = np.abs(np.asarray(a) - np.asarray(b)) % TWO_PI
    return np.minimum(d, TWO_PI - d).max(axis=-1)


def target_of(robot, q):
    T = armkit.fk(robot, q)
    return T if robot.name in POSE_TARGETS else T[..., :3, 3]


@pytest.mark.parametrize("name, family", sorted(FAMILIES.items()))
def test_detected_from_structure_not_name(name, family):
    r = armkit.load(name)
    renamed = Robot(r.joints, r.convention, "my arm", r.unit, r.base, r.tool)
    assert closed_form(renamed).family == family


@pytest.mark.parametrize("name", ["panda", "iiwa14"])   # 7 joints (stanford: the geometric family, tests/ik/geometric)
def test_no_closed_form_for_other_structures(name):
    assert closed_form(armkit.load(name)) is None


def test_a_broken_structure_is_not_detected_by_the_family_it_left():
    """A changed structure leaves its hand-written family; where the axes still allow a closed form, the
    geometric family (subproblems on the axes) takes it, and its branches are verified like any other."""
    ur = armkit.load("ur5")
    js = list(ur.joints)
    js[3] = Joint(a=0.05, d=js[3].d, alpha=js[3].alpha, lower=js[3].lower, upper=js[3].upper, name=js[3].name)
    bent = Robot(js, name="bent ur")                                  # a4 != 0: no longer UR-like offsets,
    assert closed_form(bent).family == "geometric"                   # but axes 2-4 are still parallel
    q = bent.random_q(5, rng=1)
    res = armkit.ik_all(bent, armkit.fk(bent, q), enforce_limits=False)
    assert res.success.any(axis=1).all()
    assert np.allclose(armkit.fk(bent, res.q[res.success]),
                       np.broadcast_to(armkit.fk(bent, q)[:, None], res.q.shape[:2] + (4, 4))[res.success], atol=1e-9)
    puma = armkit.load("puma560")
    js = list(puma.joints)
    js[4] = Joint(d=0.01, alpha=js[4].alpha, name=js[4].name)        # d5 != 0: wrist axes do not meet
    found = closed_form(Robot(js, name="offset wrist"))
    assert found is None or found.family == "geometric"


# ------------------------------------------------------------------------- fk(ik(T)) == T
@pytest.mark.parametrize("name", sorted(FAMILIES))
@settings(max_examples=25)
@given(seed=st.integers(0, 2**32 - 1))
def test_every_branch_reaches_the_target(name, seed):
    r = armkit.load(name)
    q = r.random_q(rng=seed)
    target = target_of(r, q)
    res = armkit.ik_all(r, target, enforce_limits=False, scene=False)   # the closed form alone (no torso, ground)
    ok = res.success
    assert ok.any()
    T = armkit.fk(r, res.q[ok])
    if target.shape == (4, 4):
        dp, dr = armkit.spatial.pose_error(T, target)
        assert np.all(dr <= 1e-9)
    else:
        dp = np.linalg.norm(T[:, :3, 3] - target, axis=-1)
    assert np.all(dp <= 1e-12 * r.reach)
    # the joint vector that made the target is one of the branches
    assert angle_gap(res.q[ok], q).min() < 1e-6
    # branches are distinct unless the arm is at a boundary or singular (then the message says so)
    qs = res.q[ok]
    for i in range(len(qs)):
        for j in range(i + 1, len(qs)):
            if angle_gap(qs[i], qs[j]) < 1e-9:
                assert "coincide" in res.message[ok][i] or "free" in res.message[ok][i]


@pytest.mark.parametrize("name", sorted(FAMILIES))
def test_error_is_tiny_relative_to_reach_on_many_targets(name):
    r = armkit.load(name)
    q = r.random_q(300, rng=7)
    target = target_of(r, q)
    res = armkit.ik_all(r, target, enforce_limits=False, scene=False)   # the closed form alone
    assert res.success.any(axis=1).all()
    assert np.all(res.position_error[res.success] <= 1e-12 * r.reach)
    assert np.all(res.rotation_error[res.success] <= 1e-10)
    assert np.all(angle_gap(res.q, q[:, None]).min(axis=1) < 1e-6)


# ------------------------------------------------------------------------- hand derivations
def test_planar2_law_of_cosines_by_hand():
    r = armkit.load("planar2")
    x, y, l1, l2 = 1.2, 0.3, 1.0, 0.5
    c2 = (x * x + y * y - l1 * l1 - l2 * l2) / (2 * l1 * l2)            # 0.28
    expected = {}
    for label, s2 in (("elbow-down", math.sqrt(1 - c2 * c2)), ("elbow-up", -math.sqrt(1 - c2 * c2))):
        t2 = math.atan2(s2, c2)
        t1 = math.atan2(y, x) - math.atan2(l2 * s2, l1 + l2 * c2)
        expected[label] = (t1, t2)
    res = armkit.ik_all(r, [x, y])
    assert set(res.branch) == {"elbow-up", "elbow-down"}
    for k in range(2):
        assert np.allclose(res.q[k], expected[res.branch[k]], atol=1e-12)
    assert math.isclose(expected["elbow-up"][1], -math.acos(0.28), abs_tol=1e-12)


def test_the_seminars_swapped_atan2_is_wrong_and_ours_is_not():
    r = armkit.load("planar2")
    x, y = 1.2, 0.3
    c2 = (x * x + y * y - 1.25) / 1.0
    t2 = math.acos(c2)
    swapped = math.atan2(y, x) - math.atan2(1.0 + 0.5 * math.cos(t2), 0.5 * math.sin(t2))
    p = armkit.fk(r, [swapped, t2])[:2, 3]
    assert np.linalg.norm(p - [x, y]) > 0.1                           # the seed's formula misses
    res = armkit.ik(r, [x, y], branch="elbow-down")
    assert np.allclose(armkit.fk(r, res.q)[:2, 3], [x, y], atol=1e-14)


def test_fighter_target_from_the_report():
    r = armkit.load("fighter")
    q = np.radians([30.0, 45.0, 60.0])
    target = armkit.fk(r, q)[:3, 3]
    res = armkit.ik_all(r, target)
    assert res.success.all() and len(res.branch) == 4
    assert set(res.branch) == {"front/elbow-up", "front/elbow-down", "back/elbow-up", "back/elbow-down"}
    k = list(res.branch).index("front/elbow-down")                    # q3 > 0 reaching forward: elbow below
    assert np.allclose(res.q[k], q, atol=1e-12)
    # the back branches: yaw turned by 180 deg
    k_back = list(res.branch).index("back/elbow-up")
    assert math.isclose(abs(res.q[k_back][0] - q[0]), math.pi, abs_tol=1e-12)


def test_fighter_back_branch_by_hand():
    """Back branch: yaw - 180 deg and the arm mirrored about the vertical, q2' = pi - q2, q3' = -q3;
    a mirror keeps the elbow on the same (lower) side of the shoulder-target line."""
    r = armkit.load("fighter")
    q = np.radians([30.0, 45.0, 60.0])
    res = armkit.ik_all(r, armkit.fk(r, q)[:3, 3])
    k = list(res.branch).index("back/elbow-down")
    assert np.allclose(res.q[k], [q[0] - math.pi, math.pi - q[1], -q[2]], atol=1e-12)


# ------------------------------------------------------------------------- branch counts
def test_puma560_has_8_distinct_solutions_for_a_generic_pose():
    r = armkit.load("puma560")
    q = np.radians([20.0, 30.0, -60.0, 40.0, 50.0, 10.0])
    res = armkit.ik_all(r, armkit.fk(r, q), enforce_limits=False)
    assert res.success.sum() == 8
    assert len(set(res.branch)) == 8
    gaps = [angle_gap(res.q[i], res.q[j]) for i in range(8) for j in range(i + 1, 8)]
    assert min(gaps) > 1e-3
    assert angle_gap(res.q, q).min() < 1e-9


def test_ur5_has_8_distinct_solutions_for_a_generic_pose():
    r = armkit.load("ur5")
    T = make_pose((rotz(0.3) @ rotx(math.pi) @ roty(0.2))[:3, :3], [0.3, -0.2, 0.4])
    res = armkit.ik_all(r, T)
    assert res.success.sum() == 8 and len(set(res.branch)) == 8
    gaps = [angle_gap(res.q[i], res.q[j]) for i in range(8) for j in range(i + 1, 8)]
    assert min(gaps) > 1e-3
    assert np.all(res.position_error <= 1e-12 * r.reach)


def test_fighter_has_4_and_planar_arms_2():
    assert armkit.ik_all(armkit.load("fighter"), [80.0, 40.0, 120.0]).success.sum() == 4
    assert armkit.ik_all(armkit.load("planar2"), [0.9, 0.6]).success.sum() == 2
    assert armkit.ik_all(armkit.load("planar3"), [1.0, 0.5], phi=0.4).success.sum() == 2


# ------------------------------------------------------------------------- boundaries and singularities
def test_planar2_fully_stretched_and_folded():
    r = armkit.load("planar2")
    res = armkit.ik_all(r, [1.5, 0.0])
    assert res.success.all() and np.allclose(res.q, 0.0, atol=1e-7)
    assert "fully stretched" in res.message[0]
    res = armkit.ik_all(r, [0.0, 0.5])                                # |L1 - L2| = 0.5: folded
    assert res.success.all()
    assert np.allclose(np.abs(res.q[:, 1]), math.pi, atol=1e-7) and "fully folded" in res.message[0]
    assert np.all(res.position_error <= 1e-12)


@pytest.mark.parametrize("r_target, reachable", [(1.5 - 1e-9, True), (1.5 + 1e-6, False),
                                                 (0.5 + 1e-9, True), (0.5 - 1e-6, False)])
def test_planar2_just_inside_and_just_outside(r_target, reachable):
    r = armkit.load("planar2")
    ang = 0.7
    res = armkit.ik_all(r, [r_target * math.cos(ang), r_target * math.sin(ang)])
    assert bool(res.success.any()) is reachable
    if not reachable:
        assert set(res.reason) == {"unreachable"}
        # the closest configuration: stretched or folded along the target direction
        p = armkit.fk(r, res.q)[:, :2, 3]
        assert np.allclose(np.linalg.norm(p - [r_target * math.cos(ang), r_target * math.sin(ang)], axis=1),
                           1e-6, rtol=1e-3)


def test_fighter_yaw_axis_is_a_family_and_says_so():
    r = armkit.load("fighter")
    res = armkit.ik_all(r, [0.0, 0.0, 213.2])                         # straight up: fully stretched
    assert res.success.all()
    assert all("any yaw angle works" in m for m in res.message)
    res = armkit.ik(r, [0.0, 0.0, 150.0], q0=[0.7, 1.0, 0.5])          # on the axis, not stretched
    assert bool(res.success) and math.isclose(res.q[0], 0.7, abs_tol=1e-12)
    assert "yaw is free" in str(res.message)
    # every yaw works: turning the returned solution keeps the tool on target
    q = res.q.copy()
    q[0] += 1.234
    assert np.allclose(armkit.fk(r, q)[:3, 3], [0, 0, 150.0], atol=1e-9)


def test_fighter_unreachable_outside_and_inside():
    r = armkit.load("fighter")
    res = armkit.ik_all(r, [500.0, 0.0, 0.0])
    assert not res.success.any() and set(res.reason) == {"unreachable"}
    assert "501.294 mm from the shoulder" in res.message[0] and "177.2 mm (outer)" in res.message[0]
    res = armkit.ik_all(r, [0.0, 0.0, 36.0 + 10.0])                    # 10 mm from the shoulder < 22.8
    assert not res.success.any() and "22.8 mm (inner)" in res.message[0]


@pytest.mark.parametrize("name, wrist", [("puma560", 4), ("ur5", 4)])
def test_wrist_singularity(name, wrist):
    r = armkit.load(name)
    q = np.radians([20.0, 30.0, -60.0, 40.0, 0.0, 10.0])
    res = armkit.ik_all(r, armkit.fk(r, q), q0=q, enforce_limits=False)
    assert res.success.any()
    assert "wrist singularity" in res.message[0]
    assert np.all(res.position_error[res.success] <= 1e-12 * r.reach)
    assert np.allclose(armkit.fk(r, res.q[0]), armkit.fk(r, q), atol=1e-12)


def test_near_wrist_singularity_stays_precise():
    r = armkit.load("ur5")
    q = np.array([0.3, -1.0, 1.2, 0.4, 3e-5, 2.0])
    res = armkit.ik_all(r, armkit.fk(r, q))
    assert np.all(res.position_error[res.success] <= 1e-12 * r.reach)
    assert angle_gap(res.q[res.success], q).min() < 1e-6


@pytest.mark.parametrize("name", sorted(FAMILIES))
def test_unreachable_is_never_success(name):
    r = armkit.load(name)
    rng = np.random.default_rng(3)
    d = rng.normal(size=(50, 3))
    if name in ("planar2", "planar3"):
        d[:, 2] = 0.0
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    far = 3.0 * r.reach * d
    if name in POSE_TARGETS:
        target = np.broadcast_to(np.eye(4), (50, 4, 4)).copy()
        target[:, :3, 3] = far
    else:
        target = far
    res = armkit.ik_all(r, target)
    assert not res.success.any()
    assert set(np.unique(res.reason)) == {"unreachable"}
    assert all(m.startswith("unreachable") for m in res.message.ravel())


# ------------------------------------------------------------------------- limits and wrapping
def test_branches_outside_limits_are_flagged():
    r = armkit.load("puma560")
    q = np.radians([20.0, 30.0, -60.0, 40.0, 50.0, 10.0])
    res = armkit.ik_all(r, armkit.fk(r, q))
    assert np.all(r.within_limits(res.q[res.success]))
    bad = ~res.success
    assert bad.any() and set(res.reason[bad]) == {"joint limits"}
    assert not res.within_limits[bad].any()
    assert all(m.startswith("outside the joint limits") for m in res.message[bad])
    loose = armkit.ik_all(r, armkit.fk(r, q), enforce_limits=False)
    assert loose.success.all()


def test_ur5_gives_the_turn_nearest_q0():
    r = armkit.load("ur5")                                           # +-360 deg on every joint
    q = np.radians([300.0, -200.0, 100.0, -300.0, 250.0, 330.0])
    res = armkit.ik(r, armkit.fk(r, q), q0=q)
    assert bool(res.success) and np.allclose(res.q, q, atol=1e-9)
    res0 = armkit.ik(r, armkit.fk(r, q), q0=q - TWO_PI * np.array([1, 0, 0, 0, 1, 1]))
    assert np.allclose(res0.q, q - TWO_PI * np.array([1, 0, 0, 0, 1, 1]), atol=1e-9)


def test_wrap_to_limits_by_hand():
    lo, hi = np.radians([-360.0, -90.0]), np.radians([360.0, 90.0])
    rev = np.array([True, True])
    q = np.radians([[350.0, 100.0]])
    out = wrap_to_limits(q, np.zeros((1, 2)), lo, hi, rev)
    assert np.allclose(np.degrees(out), [[-10.0, 100.0 - 360.0 + 360.0]])   # 100 has no in-limit turn: stays
    out = wrap_to_limits(q, np.radians([[400.0, 0.0]]), lo, hi, rev)
    assert np.allclose(np.degrees(out), [[350.0, 100.0]])


def test_sorted_by_distance_to_q0_successes_first():
    r = armkit.load("fighter")
    target = armkit.fk(r, np.radians([30.0, 45.0, 60.0]))[:3, 3]
    for k in range(4):
        ref = armkit.ik_all(r, target).q[k]
        res = armkit.ik_all(r, target, q0=ref + 0.01)
        assert np.allclose(res.q[0], ref)
        d = np.linalg.norm(res.q - (ref + 0.01), axis=1)
        assert np.all(np.diff(d) >= 0)


# ------------------------------------------------------------------------- batching, base and tool
@pytest.mark.parametrize("name", sorted(FAMILIES))
def test_batched_equals_looped(name):
    r = armkit.load(name)
    q = r.random_q(6, rng=11)
    target = target_of(r, q).reshape((2, 3) + target_of(r, q).shape[1:])
    q0 = r.random_q(6, rng=12).reshape(2, 3, r.n)
    batch = armkit.ik_all(r, target, q0=q0)
    assert batch.q.shape[:2] == (2, 3) and batch.success.shape[:2] == (2, 3)
    for i in range(2):
        for j in range(3):
            one = armkit.ik_all(r, target[i, j], q0=q0[i, j])
            assert np.array_equal(one.success, batch.success[i, j])
            assert np.allclose(one.q, batch.q[i, j], atol=1e-12)
            assert list(one.branch) == list(batch.branch[i, j])


@pytest.mark.parametrize("name", ["puma560", "ur5", "fighter", "planar3"])
def test_base_and_tool_are_respected(name):
    r = armkit.load(name)
    base = transl(0.1 * r.reach, -0.2 * r.reach, 0.05 * r.reach) @ rotz(0.7)
    tool = transl(0.02 * r.reach, 0.0, 0.1 * r.reach) @ rotz(0.3)
    if name in ("puma560", "ur5"):
        tool = tool @ rotx(0.4)
    moved = Robot(r.joints, r.convention, r.name, r.unit, base, tool)
    assert closed_form(moved) is not None
    q = moved.random_q(20, rng=5)
    target = target_of(moved, q)
    res = armkit.ik_all(moved, target, enforce_limits=False)
    assert res.success.any(axis=-1).all()
    assert np.all(res.position_error[res.success] <= 1e-12 * moved.reach)
    assert np.all(angle_gap(res.q, q[:, None]).min(axis=1) < 1e-6)


def test_modified_dh_2r_with_offsets_is_solved():
    """A 2R arm written in modified DH with a joint offset and a bent tool."""
    arm = Robot([Joint(theta=0.3), Joint(a=0.7, theta=-0.2)], convention="modified", name="m2",
                tool=transl(0.4, 0.1, 0.0))
    assert closed_form(arm).family == "planar-2r"
    q = np.array([0.4, 1.1])
    res = armkit.ik_all(arm, armkit.fk(arm, q)[:3, 3])
    assert res.success.all() and angle_gap(res.q, q).min() < 1e-9


# ------------------------------------------------------------------------- other arms of the same structure
def _random_arm(kind: str, rng: np.random.Generator) -> Robot:
    """A random arm of a closed-form family: random lengths, offsets, twist signs and tool."""
    L = lambda lo=0.05, hi=0.6: float(rng.uniform(lo, hi) * rng.choice([-1, 1]))  # noqa: E731
    sgn = lambda: float(rng.choice([-1, 1]) * math.pi / 2)  # noqa: E731
    th = lambda: float(rng.uniform(-math.pi, math.pi))  # noqa: E731
    if kind == "spherical-wrist":      # e.g. an industrial arm with a shoulder offset a1 (KUKA, ABB, Fanuc)
        rows = [dict(d=L(), a=L(), alpha=sgn()), dict(d=L(), a=L(0.2, 0.8)), dict(d=L(), a=L(), alpha=sgn()),
                dict(d=L(0.2, 0.8), alpha=sgn()), dict(alpha=sgn()), dict(d=L(), a=L(), alpha=th())]
    elif kind == "ur":
        rows = [dict(d=L(), alpha=sgn()), dict(d=L(), a=L(0.2, 0.8)), dict(d=L(), a=L(0.2, 0.8)),
                dict(d=L(), alpha=sgn()), dict(d=L(), alpha=sgn()), dict(d=L(), a=L(), alpha=th())]
    else:                              # yaw-pitch-pitch with offsets
        rows = [dict(d=L(), a=L(), alpha=sgn()), dict(d=L(), a=L(0.2, 0.8)), dict(d=L(), a=L(0.2, 0.8), alpha=th())]
    joints = [Joint(theta=th(), lower=-math.pi, upper=math.pi, **row) for row in rows]
    tool = transl(*rng.uniform(-0.1, 0.1, 3)) @ rotx(th()) @ rotz(th())
    return Robot(joints, name=f"random {kind}", base=transl(*rng.uniform(-0.5, 0.5, 3)) @ rotz(th()), tool=tool)


@pytest.mark.parametrize("kind", ["spherical-wrist", "ur", "yaw-pitch-pitch"])
@settings(max_examples=15)
@given(seed=st.integers(0, 2**32 - 1))
def test_random_arms_of_each_family(kind, seed):
    rng = np.random.default_rng(seed)
    arm = _random_arm(kind, rng)
    assert closed_form(arm).family == kind
    q = arm.random_q(5, rng=rng)
    T = armkit.fk(arm, q)
    target = T if kind != "yaw-pitch-pitch" else T[:, :3, 3]
    res = armkit.ik_all(arm, target, enforce_limits=False)
    assert res.success.any(axis=1).all()
    assert np.all(res.position_error[res.success] <= 1e-12 * arm.reach)
    assert np.all(angle_gap(res.q, q[:, None]).min(axis=1) < 1e-6)


# ------------------------------------------------ Numba kernels against the NumPy reference
FIELDS_EXACT = ("success", "branch", "within_limits", "reason", "message", "iterations")


def _both_backends(fn):
    """``fn()`` with the Numba kernels and with the NumPy code (the reference)."""
    from armkit.kinematics import get_backend
    if get_backend() != "numba":
        pytest.skip("numba not available")
    fast = fn()
    armkit.set_backend("numpy")
    try:
        ref = fn()
    finally:
        armkit.set_backend("auto")
    return fast, ref


def _assert_same(fast, ref, scale):
    for f in FIELDS_EXACT:
        assert np.array_equal(np.asarray(getattr(fast, f)), np.asarray(getattr(ref, f))), f
    assert np.allclose(fast.q, ref.q, rtol=0, atol=1e-9)
    assert np.allclose(fast.position_error, ref.position_error, rtol=0, atol=1e-12 * scale)
    assert np.allclose(fast.rotation_error, ref.rotation_error, rtol=0, atol=1e-12)


def _mixed_targets(arm, rng, count):
    """Reachable targets, targets scaled out of (or deep into) reach, and one per reference q0."""
    q = arm.random_q(count, rng=rng)
    T = armkit.fk(arm, q)
    T[count // 2:, :3, 3] *= rng.uniform(0.0, 2.5, size=(count - count // 2, 1))
    return T if arm.name in POSE_TARGETS or arm.name.startswith("random") and arm.n != 3 else T[:, :3, 3]


@pytest.mark.parametrize("name", sorted(FAMILIES))
@pytest.mark.parametrize("enforce", [True, False])
def test_numba_kernels_match_numpy_reference(name, enforce):
    arm = armkit.load(name)
    rng = np.random.default_rng(11)
    target = _mixed_targets(arm, rng, 120)
    q0 = arm.random_q(120, rng=rng)
    for call in (lambda: armkit.ik_all(arm, target, q0, enforce_limits=enforce),
                 lambda: armkit.ik(arm, target, q0, enforce_limits=enforce),
                 lambda: armkit.ik(arm, target[7], enforce_limits=enforce)):
        fast, ref = _both_backends(call)
        _assert_same(fast, ref, arm.reach)


@pytest.mark.parametrize("kind", ["spherical-wrist", "ur", "yaw-pitch-pitch"])
@settings(max_examples=8)
@given(seed=st.integers(0, 2**32 - 1))
def test_numba_kernels_match_numpy_on_random_arms(kind, seed):
    rng = np.random.default_rng(seed)
    arm = _random_arm(kind, rng)
    target = _mixed_targets(arm, rng, 8)
    fast, ref = _both_backends(lambda: armkit.ik_all(arm, target, enforce_limits=False))
    _assert_same(fast, ref, arm.reach)


def test_single_call_equals_batched_row():
    arm = armkit.load("ur5")
    T = armkit.fk(arm, arm.random_q(6, rng=3))
    batch = armkit.ik(arm, T)
    for i in range(6):
        one = armkit.ik(arm, T[i])
        assert one.q.shape == (6,) and one.branch == batch.branch[i]
        assert np.array_equal(one.q, batch.q[i])


@settings(max_examples=40)
@given(seed=st.integers(0, 2**32 - 1))
def test_wrap_kernel_matches_wrap_to_limits(seed):
    pytest.importorskip("numba")
    from armkit.ik.analytic import _jit
    from armkit.ik.analytic._layout import joint_table
    rng = np.random.default_rng(seed)
    B, m, n = 5, 3, 4
    lower = np.array([-math.pi, -2 * TWO_PI, -np.inf, 0.1])
    upper = np.array([math.pi, 2 * TWO_PI, np.inf, 0.2])        # the last: a window no turn may reach
    raw = rng.uniform(-30, 30, (B, m, n))
    raw[0, 0, 0] = math.pi                                        # a tie: +-pi from q0 = 0
    q0 = np.clip(rng.uniform(-4, 4, (B, n)), lower, upper)
    theta = rng.uniform(-1, 1, n)
    revolute = np.array([True, True, True, True])
    q, dist = _jit.wrap_dist(raw, joint_table(theta, lower, upper, ~revolute), q0)
    ref = wrap_to_limits(raw - theta, q0[:, None, :], lower, upper, revolute)
    assert np.array_equal(q, ref)
    assert np.allclose(dist, np.linalg.norm(ref - q0[:, None, :], axis=-1), rtol=1e-15, atol=0)


@settings(max_examples=40)
@given(seed=st.integers(0, 2**32 - 1))
def test_sort_kernel_is_numpys_stable_argsort(seed):
    pytest.importorskip("numba")
    from armkit.ik.analytic import _jit
    rng = np.random.default_rng(seed)
    B, m = 6, 8
    ok = rng.random((B, m)) < 0.5
    dist = rng.choice([0.0, 0.5, 1.0, 2.5], size=(B, m))      # many exact ties: stability matters
    q, dp, dr = rng.random((B, m, 3)), rng.random((B, m)), rng.random((B, m))
    within = rng.random((B, m)) < 0.5
    order, qs, oks, dps, drs, ws = _jit.sort_branches(ok, dist, q, dp, dr, within)
    ref = np.argsort(np.where(ok, 0.0, 1e9) + dist, axis=-1, kind="stable")
    assert np.array_equal(order, ref)
    assert np.array_equal(qs, np.take_along_axis(q, ref[..., None], axis=1))
    for a, b in ((oks, ok), (dps, dp), (drs, dr), (ws, within)):
        assert np.array_equal(a, np.take_along_axis(b, ref, axis=1))


# ------------------------------------------------------------------ the family contract
FAMILY_ROBOTS = {"planar-2r": "planar2", "planar-3r": "planar3", "yaw-pitch-pitch": "fighter",
                 "spherical-wrist": "puma560", "ur": "ur5", "yaw-pitch3": "so101"}


def test_every_family_keeps_the_contract():
    from armkit.ik import analytic

    assert sorted(cls.family for cls in analytic.FAMILIES) == sorted(FAMILY_ROBOTS)
    for family, name in FAMILY_ROBOTS.items():
        robot = armkit.load(name)
        solver = closed_form(robot)
        assert isinstance(solver, analytic.ClosedFormFamily) and solver.family == family
        assert solver.m == len(solver.branch_labels) == len(set(solver.branch_labels))
        g = solver.geometry
        assert g is None or (g.dtype == np.float64 and g.ndim == 1 and not g.flags.writeable)
        if family == "yaw-pitch3":
            res = armkit.ik_all(robot, armkit.fk(robot, robot.random_q(5, rng=1))[:, :3, 3], pitch=0.2)
        else:
            T = armkit.fk(robot, robot.random_q(5, rng=1))
            res = armkit.ik_all(robot, T[:, :2, 3] if robot.n == 2 else T if solver.pose_only else T[:, :3, 3])
        assert set(np.asarray(res.branch).ravel()) <= set(solver.branch_labels)   # both paths: one table


def test_the_docs_example_of_a_new_family_runs(capsys):
    import re
    from pathlib import Path

    from armkit.ik import analytic

    text = (Path(__file__).resolve().parents[2] / "docs" / "ik.md").read_text()
    section = text[text.index("## Adding a closed-form family"):]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    saved = analytic.FAMILIES
    try:
        exec(compile(code, "docs/ik.md", "exec"), {})
    finally:
        analytic.FAMILIES = saved
    assert capsys.readouterr().out.split() == ["reach", "[1.57079633]", "True"]


def test_parallel_kernels_equal_the_one_thread_ones():
    """Every closed-form kernel's multi-threaded copy gives exactly what the one-thread kernel gives (Numba's
    parfors has dropped writes to arrays reached through a tuple: this would catch it)."""
    pytest.importorskip("numba")
    from armkit import _jit_loader
    from armkit.ik import _jit_verify
    from armkit.ik.analytic import _jit
    from armkit.ik.analytic._layout import joint_table

    B = 300
    rng = np.random.default_rng(7)
    runs = []
    for name, kernel in (("planar2", _jit.planar2), ("planar3", _jit.planar3), ("fighter", _jit.yaw_pitch_pitch),
                         ("puma560", _jit.spherical_wrist), ("ur5", _jit.ur)):
        robot = armkit.load(name)
        s = closed_form(robot)
        T = armkit.fk(robot, robot.random_q(B, rng=rng)) * np.array([1, 1, 1, 1.3])   # some out of reach
        T[:, 3, 3] = 1.0
        q0 = robot.random_q(B, rng=rng)
        if kernel in (_jit.planar2,):
            args = (np.ascontiguousarray(T[:, :3, 3]), s.geometry)
        elif kernel is _jit.yaw_pitch_pitch:
            args = (np.ascontiguousarray(T[:, :3, 3]), s.geometry, np.ascontiguousarray(q0[:, 0]))
        elif kernel is _jit.planar3:
            args = (T, s.geometry)
        else:
            args = (T, s.geometry, q0)
        runs.append((kernel, args))
        raw = rng.uniform(-10, 10, (B, 8, robot.n))
        joints = joint_table(s.sf.theta, robot.lower, robot.upper, robot.prismatic)
        runs.append((_jit.wrap_pick, (raw, joints, q0, rng.random((B, 8)) < 0.3, True)))
        runs.append((_jit.wrap_dist, (raw, joints, q0)))
    ok, dist = rng.random((B, 8)) < 0.5, rng.choice([0.0, 0.5, 1.0], size=(B, 8))
    runs.append((_jit.sort_branches, (ok, dist, rng.random((B, 8, 3)), rng.random((B, 8)), rng.random((B, 8)), ok)))
    T = armkit.fk(armkit.load("ur5"), armkit.load("ur5").random_q(B, rng=rng))
    runs.append((_jit_verify.errors, (T, T[::-1].copy(), True, rng.random((B, 6)), np.array([[-1.0] * 6, [1.0] * 6]))))

    def flat(x):
        return [a for v in x for a in (flat(v) if isinstance(v, tuple) else [v])] if isinstance(x, tuple) else [x]

    old_par = _jit.PAR
    try:
        for kernel, args in runs:
            _jit.PAR = 10 ** 9
            one = flat(kernel(*args))
            _jit.PAR = 1
            if kernel is _jit_verify.errors:    # its own threshold: call the parallel kernel itself
                outs = (np.empty(B), np.empty(B), np.empty(B, bool))
                _jit_verify._parallel(args[0], args[1], args[3], args[4], (args[2], 1e-12, 1), *outs)
                many = list(outs)
            else:
                assert _jit_loader.parallel_ok()
                many = flat(kernel(*args))
            for a, b in zip(one, many):
                assert np.array_equal(a, b, equal_nan=True), kernel.__name__
    finally:
        _jit.PAR = old_par
