"""The live browser view: :func:`view` starts a viser server and returns a :class:`View` handle.

The handle owns the arm's state (``q``), the IK target and the players (tracking,
trajectories, CCD/FABRIK sweeps); the browser panels (:mod:`armkit.viz.view.panels`) and
scripts both call its methods, so the page and the handle always agree. Every update
of the arm goes out in one batch (``server.atomic()``): the link poses, the joint
sliders and the end-pose text reach the page together, and is flushed at once (viser
would otherwise hold it for up to 1/60 s to collect a window of messages).

Nothing typed in the page is ever evaluated: numbers arrive as numbers from viser's
widgets, an uploaded CSV is parsed by :func:`numpy.loadtxt`.

This module holds the handle's state, IK and life cycle; its parts live next to it and are
re-exported here: the first pose (:mod:`.home`), the port handling (:mod:`.network`), the
players (:mod:`.players`) and the screenshots (:mod:`.screenshots`).
"""

from __future__ import annotations

import collections
import contextlib
import html
import io
import math
import threading
import time
from pathlib import Path
from typing import Any, Callable, Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..._extras import require
from ...errors import ArmkitError, JointLimitError, ShapeError, ViewError
from ...ik.api import IKInputError
from ...locale import LANGUAGES, default_language
from ...kinematics import condition_number, fk, fk_frames, manipulability
from ...model import Robot, load
from ...ik import IKResult, ik, ik_all
from ...ik.analytic import closed_form
# the view's parts, re-exported here (the panels, the tests and armkit.viz.view import them from this module)
from ...spatial import rotation_to_rpy
from .home import HOME_STEPS, NEAR_SINGULAR, SINGULAR, home_pose
from .network import _port_free, _quiet, drop_unopened_connections, free_port
from .players import MAX_SWEEPS, Players
from .screenshots import Screenshots

__all__ = ["View", "ViewError", "view", "IK_METHODS", "home_pose"]

Array = NDArray[np.float64]
IK_METHODS = ("auto", "lm", "newton", "ccd", "fabrik")


class View(Players, Screenshots):
    """A live 3-D view of one arm in the browser (see :func:`view`).

    The players (:class:`~armkit.viz.view.players.Players`) and the screenshots
    (:class:`~armkit.viz.view.screenshots.Screenshots`) are its base classes.

    Attributes
    ----------
    robot : Robot
    url : str
        Address to open, e.g. ``http://127.0.0.1:8080/``.
    lang : {"en", "ko"}
    last_result : IKResult or None
        The IK result of the latest target.
    updates : int
        Number of arm updates sent so far (for benchmarks).
    scene : Scene
        The surroundings drawn (robot unit); shapes the arm overlaps turn red.
    screenshot_dir : Path
        Folder where the page's *Screenshot* button writes its PNG (default: the current folder).
    """

    def __init__(self, robot: Robot | str, port: Optional[int] = None, host: str = "127.0.0.1",
                 lang: Optional[str] = None, q: ArrayLike | None = None, scene: Any = None) -> None:
        viser = require("viser", "armkit view")
        from ...collision import Scene, as_scene, checked_against, resolve_scene

        self.robot = robot if isinstance(robot, Robot) else load(robot)
        if lang is not None and lang not in LANGUAGES:
            raise ViewError.of("lang must be one of {names}, got {lang!r}", names=', '.join(LANGUAGES), lang=lang)
        self.lang = lang or default_language()
        if port is None:
            port = free_port(host)
        elif not isinstance(port, (int, np.integer)) or isinstance(port, bool) or not 1 <= int(port) <= 65535:
            raise ViewError.of("port must be an integer in 1..65535, got {port!r}", port=port)
        elif not _port_free(host, int(port)):
            raise ViewError.of("port {port} on {host} is in use; choose another port, or leave it out for a free one",
                               port=port, host=host)
        r = self.robot
        # a bad scene file raises SceneError before the server starts; scene=False: none drawn, none checked
        self.scene = Scene([], r.unit) if scene is False else as_scene(r, scene)
        self.ik_scene = resolve_scene(r, False if scene is False else self.scene if scene is not None else None)
        self.checked_against = checked_against(r, self.ik_scene)   # what IK here is checked against (the one rule)
        self.home = home_pose(r, False if scene is False else self.scene)
        self._q = self.home.copy() if q is None else self._checked_q(q)
        self._lock = threading.RLock()
        self._stop = threading.Event()
        self._player: Optional[threading.Thread] = None
        self._player_token = 0
        self._pending: Optional[Array] = None
        self._pending_lock = threading.Lock()
        self._busy = False
        self._closed_form: dict[bool, bool] = {}
        self.branch: Optional[str] = None
        self.branches: dict[str, Array] = {}
        self.last_result: Optional[IKResult] = None
        self.target: Optional[Array] = None
        self.updates = 0
        self.update_ms: collections.deque[float] = collections.deque(maxlen=1000)   # server time per update
        self.ik_updates = 0
        self.track_frame = -1
        self.screenshot_dir = Path.cwd()      # where the page's Screenshot button saves its PNG files
        self._following = True                 # the target sits on the end pose (no IK result shown)
        self._every: Any = None                # (ik_all result, branch labels) of the current target
        self._closed = False
        self._closing = threading.Event()      # set by the page's close button (or close()): wait() returns
        self._close_reason = ""
        self._close_lock = threading.Lock()
        try:
            with _quiet():          # viser prints its own banner (in Jupyter as a display); we print the URL once
                self.server: Any = viser.ViserServer(host=host, port=int(port), verbose=False)
        except OSError as exc:
            raise ViewError.of("cannot serve on {host}:{port}: {exc}", host=host, port=port, exc=exc) from exc
        actual = int(self.server.get_port())
        if actual != int(port):
            with contextlib.redirect_stdout(io.StringIO()):       # viser's "Server stopped" line
                self.server.stop()
            raise ViewError.of("port {port} on {host} is in use; choose another port, or leave it out for a free one",
                               port=port, host=host)
        try:
            self._start(r, host, actual)
        except BaseException:     # a failure after the server started must not leave it running (nor print later)
            with contextlib.redirect_stdout(io.StringIO()):
                self.server.stop()
            raise

    def _start(self, r: Robot, host: str, actual: int) -> None:
        """The rest of ``__init__`` once the server listens: the scene, the drawings, the panels, a warm IK."""
        self.host, self.port = host, actual
        shown = "127.0.0.1" if host in ("0.0.0.0", "") else ("[::1]" if host == "::" else host)
        shown = f"[{shown}]" if ":" in shown and not shown.startswith("[") else shown
        self.url = f"http://{shown}:{actual}/"
        self._setup_scene()
        from .drawing import ArmDrawing, nice_grid
        from .obstacles import ObstacleDrawing
        from .panels import Panels

        self.drawing = ArmDrawing(self.server, r, self._q)
        self.obstacles = ObstacleDrawing(self.server, r, self.scene, nice_grid(r.reach or 1.0)[2] * r.unit_scale)
        self._build_panels()
        self.show_configuration(self._q)
        # warm the IK path once so that the first drag is not slow (Numba compiles on first use)
        try:
            self._solve(fk(r, self._q), position_only=self.panels.position_only, method="auto")
        except ArmkitError:
            pass
        self.last_result = None
        self.branches = {}
        self._every = None

    def _build_panels(self) -> None:
        """The language switch, the panels (:mod:`.panels`), the close button, and the page script."""
        from . import page
        from .labels import label
        from .panels import Panels

        gui = self.server.gui
        gui.set_panel_label(label("panel", self.lang, robot=self.robot.name))   # viser's "Connected", in words
        from ...locale.languages import TABLE      # each language's name (and word for "language") in itself

        names = {k: TABLE[k].native for k in LANGUAGES}
        self._lang_dd = gui.add_dropdown(" · ".join(dict.fromkeys(TABLE[k].word for k in LANGUAGES)),
                                         [names[k] for k in LANGUAGES], initial_value=names[self.lang])

        def switched(event: Any) -> None:
            chosen = next(k for k, v in names.items() if v == self._lang_dd.value)
            if event.client is not None and chosen != self.lang:
                threading.Thread(target=self.set_lang, args=(chosen,), daemon=True).start()

        self._lang_dd.on_update(switched)
        self.panels = Panels(self)
        close = gui.add_button(label("close_view", self.lang), color="red")
        close.on_click(lambda e: self._close_from_page() if e.client is not None else None)
        p, r = self.panels, self.robot
        deferred = [page.widget_id(h) for h in (*p.sliders, p.target_xyz, p.target_rpy)]
        steps = {page.widget_id(s): (1.0, 0.1) for s, j in zip(p.sliders, r.joints) if not j.is_prismatic}
        page.install(self.server, deferred, steps)

    def set_lang(self, lang: str) -> None:
        """Show the page's labels in ``lang`` (``"en"`` or ``"ko"``); the arm, the target and the method stay.

        The page's *language* list calls this. Players (tracking, trajectories) stop.
        """
        if lang not in LANGUAGES:
            raise ViewError.of("lang must be one of {names}, got {lang!r}", names=', '.join(LANGUAGES), lang=lang)
        if lang == self.lang:
            return
        self.stop_player()
        with self._lock:
            if self._closed:
                return
            old = self.panels
            self.lang = lang
            with self.server.atomic():
                self.server.gui.reset()
                for node in ("/workspace", "/track"):      # drawn by the old panels; the new ones start without
                    self.server.scene.remove_by_name(node)
                self._build_panels()
                self.panels.set_method(old.method)
                self.panels.set_position_only(old.position_only)
                self.drawing.set_frames_visible(False)
            target, res = self.target, self.last_result
            if not self._following and target is not None and res is not None:
                self.show_configuration(self._q, lambda: self.panels.show_target(target, res, True), follow=False)
            else:
                self.show_configuration(self._q)

    # ------------------------------------------------------------------ scene
    def _setup_scene(self) -> None:
        r, s = self.robot, self.robot.unit_scale
        self.server.scene.set_up_direction("+z")
        # no shadows and no HDRI environment: far cheaper to draw (a laptop without a GPU, SSH, CI),
        # with the default lights doing the shading
        self.server.scene.configure_environment_map(hdri=None)
        self.server.scene.configure_default_lights(enabled=True, cast_shadow=False)
        self.server.gui.configure_theme(control_width="medium", show_share_button=False, show_logo=False)
        R = (r.reach or 1.0) * s
        c, radius = self._arm_sphere()
        cam = self.server.initial_camera
        # fit the arm at its first pose: its bounding sphere fills most of the height of viser's 75 deg view,
        # seen from the front right and above; the view is slid sideways so that the arm sits left of the
        # panels (about a third of a 1000 px wide window)
        direction = np.array([1.5, -1.9, 1.2]) / np.linalg.norm([1.5, -1.9, 1.2])
        distance = 1.25 * radius / math.sin(0.5 * math.radians(75.0))
        right = np.cross(-direction, [0.0, 0.0, 1.0])
        slide = 0.7 * radius * right / np.linalg.norm(right)
        cam.position = tuple(c + distance * direction + slide)
        cam.look_at = tuple(c + slide)
        cam.up = (0.0, 0.0, 1.0)
        self._look = (cam.position, cam.look_at)

        @self.server.on_client_connect
        def _(client: Any) -> None:
            client.camera.up_direction = (0.0, 0.0, 1.0)
            client.camera.position = self._look[0]
            client.camera.look_at = self._look[1]
            client.camera.near = 0.002 * R
            client.camera.far = 100.0 * R

    def _arm_sphere(self) -> tuple[Array, float]:
        """Centre ``(3,)`` and radius (metres) of a sphere around the arm at its first pose and its base."""
        from ...analysis.workspace import skeleton_batch

        r, s = self.robot, self.robot.unit_scale
        pts = skeleton_batch(r, fk_frames(r, self._q)[None])[0] * s
        pts = np.vstack([pts, np.asarray(r.base)[:3, 3] * s])
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        c = 0.5 * (lo + hi)
        thickness = 0.08 * (r.reach or 1.0) * s          # the drawn links, joints and base around the skeleton
        return c, float(np.max(np.linalg.norm(pts - c, axis=1))) + thickness

    # ------------------------------------------------------------------ state
    def _checked_q(self, q: ArrayLike) -> Array:
        r = self.robot
        arr = r.check_q(q)
        if arr.shape != (r.n,):
            raise ShapeError.of("q must have shape ({n},) for robot {robot!r}, got {shape}", n=r.n, robot=r.name,
                                shape=arr.shape)
        bad = r.limit_violations(arr)
        if bad:
            raise JointLimitError.of("joint limit: {details}", details="; ".join(bad))
        return arr.astype(float).copy()

    @property
    def q(self) -> Array:
        """The joint vector shown now, shape ``(n,)`` (rad / length units); a copy."""
        with self._lock:
            return self._q.copy()

    @q.setter
    def q(self, q: ArrayLike) -> None:
        """``v.q = ...`` is :meth:`set_q`."""
        self.set_q(q)

    def show_configuration(self, q: Array, extra: Optional[Callable[[], None]] = None, follow: bool = True) -> None:
        """Draw ``q`` (already checked) and refresh every readout, in one batch.

        The joints, the end pose, the collision state and the target go out together. With
        ``follow`` (the joints were set directly: a slider, a typed joint, ``set_q``, the shell,
        a player) the target gizmo moves to the end pose and the IK status says so, and the
        branch list of the old target is cleared; an IK move passes ``follow=False`` and
        shows its own result in ``extra``.
        """
        with self._lock:
            if self._closed:
                return
            t0 = time.perf_counter()
            self._q = np.array(q, dtype=float)
            F = fk_frames(self.robot, self._q)
            self._following = follow
            if follow:
                self.branches = {}
                self.branch = None
                self._every = None
            with self.server.atomic():
                self.drawing.update(self._q, F)
                self.panels.show_state(self._q, F)
                self.panels.show_collision(self.obstacles.update(self._q, F))
                if follow:
                    self.panels.show_follow(F[-1])
                if extra is not None:
                    extra()
            self.server.flush()      # send now: viser otherwise waits up to 1/60 s to window messages (15 ms measured)
            self.updates += 1
            self.update_ms.append(1e3 * (time.perf_counter() - t0))

    def set_q(self, q: ArrayLike) -> None:
        """Move the arm to ``q`` ``(n,)`` (rad / length units); outside a limit raises JointLimitError."""
        qq = self._checked_q(q)
        self.stop_player()
        self.branch = None
        self.show_configuration(qq)

    def state_numbers(self, q: Optional[Array] = None) -> dict[str, Any]:
        """End point, roll-pitch-yaw (deg), manipulability and condition number of ``q`` (default: now)."""
        qq = self.q if q is None else q
        T = fk(self.robot, qq)
        return {"position": T[:3, 3].copy(), "rpy_deg": rotation_to_rpy(T[:3, :3], degrees=True),
                "manipulability": float(manipulability(self.robot, qq)),
                "condition": float(condition_number(self.robot, qq))}

    # ------------------------------------------------------------------ IK
    def _target_array(self, T: ArrayLike) -> tuple[Array, bool]:
        try:
            t = np.asarray(T, dtype=float)
        except (TypeError, ValueError) as exc:
            raise ShapeError.of("target must be a 4x4 pose or a 3-vector, got {got!r}", got=T) from exc
        if t.shape not in ((4, 4), (3,)):
            raise ShapeError.of("target must be a 4x4 pose or a 3-vector (position only), got shape {shape}",
                                shape=t.shape)
        if not np.all(np.isfinite(t)):
            raise ShapeError.of("target contains NaN or infinite values")
        return t.copy(), t.shape == (3,)

    def _solve(self, T: Array, position_only: bool, method: str) -> IKResult:
        """One IK solve from the current q; fills ``self.branches`` for closed forms."""
        r = self.robot
        tgt = T[:3, 3] if (position_only and T.shape == (4, 4)) else T
        q0 = self.q
        self.branches = {}
        self._every = None
        # a sweep (a 7-joint arm's ik_all: hundreds of rows) is no branch list to drag with: LM answers there
        if method == "auto" and closed_form(r) is not None and self._closed_form.get(tgt.shape == (3,), True):
            try:
                every = ik_all(r, tgt, q0=q0, scene=self._ik_scene_arg())
                self._closed_form[tgt.shape == (3,)] = True
            except IKInputError:
                self._closed_form[tgt.shape == (3,)] = False
            else:
                ok = np.asarray(every.success)
                labels = [str(b) for b in np.asarray(every.branch)]
                self.branches = {lab: np.asarray(every.q)[i].copy() for i, lab in enumerate(labels) if ok[i]}
                self._every = (every, labels)
                return every[0]          # successful branches first, nearest to q0 first
        name = "lm" if method == "auto" else method
        kw: dict[str, Any] = {"restarts": 3, "seed": 0} if name in ("lm", "newton") else {"seed": 0}
        if name in ("ccd", "fabrik") and tgt.shape == (4, 4):
            tgt = tgt[:3, 3]
        return ik(r, tgt, q0=q0, method=name, scene=self._ik_scene_arg(), **kw)  # type: ignore[arg-type]

    def _ik_scene_arg(self) -> Any:
        """The view's collision check as the library's ``scene=`` (False: none)."""
        return False if self.ik_scene is None else self.ik_scene

    def set_target(self, T: ArrayLike, method: Optional[str] = None) -> IKResult:
        """Put the target at ``T`` and move the arm there by IK.

        Parameters
        ----------
        T : array_like, shape (4, 4) or (3,)
            Pose ``T_world_tool``, or a position (position-only IK), in the robot's unit.
        method : {"auto", "lm", "newton", "ccd", "fabrik"}, optional
            Default: the method chosen in the page (``auto``: closed form where the arm has
            one, with every branch listed, else Levenberg-Marquardt warm-started from ``q``).

        Returns
        -------
        IKResult
            The solve. On success the arm moves to ``result.q``; otherwise it stays where it
            was, the target turns red and the page shows ``reason`` and ``message``.
        """
        t, pos_only = self._target_array(T)
        if method is not None and method not in IK_METHODS:
            raise ViewError.of("method must be one of {names}, got {method!r}", names=', '.join(IK_METHODS),
                               method=method)
        self.stop_player()
        if method is not None:
            self.panels.set_method(method)
        self.panels.set_position_only(pos_only)
        return self.update_target(t, pos_only, dragging=False, move_gizmo=True)

    def update_target(self, t: Array, position_only: bool, dragging: bool, move_gizmo: bool) -> IKResult:
        """Solve for the target ``t`` (checked: :meth:`set_target` checks it) with the page's method and show it."""
        method = self.panels.method
        with self._lock:
            q_start = self._q.copy()
            res = self._solve(t, position_only, method)
            self.ik_updates += 1
            self.last_result = res
            self.target = t
            ok = bool(np.asarray(res.success))
            self.branch = str(np.asarray(res.branch)) if ok and self.branches else None
            sweeps = (not dragging and ok is not None and method in ("ccd", "fabrik")
                      and self.panels.show_sweeps)

            def panel() -> None:
                self.panels.show_target(t, res, move_gizmo)

            if ok and not sweeps:
                self.show_configuration(np.asarray(res.q, dtype=float), panel, follow=False)
            else:
                self._following = False
                with self.server.atomic():
                    panel()
                self.server.flush()
        if sweeps:
            self._play_sweeps(t, q_start, method, res)
        return res

    def target_from_page(self, t: Array, position_only: bool, dragging: bool) -> None:
        """A target moved in the page: coalesce fast drags (only the newest pose is solved)."""
        with self._pending_lock:
            self._pending = t
            if self._busy:
                return
            self._busy = True
        try:
            while not self._stop.is_set():
                with self._pending_lock:
                    nxt, self._pending = self._pending, None
                    if nxt is None:
                        self._busy = False
                        return
                self.stop_player()
                self.update_target(nxt, position_only, dragging=dragging, move_gizmo=False)
        finally:
            with self._pending_lock:
                self._busy = False

    def choose_branch(self, label: str) -> None:
        """Jump to the closed-form branch ``label`` of the current target (listed in ``branches``)."""
        if label not in self.branches:
            if not self.branches:
                raise ViewError.of("no branch {label!r} for this target; the branches are none (no closed form)",
                                   label=label)
            raise ViewError.of("no branch {label!r} for this target; the branches are {names}", label=label,
                               names=", ".join(self.branches))
        self.stop_player()
        with self._lock:
            branches, every, t = dict(self.branches), self._every, self.target
            res = every[0][every[1].index(label)] if every is not None and label in every[1] else None
            self.branch = label
            if res is not None:
                self.last_result = res
            if res is None or t is None:
                self.show_configuration(branches[label], follow=False)
                return
            self.show_configuration(branches[label], lambda: self.panels.show_target(t, res, False), follow=False)
            self.branches, self._every, self.branch = branches, every, label


    def _close_from_page(self) -> None:
        """The page's close button: :meth:`wait` returns and the view closes."""
        self._close_reason = self._close_reason or "page"
        self._closing.set()
        threading.Thread(target=self.close, daemon=True, name="armkit-view-close").start()

    def wait(self, timeout: Optional[float] = None) -> str:
        """Serve until the page's *Close the view* button, Ctrl-C, :meth:`close` or ``timeout`` seconds.

        A script that opens a view ends with ``v.wait()``, so that the page keeps working until
        the user is done. The view is closed when this returns (not after a timeout).

        Parameters
        ----------
        timeout : float, optional
            Seconds to wait at most (None: no limit).

        Returns
        -------
        str
            Why it returned: ``"page"`` (the close button), ``"interrupt"`` (Ctrl-C),
            ``"closed"`` (:meth:`close` was called) or ``"timeout"`` (the view stays open).
        """
        deadline = None if timeout is None else time.monotonic() + float(timeout)
        try:
            while not self._closing.is_set():
                left = 0.5 if deadline is None else min(0.5, deadline - time.monotonic())
                if left <= 0:
                    return "timeout"
                self._closing.wait(left)      # short waits: Ctrl-C reaches the main thread between them
        except KeyboardInterrupt:
            self._close_reason = self._close_reason or "interrupt"
            self.close()
            return "interrupt"
        self.close()
        return self._close_reason or "closed"

    def close(self) -> None:
        """Stop the players and the server; the port is free again when this returns."""
        self._closing.set()
        self._close_reason = self._close_reason or "closed"
        with self._close_lock:          # a second caller (wait() after the page's button) returns when it is done
            if self._closed:
                return
            self._stop.set()
            self.stop_player()
            with self._lock:
                self._closed = True
            drop_unopened_connections(self.server)              # a browser's spare connection: 6 s otherwise
            with contextlib.redirect_stdout(io.StringIO()):       # viser's "Server stopped" line
                self.server.stop()
            deadline = time.monotonic() + 5.0
            while not _port_free(self.host, self.port) and time.monotonic() < deadline:
                time.sleep(0.05)

    def __enter__(self) -> "View":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"View({self.robot.name!r}, url={self.url!r})"

    def _repr_html_(self) -> str:
        """Jupyter shows the page inline: an iframe to this server (the kernel's machine must be reachable)."""
        name = html.escape(self.robot.name)
        if self._closed:
            return f"<p>armkit view of {name}: closed</p>"
        url = html.escape(self.url, quote=True)
        return (f'<iframe class="armkit-view" src="{url}" title="armkit view: {name}" width="100%" height="560" '
                f'style="border:1px solid #ccc;border-radius:4px" allow="clipboard-write"></iframe>'
                f'<p style="font-size:0.85em"><a href="{url}" target="_blank">{url}</a></p>')


def view(robot: Robot | str, port: Optional[int] = None, host: str = "127.0.0.1", lang: Optional[str] = None,
         q: ArrayLike | None = None, scene: Any = None, quiet: bool = False) -> View:
    """Open a live 3-D view of ``robot`` in the browser and return its handle.

    Parameters
    ----------
    robot : Robot or str
        A robot, or a bundled robot name / robot file path for :func:`armkit.load`.
    port : int, optional
        TCP port; None picks a free one. A port in use raises :class:`ViewError`.
    host : str
        Address to bind; ``127.0.0.1`` (this machine only) unless you ask otherwise.
    lang : {"en", "ko"}, optional
        Labels' language; default from the locale.
    q : array_like, shape (n,), optional
        First configuration (default: :func:`home_pose`, zeros unless that pose is singular).
    scene : Scene, list of Shape, str, None or False
        The surroundings drawn (translucent; red while the arm overlaps them) and checked by
        the view's IK (the one rule of :func:`armkit.collision.resolve_scene`): ``None`` the
        robot's own (its file's ``[[scene]]``, e.g. the fighter's ground), a
        :class:`armkit.Scene`, a list of shapes, or a scene file; ``armkit.Scene()`` for no
        surroundings (body and self-collision still checked); ``False`` for none drawn and no
        collision check. The robot's body (``[[body]]``, the fighter's torso) is always drawn.
    quiet : bool
        Do not print the address (it is printed once, when the view starts).

    Returns
    -------
    View
        ``.url``, ``.q``, ``set_q``, ``set_target``, ``show_path``, ``wait``, ``close``; in Jupyter
        the handle shows the page inline.
    """
    v = View(robot, port=port, host=host, lang=lang, q=q, scene=scene)
    if not quiet:
        from ...locale import N_, translate

        print(translate(N_("live view: {url}"), v.lang, url=v.url), flush=True)
    return v
