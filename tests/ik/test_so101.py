"""The SO-101 (5 joints): position-only, position + pitch (closed form), position + direction,
unreachable and 6-D requests. Targets are FK of random in-limit joints (fixed seeds).

"Flagged but wrong" is checked independently of the solvers: FK of the returned ``q``,
the joint axes from ``fk_frames`` and the URDF's axis vectors (not the solver's own
``verify`` or ``pitch_of``), joint limits from the robot file. ``benchmarks/bench_so101.py``
runs the same modes with timings.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import armkit
from armkit.errors import ShapeError
from armkit.ik import IKInputError, closed_form_family
from armkit.ik.analytic import closed_form
from armkit.ik.analytic.yaw_pitch3 import YawPitch3, pitch_of

N = 10_000          # targets per mode (the count); the whole file runs in ~15 s
RATE = 0.999


@pytest.fixture(scope="module")
def arm() -> armkit.Robot:
    return armkit.load("so101")


@pytest.fixture(scope="module")
def targets(arm):
    q = arm.random_q(N, rng=101)
    return q, armkit.fk(arm, q)


def independent_pitch(arm, q, point):
    """Pitch from link frames and the URDF axes: the roll axis (towards the tool) in the plane perpendicular
    to the shoulder_lift axis, against the pan axis (up); outward is towards ``point``."""
    axes = np.array([j.axis for j in arm.joints])
    u = armkit.fk(arm, q, link="shoulder_link")[..., :3, :3] @ axes[0]
    u = np.where(u[..., 2:3] < 0, -u, u)
    k = armkit.fk(arm, q, link="upper_arm_link")[..., :3, :3] @ axes[1]
    a = armkit.fk(arm, q, link="gripper_link")[..., :3, :3] @ axes[4]   # wrist_roll's child link
    tool_z = armkit.fk(arm, q)[..., :3, 2]
    a = np.where(np.sum(a * tool_z, axis=-1, keepdims=True) < 0, -a, a)
    h = np.cross(k, u)
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    p = point - armkit.fk(arm, q, link="shoulder_link")[..., :3, 3]
    h *= np.where(np.sum(h * p, axis=-1, keepdims=True) < 0, -1.0, 1.0)
    return np.arctan2(np.sum(a * u, axis=-1), np.sum(a * h, axis=-1))


def angle_diff(a, b):
    return np.abs(np.remainder(a - b + math.pi, 2 * math.pi) - math.pi)


def within_limits(arm, q):
    return np.all((q >= arm.lower - 1e-12) & (q <= arm.upper + 1e-12), axis=-1)


def exact_twin() -> armkit.Robot:
    """The SO-101's DH twin with the file's rounding removed (twists exactly 0/+-90 deg, tiny lengths 0)."""
    twin = armkit.load("so101").to_dh()
    joints = []
    for j in twin.joints:
        alpha = round(j.alpha / (math.pi / 2)) * (math.pi / 2)
        a = 0.0 if abs(j.a) < 1e-5 else float(j.a)
        joints.append(armkit.Joint(theta=j.theta, d=j.d, a=a, alpha=alpha, lower=j.lower, upper=j.upper,
                                   name=j.name))
    return armkit.Robot(tuple(joints), "standard", name="so101-ideal", unit="m", base=twin.base, tool=twin.tool)


# ------------------------------------------------------------------------------------------ family
def test_family_found_on_the_real_file_and_on_the_ideal_arm(arm):
    assert closed_form_family(arm) == "yaw-pitch3"
    assert closed_form(arm).sf.exact is False          # the file's 1.5708 etc.: solved on the ideal arm
    ideal = exact_twin()
    solver = closed_form(ideal)
    assert isinstance(solver, YawPitch3) and solver.sf.exact is True


def test_four_joint_arm_without_roll():
    """Yaw + three pitch joints, tool z in the arm's plane: the family without the roll joint."""
    js = (armkit.Joint(d=0.1, a=0.02, alpha=math.pi / 2, name="yaw"), armkit.Joint(a=0.12, name="p1"),
          armkit.Joint(a=0.1, name="p2"), armkit.Joint(a=0.05, alpha=0.0, name="p3"))
    T_tool = np.array([[0, 0, 1, 0.03], [0, 1, 0, 0.01], [-1, 0, 0, 0.004], [0, 0, 0, 1.0]])   # z along x4
    r4 = armkit.Robot(js, "standard", name="yp3", tool=T_tool)
    assert closed_form_family(r4) == "yaw-pitch3"
    q = r4.random_q(500, rng=4)
    T = armkit.fk(r4, q)
    every = armkit.ik_all(r4, T[:, :3, 3], pitch=pitch_of(r4, q), enforce_limits=False)
    assert every.success.any(axis=1).all()
    Tb = armkit.fk(r4, every.q)
    ok = every.success
    assert np.abs(Tb[..., :3, 3] - T[:, None, :3, 3])[ok].max() < 1e-12


# ------------------------------------------------------------------------------ position only (LM)
def test_position_only(arm, targets):
    q, T = targets
    p = T[:, :3, 3]
    res = armkit.ik(arm, p, seed=1)
    assert res.success.mean() >= RATE
    err = np.linalg.norm(armkit.fk(arm, res.q)[:, :3, 3] - p, axis=-1)
    wrong = res.success & ((err > 1e-9) | ~within_limits(arm, res.q))
    assert not wrong.any()


# --------------------------------------------------------------------- position + pitch (closed form)
def test_position_and_pitch(arm, targets):
    q, T = targets
    p = T[:, :3, 3]
    psi = independent_pitch(arm, q, p)
    q0 = np.zeros_like(q)
    q0[:, 4] = q[:, 4]                                  # the roll is kept at q0: ask for the one used
    res = armkit.ik(arm, p, q0=q0, pitch=psi)
    assert res.success.mean() >= RATE
    got = armkit.fk(arm, res.q)
    dp = np.linalg.norm(got[:, :3, 3] - p, axis=-1)
    dpitch = angle_diff(independent_pitch(arm, res.q, p), psi)
    wrong = res.success & ((dp > 1e-9) | (dpitch > 1e-9) | ~within_limits(arm, res.q)
                           | (np.abs(res.q[:, 4] - q[:, 4]) > 1e-12))
    assert not wrong.any()
    assert np.all(res.rotation_error[res.success] <= 1e-9)     # the pitch error is reported there


def test_every_branch_is_exact_on_the_true_model(arm, targets):
    """ik_all without limits: each branch is solved (FK of the real file) or geometrically out of reach."""
    q, T = targets
    q, T = q[:2000], T[:2000]
    p = T[:, :3, 3]
    psi = independent_pitch(arm, q, p)
    every = armkit.ik_all(arm, p, q0=q * [0, 0, 0, 0, 1], pitch=psi, enforce_limits=False)
    assert set(every.branch.ravel()) == {"front/elbow-up", "front/elbow-down", "back/elbow-up", "back/elbow-down"}
    got = armkit.fk(arm, every.q)
    dp = np.linalg.norm(got[..., :3, 3] - p[:, None], axis=-1)
    dpitch = angle_diff(independent_pitch(arm, every.q, p[:, None]), psi[:, None])
    ok = every.success
    assert dp[ok].max() <= 1e-9 and dpitch[ok].max() <= 1e-9
    geometric = np.char.find(every.message.astype(str), "from the shoulder") >= 0
    geometric |= np.char.find(every.message.astype(str), "sideways offset") >= 0
    other = ~ok & ~geometric
    # what is neither solved nor out of the ideal arm's reach sits on the reach boundary (fold) of the true arm
    assert other.mean() < 1e-3 and np.all(dp[other] < 1e-5)
    # at least the configuration the target came from, except on the lateral boundary: a target as far from
    # the yaw axis as the arm's sideways offset has no "outward" side (pitch p and 180 deg - p meet there)
    none = ok.sum(axis=1) == 0
    assert none.mean() < 1e-3
    assert all("sideways offset" in m for m in every.message[none, 0])


def test_perturbed_file(arm):
    """Every joint's rpy turned by up to 1e-5 rad more: still the family, every solved branch exact."""
    from armkit.model.robot import Joint, Robot
    from armkit.spatial import rpy_to_rotation

    rng = np.random.default_rng(11)
    joints = []
    for j in arm.joints:
        O = j.origin_matrix().copy()
        O[:3, :3] = O[:3, :3] @ rpy_to_rotation(rng.uniform(-1e-5, 1e-5, 3))
        joints.append(Joint(j.kind, lower=j.lower, upper=j.upper, name=j.name, origin=tuple(map(tuple, O)),
                            axis=j.axis))
    r = Robot(tuple(joints), "urdf", arm.name, arm.unit, arm.base, arm.tool, link_names=arm.link_names)
    assert closed_form_family(r) == "yaw-pitch3"
    q = r.random_q(1000, rng=12)
    p = armkit.fk(r, q)[:, :3, 3]
    psi = pitch_of(r, q)
    res = armkit.ik(r, p, q0=q * [0, 0, 0, 0, 1], pitch=psi)
    assert res.success.mean() >= RATE
    ok = res.success
    assert np.linalg.norm(armkit.fk(r, res.q)[:, :3, 3] - p, axis=-1)[ok].max() <= 1e-9
    assert angle_diff(pitch_of(r, res.q, p), psi)[ok].max() <= 1e-9


def test_exact_arm_branches_exact():
    ideal = exact_twin()
    q = ideal.random_q(2000, rng=7)
    T = armkit.fk(ideal, q)
    p = T[:, :3, 3]
    psi = pitch_of(ideal, q)
    every = armkit.ik_all(ideal, p, q0=q * [0, 0, 0, 0, 1], pitch=psi, enforce_limits=False)
    assert every.success.any(axis=1).all()
    dp = np.linalg.norm(armkit.fk(ideal, every.q)[..., :3, 3] - p[:, None], axis=-1)
    assert dp[every.success].max() < 1e-13


def test_pitch_convention(arm):
    """Wrist bent 90 deg with the arm horizontal: gripper straight down (-90 deg); straight out: 0."""
    assert abs(math.degrees(pitch_of(arm, np.radians([0, 0, 0, 90, 0]))) + 90) < 1e-3
    assert abs(math.degrees(pitch_of(arm, np.zeros(5)))) < 1e-3
    out = armkit.fk(arm, np.zeros(5))
    assert out[0, 3] > 0.3 and abs(out[0, 2] - 1) < 1e-6     # the gripper's z points outward along +x


def test_pitch_down_at_a_point(arm):
    res = armkit.ik(arm, [0.2, 0.05, 0.05], pitch=-math.pi / 2)
    assert res.success and res.branch == "front/elbow-up"
    T = armkit.fk(arm, res.q)
    assert np.allclose(T[:3, 3], [0.2, 0.05, 0.05], atol=1e-9)
    assert T[2, 2] < -1 + 1e-10                          # the gripper's z axis points down


# ------------------------------------------------------------------------ position + direction (LM)
def test_position_and_direction(arm, targets):
    q, T = targets
    p, d = T[:, :3, 3], T[:, :3, 2]
    res = armkit.ik(arm, p, direction=d, seed=2)
    assert res.success.mean() >= RATE
    got = armkit.fk(arm, res.q)
    dp = np.linalg.norm(got[:, :3, 3] - p, axis=-1)
    ang = np.arccos(np.clip(np.sum(got[:, :3, 2] * d, axis=-1), -1, 1))
    wrong = res.success & ((dp > 1e-9) | (ang > 1e-7) | ~within_limits(arm, res.q))
    assert not wrong.any()


# ------------------------------------------------------------------------------- honest failures
def test_unreachable_targets_fail_with_reasons(arm):
    far = [0.8, 0.1, 0.3]
    res = armkit.ik(arm, far, pitch=0.0)
    assert not res.success and res.reason == "unreachable"
    assert "from the shoulder" in str(res.message) and "reaches" in str(res.message)
    res = armkit.ik(arm, far)
    assert not res.success and res.reason == "unreachable" and "from the shoulder" in str(res.message)
    res = armkit.ik(arm, far, direction=[1, 0, 0])
    assert not res.success and res.reason == "unreachable"
    with pytest.raises(armkit.UnreachableError, match="from the shoulder"):
        armkit.ik(arm, far, pitch=0.0, raise_unreachable=True)


def test_six_d_pose_fails_honestly(arm):
    q = arm.random_q(20, rng=5)
    T = armkit.fk(arm, q)
    tilt = np.array([[1, 0, 0, 0], [0, math.cos(0.4), -math.sin(0.4), 0], [0, math.sin(0.4), math.cos(0.4), 0],
                     [0, 0, 0, 1.0]])
    T_bad = T @ tilt                                    # turned about the tool's x axis: out of the arm's reach
    res = armkit.ik(arm, T_bad, seed=3)
    assert not res.success.any()
    assert set(res.reason) == {"unreachable"}
    for msg in res.message:
        assert str(msg).startswith("5 joints cannot reach an arbitrary orientation; the nearest reachable pose")
        deg = float(msg.split("misses by ")[1].split(" deg")[0])
        assert 0.5 < deg <= 23.0                        # at most the 22.9 deg turn that was asked
    good = armkit.ik(arm, T[:5], seed=3)                # a pose the arm can take: solved
    assert good.success.all()


def test_bad_inputs(arm):
    with pytest.raises(IKInputError, match="give pitch="):
        armkit.ik_all(arm, [0.2, 0.0, 0.1])
    with pytest.raises(IKInputError, match="no closed form for a position and a pitch"):
        armkit.ik(armkit.load("fighter"), [30.0, 20.0, 150.0], pitch=0.1)
    with pytest.raises(IKInputError, match="not both"):
        armkit.ik(arm, [0.2, 0.0, 0.1], pitch=0.1, direction=[0, 0, -1])
    with pytest.raises(IKInputError, match="closed form"):
        armkit.ik(arm, [0.2, 0.0, 0.1], pitch=0.1, method="lm")
    with pytest.raises(IKInputError, match="numeric methods"):
        armkit.ik(arm, [0.2, 0.0, 0.1], direction=[0, 0, -1], method="ccd")
    with pytest.raises(ShapeError, match="non-zero"):
        armkit.ik(arm, [0.2, 0.0, 0.1], direction=[0, 0, 0])
    with pytest.raises(ShapeError, match="position target"):
        armkit.ik(arm, np.eye(4), pitch=0.1)
    with pytest.raises(ShapeError, match="NaN"):
        armkit.ik(arm, [0.2, 0.0, 0.1], pitch=float("nan"))
    with pytest.raises(ShapeError, match="broadcast"):
        armkit.ik(arm, [[0.2, 0.0, 0.1]] * 3, pitch=[0.1, 0.2])
    with pytest.raises(IKInputError, match="unknown branch"):
        armkit.ik(arm, [0.2, 0.0, 0.1], pitch=0.1, branch="up")


def test_meshes_resolve(arm):
    import os

    paths = [v.mesh_path for link in arm.links for v in link.visuals if getattr(v, "mesh_path", None)]
    assert len(paths) >= 13 and all(os.path.exists(p) for p in paths)
    assert all("so101_assets" in str(p) for p in paths)
