"""The arm's collision geometry: which solids move with which link, and which pairs are checked.

* Links that carry collision shapes (URDF ``<collision>``, or a robot file's ``[[body]]``) use
  them; primitives as they are, meshes through the convex hull of their vertices (coal).
* Every other segment between consecutive origins of :func:`armkit.fk_frames` becomes a
  capsule, the segment swept by a ball of the robot's ``link_radius`` (robot file; default
  3 % of :attr:`Robot.reach`).
* Pairs that touch by design are never checked (SRDF's disable-collisions): solids of the same
  or of adjacent links, pairs listed in the robot file (``allow_collision``), shapes' ``allow``
  lists, and pairs found touching in every one of 256 random configurations (e.g. two
  capsules meeting at a wrist centre through a zero-length link).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..model.robot import Robot
from .shapes import Scene, SceneError, Shape

__all__ = ["RobotCollision", "Solid", "ArmGeometry", "arm_geometry", "robot_collision", "robot_scene",
           "DEFAULT_RADIUS_FRACTION"]

Array = NDArray[np.float64]
DEFAULT_RADIUS_FRACTION = 0.03


@dataclass(frozen=True)
class RobotCollision:
    """What a robot file says about the arm's solids and surroundings.

    Attributes
    ----------
    link_radius : tuple of float or None
        Capsule radius of each joint's link segment ``(n,)`` (robot unit); ``None``: default.
    body : tuple of Shape
        Solids fixed to a link (``Shape.link``; the base link when ``None``): the robot's body.
    scene : tuple of Shape
        The robot's default surroundings (the ground), used when no scene is given.
    allow_collision : tuple of (str, str)
        Link pairs that may touch.
    """

    link_radius: tuple[float, ...] | None = None
    body: tuple[Shape, ...] = ()
    scene: tuple[Shape, ...] = ()
    allow_collision: tuple[tuple[str, str], ...] = ()


def robot_collision(robot: Robot) -> RobotCollision:
    """The robot file's collision data (an empty :class:`RobotCollision` when it has none)."""
    return getattr(robot, "collision", None) or RobotCollision()


def robot_scene(robot: Robot) -> Scene:
    """The robot's default surroundings (its file's ``[[scene]]`` shapes; empty for most arms)."""
    return Scene(robot_collision(robot).scene, robot.unit)


@dataclass(frozen=True, eq=False)
class Solid:
    """One solid of the arm: where a :class:`Shape` sits on the chain, or a chain segment.

    ``kind`` "segment" is a capsule between two frame origins (``ends``, radius ``size[0]``); any
    other kind is a row of :data:`armkit.collision.shapes.KIND_TABLE` and ``shape`` is the
    :class:`Shape` itself (``kind`` and ``size`` are its own, kept here for the kernels' packing).
    ``frame`` indexes :func:`armkit.fk_frames`; ``local`` is the shape's pose in that frame
    (link offset included). ``level`` orders the solids along the chain (adjacent levels touch).
    """

    name: str
    link: str
    kind: str
    frame: int
    level: int
    local: Array = field(default_factory=lambda: np.eye(4))
    size: tuple[float, ...] = ()
    ends: tuple[int, int] = (0, 0)
    shape: Shape | None = None


@dataclass(frozen=True, eq=False)
class ArmGeometry:
    """The solids of one robot and the self-collision pairs to check."""

    robot_name: str
    unit: str
    solids: tuple[Solid, ...]
    self_pairs: tuple[tuple[int, int], ...]
    allow_pairs: frozenset[frozenset[str]]
    always_touching: tuple[tuple[str, str], ...]

    def allowed(self, link: str, shape: Shape) -> bool:
        return link in shape.allow or frozenset((link, shape.name)) in self.allow_pairs


def _links(robot: Robot) -> list[Any]:
    links = getattr(robot, "links", ())
    if links:
        return list(links)

    class _L:   # a DH robot before links existed: one link per chain frame
        def __init__(self, name: str, frame: int) -> None:
            self.name, self.frame, self.offset, self.collisions = name, frame, np.eye(4), ()

    return [_L(nm, k) for k, nm in enumerate(robot.link_names)]


def _radii(robot: Robot, spec: RobotCollision) -> list[float]:
    if spec.link_radius is not None:
        return list(spec.link_radius)
    return [DEFAULT_RADIUS_FRACTION * robot.reach] * robot.n


def _build(robot: Robot) -> ArmGeometry:
    spec = robot_collision(robot)
    links = _links(robot)
    n = robot.n
    solids: list[Solid] = []
    by_frame: dict[int, list[Any]] = {}
    for lk in links:
        by_frame.setdefault(int(lk.frame), []).append(lk)
    shaped = {lk.name for lk in links
              if any(c.kind != "mesh" or c.mesh_path for c in getattr(lk, "collisions", ()))}
    # link-attached shapes (URDF collisions)
    for lk in links:
        for k, s in enumerate(getattr(lk, "collisions", ())):
            local = np.asarray(lk.offset, dtype=float) @ np.asarray(s.origin, dtype=float)
            # the model's URDF geometry as the collision side's one shape type (the pose is in `local`)
            shape = Shape(s.kind, np.eye(4), tuple(s.size), f"{lk.name}", (), lk.name, s.mesh_path, tuple(s.scale))
            if s.kind == "mesh" and not s.mesh_path:
                continue   # the importer could not find the file: nothing to collide with
            solids.append(Solid(lk.name if len(lk.collisions) == 1 else f"{lk.name}[{k}]", lk.name, s.kind,
                                int(lk.frame), int(lk.frame), local, tuple(s.size), shape=shape))
    # the robot file's body
    names = {lk.name: lk for lk in links}
    for s in spec.body:
        lk = names.get(s.link or links[0].name)
        if lk is None:
            raise SceneError(f"robot {robot.name!r}: body shape {s.name!r} is fixed to link {s.link!r}, which the "
                             f"robot does not have; its links are: {', '.join(names)}")
        local = np.asarray(lk.offset, dtype=float) @ s.pose
        solids.append(Solid(s.name, lk.name, s.kind, int(lk.frame), int(lk.frame), local, s.size, shape=s))
    # capsules along the chain for links without their own shapes
    # frames: 0..n from fk_frames (n with the tool), n + 1 the flange (frame n without the tool)
    radii = _radii(robot, spec)
    fixed_before = robot.convention != "standard"   # modified DH, URDF: origin k is fixed in link k - 1
    has_tool = float(np.linalg.norm(np.asarray(robot.tool)[:3, 3])) > 0
    for s in range(1, n + 1):
        owner = s - 1 if fixed_before else s
        cands = by_frame.get(owner, [])
        link = cands[0].name if cands else robot.link_names[min(owner, len(robot.link_names) - 1)]
        if link in shaped or radii[s - 1] <= 0:
            continue
        solids.append(Solid(link, link, "segment", owner, owner, size=(radii[s - 1],),
                            ends=(s - 1, n + 1 if s == n and has_tool else s)))
    if has_tool:   # the tool: from the flange to the tool point, part of the last link
        cands = by_frame.get(n, [])
        link = cands[0].name if cands else robot.link_names[-1]
        if link not in shaped and radii[-1] > 0:
            solids.append(Solid(f"{link} tool" if any(x.link == link for x in solids) else link, link, "segment", n,
                                n, size=(radii[-1],), ends=(n + 1, n)))
    allow = frozenset(frozenset(p) for p in spec.allow_collision)
    pairs = []
    for i in range(len(solids)):
        for j in range(i + 1, len(solids)):
            a, b = solids[i], solids[j]
            if abs(a.level - b.level) <= 1 or a.link == b.link or frozenset((a.link, b.link)) in allow:
                continue
            if a.shape is not None and b.link in a.shape.allow or b.shape is not None and a.link in b.shape.allow:
                continue
            pairs.append((i, j))
    geo = ArmGeometry(robot.name, robot.unit, tuple(solids), tuple(pairs), allow, ())
    if pairs:   # pairs that touch in every configuration are part of the design
        from .query import _pair_distances, chain_frames

        q = np.concatenate([np.clip(np.zeros((1, n)), robot.lower, robot.upper), robot.random_q(255, rng=12345)])
        d = _pair_distances(geo, chain_frames(robot, q), [], pairs)
        always = np.all(d < 0, axis=0)
        if always.any():
            keep = tuple(p for p, a in zip(pairs, always) if not a)
            touching = tuple((solids[i].name, solids[j].name) for (i, j), a in zip(pairs, always) if a)
            geo = ArmGeometry(robot.name, robot.unit, tuple(solids), keep, allow, touching)
    return geo


def arm_geometry(robot: Robot) -> ArmGeometry:
    """The :class:`ArmGeometry` of ``robot`` (built once, kept in the immutable robot's cache)."""
    geo = robot.cache.get("arm_geometry")
    if geo is None:
        geo = robot.cache["arm_geometry"] = _build(robot)
    return geo  # type: ignore[no-any-return]
