"""The view's players: a path, a trajectory, a tracking run or IK sweeps played in a thread.

:class:`Players` is a part of :class:`armkit.viz.view.View` (its base class): a player is a
thread running ``body(token)`` that stops when ``player_alive(token)`` turns False (another
player started, :meth:`~Players.stop_player`, the view closed). The panels
(:mod:`armkit.viz.view.panels`) start and stop players through these public methods.
"""

from __future__ import annotations

import threading
from typing import TYPE_CHECKING, Any, Callable, Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...errors import JointLimitError, ShapeError, ViewError
from ...ik import IKResult, ik

if TYPE_CHECKING:
    from ...model import Robot

__all__ = ["Players", "MAX_SWEEPS"]

Array = NDArray[np.float64]
MAX_SWEEPS = 40              # sweeps animated by "show sweeps"


class Players:
    """The player methods of :class:`armkit.viz.view.View` (a base class; the view holds the state)."""

    if TYPE_CHECKING:     # what the view provides
        robot: Robot
        panels: Any
        _lock: threading.RLock
        _stop: threading.Event
        _player: Optional[threading.Thread]
        _player_token: int

        @property
        def q(self) -> Array: ...

        def show_configuration(self, q: Array, extra: Optional[Callable[[], None]] = None,
                               follow: bool = True) -> None: ...

    def stop_player(self) -> None:
        """Stop the running player (if any) and wait for it (at most 2 s)."""
        with self._lock:
            self._player_token += 1
        th = self._player
        if th is not None and th is not threading.current_thread():
            th.join(timeout=2.0)
        self._player = None

    def start_player(self, body: Callable[[int], None]) -> None:
        """Stop the running player and run ``body(token)`` in a new daemon thread."""
        self.stop_player()
        with self._lock:
            token = self._player_token
        th = threading.Thread(target=body, args=(token,), daemon=True, name="armkit-view-player")
        self._player = th
        th.start()

    def player_alive(self, token: int) -> bool:
        """True while the player started with ``token`` should go on."""
        return token == self._player_token and not self._stop.is_set()

    def player_wait(self, seconds: float) -> bool:
        """Sleep ``seconds`` between a player's frames; returns True at once when the view closes."""
        return self._stop.wait(seconds)

    def _play_sweeps(self, t: Array, q_start: Array, method: str, final: IKResult) -> None:
        p = t[:3, 3] if t.shape == (4, 4) else t
        count = int(min(max(int(np.asarray(final.iterations)), 1), MAX_SWEEPS))

        def body(token: int) -> None:
            for k in range(1, count + 1):
                if not self.player_alive(token):
                    return
                step = ik(self.robot, p, q0=q_start, method=method, max_iterations=k,  # type: ignore[arg-type]
                          restarts=0, seed=0)
                qk = np.asarray(step.q, dtype=float)
                if np.all(np.isfinite(qk)) and self.robot.within_limits(qk):
                    err = float(np.asarray(step.position_error))
                    self.show_configuration(qk, lambda: self.panels.show_sweep(k, count, err), follow=False)
                self._stop.wait(0.12)
            if self.player_alive(token) and bool(np.asarray(final.success)):
                self.show_configuration(np.asarray(final.q, dtype=float),
                                        lambda: self.panels.show_target(t, final, False), follow=False)

        self.start_player(body)

    def show_path(self, path: Any, *, method: str = "ccd", frames: int = 200, seed: int = 0,
                  times: ArrayLike | None = None, fps: float = 20.0, play: bool = True) -> Any:
        """Play a path in the view.

        Parameters
        ----------
        path : array_like shape (m, n), Trajectory, TrackResult or str
            A joint path (rad / length units), a :class:`armkit.motion.trajectory.Trajectory`
            (played against its time stamps, with the time slider), a
            :class:`armkit.viz.tracking.TrackResult`, or a tracking path name
            (``"random"``, ``"circle"``, ``"figure8"``, or a CSV file of x,y[,z] rows)
            that is tracked here with ``method``.
        method : {"ccd", "fabrik", "lm", "newton", "analytic"}
            IK per frame for a tracking path name.
        frames, seed : int
            Frames and seed of a generated tracking path.
        times : array_like, shape (m,), optional
            Time stamps (s) of a joint path; default ``1 / fps`` apart.
        fps : float
            Playback rate (frames per second).
        play : bool
            Start playing now (else paused at the first sample).

        Returns
        -------
        Trajectory or TrackResult
            What is being played.
        """
        from ...motion.trajectory import Trajectory
        from ..tracking import TrackResult, track

        if isinstance(path, str):
            if not 1 <= int(frames) <= 100_000:
                raise ViewError.of("frames must be between 1 and 100000, got {frames!r}", frames=frames)
            res = track(self.robot, path=path, method=method, frames=int(frames), seed=seed, q0=self.q)
            self.panels.play_track(res, fps=fps, play=play)
            return res
        if isinstance(path, TrackResult):
            self.panels.play_track(path, fps=fps, play=play)
            return path
        if isinstance(path, Trajectory):
            traj = path
        else:
            Q = self.robot.check_q(path, "path")
            if Q.ndim != 2 or len(Q) < 1:
                raise ShapeError.of("path must have shape (m, {n}), got {shape}", n=self.robot.n, shape=Q.shape)
            bad = ~self.robot.within_limits(Q)
            if bad.any():
                k = int(np.argmax(bad))
                raise JointLimitError.of("path row {k}: joint limit: {details}", k=k,
                                         details="; ".join(self.robot.limit_violations(Q[k])))
            t = np.arange(len(Q)) / float(fps) if times is None else np.asarray(times, dtype=float)
            if t.shape != (len(Q),) or not np.all(np.isfinite(t)) or np.any(np.diff(t) < 0):
                raise ShapeError.of("times must be {m} increasing finite numbers, got shape {shape}", m=len(Q),
                                    shape=t.shape)
            z = np.zeros_like(Q)
            traj = Trajectory(t=t - t[0], q=Q, qd=z, qdd=z, label="joint path")
        self.panels.play_trajectory(traj, play=play)
        return traj
