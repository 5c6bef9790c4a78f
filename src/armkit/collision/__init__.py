"""Collision checking: the arm against its surroundings (a :class:`Scene`) and itself.

>>> import armkit, numpy as np
>>> arm = armkit.load("fighter")                          # ships its torso box and the ground
>>> res = armkit.collisions(arm, np.radians([0, -30, 0]))  # shoulder 30 deg down: the hand goes under the floor
>>> bool(res.colliding), res.message()
(True, 'the forearm hits the ground by 35.6 mm (3 pairs in collision)')
>>> float(armkit.clearance(arm, np.radians([0, 45, 0])))   # the turret (radius 8 mm) is 17 mm above the floor
17.0

One rule for ``scene=`` everywhere (:func:`resolve_scene`): ``None`` is the robot's own
surroundings (its body and ground from the robot file), ``False`` no check, an explicit scene
replaces the robot's ground (its body always stays). IK results and command outputs say what
they were checked against (:func:`checked_against`, ``IKResult.checked_against``).

Only NumPy is imported here; coal (the reference library, and the route for meshes) is imported
when a pair needs it. What each kind of shape is (its file keys, kernels, coal geometry, drawing)
is one row of :data:`KIND_TABLE` (``docs/adding-a-primitive.md``).
"""

from __future__ import annotations

from .geometry import ArmGeometry, RobotCollision, arm_geometry, robot_collision, robot_scene
from .query import (Collisions, as_scene, checked_against, checked_note, clearance, colliding_rows, collisions,
                    in_collision, resolve_scene, row_messages)
from .shapes import KIND_TABLE, KINDS, Scene, SceneError, Shape, ShapeKind

__all__ = ["Scene", "Shape", "SceneError", "KINDS", "KIND_TABLE", "ShapeKind", "Collisions", "collisions", "clearance", "in_collision", "colliding_rows", "row_messages", "as_scene",
           "resolve_scene", "checked_against", "checked_note",
           "ArmGeometry", "RobotCollision", "arm_geometry", "robot_collision", "robot_scene"]
