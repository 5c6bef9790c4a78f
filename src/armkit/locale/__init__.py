"""Korean and English messages for the interactive front ends (the shell).

``message(key, lang, **fields)`` formats one message; ``default_language()`` reads the
locale (``LC_ALL``, ``LC_MESSAGES``, ``LANG``): Korean when it starts with ``ko``.

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
from typing import Any

__all__ = ["LANGUAGES", "default_language", "message", "MESSAGES", "josa", "final_consonant", "cli_language",
           "translate", "LOCALE_DIR"]

LOCALE_DIR = Path(__file__).parent
"""gettext catalogues of the command line: ``ko/LC_MESSAGES/armkit.po`` (source) and ``.mo`` (built by
``make locale``, which ``make test`` runs; see docs/ko.md)."""

LANGUAGES = ("en", "ko")

MESSAGES: dict[str, dict[str, str]] = {
    "welcome": {
        "en": "armkit shell for {robot}: {n} joints ({names}), lengths in {unit}, angles in {angles}. "
              "Type help for the commands, exit to leave.",
        "ko": "armkit 셸 — {robot}: 관절 {n}개({names}), 길이 단위 {unit}, 각도 단위 {angles}. "
              "명령 목록은 help, 끝내려면 exit를 입력하세요.",
    },
    "help": {
        "en": """commands (angles in the current units, lengths in {unit}):
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
  lang en|ko                    language of the messages
  show                          print the current state again
  help                          this text
  exit, quit, Ctrl-D            leave""",
        "ko": """명령 (각도는 현재 단위, 길이는 {unit}):
  theta1 = 30; theta2 = 45      관절 번호로 값 지정 (q1 = 30처럼 쓰거나 관절 이름으로 {first} = 30처럼
                                써도 됩니다. 30deg, 0.5rad 같은 단위와 90/2, pi/4 rad 같은 간단한 계산식도 됩니다)
  q 30 45 60                    모든 관절 값을 한 번에 지정
  goto {goto}                   끝점을 목표 위치로 이동 (역기구학). [{goto}] 형식이나 숫자만 입력해도 됩니다
  branch [이름|auto]            역기구학 해(branch) 목록 보기, 또는 goto에 쓸 해 고르기
  home                          모든 관절을 0으로 (0이 한계 밖이면 가장 가까운 한계값으로)
  limits                        관절 한계 보기
  ground Z   box X0 Y0 Z0 X1 Y1 Z1   clear   scene
                                팔 주변 환경: 바닥 높이, 상자(두 모서리), 모두 지우기, 목록 보기. 이것들이나
                                팔 자신의 몸체와 부딪히는 이동은 거부됩니다
  units deg|rad                 입력과 출력의 각도 단위
  lang en|ko                    메시지 언어
  show                          현재 상태 다시 보기
  help                          이 도움말
  exit, quit, Ctrl-D            종료""",
    },
    "unknown": {"en": "cannot understand {text!r}; type help for the commands",
                "ko": "{text!r:j:을/를} 이해할 수 없습니다. help로 명령 목록을 확인하세요"},
    "not_number": {"en": "{word!r} is not a number", "ko": "{word!r:j:은/는} 숫자가 아닙니다"},
    "not_finite": {"en": "{word!r} is not a finite number", "ko": "{word!r:j:은/는} 유한한 숫자가 아닙니다"},
    "count": {"en": "{robot} has {n} joints ({names}); got {k} value(s)",
              "ko": "{robot}의 관절은 {n}개({names})인데 값은 {k}개입니다"},
    "unknown_joint": {"en": "no joint named {name!r}; the joints are {names}",
                      "ko": "{name!r:j:이라는/라는} 관절이 없습니다. 관절: {names}"},
    "bad_unit": {"en": "unit {unit!r} does not fit joint {joint} ({kind:t})",
                 "ko": "단위 {unit!r:j:은/는} {joint} 관절({kind:t} 관절)에 맞지 않습니다"},
    "limit": {"en": "joint limit: {detail}; the arm did not move",
              "ko": "관절 한계를 벗어납니다: {detail}. 팔을 움직이지 않았습니다"},
    "collision": {"en": "the {a} would hit the {b} by {depth}; the arm did not move",
                  "ko": "이 자세로 가면 {a:j:이/가} {b}에 부딪힙니다(겹침 {depth}). 팔을 움직이지 않았습니다"},
    "scene_now": {"en": "around the arm: {shapes} (and its own body; moves into them are refused)",
                  "ko": "팔 주변: {shapes}. 이것들이나 팔 자신의 몸체와 부딪히는 이동은 거부됩니다"},
    "scene_none": {"en": "nothing around the arm; only its own body and self-collision are checked",
                   "ko": "팔 주변에 아무것도 없습니다. 팔 자신의 몸체와 자기 충돌만 검사합니다"},
    "scene_hit": {"en": "note: the arm is in collision now: {detail}",
                  "ko": "참고: 팔이 지금 충돌 상태입니다: {detail}"},
    "box_count": {"en": "box needs 6 numbers: the corners x0 y0 z0 x1 y1 z1 in {unit}; got {k}",
                  "ko": "box에는 숫자 6개(두 모서리 x0 y0 z0 x1 y1 z1, 단위 {unit})가 필요한데 {k}개가 입력되었습니다"},
    "ground_count": {"en": "ground needs one number: the floor height z in {unit}; got {k}",
                     "ko": "ground에는 숫자 1개(바닥 높이 z, 단위 {unit})가 필요한데 {k}개가 입력되었습니다"},
    "ambiguous": {"en": "numbers alone are ambiguous: write q {nums} for joint values, or goto {nums} / [{nums}] "
                        "for a target",
                  "ko": "숫자만으로는 모호합니다. 관절 값은 q {nums}, 목표 위치는 goto {nums} 또는 [{nums}] 형식으로 쓰세요"},
    "goto_count": {"en": "a target for {robot} is {forms}; got {k} number(s)",
                   "ko": "{robot}의 목표 위치는 {forms} 형식인데 숫자 {k}개가 입력되었습니다"},
    "unreachable": {"en": "target not reached ({detail}); the arm did not move",
                    "ko": "목표 위치에 도달할 수 없습니다({detail}). 팔을 움직이지 않았습니다"},
    "ik_error": {"en": "inverse kinematics failed: {detail}", "ko": "역기구학 실패: {detail}"},
    "no_branches": {"en": "{robot} has no closed-form IK, so no named branches (goto uses a numerical solver)",
                    "ko": "{robot:j:은/는} 해석적 역기구학 해가 없어서 이름 붙은 해(branch)도 없습니다. goto는 수치 해법을 씁니다"},
    "branch_unknown": {"en": "no branch {name!r}; the branches are {names} (or auto)",
                       "ko": "{name!r:j:이라는/라는} 해가 없습니다. 해 목록: {names} (또는 auto)"},
    "branch_set": {"en": "goto will use branch {name}", "ko": "이제 goto는 {name} 해를 씁니다"},
    "branch_auto": {"en": "goto will use the branch nearest the current pose",
                    "ko": "이제 goto는 현재 자세에 가장 가까운 해를 씁니다"},
    "branch_missing": {"en": "branch {name} cannot reach the current end point here; kept {current}",
                       "ko": "{name} 해로는 현재 끝점에 갈 수 없어서 지금의 해({current})를 그대로 둡니다"},
    "branches_title": {"en": "IK branches for the current end point", "ko": "현재 끝점의 역기구학 해"},
    "units_now": {"en": "angles are in {u}", "ko": "각도 단위: {u}"},
    "units_bad": {"en": "units must be deg or rad, got {u!r}", "ko": "각도 단위는 deg 또는 rad이어야 합니다(입력: {u!r})"},
    "lang_now": {"en": "messages in English", "ko": "메시지를 한국어로 표시합니다"},
    "lang_bad": {"en": "language must be en or ko, got {u!r}", "ko": "언어는 en 또는 ko여야 합니다(입력: {u!r})"},
    "picture": {"en": "picture: {path}", "ko": "그림: {path}"},
    "plot_failed": {"en": "could not draw the arm ({detail}); continuing without pictures",
                    "ko": "팔을 그리지 못했습니다({detail}). 그림 없이 계속합니다"},
    "too_long": {"en": "the line has {n:,} characters, more than {limit:,}; it was not read",
                 "ko": "줄이 {n:,}자로 {limit:,}자를 넘어 읽지 않았습니다"},
    "picture_cap": {"en": "this session has written {limit} pictures; no more are drawn (start a new session for more)",
                    "ko": "이 세션에서 그림 {limit}장을 저장해서 더는 그리지 않습니다. 그림이 더 필요하면 새 세션을 시작하세요"},
    "bye": {"en": "bye", "ko": "종료합니다."},
    "internal": {"en": "internal error ({detail}); the shell goes on — please report this",
                 "ko": "내부 오류가 났습니다({detail}). 셸은 계속 동작합니다. 이 오류를 알려 주세요"},
    "exit_alone": {"en": "exit must be the last command of a line", "ko": "exit는 줄의 마지막 명령이어야 합니다"},
    "joint": {"en": "joint", "ko": "관절"},
    "value": {"en": "value", "ko": "값"},
    "limits": {"en": "limits", "ko": "한계"},
    "state_title": {"en": "{robot}: joint values", "ko": "{robot}: 관절 값"},
    "limits_title": {"en": "{robot}: joint limits", "ko": "{robot}: 관절 한계"},
    "end_point": {"en": "end point", "ko": "끝점"},
    "orientation": {"en": "orientation (roll, pitch, yaw)", "ko": "자세 (roll, pitch, yaw)"},
    "branch": {"en": "IK branch", "ko": "역기구학 해"},
    "none": {"en": "—", "ko": "—"},
    "limit_item": {"en": "{joint} = {value} outside [{lower}, {upper}] {unit}",
                   "ko": "{joint} = {value} (한계 {lower} ~ {upper} {unit})"},
    "forms_planar": {"en": "x y", "ko": "x y"},
    "forms_planar_phi": {"en": "x y, or x y phi", "ko": "x y 또는 x y phi"},
    "forms_spatial": {"en": "x y z, or x y z roll pitch yaw", "ko": "x y z 또는 x y z roll pitch yaw"},
    "unreachable_detail": {"en": "{reason}: {message}",
                           "ko": "{reason:t}, 가장 가까운 자세의 위치 오차 {error}"},
    "yes": {"en": "yes", "ko": "예"},
    "term": {"en": "{term}", "ko": "{term:t}"},
    "ok": {"en": "ok", "ko": "가능"},
}


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
    text = str(word)
    m = re.search(r"([가-힣]+|[A-Za-z°]+|[0-9]+(?:\.[0-9]+)?)[^가-힣A-Za-z0-9°]*$", text)
    if not m:
        return None
    tail = m.group(1)
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


_TERMS: dict[str, dict[str, str]] = {
    "revolute": {"ko": "회전"}, "prismatic": {"ko": "직동"}, "continuous": {"ko": "연속 회전"},
    "unreachable": {"ko": "작업 공간 밖"}, "singular": {"ko": "특이점"}, "max iterations": {"ko": "반복 횟수 초과"},
    "joint limits": {"ko": "관절 한계"}, "collision": {"ko": "충돌"}, "converged": {"ko": "수렴"},
}


class _Formatter(string.Formatter):
    """``str.format`` plus two specs: ``j:을/를`` attaches a particle (:func:`josa`), ``t`` translates a term."""

    def __init__(self, lang: str) -> None:
        self.lang = lang

    def format_field(self, value: Any, format_spec: str) -> str:
        if format_spec.startswith("j:"):
            return josa(value, format_spec[2:])
        if format_spec == "t":
            return _TERMS.get(str(value), {}).get(self.lang, str(value))
        return super().format_field(value, format_spec)


def default_language() -> str:
    """``"ko"`` when the locale (LC_ALL, LC_MESSAGES, LANG) is Korean, else ``"en"``."""
    for var in ("LC_ALL", "LC_MESSAGES", "LANG"):
        value = os.environ.get(var, "")
        if value:
            return "ko" if value.lower().startswith("ko") else "en"
    return "en"


def cli_language(flag: str | None = None) -> str:
    """The command line's language: ``--lang``, else ``ARMKIT_LANG``, else the locale (:func:`default_language`).

    >>> cli_language("ko"), cli_language("en")
    ('ko', 'en')
    """
    for value in (flag, os.environ.get("ARMKIT_LANG")):
        if value:
            return "ko" if value.lower().startswith("ko") else "en"
    return default_language()


@lru_cache(maxsize=None)
def _catalogue(lang: str) -> gettext.NullTranslations:
    """The compiled catalogue of ``lang``. ``make locale`` (run by ``make test``) builds the ``.mo`` from the
    ``.po``; when the ``.mo`` is missing or older than the ``.po`` (an install without make, a ``.po`` just
    edited) and Babel is installed, the ``.po`` is compiled in memory instead; else English."""
    po = LOCALE_DIR / lang / "LC_MESSAGES" / "armkit.po"
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
    return gettext.translation("armkit", localedir=str(LOCALE_DIR), languages=[lang], fallback=True)


def translate(text: str, lang: str = "en", **fields: object) -> str:
    """``text`` (an English message of the command line) from the gettext catalogue of ``lang``, formatted with
    ``fields`` (``{x:j:을/를}`` attaches a Korean particle, see :func:`josa`). English, or a message the
    catalogue lacks, stays as written.

    >>> translate("{what}: {value!r} is not a number", "en", what="joint values", value="x")
    "joint values: 'x' is not a number"
    """
    template = text if lang == "en" else _catalogue(lang).gettext(text)
    return _Formatter(lang).format(template, **fields)


def message(key: str, lang: str = "en", **fields: object) -> str:
    """The message ``key`` in ``lang`` (``"en"`` or ``"ko"``), formatted with ``fields``."""
    texts = MESSAGES[key]
    return _Formatter(lang).format(texts.get(lang, texts["en"]), **fields)
