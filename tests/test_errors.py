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
        mod = importlib.import_module(info.name)   # every extra is installed in the test environment
        for _, obj in inspect.getmembers(mod, inspect.isclass):
            if (issubclass(obj, BaseException) and obj.__module__ == info.name and info.name != "armkit.errors"
                    and not obj.__name__.startswith("_")):   # private control flow (symbolic's _Timeout)
                outside.append(f"{info.name}.{obj.__name__}")
    assert not outside, outside


BUILTINS = (ValueError, KeyError, OSError, ImportError, NotImplementedError, RuntimeError, KeyboardInterrupt)


@pytest.mark.parametrize("cls", _exception_classes(), ids=lambda c: c.__name__)
def test_every_error_subclasses_armkit_error_and_a_builtin(cls):
    if cls is errors.ArmkitError:
        return
    if issubclass(cls, Warning):     # a warning category, raised only through warnings.warn
        assert issubclass(cls, UserWarning), cls
        return
    if cls is errors.WriteInterrupted:   # Ctrl-C during a write stays a KeyboardInterrupt (not an Exception)
        assert issubclass(cls, KeyboardInterrupt)
        return
    assert issubclass(cls, errors.ArmkitError), cls
    assert any(issubclass(cls, b) for b in BUILTINS), cls


@pytest.mark.parametrize("old, name", [
    ("armkit.collision", "SceneError"), ("armkit.collision.shapes", "SceneError"),
    ("armkit.collision.files", "SceneFileError"), ("armkit.reach", "ReachabilityError"),
    ("armkit.reach", "MapFileError"), ("armkit.reach", "SceneNotSupportedError"),
    ("armkit.reach._map", "MapFileError"), ("armkit.viz.view", "ViewError"), ("armkit.viz.view.server", "ViewError"),
])
def test_errors_moved_into_errors_py_keep_their_old_import_path(old, name):
    assert getattr(importlib.import_module(old), name) is getattr(errors, name) is getattr(armkit, name)


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


# ----------------------------------------------------------------- raise sites that were a bare ArmkitError
@pytest.fixture(scope="module")
def small_map():
    return armkit.reachability("planar2", resolution=0.1, samples=20_000, workers=1)


@pytest.mark.parametrize("kw, match", [({"top": 0}, "top must be a positive integer"),
                                       ({"step": -1.0}, "step must be a positive length"),
                                       ({"yaws": 0}, "yaws must be a positive integer")])
def test_base_placement_arguments_are_value_errors(small_map, kw, match):
    with pytest.raises(ValueError, match=match):
        armkit.base_placement(small_map, np.eye(4), **kw)
    with pytest.raises(ValueError, match="map must be an armkit.ReachabilityMap, got str"):
        armkit.base_placement("map.zarr", np.eye(4))   # type: ignore[arg-type]


def test_a_scene_reachability_cannot_read_is_a_value_error():
    with pytest.raises(ValueError, match="scene must be an armkit.Scene"):
        armkit.reachability("planar2", scene=object(), samples=1000, workers=1)


def test_workspace_exclusion_errors_are_value_errors():
    from armkit.analysis.workspace import Exclusion, workspace

    arm = armkit.load("planar2")
    with pytest.raises(ValueError, match="exclusion must be an armkit.analysis.Exclusion, got dict"):
        workspace(arm, samples=1000, exclusion={"ground_z": 0})   # type: ignore[arg-type]
    everything = Exclusion(boxes=(([-9.0, -9.0, -9.0], [9.0, 9.0, 9.0]),))
    with pytest.raises(ValueError, match="every sample of 'planar2' enters the exclusion"):
        workspace(arm, samples=1000, exclusion=everything)


def test_tracking_csv_errors_are_value_errors(tmp_path, monkeypatch):
    from armkit.viz import tracking

    arm = armkit.load("planar2")
    bad = tmp_path / "bad.csv"
    bad.write_text("x,y\n1,banana\n")
    with pytest.raises(ValueError, match="cannot read target points as CSV numbers"):
        tracking.target_path(arm, str(bad))
    monkeypatch.setattr(tracking, "MAX_CSV_BYTES", 4)
    with pytest.raises(armkit.LimitError, match="a target CSV may have at most 4 bytes"):
        tracking.target_path(arm, str(bad))
    assert issubclass(armkit.LimitError, ValueError)


def test_an_overflowing_tool_velocity_is_a_value_error():
    from armkit.motion.velocity import joint_rates

    arm = armkit.load("planar2")
    with pytest.raises(ValueError, match="the joint rates overflow float64"):
        joint_rates(arm, [0.3, 0.5], [1e308, -1e308])


# ----------------------------------------------------------------- a missing optional extra
def _block(monkeypatch, *modules: str) -> None:
    """Make ``import MODULE`` fail (None in sys.modules) and forget armkit modules that imported it at load."""
    import sys

    for m in modules:
        monkeypatch.setitem(sys.modules, m, None)
    for name in [n for n in sys.modules if n.startswith(("armkit.symbolic", "armkit.analysis.singularity"))]:
        monkeypatch.delitem(sys.modules, name)


@pytest.mark.parametrize("args, blocked, extra", [
    (["view", "planar2"], "viser", "view"),
    (["derive", "planar2"], "sympy", "symbolic"),
    (["singular", "planar2"], "sympy", "symbolic"),
    (["reach", "show", "no-such-map.zarr"], "zarr", "scale"),
    (["plot", "planar2", "30", "45", "-o", "arm.png"], "matplotlib", "viz"),
])
def test_a_missing_extra_is_one_line_and_exit_2(monkeypatch, tmp_path, args, blocked, extra):
    from typer.testing import CliRunner

    from armkit.cli import app

    monkeypatch.chdir(tmp_path)
    _block(monkeypatch, blocked)
    res = CliRunner().invoke(app, args)
    assert res.exit_code == 2, res.output
    assert f"needs the '{extra}' extra" in res.output and f"pip install 'armkit[{extra}]'" in res.output
    assert "Traceback" not in res.output
    assert not (tmp_path / "arm.png").exists()


def test_a_missing_extra_in_the_api_is_an_import_error(monkeypatch, tmp_path):
    from armkit.viz.animation import render_animation

    _block(monkeypatch, "imageio", "imageio.v2")
    arm = armkit.load("planar2")
    with pytest.raises(ImportError, match=r"writing MP4 needs the 'viz' extra .*pip install 'armkit\[viz\]'"):
        render_animation(arm, np.zeros((2, 2)), tmp_path / "a.mp4", progress=False)
    assert not (tmp_path / "a.mp4").exists()
    _block(monkeypatch, "sympy")
    with pytest.raises(armkit.MissingExtraError, match="armkit.symbolic needs the 'symbolic' extra"):
        importlib.import_module("armkit.symbolic")


def test_every_extra_named_in_the_code_is_declared_in_pyproject():
    import sys
    from pathlib import Path

    from armkit._extras import EXTRAS

    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover
        import tomli as tomllib
    meta = tomllib.loads((Path(__file__).parent.parent / "pyproject.toml").read_text())["project"]
    extras = meta["optional-dependencies"]
    for module, extra in EXTRAS.items():
        assert extra in extras, (module, extra)
    used = set(EXTRAS.values())
    assert all(f"armkit[{','.join(sorted(used, key=list(extras).index))}]" in req for req in extras["all"])
    assert "armkit[all]" in extras["test"]   # make test / make demo install every extra
    core = " ".join(meta["dependencies"])
    for heavy in ("matplotlib", "sympy", "viser", "coal", "zarr", "dask"):
        assert heavy not in core, heavy


def test_a_mesh_without_coal_names_the_scene_extra(monkeypatch):
    from pathlib import Path

    from armkit.collision import Scene, clearance

    arm = armkit.load("puma560")
    stl = next((Path(armkit.__file__).parent / "robots").glob("*/*.stl"))
    scene = Scene([Scene.mesh(str(stl), armkit.spatial.transl(0.5, 0.0, 0.3))])   # meshes are checked by coal
    assert np.isfinite(clearance(arm, np.zeros((2, 6)), scene)).all()
    _block(monkeypatch, "coal")
    with pytest.raises(ImportError, match=r"needs the 'scene' extra .*pip install 'armkit\[scene\]'"):
        clearance(arm, np.zeros((2, 6)), scene)
