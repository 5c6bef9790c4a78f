"""armkit.lerobot: LeRobot calibration files, servo readings <-> the bundled SO-101's joint angles, and the
drop-in RobotKinematics.

The hand-worked values below come from LeRobot's formulas (src/lerobot/motors/motors_bus.py,
MotorsBus._normalize / _unnormalize), written out here, with a = range_min, b = range_max,
mid = (a + b) / 2 and 4095 = the STS3215's resolution minus one:

    degrees:         v = (t - mid) * 360 / 4095          no clamp, drive_mode NOT applied
    range_m100_100:  v = (clamp(t) - a) / (b - a) * 200 - 100,  v -> -v with drive_mode 1
    range_0_100:     v = (clamp(t) - a) / (b - a) * 100,        v -> 100 - v with drive_mode 1

and LeRobot passes its degrees values to its RobotKinematics as URDF angles (so101_new_calib.urdf,
the URDF armkit bundles): q = radians(degrees value).
"""

from __future__ import annotations

import contextlib
import copy
import json
import math
import warnings
from pathlib import Path

import numpy as np
import pytest

import armkit
from armkit.errors import ArgumentError, UnreachableError
from armkit.lerobot import (ARM_MOTORS, Calibration, CalibrationRangeWarning, RobotKinematics, new_calib_to_old,
                            old_calib_to_new)

ROOT = Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "examples" / "so101_calibration.json"
DATA = json.loads(SAMPLE.read_text())
MOTORS = ("shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex", "wrist_roll", "gripper")
ALL_TICKS = np.arange(4096)


@pytest.fixture(scope="module")
def cal() -> Calibration:
    return Calibration.load(SAMPLE)


@contextlib.contextmanager
def quiet():
    """A context in which the out-of-range warnings of a deliberate sweep are not shown."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CalibrationRangeWarning)
        yield


def write(tmp_path, data, name="cal.json") -> Path:
    p = tmp_path / name
    p.write_text(data if isinstance(data, str) else json.dumps(data))
    return p


# ------------------------------------------------------------------ the file
def test_sample_file_loads_in_order(cal):
    assert cal.motor_names == MOTORS
    assert cal.motors["shoulder_pan"].range_min == 790 and cal.motors["shoulder_pan"].range_max == 3290
    assert cal.motors["wrist_roll"].mid == 2047.5
    assert cal.to_dict() == DATA


def test_hand_worked_degrees(cal):
    # shoulder_pan: a = 790, b = 3290, mid = 2040
    q = cal.to_q({"shoulder_pan": 2040, "shoulder_lift": 2055, "elbow_flex": 1995.5, "wrist_flex": 2043,
                  "wrist_roll": 2047.5}, mode="ticks")
    assert np.allclose(q, 0.0, atol=1e-15)                       # every range's middle is the URDF zero
    q = cal.to_q([3290, 3192, 3096, 3123, 4095, 3452], mode="ticks")
    expected_deg = [(3290 - 790) / 2 * 360 / 4095, (3192 - 918) / 2 * 360 / 4095, (3096 - 895) / 2 * 360 / 4095,
                    (3123 - 963) / 2 * 360 / 4095, (4095 - 0) / 2 * 360 / 4095]
    assert np.allclose(np.degrees(q), expected_deg, rtol=0, atol=1e-12)
    assert math.isclose(np.degrees(q[0]), 109.89010989010988, abs_tol=1e-12)
    assert math.isclose(np.degrees(q[4]), 180.0, abs_tol=1e-12)     # wrist_roll: 0..4095 -> +-180 deg
    # the same readings in LeRobot's degrees are the URDF angles in degrees
    assert np.allclose(cal.to_q(dict(zip(ARM_MOTORS, expected_deg)), mode="degrees"), q, atol=1e-15)


def test_hand_worked_range_modes(cal):
    out = cal.from_q(cal.to_q([3290, 918, 2040, 2043, 2047.5, 2741.5], mode="ticks"), mode="range_m100_100")
    assert out == pytest.approx({"shoulder_pan": 100.0, "shoulder_lift": -100.0, "elbow_flex": (2040 - 895) / 2201
                                 * 200 - 100, "wrist_flex": 0.0, "wrist_roll": 0.0}, abs=1e-9)
    # the gripper (range_0_100): a = 2031, b = 3452
    r = cal.from_q(np.zeros(5), mode="range_m100_100", gripper=50.0)
    assert r["gripper"] == 50.0
    q6 = cal.to_q([2040, 2055, 1995.5, 2043, 2047.5, 2741.5], mode="ticks", with_gripper=True)
    assert q6.shape == (6,)
    assert cal.from_q(q6, mode="range_0_100")["gripper"] == pytest.approx(50.0, abs=1e-9)
    assert cal.from_q(q6, mode="degrees", gripper_mode="ticks")["gripper"] == 2742   # 2741.5 rounds to even


def test_drive_mode_flips_the_range_modes_only():
    data = copy.deepcopy(DATA)
    data["shoulder_pan"]["drive_mode"] = 1
    data["gripper"]["drive_mode"] = 1
    flipped = Calibration.from_dict(data)
    plain = Calibration.from_dict(DATA)
    t = 3290                                                      # shoulder_pan's range_max
    assert flipped.normalize("shoulder_pan", t, "range_m100_100") == -100.0
    assert plain.normalize("shoulder_pan", t, "range_m100_100") == 100.0
    assert flipped.normalize("gripper", 2031, "range_0_100") == 100.0
    # degrees: LeRobot's _normalize does not apply drive_mode
    assert flipped.normalize("shoulder_pan", t, "degrees") == plain.normalize("shoulder_pan", t, "degrees")
    # so q (a function of the tick) is the same whatever the mode the reading came in
    ticks = {"shoulder_pan": 2600, "shoulder_lift": 2000, "elbow_flex": 2100, "wrist_flex": 1900, "wrist_roll": 100}
    q = flipped.to_q(ticks, mode="ticks")
    for mode in ("degrees", "range_m100_100", "range_0_100"):
        values = flipped.from_q(q, mode=mode)
        assert np.allclose(flipped.to_q(values, mode=mode), q, atol=1e-12)
    assert flipped.from_q(q, mode="range_m100_100")["shoulder_pan"] == pytest.approx(-((2600 - 790) / 2500 * 200 - 100))


# ------------------------------------------------------------------ round trips
@pytest.mark.parametrize("mode", ["ticks", "degrees"])
def test_round_trip_every_tick(cal, mode):
    ticks = np.repeat(ALL_TICKS[:, None], 6, axis=1)               # (4096, 6) in the file's order
    with quiet():
        q = cal.to_q(ticks, mode="ticks", with_gripper=True)
        assert q.shape == (4096, 6)
        values = cal.from_q(q, mode=mode, gripper_mode=mode)
        q2 = cal.to_q(values, mode=mode, gripper_mode=mode, with_gripper=True)
        back = cal.from_q(q2, mode="ticks")
    for m in MOTORS:
        assert back[m].dtype == np.int64
        assert np.array_equal(back[m], ALL_TICKS), m


@pytest.mark.parametrize("mode", ["range_m100_100", "range_0_100"])
def test_round_trip_every_tick_in_the_calibrated_range(cal, mode):
    for m in MOTORS:
        c = cal.motors[m]
        t = np.arange(c.range_min, c.range_max + 1)
        values = {k: np.full(t.shape, cal.motors[k].mid) for k in MOTORS}
        values[m] = t
        q = cal.to_q(values, mode="ticks", with_gripper=True)
        norm = cal.from_q(q, mode=mode, gripper_mode=mode)
        lo = -100.0 if mode == "range_m100_100" else 0.0
        assert norm[m].min() == pytest.approx(lo) and norm[m].max() == pytest.approx(100.0)
        back = cal.from_q(cal.to_q(norm, mode=mode, gripper_mode=mode, with_gripper=True), mode="ticks")
        assert np.array_equal(back[m], t), m


def test_scalar_and_dict_forms(cal):
    q = cal.to_q({f"{m}.pos": v for m, v in zip(MOTORS, [10.0, -20.0, 30.0, 40.0, 0.0, 50.0])}, mode="degrees")
    assert q.shape == (5,) and np.allclose(np.degrees(q), [10, -20, 30, 40, 0])
    out = cal.from_q(q, mode="degrees")
    assert list(out) == list(ARM_MOTORS) and all(isinstance(v, float) for v in out.values())
    assert isinstance(cal.from_q(q, mode="ticks")["shoulder_pan"], int)
    assert cal.to_q([2048] * 5, mode="ticks").shape == (5,)       # arm only, without the gripper


def test_signs_and_offsets():
    cal = Calibration.load(SAMPLE, signs={"wrist_roll": -1}, offsets_deg={"shoulder_lift": 90})
    q = cal.to_q({"shoulder_pan": 0, "shoulder_lift": 10, "elbow_flex": 0, "wrist_flex": 0, "wrist_roll": 20},
                 mode="degrees")
    assert np.allclose(np.degrees(q), [0, 100, 0, 0, -20])
    assert cal.from_q(q, mode="degrees") == pytest.approx(
        {"shoulder_pan": 0, "shoulder_lift": 10, "elbow_flex": 0, "wrist_flex": 0, "wrist_roll": 20})
    with pytest.raises(ArgumentError, match="signs"):
        Calibration.load(SAMPLE, signs={"wrist_roll": 2})
    with pytest.raises(ArgumentError, match="unknown arm motor 'elbow'"):
        Calibration.load(SAMPLE, offsets_deg={"elbow": 1})


def test_old_and_new_urdf_offsets():
    q_old = np.radians([10, -90, 90, 5, 0])
    assert np.allclose(np.degrees(old_calib_to_new(q_old)), [10, 0, 0, 5, math.degrees(0.0486795)])
    assert np.allclose(new_calib_to_old(old_calib_to_new(q_old)), q_old)


# ------------------------------------------------------------------ readings out of range
def test_reading_beyond_4095_is_an_error(cal):
    with pytest.raises(ArgumentError, match=r"elbow_flex: reading 4096 is outside 0\.\.4095"):
        cal.to_q([2048, 2048, 4096, 2048, 2048, 2048], mode="ticks")
    with pytest.raises(ValueError, match="outside 0..4095"):
        cal.to_q({"shoulder_pan": -1, "shoulder_lift": 2048, "elbow_flex": 2048, "wrist_flex": 2048,
                  "wrist_roll": 2048}, mode="ticks")
    with pytest.raises(ArgumentError, match="shoulder_pan: the degrees value would be tick"):
        cal.to_q([200.0, 0, 0, 0, 0], mode="degrees")             # 2040 + 2275 ticks > 4095
    with pytest.raises(ArgumentError, match="wrist_flex: the joint angle would be tick"):
        cal.from_q(np.radians([0, 0, 0, 190, 0]), mode="ticks")
    with pytest.raises(ArgumentError, match="NaN"):
        cal.to_q([np.nan] * 5, mode="ticks")


def test_out_of_calibrated_range_warns_once_and_maps_as_lerobot(cal):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        q = cal.to_q([700, 3300, 2000, 2000, 2000, 2000], mode="ticks")   # pan, lift and gripper outside
    assert len(caught) == 1 and caught[0].category is CalibrationRangeWarning
    text = str(caught[0].message)
    assert "shoulder_pan at tick 700" in text and "shoulder_lift at tick 3300" in text and "gripper" in text
    assert "elbow_flex" not in text
    assert caught[0].filename == __file__                           # points at the caller
    # degrees: not clamped (LeRobot's degrees mode)
    assert math.isclose(np.degrees(q[0]), (700 - 2040) * 360 / 4095, abs_tol=1e-12)
    # range modes: clamped to the range's end (LeRobot's _normalize)
    with pytest.warns(CalibrationRangeWarning, match="clamped") as rec:
        out = cal.from_q(q, mode="range_m100_100")
    assert len(rec) == 1 and out["shoulder_pan"] == -100.0 and out["shoulder_lift"] == 100.0
    # values beyond -100..100 are clamped as _unnormalize does
    with pytest.warns(CalibrationRangeWarning, match="shoulder_pan value 120"):
        q = cal.to_q([120, 0, 0, 0, 0], mode="range_m100_100")
    assert math.isclose(np.degrees(q[0]), 1250 * 360 / 4095, abs_tol=1e-12)


def test_far_outside_hints_at_a_wrap(cal):
    with pytest.warns(CalibrationRangeWarning, match="wrap at 4096"):
        cal.to_q([10, 2048, 2048, 2048, 2048], mode="ticks")


def test_in_range_readings_do_not_warn(cal):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        cal.to_q([790, 3192, 2000, 963, 0, 3452], mode="ticks")
        cal.from_q(np.zeros(5), mode="range_0_100")


def test_bad_values(cal):
    with pytest.raises(ArgumentError, match="mode must be one of ticks, degrees, range_m100_100, range_0_100"):
        cal.to_q([0] * 6, mode="radians")
    with pytest.raises(ArgumentError, match=r"array \(\.\.\., 6\)"):
        cal.to_q([2048] * 4, mode="ticks")
    with pytest.raises(ArgumentError, match="no value for the motor 'wrist_roll'"):
        cal.to_q({m: 0 for m in ARM_MOTORS[:4]}, mode="degrees")
    with pytest.raises(ArgumentError, match="unknown motor 'elbow'"):
        cal.to_q({**{m: 0 for m in ARM_MOTORS}, "elbow": 0}, mode="degrees")
    with pytest.raises(ArgumentError, match="5 joint angles"):
        cal.from_q([0, 0, 0], mode="ticks")
    with pytest.raises(ArgumentError, match="not both"):
        cal.from_q(np.zeros(6), mode="ticks", gripper=2000)


# ------------------------------------------------------------------ bad files
@pytest.mark.parametrize("edit, match", [
    (lambda d: d.pop("elbow_flex"), "no motor 'elbow_flex'"),
    (lambda d: d["wrist_flex"].pop("range_max"), "motor 'wrist_flex': missing field 'range_max'"),
    (lambda d: d["shoulder_pan"].update(range_min="790"), "motor 'shoulder_pan': field 'range_min' must be an integer"),
    (lambda d: d["shoulder_pan"].update(homing_offset=1.5), "field 'homing_offset' must be an integer, got 1.5"),
    (lambda d: d["shoulder_pan"].update(id=True), "field 'id' must be an integer, got True"),
    (lambda d: d["elbow_flex"].update(range_min=3096), r"motor 'elbow_flex': range_min \(3096\) must be less than "
                                                      r"range_max \(3096\)"),
    (lambda d: d["elbow_flex"].update(range_min=3200), "range_min .3200. must be less than range_max"),
    (lambda d: d["gripper"].update(range_max=4096), "field 'range_max' must be a tick in 0..4095"),
    (lambda d: d["gripper"].update(drive_mode=2), "'drive_mode' must be 0 or 1"),
    (lambda d: d["gripper"].update(id=1), "two motors have the id 1"),
    (lambda d: d.update(elbow=d["elbow_flex"]), "unknown motor 'elbow'"),
    (lambda d: d.update(gripper=[1, 2]), "motor 'gripper' must be an object"),
])
def test_bad_file_names_file_and_field(tmp_path, edit, match):
    data = copy.deepcopy(DATA)
    edit(data)
    p = write(tmp_path, data)
    with pytest.raises(ArgumentError, match=match) as info:
        Calibration.load(p)
    assert str(p) in str(info.value)


@pytest.mark.parametrize("text, match", [
    ('{"shoulder_pan": {"id": 1,', "not valid JSON .line 1, column"),
    ("[1, 2]", "must be a JSON object"),
    ("", "not valid JSON"),
])
def test_not_a_calibration(tmp_path, text, match):
    p = write(tmp_path, text)
    with pytest.raises(ArgumentError, match=match):
        Calibration.load(p)


def test_missing_file_and_folder(tmp_path):
    with pytest.raises(ArgumentError, match=r"calibration file .*nope\.json: not found"):
        Calibration.load(tmp_path / "nope.json")
    with pytest.raises(ArgumentError, match="not a file"):
        Calibration.load(tmp_path)


def test_without_gripper(tmp_path):
    data = copy.deepcopy(DATA)
    data.pop("gripper")
    cal = Calibration.load(write(tmp_path, data))
    assert cal.to_q([2040, 2055, 1995.5, 2043, 2047.5], mode="ticks") == pytest.approx(np.zeros(5))
    with pytest.raises(ArgumentError, match="no gripper"):
        cal.from_q(np.zeros(5), mode="ticks", gripper=10)


# ------------------------------------------------------------------ RobotKinematics
LEROBOT_JOINTS = list(MOTORS)                                       # what LeRobot passes: its motor names
URDF = str(Path(armkit.model.files.BUNDLED_DIR) / "so101.urdf")


@pytest.fixture(scope="module")
def kin() -> RobotKinematics:
    return RobotKinematics(URDF, target_frame_name="gripper_frame_link", joint_names=LEROBOT_JOINTS)


def test_constructor_defaults_like_lerobot():
    k = RobotKinematics(URDF)
    assert k.target_frame_name == "gripper_frame_link"
    assert k.joint_names == LEROBOT_JOINTS                          # the chain, then the jaw
    assert k.last_result is None and k.strict is False
    with pytest.raises(ArgumentError, match="joint_names lacks 'wrist_roll'"):
        RobotKinematics(URDF, joint_names=LEROBOT_JOINTS[:4])
    with pytest.raises(ArgumentError, match="no moving joint 'elbow'"):
        RobotKinematics(URDF, joint_names=[*LEROBOT_JOINTS, "elbow"])


def test_fk_equals_armkit_fk_in_degrees(kin):
    arm = armkit.load("so101")
    q = arm.random_q(50, rng=7)
    for qi in q:
        deg = np.append(np.degrees(qi), 37.0)                         # the gripper value rides along
        T = kin.forward_kinematics(deg)
        assert T.shape == (4, 4)
        assert np.allclose(T, armkit.fk(arm, qi), atol=1e-15)
    assert np.allclose(kin.forward_kinematics(np.append(np.degrees(q), np.zeros((50, 1)), axis=1)), armkit.fk(arm, q))


def test_fk_hand_worked_zero_pose(kin):
    T = kin.forward_kinematics(np.zeros(6))
    assert np.allclose(T[:3, 3], [0.3914, 0.0, 0.2265], atol=1e-4)   # docs/so101.md: stretched out along +x
    assert np.allclose(T[:3, 2], [1, 0, 0], atol=1e-5)               # the approach axis along +x


def test_calibration_feeds_the_kinematics(kin, cal):
    obs = {"shoulder_pan.pos": 12.0, "shoulder_lift.pos": -30.0, "elbow_flex.pos": 45.0, "wrist_flex.pos": 20.0,
           "wrist_roll.pos": -5.0, "gripper.pos": 40.0}
    q = cal.to_q(obs, mode="degrees")
    T = kin.forward_kinematics(np.array(list(obs.values())))
    assert np.allclose(T, armkit.fk(kin.robot, q), atol=1e-15)


def test_ik_round_trip(kin):
    arm = kin.robot
    rng = np.random.default_rng(3)
    for qi in arm.random_q(30, rng=11):
        deg = np.append(np.degrees(qi), 25.0)
        T = kin.forward_kinematics(deg)
        start = deg + np.append(rng.normal(0, 3, 5), 0.0)
        out = kin.inverse_kinematics(start, T)
        assert out.shape == (6,) and out[5] == 25.0                   # the jaw unchanged
        assert kin.last_stage == "pose" and bool(kin.last_result.success)
        assert np.allclose(kin.forward_kinematics(out), T, atol=1e-8)
        assert kin.last_pose_error[0] < 1e-9 and kin.last_pose_error[1] < 1e-8


def test_ik_position_only_and_extra_values(kin):
    T = kin.forward_kinematics(np.array([5, 10, 20, 30, 0, 0.0]))
    T_turned = T @ armkit.spatial.rotx(0.4)
    out = kin.inverse_kinematics(np.array([0, 0, 0, 0, 0, 60.0, 99.0]), T_turned, orientation_weight=0.0)
    assert out.shape == (7,) and out[5] == 60.0 and out[6] == 99.0   # LeRobot keeps values past joint_names
    assert kin.last_stage == "position"
    assert np.linalg.norm(kin.forward_kinematics(out)[:3, 3] - T[:3, 3]) < 1e-9


def test_ik_infeasible_orientation_meets_the_position_and_says_so(kin):
    deg = np.array([5, 10, 20, 30, 0, 0.0])
    T = kin.forward_kinematics(deg) @ armkit.spatial.rotx(0.3)       # 5 joints cannot turn about the gripper's x
    out = kin.inverse_kinematics(deg, T)
    assert kin.last_stage in ("direction", "pitch", "position")
    assert bool(kin.last_result.success)
    assert kin.last_pose_error[0] < 1e-9 and kin.last_pose_error[1] > 0.05
    assert np.linalg.norm(kin.forward_kinematics(out)[:3, 3] - T[:3, 3]) < 1e-9


def test_ik_unreachable_strict_raises(kin):
    far = np.eye(4)
    far[:3, 3] = [0.8, 0.0, 0.2]
    start = np.zeros(6)
    out = kin.inverse_kinematics(start, far)                          # drop-in: returns, as LeRobot does
    assert out.shape == (6,) and kin.last_stage == "failed"
    assert not bool(kin.last_result.success) and kin.last_result.reason == "unreachable"
    strict = RobotKinematics(URDF, joint_names=LEROBOT_JOINTS, strict=True)
    with pytest.raises(UnreachableError, match="gripper_frame_link at .0.8000, 0.0000, 0.2000. m"):
        strict.inverse_kinematics(start, far)
    assert strict.last_stage == "failed"


def test_ik_bad_arguments(kin):
    with pytest.raises(ArgumentError, match="4x4 pose"):
        kin.inverse_kinematics(np.zeros(6), np.eye(3))
    with pytest.raises(ArgumentError, match="at least 6 values"):
        kin.inverse_kinematics(np.zeros(4), np.eye(4))
    with pytest.raises(ArgumentError, match="orientation_weight must be a finite number >= 0"):
        kin.inverse_kinematics(np.zeros(6), kin.forward_kinematics(np.zeros(6)), orientation_weight=-1)
