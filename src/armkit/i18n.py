"""Korean and English messages for the interactive front ends (the shell).

``message(key, lang, **fields)`` formats one message; ``default_language()`` reads the
locale (``LC_ALL``, ``LC_MESSAGES``, ``LANG``): Korean when it starts with ``ko``.

>>> message("bye", "ko")
'종료합니다.'
>>> message("unknown_joint", "en", name="wrist", names="yaw, shoulder, elbow")
"no joint named 'wrist'; the joints are yaw, shoulder, elbow"
"""

from __future__ import annotations

import os

__all__ = ["LANGUAGES", "default_language", "message", "MESSAGES"]

LANGUAGES = ("en", "ko")

MESSAGES: dict[str, dict[str, str]] = {
    "welcome": {
        "en": "armkit shell for {robot}: {n} joints ({names}), lengths in {unit}, angles in {angles}. "
              "Type help for the commands, exit to leave.",
        "ko": "armkit 셸 — {robot}: 관절 {n}개 ({names}), 길이 단위 {unit}, 각도 단위 {angles}. "
              "명령 목록은 help, 종료는 exit.",
    },
    "help": {
        "en": """commands (angles in the current units, lengths in {unit}):
  theta1 = 30; theta2 = 45      set joints by number (also q1 = 30, or by name: {first} = 30; 30deg, 0.5rad work)
  q 30 45 60                    set every joint at once
  goto {goto}                   move the end point to a target (inverse kinematics); also [{goto}]
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
  theta1 = 30; theta2 = 45      관절 번호로 값 지정 (q1 = 30, 관절 이름 {first} = 30 도 가능; 30deg, 0.5rad 표기 가능)
  q 30 45 60                    모든 관절을 한 번에 지정
  goto {goto}                   끝점을 목표 위치로 이동 (역기구학); [{goto}] 도 가능
  branch [이름|auto]            IK 해(branch) 목록 보기, 또는 goto 가 쓸 해 고르기
  home                          모든 관절을 0 으로 (한계 밖이면 가장 가까운 한계로)
  limits                        관절 한계 보기
  ground Z   box X0 Y0 Z0 X1 Y1 Z1   clear   scene
                                팔 주변 환경: 바닥, 상자 (모서리), 모두 지우기, 목록; 그 안으로 (또는 팔 자체의
                                몸체 안으로) 들어가는 이동은 거부됩니다
  units deg|rad                 입력과 출력의 각도 단위
  lang en|ko                    메시지 언어
  show                          현재 상태 다시 출력
  help                          이 도움말
  exit, quit, Ctrl-D            종료""",
    },
    "unknown": {"en": "cannot understand {text!r}; type help for the commands",
                "ko": "{text!r} 을(를) 이해할 수 없습니다. help 로 명령을 확인하세요"},
    "not_number": {"en": "{word!r} is not a number", "ko": "{word!r} 은(는) 숫자가 아닙니다"},
    "not_finite": {"en": "{word!r} is not a finite number", "ko": "{word!r} 은(는) 유한한 숫자가 아닙니다"},
    "count": {"en": "{robot} has {n} joints ({names}); got {k} value(s)",
              "ko": "{robot} 의 관절은 {n}개 ({names}) 인데 값이 {k}개입니다"},
    "unknown_joint": {"en": "no joint named {name!r}; the joints are {names}",
                      "ko": "{name!r} 이라는 관절이 없습니다. 관절: {names}"},
    "bad_unit": {"en": "unit {unit!r} does not fit joint {joint} ({kind})",
                 "ko": "단위 {unit!r} 는 관절 {joint} ({kind}) 에 맞지 않습니다"},
    "limit": {"en": "joint limit: {detail}; the arm did not move",
              "ko": "관절 한계 초과: {detail}; 팔을 움직이지 않았습니다"},
    "collision": {"en": "the {a} would hit the {b} by {depth}; the arm did not move",
                  "ko": "{a} 이(가) {b} 에 {depth} 만큼 부딪힙니다; 팔을 움직이지 않았습니다"},
    "scene_now": {"en": "around the arm: {shapes} (and its own body; moves into them are refused)",
                  "ko": "팔 주변: {shapes} (팔 자체의 몸체 포함; 이 안으로의 이동은 거부됩니다)"},
    "scene_none": {"en": "nothing around the arm; only its own body and self-collision are checked",
                   "ko": "팔 주변에 아무것도 없습니다. 팔 자체의 몸체와 자기 충돌만 검사합니다"},
    "scene_hit": {"en": "note: the arm is in collision now: {detail}",
                  "ko": "참고: 팔이 지금 충돌 상태입니다: {detail}"},
    "box_count": {"en": "box needs 6 numbers: the corners x0 y0 z0 x1 y1 z1 in {unit}; got {k}",
                  "ko": "box 에는 숫자 6개 (모서리 x0 y0 z0 x1 y1 z1, 단위 {unit}) 가 필요합니다. {k}개를 받았습니다"},
    "ground_count": {"en": "ground needs one number: the floor height z in {unit}; got {k}",
                     "ko": "ground 에는 숫자 1개 (바닥 높이 z, 단위 {unit}) 가 필요합니다. {k}개를 받았습니다"},
    "ambiguous": {"en": "numbers alone are ambiguous: write q {nums} for joint values, or goto {nums} / [{nums}] "
                        "for a target",
                  "ko": "숫자만으로는 모호합니다: 관절 값은 q {nums}, 목표 위치는 goto {nums} 또는 [{nums}] 로 쓰세요"},
    "goto_count": {"en": "a target for {robot} is {forms}; got {k} number(s)",
                   "ko": "{robot} 의 목표는 {forms} 형식입니다. 숫자 {k}개를 받았습니다"},
    "unreachable": {"en": "target not reached ({detail}); the arm did not move",
                    "ko": "목표에 도달할 수 없습니다 ({detail}); 팔을 움직이지 않았습니다"},
    "ik_error": {"en": "inverse kinematics failed: {detail}", "ko": "역기구학 실패: {detail}"},
    "no_branches": {"en": "{robot} has no closed-form IK, so no named branches (goto uses a numerical solver)",
                    "ko": "{robot} 은(는) 닫힌 해 IK 가 없어 이름 있는 해가 없습니다 (goto 는 수치 해법 사용)"},
    "branch_unknown": {"en": "no branch {name!r}; the branches are {names} (or auto)",
                       "ko": "{name!r} 라는 해가 없습니다. 해 목록: {names} (또는 auto)"},
    "branch_set": {"en": "goto will use branch {name}", "ko": "goto 는 이제 {name} 해를 씁니다"},
    "branch_auto": {"en": "goto will use the branch nearest the current pose",
                    "ko": "goto 는 현재 자세에 가장 가까운 해를 씁니다"},
    "branch_missing": {"en": "branch {name} cannot reach the current end point here; kept {current}",
                       "ko": "{name} 해로는 현재 끝점에 갈 수 없어 {current} 를 유지합니다"},
    "branches_title": {"en": "IK branches for the current end point", "ko": "현재 끝점의 IK 해"},
    "units_now": {"en": "angles are in {u}", "ko": "각도 단위: {u}"},
    "units_bad": {"en": "units must be deg or rad, got {u!r}", "ko": "단위는 deg 또는 rad 이어야 합니다: {u!r}"},
    "lang_now": {"en": "messages in English", "ko": "메시지를 한국어로 표시합니다"},
    "lang_bad": {"en": "language must be en or ko, got {u!r}", "ko": "언어는 en 또는 ko 이어야 합니다: {u!r}"},
    "picture": {"en": "picture: {path}", "ko": "그림: {path}"},
    "plot_failed": {"en": "could not draw the arm ({detail}); continuing without pictures",
                    "ko": "팔을 그리지 못했습니다 ({detail}); 그림 없이 계속합니다"},
    "too_long": {"en": "the line has {n:,} characters, more than {limit:,}; it was not read",
                 "ko": "줄이 {n:,}자로 {limit:,}자를 넘어 읽지 않았습니다"},
    "picture_cap": {"en": "this session has written {limit} pictures; no more are drawn (start a new session for more)",
                    "ko": "이 세션에서 그림 {limit}장을 저장했습니다. 더 이상 그리지 않습니다 (새 세션을 시작하세요)"},
    "bye": {"en": "bye", "ko": "종료합니다."},
    "internal": {"en": "internal error ({detail}); the shell goes on — please report this",
                 "ko": "내부 오류 ({detail}); 셸은 계속됩니다 — 알려 주세요"},
    "exit_alone": {"en": "exit must be the last command of a line", "ko": "exit 는 줄의 마지막 명령이어야 합니다"},
    "joint": {"en": "joint", "ko": "관절"},
    "value": {"en": "value", "ko": "값"},
    "limits": {"en": "limits", "ko": "한계"},
    "state_title": {"en": "{robot}: joint values", "ko": "{robot}: 관절 값"},
    "limits_title": {"en": "{robot}: joint limits", "ko": "{robot}: 관절 한계"},
    "end_point": {"en": "end point", "ko": "끝점"},
    "orientation": {"en": "orientation (roll, pitch, yaw)", "ko": "자세 (roll, pitch, yaw)"},
    "branch": {"en": "IK branch", "ko": "IK 해"},
    "none": {"en": "—", "ko": "—"},
}


def default_language() -> str:
    """``"ko"`` when the locale (LC_ALL, LC_MESSAGES, LANG) is Korean, else ``"en"``."""
    for var in ("LC_ALL", "LC_MESSAGES", "LANG"):
        value = os.environ.get(var, "")
        if value:
            return "ko" if value.lower().startswith("ko") else "en"
    return "en"


def message(key: str, lang: str = "en", **fields: object) -> str:
    """The message ``key`` in ``lang`` (``"en"`` or ``"ko"``), formatted with ``fields``."""
    texts = MESSAGES[key]
    return texts.get(lang, texts["en"]).format(**fields)
