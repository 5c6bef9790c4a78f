"""The collision keys of a robot file: ``link_radius``, ``allow_collision``, ``[[body]]`` and ``[[scene]]``.

::

    link_radius = 8                          # capsule radius of every link (robot unit)
    allow_collision = [["turret", "forearm"]]   # link pairs that may touch

    [[joints]]
    link_radius = 12                         # this joint's link only

    [[body]]                                 # a solid fixed to a link (default: the base link)
    type = "box"
    name = "torso"
    center = [0, 0, -12.5]
    size = [160, 120, 25]

    [[scene]]                                # the robot's default surroundings
    type = "plane"
    name = "ground"
    normal = [0, 0, 1]
    offset = -25

Shapes are written as in scene files (``docs/scene.md``), in the robot's units.
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

from ..errors import RobotFileError
from ..model.robot import Robot
from ..model.files import finite_number
from .files import MAX_SHAPES, block_line, mesh_lookup, shape_from_table
from .geometry import RobotCollision
from .shapes import KIND_TABLE

__all__ = ["attach", "surroundings", "carry_collision"]


def attach(robot: Robot, data: dict, text: str, path: str, allow_outside: bool = False) -> None:
    """Read the collision keys of a parsed robot file and keep them on ``robot`` as ``robot.collision``.

    Mesh paths follow the scene files' rules (``allow_outside``); more than ``MAX_SHAPES`` shapes are refused.
    """
    lines = text.splitlines()
    ang = math.pi / 180.0 if data.get("angle_unit", "deg") == "deg" else 1.0

    def top_line(key: str) -> int | None:
        return next((i + 1 for i, ln in enumerate(lines) if re.match(rf"\s*{re.escape(key)}\s*=", ln)), None)

    def finite_radius(v: Any, field: str, line: int | None) -> float:
        if not finite_number(v) or v < 0:
            raise RobotFileError(path, "must be a finite number >= 0 (a radius in {unit}), got {got!r}", line,
                                 field, unit=robot.unit, got=v)
        return float(v)

    default = None
    if "link_radius" in data:
        default = finite_radius(data["link_radius"], "link_radius", top_line("link_radius"))
    rows = data.get("joints", [])
    per = [row.get("link_radius") if isinstance(row, dict) else None for row in rows]
    radii = None
    if default is not None or any(v is not None for v in per):
        from .geometry import DEFAULT_RADIUS_FRACTION

        fallback = default if default is not None else DEFAULT_RADIUS_FRACTION * robot.reach
        radii = tuple(fallback if v is None else finite_radius(
            v, f"joints[{k + 1}].link_radius", block_line(lines, "joints", k, "link_radius"))
            for k, v in enumerate(per))
    links = list(robot.link_names)
    if getattr(robot, "links", ()):
        links = [lk.name for lk in robot.links]
    pairs = data.get("allow_collision", [])
    line = top_line("allow_collision")
    if not isinstance(pairs, list) or not all(isinstance(p, list) and len(p) == 2 and all(isinstance(x, str) for x in p)
                                               for p in pairs):
        raise RobotFileError(path, "must be a list of [link, link] pairs, got {got!r}", line, "allow_collision",
                             got=pairs)
    for p in pairs:
        for x in p:
            if x not in links:
                raise RobotFileError(path, "no link {name!r}; the links are: {names}", line,
                                     "allow_collision", name=x, names=', '.join(links))
    tables: dict[str, list] = {}
    folder = Path(path).resolve().parent
    meshes = mesh_lookup(folder, allow_outside)
    for key in ("body", "scene"):
        rows_k = data.get(key, [])
        if not isinstance(rows_k, list):
            raise RobotFileError(path, "must be an array of tables: write [[{key}]] above each shape",
                                 top_line(key), key, key=key)
        if len(rows_k) > MAX_SHAPES:
            raise RobotFileError(path, "{n:,} shapes; a robot file may hold at most {limit:,} "
                                 "[[{key}]] tables", None, key, n=len(rows_k), limit=MAX_SHAPES, key=key)
        out = []
        for k, row in enumerate(rows_k):
            def fail(message: str, field: str, key_: str | None, k: int = k, key: str = key,
                     **fields: object) -> Exception:
                return RobotFileError(path, message, block_line(lines, key, k, key_), field, **fields)

            shape, extra = shape_from_table(row, f"{key}[{k + 1}]", fail, ang, folder,
                                            frozenset({"link"}) if key == "body" else frozenset(), meshes)
            link = extra.get("link")
            if link is not None:
                if not isinstance(link, str) or link not in links:
                    raise fail("no link {name!r}; the links are: {names}", f"{key}[{k + 1}].link", "link", name=link,
                               names=', '.join(links))
                from dataclasses import replace

                shape = replace(shape, link=link)
            if key == "body" and shape.kind == "plane":
                raise fail("a body shape must be a solid of finite size; put planes (the ground) in [[scene]]",
                           f"{key}[{k + 1}].type", "type")
            out.append(shape)
        tables[key] = out
    object.__setattr__(robot, "collision", RobotCollision(radii, tuple(tables["body"]), tuple(tables["scene"]),
                                                          tuple((a, b) for a, b in pairs)))


def _shape_row(s: Any, scale: float) -> dict[str, Any]:
    """One Shape as a robot-file table (lengths times ``scale``, rpy in radians: the caller converts)."""
    row: dict[str, Any] = {"type": s.kind, "name": s.name}
    row.update(KIND_TABLE[s.kind].write(s, scale))
    if s.allow:
        row["allow"] = list(s.allow)
    if s.link is not None:
        row["link"] = s.link
    return row


def surroundings(robot: Robot, scale: float = 1.0, links: Any = None) -> dict[str, Any]:
    """The collision keys :func:`attach` reads, from ``robot.collision``: what a save writes back (issue 24).

    ``{"link_radius": r}`` or ``{"joint_radius": [r1, ...]}`` (one per joint, for the ``[[joints]]`` tables),
    ``allow_collision``, ``body`` and ``scene`` (lists of tables; every ``rpy`` in radians). Lengths are
    multiplied by ``scale`` (a URDF is written in metres). ``links``: the link names the written robot has;
    body shapes and allowed pairs that name another link are left out with a warning. Empty when the robot
    has no collision keys.
    """
    spec = getattr(robot, "collision", None)
    if spec is None:
        return {}
    out: dict[str, Any] = {}
    if spec.link_radius is not None:
        radii = [float(r) * scale for r in spec.link_radius]
        if len(set(radii)) == 1:
            out["link_radius"] = radii[0]
        else:
            out["joint_radius"] = radii
    names = None if links is None else set(links)
    dropped: list[str] = []
    pairs = [list(p) for p in spec.allow_collision]
    if names is not None:
        dropped += [f"{a}/{b}" for a, b in pairs if a not in names or b not in names]
        pairs = [p for p in pairs if p[0] in names and p[1] in names]
    if pairs:
        out["allow_collision"] = pairs
    for key in ("body", "scene"):
        rows = []
        for s in getattr(spec, key):
            if names is not None and s.link is not None and s.link not in names:
                dropped.append(s.name)
                continue
            rows.append(_shape_row(s, scale))
        if rows:
            out[key] = rows
    if dropped:
        import warnings

        warnings.warn(f"robot {robot.name!r}: {len(dropped)} collision entries name links the written file does not "
                      f"have and were left out (first: {dropped[0]})", stacklevel=3)
    return out


def carry_collision(source: Robot, target: Robot) -> None:
    """Give ``target`` (``source``'s DH twin: the same joints) ``source``'s collision keys; entries that name a
    link ``target`` does not have are left out."""
    spec = getattr(source, "collision", None)
    if spec is None or target.n != source.n:
        return
    names = {lk.name for lk in target.links} | set(target.link_names)
    body = tuple(s for s in spec.body if s.link is None or s.link in names)
    pairs = tuple(p for p in spec.allow_collision if p[0] in names and p[1] in names)
    object.__setattr__(target, "collision", RobotCollision(spec.link_radius, body, spec.scene, pairs))
