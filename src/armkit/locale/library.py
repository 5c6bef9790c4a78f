"""Korean for the sentences the library writes in English: errors raised to the user and the IK solvers'
explanations.

The core (``model``, ``kinematics``, ``ik``) imports only NumPy and writes its messages in
English, each built from a template and its fields (:meth:`armkit.errors.ArmkitError.of`,
:class:`armkit._text.Fielded`); the front ends render them in the user's language from the
catalogue (:data:`KEYED` lists the templates for ``pybabel extract``), so nothing is read back
from the English. A few sentences of modules not yet converted are still matched, whole,
against :data:`PATTERNS` (``{name}`` matches any text, which the Korean entry then places,
particles chosen by :func:`armkit.locale.josa`). An IK result's explanation that has neither
is rebuilt from its reason code and residual, so a Korean user never gets the solver's English.

>>> from armkit.errors import UnknownRobotError
>>> localize(UnknownRobotError("x", ["a", "b"]), "ko")
"'x'라는 로봇이 없습니다. 내장 로봇: a, b (또는 .toml, .urdf 로봇 파일의 경로를 지정하세요)"
>>> ik_explanation("unreachable", "target is 302.152 mm from the shoulder; the arm reaches 177.2 mm (outer) "
...                "and 22.8 mm (inner).", 120.0, "mm", "ko")
'작업 공간 밖: 목표가 어깨에서 302.152 mm 떨어져 있습니다. 팔이 닿는 거리는 바깥 177.2 mm, 안쪽 22.8 mm입니다.'
"""

from __future__ import annotations

import re
import string
from functools import lru_cache
from typing import Any

from . import N_, SOURCE, _Formatter, _template, translate

__all__ = ["PATTERNS", "localize", "fielded", "ik_explanation"]

PATTERNS = (
    # Sentences still written as plain English by modules outside this round's conversion (issue 21): each is
    # read back here until its raise site keeps its template and fields. The site is named next to it.
    N_("{what} contains NaN or infinite values"),            # collision/shapes.py, ik/api.py, viz/view, viz/tracking
    N_("target is {distance} from the shoulder; the arm reaches {outer} (outer) and {inner} (inner)."),  # analytic
    N_("fully stretched: elbow-up and elbow-down coincide."),                                # ik/analytic/_common.py
    N_("fully folded: elbow-up and elbow-down coincide."),                                   # ik/analytic/_common.py
)
"""English messages still matched back (``pybabel extract`` finds them here); every other message of the library
keeps its template and fields (:data:`KEYED`) and is rendered, never matched."""

KEYED = (
    # robot files (model/files.py, collision/robot_file.py): RobotFileError's template, "{where}: " + message
    N_("{where}: must be a finite number, got {got}"),
    N_("{where}: must be a number (inf allowed), got {got}"),
    N_("{where}: must be a table with xyz = [x, y, z] and rpy = [r, p, y]"),
    N_("{where}: unknown key(s) {keys}; allowed: xyz, rpy"),
    N_("{where}: must be a list of 3 numbers, got {got!r}"),
    N_("{where}: not valid TOML: {reason}"),
    N_("{where}: not valid TOML: arrays or tables nested too deeply"),
    N_("{where}: must be a string, got {kind} {got}"),
    N_("{where}: must be a list of strings, got {got}"),
    N_("{where}: must be 'deg' or 'rad', got {got!r}"),
    N_("{where}: the file needs at least one [[joints]] table"),
    N_("{where}: {n:,} joints; armkit handles serial arms of at most {limit:,} joints"),
    N_("{where}: base xyz is too long: positions would overflow (above 1.8e308)"),
    N_("{where}: joint {name!r}: the chain's lengths (|a| + |d| from the base to this joint) add up past 1.8e308, so "
       "its positions would overflow to inf; use a larger unit or smaller values"),
    N_("{where}: tool xyz makes the chain longer than 1.8e308: positions would overflow"),
    N_("{where}: must be a table (write each joint as a [[joints]] table), got {got}"),
    N_("{where}: must be 'revolute' or 'prismatic', got {got!r}"),
    N_("{where}: a prismatic joint needs limits = [lower, upper] in length units"),
    N_("{where}: must be [lower, upper], got {got!r}"),
    N_("{where}: lower limit {lower} is greater than upper limit {upper}"),
    N_("{where}: must be a string, got {got!r}"),
    N_("{where}: base= and tip= choose a chain in a URDF file; a TOML robot file is a single chain already"),
    N_("{where}: the file has {size:,} bytes; a robot file may have at most {limit:,}"),
    N_("{where}: cannot read file: {reason}"),
    N_("{where}: must be a finite number >= 0 (a radius in {unit}), got {got!r}"),
    N_("{where}: must be a list of [link, link] pairs, got {got!r}"),
    N_("{where}: no link {name!r}; the links are: {names}"),
    N_("{where}: must be an array of tables: write [[{key}]] above each shape"),
    N_("{where}: {n:,} shapes; a robot file may hold at most {limit:,} [[{key}]] tables"),
    # a scene's shapes in words (collision/shapes.py): Fielded
    N_("floor at z = {z}"), N_("plane normal ({normal}) offset {offset}"), N_("box at ({at}) size {size}"),
    N_("sphere at ({at}) radius {radius}"), N_("cylinder at ({at}) radius {radius} length {length}"),
    N_("capsule at ({at}) radius {radius} length {length}"), N_("mesh {path}"),
    # trajectories' labels (motion/trajectory.py): Fielded
    N_("{n} waypoints, {shape} blends of {blend}"), N_("{n} waypoints, sharp corners"), N_("circular"),
    N_("parabolic"), N_("Cartesian path"),
    # IK targets (ik/api.py): ShapeError.of
    N_("unknown branch {name!r} for robot {robot!r}; valid branches: {names}"),
    N_("2-D targets (x, y) are for planar arms moving in the world xy plane; robot {robot!r} is not one: give "
       "(x, y, z) or a pose"),
    # output files (_io.py): WriteError's template, "cannot write {path}: " + reason
    N_("cannot write {path}: {what} must end in {suffixes}, got {got!r}"),
    N_("cannot write {path}: {what} must end in {suffixes}; the name has no suffix"),
    N_("cannot write {path}: it is a folder; give a file name"),
    N_("cannot write {path}: it is not a regular file"),
    N_("cannot write {path}: the file is read-only"),
    N_("cannot write {path}: a part of the folder path is a file, not a folder"),
    # robots, robot files and errors that now keep their fields (no longer matched; issue 21)
    N_("unknown robot {name!r}; bundled robots are: {names} (or give the path of a .toml or .urdf robot file)"),
    N_("{path}: file not found"),
    N_("{what} needs the {extra} extra ({reason}): {command}"),
    N_("{what} needs the {extra} extra: {command}"),
    N_("unknown arm {name!r} of example-robot-data; known arms: {names} (or example-robot-data:PATH.urdf, a "
       "file of its robots folder)"),
    N_("robot {robot!r} has no link {link!r}; its links are: {names}"),
    N_("{where}: unknown key; allowed keys: {keys}"),
    N_("{what} must have shape (..., {n}) for robot {robot!r}, got {shape}"),
    N_("target is {distance} from the base origin; the arm reaches at most {reach}; q is the closest "
       "configuration found"),
    N_("CCD did not converge in {n} sweeps ({starts} starts)"),
    N_("stretched or folded elbow ({joint})"),
    N_("{point} on {axis}"),
    N_("{point} in the plane through {axis} parallel to the axis of joint 2 (shoulder singularity)"),
    N_("axes of joints {i} ({a}) and {j} ({b}) line up"),
    N_("axes of joints {i} ({a}) and {j} ({b}) become parallel"),
    N_("prismatic joint {joint} at zero extension"),
    N_("the Jacobian loses rank where {expression} = 0"),
    N_("tool point"),
    N_("wrist point"),
    N_("point on the axis of joint {k}"),
    N_("the yaw axis (joint 1)"),
    N_("the axis of joint 1"),
    N_("stretched"),
    N_("folded"),
    N_("on axis"),
    N_("shoulder plane"),
    N_("axes collinear"),
    N_("axes parallel"),
    N_("the {a} hits the {b} by {depth} ({n} pairs in collision)"),
    N_("the {a} hits the {b} by {depth}"),
    N_("joint space, {profile}"),
    N_("{path} via resolved rate"),
    N_("{path} via IK"),
    N_("straight line"),
    N_("arc"),
    # URDF files (model/urdf.py): RobotFileError's template, "{where}: " + message; the warnings
    N_("{location}: {field}"),
    N_("joint {name!r}"),
    N_("link {name!r} visual"),
    N_("link {name!r} collision"),
    N_("{where}: {attr}={text!r} must be {count} numbers"),
    N_("{where}: {attr}={text!r} must be {count} numbers, got {got}"),
    N_("{where}: {attr}={text!r} holds NaN or infinite values"),
    N_("{where}: the root element must be <robot>, got <{tag}>"),
    N_("{where}: {count:,} <{tag}> elements; armkit reads URDF trees of at most {limit:,} joints ({links:,} links)"),
    N_("{where}: the file has no <link>"),
    N_("{where}: <link> without a name"),
    N_("{where}: link {name!r} is defined twice (first on line {first})"),
    N_("{where}: <{kind}> needs a <geometry> with a box, cylinder, sphere or mesh"),
    N_("{where}: <mesh> needs a filename"),
    N_("{where}: unknown geometry <{tag}>; expected box, cylinder, sphere or mesh"),
    N_("{where}: <joint> without a name"),
    N_("{where}: joint {name!r} is defined twice (first on line {first})"),
    N_("{where}: unknown joint type {type!r}; URDF knows {names}"),
    N_('{where}: needs <{tag} link="..."/>'),
    N_("{where}: parent link {link!r} does not exist"),
    N_("{where}: child link {link!r} does not exist"),
    N_("{where}: parent and child are the same link"),
    N_("{where}: origin xyz={xyz!r} is too long: its length overflows (above 1.8e308)"),
    N_("{where}: axis has zero length; a joint needs a direction"),
    N_("{where}: a prismatic joint needs <limit lower=... upper=...>"),
    N_("{where}: <mimic> needs a joint attribute"),
    N_("{where}: cannot read the URDF: {kind}: {reason}"),
    N_("{where}: the {note!r} comment is not valid JSON"),
    N_("{where}: the {note!r} comment holds unknown keys"),
    N_("{where}: the file has {size:,} bytes; a robot file may have at most {limit:,}; it was not read"),
    N_("{where}: not valid XML: {reason}"),
    N_("{where}: link {link!r} has two parent joints ({first!r} and {second!r}); a URDF must be a tree"),
    N_("{where}: no root link: the joints form a cycle"),
    N_("{where}: {n} root links ({names}); a URDF tree has exactly one (add a joint that connects them)"),
    N_("{where}: the joints form a cycle through links {names}"),
    N_("{where}: base link {base!r} does not exist; links: {names}"),
    N_("{where}: no moving joint below link {base!r}: the chain would be empty"),
    N_("{where}: the tree has {n} possible tip links: {names}; choose one with tip=... (CLI: --tip)"),
    N_("{where}: tip link {tip!r} does not exist; links: {names}"),
    N_("{where}: tip link {tip!r} is not below base link {base!r}"),
    N_("{where}: a {kind} joint on the chain {base} -> {tip} is not a serial-arm joint; choose base= below it"),
    N_("{where}: joint {name!r} mimics joint {other!r}; armkit's chains have independent joints (choose a "
       "tip before it, or remove the mimic)"),
    N_("{where}: the chain {base} -> {tip} has no moving joint"),
    N_("{where}: origin xyz makes the chain from the base longer than 1.8e308: its poses overflow"),
    N_("{path}: revolute joint(s) {names} have no <limit>; treated as unlimited"),
    N_("{path}: {n} mesh path(s) outside the robot's folder and package path were not read (first: "
       "{first}); to read them anyway pass allow_outside=True (armkit.load), --allow-outside (armkit) or "
       "set {variable}=1"),
    N_("{path}: {n} mesh file(s) not found (first: {first}); kinematics are not affected. Set "
       "ARMKIT_PACKAGE_PATH to the folder that holds the package to see the meshes."),
    # scene and shape tables (collision/files.py)
    N_("{where}: must be a table"),
    N_("{where}: type must be one of {kinds}; got {got!r}"),
    N_("{where}: unknown key for a {kind}; allowed: {keys}"),
    N_("{where}: must be a list of link names, got {got!r}"),
    N_("{where}: a {kind} needs {entry} = <number>"),
    N_("{where}: a {kind} needs {entry} = [x, y, z]"),
    N_("{where}: must be a list of 3 finite numbers, got {got!r}"),
    N_('{where}: a mesh needs {entry} = "file.stl", got {got!r}'),
    N_("{where}: mesh path {path!r} leads outside the file's folder and the package path; it was not read "
       "(to read it anyway: allow_outside=True, or set {variable}=1)"),
    N_("{where}: mesh file not found: {path!r}"),
    N_("{where}: must be 'm', 'cm' or 'mm', got {got!r}"),
    N_("{where}: {n:,} shapes; a scene file may hold at most {limit:,}"),
    N_("{where}: no such scene file"),
    N_("{where}: the file has {size:,} bytes; a scene file may have at most {limit:,}; it was not read"),
    # robots built in code (model/robot.py): RobotDefinitionError.of, ShapeError.of
    N_("no reader of the collision keys is plugged in (armkit/__init__.py does it)"),
    N_("joint {name!r}: type must be 'revolute' or 'prismatic', got {got!r}"),
    N_("joint {name!r}: lower limit must be a number, got {got}"),
    N_("joint {name!r}: upper limit must be a number, got {got}"),
    N_("joint {name!r}: {field} must be a finite number, got {got}"),
    N_("joint {name!r}: lower limit {lower} is greater than upper limit {upper}"),
    N_("joint {name!r}: give either DH parameters or origin + axis, not both"),
    N_("joint {name!r}: axis must be 3 numbers, got {got!r}"),
    N_("joint {name!r}: axis must be 3 finite numbers, got {got!r}"),
    N_("joint {name!r}: axis {axis} has zero length; a joint needs a direction to turn about or slide along"),
    N_("{what} must be a 4x4 pose, got shape {shape}"),
    N_("robot {name!r} has no joints; a serial arm needs at least one"),
    N_("joints must be armkit.Joint objects"),
    N_("{what} must be a string, got {kind}"),
    N_("convention must be one of {names}, got {got!r}"),
    N_("unit must be one of {names}, got {got!r}"),
    N_("convention 'urdf' needs every joint given as origin + axis"),
    N_("convention {convention!r} needs DH rows; joints with origin + axis belong to convention 'urdf'"),
    N_("joint names must be unique, got {names}"),
    N_("link_names must be a sequence of strings (base link + one per joint), got {got}"),
    N_("link_names needs {n} names (base link + one per joint), got {got}"),
    N_("links must be armkit.model.Link objects with frame in 0..n"),
    N_("link names must be unique, got {names}"),
    N_("convention must be 'standard' or 'modified', got {got!r}"),
    # IK notes (ik/numeric.py, ccd.py, fabrik.py, partial.py, analytic), why-not sentences (ik/api.py), singular sets
    N_("{where}: {error}"),
    N_("target is {distance} from the shoulder; the arm reaches at most {reach}; q is the closest configuration found"),
    N_("position error {error}"),
    N_("position error {error}, rotation error {rotation}"),
    N_("converged in {n} iterations: {residual}."),
    N_("{text}; {residual}."),
    N_("the configuration breaks the joint limits; {residual}."),
    N_("no solution within {n} iterations; best {residual}."),
    N_("{message} {note}"),
    N_("found solutions only outside the joint limits ({broken}); q is the best configuration found inside them"),
    N_("stalled at a singular configuration (smallest singular value {sigma}) after {n} iterations and "
       "{starts} starts"),
    N_("no solution within {n} iterations ({starts} starts of at most {steps} steps)"),
    N_("({what} matches the position only; the target's orientation was not used.)"),
    N_("FABRIK did not converge in {n} passes ({kind} structure)"),
    N_("{name} must be numeric, got {got}"),
    N_("{name} must be a number or broadcast to the target's leading shape {lead}, got shape {shape}"),
    N_("{name} must be shape {tail} or broadcast to the target's leading shape {lead}, got shape {shape}"),
    N_("{what} goes with a position target (..., 3); got shape {shape}"),
    N_("direction= is solved in closed form ('analytic', for a yaw + three pitch joints arm such as the "
       "SO-101) or by the numeric methods 'lm' and 'newton' (or 'auto'); got method {method!r}"),
    N_("mask= does not go with direction=: direction= uses the mask (1, 1, 1, 1, 1, 0)"),
    N_("phi= does not go with direction=: phi= is for planar (x, y) targets"),
    N_("branch= does not go with direction=: branch= picks a closed-form solution; direction= is numeric"),
    N_("scene= does not go with direction=: scene= is not available with direction= yet"),
    N_("direction must be a non-zero 3-vector (the way the tool's z axis should point)"),
    N_("robot {robot!r} has no closed form for a position and a pointing direction (that is for arms with a "
       "yaw joint and three parallel pitch joints, like the SO-101); use method='lm'"),
    N_("phi= is for planar (x, y) targets; it does not go with direction="),
    N_("robot {robot!r} has no closed form for a position and a pointing direction (ik_all with direction= "
       "is for arms with a yaw joint and three parallel pitch joints, like the SO-101); use armkit.ik(..., "
       "direction=...) (numeric)"),
    N_("pitch= is solved in closed form (method 'auto' or 'analytic'), got method {method!r}; for a numeric "
       "solve give the pointing direction instead (direction=)"),
    N_("mask= is for the numeric methods; pitch= is solved in closed form"),
    N_("phi= is for planar (x, y) targets; it does not go with pitch="),
    N_("{n} joints cannot reach {what}; the nearest reachable pose (with the position met) misses by "
       "{angle}; q is the least-squares compromise found (1 m weighs as 1 rad)"),
    N_("{n} joints cannot reach {what}; the nearest pose found misses by {angle} and {distance}"),
    N_("an arbitrary orientation"),
    N_("this position and pointing direction"),
    N_("robot {robot!r} ({n} DOF {types}) has no closed form in armkit: it solves 2R and 3R arms (a position; a "
       "planar 3R with the end angle; three axes through one point, an orientation), 1 to 3 joints "
       "with prismatic ones (a position: Cartesian, cylindrical, spherical, SCARA and the rest), a 4-joint SCARA "
       "(position and turn), yaw + three pitch joints (+ roll), 6R arms (by subproblems, or a 1-D or "
       "2-D search where the axes need one; prismatic joints before a spherical wrist, as in the Stanford arm) "
       "and 7-joint arms with a joint held (fixed=) or swept (ik_all); use method='lm'"),
    N_("robot {robot!r} ({family}, {n} joints) has a closed form for a position and the tool pitch: give "
       "pitch= (rad); for a position alone, a pointing direction (direction=) or a pose use method='lm' "
       "(armkit.ik's default)"),
    N_("robot {robot!r} ({family}, {n} joints) has no closed form for a position and a pitch (pitch= is for "
       "arms with a yaw joint and three parallel pitch joints, like the SO-101); leave pitch out"),
    N_("robot {robot!r} ({family}) needs a pose target for its closed form: give the end angle with phi=, "
       "or use method='lm' for position-only IK"),
    N_("robot {robot!r} ({family}) needs a pose target for its closed form: give a (4, 4) pose, or use "
       "method='lm' for position-only IK"),
    N_("outside the joint limits: {names} (see armkit info for the limits)."),
    N_("unreachable: out of this branch's reach."),
    N_("unreachable: the closest configuration misses the target."),
    N_("unreachable: {why}"),
    N_("unreachable: the closest configuration of this branch misses the target by {distance} and {angle} "
       "(this arm cannot turn to that orientation there)."),
    N_("unreachable: the closest configuration of this branch misses the target by {distance} and {angle}."),
    N_("{meaning}: {expression} = 0"),
    N_("{expression} (a constant of the arm, not zero)"),
    # a robot file's body (collision/robot_file.py) and out= arrays (kinematics): raise sites found by the scan
    N_("{where}: a body shape must be a solid of finite size; put planes (the ground) in [[scene]]"),
    N_("out must be a numpy.ndarray (np.empty({shape})), got {type}"), N_("out must have dtype float64, got {dtype}"),
    N_("out must have shape {expected} (the shape of the result), got {shape}"),
    N_("out must be C-contiguous (as np.empty({shape}) is), got a strided view"),
    N_("out must be writable, got a read-only array"),
    N_("out must not overlap q (the result would overwrite the joint values it is computed from)"),
)
"""Templates of errors that carry their fields (:func:`fielded`), raised in modules that do not import the
catalogue: listed here so that ``pybabel extract`` finds them. They are rendered, never matched."""

_FIELD = re.compile(r"\{(\w+)(![rsa])?(:[^{}]*)?\}")


MAX_STEPS = 256      # places one pattern may try for its fields before it gives up on a message (issue 24)
MAX_NESTING = 4      # levels of parts translated inside parts


@lru_cache(maxsize=None)
def _pieces(pattern: str) -> tuple[str, tuple[tuple[str, str], ...]]:
    """``pattern`` as its leading literal and ``(field name, literal after it)`` pairs."""
    head = ""
    fields: list[tuple[str, str]] = []
    for literal, name, _spec, _conv in string.Formatter().parse(pattern):
        if fields:
            fields[-1] = (fields[-1][0], fields[-1][1] + literal)
        else:
            head += literal
        if name is not None:
            fields.append((name, ""))
    return head, tuple(fields)


class _OutOfSteps(Exception):
    pass


def _match(pattern: str, text: str) -> dict[str, str] | None:
    """The fields of ``text`` read as ``pattern`` whole, or None.

    The same answer as the regular expression ``literal (?P<name>.+?) literal ...`` with ``fullmatch`` (each
    field one character or more, the shortest first, a repeated name the same text), found by ``str.find``
    from field to field. That expression backtracked through every combination of a field's separators: a
    2,000-character message made of ``" ("`` and ``") and "`` took 26 s, 100,000 characters years. Here at
    most :data:`MAX_STEPS` places are tried; a message that needs more stays in English.
    """
    head, fields = _pieces(pattern)
    if not text.startswith(head):
        return None
    end = len(text)
    groups: dict[str, str] = {}
    steps = [MAX_STEPS]

    def solve(i: int, pos: int) -> bool:
        if i == len(fields):
            return pos == end
        name, literal = fields[i]
        if name in groups:                          # a repeated name: exactly the earlier text
            value = groups[name]
            if text.startswith(value, pos) and text.startswith(literal, pos + len(value)):
                return solve(i + 1, pos + len(value) + len(literal))
            return False
        if i == len(fields) - 1:                    # the last field runs to the final literal at the end
            stop = end - len(literal)
            if stop > pos and text.endswith(literal):
                groups[name] = text[pos:stop]
                return True
            return False
        start = pos + 1
        while True:
            steps[0] -= 1
            if steps[0] < 0:
                raise _OutOfSteps
            stop = text.find(literal, start)
            if stop < 0:
                return False
            groups[name] = text[pos:stop]
            if solve(i + 1, stop + len(literal)):
                return True
            del groups[name]
            start = stop + 1

    try:
        return groups if solve(0, len(head)) else None
    except _OutOfSteps:
        return None


def _fill(template: str, lang: str, fields: dict[str, str]) -> str:
    """The translated ``template`` with ``fields`` (already text: conversions and number formats dropped, the
    particle ``j:`` and term ``t`` specs kept)."""
    def keep(m: re.Match[str]) -> str:
        spec = m.group(3) or ""
        return "{" + m.group(1) + (spec if spec.startswith((":j:", ":t")) else "") + "}"

    return _Formatter(lang).format(_FIELD.sub(keep, template), **fields)


def fielded(obj: object) -> tuple[str, dict[str, Any]] | None:
    """``(template, fields)`` of an error or warning built from a template (``.template`` and a dict ``.fields``:
    :meth:`armkit.errors.ArmkitError.of`, :class:`~armkit.errors.RobotFileError`, ...), else None."""
    template, fields = getattr(obj, "template", None), getattr(obj, "fields", None)
    if isinstance(template, str) and template and isinstance(fields, dict):
        return template, fields
    return None


def localize(text: object, lang: str, _depth: int = 0) -> str:
    """``text``, a message of the library, in ``lang``.

    A message that carries its template and fields (:func:`fielded`: an error built by
    :meth:`~armkit.errors.ArmkitError.of`, a :class:`~armkit._text.Fielded` sentence, or an error whose text is
    one) is rendered from the catalogue, its parts too: nothing is read back from its English. Any other text
    is matched against :data:`PATTERNS`: the first that matches it whole gives the translation; otherwise (or
    in English) ``text`` as it is. Linear in the length of ``text`` (:func:`_match`); parts are translated
    :data:`MAX_NESTING` levels deep at most.

    >>> from armkit.errors import ShapeError
    >>> localize(ShapeError.of("{what} contains NaN or infinite values", what="q"), "ko")
    'q에 NaN이나 무한대 값이 있습니다'
    """
    keyed = fielded(text)
    if keyed is None and not isinstance(text, str):
        text = str(text)              # an error made from a Fielded sentence: str() gives the sentence back
        keyed = fielded(text)
    if keyed is not None:
        if lang == SOURCE:
            return str.__str__(text) if isinstance(text, str) else str(text)
        fields = dict(keyed[1])
        for k, v in fields.items():
            if _depth < MAX_NESTING and fielded(v) is not None:   # a part built from its own template
                fields[k] = localize(v, lang, _depth + 1)
            elif k in getattr(text, "terms", ()):      # a word among the fields (ground, torso): the catalogue's
                fields[k] = _template(str(v), lang)
            elif _depth < MAX_NESTING and isinstance(v, str) and len(v) > 12:   # a sentence of a module that
                fields[k] = localize(v, lang, _depth + 1)                      # still writes English (PATTERNS)
        return translate(keyed[0], lang, **fields)
    text = str(text)
    if lang == SOURCE:
        return text
    stripped = text.strip()
    for pattern in PATTERNS:
        m = _match(pattern, stripped)
        if m is not None:   # the parts are translated too
            return _fill(_template(pattern, lang), lang,
                         {k: localize(v, lang, _depth + 1) if _depth < MAX_NESTING else v for k, v in m.items()})
    return text


def ik_explanation(reason: str, message: str, position_error: float, unit: str, lang: str) -> str:
    """An IK result's explanation in ``lang``: the solver's ``message`` (rendered from its template and fields, or
    translated when a pattern knows it), else a sentence from the ``reason`` code and the residual
    ``position_error`` (in ``unit``)."""
    if lang == SOURCE:
        return message or f"{reason}: FK misses the target by {position_error:.3g} {unit}"
    keyed = fielded(message)
    if keyed is not None:
        text = localize(message, lang)
        if reason in ("converged", "solved") or keyed[0].startswith(f"{reason}: "):    # says its reason itself
            return text
        return _fill(_template(N_("{reason}: {explanation}"), lang), lang, {"reason": reason, "explanation": text})
    message = str(message)
    if message.startswith(f"{reason}: "):       # the solver's sentence may repeat the reason in front
        message = message[len(reason) + 2:]
    text = localize(message, lang) if message else ""
    if message and text != message:
        return _fill(_template(N_("{reason}: {explanation}"), lang), lang,
                     {"reason": reason, "explanation": text}) if reason not in ("converged", "solved") else text
    return _fill(_template(N_("{reason}; position error of the closest pose {error}"), lang), lang,
                 {"reason": reason, "error": f"{position_error:.3g} {unit}"})
