"""URDF arms against Pinocchio's own URDF parser and kinematics (optional peer extra).

Run with ``.venv-bench/bin/python -m pytest tests/peers`` (``make bench`` does); skipped
when Pinocchio is not installed. Pinocchio reads the same files independently (urdfdom),
so agreement to 1e-12 checks the parser, the folding of fixed joints, axes and origins.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit

pin = pytest.importorskip("pinocchio")

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "model"))
from test_urdf import ERD, REAL, chain_strategy, load_real, urdf_text  # noqa: E402


def _pin_q(model, robot: armkit.Robot, q: np.ndarray) -> np.ndarray:
    """armkit joint values -> Pinocchio's configuration (continuous joints are (cos, sin))."""
    out = pin.neutral(model)
    for name, v in zip(robot.joint_names, q):
        j = model.joints[model.getJointId(name)]
        if j.nq == 2:
            out[j.idx_q], out[j.idx_q + 1] = math.cos(v), math.sin(v)
        else:
            out[j.idx_q] = v
    return out


def _compare(path: Path, robot: armkit.Robot, tip: str, count: int, seed: int) -> tuple[float, float]:
    model = pin.buildModelFromUrdf(str(path))
    data = model.createData()
    fid = model.getFrameId(tip)
    q = robot.random_q(count, rng=seed)
    T = armkit.fk(robot, q)
    J = armkit.jacobian(robot, q)
    cols = [model.joints[model.getJointId(nm)].idx_v for nm in robot.joint_names]
    fk_err = jac_err = 0.0
    for k in range(count):
        pq = _pin_q(model, robot, q[k])
        pin.framesForwardKinematics(model, data, pq)
        fk_err = max(fk_err, float(np.abs(data.oMf[fid].homogeneous - T[k]).max()))
        Jp = np.asarray(pin.computeFrameJacobian(model, data, pq, fid, pin.LOCAL_WORLD_ALIGNED)).reshape(6, -1)
        jac_err = max(jac_err, float(np.abs(Jp[:, cols] - J[k]).max()))
    return fk_err, jac_err


@pytest.mark.parametrize("name", sorted(REAL))
def test_real_urdf_fk_and_jacobian_match_pinocchio(name):
    path, r, _, tip = load_real(name)
    fk_err, jac_err = _compare(path, r, tip, 1000, seed=3)
    assert fk_err <= 1e-12 and jac_err <= 1e-12, (fk_err, jac_err)


@settings(max_examples=30, deadline=None)
@given(joints=chain_strategy)
def test_random_urdf_chain_matches_pinocchio(joints, tmp_path_factory):
    path = tmp_path_factory.mktemp("pin") / "arm.urdf"
    path.write_text(urdf_text(joints))
    r = armkit.load(path)
    fk_err, jac_err = _compare(path, r, f"link{len(joints)}", 10, seed=0)
    scale = 1.0 + r.reach
    assert fk_err <= 1e-12 * scale and jac_err <= 1e-12 * scale


@pytest.mark.parametrize("name", armkit.bundled_robots())
def test_every_bundled_robot_saved_as_urdf_loads_in_pinocchio_with_the_same_fk(name, tmp_path):
    r = armkit.load(name)
    path = armkit.save(r, tmp_path / f"{name}.urdf")
    back = armkit.load(path)
    tip = [lk.name for lk in back.links if lk.joint not in back.ignored_joints][-1]
    fk_err, _ = _compare(path, back, tip, 200, seed=1)
    assert fk_err <= 1e-12
    q = r.random_q(200, rng=1)
    s = r.unit_scale
    Ta, Tb = armkit.fk(r, q), armkit.fk(back, q * np.where(r.prismatic, s, 1.0))
    assert np.abs(Tb[:, :3, 3] - Ta[:, :3, 3] * s).max() <= 1e-12 and np.abs(Tb[:, :3, :3] - Ta[:, :3, :3]).max() <= 1e-12


def test_example_robot_data_is_where_the_tests_look():
    assert ERD.is_dir()
