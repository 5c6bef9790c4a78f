"""Drawing the arm into a viser scene: links, joint axes, frames, grid, base, meshes.

The scene is in metres (viser's camera and lights are sized for that); every length of
the robot (in ``robot.unit``) is multiplied by ``robot.unit_scale`` on the way in.

DH arms (every bundled robot) are drawn from the chain: a capsule (cylinder with round
ends) between consecutive points of :func:`armkit.analysis.workspace.skeleton_batch`
(the frame origins of :func:`armkit.fk_frames`, with the corner of a row that has both
``d`` and ``a``), a short cylinder along each joint axis, and a sphere at each joint.
A model whose ``robot.links`` carry visual shapes (URDF arms) is drawn from them,
posed by ``armkit.link_frames``; a mesh file that was not found falls back to capsules.
"""

from __future__ import annotations

import math
from typing import Any, Optional, Sequence

import numpy as np
from numpy.typing import NDArray

from ...analysis.workspace import skeleton_batch
from ...kinematics import fk_frames, link_frames
from ...model.robot import Robot

__all__ = ["ArmDrawing", "ARM_COLOUR", "add_primitive", "nice_grid", "wxyz_from_rotation", "rotation_from_wxyz",
           "z_to_direction"]

Array = NDArray[np.float64]
ARM_COLOUR = (238, 122, 24)      # the links: a saturated orange the tests look for in screenshots
JOINT_COLOUR = (60, 60, 70)
AXIS_COLOUR = (40, 110, 230)
BASE_COLOUR = (120, 120, 130)


def wxyz_from_rotation(R: Array) -> Array:
    """Unit quaternion ``(w, x, y, z)`` (viser's order, ``w >= 0``) of a rotation ``(3, 3)``."""
    m = np.asarray(R, dtype=float)
    tr = m[0, 0] + m[1, 1] + m[2, 2]
    if tr > 0:
        s = 2.0 * math.sqrt(tr + 1.0)
        q = np.array([0.25 * s, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s])
    elif m[0, 0] > m[1, 1] and m[0, 0] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2])
        q = np.array([(m[2, 1] - m[1, 2]) / s, 0.25 * s, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s])
    elif m[1, 1] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[1, 1] - m[0, 0] - m[2, 2])
        q = np.array([(m[0, 2] - m[2, 0]) / s, (m[0, 1] + m[1, 0]) / s, 0.25 * s, (m[1, 2] + m[2, 1]) / s])
    else:
        s = 2.0 * math.sqrt(1.0 + m[2, 2] - m[0, 0] - m[1, 1])
        q = np.array([(m[1, 0] - m[0, 1]) / s, (m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, 0.25 * s])
    q /= np.linalg.norm(q)
    return -q if q[0] < 0 else q


def rotation_from_wxyz(wxyz: Sequence[float] | Array) -> Array:
    """Rotation ``(3, 3)`` of a quaternion ``(w, x, y, z)`` (normalised here)."""
    w, x, y, z = np.asarray(wxyz, dtype=float) / np.linalg.norm(wxyz)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def z_to_direction(d: Array) -> Array:
    """Quaternion ``(w, x, y, z)`` turning the z axis onto the unit vector ``d`` ``(3,)``."""
    c = float(np.clip(d[2], -1.0, 1.0))
    if c < -1 + 1e-12:
        return np.array([0.0, 1.0, 0.0, 0.0])
    axis = np.array([-d[1], d[0], 0.0])      # z x d
    q = np.array([1.0 + c, axis[0], axis[1], axis[2]])
    return q / np.linalg.norm(q)


def nice_grid(reach: float) -> tuple[float, float, float]:
    """``(cell, section, width)`` of a ground grid in the robot's unit: 1-2-5 steps, about 10 cells per reach."""
    reach = reach if reach > 0 and math.isfinite(reach) else 1.0
    raw = reach / 10.0
    e = 10.0 ** math.floor(math.log10(raw))
    cell = next(m * e for m in (1.0, 2.0, 5.0, 10.0) if m * e >= raw)
    section = 5 * cell
    width = 2 * math.ceil(1.3 * reach / section) * section
    return cell, section, width


def add_primitive(scene: Any, name: str, kind: str, size: Sequence[float], position: Sequence[float],
                  wxyz: Sequence[float], **style: Any) -> Any:
    """The viser node of a box (``size`` x y z), sphere (r) or cylinder (r, h about z), sizes in metres;
    None for any other kind or a size that does not fit it. ``style``: colour, opacity, shadows.

    The one place both the robot's URDF visuals and the collision scene (:mod:`.obstacles`) draw these.
    """
    position, wxyz = tuple(position), tuple(wxyz)
    if kind == "box" and len(size) == 3:
        return scene.add_box(name, dimensions=tuple(size), position=position, wxyz=wxyz, **style)
    if kind == "sphere" and len(size) >= 1:
        return scene.add_icosphere(name, radius=size[0], position=position, wxyz=wxyz, **style)
    if kind == "cylinder" and len(size) == 2:
        return scene.add_cylinder(name, radius=size[0], height=size[1], position=position, wxyz=wxyz, **style)
    return None


def _has_visuals(robot: Robot) -> bool:
    links = getattr(robot, "links", ()) or ()
    return any(getattr(link, "visuals", ()) for link in links)


class ArmDrawing:
    """The scene nodes of one arm, updated in place by :meth:`update`.

    Parameters
    ----------
    server : viser.ViserServer
    robot : Robot
    q : ndarray, shape (n,)
        Configuration drawn first.
    """

    def __init__(self, server: Any, robot: Robot, q: Array) -> None:
        self.server = server
        self.robot = robot
        self.s = robot.unit_scale                 # metres per robot unit
        reach = robot.reach or 1.0
        self.reach_m = reach * self.s
        self.radius = 0.035 * self.reach_m
        self._lengths: list[float] = []
        self._links: list[Any] = []
        self._caps: list[Any] = []
        self._joints: list[Any] = []
        self._axes: list[Any] = []
        self._frames: list[Any] = []
        self._mesh_links: list[Any] = []
        self.frames_visible = False
        sc = server.scene
        cell, section, width = nice_grid(reach)
        self.grid_text = f"{cell:g} {robot.unit}"
        sc.add_grid("/ground", width=width * self.s, height=width * self.s, cell_size=cell * self.s,
                    section_size=section * self.s, plane="xy", shadow_opacity=0.0)
        base = np.asarray(robot.base)
        sc.add_cylinder("/arm/base", radius=2.2 * self.radius, height=0.6 * self.radius, color=BASE_COLOUR,
                        position=tuple(base[:3, 3] * self.s - base[:3, 2] * 0.3 * self.radius),
                        wxyz=tuple(wxyz_from_rotation(base[:3, :3])))
        self.meshes = self._add_meshes() if _has_visuals(robot) else False
        n = robot.n
        if not self.meshes:
            m = skeleton_batch(robot, fk_frames(robot, q)[None]).shape[1]
            self._lengths = [-1.0] * (m - 1)
            self._links = [None] * (m - 1)
            self._caps = [sc.add_icosphere(f"/arm/caps/{i}", radius=self.radius, color=ARM_COLOUR, subdivisions=2,
                                         cast_shadow=False, receive_shadow=False)
                          for i in range(m)]
        for k in range(n):
            self._joints.append(sc.add_icosphere(f"/arm/joints/{k}", radius=1.35 * self.radius,
                                                 color=JOINT_COLOUR, subdivisions=2, cast_shadow=False,
                                                 receive_shadow=False))
            self._axes.append(sc.add_cylinder(f"/arm/axes/{k}", radius=0.45 * self.radius,
                                              height=5.0 * self.radius, color=AXIS_COLOUR, cast_shadow=False,
                                              receive_shadow=False))
        for k in range(n + 1):
            self._frames.append(sc.add_frame(f"/frames/{k}", axes_length=0.18 * self.reach_m,
                                             axes_radius=0.012 * self.reach_m, visible=False))
        self.update(q)

    # ------------------------------------------------------------------ meshes
    def _add_meshes(self) -> bool:
        """Nodes for the visual shapes of ``robot.links`` (URDF); False when none could be drawn."""
        try:
            import trimesh
        except ImportError:   # pragma: no cover - trimesh comes with viser
            return False
        sc = self.server.scene
        drawn = 0
        for li, link in enumerate(self.robot.links):  # type: ignore[attr-defined]
            node = sc.add_frame(f"/arm/links/{li}", show_axes=False)
            self._mesh_links.append(node)
            for si, shape in enumerate(getattr(link, "visuals", ())):
                name = f"/arm/links/{li}/v{si}"
                T = np.asarray(shape.origin, dtype=float)
                pos = tuple(T[:3, 3] * self.s)
                wxyz = tuple(wxyz_from_rotation(T[:3, :3]))
                rgba = shape.rgba if getattr(shape, "rgba", None) is not None else (0.93, 0.48, 0.09, 1.0)
                colour = tuple(int(round(255 * c)) for c in rgba[:3])
                size = tuple(float(v) * self.s for v in (shape.size or ()))
                if shape.kind == "mesh":
                    if not shape.mesh_path:
                        continue
                    try:
                        from ..._limits import check_mesh_file

                        check_mesh_file(shape.mesh_path)       # too large: not drawn, like a bad file
                        mesh: Any = trimesh.load(shape.mesh_path, force="mesh")
                    except Exception:  # noqa: BLE001 - a bad mesh file: draw the others
                        continue
                    scale = np.asarray(getattr(shape, "scale", (1.0, 1.0, 1.0)), dtype=float) * self.s
                    mesh.apply_scale(scale)
                    if getattr(shape, "rgba", None) is not None:
                        mesh.visual = trimesh.visual.ColorVisuals(mesh, face_colors=np.array(rgba) * 255)
                    sc.add_mesh_trimesh(name, mesh, position=pos, wxyz=wxyz)
                elif add_primitive(sc, name, shape.kind, size, pos, wxyz, color=colour) is None:
                    continue
                drawn += 1
        if drawn == 0:
            sc.remove_by_name("/arm/links")
            self._mesh_links = []
        return drawn > 0

    # ------------------------------------------------------------------ update
    def set_frames_visible(self, visible: bool) -> None:
        """Show or hide the link frames (x red, y green, z blue)."""
        self.frames_visible = bool(visible)
        for f in self._frames:
            f.visible = self.frames_visible

    def update(self, q: Array, frames: Optional[Array] = None) -> None:
        """Move every node to configuration ``q`` ``(n,)`` (``frames``: its ``fk_frames``, if known)."""
        robot, s, sc = self.robot, self.s, self.server.scene
        F = fk_frames(robot, q) if frames is None else frames
        if self.meshes:
            L = np.asarray(link_frames(robot, q))
            for node, T in zip(self._mesh_links, L):
                node.position = tuple(T[:3, 3] * s)
                node.wxyz = tuple(wxyz_from_rotation(T[:3, :3]))
        else:
            pts = skeleton_batch(robot, F[None])[0] * s
            for i, cap in enumerate(self._caps):
                cap.position = tuple(pts[i])
            for i in range(len(pts) - 1):
                d = pts[i + 1] - pts[i]
                length = float(np.linalg.norm(d))
                if length < 1e-9 * max(self.reach_m, 1e-9):
                    if self._links[i] is not None:
                        self._links[i].visible = False
                    continue
                if self._links[i] is None or abs(length - self._lengths[i]) > 1e-9 * self.reach_m:
                    self._links[i] = sc.add_cylinder(f"/arm/links/{i}", radius=self.radius, height=length,
                                                     color=ARM_COLOUR, cast_shadow=False, receive_shadow=False)
                    self._lengths[i] = length
                link = self._links[i]
                link.visible = True
                link.position = tuple(0.5 * (pts[i] + pts[i + 1]))
                link.wxyz = tuple(z_to_direction(d / length))
        A = F[:-1] @ robot.chain.pre        # joint k turns about the z axis of this frame
        for k in range(robot.n):
            p = A[k, :3, 3] * s
            self._joints[k].position = tuple(p)
            self._axes[k].position = tuple(p)
            self._axes[k].wxyz = tuple(z_to_direction(A[k, :3, 2]))
        if self.frames_visible:
            for f, T in zip(self._frames, F):
                f.position = tuple(T[:3, 3] * s)
                f.wxyz = tuple(wxyz_from_rotation(T[:3, :3]))
