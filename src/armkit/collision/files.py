"""Scene files (TOML) and the shape tables that robot files share with them.

Example (``scene.toml``)::

    unit = "m"              # length unit: "m" (default), "cm" or "mm"
    angle_unit = "deg"      # unit of rpy: "deg" (default) or "rad"

    [[shapes]]
    type = "plane"          # the ground: the half-space normal · x <= offset
    normal = [0, 0, 1]
    offset = 0

    [[shapes]]
    type = "box"
    name = "table"
    center = [0.5, 0, 0.2]
    size = [0.4, 0.6, 0.4]  # full extents
    rpy = [0, 0, 30]

Errors name the file, the line and the field: ``scene.toml:9: shapes[2].size: ...``.
"""

from __future__ import annotations

import math
import re
import sys
from pathlib import Path
from typing import Any, Callable

from ..errors import SceneFileError
from .shapes import Scene, SceneError, Shape

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = ["load_scene", "parse_scene", "shape_from_table", "SceneFileError", "SHAPE_KEYS", "block_line"]

_SCENE_TOP = {"unit", "angle_unit", "shapes", "name", "description"}
SHAPE_KEYS = {
    "plane": {"normal", "offset"},
    "box": {"center", "size", "rpy"},
    "sphere": {"center", "radius"},
    "cylinder": {"center", "radius", "length", "rpy"},
    "capsule": {"a", "b", "radius"},
    "mesh": {"path", "xyz", "rpy", "scale"},
}
_COMMON = {"type", "name", "allow"}


def block_line(lines: list[str], header: str, index: int, key: str | None) -> int | None:
    """1-based line of ``key`` inside the ``index``-th ``[[header]]`` block (or of the header)."""
    starts = [i for i, ln in enumerate(lines) if re.match(rf"\s*\[\[\s*{re.escape(header)}\s*\]\]", ln)]
    if index >= len(starts):
        return None
    lo = starts[index]
    hi = next((i for i in range(lo + 1, len(lines)) if re.match(r"\s*\[", lines[i])), len(lines))
    if key is not None:
        for i in range(lo, hi):
            if re.match(rf"\s*{re.escape(key)}\s*=", lines[i]):
                return i + 1
    return lo + 1


def shape_from_table(row: Any, where: str, fail: Callable[[str, str, str | None], Exception], angle: float,
                     base_dir: Path | None = None, extra: frozenset[str] = frozenset()) -> tuple[Shape, dict]:
    """One ``[[shapes]]`` (or robot-file ``[[body]]``/``[[scene]]``) table -> a :class:`Shape`.

    ``fail(message, field, key)`` builds the exception to raise; ``extra`` are keys the caller
    handles itself (returned in the second value).
    """
    if not isinstance(row, dict):
        raise fail("must be a table", where, None)
    kind = row.get("type")
    if kind not in SHAPE_KEYS:
        raise fail(f"type must be one of {', '.join(SHAPE_KEYS)}; got {kind!r}", f"{where}.type", "type")
    allowed = SHAPE_KEYS[kind] | _COMMON | extra
    bad = sorted(set(row) - allowed)
    if bad:
        raise fail(f"unknown key for a {kind}; allowed: {', '.join(sorted(allowed))}", f"{where}.{bad[0]}", bad[0])

    def num(key: str, default: float | None = None) -> float:
        v = row.get(key, default)
        if v is None:
            raise fail(f"a {kind} needs {key} = <number>", f"{where}.{key}", key)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise fail(f"must be a finite number, got {v!r}", f"{where}.{key}", key)
        return float(v)

    def vec(key: str, default: list | None = None) -> list[float]:
        v = row.get(key, default)
        if v is None:
            raise fail(f"a {kind} needs {key} = [x, y, z]", f"{where}.{key}", key)
        if not isinstance(v, list) or len(v) != 3 or any(
                isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(x) for x in v):
            raise fail(f"must be a list of 3 finite numbers, got {v!r}", f"{where}.{key}", key)
        return [float(x) for x in v]

    name = row.get("name", "")
    if not isinstance(name, str):
        raise fail(f"must be a string, got {name!r}", f"{where}.name", "name")
    allow = row.get("allow", [])
    if not isinstance(allow, list) or not all(isinstance(a, str) for a in allow):
        raise fail(f"must be a list of link names, got {allow!r}", f"{where}.allow", "allow")
    try:
        if kind == "plane":
            shape = Scene.plane(vec("normal"), num("offset", 0.0), name=name, allow=allow)
        elif kind == "box":
            shape = Scene.box(vec("center"), vec("size"), [v * angle for v in vec("rpy", [0, 0, 0])], name=name,
                              allow=allow)
        elif kind == "sphere":
            shape = Scene.sphere(vec("center"), num("radius"), name=name, allow=allow)
        elif kind == "cylinder":
            shape = Scene.cylinder(vec("center"), num("radius"), num("length"),
                                   [v * angle for v in vec("rpy", [0, 0, 0])], name=name, allow=allow)
        elif kind == "capsule":
            shape = Scene.capsule(vec("a"), vec("b"), num("radius"), name=name, allow=allow)
        else:
            from ..spatial import make_pose, rpy_to_rotation

            p = row.get("path")
            if not isinstance(p, str) or not p:
                raise fail(f"a mesh needs path = \"file.stl\", got {p!r}", f"{where}.path", "path")
            full = Path(p) if Path(p).is_absolute() or base_dir is None else base_dir / p
            if not full.is_file():
                raise fail(f"mesh file not found: {str(full)!r}", f"{where}.path", "path")
            import numpy as np

            pose = make_pose(rpy_to_rotation(np.array(vec("rpy", [0, 0, 0])) * angle), np.array(vec("xyz", [0, 0, 0])))
            shape = Scene.mesh(str(full), pose, vec("scale", [1, 1, 1]), name=name, allow=allow)
    except SceneError as exc:
        key = next((k for k in ("size", "radius", "length", "normal", "offset") if k in str(exc)), None)
        raise fail(str(exc), f"{where}.{key}" if key else where, key) from None
    return shape, {k: row[k] for k in extra if k in row}


def parse_scene(text: str, path: str) -> Scene:
    """The :class:`Scene` in a scene file's text; ``path`` names it in messages."""
    lines = text.splitlines()
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        m = re.search(r"line (\d+)", str(exc))
        raise SceneFileError(path, f"not valid TOML: {exc}", int(m.group(1)) if m else None) from None

    def top_line(key: str) -> int | None:
        return next((i + 1 for i, ln in enumerate(lines) if re.match(rf"\s*{re.escape(key)}\s*=", ln)), None)

    bad = sorted(set(data) - _SCENE_TOP)
    if bad:
        raise SceneFileError(path, f"unknown key; allowed keys: {', '.join(sorted(_SCENE_TOP))}", top_line(bad[0]),
                             bad[0])
    unit = data.get("unit", "m")
    if unit not in ("m", "cm", "mm"):
        raise SceneFileError(path, f"must be 'm', 'cm' or 'mm', got {unit!r}", top_line("unit"), "unit")
    angle_unit = data.get("angle_unit", "deg")
    if angle_unit not in ("deg", "rad"):
        raise SceneFileError(path, f"must be 'deg' or 'rad', got {angle_unit!r}", top_line("angle_unit"), "angle_unit")
    rows = data.get("shapes", [])
    if not isinstance(rows, list):
        raise SceneFileError(path, "must be an array of tables: write [[shapes]] above each shape",
                             top_line("shapes"), "shapes")
    shapes = []
    for k, row in enumerate(rows):
        def fail(message: str, field: str, key: str | None, k: int = k) -> Exception:
            return SceneFileError(path, message, block_line(lines, "shapes", k, key), field)

        shape, _ = shape_from_table(row, f"shapes[{k + 1}]", fail, math.pi / 180 if angle_unit == "deg" else 1.0,
                                    Path(path).resolve().parent)
        shapes.append(shape)
    return Scene(shapes, unit)


def load_scene(path: str | Path) -> Scene:
    """Read a scene file; a missing or unreadable file raises :class:`SceneFileError`."""
    p = Path(path)
    if not p.is_file():
        raise SceneFileError(str(path), "no such scene file")
    try:
        text = p.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise SceneFileError(str(path), f"cannot read file: {exc}") from None
    return parse_scene(text, str(path))
