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
from .files import block_line, shape_from_table
from .geometry import RobotCollision

__all__ = ["attach"]


def attach(robot: Robot, data: dict, text: str, path: str) -> None:
    """Read the collision keys of a parsed robot file and keep them on ``robot`` as ``robot.collision``."""
    lines = text.splitlines()
    ang = math.pi / 180.0 if data.get("angle_unit", "deg") == "deg" else 1.0

    def top_line(key: str) -> int | None:
        return next((i + 1 for i, ln in enumerate(lines) if re.match(rf"\s*{re.escape(key)}\s*=", ln)), None)

    def finite_radius(v: Any, field: str, line: int | None) -> float:
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
            raise RobotFileError(path, f"must be a finite number >= 0 (a radius in {robot.unit}), got {v!r}", line,
                                 field)
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
        raise RobotFileError(path, f"must be a list of [link, link] pairs, got {pairs!r}", line, "allow_collision")
    for p in pairs:
        for x in p:
            if x not in links:
                raise RobotFileError(path, f"no link {x!r}; the links are: {', '.join(links)}", line,
                                     "allow_collision")
    tables: dict[str, list] = {}
    for key in ("body", "scene"):
        rows_k = data.get(key, [])
        if not isinstance(rows_k, list):
            raise RobotFileError(path, f"must be an array of tables: write [[{key}]] above each shape",
                                 top_line(key), key)
        out = []
        for k, row in enumerate(rows_k):
            def fail(message: str, field: str, key_: str | None, k: int = k, key: str = key) -> Exception:
                return RobotFileError(path, message, block_line(lines, key, k, key_), field)

            shape, extra = shape_from_table(row, f"{key}[{k + 1}]", fail, ang, Path(path).resolve().parent,
                                            frozenset({"link"}) if key == "body" else frozenset())
            link = extra.get("link")
            if link is not None:
                if not isinstance(link, str) or link not in links:
                    raise fail(f"no link {link!r}; the links are: {', '.join(links)}", f"{key}[{k + 1}].link", "link")
                from dataclasses import replace

                shape = replace(shape, link=link)
            if key == "body" and shape.kind == "plane":
                raise fail("a body shape must be a solid of finite size; put planes (the ground) in [[scene]]",
                           f"{key}[{k + 1}].type", "type")
            out.append(shape)
        tables[key] = out
    object.__setattr__(robot, "collision", RobotCollision(radii, tuple(tables["body"]), tuple(tables["scene"]),
                                                          tuple((a, b) for a, b in pairs)))
