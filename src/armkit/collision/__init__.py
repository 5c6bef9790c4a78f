"""Collision checking: the arm against its surroundings (a :class:`Scene`) and itself.

>>> import armkit, numpy as np
>>> arm = armkit.load("fighter")                          # ships its torso box and the ground
>>> bool(armkit.collisions(arm, np.radians([0, -30, 0])).colliding)
True
>>> round(float(armkit.clearance(arm, np.radians([0, 45, 0]))), 3)
30.142

Only NumPy is imported here; coal (the reference library, and the route for cylinders and
meshes) is imported when a pair needs it.
"""

from __future__ import annotations

from .geometry import ArmGeometry, RobotCollision, arm_geometry, robot_collision, robot_scene
from .query import Collisions, as_scene, clearance, collisions, in_collision
from .shapes import KINDS, Scene, SceneError, Shape

__all__ = ["Scene", "Shape", "SceneError", "KINDS", "Collisions", "collisions", "clearance", "in_collision", "as_scene",
           "ArmGeometry", "RobotCollision", "arm_geometry", "robot_collision", "robot_scene"]
