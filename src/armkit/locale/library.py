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


@lru_cache(maxsize=None)
def _regex(pattern: str) -> re.Pattern[str]:
    """``pattern`` as a regular expression: each ``{name}`` a lazy group, each literal escaped."""
    out, seen = [], set()
    for literal, name, _spec, _conv in string.Formatter().parse(pattern):
        out.append(re.escape(literal))
        if name is not None:
            out.append(f"(?P={name})" if name in seen else f"(?P<{name}>.+?)")
            seen.add(name)
    return re.compile("".join(out), re.S)


def _fill(template: str, lang: str, fields: dict[str, str]) -> str:
    """The translated ``template`` with ``fields`` (already text: conversions and number formats dropped, the
    particle ``j:`` and term ``t`` specs kept)."""
    def keep(m: re.Match[str]) -> str:
        spec = m.group(3) or ""
        return "{" + m.group(1) + (spec if spec.startswith((":j:", ":t")) else "") + "}"

    return _Formatter(lang).format(_FIELD.sub(keep, template), **fields)


def localize(text: str, lang: str) -> str:
    """``text``, an English message of the library, in ``lang``: the first pattern of :data:`PATTERNS` that
    matches it whole gives the translation; otherwise (or in English) ``text`` as it is."""
    if lang == "en":
        return text
    for pattern in PATTERNS:
        m = _regex(pattern).fullmatch(text.strip())
        if m:      # the parts are translated too (a point and an axis inside a singular set's description)
            return _fill(_template(pattern, lang), lang, {k: localize(v, lang) for k, v in m.groupdict().items()})
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
