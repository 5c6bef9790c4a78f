"""Drawing the arm's surroundings into the view: the collision scene and the robot's body.

The shapes of :mod:`armkit.collision` (the robot file's ``[[scene]]`` and ``[[body]]``, or a
scene the user gives) are drawn translucent: boxes, spheres, cylinders, capsules (a
cylinder with two spheres), meshes, and a plane as a thin square of the ground grid's width
(the solid half-space is the side behind its normal). Body shapes move with their link.
After every move :func:`armkit.collisions` is asked which pairs overlap; every drawn shape
named in such a pair turns red, the others go back to grey-blue.
"""

from __future__ import annotations

from typing import Any, Optional

import numpy as np
from numpy.typing import NDArray

from ...collision import Collisions, Scene, Shape, arm_geometry, collisions, robot_collision
from ...model.robot import Robot
from .drawing import add_primitive, wxyz_from_rotation

__all__ = ["ObstacleDrawing", "FREE_COLOUR", "HIT_COLOUR"]

Array = NDArray[np.float64]
FREE_COLOUR = (110, 135, 175)     # translucent grey-blue: something the arm must not touch
HIT_COLOUR = (225, 25, 25)        # the same shape while the arm overlaps it
FREE_OPACITY, HIT_OPACITY = 0.35, 0.6


class ObstacleDrawing:
    """The scene nodes of the arm's surroundings and body, coloured by collision.

    Parameters
    ----------
    server : viser.ViserServer
    robot : Robot
    scene : Scene
        The surroundings, in the robot's unit (:func:`armkit.collision.as_scene`).
    plane_width : float
        Side of the square that stands for a plane, in metres (the ground grid's width).
    """

    def __init__(self, server: Any, robot: Robot, scene: Scene, plane_width: float) -> None:
        self.server, self.robot, self.scene = server, robot, scene
        self.s = robot.unit_scale
        self.plane_width = plane_width
        self.nodes: dict[str, list[Any]] = {}          # shape name -> its nodes (a capsule has three)
        self._moving: list[tuple[Any, int, Array]] = []   # (root node, fk frame, pose in that frame)
        self.colliding: tuple[str, ...] = ()
        self.result: Optional[Collisions] = None
        spec = robot_collision(robot)
        body = [sol for sol in arm_geometry(robot).solids
                if sol.shape is not None and any(sol.shape is b for b in spec.body)]
        for i, shape in enumerate(scene):               # fixed in the world: posed once
            self._add(f"/obstacles/scene/{i}", shape, shape.pose)
        for i, sol in enumerate(body):
            assert sol.shape is not None
            root = self._add(f"/obstacles/body/{i}", sol.shape, np.eye(4))
            self._moving.append((root, sol.frame, np.asarray(sol.local, dtype=float)))
        self.active = bool(self.nodes)

    # ------------------------------------------------------------------ nodes
    def _add(self, name: str, shape: Shape, T: Array) -> Any:
        """Nodes for ``shape`` at pose ``T`` (robot unit); returns the root node."""
        sc, s = self.server.scene, self.s
        common = dict(color=FREE_COLOUR, opacity=FREE_OPACITY, cast_shadow=False, receive_shadow=False)
        pos = tuple(np.asarray(T)[:3, 3] * s)
        wxyz = tuple(wxyz_from_rotation(np.asarray(T)[:3, :3]))
        size = tuple(float(v) * s for v in shape.size)
        made: list[Any] = []
        if shape.kind == "plane":
            thick = 0.002 * self.plane_width
            n = np.asarray(T)[:3, 2]
            base = np.asarray(self.robot.base)[:3, 3] * s
            foot = base - (float(n @ base) - float(n @ np.asarray(T)[:3, 3]) * s) * n   # the base's foot on it
            root = sc.add_box(name, dimensions=(self.plane_width, self.plane_width, thick),
                              position=tuple(foot - 0.5 * thick * n), wxyz=wxyz, **common)
            made.append(root)
        elif shape.kind in ("box", "sphere", "cylinder"):
            root = add_primitive(sc, name, shape.kind, size, pos, wxyz, **common)
            made.append(root)
        elif shape.kind == "capsule":
            root = sc.add_frame(name, show_axes=False, position=pos, wxyz=wxyz)
            r, h = size[0], size[1]
            made.append(sc.add_cylinder(f"{name}/body", radius=r, height=h, **common))
            for k, z in enumerate((-0.5 * h, 0.5 * h)):
                made.append(sc.add_icosphere(f"{name}/end{k}", radius=r, position=(0.0, 0.0, z), subdivisions=3,
                                             **common))
        else:   # mesh
            root = sc.add_frame(name, show_axes=False, position=pos, wxyz=wxyz)
            try:
                import trimesh

                from ..._limits import check_mesh_file

                check_mesh_file(shape.mesh_path)  # type: ignore[arg-type]  # too large: left out like an unreadable mesh
                mesh: Any = trimesh.load(shape.mesh_path, force="mesh")
                verts = np.asarray(mesh.vertices, dtype=float) * np.asarray(shape.scale, dtype=float) * s
                made.append(sc.add_mesh_simple(f"{name}/mesh", vertices=verts.astype(np.float32),
                                               faces=np.asarray(mesh.faces, dtype=np.uint32), side="double",
                                               **common))
            except Exception:  # noqa: BLE001 - a mesh that cannot be read is left out of the picture only
                pass
        self.nodes.setdefault(shape.name, []).extend(made)
        return root

    # ------------------------------------------------------------------ update
    def update(self, q: Array, frames: Array) -> Optional[Collisions]:
        """Move the body shapes to ``q`` (``frames``: its :func:`armkit.fk_frames`) and colour by collision."""
        if not self.active:
            return None
        for node, k, local in self._moving:
            T = frames[k] @ local
            node.position = tuple(T[:3, 3] * self.s)
            node.wxyz = tuple(wxyz_from_rotation(T[:3, :3]))
        res = collisions(self.robot, q, self.scene)
        hit = {name for a, b, _ in res.colliding_pairs() for name in (a, b)}
        colliding = tuple(sorted(name for name in self.nodes if name in hit))
        if colliding != self.colliding:
            for name, nodes in self.nodes.items():
                on = name in hit
                for node in nodes:
                    node.color = HIT_COLOUR if on else FREE_COLOUR
                    node.opacity = HIT_OPACITY if on else FREE_OPACITY
            self.colliding = colliding
        self.result = res
        return res
