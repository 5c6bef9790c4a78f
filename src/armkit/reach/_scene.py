"""Excluding configurations that collide with a scene (``scene=`` of :func:`armkit.reachability`).

The collision module (``armkit.collision``) provides ``clearance(robot, q, scene)``: the
signed distance between the arm and the scene (and itself), batched over ``q`` ``(..., n)``.
A sample (FK method) or an IK solution (IK method) counts only where the clearance is
positive. Without that module a scene is refused with a clear message, never ignored.
"""

from __future__ import annotations

import importlib
from typing import Any, Callable

import numpy as np
from numpy.typing import NDArray

from ..errors import ArmkitError, SceneError, SceneNotSupportedError
from ..model.robot import Robot

__all__ = ["SceneNotSupportedError", "clearance_function", "collision_free"]


def clearance_function() -> Callable[..., Any]:
    """``armkit.collision.clearance`` or :class:`SceneNotSupportedError`."""
    try:
        mod = importlib.import_module("armkit.collision")
        fn = getattr(mod, "clearance")
    except (ImportError, AttributeError):
        raise SceneNotSupportedError.of(
            "scene= needs collision checking (armkit.collision.clearance), which this build of armkit "
            "does not have; build the map without a scene (scene=None)") from None
    return fn  # type: ignore[no-any-return]


def check_scene(robot: Robot, scene: Any) -> Any:
    """The scene as ``armkit.collision`` takes it (a :class:`armkit.Scene` in the robot's unit), or None.

    Raises :class:`SceneNotSupportedError` when collision checking is missing, and the collision
    module's own error for a scene it cannot read.
    """
    if scene is None:
        return None
    clearance_function()
    mod = importlib.import_module("armkit.collision")
    as_scene = getattr(mod, "as_scene", None)
    if as_scene is None:
        return scene
    try:
        return as_scene(robot, scene)
    except ArmkitError:
        raise
    except (TypeError, ValueError, AttributeError) as exc:
        raise SceneError.of("scene must be an armkit.Scene, a sequence of shapes, a scene file or 'robot'; got {type} "
                            "({exc})", type=type(scene).__name__, exc=exc) from None


def collision_free(robot: Robot, q: NDArray[np.float64], scene: Any) -> NDArray[np.bool_]:
    """True where configuration ``q`` ``(N, n)`` keeps a positive clearance to ``scene``."""
    d = np.asarray(clearance_function()(robot, q, scene), dtype=float)
    return np.asarray(d > 0.0).reshape(len(q))
