"""The compiled single-target path of the SO-101 (issue 20, item 4): equal to the NumPy path it replaces.

``armkit.ik(arm, xyz, pitch=...)`` takes the nearest branch from
:func:`armkit.ik.analytic.yaw_pitch3.nearest_pitch` (the Numba kernels) and
``armkit.lerobot.RobotKinematics.inverse_kinematics`` makes one kernel call
(``_yaw_pitch3_jit.teleop_call``). Each is compared here with the NumPy code it stands for, and
every answer is checked by FK on its own. Timing lives in benchmarks/bench_so101.py.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import armkit
from armkit.errors import ArgumentError
from armkit.ik.analytic.yaw_pitch3 import (_solver_of, fast_geometry, nearest_pitch, pitch_of, shoulder_reach,
                                           solve_pitch)
from armkit.lerobot import RobotKinematics
from armkit.spatial import rotx

JOINTS = ["shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex", "wrist_roll", "gripper"]


@pytest.fixture(scope="module")
def arm():
    return armkit.load("so101")


@pytest.fixture(scope="module")
def compiled(arm):
    if fast_geometry(arm) is None:
        armkit.set_backend("numba")    # the kernels only serve the Numba back end
    if fast_geometry(arm) is None:
        pytest.skip("Numba is not available")
    return arm


@pytest.fixture(scope="module")
def kin(compiled):
    return RobotKinematics("so101", joint_names=JOINTS)


def _slow(kin: RobotKinematics, monkeypatch, *args, **kw):
    """The same call by the NumPy path (the compiled one switched off for it)."""
    with monkeypatch.context() as m:
        m.setattr(kin, "_compiled_call", lambda: None)
        m.setattr(kin, "_teleop", None)
        out = kin.inverse_kinematics(*args, **kw)
        return out, kin.last_stage, kin.last_result, kin.last_pose_error


def test_nearest_pitch_equals_the_numpy_path(compiled):
    arm = compiled
    q = arm.random_q(600, rng=21)
    p = armkit.fk(arm, q)[:, :3, 3]
    psi = pitch_of(arm, q)
    rng = np.random.default_rng(4)
    q0 = arm.random_q(600, rng=22)
    q0[:, 4] = q[:, 4]
    psi[::5] = rng.uniform(-math.pi, math.pi, 120)        # some pitches not reachable there: the NumPy path answers
    sh = shoulder_reach(arm)
    p[::50] = sh[0] + (p[::50] - sh[0]) * 3.0              # and some targets beyond the reach
    solver = _solver_of(arm)
    fast = nearest_pitch(arm, solver, p, psi, q0)
    slow = solve_pitch(arm, solver, p, psi, q0)[np.arange(len(p)), 0]
    assert fast is not None
    assert np.array_equal(fast.success, slow.success)
    assert 0.5 < fast.success.mean() < 1.0                 # both kinds are in the sample
    assert np.abs(fast.q - slow.q).max() < 1e-9
    for field in ("branch", "reason", "message", "within_limits"):
        assert np.array_equal(np.asarray(getattr(fast, field)), np.asarray(getattr(slow, field))), field
    ok = fast.success
    T = armkit.fk(arm, fast.q[ok])                        # an independent check of every success
    assert np.linalg.norm(T[:, :3, 3] - p[ok], axis=-1).max() <= 1e-9
    err = np.remainder(pitch_of(arm, fast.q[ok], p[ok]) - psi[ok] + math.pi, 2 * math.pi) - math.pi
    assert np.abs(err).max() <= 1e-9


def test_ik_with_pitch_single_target_uses_it(compiled):
    arm = compiled
    q = np.radians([10.0, -20.0, 30.0, 40.0, 5.0])
    T = armkit.fk(arm, q)
    res = armkit.ik(arm, T[:3, 3], q0=q, pitch=float(pitch_of(arm, q)))
    assert bool(res.success) and res.q.shape == (5,)
    assert np.allclose(res.q, q, atol=1e-9)               # the branch the target came from is the nearest to it
    assert str(res.branch) in ("front/elbow-up", "front/elbow-down") and str(res.message) == ""


def test_held_still_gives_the_current_joints(kin):
    cur = np.array([12.0, -30.0, 45.0, 20.0, -5.0, 33.0])
    T = kin.forward_kinematics(cur)
    out = kin.inverse_kinematics(cur, T)
    assert np.array_equal(out, cur)                       # hand-worked: nothing to move
    assert kin.last_stage == "pose" and bool(kin.last_result.success)
    assert kin.last_pose_error[0] < 1e-12 and kin.last_pose_error[1] < 1e-9


def _stage_holds(arm, stage, q, T, start):
    """Whether joints ``q`` meet what ``stage`` promises for the desired pose ``T`` (an FK check)."""
    X = armkit.fk(arm, q)
    if np.linalg.norm(X[:3, 3] - T[:3, 3]) > 1e-9 or not arm.within_limits(q):
        return False
    if stage == "pose":
        return armkit.spatial.pose_error(X, T)[1] <= 1e-9
    if stage == "direction":
        return math.acos(min(1.0, float(X[:3, 2] @ T[:3, 2]))) <= 1e-7
    if stage == "pitch":
        out = T[:2, 3] - armkit.fk(arm, np.zeros(5), link=arm.links[1].name)[:2, 3]
        want = math.atan2(T[2, 2], float(T[:2, 2] @ out) / np.linalg.norm(out))
        return abs(math.remainder(float(pitch_of(arm, q, T[:3, 3])) - want, 2 * math.pi)) <= 1e-9
    return stage == "position"


RANK = {"pose": 0, "direction": 1, "pitch": 2, "position": 3, "failed": 4}


@pytest.mark.parametrize("case", ["held", "step", "turned", "position-only"])
def test_teleop_calls_agree_with_the_numpy_path(kin, monkeypatch, case):
    arm = kin.robot
    rng = np.random.default_rng(5)
    q = arm.random_q(60, rng=31)
    fast_stages = []
    for qi in q:
        cur = np.append(np.degrees(qi), 10.0)
        T = kin.forward_kinematics(cur)
        if case in ("step", "position-only"):
            T[:3, 3] += rng.normal(0, 0.004, 3)
        if case == "turned":
            T = T @ rotx(0.2)
        w = 0.0 if case == "position-only" else 0.01
        out = kin.inverse_kinematics(cur, T, orientation_weight=w)
        stage, res, err = kin.last_stage, kin.last_result, kin.last_pose_error
        fast_stages.append(stage)
        slow, slow_stage, slow_res, _ = _slow(kin, monkeypatch, cur, T, orientation_weight=w)
        assert out.shape == (6,) and out[5] == 10.0
        assert bool(res.success) == (stage != "failed")
        if stage == "failed":
            assert slow_stage == "failed"
            continue
        qo = np.radians(out[:5])
        assert _stage_holds(arm, stage, qo, T, qi), (case, stage)
        X = armkit.fk(arm, qo)
        assert err[0] == pytest.approx(np.linalg.norm(X[:3, 3] - T[:3, 3]), abs=1e-12)
        assert err[1] == pytest.approx(armkit.spatial.pose_error(X, T)[1], abs=1e-8)
        assert RANK[stage] <= RANK[slow_stage]            # never a worse stage than the NumPy path
        if stage == slow_stage == "pitch":               # both the nearest closed-form branch
            assert np.allclose(out, slow, atol=1e-7)
    if case == "held":
        assert set(fast_stages) == {"pose"}
    if case == "position-only":
        assert fast_stages.count("position") >= 55
    if case == "step":
        assert fast_stages.count("failed") <= 3          # a random 4 mm step may leave the limits (the NumPy path agrees)


def test_position_only_keeps_the_current_pitch(kin):
    arm = kin.robot
    cur = np.array([5.0, 10.0, 20.0, 30.0, 15.0, 0.0])
    T = kin.forward_kinematics(cur)
    T[:3, 3] += [0.01, -0.01, 0.005]
    out = kin.inverse_kinematics(cur, T, orientation_weight=0.0)
    assert kin.last_stage == "position" and out[4] == pytest.approx(15.0, abs=1e-9)   # the roll kept
    q0, q = np.radians(cur[:5]), np.radians(out[:5])
    assert float(pitch_of(arm, q, T[:3, 3])) == pytest.approx(float(pitch_of(arm, q0, T[:3, 3])), abs=1e-9)


def test_teleop_bad_input_still_gets_its_message(kin):
    cur = np.zeros(6)
    T = kin.forward_kinematics(cur)
    bad = T.copy()
    bad[0, 3] = np.nan
    with pytest.raises(ArgumentError, match="NaN or infinite"):
        kin.inverse_kinematics(cur, bad)
    with pytest.raises(ValueError, match="not a rigid transform"):
        kin.inverse_kinematics(cur, T @ np.diag([1.0, 1.0, 1.1, 1.0]))
    with pytest.raises(ArgumentError, match="NaN or infinite"):
        kin.inverse_kinematics(np.array([0, np.inf, 0, 0, 0, 0.0]), T)


def test_last_result_is_built_once_and_says_what_was_met(kin):
    cur = np.array([0.0, -20.0, 30.0, 50.0, 0.0, 0.0])
    T = kin.forward_kinematics(cur) @ rotx(0.3)           # 5 joints cannot turn about the gripper's x
    kin.inverse_kinematics(cur, T)
    res = kin.last_result
    assert res is kin.last_result                         # built when first read, then kept
    assert kin.last_stage in ("direction", "pitch") and bool(res.success) and res.reason == "converged"
    assert float(res.position_error) <= 1e-9 and float(res.rotation_error) <= 1e-9   # the stage's own error
    assert kin.last_pose_error[1] > 0.2                   # the whole pose is missed by about the 0.3 rad turn


def test_numpy_back_end_answers_without_the_kernels(kin):
    before = armkit.get_backend()
    cur = np.array([0.0, -20.0, 30.0, 50.0, 0.0, 0.0])
    T = kin.forward_kinematics(cur)
    T[:3, 3] += [0.0, 0.0, 0.01]                          # 1 cm straight up: in the arm's plane
    fast = kin.inverse_kinematics(cur, T)
    stage = kin.last_stage
    try:
        armkit.set_backend("numpy")
        assert fast_geometry(kin.robot) is None
        slow = kin.inverse_kinematics(cur, T)
        # in the arm's plane: the direction is met (the whole pose too, but for the 3e-6 rad by which the
        # URDF's rounded axes tilt the gripper), and both paths find the same joints
        assert kin.last_stage == stage == "direction" and kin.last_pose_error[1] < 1e-5
        assert np.allclose(slow, fast, atol=1e-7)
    finally:
        armkit.set_backend(before)


def test_last_result_is_not_changed_by_the_next_call(kin):
    cur = np.array([0.0, -20.0, 30.0, 50.0, 0.0, 0.0])
    T = kin.forward_kinematics(cur)
    T[:3, 3] += [0.003, 0.0, 0.002]
    out = kin.inverse_kinematics(cur, T)
    first = kin.last_result
    q_first, err_first = np.array(first.q), kin.last_pose_error
    assert np.allclose(np.radians(out[:5]), q_first, atol=1e-12)           # last_result's q is the answer's
    T2 = kin.forward_kinematics(np.array([30.0, 10.0, -20.0, 10.0, 40.0, 0.0]))
    kin.inverse_kinematics(out, T2)
    assert np.array_equal(first.q, q_first)                  # the compiled call writes fresh buffers each time
    assert kin.last_result is not first and kin.last_pose_error != err_first


@pytest.mark.parametrize("weight", [True, float("nan"), float("inf"), -1.0])
def test_bad_weights_get_the_numpy_paths_message(kin, weight):
    cur = np.zeros(6)
    T = kin.forward_kinematics(cur)
    kin.inverse_kinematics(cur, T)                           # the compiled call is set up
    with pytest.raises(ArgumentError, match="orientation_weight must be a finite number >= 0"):
        kin.inverse_kinematics(cur, T, orientation_weight=weight)


def test_list_input_takes_the_compiled_call(kin):
    cur = [12.0, -30.0, 45.0, 20.0, -5.0, 33.0]
    T = kin.forward_kinematics(np.array(cur))
    out = kin.inverse_kinematics(cur, T.tolist())
    assert np.array_equal(out, cur) and kin.last_stage == "pose"


def test_pitch_branches_polish_mask_gives_the_same_rows(compiled):
    """``polish`` (a bit mask) polishes only the branches asked for; a branch polished alone comes out bit for bit
    as when all are polished (direction_branches polishes its starts one at a time, when their turn comes)."""
    from armkit.ik.analytic import _yaw_pitch3_jit as kern

    arm = compiled
    g = fast_geometry(arm)
    tol = (1e-9, 1e-9)
    q = arm.random_q(40, rng=77)
    P = armkit.fk(arm, q)[:, :3, 3]
    psi = pitch_of(arm, q)
    out = [np.empty((4, 5)), np.empty(4), np.empty(4), np.empty(4, dtype=bool), np.empty(4, dtype=bool),
           np.empty(4, dtype=np.int64)]
    one = [np.empty_like(a) for a in out]
    for i in range(len(q)):
        kern.pitch_branches(g, P[i], psi[i], q[i], tol[0], tol[1], True, np.inf, *out, 15)
        for j in range(4):
            kern.pitch_branches(g, P[i], psi[i], q[i], tol[0], tol[1], True, np.inf, *one, 1 << j)
            assert np.array_equal(one[0][j], out[0][j]) and one[1][j] == out[1][j] and one[3][j] == out[3][j]
        kern.pitch_branches(g, P[i], psi[i], q[i], tol[0], tol[1], True, np.inf, *one, 0)
        assert np.allclose(one[0], out[0], atol=1e-2)        # the closed form alone: near the polished branches


def test_direction_part_is_its_own_module():
    from armkit.ik.analytic import yaw_pitch3, yaw_pitch3_direction

    assert yaw_pitch3.solve_direction is yaw_pitch3_direction.solve_direction
    assert yaw_pitch3._polish_direction is yaw_pitch3_direction._polish_direction
    with pytest.raises(AttributeError):
        yaw_pitch3.no_such_name  # noqa: B018


def test_position_stage_is_compiled_and_meets_the_position(kin, monkeypatch):
    """Where no pose, direction or pitch is met from the current joints, the compiled call solves the position alone
    (Newton steps from the current joints) instead of the NumPy path's LM: checked by FK here; the NumPy path
    reaches no better stage for the same calls."""
    arm = kin.robot
    rng = np.random.default_rng(8)
    q = arm.random_q(80, rng=41)
    compiled = 0
    for qi in q:
        cur = np.append(np.degrees(qi), 0.0)
        T = kin.forward_kinematics(cur)
        T[:3, 3] += rng.normal(0, 0.01, 3)                   # 1 cm off, the orientation kept: often no pitch is met
        for w in (0.01, 0.0):
            out = kin.inverse_kinematics(cur, T, orientation_weight=w)
            if kin.last_stage != "position":
                continue
            compiled += not kin._numpy
            qo = np.radians(out[:5])
            X = armkit.fk(arm, qo)
            assert np.linalg.norm(X[:3, 3] - T[:3, 3]) <= 1e-9 and arm.within_limits(qo)
            assert float(kin.last_result.position_error) <= 1e-9 and bool(kin.last_result.success)
            assert kin.last_pose_error[0] == pytest.approx(np.linalg.norm(X[:3, 3] - T[:3, 3]), abs=1e-12)
            _, slow_stage, _, _ = _slow(kin, monkeypatch, cur, T, orientation_weight=w)
            assert slow_stage in ("position", "failed")        # never a better stage by the NumPy path
    assert compiled >= 5                                      # the case occurs, and the kernel answers it
