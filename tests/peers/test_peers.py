"""armkit's FK and Jacobian agree with Peter Corke's Robotics Toolbox and with Pinocchio.

Optional: these run only where the peers are installed (``make bench`` builds
``.venv-bench``; then ``.venv-bench/bin/python -m pytest tests/peers``) and are skipped
cleanly elsewhere. Each peer builds the arm from armkit's DH table through its own code
(RTB: ``DHRobot`` with ``RevoluteDH``/``PrismaticDH`` or the ``MDH`` links, its C++
``ETS``; Pinocchio: a URDF written from the DH rows, see ``benchmarks/_peers.py``), so an
error in armkit's chain compilation or in its kernels shows up here. Both armkit back ends
(Numba and NumPy) are checked, to 1e-12 relative to the arm's reach.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

import armkit
from armkit import kinematics

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
import _peers  # noqa: E402

TOL = 1e-12
ROBOTS = sorted(armkit.bundled_robots())


@pytest.fixture(params=["numba", "numpy"])
def backend(request):
    kinematics.set_backend(request.param)
    yield request.param
    kinematics.set_backend("auto")


def _configurations(robot, count=20):
    """Random q inside the limits plus a few beyond +-pi (the reduction of the angles differs there)."""
    Q = robot.random_q(count, rng=2024)
    Q[-3:] = Q[-3:] * 3.0
    return Q


def _scale(robot):
    return max(1.0, robot.reach)


@pytest.mark.parametrize("name", ROBOTS)
def test_fk_and_jacobian_agree_with_rtb(name, backend):
    pytest.importorskip("roboticstoolbox")
    robot = armkit.load(name)
    dh, ets = _peers.build_rtb(robot)
    Q = _configurations(robot)
    T = armkit.fk(robot, Q)
    J = armkit.jacobian(robot, Q)
    for i, q in enumerate(Q):
        np.testing.assert_allclose(dh.fk(q), T[i], rtol=0, atol=TOL * _scale(robot))   # Python DH
        np.testing.assert_allclose(ets.fk(q), T[i], rtol=0, atol=TOL * _scale(robot))  # C++ ETS
        np.testing.assert_allclose(ets.jacobian(q), J[i], rtol=0, atol=TOL * _scale(robot))
        np.testing.assert_allclose(armkit.fk(robot, q), T[i], rtol=0, atol=TOL * _scale(robot))  # single == batch


@pytest.mark.parametrize("name", ROBOTS)
def test_fk_and_jacobian_agree_with_pinocchio(name, backend):
    pytest.importorskip("pinocchio")
    robot = armkit.load(name)
    peer = _peers.build_pinocchio(robot)
    Q = _configurations(robot)
    for q in Q:
        np.testing.assert_allclose(peer.fk(q), armkit.fk(robot, q), rtol=0, atol=TOL * _scale(robot))
        np.testing.assert_allclose(peer.jacobian(q), armkit.jacobian(robot, q), rtol=0, atol=TOL * _scale(robot))


@pytest.mark.parametrize("name", ["puma560", "stanford", "panda"])
def test_tool_frame_jacobian_agrees_with_pinocchio_local(name, backend):
    pin = pytest.importorskip("pinocchio")
    robot = armkit.load(name)
    model, data, fid = _peers.build_pinocchio(robot).model
    for q in _configurations(robot, 8):
        J_local = pin.computeFrameJacobian(model, data, q, fid, pin.ReferenceFrame.LOCAL)
        np.testing.assert_allclose(armkit.jacobian(robot, q, frame="tool"), J_local, rtol=0,
                                   atol=TOL * _scale(robot))


def test_rtb_rejects_a_wrong_arm():
    """The comparison can fail: a DH table with one changed length gives another pose."""
    pytest.importorskip("roboticstoolbox")
    robot = armkit.load("puma560")
    joints = list(robot.joints)
    j = joints[2]
    joints[2] = armkit.Joint(j.kind, j.theta, j.d, j.a + 0.01, j.alpha, j.lower, j.upper, j.name)
    other = armkit.Robot(joints, robot.convention, "puma560-changed", robot.unit, robot.base, robot.tool)
    _, ets = _peers.build_rtb(other)
    q = robot.random_q(rng=1)
    assert np.abs(ets.fk(q) - armkit.fk(robot, q)).max() > 1e-4


def test_the_bundled_cobra600_is_rtbs_own_model():
    """The SCARA's file against RTB's own Cobra600 model (its DH rows typed by RTB's authors, not built from armkit's
    table): the same FK everywhere, and every closed-form branch puts RTB's arm on the target."""
    rtb = pytest.importorskip("roboticstoolbox")
    theirs = rtb.models.DH.Cobra600()
    robot = armkit.load("cobra600")
    Q = _configurations(robot)
    T = armkit.fk(robot, Q)
    for i, q in enumerate(Q):
        np.testing.assert_allclose(theirs.fkine(q).A, T[i], rtol=0, atol=TOL * _scale(robot))
    res = armkit.ik_all(robot, T[:5], enforce_limits=False)
    for i in range(5):
        for q in res.q[i][np.asarray(res.success[i])]:
            np.testing.assert_allclose(theirs.fkine(q).A, T[i], rtol=0, atol=1e-9)
