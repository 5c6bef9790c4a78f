"""URDF robot files: read any serial chain out of a URDF tree, and write any armkit robot as URDF.

Reading (:func:`load_urdf`) checks the XML with lxml (errors carry the line), parses it
with yourdfpy, then picks the chain ``base -> tip`` out of the tree:

* ``base`` defaults to the root link; ``tip`` to the single leaf reached through moving
  joints. Several candidates (two gripper jaws, a humanoid's limbs) are an error that
  lists them and asks for ``tip=``.
* ``revolute``, ``continuous`` (no limits; IK returns the turn nearest ``q0``),
  ``prismatic`` and ``fixed`` joints; fixed joints fold into the constant transforms,
  so a chain of 12 joints of which 6 move has ``n = 6``. ``floating``, ``planar`` and
  ``mimic`` joints on the chain are errors naming the joint. Joints off the chain are
  ignored (listed in ``robot.ignored_joints``; their links keep their geometry at
  ``q = 0`` so that viewers can draw a gripper's jaw).
* Visual and collision shapes are kept on ``robot.links``; mesh files are found
  relative to the URDF, through ``package://NAME/...`` in the folders of
  ``ARMKIT_PACKAGE_PATH`` and ``ROS_PACKAGE_PATH`` (``os.pathsep``-separated), then in
  the URDF's own package (a folder above it with that name, or holding a ``package.xml``).
  A missing mesh is one warning, never an error. Paths that lead out of the URDF's
  folder, its package and the package path are not read (one warning names them) unless
  ``allow_outside=True`` or ``ARMKIT_ALLOW_OUTSIDE=1`` (:class:`_MeshLookup`).
* A joint axis is normalised after dividing by its largest component, so a huge but
  finite axis such as ``0 0 1e200`` is the direction it names; a zero, NaN or infinite
  axis, or origins whose lengths add up past 1.8e308, are errors naming the joint.

Writing (:func:`dumps_urdf`) keeps a URDF robot's links, joints, origins, axes and
geometry; a DH robot becomes one link per joint frame (on the joint axis) plus a
``tool`` link on a fixed joint.
"""

from __future__ import annotations

import math
import os
import re
import warnings
from pathlib import Path
from typing import Any
from xml.sax.saxutils import escape, quoteattr

import numpy as np
from numpy.typing import NDArray

from .._text import Fielded
from ..errors import RobotDefinitionError, RobotFileError, warning_of
from ..spatial import rotation_to_rpy
from .files import MAX_FILE_BYTES, MAX_JOINTS
from .robot import Joint, Link, Robot, Shape, collision_keys

__all__ = ["load_urdf", "dumps_urdf", "resolve_mesh", "PACKAGE_PATH_VARIABLES", "ALLOW_OUTSIDE_VARIABLE"]

Array = NDArray[np.float64]
PACKAGE_PATH_VARIABLES = ("ARMKIT_PACKAGE_PATH", "ROS_PACKAGE_PATH")
_MOVING = ("revolute", "continuous", "prismatic")
_KNOWN = _MOVING + ("fixed", "floating", "planar")


# ---------------------------------------------------------------------------- reading
def _joint(name: str) -> Fielded:
    """A joint named in an error's place (``joint 'elbow'``), in any language."""
    return Fielded.of("joint {name!r}", name=name)


def _numbers(el: Any, attr: str, count: int, default: str, path: str, what: Fielded) -> list[float]:
    text = el.get(attr, default) if el is not None else default
    parts = text.split()
    try:
        vals = [float(v) for v in parts]
    except ValueError:
        raise RobotFileError(path, "{attr}={text!r} must be {count} numbers", el.sourceline, what, attr=attr,
                             text=text, count=count) from None
    if len(vals) != count:
        raise RobotFileError(path, "{attr}={text!r} must be {count} numbers, got {got}", el.sourceline, what,
                             attr=attr, text=text, count=count, got=len(vals))
    if not all(math.isfinite(v) for v in vals):
        raise RobotFileError(path, "{attr}={text!r} holds NaN or infinite values", el.sourceline, what, attr=attr,
                             text=text)
    return vals


def _check_xml(root: Any, path: str) -> tuple[dict[str, Any], dict[str, Any]]:
    """Structural checks with line numbers, before yourdfpy reads the values; the link and joint elements by name."""
    if root.tag != "robot":
        raise RobotFileError(path, "the root element must be <robot>, got <{tag}>", root.sourceline, tag=root.tag)

    for tag, most in (("joint", MAX_JOINTS), ("link", MAX_JOINTS + 1)):   # counted before anything is built
        count = sum(1 for _ in root.iterchildren(tag))
        if count > most:
            raise RobotFileError(path, "{count:,} <{tag}> elements; armkit reads URDF trees of at most "
                                 "{limit:,} joints ({links:,} links)", root.sourceline, count=count, tag=tag,
                                 limit=MAX_JOINTS, links=MAX_JOINTS + 1)
    links = _check_links(root, path)
    if not links:
        raise RobotFileError(path, "the file has no <link>", root.sourceline)
    return links, _check_joints(root, path, links)


def _check_links(root: Any, path: str) -> dict[str, Any]:
    """The ``<link>`` elements by name: names unique, every visual and collision geometry readable."""
    links: dict[str, Any] = {}
    for el in root.findall("link"):
        name = el.get("name")
        if not name:
            raise RobotFileError(path, "<link> without a name", el.sourceline)
        if name in links:
            raise RobotFileError(path, "link {name!r} is defined twice (first on line {first})", el.sourceline,
                                 name=name, first=links[name].sourceline)
        links[name] = el
        for kind in ("visual", "collision"):
            for sub in el.findall(kind):
                _check_geometry(sub, kind, path, Fielded.of("link {name!r} visual", name=name) if kind == "visual"
                                else Fielded.of("link {name!r} collision", name=name))
    return links


def _check_geometry(sub: Any, kind: str, path: str, where: Fielded) -> None:
    """One ``<visual>`` or ``<collision>``: its origin and its single box, cylinder, sphere or mesh."""
    origin = sub.find("origin")
    if origin is not None:
        _numbers(origin, "xyz", 3, "0 0 0", path, where)
        _numbers(origin, "rpy", 3, "0 0 0", path, where)
    geo = sub.find("geometry")
    if geo is None or len(geo) == 0:
        raise RobotFileError(path, "<{kind}> needs a <geometry> with a box, cylinder, sphere or mesh",
                             sub.sourceline, where, kind=kind)
    shape = geo[0]
    if shape.tag == "box":
        _numbers(shape, "size", 3, "", path, where)
    elif shape.tag == "cylinder":
        _numbers(shape, "radius", 1, "", path, where)
        _numbers(shape, "length", 1, "", path, where)
    elif shape.tag == "sphere":
        _numbers(shape, "radius", 1, "", path, where)
    elif shape.tag == "mesh":
        if not shape.get("filename"):
            raise RobotFileError(path, "<mesh> needs a filename", shape.sourceline, where)
        if shape.get("scale") is not None:
            n = len(shape.get("scale").split())
            _numbers(shape, "scale", 1 if n == 1 else 3, "1 1 1", path, where)
    else:
        raise RobotFileError(path, "unknown geometry <{tag}>; expected box, cylinder, sphere or mesh",
                             shape.sourceline, where, tag=shape.tag)


def _check_joints(root: Any, path: str, links: dict[str, Any]) -> dict[str, Any]:
    """The ``<joint>`` elements by name: type, parent and child links, origin, axis, limits, mimic."""
    joints: dict[str, Any] = {}
    for el in root.findall("joint"):
        name = el.get("name")
        if not name:
            raise RobotFileError(path, "<joint> without a name", el.sourceline)
        where = _joint(name)
        if name in joints:
            raise RobotFileError(path, "joint {name!r} is defined twice (first on line {first})", el.sourceline,
                                 name=name, first=joints[name].sourceline)
        joints[name] = el
        jtype = el.get("type")
        if jtype not in _KNOWN:
            raise RobotFileError(path, "unknown joint type {type!r}; URDF knows {names}", el.sourceline, where,
                                 type=jtype, names=", ".join(_KNOWN))
        for tag in ("parent", "child"):
            sub = el.find(tag)
            if sub is None or not sub.get("link"):
                raise RobotFileError(path, "needs <{tag} link=\"...\"/>", el.sourceline, where, tag=tag)
            if sub.get("link") not in links:
                raise RobotFileError(path, "parent link {link!r} does not exist" if tag == "parent" else
                                     "child link {link!r} does not exist", sub.sourceline, where, link=sub.get("link"))
        if el.find("parent").get("link") == el.find("child").get("link"):
            raise RobotFileError(path, "parent and child are the same link", el.sourceline, where)
        origin = el.find("origin")
        if origin is not None:
            xyz = _numbers(origin, "xyz", 3, "0 0 0", path, where)
            if not math.isfinite(math.hypot(*xyz)):    # hypot scales first: only a length past 1.8e308 overflows
                raise RobotFileError(path, "origin xyz={xyz!r} is too long: its length overflows (above 1.8e308)",
                                     origin.sourceline, where, xyz=origin.get("xyz"))
            _numbers(origin, "rpy", 3, "0 0 0", path, where)
        axis = el.find("axis")
        if axis is not None:
            xyz = _numbers(axis, "xyz", 3, "1 0 0", path, where)
            if jtype in _MOVING and math.hypot(*xyz) < 1e-9:
                raise RobotFileError(path, "axis has zero length; a joint needs a direction", axis.sourceline, where)
        limit = el.find("limit")
        if limit is not None:
            for attr in ("lower", "upper", "effort", "velocity"):
                if limit.get(attr) is not None:
                    v = _numbers(limit, attr, 1, "0", path, where)[0]
                    del v
            if jtype in ("revolute", "prismatic") and limit.get("lower") and limit.get("upper"):
                lo, hi = float(limit.get("lower")), float(limit.get("upper"))
                if lo > hi:
                    raise RobotFileError(path, "lower limit {lower} is greater than upper limit {upper}",
                                         limit.sourceline, where, lower=f"{lo:g}", upper=f"{hi:g}")
        elif jtype == "prismatic":
            raise RobotFileError(path, "a prismatic joint needs <limit lower=... upper=...>", el.sourceline, where)
        mimic = el.find("mimic")
        if mimic is not None and not mimic.get("joint"):
            raise RobotFileError(path, "<mimic> needs a joint attribute", mimic.sourceline, where)
    return joints


ALLOW_OUTSIDE_VARIABLE = "ARMKIT_ALLOW_OUTSIDE"


def allow_outside_default() -> bool:
    """True when ``ARMKIT_ALLOW_OUTSIDE`` is set to 1 (or true, yes, on): mesh paths may lead anywhere."""
    return os.environ.get(ALLOW_OUTSIDE_VARIABLE, "").strip().lower() in ("1", "true", "yes", "on")


def _package_roots() -> list[Path]:
    roots: list[Path] = []
    for var in PACKAGE_PATH_VARIABLES:
        roots += [Path(p) for p in os.environ.get(var, "").split(os.pathsep) if p]
    return roots


def _inside(path: Path, root: Path) -> bool:
    """``path`` lies in ``root`` once both are resolved: no ``..`` and no symbolic link leads out."""
    try:
        path.resolve().relative_to(root.resolve())
        return True
    except (ValueError, OSError, RuntimeError):
        return False


def _is_file(path: Path) -> bool:
    try:
        return path.is_file()
    except (OSError, ValueError):       # a name too long, a NUL byte
        return False


class _MeshLookup:
    """Where the mesh files of one URDF may come from (issue 24), and what was missing or refused.

    Without ``allow_outside`` a mesh is read only from

    * the URDF's folder and the folders below it, and its package: the nearest folder above that holds a
      ``package.xml``, or else the parent of a folder named ``urdf`` (``pkg/urdf/arm.urdf`` reads ``pkg/meshes``);
    * ``package://NAME/...``: the folder ``NAME`` in a folder of ``ARMKIT_PACKAGE_PATH`` or ``ROS_PACKAGE_PATH``
      (or such a folder that is itself named ``NAME``), a folder above the URDF named ``NAME``, or a folder
      ``NAME`` holding a ``package.xml`` next to a folder above the URDF; never out of that package folder;
    * a folder of ``ARMKIT_PACKAGE_PATH`` or ``ROS_PACKAGE_PATH``.

    Absolute and ``file://`` paths are read when they lie in one of these folders (armkit writes absolute
    paths itself). Anything else (``package://../../etc/passwd``, ``/etc/passwd``, a symbolic link that
    leads out) is not even looked at: the mesh counts as refused, and the loader warns once, naming the
    path. ``allow_outside=True`` (or ``ARMKIT_ALLOW_OUTSIDE=1``, or ``--allow-outside``) reads any path.
    """

    def __init__(self, urdf_path: Path, allow_outside: bool = False) -> None:
        self.folder = urdf_path.resolve().parent
        self.allow_outside = allow_outside or allow_outside_default()
        self.missing: list[str] = []
        self.refused: list[str] = []
        self._homes: list[Path] | None = None

    def homes(self) -> list[Path]:
        if self._homes is None:
            homes = [self.folder, *_package_roots()]
            for anc in (self.folder, *self.folder.parents):
                if _is_file(anc / "package.xml"):
                    homes.append(anc)
                    break
            else:
                if self.folder.name.lower() == "urdf":
                    homes.append(self.folder.parent)
            self._homes = homes
        return self._homes

    def find(self, filename: str) -> str | None:
        """The mesh file for ``filename``; None when it is missing or refused (recorded in either list)."""
        found, refused = self._locate(filename)
        if found is None:
            (self.refused if refused else self.missing).append(filename)
        return found

    def _locate(self, filename: str) -> tuple[str | None, bool]:
        if filename.startswith("package://"):
            return self._package(filename[len("package://"):])
        if filename.startswith("file://"):
            cand = Path(filename[len("file://"):])
        else:
            cand = Path(filename)
            if not cand.is_absolute():
                cand = self.folder / cand
        if not self.allow_outside and not any(_inside(cand, home) for home in self.homes()):
            return None, True
        return (str(cand.resolve()) if _is_file(cand) else None), False

    def _package(self, rest: str) -> tuple[str | None, bool]:
        package, _, inner = rest.partition("/")
        if not self.allow_outside and (package in ("", ".", "..") or "\\" in package or not inner):
            return None, True
        places: list[tuple[Path, Path]] = []          # (candidate, the package folder it must stay in)
        for root in _package_roots():
            places.append((root / package / inner, root / package))
            if root.name == package:
                places.append((root / inner, root))
        for anc in (self.folder, *self.folder.parents):
            if anc.name == package:
                places.append((anc / inner, anc))
            if self.allow_outside or _is_file(anc / package / "package.xml"):
                places.append((anc / package / inner, anc / package))
        refused = False
        for cand, home in places:
            if not self.allow_outside and not _inside(cand, home):
                refused = True
                continue
            if _is_file(cand):
                return str(cand.resolve()), False
        return None, refused


def resolve_mesh(filename: str, urdf_path: Path, allow_outside: bool = False) -> str | None:
    """The mesh file on disk for a URDF ``filename`` (``package://``, ``file://``, relative or absolute), or None
    when it is not found or lies outside the folders a URDF may read (see :class:`_MeshLookup`; ``allow_outside``
    lifts that)."""
    return _MeshLookup(Path(urdf_path), allow_outside).find(filename)


def _shapes(items: list, lookup: _MeshLookup, colors: dict[str, Any]) -> tuple[Shape, ...]:
    out = []
    for it in items:
        origin = np.eye(4) if it.origin is None else np.array(it.origin, dtype=float)
        g = it.geometry
        rgba = None
        mat = getattr(it, "material", None)
        if mat is not None:
            color = mat.color if mat.color is not None else colors.get(mat.name or "")
            if color is not None:
                rgba = tuple(float(v) for v in color.rgba)
        if g.box is not None:
            out.append(Shape("box", origin, tuple(float(v) for v in g.box.size), rgba=rgba))  # type: ignore[arg-type]
        elif g.cylinder is not None:
            out.append(Shape("cylinder", origin, (float(g.cylinder.radius), float(g.cylinder.length)), rgba=rgba))  # type: ignore[arg-type]
        elif g.sphere is not None:
            out.append(Shape("sphere", origin, (float(g.sphere.radius),), rgba=rgba))  # type: ignore[arg-type]
        elif g.mesh is not None:
            scale = g.mesh.scale
            sc = (1.0, 1.0, 1.0) if scale is None else tuple(float(v) for v in np.broadcast_to(scale, (3,)))
            found = lookup.find(g.mesh.filename)
            out.append(Shape("mesh", origin, (), found, g.mesh.filename, sc, rgba))  # type: ignore[arg-type]
    return tuple(out)


def _short(text: str, limit: int = 200) -> str:
    return text if len(text) <= limit else text[:limit - 3] + "..."


def _names(names: list[str], limit: int) -> str:
    """``a, b, c`` for a message, at most ``limit`` names and then how many more."""
    shown = ", ".join(names[:limit])
    return shown + (f", ... ({len(names) - limit} more)" if len(names) > limit else "")


def _leaf_candidates(base: str, children: dict[str, list], jtype: dict[str, str]) -> list[str]:
    """Leaves below ``base`` whose path from ``base`` passes a moving joint."""
    out = []
    stack = [(base, False)]
    while stack:
        link, moved = stack.pop()
        kids = children.get(link, [])
        if not kids and moved:
            out.append(link)
        for joint, child in kids:
            stack.append((child, moved or jtype[joint] in _MOVING))
    return sorted(out)


def load_urdf(path: str | Path, base: str | None = None, tip: str | None = None,
              warn_missing_meshes: bool = True, name: str | None = None, allow_outside: bool = False) -> Robot:
    """Read the chain ``base -> tip`` of a URDF file as a :class:`Robot` (``convention="urdf"``, metres).

    Parameters
    ----------
    path : str or Path
    base, tip : str, optional
        Link names; default the root link and the single leaf reached through moving joints.
    warn_missing_meshes : bool
        Warn once when mesh files cannot be found (bundled robots load without meshes quietly).
    name : str, optional
        The robot's name (default: the ``name`` attribute of ``<robot>``).
    allow_outside : bool
        Read mesh files wherever their paths lead. By default only the URDF's folder, its package and the
        package path (``ARMKIT_PACKAGE_PATH``, ``ROS_PACKAGE_PATH``) are read; other paths
        (``package://../../etc/passwd``, ``/etc/passwd``) are refused with one warning naming them. The
        environment variable ``ARMKIT_ALLOW_OUTSIDE=1`` does the same as ``True``.

    Raises
    ------
    RobotFileError
        Malformed XML or URDF (the message names the file and line), a chain that cannot be
        built (several tips, a floating joint on it, ...).
    """
    p = Path(path)
    spath = str(path)
    root, notes = _read_xml(p, spath)
    links_el, joints_el = _check_xml(root, spath)
    base, tip, description, source = _read_notes(notes, base, tip, spath, str(root.get("name")))

    import yourdfpy

    try:
        model = yourdfpy.URDF._parse_robot(xml_element=root)
    except Exception as exc:  # noqa: BLE001 - anything the parser raises is a malformed file
        raise RobotFileError(spath, "cannot read the URDF: {kind}: {reason}", kind=type(exc).__name__,
                             reason=str(exc)) from None
    parent_of, children, root_link = _tree(model, root, links_el, joints_el, spath)
    jmap = {j.name: j for j in model.joints}
    base = root_link if base is None else base
    tip = _choose_tip(base, tip, links_el, children, {j.name: j.type for j in model.joints}, spath)
    path_joints = _chain_joints(base, tip, parent_of, jmap, joints_el, spath)
    joints, link_names, placed, warned_limits = _chain(path_joints, jmap, joints_el, base, spath)
    if warned_limits:
        warnings.warn(warning_of("{path}: revolute joint(s) {names} have no <limit>; treated as unlimited", path=spath,
                                 names=", ".join(warned_limits)), stacklevel=3)
    tool = placed[-1][2]                     # from the last moving joint's child link to the tip
    lookup = _MeshLookup(p, allow_outside)   # mesh files not found or refused, among the links kept
    links = _links(model, placed, children, jmap, tool, len(joints), lookup)
    missing = lookup.missing
    if lookup.refused:
        warnings.warn(warning_of("{path}: {n} mesh path(s) outside the robot's folder and package path were not "
                                 "read (first: {first}); to read them anyway pass allow_outside=True (armkit.load), "
                                 "--allow-outside (armkit) or set {variable}=1", path=spath, n=len(lookup.refused),
                                 first=_short(lookup.refused[0]), variable=ALLOW_OUTSIDE_VARIABLE), stacklevel=3)
    if missing and warn_missing_meshes:
        warnings.warn(warning_of("{path}: {n} mesh file(s) not found (first: {first}); kinematics are not affected. "
                                 "Set ARMKIT_PACKAGE_PATH to the folder that holds the package to see the meshes.",
                                 path=spath, n=len(missing), first=missing[0]), stacklevel=3)
    on_chain = set(path_joints)
    ignored = [jn for jn in jmap if jn not in on_chain]
    try:
        robot = Robot(joints, "urdf", name or str(root.get("name")), "m", None, tool, description, source, link_names,
                      links, ignored)
    except RobotDefinitionError as exc:
        raise RobotFileError.wrap(spath, exc) from None
    _attach_surroundings(robot, notes, spath, allow_outside)
    return robot


_SURROUNDINGS = "armkit surroundings:"


def _attach_surroundings(robot: Robot, notes: list[str], spath: str, allow_outside: bool) -> None:
    """The robot's surroundings that :func:`dumps_urdf` wrote in a comment (link radius, body, scene), if any."""
    import json

    for note in notes:
        if note.startswith(_SURROUNDINGS):
            try:
                data = json.loads(note[len(_SURROUNDINGS):])
            except (ValueError, RecursionError):
                raise RobotFileError(spath, "the {note!r} comment is not valid JSON", note=_SURROUNDINGS) from None
            if not isinstance(data, dict) or set(data) - {"angle_unit", "link_radius", "joints", "allow_collision",
                                                           "body", "scene"}:
                raise RobotFileError(spath, "the {note!r} comment holds unknown keys", note=_SURROUNDINGS)
            collision_keys().attach(robot, data, "", spath, allow_outside)
            return


def _surroundings_note(robot: Robot, links: list[str]) -> str:
    """The robot's surroundings (scaled to metres) as an XML comment that :func:`load_urdf` reads back."""
    import json

    extra = collision_keys().surroundings(robot, robot.unit_scale, links)
    if not extra:
        return ""
    data: dict[str, Any] = {"angle_unit": "rad"}
    if "link_radius" in extra:
        data["link_radius"] = extra["link_radius"]
        data["joints"] = [{} for _ in robot.joints]      # attach reads one entry per joint
    if "joint_radius" in extra:
        data["joints"] = [{"link_radius": r} for r in extra["joint_radius"]]
    for key in ("allow_collision", "body", "scene"):
        if key in extra:
            data[key] = extra[key]
    text = json.dumps(data, ensure_ascii=True, allow_nan=False, separators=(",", ":"))
    # "--" cannot stand in an XML comment; it only occurs inside JSON strings, where \u002d is the same "-"
    return f"<!-- {_SURROUNDINGS} " + text.replace("--", "-\\u002d") + " -->\n"


def _read_xml(p: Path, spath: str) -> tuple[Any, list[str]]:
    """The ``<robot>`` element (comments removed, a name set) and the comments written before it."""
    from lxml import etree


    try:
        size = p.stat().st_size
        if size > MAX_FILE_BYTES:      # refused unread: a 50 MB URDF took minutes and gigabytes (issue 24)
            raise RobotFileError(spath, "the file has {size:,} bytes; a robot file may have at most {limit:,}; it "
                                 "was not read", size=size, limit=MAX_FILE_BYTES)
        data = p.read_bytes()
    except OSError as exc:
        raise RobotFileError(spath, "cannot read file: {reason}", reason=str(exc.strerror or exc)) from None
    try:
        parser = etree.XMLParser(remove_blank_text=True, resolve_entities=False, no_network=True, huge_tree=False)
        root = etree.fromstring(data, parser=parser)
    except etree.XMLSyntaxError as exc:
        line = exc.lineno if getattr(exc, "lineno", None) else None
        raise RobotFileError(spath, "not valid XML: {reason}", line, reason=str(exc.msg)) from None
    notes = [str(c.text).strip() for c in reversed(list(root.itersiblings(preceding=True)))
             if not isinstance(c.tag, str) and c.text and c.text.strip()]
    for el in list(root.iter()):   # comments and processing instructions are not URDF elements
        if not isinstance(el.tag, str):
            el.getparent().remove(el)
    if not root.get("name"):     # required by the URDF spec; some files in the wild omit it
        root.set("name", p.stem)
    return root, notes


def _read_notes(notes: list[str], base: str | None, tip: str | None, spath: str,
                robot_name: str) -> tuple[str | None, str | None, str, str]:
    """``base``, ``tip`` (from an ``armkit chain:`` note unless given), the description and the source text."""
    for note in notes:   # written by dumps_urdf: the chain this file was saved from
        m = re.search(r"armkit chain: (\S+) -> (\S+)", note)
        if m:
            base = m.group(1) if base is None else base
            tip = m.group(2) if tip is None else tip
    notes = [nt for nt in notes if not nt.startswith(("armkit chain:", "written by armkit", _SURROUNDINGS))]
    lines = [line for nt in notes for line in _text_lines(nt)]
    first = next((i for i, line in enumerate(lines) if not _XACRO_BANNER.search(line)), None)
    description: str
    if first is None:      # no comment, or only xacro's banner: the robot's name describes it
        description = Fielded.of("URDF robot {name!r}", name=robot_name)
    else:
        description = lines.pop(first)
    rest = "\n".join(lines)
    source = (Fielded.of("{notes}\n(URDF file {path})", notes=rest, path=spath) if rest
              else Fielded.of("URDF file {path}", path=spath))
    return base, tip, description, source


_XACRO_BANNER = re.compile(r"autogenerated by xacro|editing this file by hand is not recommended", re.IGNORECASE)
"""The banner xacro writes at the top of every URDF it makes: where the file came from, not what the robot is
(it goes in the source, never in the description)."""


def _text_lines(note: str) -> list[str]:
    """The lines of a comment that hold words, with the box drawn around them taken off: ``| text |`` gives
    ``text``, a rule ``=====`` or ``-----`` nothing (the banner of xacro-made URDFs is such a box)."""
    out = []
    for line in note.splitlines():
        line = line.strip().strip("|").strip()
        if any(ch.isalnum() for ch in line):
            out.append(line)
    return out


def _tree(model: Any, root: Any, links_el: dict[str, Any], joints_el: dict[str, Any],
          spath: str) -> tuple[dict[str, tuple[str, str]], dict[str, list], str]:
    """Parent joint and link of each link, the children of each link, and the root link; checks it is a tree."""
    parent_of: dict[str, tuple[str, str]] = {}
    children: dict[str, list] = {}
    for j in model.joints:
        if j.child in parent_of:
            raise RobotFileError(spath, "link {link!r} has two parent joints ({first!r} and {second!r}); a URDF "
                                 "must be a tree", joints_el[j.name].sourceline, _joint(j.name), link=j.child,
                                 first=parent_of[j.child][0], second=j.name)
        parent_of[j.child] = (j.name, j.parent)
        children.setdefault(j.parent, []).append((j.name, j.child))
    roots = [nm for nm in links_el if nm not in parent_of]
    if not roots:
        raise RobotFileError(spath, "no root link: the joints form a cycle", root.sourceline)
    if len(roots) > 1:
        raise RobotFileError(spath, "{n} root links ({names}); a URDF tree has exactly one (add a joint that "
                             "connects them)", links_el[roots[1]].sourceline, n=len(roots), names=_names(roots, 10))
    reached, stack = {roots[0]}, [roots[0]]
    while stack:
        for _, child in children.get(stack.pop(), []):
            if child not in reached:
                reached.add(child)
                stack.append(child)
    if len(reached) != len(links_el):
        loop = sorted(set(links_el) - reached)
        raise RobotFileError(spath, "the joints form a cycle through links {names}", links_el[loop[0]].sourceline,
                             names=_names(loop, 10))
    return parent_of, children, roots[0]


def _choose_tip(base: str, tip: str | None, links_el: dict[str, Any], children: dict[str, list],
                jtype: dict[str, str], spath: str) -> str:
    """``tip``, or the single leaf below ``base`` reached through a moving joint; both links must exist."""
    if base not in links_el:
        raise RobotFileError(spath, "base link {base!r} does not exist; links: {names}", base=base,
                             names=_names(list(links_el), 40))
    if tip is None:
        cands = _leaf_candidates(base, children, jtype)
        if not cands:
            raise RobotFileError(spath, "no moving joint below link {base!r}: the chain would be empty", base=base)
        if len(cands) > 1:
            raise RobotFileError(spath, "the tree has {n} possible tip links: {names}; choose one with tip=... "
                                 "(CLI: --tip)", n=len(cands), names=_names(cands, 20))
        tip = cands[0]
    if tip not in links_el:
        raise RobotFileError(spath, "tip link {tip!r} does not exist; links: {names}", tip=tip,
                             names=_names(list(links_el), 40))
    return tip


def _chain_joints(base: str, tip: str, parent_of: dict[str, tuple[str, str]], jmap: dict[str, Any],
                  joints_el: dict[str, Any], spath: str) -> list[str]:
    """The joints from ``base`` to ``tip`` in order; none floating, planar or mimicking, at least one moving."""
    path_joints: list[str] = []
    link = tip
    while link != base:
        if link not in parent_of:
            raise RobotFileError(spath, "tip link {tip!r} is not below base link {base!r}", tip=tip, base=base)
        jn, link = parent_of[link]
        path_joints.append(jn)
    path_joints.reverse()
    for jn in path_joints:
        j = jmap[jn]
        if j.type in ("floating", "planar"):
            raise RobotFileError(spath, "a {kind} joint on the chain {base} -> {tip} is not a serial-arm joint; "
                                 "choose base= below it", joints_el[jn].sourceline, _joint(jn), kind=j.type,
                                 base=base, tip=tip)
        if j.mimic is not None and j.type in _MOVING:
            raise RobotFileError(spath, "joint {name!r} mimics joint {other!r}; armkit's chains have independent "
                                 "joints (choose a tip before it, or remove the mimic)", joints_el[jn].sourceline,
                                 _joint(jn), name=jn, other=j.mimic.joint)
    if not any(jmap[jn].type in _MOVING for jn in path_joints):
        raise RobotFileError(spath, "the chain {base} -> {tip} has no moving joint", base=base, tip=tip)
    return path_joints


_Placed = tuple[str, int, Array, "str | None", "str | None", "Array | None"]


def _chain(path_joints: list[str], jmap: dict[str, Any], joints_el: dict[str, Any], base: str,
           spath: str) -> tuple[list[Joint], list[str], list[_Placed], list[str]]:
    """The moving joints (fixed joints folded into the next origin), the link names, where each link sits
    (name, moving-joint index, offset, parent, joint, origin; the last offset is the tool) and the joints
    without a ``<limit>``."""
    joints: list[Joint] = []
    link_names = [base]
    placed: list[_Placed] = [(base, 0, np.eye(4), None, None, None)]
    acc = np.eye(4)
    warned_limits = []
    length = 0.0           # the chain's length so far: past 1.8e308 FK would give inf silently (issue 24)
    for jn in path_joints:
        j = jmap[jn]
        origin = np.eye(4) if j.origin is None else np.array(j.origin, dtype=float)
        length += math.hypot(*(float(v) for v in origin[:3, 3]))
        if not math.isfinite(length):
            raise RobotFileError(spath, "origin xyz makes the chain from the base longer than 1.8e308: its poses "
                                 "overflow", joints_el[jn].sourceline, _joint(jn))
        parent_link = j.parent
        if j.type in _MOVING:
            axis = np.array([1.0, 0.0, 0.0]) if j.axis is None else np.array(j.axis, dtype=float)
            lim = j.limit
            if j.type == "continuous":
                lo, hi = -math.inf, math.inf
            elif lim is None:
                lo, hi = -math.inf, math.inf
                warned_limits.append(jn)
            else:
                lo = 0.0 if lim.lower is None else float(lim.lower)
                hi = 0.0 if lim.upper is None else float(lim.upper)
            try:
                joints.append(Joint("prismatic" if j.type == "prismatic" else "revolute", lower=lo, upper=hi,
                                    name=jn, origin=tuple(map(tuple, acc @ origin)), axis=tuple(axis)))  # type: ignore[arg-type]
            except RobotDefinitionError as exc:
                raise RobotFileError.wrap(spath, exc, joints_el[jn].sourceline, _joint(jn)) from None
            acc = np.eye(4)
            link_names.append(j.child)
        else:
            acc = acc @ origin
        placed.append((j.child, len(joints), acc.copy(), parent_link, jn, origin))
    return joints, link_names, placed, warned_limits


def _links(model: Any, placed: list[_Placed], children: dict[str, list], jmap: dict[str, Any], tool: Array, n: int,
           lookup: _MeshLookup) -> list[Link]:
    """Every kept link with its shapes: the chain's, then those hanging off it (a gripper's jaw) fixed at q = 0."""
    colors = {m.name: m.color for m in model.materials if m.color is not None}
    by_name = {lk.name: lk for lk in model.links}

    def geometry(name: str) -> tuple[tuple[Shape, ...], tuple[Shape, ...]]:
        lk = by_name[name]
        return _shapes(lk.visuals, lookup, colors), _shapes(lk.collisions, lookup, colors)

    tool_inv = np.array(np.linalg.inv(tool), dtype=np.float64)
    on_path = {nm for nm, *_ in placed}
    links = [Link(nm, k, tool_inv @ off if k == n else off, par, jn, org, *geometry(nm))
             for nm, k, off, par, jn, org in placed]
    index = {nm: (k, off) for nm, k, off, *_ in placed}
    stack = [nm for nm in index]
    while stack:
        parent = stack.pop()
        for jn, child in children.get(parent, []):
            if child in on_path or child in index:
                continue
            k, off = index[parent]
            j = jmap[jn]
            origin = np.eye(4) if j.origin is None else np.array(j.origin, dtype=float)
            off_child = off @ origin
            index[child] = (k, off_child)
            links.append(Link(child, k, tool_inv @ off_child if k == n else off_child, parent, jn, origin,
                              *geometry(child)))
            stack.append(child)
    return links


# ---------------------------------------------------------------------------- writing
def _f(x: float) -> str:
    return repr(float(x) + 0.0)


def _origin_xml(T: Array, indent: str) -> str:
    rpy = rotation_to_rpy(T[:3, :3])
    return (f'{indent}<origin xyz="{" ".join(_f(v) for v in T[:3, 3])}" '
            f'rpy="{" ".join(_f(v) for v in rpy)}"/>\n')


def _shape_xml(kind: str, s: Shape, indent: str) -> str:
    out = f"{indent}<{kind}>\n" + _origin_xml(s.origin, indent + "  ") + f"{indent}  <geometry>\n"
    if s.kind == "box":
        out += f'{indent}    <box size="{" ".join(_f(v) for v in s.size)}"/>\n'
    elif s.kind == "cylinder":
        out += f'{indent}    <cylinder radius="{_f(s.size[0])}" length="{_f(s.size[1])}"/>\n'
    elif s.kind == "sphere":
        out += f'{indent}    <sphere radius="{_f(s.size[0])}"/>\n'
    else:
        out += (f'{indent}    <mesh filename={quoteattr(s.mesh_path or s.mesh_uri)} '
                f'scale="{" ".join(_f(v) for v in s.scale)}"/>\n')
    out += f"{indent}  </geometry>\n"
    if kind == "visual" and s.rgba is not None:
        out += (f'{indent}  <material name=""><color rgba="{" ".join(_f(v) for v in s.rgba)}"/></material>\n')
    return out + f"{indent}</{kind}>\n"


def _link_xml(name: str, lk: Link | None) -> str:
    if lk is None or not (lk.visuals or lk.collisions):
        return f"  <link name={quoteattr(name)}/>\n"
    body = "".join(_shape_xml("visual", s, "    ") for s in lk.visuals)
    body += "".join(_shape_xml("collision", s, "    ") for s in lk.collisions)
    return f"  <link name={quoteattr(name)}>\n{body}  </link>\n"


def _joint_xml(name: str, kind: str, parent: str, child: str, origin: Array, axis: Array | None = None,
               lower: float = 0.0, upper: float = 0.0) -> str:
    out = (f"  <joint name={quoteattr(name)} type=\"{kind}\">\n    <parent link={quoteattr(parent)}/>\n"
           f"    <child link={quoteattr(child)}/>\n" + _origin_xml(origin, "    "))
    if axis is not None:
        out += f'    <axis xyz="{" ".join(_f(v) for v in axis)}"/>\n'
    if kind in ("revolute", "prismatic"):
        out += f'    <limit lower="{_f(lower)}" upper="{_f(upper)}" effort="0" velocity="0"/>\n'
    return out + "  </joint>\n"


def _comment(text: str) -> str:
    """Text safe inside an XML comment (no ``--``)."""
    return escape(text).replace("--", "- -").replace("\n", " ")


def _moving_kind(j: Joint) -> str:
    if j.is_prismatic:
        return "prismatic"
    return "continuous" if j.is_continuous else "revolute"


def dumps_urdf(robot: Robot) -> str:
    """The URDF text of any armkit robot (lengths in metres); :func:`load_urdf` reads it back with the same FK."""
    s = robot.unit_scale
    scaled = lambda T: np.vstack([np.hstack([T[:3, :3], T[:3, 3:] * s]), [[0, 0, 0, 1.0]]])  # noqa: E731
    head = ['<?xml version="1.0"?>\n',
            f"<!-- written by armkit from robot {_comment(robot.name)} ({robot.convention}) -->\n"]
    if robot.description:
        head.append(f"<!-- {_comment(robot.description)} -->\n")
    out = [f"<robot name={quoteattr(robot.name)}>\n"]
    if not robot.is_dh:
        by_joint = {j.name: j for j in robot.joints}
        for lk in robot.links:
            out.append(_link_xml(lk.name, lk))
        for lk in robot.links[1:]:
            assert lk.parent is not None and lk.joint is not None and lk.joint_origin is not None
            j = by_joint.get(lk.joint)
            if j is None:     # fixed (or off-chain, written at its q = 0 place)
                out.append(_joint_xml(lk.joint, "fixed", lk.parent, lk.name, lk.joint_origin))
            else:
                out.append(_joint_xml(j.name, _moving_kind(j), lk.parent, lk.name, lk.joint_origin, j.axis_vector(),
                                      j.lower, j.upper))
        ignored = set(robot.ignored_joints)
        tip = [lk.name for lk in robot.links if lk.joint not in ignored][-1]   # links off the chain come last
        head.append(f"<!-- armkit chain: {robot.links[0].name} -> {tip} -->\n")
        head.append(_surroundings_note(robot, [lk.name for lk in robot.links]))
        return "".join(head + out) + "</robot>\n"
    # a DH robot: link k on joint axis k (the frame just after joint k's motion), then the tool
    c = robot.chain
    names = list(robot.link_names)
    tool_name = "tool" if "tool" not in names else "tool_frame"
    for nm in names + [tool_name]:
        out.append(_link_xml(nm, None))
    for i, j in enumerate(robot.joints):
        origin = c.base @ c.pre[0] if i == 0 else c.post[i - 1] @ c.pre[i]
        lower, upper = (j.lower * s, j.upper * s) if j.is_prismatic else (j.lower, j.upper)
        out.append(_joint_xml(j.name, _moving_kind(j), names[i], names[i + 1], scaled(origin), np.array([0, 0, 1.0]),
                              lower, upper))
    out.append(_joint_xml(f"{tool_name}_joint", "fixed", names[-1], tool_name, scaled(c.post[-1] @ c.tool)))
    head.append(_surroundings_note(robot, names + [tool_name]))
    return "".join(head + out) + "</robot>\n"
