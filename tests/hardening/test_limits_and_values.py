"""Issue 10, items 3 and 7: requests that cannot finish are refused before allocating; bad values get messages."""

from __future__ import annotations

import math

import numpy as np
import pytest

import armkit
from armkit._limits import check_memory, parse_size
from armkit.errors import ArmkitError, LimitError, ShapeError
from armkit.motion.trajectory import joint_trajectory

from hardening_helpers import invoke


@pytest.mark.parametrize("extra", [("--dt", "1e-9"), ("--qdd-max", "1e-9"), ("--duration", "1e9"),
                                   ("--qd-max", "1e-12")])
def test_traj_that_cannot_fit_is_refused(extra):
    code, out, exc = invoke("traj", "fighter", "--joint", "0,0,0", "30,45,60", "--deg", *extra)
    assert exc is None and code == 2
    assert "more than the limit of 2 GiB" in out and "ARMKIT_MEMORY_LIMIT" in out


def test_workspace_of_1e8_samples_is_refused_with_the_way_out():
    code, out, exc = invoke("workspace", "fighter", "-n", "100000000")
    assert exc is None and code == 2
    assert "100,000,000 samples" in out and "--samples" in out and "ARMKIT_MEMORY_LIMIT" in out


def test_the_limit_can_be_raised_and_lowered():
    code, out, _ = invoke("workspace", "planar2", "-n", "20000", env={"ARMKIT_MEMORY_LIMIT": "1M"})
    assert code == 2 and "limit of 1 MiB" in out
    code, out, _ = invoke("workspace", "planar2", "-n", "20000", env={"ARMKIT_MEMORY_LIMIT": "64M"})
    assert code == 0
    code, out, _ = invoke("workspace", "planar2", "-n", "20000", env={"ARMKIT_MEMORY_LIMIT": "lots"})
    assert code == 2 and "ARMKIT_MEMORY_LIMIT must be a size" in out
    assert parse_size("1.5G") == 3 * 2 ** 29 and parse_size("100") == 100
    with pytest.raises(LimitError):
        check_memory(math.inf, "x")
    with pytest.raises(LimitError):
        check_memory(math.nan, "x")


def test_traj_with_a_dt_longer_than_the_motion_still_reports_the_peak_speed():
    tr = joint_trajectory([[0.0], [1.0]], "quintic", duration=2.0, dt=1e9)
    assert len(tr) == 3 and math.isclose(np.abs(tr.qd).max(), 1.875 / 2.0)
    code, out, _ = invoke("traj", "planar2", "--joint", "0,0", "1,1", "--dt", "1e9")
    assert code == 0 and "peak joint speed: q1 0" not in out


@pytest.mark.parametrize("value", ["nan", "inf", "-1", "0"])
def test_traj_bad_dt(value):
    code, out, exc = invoke("traj", "planar2", "--joint", "0,0", "1,1", "--dt", value)
    assert exc is None and code == 2 and "dt must be" in out


def test_velocity_overflow_is_an_error_not_an_inf_table():
    code, out, exc = invoke("velocity", "planar2", "30", "45", "--deg", "--ee-vel", "1e308,0")
    assert exc is None and code == 2 and "too large" in out and "inf" not in out and "nan" not in out


def test_track_with_no_reached_frame_prints_no_nan(tmp_path):
    csv = tmp_path / "far.csv"
    csv.write_text("100,100\n101,100\n", encoding="utf-8")
    code, out, exc = invoke("track", "planar2", "--path", str(csv), "--method", "analytic", "--no-animation")
    assert exc is None and code in (0, 1) and "nan" not in out and "no frame reached" in out
    code, out, _ = invoke("track", "planar2", "--path", str(csv), "--method", "analytic", "--no-animation", "--json")
    assert "NaN" not in out


@pytest.mark.parametrize("args", [("ik", "planar2", "1", "0.2", "--method", "lm", "--seed", "-1"),
                                  ("workspace", "planar2", "--seed", "-1"),
                                  ("track", "planar2", "--seed", "-1", "--no-animation")])
def test_negative_seed_is_a_message(args):
    code, out, exc = invoke(*args)
    assert exc is None and code == 2 and "seed" in out


FIGHTER = armkit.load("fighter")
TARGET = armkit.fk(FIGHTER, np.radians([30, 45, 60]))[:3, 3]


@pytest.mark.parametrize("kwargs,match", [
    ({"target": TARGET.astype(complex)}, "complex"),
    ({"target": np.ma.masked_array(TARGET, [0, 1, 0])}, "masked"),
    ({"target": [10 ** 400, 0, 0]}, "too large"),
    ({"target": "24 14 187"}, "string"),
    ({"target": TARGET, "tol": 0}, "tol must be positive"),
    ({"target": TARGET, "tol": -1e-6}, "tol must be positive"),
    ({"target": TARGET, "tol": float("nan")}, "tol must be positive"),
    ({"target": TARGET, "q0": np.array([0, 0, 0]) + 1j}, "complex"),
    ({"target": TARGET, "seed": -1, "method": "lm"}, "seed"),
    ({"target": TARGET, "seed": 1.5, "method": "lm"}, "seed"),
    ({"target": TARGET, "max_iterations": 0, "method": "lm"}, "max_iterations"),
])
def test_bad_ik_arguments_are_named(kwargs, match):
    with pytest.raises(ArmkitError, match=match):
        armkit.ik(FIGHTER, **kwargs)


def test_a_robot_name_where_a_robot_goes():
    with pytest.raises(ArmkitError, match=r"armkit.load\('fighter'\)"):
        armkit.ik("fighter", TARGET)
    with pytest.raises(ArmkitError, match="armkit.Robot"):
        armkit.ik_all("fighter", TARGET)


def test_numpy_scalars_and_huge_q0_are_fine():
    res = armkit.ik(FIGHTER, TARGET.astype(np.float32).astype(float), tol=np.float32(1e-6))
    assert bool(res.success)
    res = armkit.ik(FIGHTER, TARGET, q0=[1e308, 0.0, 0.0])
    assert bool(res.success)


def test_default_lm_is_reproducible():
    arm = armkit.load("panda")
    q = arm.random_q(20, rng=3)
    T = armkit.fk(arm, q)
    a = armkit.ik(arm, T, method="lm", q0=np.zeros(7))
    b = armkit.ik(arm, T, method="lm", q0=np.zeros(7))
    np.testing.assert_array_equal(a.q, b.q)


def test_messages_cap_long_lists(tmp_path):
    p = tmp_path / "many.toml"
    p.write_text("[[joints]]\na = 0.1\n" * 900, encoding="utf-8")
    code, out, exc = invoke("fk", p, "1", "2")
    assert exc is None and code == 2 and "(900 in all)" in out and len(out) < 2000


def test_shape_error_for_strings_in_q():
    with pytest.raises(ShapeError):
        armkit.ik(FIGHTER, [1, "a", 3])
