"""The browser panels of :class:`armkit.viz.view.View`: joints, end pose, target/IK, track, workspace,
trajectory, view options.

Every widget callback checks ``event.client``: an update that the server itself made
(``client is None``, e.g. a slider moved to follow ``set_q``) is not fed back. Values
arrive as numbers from viser's widgets; nothing typed is evaluated.
"""

from __future__ import annotations

import html
import math
import re
import tempfile
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any, Optional

import numpy as np
from numpy.typing import NDArray

from ...errors import ArmkitError
from ...ik import IKResult
from ...kinematics import condition_number, fk, manipulability
from ...spatial import rotation_to_rpy, rpy_to_rotation
from .drawing import rotation_from_wxyz, wxyz_from_rotation
from .labels import label

if TYPE_CHECKING:  # pragma: no cover
    from .server import View

__all__ = ["Panels", "format_numbers", "singular_html"]

Array = NDArray[np.float64]
_DECIMALS = {"m": 5, "cm": 4, "mm": 3}
TRAIL = 400                  # end points kept in the tracking trail


def format_numbers(values: Any, decimals: int) -> str:
    """``"24.861, 14.353, 187.181"``: numbers joined by commas, fixed decimals, no ``-0``."""
    out = []
    for v in np.asarray(values, dtype=float).ravel():
        s = f"{v:.{decimals}f}"
        out.append(s[1:] if s.startswith("-") and float(s) == 0.0 else s)
    return ", ".join(out)


def singular_html(w: float, c: float, lang: str) -> str:
    """The singularity line for manipulability ``w`` and condition number ``c`` (empty when well away).

    Above :data:`~armkit.viz.view.server.SINGULAR` (1e12) the number is rounding noise: the
    line says "singular" in words with the manipulability, never the number.
    """
    from .server import NEAR_SINGULAR, SINGULAR

    if math.isfinite(c) and c <= NEAR_SINGULAR:
        return ""
    if not math.isfinite(c) or c > SINGULAR:
        text = label("singular", lang, w=f"{w:.3g}")
    else:
        text = label("near_singular", lang, w=f"{w:.3g}", c=f"{c:.3g}")
    return f'<div class="armkit-singular" style="color:#b45309;font-size:0.85em;padding:0 0.5em">{html.escape(text)}</div>'


class Panels:
    """The widgets of one view (built once, updated in place)."""

    def __init__(self, view: "View") -> None:
        self.view = view
        self.robot = r = view.robot
        self.lang = view.lang
        self.server: Any = view.server           # viser's handles are used untyped (their setters confuse mypy)
        self.dec = _DECIMALS.get(r.unit, 5)
        self.track: Any = None
        self.track_k = 0
        self.traj: Any = None
        self._csv: Optional[Path] = None
        self._ws_cloud: Any = None
        self.position_only = r.n < 6
        self._build_joints()
        self._build_pose()
        self._build_target()
        self._build_track()
        self._build_workspace()
        self._build_trajectory()
        self._build_view_folder()
        from .readouts import Readouts          # T and J, stored configurations, frames, camera presets

        self.readouts = Readouts(view, self.lang, self.dec)

    def _build_joints(self) -> None:
        """A slider per joint (degrees, or the robot's unit for a prismatic joint) and Home."""
        r, view, gui, L = self.robot, self.view, self.server.gui, self._l
        with gui.add_folder(L("joints")):
            self.sliders = []
            for k, j in enumerate(r.joints):
                if j.is_prismatic:
                    lo = j.lower if math.isfinite(j.lower) else -r.reach
                    hi = j.upper if math.isfinite(j.upper) else r.reach
                    step = float(f"{(hi - lo) / 1000:.1g}") or 1e-3
                    text = f"{j.name} ({r.unit})"
                    value = float(view.q[k])
                else:
                    lo = math.degrees(j.lower) if math.isfinite(j.lower) else -180.0
                    hi = math.degrees(j.upper) if math.isfinite(j.upper) else 180.0
                    step, text, value = 0.01, f"{j.name} (°)", math.degrees(float(view.q[k]))
                s = gui.add_slider(text, min=round(lo, 6), max=round(hi, 6), step=step,
                                   initial_value=float(np.clip(value, lo, hi)))
                s.on_update(self._joint_callback(k))
                self.sliders.append(s)
            home = gui.add_button(label("home", self.lang))
            home.on_click(lambda e: self.view.set_q(self.view.home) if e.client is not None else None)

    def _build_pose(self) -> None:
        """The end pose, manipulability, singularity and collision lines."""
        r, gui, L = self.robot, self.server.gui, self._l
        with gui.add_folder(L("pose")):
            self.pose_text = gui.add_text(f"{label('end_point', self.lang)} ({r.unit})", "", disabled=True)
            self.rpy_text = gui.add_text(L("rpy"), "", disabled=True)
            self.manip_text = gui.add_text(L("manipulability"), "", disabled=True)
            self.singular_html = gui.add_html("")
            self.collision_html = gui.add_html("")

    def _build_target(self) -> None:
        """The IK target: gizmo, method, mode, typed target, branch list, sweeps."""
        r, view, gui, sc, L = self.robot, self.view, self.server.gui, self.server.scene, self._l
        reach_m = (r.reach or 1.0) * r.unit_scale
        T0 = fk(r, view.q)
        with gui.add_folder(L("target")):
            self.show_gizmo = gui.add_checkbox(L("show_target"), True)
            self.method_dd = gui.add_dropdown(L("ik_method"), ["auto", "lm", "newton", "ccd", "fabrik"],
                                              initial_value="auto")
            self._modes = [L("position_only"), L("full_pose")]
            self.mode_dd = gui.add_dropdown(L("ik_mode"), self._modes,
                                            initial_value=self._modes[0 if self.position_only else 1])
            self.target_xyz = gui.add_vector3(f"xyz ({r.unit})", tuple(np.round(T0[:3, 3], self.dec)),
                                              step=10.0 ** -self.dec)

            self.target_rpy = gui.add_vector3(L("rpy"), tuple(np.round(rotation_to_rpy(T0[:3, :3], degrees=True),
                                                                        3)), step=0.001)
            self.branch_dd = gui.add_dropdown(label("branch", self.lang), ["—"], initial_value="—")
            self.sweeps_cb = gui.add_checkbox(L("show_sweeps"), False)
            self.ik_html = gui.add_html("")
        self.gizmo = sc.add_transform_controls("/target", scale=0.22 * reach_m, position=tuple(T0[:3, 3] * r.unit_scale),
                                               wxyz=tuple(wxyz_from_rotation(T0[:3, :3])), depth_test=False)
        self.target_ball = sc.add_icosphere("/target/ball", radius=0.03 * reach_m, color=(40, 180, 80),
                                            subdivisions=2)
        self.gizmo.on_update(self._gizmo_update)
        self.show_gizmo.on_update(self._toggle_gizmo)
        self.mode_dd.on_update(self._mode_changed)
        self.target_xyz.on_update(self._typed_target)
        self.target_rpy.on_update(self._typed_target)
        self.branch_dd.on_update(self._branch_chosen)

    def _build_track(self) -> None:
        """Tracking a moving target: path, method, frames, speed, play/pause/step, CSV upload."""
        gui, L = self.server.gui, self._l
        from ..tracking import PATHS, TRACK_METHODS

        with gui.add_folder(L("track"), expand_by_default=False):
            self.path_dd = gui.add_dropdown(L("path"), list(PATHS), initial_value="circle")
            self.track_method_dd = gui.add_dropdown(L("method"), list(TRACK_METHODS), initial_value="lm")
            self.frames_nb = gui.add_number(L("frames"), 200, min=2, max=5000, step=1)
            self.speed = gui.add_slider(L("speed"), min=1, max=120, step=1, initial_value=20)
            self.play_btn = gui.add_button(L("play"))
            self.pause_btn = gui.add_button(L("pause"))
            self.step_btn = gui.add_button(L("step"))
            self.upload = gui.add_upload_button(L("upload_csv"), mime_type="text/csv")
            self.track_text = gui.add_text(L("frame"), "", disabled=True)
        self.play_btn.on_click(self._track_play)
        self.pause_btn.on_click(lambda e: self.view.stop_player())
        self.step_btn.on_click(self._track_step)
        self.upload.on_upload(self._csv_uploaded)

    def _build_workspace(self) -> None:
        """The reach cloud toggle."""
        gui, L = self.server.gui, self._l
        with gui.add_folder(L("workspace"), expand_by_default=False):
            self.ws_cb = gui.add_checkbox(L("show_workspace"), False)
            self.ws_bar = gui.add_html("")            # the cloud's colour bar (readouts.colour_bar_html)
        self.ws_cb.on_update(self._toggle_workspace)

    def _build_trajectory(self) -> None:
        """Trajectory playback with a time slider."""
        gui, L = self.server.gui, self._l
        with gui.add_folder(L("trajectory"), expand_by_default=False):
            self.time_slider = gui.add_slider(L("time"), min=0.0, max=1.0, step=0.001, initial_value=0.0)
            self.traj_play = gui.add_button(L("play"))
            self.traj_plan = gui.add_button(L("plan_home"))
            self.traj_text = gui.add_text(L("trajectory"), L("no_path"), disabled=True)
        self.time_slider.on_update(self._time_moved)
        self.traj_play.on_click(lambda e: self._play_traj_from(self.time_slider.value) if self.traj else None)
        self.traj_plan.on_click(self._plan_home)

    def _build_view_folder(self) -> None:
        """Frames, screenshot, the grid's cell size."""
        view, gui, L = self.view, self.server.gui, self._l
        with gui.add_folder(L("view"), expand_by_default=False):
            self.frames_cb = gui.add_checkbox(L("show_frames"), False)
            self.shot_btn = gui.add_button(L("screenshot"))
            self.shot_html = gui.add_html("")
            gui.add_markdown(html.escape(L("grid_cells", size=view.drawing.grid_text)))
        self.frames_cb.on_update(self._toggle_frames)
        self.shot_btn.on_click(self._screenshot)

    # ------------------------------------------------------------------ helpers
    def _l(self, key: str, **fields: object) -> str:
        return label(key, self.lang, **fields)

    @property
    def method(self) -> str:
        return str(self.method_dd.value)

    @property
    def show_sweeps(self) -> bool:
        return bool(self.sweeps_cb.value)

    def set_method(self, method: str) -> None:
        self.method_dd.value = method

    def set_position_only(self, position_only: bool) -> None:
        self.position_only = position_only
        self.mode_dd.value = self._modes[0 if position_only else 1]
        self.gizmo.disable_rotations = position_only

    def set_playing(self, playing: bool) -> None:
        """Called when a player stops (nothing to show today; kept for the buttons' state)."""

    # ------------------------------------------------------------------ state
    def show_state(self, q: Array, F: Array) -> None:
        """Sliders, end pose and manipulability for ``q`` (frames ``F``); called inside ``server.atomic()``."""
        r = self.robot
        for k, s in enumerate(self.sliders):
            v = float(q[k]) if r.joints[k].is_prismatic else math.degrees(float(q[k]))
            s.value = round(v, 10)
        T = F[-1]
        self.pose_text.value = format_numbers(T[:3, 3], self.dec)
        self.rpy_text.value = format_numbers(rotation_to_rpy(T[:3, :3], degrees=True), 3)
        w = float(manipulability(r, q))
        c = float(condition_number(r, q))
        self.manip_text.value = f"{w:.4g}"
        self.singular_html.content = singular_html(w, c, self.lang)
        self.readouts.show_state(q, F)

    def show_follow(self, T: Array) -> None:
        """The joints were set directly: the target (gizmo, typed target) moves to the end pose ``T`` (4, 4),
        the branch list empties and the IK status says so; called inside ``server.atomic()``."""
        r = self.robot
        self.gizmo.position = tuple(T[:3, 3] * r.unit_scale)
        self.gizmo.wxyz = tuple(wxyz_from_rotation(T[:3, :3]))
        self.target_ball.color = (40, 180, 80)
        self.target_xyz.value = tuple(float(v) for v in np.round(T[:3, 3], self.dec))
        self.target_rpy.value = tuple(float(v) for v in np.round(rotation_to_rpy(T[:3, :3], degrees=True), 3))
        self.branch_dd.options = ["—"]
        self.branch_dd.value = "—"
        self.ik_html.content = (f'<div class="armkit-ik-status" data-ok="follow" style="color:#475569;'
                                f'font-size:0.85em;padding:0 0.5em">{html.escape(self._l("follows"))}</div>')

    def show_collision(self, res: Any) -> None:
        """The collision line: what the arm hits and by how much (empty when clear or without a scene)."""
        msg = res.message() if res is not None else ""
        self.collision_html.content = (f'<div class="armkit-collision" style="color:#b91c1c;font-size:0.85em;'
                                       f'padding:0 0.5em">{html.escape(self._l("collision", message=msg))}</div>'
                                       if msg else "")

    def show_target(self, t: Array, res: IKResult, move_gizmo: bool) -> None:
        """Target marker colour, branch list and the IK status line for result ``res``."""
        r = self.robot
        ok = bool(np.asarray(res.success))
        self.target_ball.color = (40, 180, 80) if ok else (220, 30, 30)
        p = t[:3, 3] if t.shape == (4, 4) else t
        if move_gizmo:
            self.gizmo.position = tuple(p * r.unit_scale)
            if t.shape == (4, 4):
                self.gizmo.wxyz = tuple(wxyz_from_rotation(t[:3, :3]))
        self.target_xyz.value = tuple(float(v) for v in np.round(p, self.dec))
        if t.shape == (4, 4):
            self.target_rpy.value = tuple(float(v) for v in np.round(rotation_to_rpy(t[:3, :3], degrees=True), 3))
        names = list(self.view.branches)
        self.branch_dd.options = names or ["—"]
        current = self.view.branch if self.view.branch in names else (names[0] if names else "—")
        self.branch_dd.value = current
        if ok:
            text = self._l("reached", method=self.method, branch=html.escape(str(np.asarray(res.branch))),
                           err=f"{float(np.asarray(res.position_error)):.2g}", unit=r.unit)
            colour = "#15803d"
        else:
            from ...locale import SOURCE
            from ...locale.library import ik_explanation

            reason, msg = str(np.asarray(res.reason)), str(np.asarray(res.message))
            msg = (msg if msg.startswith(reason) else f"{reason}: {msg}") if self.lang == SOURCE else \
                ik_explanation(reason, msg, float(np.asarray(res.position_error)), r.unit, self.lang)

            text = self._l("not_reached", message=html.escape(msg))
            colour = "#b91c1c"
        if res.checked_against:   # what the answer was checked against, as the CLI says it
            from ...locale import N_, translate

            text += "<br>" + html.escape(translate(N_("checked against: {names}"), self.lang,
                                                   names=", ".join(res.checked_against)))
        self.ik_html.content = (f'<div class="armkit-ik-status" data-ok="{int(ok)}" '
                                f'style="color:{colour};font-size:0.85em;padding:0 0.5em">{text}</div>')

    def show_sweep(self, k: int, m: int, err: float) -> None:
        self.ik_html.content = (f'<div class="armkit-ik-status" style="font-size:0.85em;padding:0 0.5em">'
                                f'{html.escape(self._l("sweep", k=k, m=m, err=f"{err:.3g}", unit=self.robot.unit))}'
                                "</div>")

    # ------------------------------------------------------------------ callbacks: joints and target
    def _joint_callback(self, k: int) -> Any:
        def cb(event: Any) -> None:
            if event.client is None:
                return
            r = self.robot
            v = float(self.sliders[k].value)
            q = self.view.q
            q[k] = v if r.joints[k].is_prismatic else math.radians(v)
            q[k] = float(np.clip(q[k], r.lower[k], r.upper[k]))
            self.view.stop_player()
            self.view.branch = None
            self.view.show_configuration(q)
        return cb

    def _gizmo_target(self) -> Array:
        r = self.robot
        p = np.asarray(self.gizmo.position, dtype=float) / r.unit_scale
        if self.position_only:
            return p
        T = np.eye(4)
        T[:3, :3] = rotation_from_wxyz(self.gizmo.wxyz)
        T[:3, 3] = p
        return T

    def _gizmo_update(self, event: Any) -> None:
        if event.client is None:
            return
        if getattr(event, "phase", None) == "end":       # released: animate the sweeps if asked
            if self.method in ("ccd", "fabrik") and self.show_sweeps:
                self.view.update_target(self._gizmo_target(), self.position_only, dragging=False,
                                        move_gizmo=False)
            return
        self.view.target_from_page(self._gizmo_target(), self.position_only, dragging=True)

    def _typed_target(self, event: Any) -> None:
        if event.client is None:
            return

        p = np.asarray(self.target_xyz.value, dtype=float)
        if self.position_only:
            t: Array = p
        else:
            t = np.eye(4)
            t[:3, :3] = rpy_to_rotation(np.asarray(self.target_rpy.value, dtype=float), degrees=True)
            t[:3, 3] = p
        self.view.stop_player()
        self.view.update_target(t, self.position_only, dragging=False, move_gizmo=True)

    def _toggle_gizmo(self, event: Any) -> None:
        self.gizmo.visible = bool(self.show_gizmo.value)

    def _mode_changed(self, event: Any) -> None:
        if event.client is None:
            return
        self.position_only = self.mode_dd.value == self._modes[0]
        self.gizmo.disable_rotations = self.position_only

    def _branch_chosen(self, event: Any) -> None:
        if event.client is None or self.branch_dd.value not in self.view.branches:
            return
        self.view.choose_branch(str(self.branch_dd.value))

    # ------------------------------------------------------------------ track
    def _track_play(self, event: Any) -> None:
        if event.client is None:
            return
        path = self.path_dd.value
        path_arg = str(self._csv) if path == "CSV" and self._csv is not None else str(path)
        key = (path_arg, str(self.track_method_dd.value), max(2, min(5000, int(self.frames_nb.value))))
        if self.track is not None and getattr(self, "_track_key", None) == key:
            self._start_track()
            return
        self.track_text.value = "…"
        q0 = self.view.q

        def body(token: int) -> None:          # tracking is computed off the callback thread
            from ..tracking import track

            try:
                res = track(self.robot, path=key[0], method=key[1], frames=key[2], seed=0, q0=q0)
            except ArmkitError as exc:
                self.track_text.value = str(exc).replace(str(self._csv), "CSV") if self._csv else str(exc)
                return
            if not self.view.player_alive(token):
                return
            self._track_key = key
            self._load_track(res, float(self.speed.value))
            self._track_loop(token)

        self.view.start_player(body)

    def play_track(self, res: Any, fps: float = 20.0, play: bool = True) -> None:
        """Load a :class:`~armkit.viz.tracking.TrackResult` and play it (looping) or show frame 0."""
        self.view.stop_player()
        self._load_track(res, fps)
        if play:
            self._start_track()
        else:
            self._show_track_frame(0)

    def _load_track(self, res: Any, fps: float) -> None:
        self.track = res
        self.track_k = 0
        self._track_ends = fk(self.robot, res.q)[:, :3, 3]
        self.speed.value = float(np.clip(round(fps), 1, 120))
        sc = self.server.scene
        reach_m = (self.robot.reach or 1.0) * self.robot.unit_scale
        self._track_ball = sc.add_icosphere("/track/target", radius=0.025 * reach_m, color=(220, 30, 30),
                                            subdivisions=2)

    def _show_track_frame(self, k: int) -> None:
        res = self.track
        r = self.robot
        s = r.unit_scale
        reach_m = (r.reach or 1.0) * s
        F = len(res.q)
        lo = max(0, k - TRAIL)
        ends = self._track_ends[lo:k + 1] * s
        sc = self.server.scene
        ok = bool(res.reached[k])
        state = self._l("state_reached" if ok else "state_out" if res.out_of_reach[k] else
                        "state_limits" if res.outside_limits is not None and res.outside_limits[k] else
                        "state_blocked" if res.blocked is not None and res.blocked[k] else "state_not_converged")

        def extra() -> None:
            self._track_ball.position = tuple(res.targets[k] * s)
            self._track_ball.color = (40, 180, 80) if ok else (220, 30, 30)
            if len(ends) >= 2:
                segs = np.stack([ends[:-1], ends[1:]], axis=1).astype(np.float32)
                sc.add_line_segments("/track/trail", segs, colors=(30, 90, 220), thickness=0.004 * reach_m)
            self.track_text.value = self._l("track_status", k=k + 1, m=F, state=state,
                                            err=f"{float(res.error[k]):.2g}", unit=r.unit)

        self.view.track_frame = k
        self.view.show_configuration(np.asarray(res.q[k], dtype=float), extra)

    def _start_track(self) -> None:
        self.view.start_player(self._track_loop)

    def _track_loop(self, token: int) -> None:
        """Play the loaded track, looping, until the player is cancelled."""
        view = self.view
        next_time = time.perf_counter()
        while view.player_alive(token):
            self._show_track_frame(self.track_k)
            self.track_k = (self.track_k + 1) % len(self.track.q)
            next_time += 1.0 / max(1.0, float(self.speed.value))
            delay = next_time - time.perf_counter()
            if delay < -0.5:             # fell behind (a slow machine): do not try to catch up
                next_time = time.perf_counter()
            view.player_wait(max(0.0, delay))

    def _track_step(self, event: Any) -> None:
        if event.client is None or self.track is None:
            return
        self.view.stop_player()
        self._show_track_frame(self.track_k)
        self.track_k = (self.track_k + 1) % len(self.track.q)

    def _csv_uploaded(self, event: Any) -> None:
        if event.client is None:
            return
        from ..tracking import target_path

        data = self.upload.value.content
        tmp = Path(tempfile.mkdtemp(prefix="armkit-view-")) / "path.csv"
        tmp.write_bytes(bytes(data[:5_000_000]))
        try:
            target_path(self.robot, str(tmp))
        except ArmkitError as exc:
            detail = str(exc).replace(str(tmp), "CSV")
            self.track_text.value = self._l("bad_csv", detail=detail)
            return
        self._csv = tmp
        self.path_dd.options = [*self.path_dd.options[:3], "CSV"]
        self.path_dd.value = "CSV"
        self.track = None

    # ------------------------------------------------------------------ workspace, frames, screenshot
    def _toggle_workspace(self, event: Any) -> None:
        on = bool(self.ws_cb.value)
        if on and self._ws_cloud is None:
            from matplotlib import colormaps

            from ...analysis.workspace import workspace

            ws = workspace(self.robot, samples=20_000, seed=0, manipulability=True,
                           scene=False if self.view.ik_scene is None else self.view.ik_scene)
            w = np.asarray(ws.manipulability, dtype=float)
            top = float(np.percentile(w, 99)) or 1.0
            self.ws_top = top
            colours = (colormaps["viridis"](np.clip(w / top, 0, 1))[:, :3] * 255).astype(np.uint8)
            s = self.robot.unit_scale
            reach_m = (self.robot.reach or 1.0) * s
            self._ws_cloud = self.server.scene.add_point_cloud("/workspace", (ws.points * s).astype(np.float32),
                                                               colors=colours, point_size=0.008 * reach_m)
        if self._ws_cloud is not None:
            self._ws_cloud.visible = on
            from .readouts import colour_bar_html

            self.ws_bar.content = colour_bar_html(self.ws_top, self.lang) if on else ""

    def _toggle_frames(self, event: Any) -> None:
        self.view.drawing.set_frames_visible(bool(self.frames_cb.value))
        self.view.show_configuration(self.view.q)

    def _screenshot(self, event: Any) -> None:
        client = event.client
        if client is None:
            return
        png = self.view.screenshot_png(client)
        try:                                   # a copy on the machine that serves the view ...
            path = self.view.write_png(png)
            text, colour = self._l("saved_to", path=str(path)), "#15803d"
        except ArmkitError as exc:
            text, colour = str(exc), "#b91c1c"
        self.shot_html.content = (f'<div class="armkit-screenshot" style="color:{colour};font-size:0.8em;'
                                  f'padding:0 0.5em;overflow-wrap:anywhere">{html.escape(text)}</div>')
        name = re.sub(r"[^A-Za-z0-9_.-]", "_", self.robot.name) or "arm"
        client.send_file_download(f"armkit-{name}.png", png, save_immediately=True)   # ... and in the browser

    # ------------------------------------------------------------------ trajectory
    def play_trajectory(self, traj: Any, play: bool = True) -> None:
        """Load a :class:`~armkit.motion.trajectory.Trajectory`: time slider from 0 to its duration."""
        self.view.stop_player()
        self.traj = traj
        d = max(float(traj.t[-1]), 1e-3)
        self.time_slider.max = round(d, 6)
        self.time_slider.step = float(f"{d / 1000:.1g}")
        self.time_slider.value = 0.0
        self.traj_text.value = self._l("path_info", label=traj.label or "path", m=len(traj.t), d=f"{d:.3g}")
        if play:
            self._play_traj_from(0.0)
        else:
            self._show_time(0.0)

    def _q_at(self, t: float) -> Array:
        traj = self.traj
        return np.array([np.interp(t, traj.t, traj.q[:, j]) for j in range(traj.q.shape[1])])

    def _show_time(self, t: float) -> None:
        q = np.clip(self._q_at(t), self.robot.lower, self.robot.upper)

        def extra() -> None:
            self.time_slider.value = round(float(t), 6)

        self.view.show_configuration(q, extra)

    def _play_traj_from(self, t0: float) -> None:
        traj = self.traj
        d = float(traj.t[-1])
        t0 = 0.0 if t0 >= d else float(t0)

        def body(token: int) -> None:
            start = time.perf_counter() - t0
            while self.view.player_alive(token):
                t = min(time.perf_counter() - start, d)
                self._show_time(t)
                if t >= d:
                    return
                self.view.player_wait(1 / 30)

        self.view.start_player(body)

    def _time_moved(self, event: Any) -> None:
        if event.client is None or self.traj is None:
            return
        self.view.stop_player()
        self._show_time(float(self.time_slider.value))

    def _plan_home(self, event: Any) -> None:
        if event.client is None:
            return
        from ...motion.trajectory import joint_trajectory

        q = self.view.q
        try:
            traj = joint_trajectory(np.stack([self.view.home, q]), "quintic", duration=2.0, robot=self.robot)
        except ArmkitError as exc:
            self.traj_text.value = str(exc)
            return
        self.play_trajectory(traj, play=True)
