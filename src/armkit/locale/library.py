"""Korean for the sentences the library writes in English: errors raised to the user and the IK solvers'
explanations.

The core (``model``, ``kinematics``, ``ik``) imports only NumPy and writes its messages in
English; the front ends translate them where they are shown. A message is matched, whole,
against the English patterns below (each a catalogue entry: ``{name}`` matches any text,
which the Korean entry then places, particles chosen by :func:`armkit.locale.josa`). An
IK result's explanation that no pattern matches is rebuilt from its reason code and
residual, so a Korean user never gets the solver's English sentence.

>>> localize("unknown robot 'x'; bundled robots are: a, b (or give the path of a .toml or .urdf robot file)", "ko")
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

from . import N_, _Formatter, _template, translate

__all__ = ["PATTERNS", "localize", "fielded", "ik_explanation"]

PATTERNS = (
    # model: robots and robot files
    N_("unknown robot {name!r}; bundled robots are: {names} (or give the path of a .toml or .urdf robot file)"),
    N_("{path}: no such file"),
    N_("{path}: file not found"),
    N_("{what} needs the {extra} extra ({reason}): {command}"),
    N_("{what} needs the {extra} extra: {command}"),
    N_("unknown arm {name!r} of example-robot-data; known arms: {names} (or example-robot-data:PATH.urdf, a file of "
       "its robots folder)"),
    N_("robot {robot!r} has no link {link!r}; its links are: {names}"),
    N_("{where}: unknown key; allowed keys: {keys}"),
    N_("{what} must have shape (..., {n}) for robot {robot!r}, got {shape}"),
    N_("{what} contains NaN or infinite values"),
    N_("unknown branch {name!r} for robot {robot!r}; valid branches: {names}"),
    N_("waypoints must have shape (m, n) with m >= 2, got {shape}"),
    # ik: the solvers' explanations
    N_("target is {distance} from the shoulder; the arm reaches {outer} (outer) and {inner} (inner)."),
    N_("target is {distance} from the base origin; the arm reaches at most {reach}; q is the closest configuration "
       "found"),
    N_("target is {distance} from the base origin; the arm reaches at most {reach}; q is the closest configuration "
       "found; position error {error}."),
    # (the longer first: the shorter one's last field would swallow ", rotation error ..." whole)
    N_("converged in {n} iterations: position error {error}, rotation error {rotation}."),
    N_("converged in {n} iterations: position error {error}."),
    N_("CCD did not converge in {n} sweeps ({starts} starts)"),
    N_("fully stretched: elbow-up and elbow-down coincide."),
    N_("fully folded: elbow-up and elbow-down coincide."),
    # analysis: the singular sets in words (armkit singular), their parts and the solutions' labels
    N_("stretched or folded elbow ({joint})"),
    N_("{point} on {axis}"),
    N_("{point} in the plane through {axis} parallel to the axis of joint 2 (shoulder singularity)"),
    N_("axes of joints {i} ({a}) and {j} ({b}) line up"),
    N_("axes of joints {i} ({a}) and {j} ({b}) become parallel"),
    N_("prismatic joint {joint} at zero extension"),
    N_("the Jacobian loses rank where {expression} = 0"),
    N_("tool point"), N_("wrist point"), N_("point on the axis of joint {k}"), N_("the yaw axis (joint 1)"),
    N_("the axis of joint 1"), N_("stretched"), N_("folded"), N_("on axis"), N_("shoulder plane"),
    N_("axes collinear"), N_("axes parallel"),
    # collision: what hits what
    N_("the {a} hits the {b} by {depth} ({n} pairs in collision)"),
    N_("the {a} hits the {b} by {depth}"),
    # motion: velocity kinematics and trajectories
    N_("well-conditioned (smallest singular value {sigma} m)"),
    N_("near a singularity (smallest singular value {sigma} m): the arm cannot move along ({direction}); rates are "
       "damped, the velocity is only approximated"),
    N_("near a singularity (smallest singular value {sigma} m): the arm cannot move along ({direction}); the "
       "pseudo-inverse drops that direction"),
    N_("joint space, {profile}"), N_("{path} via resolved rate"), N_("{path} via IK"), N_("straight line"),
    N_("arc"),
)
"""English messages of the library, as the catalogue holds them (``pybabel extract`` finds them here)."""

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
    N_("2-D targets (x, y) are for planar arms moving in the world xy plane; robot {robot!r} is not one: give "
       "(x, y, z) or a pose"),
    # output files (_io.py): WriteError's template, "cannot write {path}: " + reason
    N_("cannot write {path}: {what} must end in {suffixes}, got {got!r}"),
    N_("cannot write {path}: {what} must end in {suffixes}; the name has no suffix"),
    N_("cannot write {path}: it is a folder; give a file name"),
    N_("cannot write {path}: it is not a regular file"),
    N_("cannot write {path}: the file is read-only"),
    N_("cannot write {path}: a part of the folder path is a file, not a folder"),
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

    An error (or warning) that carries its template and fields (:func:`fielded`) is rendered from the
    catalogue: nothing is read back from its English. Any other text is matched against :data:`PATTERNS`:
    the first that matches it whole gives the translation; otherwise (or in English) ``text`` as it is.
    Linear in the length of ``text`` (:func:`_match`); parts are translated :data:`MAX_NESTING` levels deep
    at most.

    >>> from armkit.errors import ShapeError
    >>> localize(ShapeError.of("{what} contains NaN or infinite values", what="q"), "ko")
    'q에 NaN이나 무한대 값이 있습니다'
    """
    keyed = fielded(text)
    if keyed is not None and (lang == "en" or _template(keyed[0], lang) != keyed[0]):
        fields = dict(keyed[1])      # (a template the catalogue lacks: the patterns below)
        for k, v in fields.items():
            if _depth < MAX_NESTING and fielded(v) is not None:   # a part built from its own template
                fields[k] = localize(v, lang, _depth + 1)
            elif k in getattr(text, "terms", ()):      # a word among the fields (ground, torso): the catalogue's
                fields[k] = _template(str(v), lang)
        return translate(keyed[0], lang, **fields)
    text = str(text)
    if lang == "en":
        return text
    stripped = text.strip()
    for pattern in PATTERNS:
        m = _match(pattern, stripped)
        if m is not None:   # the parts are translated too (a point and an axis inside a singular set's description)
            return _fill(_template(pattern, lang), lang,
                         {k: localize(v, lang, _depth + 1) if _depth < MAX_NESTING else v for k, v in m.items()})
    return text


def ik_explanation(reason: str, message: str, position_error: float, unit: str, lang: str) -> str:
    """An IK result's explanation in ``lang``: the solver's ``message`` (translated when a pattern knows it), else
    a sentence from the ``reason`` code and the residual ``position_error`` (in ``unit``)."""
    if lang == "en":
        return message or f"{reason}: FK misses the target by {position_error:.3g} {unit}"
    if message.startswith(f"{reason}: "):       # the solver's sentence may repeat the reason in front
        message = message[len(reason) + 2:]
    text = localize(message, lang) if message else ""
    if message and text != message:
        return _fill(_template(N_("{reason}: {explanation}"), lang), lang,
                     {"reason": reason, "explanation": text}) if reason not in ("converged", "solved") else text
    return _fill(_template(N_("{reason}; position error of the closest pose {error}"), lang), lang,
                 {"reason": reason, "error": f"{position_error:.3g} {unit}"})
