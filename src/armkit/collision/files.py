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

Limits (issue 24): a scene file larger than 16 MB is refused unread, one with more than
:data:`MAX_SHAPES` shapes before any is built; a mesh ``path`` is read only from the scene
file's folder (and the folders below it, its package, ``ARMKIT_PACKAGE_PATH``), as URDF
meshes are (:class:`armkit.model.urdf._MeshLookup`), unless ``allow_outside=True`` or
``ARMKIT_ALLOW_OUTSIDE=1``; a mesh file over the mesh size limit is refused unread.
"""

from __future__ import annotations

import math
import re
import sys
from pathlib import Path
from typing import Any, Callable

from ..errors import LimitError, SceneFileError
from ..model.files import finite_number
from .shapes import KIND_TABLE, Scene, SceneError, Shape

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = ["load_scene", "parse_scene", "shape_from_table", "SceneFileError", "SHAPE_KEYS", "block_line",
           "MAX_SHAPES", "MAX_SCENE_BYTES"]

MAX_SHAPES = 10_000                  # shapes in one scene file (or a robot file's [[body]] and [[scene]] tables)
MAX_SCENE_BYTES = 16 * 1024 ** 2     # a scene file larger than this is refused unread (as robot files are)

_SCENE_TOP = {"unit", "angle_unit", "shapes", "name", "description"}
SHAPE_KEYS = {name: row.keys for name, row in KIND_TABLE.items()}
"""The file keys of each shape type (from :data:`armkit.collision.shapes.KIND_TABLE`)."""
_COMMON = {"type", "name", "allow"}


def _block_starts(lines: list[str], header: str) -> list[int]:
    return [i for i, ln in enumerate(lines) if re.match(rf"\s*\[\[\s*{re.escape(header)}\s*\]\]", ln)]


def block_line(lines: list[str], header: str, index: int, key: str | None,
               starts: list[int] | None = None) -> int | None:
    """1-based line of ``key`` inside the ``index``-th ``[[header]]`` block (or of the header)."""
    starts = _block_starts(lines, header) if starts is None else starts
    if index >= len(starts):
        return None
    lo = starts[index]
    hi = next((i for i in range(lo + 1, len(lines)) if re.match(r"\s*\[", lines[i])), len(lines))
    if key is not None:
        for i in range(lo, hi):
            if re.match(rf"\s*{re.escape(key)}\s*=", lines[i]):
                return i + 1
    return lo + 1


def shape_from_table(row: Any, where: str, fail: Callable[..., Exception], angle: float,
                     base_dir: Path | None = None, extra: frozenset[str] = frozenset(),
                     meshes: Any = None) -> tuple[Shape, dict]:
    """One ``[[shapes]]`` (or robot-file ``[[body]]``/``[[scene]]``) table -> a :class:`Shape`.

    ``fail(template, field, key, **fields)`` builds the exception to raise (its message: ``template`` with
    ``fields``, kept for the catalogue); ``extra`` are keys the caller
    handles itself (returned in the second value). ``meshes``: the :class:`~armkit.model.urdf._MeshLookup`
    of the file (where its mesh paths may lead); by default one for a file in ``base_dir``.
    """
    if not isinstance(row, dict):
        raise fail("must be a table", where, None)
    kind = row.get("type")
    if not isinstance(kind, str) or kind not in KIND_TABLE:     # type = [] or {} is not hashable
        raise fail("type must be one of {kinds}; got {got!r}", f"{where}.type", "type", kinds=", ".join(KIND_TABLE),
                   got=kind)
    allowed = KIND_TABLE[kind].keys | _COMMON | extra
    bad = sorted(set(row) - allowed)
    if bad:
        raise fail("unknown key for a {kind}; allowed: {keys}", f"{where}.{bad[0]}", bad[0], kind=kind,
                   keys=", ".join(sorted(allowed)))

    name = row.get("name", "")
    if not isinstance(name, str):
        raise fail("must be a string, got {got!r}", f"{where}.name", "name", got=name)
    allow = row.get("allow", [])
    if not isinstance(allow, list) or not all(isinstance(a, str) for a in allow):
        raise fail("must be a list of link names, got {got!r}", f"{where}.allow", "allow", got=allow)
    fields = _Fields(row, kind, where, fail, angle, name, allow, base_dir, meshes)
    try:
        shape = KIND_TABLE[kind].read(fields)
    except SceneError as exc:
        key = next((k for k in ("size", "radius", "length", "normal", "offset") if k in str(exc)), None)
        raise _refail(fail, exc, f"{where}.{key}" if key else where, key) from None
    return shape, {k: row[k] for k in extra if k in row}


class _Fields:
    """One file table as a kind's ``read`` sees it (:class:`armkit.collision.shapes.Fields`): every malformed or
    missing key raises the file's error naming it."""

    def __init__(self, row: dict, kind: str, where: str, fail: Callable[..., Exception],
                 angle: float, name: str, allow: list[str], base_dir: Path | None, meshes: Any) -> None:
        self.row, self.kind, self.where, self.fail, self.angle = row, kind, where, fail, angle
        self.name, self.allow, self.base_dir, self.meshes = name, allow, base_dir, meshes

    def number(self, key: str, default: float | None = None) -> float:
        v = self.row.get(key, default)
        if v is None:
            raise self.fail("a {kind} needs {entry} = <number>", f"{self.where}.{key}", key, kind=self.kind, entry=key)
        if not finite_number(v):
            raise self.fail("must be a finite number, got {got}", f"{self.where}.{key}", key, got=repr(v))
        return float(v)

    def vector(self, key: str, default: list[float] | None = None) -> list[float]:
        v = self.row.get(key, default)
        if v is None:
            raise self.fail("a {kind} needs {entry} = [x, y, z]", f"{self.where}.{key}", key, kind=self.kind, entry=key)
        if not isinstance(v, list) or len(v) != 3 or not all(finite_number(x) for x in v):
            raise self.fail("must be a list of 3 finite numbers, got {got!r}", f"{self.where}.{key}", key, got=v)
        return [float(x) for x in v]

    def angles(self, key: str) -> list[float]:
        return [v * self.angle for v in self.vector(key, [0.0, 0.0, 0.0])]

    def mesh_file(self, key: str) -> str:
        where, fail = self.where, self.fail
        p = self.row.get(key)
        if not isinstance(p, str) or not p:
            raise fail("a mesh needs {entry} = \"file.stl\", got {got!r}", f"{where}.{key}", key, entry=key, got=p)
        if self.meshes is None:
            self.meshes = mesh_lookup(self.base_dir if self.base_dir is not None else Path.cwd())
        found, refused = self.meshes._locate(p)
        if refused:
            raise fail("mesh path {path!r} leads outside the file's folder and the package path; it was not read "
                       "(to read it anyway: allow_outside=True, or set {variable}=1)", f"{where}.{key}", key,
                       path=_short(p), variable=_ALLOW_OUTSIDE)
        if found is None:
            full = Path(p) if Path(p).is_absolute() or self.base_dir is None else self.base_dir / p
            raise fail("mesh file not found: {path!r}", f"{where}.{key}", key, path=_short(str(full)))
        from .._limits import check_mesh_file

        try:
            check_mesh_file(found)           # a 3 GB file is refused here, unread
        except LimitError as exc:
            raise _refail(fail, exc, f"{where}.{key}", key) from None
        return str(Path(found))


_ALLOW_OUTSIDE = "ARMKIT_ALLOW_OUTSIDE"


def _refail(fail: Callable[..., Exception], exc: Exception, field: str, key: str | None) -> Exception:
    """The file's error for ``exc`` (a shape or limit error): its template and fields when it has them, else its
    text as it is (braces kept literally)."""
    template, fields = getattr(exc, "template", None), getattr(exc, "fields", None)
    if isinstance(template, str) and isinstance(fields, dict) and fields:
        return fail(template, field, key, **fields)
    return fail(str(exc), field, key)


def _short(text: str, limit: int = 200) -> str:
    return text if len(text) <= limit else text[:limit - 3] + "..."


def mesh_lookup(folder: Path, allow_outside: bool = False) -> Any:
    """Where the mesh paths of a file in ``folder`` may lead: the URDF loader's rules (one implementation)."""
    from ..model.urdf import _MeshLookup

    return _MeshLookup(Path(folder) / "scene.toml", allow_outside)


def parse_scene(text: str, path: str, *, allow_outside: bool = False) -> Scene:
    """The :class:`Scene` in a scene file's text; ``path`` names it in messages.

    More than :data:`MAX_SHAPES` shapes are refused before any is built; mesh paths follow
    :func:`load_scene`'s rules (``allow_outside``).
    """
    lines = text.splitlines()
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        m = re.search(r"line (\d+)", str(exc))
        raise SceneFileError(path, "not valid TOML: {reason}", int(m.group(1)) if m else None, reason=str(exc)) from None
    except RecursionError:     # tomllib recurses once per nesting level: [[[[...]]]] 500 deep (as robot files)
        raise SceneFileError(path, "not valid TOML: arrays or tables nested too deeply") from None

    def top_line(key: str) -> int | None:
        return next((i + 1 for i, ln in enumerate(lines) if re.match(rf"\s*{re.escape(key)}\s*=", ln)), None)

    bad = sorted(set(data) - _SCENE_TOP)
    if bad:
        raise SceneFileError(path, "unknown key; allowed keys: {keys}", top_line(bad[0]), bad[0],
                             keys=", ".join(sorted(_SCENE_TOP)))
    unit = data.get("unit", "m")
    if unit not in ("m", "cm", "mm"):
        raise SceneFileError(path, "must be 'm', 'cm' or 'mm', got {got!r}", top_line("unit"), "unit", got=unit)
    angle_unit = data.get("angle_unit", "deg")
    if angle_unit not in ("deg", "rad"):
        raise SceneFileError(path, "must be 'deg' or 'rad', got {got!r}", top_line("angle_unit"), "angle_unit",
                             got=angle_unit)
    rows = data.get("shapes", [])
    if not isinstance(rows, list):
        raise SceneFileError(path, "must be an array of tables: write [[{key}]] above each shape",
                             top_line("shapes"), "shapes", key="shapes")
    if len(rows) > MAX_SHAPES:
        raise SceneFileError(path, "{n:,} shapes; a scene file may hold at most {limit:,}", top_line("shapes"),
                             "shapes", n=len(rows), limit=MAX_SHAPES)
    folder = Path(path).resolve().parent
    meshes = mesh_lookup(folder, allow_outside)
    starts = _block_starts(lines, "shapes")
    shapes = []
    for k, row in enumerate(rows):
        def fail(message: str, field: str, key: str | None, k: int = k, **fields: object) -> Exception:
            return SceneFileError(path, message, block_line(lines, "shapes", k, key, starts), field, **fields)

        shape, _ = shape_from_table(row, f"shapes[{k + 1}]", fail, math.pi / 180 if angle_unit == "deg" else 1.0,
                                    folder, meshes=meshes)
        shapes.append(shape)
    return Scene(shapes, unit)


def load_scene(path: str | Path, *, allow_outside: bool = False) -> Scene:
    """Read a scene file; a missing, unreadable or too large file raises :class:`SceneFileError`.

    Mesh paths are read only from the file's folder (and below), its package and the package path
    (``ARMKIT_PACKAGE_PATH``, ``ROS_PACKAGE_PATH``); ``allow_outside=True`` (or ``ARMKIT_ALLOW_OUTSIDE=1``)
    reads any path.
    """
    p = Path(path)
    try:
        if not p.is_file():
            raise SceneFileError(str(path), "no such scene file")
        size = p.stat().st_size
    except (OSError, ValueError) as exc:
        raise SceneFileError(str(path), "cannot read file: {reason}", reason=str(exc)) from None
    if size > MAX_SCENE_BYTES:
        raise SceneFileError(str(path), "the file has {size:,} bytes; a scene file may have at most {limit:,}; it "
                             "was not read", size=size, limit=MAX_SCENE_BYTES)
    try:
        text = p.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise SceneFileError(str(path), "cannot read file: {reason}", reason=str(exc)) from None
    return parse_scene(text, str(path), allow_outside=allow_outside)
