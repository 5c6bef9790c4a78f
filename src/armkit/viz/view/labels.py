"""Korean and English labels of the browser view.

Wording shared with the shell comes from :mod:`armkit.locale` (``joint``, ``end_point``,
``branch``, ...); the view's own labels live in :data:`LABELS`.

>>> label("track", "ko"), label("end_point", "en")
('목표 추적', 'end point')
"""

from __future__ import annotations

from ...locale import MESSAGES, N_, NC_, translate_in

__all__ = ["LABELS", "label"]

LABELS: dict[str, str] = {     # English here, Korean in the catalogue (armkit/locale, docs/languages.md)
    "joints": N_("Joints"),
    "panel": N_("armkit view: {robot}"),     # the panel's title (viser would show its English "Connected")
    "grid_cells": N_("ground grid: cells of {size}"),
    "pose": N_("End pose"),
    "rpy": N_("roll pitch yaw (deg)"),
    "manipulability": N_("manipulability"),
    "near_singular": N_("⚠ near a singularity: manipulability {w}, condition number {c}"),
    "singular": N_("⚠ singular: manipulability {w}"),
    "follows": N_("the target is at the end point (joints set directly): drag it or type one to solve IK"),
    "close_view": N_("Close the view"),
    "not_singular": N_("not near a singularity"),
    "collision": N_("⚠ collision: {message}"),
    "target": N_("Target (IK)"),
    "show_target": N_("show target gizmo"),
    "ik_method": N_("IK method"),
    "ik_mode": N_("target type"),
    "position_only": N_("position"),
    "full_pose": N_("full pose"),
    "branches": N_("branches"),
    "no_closed_form": N_("no closed form for this target: {method}"),
    "reached": N_("✓ reached ({method}, {branch}); error {err} {unit}"),
    "not_reached": N_("✗ not reached: {message}"),
    "show_sweeps": N_("show sweeps"),
    "sweep": N_("sweep {k} of {m}: error {err} {unit}"),
    "track": N_("Track"),
    "path": N_("path"),
    "method": N_("method"),
    "frames": N_("frames"),
    "speed": N_("speed (frames/s)"),
    "play": N_("Play"),
    "pause": N_("Pause"),
    "step": N_("Step"),
    "upload_csv": N_("Upload CSV path"),
    "frame": NC_("animation", "frame"),   # an animation's frame (a coordinate frame is another word in Korean)
    "track_status": N_("frame {k}/{m}: {state}, error {err} {unit}"),
    "state_reached": N_("reached"),
    "state_out": N_("out of reach"),
    "state_not_converged": N_("not converged"),
    "state_limits": N_("only outside the joint limits"),
    "state_blocked": N_("every solution collides"),
    "workspace": N_("Workspace"),
    "show_workspace": N_("reach cloud (colour: manipulability)"),
    "trajectory": N_("Trajectory"),
    "time": N_("time (s)"),
    "plan_home": N_("Plan: home → here"),
    "no_path": N_("no trajectory loaded"),
    "path_info": N_("{label}: {m} samples, {d} s"),
    "view": N_("View"),
    "show_frames": N_("show link frames"),
    "screenshot": N_("Screenshot (PNG)"),
    "saved_to": N_("saved to {path}"),
    "home": N_("Home"),
    "bad_csv": N_("cannot use the uploaded file: {detail}"),
}
_SHARED = ("joint", "end_point", "orientation", "branch", "limits", "value")


def label(key: str, lang: str = "en", **fields: object) -> str:
    """The label ``key`` in ``lang`` (``"en"`` or ``"ko"``), formatted with ``fields``.

    Keys of the shell's wording (``joint``, ``end_point``, ``branch``, ...) come from
    :data:`armkit.locale.MESSAGES`, so the view and the CLI say the same thing.
    """
    if key in _SHARED:
        texts = MESSAGES[key]
        text = texts.get(lang, texts["en"])
        return text.format(**fields) if fields else text
    return translate_in(_CONTEXT.get(key), LABELS[key], lang, **fields)


_CONTEXT = {"frame": "animation"}
"""Labels whose English word means something else elsewhere (their catalogue entries carry this context)."""

