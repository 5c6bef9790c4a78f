"""Velocity kinematics: twists against finite differences of FK, pseudo-inverse and DLS, resolved rate, CLI."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

import armkit
from armkit.cli import app
from armkit.motion.velocity import (DLS_LAMBDA_MAX, damping_schedule, joint_rates, resolved_rate, velocity_rows,
                                    twist)

runner = CliRunner()


@pytest.mark.parametrize("name", ["planar2", "fighter", "puma560", "stanford"])
def test_twist_linear_part_is_the_derivative_of_fk(name, rng):
    r = armkit.load(name)
    q = r.random_q(rng=rng)
    qd = rng.normal(size=r.n)
    h = 1e-6
    dp = (armkit.fk(r, q + h * qd)[:3, 3] - armkit.fk(r, q - h * qd)[:3, 3]) / (2 * h)
    tw = twist(r, q, qd)
    np.testing.assert_allclose(tw[:3], dp, atol=1e-6 * max(1.0, r.reach))
    # angular part: R_dot R^T = [w]x
    Rp, Rm, R = armkit.fk(r, q + h * qd)[:3, :3], armkit.fk(r, q - h * qd)[:3, :3], armkit.fk(r, q)[:3, :3]
    W = (Rp - Rm) / (2 * h) @ R.T
    np.testing.assert_allclose(tw[3:], [W[2, 1], W[0, 2], W[1, 0]], atol=1e-6)


def test_planar2_hand_example():
    # stretched along x, both joints at 1 rad/s: vy = (a1 + a2) * 1 + a2 * 1 = 2.0 m/s, wz = 2 rad/s
    tw = twist(armkit.load("planar2"), [0.0, 0.0], [1.0, 1.0])
    np.testing.assert_allclose(tw, [0, 2.0, 0, 0, 0, 2.0], atol=1e-12)


@settings(max_examples=30)
@given(q1=st.floats(-math.pi, math.pi), q2=st.floats(0.3, math.pi - 0.3), sgn=st.sampled_from([1, -1]),
       vx=st.floats(-1, 1), vy=st.floats(-1, 1))
def test_pinv_reproduces_the_requested_velocity_planar(q1, q2, sgn, vx, vy):
    r = armkit.load("planar2")
    res = joint_rates(r, [q1, sgn * q2], [vx, vy])
    J = armkit.jacobian(r, [q1, sgn * q2])[:2]
    np.testing.assert_allclose(J @ res.qd, [vx, vy], atol=1e-9)
    assert not res.singular and res.residual < 1e-9


@pytest.mark.parametrize("name,rows", [("fighter", 3), ("puma560", 6), ("stanford", 6)])
def test_pinv_reproduces_twist_away_from_singularities(name, rows, rng):
    r = armkit.load(name)
    for _ in range(10):
        q = r.random_q(rng=rng)
        if armkit.manipulability(r, q) > 0.05 * armkit.manipulability(r, r.random_q(64, rng=1)).mean():
            break
    xd = rng.normal(size=rows)
    res = joint_rates(r, q, xd)
    np.testing.assert_allclose(armkit.jacobian(r, q)[:rows] @ res.qd, xd, atol=1e-8 * max(1.0, r.reach))


def test_dls_stays_bounded_near_a_singularity():
    r = armkit.load("planar2")
    q = [0.3, 1e-7]                                  # almost stretched
    xd = [0.1 * math.cos(0.3), 0.1 * math.sin(0.3)]  # straight out along the arm: impossible
    pinv = joint_rates(r, q, xd, method="pinv")
    dls = joint_rates(r, q, xd, method="dls")
    assert np.linalg.norm(pinv.qd) > 1e4            # the pseudo-inverse explodes
    lam = DLS_LAMBDA_MAX                             # |qd| <= |xd| / (2 lambda) for DLS
    assert np.linalg.norm(dls.qd) <= np.linalg.norm(xd) / (2 * lam * math.sqrt(1 - (1e-7 / 0.04) ** 2)) + 1e-9
    assert dls.singular and pinv.singular
    # the warning names the direction the arm cannot move: along the stretched arm (radial)
    np.testing.assert_allclose(abs(dls.direction @ [math.cos(0.3), math.sin(0.3)]), 1.0, atol=1e-6)
    assert "cannot move along" in dls.message
    fixed = joint_rates(r, q, xd, method="dls", damping=0.01)
    assert fixed.damping == pytest.approx(1e-4)


def test_damping_schedule_documented_values():
    np.testing.assert_allclose(damping_schedule([1.0, 0.04, 0.02, 0.0]),
                               [0.0, 0.0, 0.04 ** 2 * 0.75, 0.04 ** 2])


def test_velocity_rows_and_errors():
    assert velocity_rows(6) == (0, 1, 2, 3, 4, 5)
    with pytest.raises(armkit.ShapeError, match="6 .* 3 .* or 2"):
        velocity_rows(4)
    with pytest.raises(armkit.ShapeError, match="q must be one configuration"):
        joint_rates(armkit.load("planar2"), np.zeros((2, 2)), [0, 1])
    with pytest.raises(armkit.ArmkitError, match="method"):
        joint_rates(armkit.load("planar2"), [0, 1], [0, 1], method="magic")  # type: ignore[arg-type]


def test_resolved_rate_honours_speed_and_joint_limits():
    J = armkit.Joint
    r = armkit.Robot([J(a=1.0, lower=-1.0, upper=1.0), J(a=0.5, lower=0.2, upper=0.6)], name="tight")

    def path(t):  # ask for far more than the arm can do
        return np.array([0.0, 1.4]), np.zeros(2)

    tr = resolved_rate(r, [0.0, 0.4], path, duration=1.0, dt=0.01, qd_max=0.5)
    assert np.all(np.abs(tr.qd) <= 0.5 + 1e-12)
    assert np.all(r.within_limits(tr.q))


def test_cli_velocity_both_ways():
    res = runner.invoke(app, ["velocity", "planar2", "30", "45", "--deg", "--ee-vel", "0.1", "0"])
    assert res.exit_code == 0, res.output
    assert "joint rates" in res.output and "q1" in res.output
    res = runner.invoke(app, ["velocity", "planar2", "30", "45", "--deg", "--ee-vel", "0.1,0", "--json"])
    import json
    data = json.loads(res.output)
    r = armkit.load("planar2")
    J = armkit.jacobian(r, np.radians([30, 45]))[:2]
    np.testing.assert_allclose(J @ np.array(data["qd_rad_s"]), [0.1, 0.0], atol=1e-12)
    res = runner.invoke(app, ["velocity", "planar2", "0", "90", "--deg", "--q-vel", "1", "0", "--json"])
    # --deg makes the rates deg/s too; hand: vy = (a1 + a2 c2) q1_dot = 1 m * (pi/180) rad/s
    assert json.loads(res.output)["twist"][1] == pytest.approx(math.radians(1.0))
    res = runner.invoke(app, ["velocity", "planar2", "30", "45", "--deg", "--ee-vel", "0.1", "0", "1", "2"])
    assert res.exit_code == 2 and "2 (vx vy)" in res.output
    res = runner.invoke(app, ["velocity", "planar2", "30", "45"])
    assert res.exit_code == 2 and "exactly one" in res.output


def test_a_scara_is_conditioned_by_the_rows_it_can_move():
    """The eCobra 600 never turns its tool about x or y: a full twist is not 'near a singularity' at a regular
    configuration. By hand, rows (vx, vy, vz, wz) at q2 = 45 deg: det = a1 a2 sin q2 != 0, well-conditioned; at
    q2 = 0 the elbow is stretched and the arm cannot move along its own direction (cos q1, sin q1)."""
    from armkit.motion.velocity import joint_rates

    cobra = armkit.load("cobra600")
    q = np.array([np.radians(30), np.radians(45), 0.1, 0.2])
    r = joint_rates(cobra, q, [0.1, 0.0, 0.0, 0.0, 0.0, 0.0])
    assert not r.singular and r.residual < 1e-12 and "never moves" not in r.message
    r = joint_rates(cobra, q, [0.1, 0.0, 0.0, 0.2, 0.0, 0.0])      # wx asked: dropped, and said
    assert not r.singular and abs(r.residual - 0.2) < 1e-12 and "never moves along wx" in r.message
    stretched = joint_rates(cobra, np.array([np.radians(30), 0.0, 0.1, 0.2]), [0.1, 0.0, 0.0, 0.0, 0.0, 0.0])
    assert stretched.singular
    d = stretched.direction[:2] / np.linalg.norm(stretched.direction[:2])
    assert abs(abs(d @ [np.cos(np.radians(30)), np.sin(np.radians(30))]) - 1.0) < 1e-9
    assert np.allclose(stretched.direction[3:5], 0.0)
