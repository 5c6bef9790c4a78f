"""Korean for the sentences the library writes in English: errors raised to the user and the IK solvers'
explanations.

The core (``model``, ``kinematics``, ``ik``) imports only NumPy and writes its messages in
English; the front ends translate them where they are shown. A message is matched, whole,
against the English patterns below (each a catalogue entry: ``{name}`` matches any text,
which the Korean entry then places, particles chosen by :func:`armkit.locale.josa`). An
IK result's explanation that no pattern matches is rebuilt from its reason code and
residual, so a Korean user never gets the solver's English sentence.

>>> localize("unknown robot 'x'; bundled robots are: a, b (or give the path of a .toml or .urdf robot file)", "ko")
"'x'라는 로봇이 없습니다. 들어 있는 로봇: a, b (또는 .toml, .urdf 로봇 파일의 경로를 주세요)"
>>> ik_explanation("unreachable", "target is 302.152 mm from the shoulder; the arm reaches 177.2 mm (outer) "
...                "and 22.8 mm (inner).", 120.0, "mm", "ko")
'작업 공간 밖: 목표가 어깨에서 302.152 mm 떨어져 있습니다. 팔이 닿는 거리는 바깥 177.2 mm, 안쪽 22.8 mm입니다.'
"""

from __future__ import annotations

import re
import string
from functools import lru_cache

from . import N_, _Formatter, _template

__all__ = ["PATTERNS", "localize", "ik_explanation"]

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
    N_("converged in {n} iterations: position error {error}."),
    N_("converged in {n} iterations: position error {error}, rotation error {rotation}."),
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


def localize(text: str, lang: str, _depth: int = 0) -> str:
    """``text``, an English message of the library, in ``lang``: the first pattern of :data:`PATTERNS` that
    matches it whole gives the translation; otherwise (or in English) ``text`` as it is. Linear in the
    length of ``text`` (:func:`_match`); parts are translated :data:`MAX_NESTING` levels deep at most."""
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
