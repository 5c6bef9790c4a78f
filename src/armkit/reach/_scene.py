"""Excluding configurations that collide with a scene (``scene=`` of :func:`armkit.reachability`).

The collision module (``armkit.collision``) provides ``clearance(robot, q, scene)``: the
signed distance between the arm and the scene, batched over ``q`` ``(..., n)``. A sample
counts only where the clearance is positive. Until that module is present, a scene is
refused with a clear message rather than ignored.
"""

from __future__ import annotations

import importlib
from typing import Any, Callable

import numpy as np
from numpy.typing import NDArray

from ..errors import ArmkitError
from ..model.robot import Robot

__all__ = ["SceneNotSupportedError", "clearance_function", "collision_free"]


class SceneNotSupportedError(ArmkitError, NotImplementedError):
    """``scene=`` was given but this build of armkit has no collision checking."""


def clearance_function() -> Callable[..., Any]:
    """``armkit.collision.clearance`` or :class:`SceneNotSupportedError`."""
    try:
        mod = importlib.import_module("armkit.collision")
        fn = getattr(mod, "clearance")
    except (ImportError, AttributeError):
        raise SceneNotSupportedError(
            "scene= needs collision checking (armkit.collision.clearance), which this build of armkit "
            "does not have; build the map without a scene (scene=None)") from None
    return fn  # type: ignore[no-any-return]


def check_scene(scene: Any) -> None:
    """Raise early when a scene is given but cannot be used."""
    if scene is None:
        return
    clearance_function()
    try:
        Scene = getattr(importlib.import_module("armkit"), "Scene")
    except AttributeError:
        return
    if not isinstance(scene, Scene):
        raise ArmkitError(f"scene must be an armkit.Scene or None, got {type(scene).__name__}")


def collision_free(robot: Robot, q: NDArray[np.float64], scene: Any) -> NDArray[np.bool_]:
    """True where configuration ``q`` ``(N, n)`` keeps a positive clearance to ``scene``."""
    d = np.asarray(clearance_function()(robot, q, scene), dtype=float)
    return np.asarray(d > 0.0).reshape(len(q))
