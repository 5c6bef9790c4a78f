"""Every text armkit shows a user, in English and Korean, from one gettext catalogue (Babel).

The English is written in the code, marked ``_("...")`` (translated where it is used) or
``N_("...")`` (marked only); each other language lives in its catalogue, the Korean in
``ko/LC_MESSAGES/armkit.po``; the languages are the rows of :data:`armkit.locale.languages.TABLE`
(docs/languages.md).
The command line, the shell, the plots' labels and the browser view all read it:
``_(text, **fields)`` in the current language (``--lang``, ``ARMKIT_LANG``, the locale),
``translate(text, lang, **fields)`` in a given one, ``message(key, lang, **fields)`` for the
shell's messages by key. ``default_language()`` reads the locale (``LC_ALL``, ``LC_MESSAGES``,
``LANG``): the language whose code it starts with (``ko_KR.UTF-8``: Korean), else English.

Korean particles that follow a placeholder are chosen by the word they follow:
``{name!r:j:이라는/라는}`` formats ``name`` and attaches 이라는 after a final consonant,
라는 after a vowel (:func:`josa`); ``{kind:t}`` writes a term (``revolute``) in the
message's language. Particles are attached without a space, as Korean is written.

>>> message("bye", "ko")
'종료합니다.'
>>> message("unknown_joint", "en", name="wrist", names="yaw, shoulder, elbow")
"no joint named 'wrist'; the joints are yaw, shoulder, elbow"
>>> message("unknown_joint", "ko", name="theta4", names="yaw, shoulder, elbow")
"'theta4'라는 관절이 없습니다. 관절: yaw, shoulder, elbow"
>>> message("branch_unknown", "ko", name="elbow-up", names="front, back")
"'elbow-up'이라는 해가 없습니다. 해 목록: front, back (또는 auto)"
"""

from __future__ import annotations

import gettext
import os
import re
import string
from functools import lru_cache
from pathlib import Path
from typing import Any, Dict, Iterator, Mapping

from .languages import LANGUAGES, SOURCE, catalogue_dir, choices, language_of

__all__ = ["LANGUAGES", "LANG", "default_language", "message", "MESSAGES", "josa", "final_consonant",
           "cli_language", "current_language", "translate", "translate_in", "LOCALE_DIR", "TERMS", "_", "N_", "NC_",
           "SOURCE", "choices", "language_of"]


LOCALE_DIR = Path(__file__).parent
"""gettext catalogues of the command line: ``ko/LC_MESSAGES/armkit.po`` (source) and ``.mo`` (built by
``make locale``, which ``make test`` runs; see docs/languages.md). A language added from outside may keep its
catalogue elsewhere (:attr:`armkit.locale.languages.Language.folder`)."""

LANG: dict[str, str | None] = {"lang": None}
"""``--lang`` of the command line (the command group sets it for every command); see :func:`current_language`."""


def N_(text: str) -> str:
    """Mark ``text`` for the catalogue without translating it here (it is translated where it is shown)."""
    return text

_SOURCE: dict[str, str] = {     # the shell's and the view's shared wording; Korean in ko/LC_MESSAGES/armkit.po
    "welcome": N_("armkit shell for {robot}: {n} joints ({names}), lengths in {unit}, angles in {angles}. "
                  "Type help for the commands, exit to leave."),
    "help": N_("""commands (angles in the current units, lengths in {unit}):
  theta1 = 30; theta2 = 45      set joints by number (also q1 = 30, or by name: {first} = 30; 30deg, 0.5rad,
                                and simple arithmetic such as 90/2 or pi/4 rad work)
  q 30 45 60                    set every joint at once
  goto {goto}                   move the end point to a target (inverse kinematics); also [{goto}] or the
                                numbers alone
  branch [NAME|auto]            list the IK branches, or pick the one goto should use
  home                          all joints to zero (or their nearest limit)
  limits                        show the joint limits
  ground Z   box X0 Y0 Z0 X1 Y1 Z1   clear   scene
                                the arm's surroundings: a floor, a box (corners), remove all, list; moves
                                into them (or into the arm's own body) are refused
  units deg|rad                 angle units for input and output
  lang {languages:<25}language of the messages
  show                          print the current state again
  help                          this text
  exit, quit, Ctrl-D            leave"""),
    "unknown": N_("cannot understand {text!r}; type help for the commands"),
    "not_number": N_("{word!r} is not a number"),
    "not_finite": N_("{word!r} is not a finite number"),
    "count": N_("{robot} has {n} joints ({names}); got {k} value(s)"),
    "unknown_joint": N_("no joint named {name!r}; the joints are {names}"),
    "bad_unit": N_("unit {unit!r} does not fit joint {joint} ({kind:t})"),
    "limit": N_("joint limit: {detail}; the arm did not move"),
    "collision": N_("the {a} would hit the {b} by {depth}; the arm did not move"),
    "scene_now": N_("around the arm: {shapes} (and its own body; moves into them are refused)"),
    "scene_none": N_("nothing around the arm; only its own body and self-collision are checked"),
    "scene_hit": N_("note: the arm is in collision now: {detail}"),
    "box_count": N_("box needs 6 numbers: the corners x0 y0 z0 x1 y1 z1 in {unit}; got {k}"),
    "ground_count": N_("ground needs one number: the floor height z in {unit}; got {k}"),
    "ambiguous": N_("numbers alone are ambiguous: write q {nums} for joint values, or goto {nums} / [{nums}] "
                    "for a target"),
    "goto_count": N_("a target for {robot} is {forms}; got {k} number(s)"),
    "unreachable": N_("target not reached ({detail}); the arm did not move"),
    "ik_error": N_("inverse kinematics failed: {detail}"),
    "no_branches": N_("{robot} has no closed-form IK, so no named branches (goto uses a numerical solver)"),
    "branch_unknown": N_("no branch {name!r}; the branches are {names} (or auto)"),
    "branch_set": N_("goto will use branch {name}"),
    "branch_auto": N_("goto will use the branch nearest the current pose"),
    "branch_missing": N_("branch {name} cannot reach the current end point here; kept {current}"),
    "branches_title": N_("IK branches for the current end point"),
    "units_now": N_("angles are in {u}"),
    "units_bad": N_("units must be deg or rad, got {u!r}"),
    "lang_now": N_("messages in English"),
    "lang_bad": N_("language must be one of {languages}, got {u!r}"),
    "picture": N_("picture: {path}"),
    "plot_failed": N_("could not draw the arm ({detail}); continuing without pictures"),
    "too_long": N_("the line has {n:,} characters, more than {limit:,}; it was not read"),
    "picture_cap": N_("this session has written {limit} pictures; no more are drawn (start a new session for "
                      "more)"),
    "bye": N_("bye"),
    "internal": N_("internal error ({detail}); the shell goes on — please report this"),
    "exit_alone": N_("exit must be the last command of a line"),
    "joint": N_("joint"),
    "value": N_("value"),
    "limits": N_("limits"),
    "state_title": N_("{robot}: joint values"),
    "limits_title": N_("{robot}: joint limits"),
    "end_point": N_("end point"),
    "orientation": N_("orientation (roll, pitch, yaw)"),
    "branch": N_("IK branch"),
    "none": N_("—"),
    "limit_item": N_("{joint} = {value} outside [{lower}, {upper}] {unit}"),
    "forms_planar": N_("x y"),
    "forms_planar_phi": N_("x y, or x y phi"),
    "forms_spatial": N_("x y z, or x y z roll pitch yaw"),
    "unreachable_detail": N_("{reason}: {message}"),
    "yes": N_("yes"),
    "term": N_("{term}"),
    "ok": N_("ok"),
}


class _Messages(Mapping[str, Dict[str, str]]):
    """``MESSAGES[key]``: ``{"en": English, "ko": Korean, ...}``, one entry per language of the table, each but
    English read from its catalogue."""

    def __getitem__(self, key: str) -> dict[str, str]:
        return {lang: _template(_SOURCE[key], lang) for lang in LANGUAGES}

    def __iter__(self) -> Iterator[str]:
        return iter(_SOURCE)

    def __len__(self) -> int:
        return len(_SOURCE)


MESSAGES: Mapping[str, dict[str, str]] = _Messages()
"""The messages of the shell (and the wording the browser view shares with it) by key, each ``{"en": ..., "ko":
...}``: the English is written here, the Korean comes from the catalogue (``ko/LC_MESSAGES/armkit.po``)."""


# ---------------------------------------------------------------- Korean particles
# How a Korean reader says the end of a Latin or numeric word: True when the reading ends in a final
# consonant (받침), "ㄹ" when that consonant is ㄹ (which takes 로, not 으로), False after a vowel.
_DIGITS: dict[str, Any] = {"0": True, "1": "ㄹ", "2": False, "3": True, "4": False, "5": False, "6": True,
                           "7": "ㄹ", "8": "ㄹ", "9": False}      # 영 일 이 삼 사 오 육 칠 팔 구
_TENS: dict[int, Any] = {1: True, 2: True, 3: True, 4: True}      # 십 백 천 만
_LETTERS: dict[str, Any] = {"l": "ㄹ", "m": True, "n": True, "r": False}   # 엘 엠 엔 아르; other letters: 에이, 비, 씨 ...
_WORDS: dict[str, Any] = {"mm": False, "cm": False, "m": False, "km": False, "deg": False, "°": False,  # 미터, 도
                          "rad": True, "auto": False, "help": False, "goto": False, "exit": False,
                          "q": False, "box": False, "ground": True, "scene": True, "ik": False, "fk": False}
_ENDINGS: tuple[tuple[str, Any], ...] = (   # English endings as Korean says them (업, 다운, 백, 롤 ...)
    ("ng", True), ("ck", True), ("ll", "ㄹ"), ("le", "ㄹ"), ("l", "ㄹ"), ("m", True), ("n", True), ("p", True),
    ("k", True),
)


_SKIP_BACK = re.compile("[^가-힣A-Za-z0-9°]*")
_WORD_BACK = re.compile("[가-힣]+|[A-Za-z°]+|[0-9]+(?:\\.[0-9]+)?")


def _last_word(text: str) -> str:
    """The last run of Hangul, of Latin letters (and °), or the last number (``12.5``) of ``text``, skipping what
    follows it; ``""`` when there is none.

    Read backwards, with two anchored patterns over the reversed text: linear. The search it replaces,
    ``([가-힣]+|[A-Za-z°]+|[0-9]+(?:\\.[0-9]+)?)[^가-힣A-Za-z0-9°]*$``, took quadratic time on a long word
    followed by another (100,000 characters: minutes; issue 24).
    """
    rev = text[::-1]
    skip = _SKIP_BACK.match(rev)            # always matches (maybe nothing)
    pos = skip.end() if skip else 0
    m = _WORD_BACK.match(rev, pos)
    return m.group(0)[::-1] if m else ""


def final_consonant(word: object) -> Any:
    """Whether the spoken end of ``word`` has a final consonant: ``True``, ``"ㄹ"`` (for ㄹ), ``False``, or
    ``None`` when the word has nothing to read (punctuation only).

    Hangul: the last syllable's 받침. Digits: the Korean reading of the number (…1 일, …10 십, …100 백).
    Latin: a short table of units and commands, then the English ending as Korean says it
    (``elbow-up`` 업, ``down`` 다운, ``back`` 백, ``roll`` 롤); single letters by their names
    (``l`` 엘, ``m`` 엠, ``n`` 엔). Quotes, brackets and signs around the word are skipped.

    >>> final_consonant("관절"), final_consonant("해"), final_consonant("'theta4'"), final_consonant("0")
    ('ㄹ', False, False, True)
    """
    tail = _last_word(str(word))
    if not tail:
        return None
    c = tail[-1]
    if "가" <= c <= "힣":
        jong = (ord(c) - 0xAC00) % 28
        return False if jong == 0 else ("ㄹ" if jong == 8 else True)
    if c.isdigit():
        if "." not in tail:
            zeros = len(tail) - len(tail.rstrip("0"))
            if 0 < zeros < len(tail):
                return _TENS.get(min(zeros, 4), True)
        return _DIGITS[c]
    low = tail.lower()
    if low in _WORDS:
        return _WORDS[low]
    if len(low) == 1:
        return _LETTERS.get(low, False)
    for ending, value in _ENDINGS:
        if low.endswith(ending):
            return value
    return False


def josa(word: object, pair: str) -> str:
    """``word`` with the right form of a Korean particle attached (no space).

    ``pair`` is ``"after consonant/after vowel"``: ``"을/를"``, ``"이/가"``, ``"은/는"``, ``"과/와"``,
    ``"이라는/라는"``, ``"으로/로"`` (ㄹ takes 로). When the word cannot be read, both forms are
    written the traditional way, ``을(를)``.

    >>> josa("관절", "을/를"), josa("해", "을/를"), josa("'elbow-up'", "이라는/라는"), josa("0", "으로/로")
    ('관절을', '해를', "'elbow-up'이라는", '0으로')
    >>> josa("1", "으로/로"), josa("front/elbow-down", "은/는"), josa("—", "을/를")
    ('1로', 'front/elbow-down은', '—을(를)')
    """
    consonant, vowel = pair.split("/")
    final = final_consonant(word)
    if final is None:
        return f"{word}{consonant}({vowel})"
    if consonant == "으로":
        return f"{word}{'로' if final in (False, 'ㄹ') else '으로'}"
    return f"{word}{consonant if final else vowel}"


TERMS = (N_("revolute"), N_("prismatic"), N_("continuous"), N_("unreachable"), N_("singular"),
         N_("max iterations"), N_("joint limits"), N_("collision"), N_("converged"), N_("solved"),
         N_("not converged"), N_("bad input"), N_("unsupported"), N_("base"), N_("tool"), N_("standard"),
         N_("modified"), N_("area"), N_("volume"))
"""Words written by ``{x:t}`` (or ``_(word)``) in the message's language: joint kinds, the IK results' ``reason``
codes, frames (base, tool) and DH conventions."""


class _Formatter(string.Formatter):
    """``str.format`` plus two specs: ``j:을/를`` attaches a particle (:func:`josa`), ``t`` translates a term
    (a word of :data:`TERMS`, from the catalogue)."""

    def __init__(self, lang: str) -> None:
        self.lang = lang

    def format_field(self, value: Any, format_spec: str) -> str:
        if format_spec.startswith("j:"):
            return josa(value, format_spec[2:])
        if format_spec == "t":
            return _template(str(value), self.lang)
        return super().format_field(value, format_spec)


def default_language() -> str:
    """The language of the locale (LC_ALL, LC_MESSAGES, LANG: the first one set) when the table has it (``ko`` for
    ``ko_KR.UTF-8``), else English."""
    for var in ("LC_ALL", "LC_MESSAGES", "LANG"):
        value = os.environ.get(var, "")
        if value:
            return language_of(value) or SOURCE
    return SOURCE


def current_language() -> str:
    """The language of what armkit prints now: the command line's ``--lang`` (:data:`LANG`), else
    ``ARMKIT_LANG``, else the locale."""
    return cli_language(LANG["lang"])


def cli_language(flag: str | None = None) -> str:
    """The command line's language: ``--lang``, else ``ARMKIT_LANG``, else the locale (:func:`default_language`).

    >>> cli_language("ko"), cli_language("en")
    ('ko', 'en')
    """
    for value in (flag, os.environ.get("ARMKIT_LANG")):
        if value:
            return language_of(value) or SOURCE
    return default_language()


@lru_cache(maxsize=None)
def _catalogue(lang: str) -> gettext.NullTranslations:
    """The compiled catalogue of ``lang``. ``make locale`` (run by ``make test``) builds the ``.mo`` from the
    ``.po``; when the ``.mo`` is missing or older than the ``.po`` (an install without make, a ``.po`` just
    edited) and Babel is installed, the ``.po`` is compiled in memory instead; else English."""
    folder = catalogue_dir(lang)
    po = folder / lang / "LC_MESSAGES" / "armkit.po"
    mo = po.with_suffix(".mo")
    if po.is_file() and (not mo.is_file() or mo.stat().st_mtime < po.stat().st_mtime):
        try:
            import io

            from babel.messages.mofile import write_mo
            from babel.messages.pofile import read_po
        except ImportError:
            pass
        else:
            buf = io.BytesIO()
            with po.open("rb") as f:
                write_mo(buf, read_po(f))
            buf.seek(0)
            return gettext.GNUTranslations(buf)
    return gettext.translation("armkit", localedir=str(folder), languages=[lang], fallback=True)


def translate(text: str, lang: str = "en", /, **fields: object) -> str:
    """``text`` (an English message of the command line) from the gettext catalogue of ``lang``, formatted with
    ``fields`` (``{x:j:을/를}`` attaches a Korean particle, see :func:`josa`). English, or a message the
    catalogue lacks, stays as written.

    >>> translate("{what}: {value!r} is not a number", "en", what="joint values", value="x")
    "joint values: 'x' is not a number"
    """
    return _Formatter(lang).format(_template(text, lang), **fields)


def _template(text: str, lang: str) -> str:
    """The catalogue's translation of ``text`` (unformatted); English, or a missing entry, stays as written."""
    return text if lang == SOURCE or not text else _catalogue(lang).gettext(text)


def NC_(context: str, text: str) -> str:
    """Mark ``text`` for the catalogue with a ``context`` (``msgctxt``): the same English word with another
    meaning (an animation's frame, a coordinate frame) gets its own translation."""
    return text


def translate_in(context: str | None, text: str, lang: str = "en", /, **fields: object) -> str:
    """:func:`translate` of an entry marked with :func:`NC_` (``context=None``: an entry without context)."""
    if context is None or lang == SOURCE:
        return translate(text, lang, **fields)
    return _Formatter(lang).format(_catalogue(lang).pgettext(context, text), **fields)


def _(text: str, /, **fields: object) -> str:
    """``text`` in the current language (:func:`current_language`), formatted with ``fields``."""
    return translate(text, current_language(), **fields)


def message(key: str, lang: str = "en", /, **fields: object) -> str:
    """The shell's message ``key`` in ``lang`` (a code of :data:`LANGUAGES`), formatted with ``fields``."""
    return translate(_SOURCE[key], lang, **fields)

