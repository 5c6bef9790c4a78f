"""Issue 10, item 7, model side: the robot model and the kinematics refuse values they cannot use."""

from __future__ import annotations

import numpy as np
import pytest

import armkit
from armkit import kinematics
from armkit.errors import RobotDefinitionError, ShapeError
from armkit.model import Joint, Robot


def test_numpy_scalars_are_numbers():
    j = Joint(a=np.float32(0.5), d=np.int64(2), lower=np.float64(-1.0))
    assert type(j.a) is float and j.a == 0.5 and j.d == 2.0 and j.lower == -1.0


@pytest.mark.parametrize("kwargs,match", [
    ({"link_names": "abc"}, "sequence of strings"),
    ({"link_names": ["a", 1, "c"]}, "sequence of strings"),
    ({"unit": ["m"]}, "unit must be one of"),
    ({"convention": ["standard"]}, "convention must be one of"),
    ({"name": 5}, "name must be a string"),
])
def test_robot_arguments(kwargs, match):
    with pytest.raises(RobotDefinitionError, match=match):
        Robot([Joint(a=1.0), Joint(a=1.0)], **kwargs)


def test_joints_must_be_joints_and_numbers_must_fit_a_float():
    with pytest.raises(RobotDefinitionError, match="Joint objects"):
        Robot([1, 2])  # type: ignore[list-item]
    with pytest.raises(RobotDefinitionError, match="finite number"):
        Joint(a=10 ** 400)
    with pytest.raises(RobotDefinitionError, match="finite number"):
        Joint(a=True)


@pytest.mark.parametrize("backend", ["numpy", "numba"])
@pytest.mark.parametrize("q,match", [(np.array([1 + 1j, 0]), "complex"), (np.ma.masked_array([1.0, 2], [0, 1]), "masked"),
                                     ([10 ** 400, 0], "too large"), ([1, "a"], "numeric")])
def test_fk_and_jacobian_refuse_values_they_would_mangle(backend, q, match):
    old = kinematics.get_backend() if hasattr(kinematics, "get_backend") else None
    kinematics.set_backend(backend)
    try:
        arm = armkit.load("planar2")
        for f in (armkit.fk, armkit.fk_frames, armkit.jacobian, armkit.manipulability):
            with pytest.raises(ShapeError, match=match):
                f(arm, q)
    finally:
        if old is not None:
            kinematics.set_backend(old)


def test_manipulability_of_many_configurations_is_chunked(monkeypatch):
    arm = armkit.load("puma560")
    q = arm.random_q(2500, rng=1).reshape(5, 500, 6)
    whole = armkit.manipulability(arm, q)
    monkeypatch.setattr(kinematics, "_SVD_CHUNK", 300)
    np.testing.assert_array_equal(armkit.manipulability(arm, q), whole)
    assert armkit.condition_number(arm, q).shape == (5, 500)
