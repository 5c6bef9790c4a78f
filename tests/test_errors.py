"""Every armkit exception lives in armkit.errors, subclasses the matching builtin and is exported from armkit."""

from __future__ import annotations

import importlib
import inspect

import numpy as np
import pytest

import armkit
from armkit import errors


def _exception_classes() -> list[type]:
    return [obj for _, obj in inspect.getmembers(errors, inspect.isclass)
            if issubclass(obj, BaseException) and obj.__module__ == errors.__name__]


def test_every_exception_is_listed_and_exported():
    names = {cls.__name__ for cls in _exception_classes()}
    assert names == set(errors.__all__)
    for name in names:
        assert name in armkit.__all__, name
        assert getattr(armkit, name) is getattr(errors, name)


def test_no_exception_class_is_defined_outside_errors_py():
    import pkgutil

    outside = []
    for info in pkgutil.walk_packages(armkit.__path__, "armkit."):
        if info.name.startswith(("armkit.viz.view", "armkit.cli", "armkit.reach", "armkit.collision",
                                 "armkit.symbolic", "armkit.viz")):
            # not yet: view, reach and collision still define their own errors (ViewError, MapFileError,
            # ReachabilityError, SceneError, SceneFileError, SceneNotSupportedError); cli/viz/symbolic are extras
            continue
        mod = importlib.import_module(info.name)
        for _, obj in inspect.getmembers(mod, inspect.isclass):
            if issubclass(obj, BaseException) and obj.__module__ == info.name and info.name != "armkit.errors":
                outside.append(f"{info.name}.{obj.__name__}")
    assert not outside, outside


@pytest.mark.parametrize("name", ["ArgumentError", "ShapeError", "RobotDefinitionError", "RobotFileError",
                                  "JointLimitError", "UnreachableError", "LimitError", "IKInputError", "ParseError"])
def test_value_errors_are_value_errors_and_armkit_errors(name):
    cls = getattr(armkit, name)
    assert issubclass(cls, armkit.ArmkitError) and issubclass(cls, ValueError)


def test_moved_errors_are_the_same_class_at_their_old_import_paths():
    from armkit.ik import IKInputError as a
    from armkit.ik.api import IKInputError as b
    from armkit.cli.shell import ParseError as c

    assert a is b is errors.IKInputError is armkit.IKInputError
    assert c is errors.ParseError is armkit.ParseError


def test_bad_jacobian_frame_is_a_value_error():
    arm = armkit.load("planar2")
    with pytest.raises(ValueError, match=r"frame must be 'base' or 'tool', got 'world'"):
        armkit.jacobian(arm, np.zeros(2), frame="world")   # type: ignore[arg-type]


def test_bad_backend_is_a_value_error():
    from armkit import kinematics

    before = kinematics._backend
    with pytest.raises(ValueError, match=r"backend must be 'auto', 'numba' or 'numpy', got 'cuda'"):
        armkit.set_backend("cuda")   # type: ignore[arg-type]
    assert kinematics._backend == before


def test_bad_ik_method_is_a_value_error():
    arm = armkit.load("planar2")
    with pytest.raises(ValueError, match="method"):
        armkit.ik(arm, [1.0, 0.5], method="magic")   # type: ignore[arg-type]


def test_fabrik_on_an_unsupported_arm_is_an_ik_input_error():
    arm = armkit.load("puma560")
    with pytest.raises(armkit.IKInputError, match="FABRIK"):
        armkit.ik(arm, armkit.fk(arm, np.zeros(6))[:3, 3], method="fabrik")


def test_shell_errors_are_value_errors():
    from armkit.cli.shell import Shell, parse_numbers

    with pytest.raises(ValueError, match="banana"):
        parse_numbers(["30", "banana"])
    with pytest.raises(ValueError, match=r"units must be 'deg' or 'rad', got 'furlong'"):
        Shell(armkit.load("fighter"), units="furlong", plot="none")
