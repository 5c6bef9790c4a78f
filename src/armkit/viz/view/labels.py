"""Korean and English labels of the browser view.

Wording shared with the shell comes from :mod:`armkit.locale` (``joint``, ``end_point``,
``branch``, ...); the view's own labels live in :data:`LABELS`.

>>> label("track", "ko"), label("end_point", "en")
('목표 추적', 'end point')
"""

from __future__ import annotations

from ...locale import MESSAGES

__all__ = ["LABELS", "label"]

LABELS: dict[str, dict[str, str]] = {
    "joints": {"en": "Joints", "ko": "관절"},
    "pose": {"en": "End pose", "ko": "끝점 자세"},
    "rpy": {"en": "roll pitch yaw (deg)", "ko": "roll pitch yaw (도)"},
    "manipulability": {"en": "manipulability", "ko": "조작성"},
    "near_singular": {"en": "⚠ near a singularity (condition number {c})",
                      "ko": "⚠ 특이점 근처입니다 (조건수 {c})"},
    "not_singular": {"en": "not near a singularity", "ko": "특이점에서 멀리 있습니다"},
    "collision": {"en": "⚠ collision: {message}", "ko": "⚠ 충돌: {message}"},
    "target": {"en": "Target (IK)", "ko": "목표 (역기구학)"},
    "show_target": {"en": "show target gizmo", "ko": "목표 기즈모 보기"},
    "ik_method": {"en": "IK method", "ko": "IK 방법"},
    "ik_mode": {"en": "target type", "ko": "목표 종류"},
    "position_only": {"en": "position", "ko": "위치"},
    "full_pose": {"en": "full pose", "ko": "위치+자세"},
    "branches": {"en": "branches", "ko": "해 목록"},
    "no_closed_form": {"en": "no closed form for this target: {method}", "ko": "이 목표에는 닫힌 해가 없습니다: {method}"},
    "reached": {"en": "✓ reached ({method}, {branch}); error {err} {unit}",
                "ko": "✓ 도달 ({method}, {branch}); 오차 {err} {unit}"},
    "not_reached": {"en": "✗ not reached: {message}", "ko": "✗ 도달 실패: {message}"},
    "show_sweeps": {"en": "show sweeps", "ko": "반복 과정 보기"},
    "sweep": {"en": "sweep {k} of {m}: error {err} {unit}", "ko": "반복 {k}/{m}: 오차 {err} {unit}"},
    "track": {"en": "Track", "ko": "목표 추적"},
    "path": {"en": "path", "ko": "경로"},
    "method": {"en": "method", "ko": "방법"},
    "frames": {"en": "frames", "ko": "프레임 수"},
    "speed": {"en": "speed (frames/s)", "ko": "속도 (프레임/초)"},
    "play": {"en": "Play", "ko": "재생"},
    "pause": {"en": "Pause", "ko": "일시정지"},
    "step": {"en": "Step", "ko": "한 단계"},
    "upload_csv": {"en": "Upload CSV path", "ko": "CSV 경로 올리기"},
    "frame": {"en": "frame", "ko": "프레임"},
    "track_status": {"en": "frame {k}/{m}: {state}, error {err} {unit}",
                     "ko": "프레임 {k}/{m}: {state}, 오차 {err} {unit}"},
    "state_reached": {"en": "reached", "ko": "도달"},
    "state_out": {"en": "out of reach", "ko": "도달 불가"},
    "state_not_converged": {"en": "not converged", "ko": "수렴 안 됨"},
    "workspace": {"en": "Workspace", "ko": "작업 공간"},
    "show_workspace": {"en": "reach cloud (colour: manipulability)", "ko": "도달 영역 (색: 조작성)"},
    "trajectory": {"en": "Trajectory", "ko": "궤적"},
    "time": {"en": "time (s)", "ko": "시간 (초)"},
    "plan_home": {"en": "Plan: home → here", "ko": "계획: 원점 → 현재"},
    "no_path": {"en": "no trajectory loaded", "ko": "불러온 궤적이 없습니다"},
    "path_info": {"en": "{label}: {m} samples, {d} s", "ko": "{label}: 샘플 {m}개, {d} 초"},
    "view": {"en": "View", "ko": "보기"},
    "show_frames": {"en": "show link frames", "ko": "링크 좌표계 보기"},
    "screenshot": {"en": "Screenshot (PNG)", "ko": "화면 저장 (PNG)"},
    "saved_to": {"en": "saved to {path}", "ko": "{path}에 저장했습니다"},
    "home": {"en": "Home", "ko": "원점"},
    "bad_csv": {"en": "cannot use the uploaded file: {detail}", "ko": "올린 파일을 쓸 수 없습니다: {detail}"},
}
_SHARED = ("joint", "end_point", "orientation", "branch", "limits", "value")


def label(key: str, lang: str = "en", **fields: object) -> str:
    """The label ``key`` in ``lang`` (``"en"`` or ``"ko"``), formatted with ``fields``.

    Keys of the shell's wording (``joint``, ``end_point``, ``branch``, ...) come from
    :data:`armkit.locale.MESSAGES`, so the view and the CLI say the same thing.
    """
    texts = MESSAGES[key] if key in _SHARED else LABELS[key]
    text = texts.get(lang, texts["en"])
    return text.format(**fields) if fields else text
