"""armkit: serial robot-arm kinematics for students and engineers.

>>> import armkit, numpy as np
>>> arm = armkit.load("fighter")
>>> np.round(armkit.fk(arm, np.radians([30, 45, 60]))[:3, 3], 3)
array([ 24.861,  14.353, 187.181])
"""

from __future__ import annotations

from . import spatial
from ._version import __version__
from .errors import (ArgumentError, ArmkitError, CalibrationInputError, CalibrationRangeWarning, IKInputError, JointLimitError, LimitError, MapFileError,
                     MissingExtraError, NotRigidError, ParseError, ReachabilityError, RobotDefinitionError,
                     RobotFileError, RobotFileNotFoundError, SceneError, SceneFileError, SceneNotSupportedError,
                     ShapeError,
                     UnknownRobotError, UnreachableError, ViewError, WriteError, WriteInterrupted)
from .kinematics import (condition_number, fk, fk_frames, get_backend, is_singular, jacobian, link_frames,
                         manipulability, set_backend)
from .model import Joint, Link, Robot, Shape, bundled_robots, load, save
from .ik import IKResult, ik, ik_all
from .warmup import warmup
from .model.robot import CollisionKeys, read_collision_keys_with


def _collision_keys() -> CollisionKeys:
    """The collision floor reads a robot file's collision keys; imported only when a file has them."""
    from .collision import robot_file

    return robot_file  # type: ignore[return-value]


read_collision_keys_with(_collision_keys)   # the top floor plugs the collision floor into the model floor


def view(robot: "Robot | str", port: "int | None" = None, **kwargs):  # type: ignore[no-untyped-def]
    """Open a live 3-D view of ``robot`` in the browser; see :func:`armkit.viz.view.view` and docs/view.md.

    Imports viser only when called (``import armkit`` stays light). Returns the handle
    (``.url``, ``.q``, ``set_q``, ``set_target``, ``show_path``, ``close``).
    """
    from .viz.view import view as _open

    return _open(robot, port=port, **kwargs)


__all__ = [
    "spatial", "Joint", "Robot", "Link", "Shape", "load", "save", "bundled_robots",
    "fk", "fk_frames", "link_frames", "jacobian", "manipulability", "condition_number", "is_singular",
    "set_backend", "get_backend", "warmup",
    "ArmkitError", "ArgumentError", "ShapeError", "RobotDefinitionError", "RobotFileError", "UnknownRobotError",
    "RobotFileNotFoundError", "JointLimitError", "UnreachableError", "IKInputError", "ParseError", "LimitError",
    "WriteError", "WriteInterrupted",
    "MissingExtraError", "SceneError", "SceneFileError", "SceneNotSupportedError", "ReachabilityError", "MapFileError",
    "ViewError", "NotRigidError", "CalibrationRangeWarning", "CalibrationInputError",
    "IKResult", "ik", "ik_all", "view",
    "Scene", "Collisions", "collisions", "clearance",
    "reachability", "ReachabilityMap", "base_placement",
]

_LAZY = {"Scene", "Collisions", "collisions", "clearance"}   # armkit.collision, imported on first use
_REACH = {"reachability", "ReachabilityMap", "base_placement"}   # armkit.reach (dask/zarr only when a map is built)


def __getattr__(name: str) -> object:
    if name in _LAZY or name == "collision":
        import importlib

        collision = importlib.import_module("armkit.collision")   # not "from . import": that asks __getattr__ again
        return collision if name == "collision" else getattr(collision, name)
    if name in _REACH:
        from . import reach

        return getattr(reach, name)
    raise AttributeError(f"module 'armkit' has no attribute {name!r}")
