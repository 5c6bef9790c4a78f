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

from .._io import atomic_write
from ..errors import RobotDefinitionError, RobotFileError, UnknownRobotError, WriteError
from ..spatial import make_pose, rotation_to_rpy, rpy_to_rotation
from .robot import Joint, Robot, collision_keys

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


# bundled URDF arms whose tree has several leaves: the chain armkit uses by default
BUNDLED_CHAINS = {"so101": ("base_link", "gripper_frame_link")}


def bundled_robots() -> list[str]:
    """Names of the robots shipped with armkit (TOML DH tables and URDF files), sorted."""
    return sorted({p.stem for p in BUNDLED_DIR.glob("*.toml")} | {p.stem for p in BUNDLED_DIR.glob("*.urdf")})


def _is_urdf(path: Path) -> bool:
    return path.suffix.lower() in (".urdf", ".xml")


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


def finite_number(value: object) -> bool:
    """Whether a value read from a file is a number armkit can use: an int or float (not a bool), finite, an integer
    within the float range (TOML integers have any size; ``math.isfinite`` raises OverflowError beyond it). The rule
    of robot files and of scene files (:mod:`armkit.collision.files`)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return False
    if isinstance(value, int):
        return abs(value) <= 2 ** 1023
    return math.isfinite(value)


def _number(value: Any, path: str, loc: _Locator, key: str, field: str, joint: int | None = None,
            table: str | None = None, infinite: bool = False) -> float:
    """A finite float (``infinite``: +-inf allowed too, for limits); integers beyond float range refused."""
    ok = finite_number(value) or (infinite and isinstance(value, float) and math.isinf(value))
    if not ok:
        shown = repr(value)
        raise RobotFileError(path, "must be a number (inf allowed), got {got}" if infinite else
                             "must be a finite number, got {got}", loc.line(key, joint, table), field,
                             got=shown if len(shown) <= 60 else shown[:57] + '...')
    return float(value)


def _pose_from_table(data: Any, path: str, loc: _Locator, table: str, angle: float) -> np.ndarray:
    if not isinstance(data, dict):
        raise RobotFileError(path, "must be a table with xyz = [x, y, z] and rpy = [r, p, y]", None, table)
    unknown = set(data) - {"xyz", "rpy"}
    if unknown:
        raise RobotFileError(path, "unknown key(s) {keys}; allowed: xyz, rpy",
                             loc.line(sorted(unknown)[0], table=table), table, keys=sorted(unknown))
    vec = {}
    for key in ("xyz", "rpy"):
        v = data.get(key, [0, 0, 0])
        if not isinstance(v, list) or len(v) != 3:
            raise RobotFileError(path, "must be a list of 3 numbers, got {got!r}", loc.line(key, table=table),
                                 f"{table}.{key}", got=v)
        vec[key] = [_number(x, path, loc, key, f"{table}.{key}", table=table) for x in v]
    return make_pose(rpy_to_rotation(np.array(vec["rpy"]) * angle), np.array(vec["xyz"]))


def _parse(text: str, path: str, allow_outside: bool = False) -> Robot:
    loc = _Locator(text)
    text = text[1:] if text.startswith("\ufeff") else text      # a UTF-8 byte order mark (Windows editors)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        m = re.search(r"line (\d+)", str(exc))
        raise RobotFileError(path, "not valid TOML: {reason}", int(m.group(1)) if m else None, reason=str(exc)) from None
    except RecursionError:
        raise RobotFileError(path, "not valid TOML: arrays or tables nested too deeply") from None
    for top in ("name", "description", "source", "convention", "unit", "angle_unit"):
        if top in data and not isinstance(data[top], str):
            raise RobotFileError(path, "must be a string, got {kind} {got}",
                                 loc.line(top), top, kind=type(data[top]).__name__, got=_short(data[top]))
    if "link_names" in data and (not isinstance(data["link_names"], list)
                                 or not all(isinstance(x, str) for x in data["link_names"])):
        raise RobotFileError(path, "must be a list of strings, got {got}",
                             loc.line("link_names"), "link_names", got=_short(data['link_names']))
    unknown = set(data) - _TOP_KEYS
    if unknown:
        key = sorted(unknown)[0]
        raise RobotFileError(path, "unknown key; allowed keys: {keys}", loc.line(key), key,
                             keys=', '.join(sorted(_TOP_KEYS)))
    angle_unit = data.get("angle_unit", "deg")
    if angle_unit not in ("deg", "rad"):
        raise RobotFileError(path, "must be 'deg' or 'rad', got {got!r}", loc.line("angle_unit"), "angle_unit",
                             got=angle_unit)
    ang = math.pi / 180.0 if angle_unit == "deg" else 1.0
    rows = data.get("joints")
    if not isinstance(rows, list) or not rows:
        raise RobotFileError(path, "the file needs at least one [[joints]] table", None, "joints")
    if len(rows) > MAX_JOINTS:
        raise RobotFileError(path, "{n:,} joints; armkit handles serial arms of at most {limit:,} joints",
                             None, "joints", n=len(rows), limit=MAX_JOINTS)
    joints = [_joint(row, k, path, loc, ang) for k, row in enumerate(rows)]
    base = _pose_from_table(data["base"], path, loc, "base", ang) if "base" in data else None
    tool = _pose_from_table(data["tool"], path, loc, "tool", ang) if "tool" in data else None
    _check_length(joints, base, tool, path, loc)
    try:
        robot = Robot(joints, data.get("convention", "standard"), str(data.get("name", Path(path).stem)),
                      data.get("unit", "m"), base, tool, str(data.get("description", "")),
                      str(data.get("source", "")), tuple(data.get("link_names", ())))
    except RobotDefinitionError as exc:
        key = next((k for k in ("convention", "unit", "link_names") if k in str(exc)), None)
        raise RobotFileError.wrap(path, exc, loc.line(key) if key else None, key) from None
    if _COLLISION_KEYS & set(data) or any("link_radius" in row for row in rows):
        collision_keys().attach(robot, data, text, path, allow_outside)   # NumPy only; coal is never imported
    return robot


def _check_length(joints: list[Joint], base: Any, tool: Any, path: str, loc: _Locator) -> None:
    """Refuse lengths whose FK can overflow (issue 24: ``a = 1e308`` gave x = inf).

    Every position FK computes is a sum of the base, joint and tool translations turned by rotations, so its
    components are at most the sum of ``|x| + |y| + |z|`` of the base, ``|a| + |d|`` (plus the largest finite
    stroke of a prismatic joint) of each joint and the tool's: that sum must be a finite float.
    """
    def l1(T: Any) -> float:
        return 0.0 if T is None else float(sum(abs(float(v)) for v in np.asarray(T)[:3, 3]))

    total = l1(base)
    if not math.isfinite(total):
        raise RobotFileError(path, "base xyz is too long: positions would overflow (above 1.8e308)",
                             loc.line("xyz", table="base"), "base.xyz")
    for k, j in enumerate(joints):
        total += abs(j.a) + abs(j.d)
        key = "a" if abs(j.a) >= abs(j.d) else "d"
        if j.is_prismatic and math.isfinite(total):
            total += max((abs(v) for v in (j.lower, j.upper) if math.isfinite(v)), default=0.0)
            key = "limits"
        if not math.isfinite(total):
            raise RobotFileError(path, "joint {name!r}: the chain's lengths (|a| + |d| from the base to this "
                                 "joint) add up past 1.8e308, so its positions would overflow to inf; use a "
                                 "larger unit or smaller values", loc.line(key, k), f"joints[{k + 1}].{key}",
                                 name=j.name)
    total += l1(tool)
    if not math.isfinite(total):
        raise RobotFileError(path, "tool xyz makes the chain longer than 1.8e308: positions would overflow",
                             loc.line("xyz", table="tool"), "tool.xyz")


def _joint(row: Any, k: int, path: str, loc: _Locator, ang: float) -> Joint:
    """The ``k``-th ``[[joints]]`` table (0-based) as a Joint; angles times ``ang`` (degrees to radians or 1)."""
    where = f"joints[{k + 1}]"
    if not isinstance(row, dict):
        raise RobotFileError(path, "must be a table (write each joint as a [[joints]] table), got {got}",
                             loc.line("joints"), where, got=_short(row))
    bad = set(row) - _JOINT_KEYS
    if bad:
        key = sorted(bad)[0]
        raise RobotFileError(path, "unknown key; allowed keys: {keys}",
                             loc.line(key, k), f"{where}.{key}", keys=', '.join(sorted(_JOINT_KEYS)))
    kind = row.get("type", "revolute")
    if kind not in ("revolute", "prismatic"):
        raise RobotFileError(path, "must be 'revolute' or 'prismatic', got {got!r}", loc.line("type", k),
                             f"{where}.type", got=kind)
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
            raise RobotFileError(path, "must be [lower, upper], got {got!r}", loc.line("limits", k),
                                 f"{where}.limits", got=limits)
        lo, hi = (_number(x, path, loc, "limits", f"{where}.limits", k, infinite=True) for x in limits)
        if kind == "revolute":
            lo, hi = lo * ang, hi * ang
        if lo > hi:
            raise RobotFileError(path, "lower limit {lower} is greater than upper limit {upper}",
                                 loc.line("limits", k), f"{where}.limits", lower=limits[0], upper=limits[1])
    name = row.get("name", f"q{k + 1}")
    if not isinstance(name, str):
        raise RobotFileError(path, "must be a string, got {got!r}", loc.line("name", k), f"{where}.name", got=name)
    return Joint(kind, vals["theta"], vals["d"], vals["a"], vals["alpha"], lo, hi, name)


def _short(value: Any, limit: int = 60) -> str:
    text = repr(value)
    return text if len(text) <= limit else text[:limit - 3] + "..."


def load(name_or_path: str | Path, base: str | None = None, tip: str | None = None, *,
         allow_outside: bool = False) -> Robot:
    """Load a bundled robot by name (``"fighter"``, ``"so101"``) or a robot file by path (``.toml`` or ``.urdf``).

    Parameters
    ----------
    name_or_path : str or Path
    base, tip : str, optional
        URDF only: the links where the chain starts and ends (default: the root link and
        the single leaf reached through moving joints; see :mod:`armkit.model.urdf`).
    allow_outside : bool
        URDF only: read mesh files wherever their paths lead. By default a URDF's meshes are read only from
        its folder, its package and ``ARMKIT_PACKAGE_PATH``/``ROS_PACKAGE_PATH``; other paths are refused
        with a warning (``ARMKIT_ALLOW_OUTSIDE=1`` lifts this too).

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
    >>> load("so101").joint_names
    ('shoulder_pan', 'shoulder_lift', 'elbow_flex', 'wrist_flex', 'wrist_roll')
    """
    from .erd import resolve   # "example-robot-data:ur5"; a missing path: "file not found" (armkit.model.erd)

    name_or_path, base, tip = resolve(name_or_path, base, tip)
    text_path = Path(name_or_path)
    bundled_chain: tuple[str | None, str | None] = (None, None)
    if isinstance(name_or_path, str) and "/" not in name_or_path and not text_path.suffix:
        for suffix in (".toml", ".urdf"):
            if _is_file(BUNDLED_DIR / f"{name_or_path}{suffix}"):
                text_path = BUNDLED_DIR / f"{name_or_path}{suffix}"
                bundled_chain = BUNDLED_CHAINS.get(name_or_path, (None, None))
                break
    if not _is_file(text_path):
        raise UnknownRobotError(str(name_or_path), bundled_robots())
    if _is_urdf(text_path):
        from .urdf import load_urdf

        bundled = text_path.parent == BUNDLED_DIR
        robot = load_urdf(text_path if bundled else name_or_path, base if base is not None else bundled_chain[0],
                          tip if tip is not None else bundled_chain[1], warn_missing_meshes=not bundled,
                          name=text_path.stem if bundled else None, allow_outside=allow_outside)
        return _mark_source(robot, text_path)
    if base is not None or tip is not None:
        raise RobotFileError(str(name_or_path), "base= and tip= choose a chain in a URDF file; a TOML robot file "
                             "is a single chain already")
    try:
        size = text_path.stat().st_size
        if size > MAX_FILE_BYTES:
            raise RobotFileError(str(name_or_path), "the file has {size:,} bytes; a robot file may have at most "
                                 "{limit:,}", size=size, limit=MAX_FILE_BYTES)
        text = text_path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise RobotFileError(str(name_or_path), "cannot read file: {reason}", reason=str(exc)) from None
    return _mark_source(_parse(text, str(name_or_path), allow_outside), text_path)


def _mark_source(robot: Robot, path: Path) -> Robot:
    """Remember the file ``robot`` was read from (``robot.loaded_from``): :func:`save` never writes onto it."""
    try:
        object.__setattr__(robot, "loaded_from", str(path.resolve()))   # a declared field, not part of the value
    except (OSError, RuntimeError):
        pass
    return robot


def _is_file(path: Path) -> bool:
    """``path.is_file()``, False for a name the system cannot look up (too long: ENAMETOOLONG; a NUL byte)."""
    try:
        return path.is_file()
    except (OSError, ValueError):
        return False


_DEG = math.pi / 180.0            # the loader's degrees -> radians factor
MAX_FILE_BYTES = 16 * 1024 ** 2   # a robot file larger than this is refused unread
MAX_JOINTS = 1000                 # joints in one robot file


def dumps(robot: Robot) -> str:
    """The TOML text of a robot; :func:`load` reads the same robot back, value for value.

    Written with tomli_w, so any name or description (quotes, ``\"\"\"``, control
    characters, backslashes) and infinite limits survive. Angles are in degrees when
    every one converts back exactly, else in radians (``angle_unit`` says which).

    A URDF chain is written as its standard-DH twin (:meth:`Robot.to_dh`).

    The robot's surroundings (``robot.collision``: ``link_radius``, ``allow_collision``, ``[[body]]``,
    ``[[scene]]``) are written too, so that the file read back collides as the robot does (issue 24).
    """
    original = robot
    if not robot.is_dh:
        robot = robot.to_dh()
    extra = collision_keys().surroundings(original,
                                          links=None if original is robot else [lk.name for lk in robot.links])
    import tomli_w

    poses = {}
    for which in ("base", "tool"):
        T = getattr(robot, which)
        if not np.array_equal(T, np.eye(4)):
            poses[which] = (T[:3, 3], rotation_to_rpy(T[:3, :3]))
    # Angles in degrees when every one of them comes back bit for bit (the loader multiplies
    # by pi/180), else in radians: a save never moves a value (no 2.2e-16 drift per save).
    angles = [v for j in robot.joints for v in (j.theta, j.alpha) + (() if j.is_prismatic else (j.lower, j.upper))]
    angles += [float(v) for _, rpy in poses.values() for v in rpy]
    angles += [float(v) for key in ("body", "scene") for row in extra.get(key, []) for v in row.get("rpy", ())]
    to_deg = 180.0 / math.pi
    use_deg = all(not math.isfinite(v) or (v * to_deg) * _DEG == v for v in angles)
    k = to_deg if use_deg else 1.0
    data: dict[str, Any] = {"name": robot.name}
    for key in ("description", "source"):
        if getattr(robot, key):
            data[key] = getattr(robot, key)
    data.update({"convention": robot.convention, "unit": robot.unit, "angle_unit": "deg" if use_deg else "rad",
                 "link_names": list(robot.link_names)})
    for which, (xyz, rpy) in poses.items():
        data[which] = {"xyz": [float(v) for v in xyz], "rpy": [float(v) * k for v in rpy]}
    data["joints"] = [{"name": j.name, "type": j.kind, "theta": j.theta * k, "d": float(j.d), "a": float(j.a),
                       "alpha": j.alpha * k,
                       "limits": [float(j.lower), float(j.upper)] if j.is_prismatic else [j.lower * k, j.upper * k]}
                      for j in robot.joints]
    if "link_radius" in extra:
        data["link_radius"] = extra["link_radius"]
    for row, radius in zip(data["joints"], extra.get("joint_radius", ())):
        row["link_radius"] = radius
    if "allow_collision" in extra:
        data["allow_collision"] = extra["allow_collision"]
    for key in ("body", "scene"):
        if key in extra:
            for row in extra[key]:
                if "rpy" in row:
                    row["rpy"] = [v * k for v in row["rpy"]]
            data[key] = extra[key]
    return str(tomli_w.dumps(data))


def _same_file(a: Path, b: Path) -> bool:
    """``a`` and ``b`` are the same file: the same resolved path, or (both existing) the same inode."""
    try:
        if a.resolve() == b.resolve():
            return True
        return a.exists() and b.exists() and a.samefile(b)
    except (OSError, ValueError, RuntimeError):
        return False


def _toml_str(s: str) -> str:
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def save(robot: Robot, path: str | Path) -> Path:
    """Write ``robot`` as a robot file chosen by the suffix: ``.urdf`` (URDF, metres) or TOML otherwise.

    ``load(path)`` gives a robot with the same FK back (a URDF is always in metres; a TOML
    file of a URDF chain holds its DH twin).
    """
    p = Path(path)
    source = robot.loaded_from
    if source is not None and _same_file(p, Path(source)):
        raise WriteError(p, "it is the file this robot was read from; a save keeps only what armkit models "
                         "(a URDF's transmissions, gazebo blocks and comments would be lost): write to another file")
    if _is_urdf(p):
        from .urdf import dumps_urdf

        text = dumps_urdf(robot)
    else:
        text = dumps(robot)
    atomic_write(p, text)         # a temporary file renamed into place: a failed save leaves the old file
    return p
