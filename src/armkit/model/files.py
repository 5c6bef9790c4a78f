"""Robot files: a TOML format a student can write by hand.

Example (``my_arm.toml``)::

    name = "my_arm"
    convention = "standard"     # or "modified" (Craig)
    unit = "mm"                 # length unit of d, a, base and tool
    angle_unit = "deg"          # angles in this file (default "deg"; "rad" also accepted)

    [[joints]]
    name = "yaw"
    type = "revolute"           # or "prismatic"
    d = 36
    a = 0
    alpha = 90
    limits = [-180, 180]

    [tool]                      # optional, like [base]
    xyz = [0, 0, 10]
    rpy = [0, 0, 0]             # roll, pitch, yaw in angle_unit

Errors name the file, the line and the field: ``my_arm.toml:12: joints[2].alpha: ...``.
"""

from __future__ import annotations

import math
import re
import sys
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import RobotDefinitionError, RobotFileError, UnknownRobotError
from .robot import Joint, Robot

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = ["load", "save", "bundled_robots", "BUNDLED_DIR"]

BUNDLED_DIR = Path(__file__).resolve().parent.parent / "robots"
_TOP_KEYS = {"name", "description", "source", "convention", "unit", "angle_unit", "joints", "base", "tool",
             "link_names", "notes"}
_JOINT_KEYS = {"name", "type", "theta", "d", "a", "alpha", "limits"}
# collision keys (read by armkit.collision.robot_file, see docs/scene.md)
_COLLISION_KEYS = {"link_radius", "allow_collision", "body", "scene"}
_TOP_KEYS |= _COLLISION_KEYS
_JOINT_KEYS |= {"link_radius"}


def bundled_robots() -> list[str]:
    """Names of the robots shipped with armkit, sorted."""
    return sorted(p.stem for p in BUNDLED_DIR.glob("*.toml"))


class _Locator:
    """Finds the line of a field in the raw TOML text, for error messages."""

    def __init__(self, text: str):
        self.lines = text.splitlines()

    def _joint_block(self, index: int) -> tuple[int, int]:
        starts = [i for i, ln in enumerate(self.lines) if re.match(r"\s*\[\[\s*joints\s*\]\]", ln)]
        if index >= len(starts):
            return 0, len(self.lines)
        start = starts[index]
        end = next((i for i in range(start + 1, len(self.lines)) if re.match(r"\s*\[", self.lines[i])),
                   len(self.lines))
        return start, end

    def line(self, key: str, joint: int | None = None, table: str | None = None) -> int | None:
        if joint is not None:
            lo, hi = self._joint_block(joint)
        elif table is not None:
            found = next((i for i, ln in enumerate(self.lines) if re.match(rf"\s*\[\s*{table}\s*\]", ln)), None)
            if found is None:
                return None
            lo = found
            hi = next((i for i in range(lo + 1, len(self.lines)) if re.match(r"\s*\[", self.lines[i])),
                      len(self.lines))
        else:
            lo, hi = 0, next((i for i, ln in enumerate(self.lines) if re.match(r"\s*\[", ln)), len(self.lines))
        for i in range(lo, hi):
            if re.match(rf"\s*{re.escape(key)}\s*=", self.lines[i]):
                return i + 1
        return lo + 1 if joint is not None else None


def _number(value: Any, path: str, loc: _Locator, key: str, field: str, joint: int | None = None,
            table: str | None = None) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise RobotFileError(path, f"must be a finite number, got {value!r}", loc.line(key, joint, table), field)
    return float(value)


def _pose_from_table(data: Any, path: str, loc: _Locator, table: str, angle: float) -> np.ndarray:
    from ..spatial import make_pose, rpy_to_rotation

    if not isinstance(data, dict):
        raise RobotFileError(path, "must be a table with xyz = [x, y, z] and rpy = [r, p, y]", None, table)
    unknown = set(data) - {"xyz", "rpy"}
    if unknown:
        raise RobotFileError(path, f"unknown key(s) {sorted(unknown)}; allowed: xyz, rpy",
                             loc.line(sorted(unknown)[0], table=table), table)
    vec = {}
    for key in ("xyz", "rpy"):
        v = data.get(key, [0, 0, 0])
        if not isinstance(v, list) or len(v) != 3:
            raise RobotFileError(path, f"must be a list of 3 numbers, got {v!r}", loc.line(key, table=table),
                                 f"{table}.{key}")
        vec[key] = [_number(x, path, loc, key, f"{table}.{key}", table=table) for x in v]
    return make_pose(rpy_to_rotation(np.array(vec["rpy"]) * angle), np.array(vec["xyz"]))


def _parse(text: str, path: str) -> Robot:
    loc = _Locator(text)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        m = re.search(r"line (\d+)", str(exc))
        raise RobotFileError(path, f"not valid TOML: {exc}", int(m.group(1)) if m else None) from None
    unknown = set(data) - _TOP_KEYS
    if unknown:
        key = sorted(unknown)[0]
        raise RobotFileError(path, f"unknown key; allowed keys: {', '.join(sorted(_TOP_KEYS))}", loc.line(key), key)
    angle_unit = data.get("angle_unit", "deg")
    if angle_unit not in ("deg", "rad"):
        raise RobotFileError(path, f"must be 'deg' or 'rad', got {angle_unit!r}", loc.line("angle_unit"), "angle_unit")
    ang = math.pi / 180.0 if angle_unit == "deg" else 1.0
    rows = data.get("joints")
    if not isinstance(rows, list) or not rows:
        raise RobotFileError(path, "the file needs at least one [[joints]] table", None, "joints")
    joints = []
    for k, row in enumerate(rows):
        where = f"joints[{k + 1}]"
        bad = set(row) - _JOINT_KEYS
        if bad:
            key = sorted(bad)[0]
            raise RobotFileError(path, f"unknown key; allowed: {', '.join(sorted(_JOINT_KEYS))}",
                                 loc.line(key, k), f"{where}.{key}")
        kind = row.get("type", "revolute")
        if kind not in ("revolute", "prismatic"):
            raise RobotFileError(path, f"must be 'revolute' or 'prismatic', got {kind!r}", loc.line("type", k),
                                 f"{where}.type")
        vals = {key: _number(row.get(key, 0.0), path, loc, key, f"{where}.{key}", k)
                for key in ("theta", "d", "a", "alpha")}
        vals["theta"] *= ang
        vals["alpha"] *= ang
        limits = row.get("limits")
        if limits is None:
            if kind == "prismatic":
                raise RobotFileError(path, "a prismatic joint needs limits = [lower, upper] in length units",
                                     loc.line("limits", k), f"{where}.limits")
            lo, hi = -math.pi, math.pi
        else:
            if not isinstance(limits, list) or len(limits) != 2:
                raise RobotFileError(path, f"must be [lower, upper], got {limits!r}", loc.line("limits", k),
                                     f"{where}.limits")
            lo, hi = (_number(x, path, loc, "limits", f"{where}.limits", k) for x in limits)
            if kind == "revolute":
                lo, hi = lo * ang, hi * ang
            if lo > hi:
                raise RobotFileError(path, f"lower limit {limits[0]} is greater than upper limit {limits[1]}",
                                     loc.line("limits", k), f"{where}.limits")
        name = row.get("name", f"q{k + 1}")
        if not isinstance(name, str):
            raise RobotFileError(path, f"must be a string, got {name!r}", loc.line("name", k), f"{where}.name")
        joints.append(Joint(kind, vals["theta"], vals["d"], vals["a"], vals["alpha"], lo, hi, name))
    base = _pose_from_table(data["base"], path, loc, "base", ang) if "base" in data else None
    tool = _pose_from_table(data["tool"], path, loc, "tool", ang) if "tool" in data else None
    try:
        robot = Robot(joints, data.get("convention", "standard"), str(data.get("name", Path(path).stem)),
                      data.get("unit", "m"), base, tool, str(data.get("description", "")),
                      str(data.get("source", "")), tuple(data.get("link_names", ())))
    except RobotDefinitionError as exc:
        key = next((k for k in ("convention", "unit", "link_names") if k in str(exc)), None)
        raise RobotFileError(path, str(exc), loc.line(key) if key else None, key) from None
    if _COLLISION_KEYS & set(data) or any("link_radius" in row for row in rows):
        from ..collision.robot_file import attach   # NumPy only; coal is never imported here

        attach(robot, data, text, path)
    return robot


def load(name_or_path: str | Path) -> Robot:
    """Load a bundled robot by name (``"fighter"``) or a robot file by path.

    Raises
    ------
    UnknownRobotError
        The name is neither bundled nor an existing file; the message lists the bundled robots.
    RobotFileError
        The file is malformed; the message names the file, line and field.

    Examples
    --------
    >>> load("fighter").joint_types
    'RRR'
    """
    text_path = Path(name_or_path)
    if isinstance(name_or_path, str) and not name_or_path.endswith(".toml") and (BUNDLED_DIR / f"{name_or_path}.toml").is_file():
        text_path = BUNDLED_DIR / f"{name_or_path}.toml"
    if not text_path.is_file():
        raise UnknownRobotError(str(name_or_path), bundled_robots())
    try:
        text = text_path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise RobotFileError(str(name_or_path), f"cannot read file: {exc}") from None
    return _parse(text, str(name_or_path))


def _fmt(x: float) -> str:
    return repr(float(round(x, 12)) + 0.0)


def dumps(robot: Robot) -> str:
    """The TOML text of a robot (angles in degrees); :func:`load` reads it back."""
    from ..spatial import rotation_to_rpy

    deg = 180.0 / math.pi
    out = [f"name = {robot.name!r}".replace("'", '"')]
    for key in ("description", "source"):
        val = getattr(robot, key)
        if val:
            out.append(f'{key} = """{val}"""' if "\n" in val else f"{key} = {_toml_str(val)}")
    out += [f'convention = "{robot.convention}"', f'unit = "{robot.unit}"', 'angle_unit = "deg"',
            "link_names = [" + ", ".join(_toml_str(s) for s in robot.link_names) + "]"]
    for which in ("base", "tool"):
        T = getattr(robot, which)
        if not np.allclose(T, np.eye(4), atol=0):
            rpy = rotation_to_rpy(T[:3, :3]) * deg
            out += ["", f"[{which}]", "xyz = [" + ", ".join(_fmt(v) for v in T[:3, 3]) + "]",
                    "rpy = [" + ", ".join(repr(float(v)) for v in rpy) + "]"]
    for j in robot.joints:
        lim = [j.lower, j.upper] if j.is_prismatic else [j.lower * deg, j.upper * deg]
        out += ["", "[[joints]]", f"name = {_toml_str(j.name)}", f'type = "{j.kind}"',
                f"theta = {j.theta * deg!r}", f"d = {j.d!r}", f"a = {j.a!r}", f"alpha = {j.alpha * deg!r}",
                f"limits = [{lim[0]!r}, {lim[1]!r}]"]
    return "\n".join(out).replace("inf", "inf") + "\n"


def _toml_str(s: str) -> str:
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def save(robot: Robot, path: str | Path) -> Path:
    """Write ``robot`` as a TOML robot file; ``load(path)`` gives the same robot back."""
    p = Path(path)
    p.write_text(dumps(robot), encoding="utf-8")
    return p
