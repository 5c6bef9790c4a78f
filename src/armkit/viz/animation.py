"""Animations of the arm moving through a sequence of configurations: GIF (Pillow) or MP4 (ffmpeg)."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Optional

import numpy as np
from numpy.typing import ArrayLike

from .._io import atomic_path
from ..analysis.workspace import skeleton_batch
from .._extras import require
from ..errors import ArgumentError, ShapeError
from ..kinematics import fk_frames
from ..model.robot import Robot
from ..locale.fonts import plot_text as _      # the labels, in Korean only with a Korean font
from ._mpl import COLORS, angle_text

__all__ = ["render_animation", "SUFFIXES"]

SUFFIXES = (".gif", ".mp4")


def render_animation(robot: Robot, q: ArrayLike, out_path: str | Path, targets: Optional[ArrayLike] = None,
                     fps: int = 20, trail: bool = True, title: Optional[str] = None, *, progress: bool = True,
                     dpi: int = 80, size: tuple[float, float] = (6.4, 5.6), trail_length: int = 60,
                     console: Any = None) -> Path:
    """Render the arm at each configuration of ``q`` into a GIF or an MP4 file.

    Parameters
    ----------
    robot : Robot
    q : array_like, shape (F, n)
        One configuration per frame (rad / length units).
    out_path : path
        ``.gif`` (written with Pillow) or ``.mp4`` (H.264 through imageio-ffmpeg).
    targets : array_like, shape (F, 3), optional
        A target point per frame, drawn as a red cross (frames where it is NaN show none).
    fps : int
        Frames per second.
    trail : bool
        Draw the path of the end point over the last ``trail_length`` frames.
    title : str, optional
        Figure title (default: the robot's name); the frame number and joint values are
        shown below it.
    progress : bool
        Show a Rich progress bar while rendering.
    dpi, size
        Resolution: ``size`` inches at ``dpi`` (MP4 needs even pixel sizes; the default is
        512 x 448).

    Returns
    -------
    pathlib.Path
        The file written.
    """
    out = Path(out_path)
    suffix = out.suffix.lower()
    if suffix not in SUFFIXES:
        raise ArgumentError.of("animation file must end in .gif or .mp4, got {name!r}", name=out.name)
    Q = robot.check_q(q, "q")
    if Q.ndim != 2 or len(Q) == 0:
        raise ShapeError.of("q must have shape (frames, {n}), got {shape}", n=robot.n, shape=Q.shape)
    T = None
    if targets is not None:
        T = np.asarray(targets, dtype=float)
        if T.shape != (len(Q), 3):
            raise ShapeError.of("targets must have shape ({frames}, 3) to match q, got {shape}", frames=len(Q),
                                shape=T.shape)
    if not isinstance(fps, (int, np.integer)) or fps < 1:
        raise ArgumentError.of("fps must be a positive integer, got {fps!r}", fps=fps)
    stage = _Stage(robot, Q, T, trail, trail_length, title, size, dpi)
    _write_frames(out, stage, int(fps), progress, console)
    return out


class _Stage:
    """The figure of an animation: the static parts drawn once, the moving artists blitted on them per frame."""

    trail_line: Any
    arm: Any
    jts: Any
    end: Any
    tgt: Any

    def __init__(self, robot: Robot, Q: np.ndarray, T: Optional[np.ndarray], trail: bool, trail_length: int,
                 title: Optional[str], size: tuple[float, float], dpi: int) -> None:
        require("matplotlib", "writing an animation")
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        from ..analysis.workspace import is_planar
        from .arm import setup_axes

        self.robot, self.Q, self.T, self.trail, self.trail_length = robot, Q, T, trail, trail_length
        self.planar = planar = is_planar(robot)
        fig = self.fig = Figure(figsize=size, dpi=dpi)
        self.canvas = FigureCanvasAgg(fig)
        ax = fig.add_subplot(111) if planar else fig.add_subplot(111, projection="3d")
        setup_axes(robot, ax, planar=planar)
        if not planar:
            fig.subplots_adjust(left=0.0, right=0.96, bottom=0.04, top=0.86)
        else:
            fig.subplots_adjust(left=0.13, right=0.97, bottom=0.1, top=0.86)
        frames = fk_frames(robot, Q)                                  # (F, n+1, 4, 4)
        self.sk = skeleton_batch(robot, frames)                       # (F, m, 3)
        self.joints = (frames[:, :-1] @ robot.chain.pre)[..., :3, 3]  # (F, n, 3) points on the joint axes
        self.ends = frames[:, -1, :3, 3]
        empty: list[list[float]] = [[] for _ in ((0, 1) if planar else (0, 1, 2))]
        (self.trail_line,) = ax.plot(*empty, "-", color="#ff7f0e", lw=1.3, alpha=0.8,
                                     label=_("end-point trail") if trail else None)
        (self.arm,) = ax.plot(*empty, "-", color=COLORS[0], lw=3.2, solid_capstyle="round", label=robot.name)
        (self.jts,) = ax.plot(*empty, "o", color="white", mec=COLORS[0], mew=2.0, ms=7)
        (self.end,) = ax.plot(*empty, "*", color=COLORS[0], mec="black", mew=0.6, ms=13)
        (self.tgt,) = ax.plot(*empty, "x", color="red", ms=11, mew=2.5, label=_("target") if T is not None else None)
        if not trail:
            self.trail_line.set_visible(False)
        if T is None:
            self.tgt.set_visible(False)
        ax.legend(loc="upper left", fontsize=8, framealpha=0.85)
        fig.suptitle(title or f"{robot.name}", fontsize=11)
        self.info = fig.text(0.5, 0.895, "", ha="center", fontsize=8, color="0.25")
        self.dynamic = [self.trail_line, self.arm, self.jts, self.end, self.tgt, self.info]
        for a in self.dynamic:
            a.set_animated(True)
        self.canvas.draw()                              # the static picture once; frames are blitted on it
        self.background = self.canvas.copy_from_bbox(fig.bbox)

    def _put(self, artist: Any, pts: np.ndarray) -> None:
        if self.planar:
            artist.set_data(pts[:, 0], pts[:, 1])
        else:
            artist.set_data_3d(pts[:, 0], pts[:, 1], pts[:, 2])

    def frame(self, k: int) -> np.ndarray:
        """The RGB picture ``(H, W, 3)`` of frame ``k`` (a view of the canvas: copy it to keep it)."""
        T, ends = self.T, self.ends
        self._put(self.arm, self.sk[k])
        self._put(self.jts, self.joints[k])
        self._put(self.end, ends[k:k + 1])
        if self.trail:
            self._put(self.trail_line, ends[max(0, k - self.trail_length):k + 1])
        if T is not None:
            self._put(self.tgt, T[k:k + 1] if np.all(np.isfinite(T[k])) else np.empty((0, 3)))
        self.info.set_text(_("frame {k}/{n}: {angles}", k=k + 1, n=len(self.Q), angles=angle_text(self.robot,
                                                                                              self.Q[k])))

        self.canvas.restore_region(self.background)
        for a in self.dynamic:
            if a.get_visible():
                self.fig.draw_artist(a)
        return np.asarray(self.canvas.buffer_rgba())[..., :3]


def _write_frames(out: Path, stage: _Stage, fps: int, progress: bool, console: Any) -> None:
    """Stream every frame of ``stage`` into ``out`` (GIF or MP4), with a progress bar."""
    from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

    F = len(stage.Q)
    bar = Progress(TextColumn("rendering {task.description}"), BarColumn(), TextColumn("{task.completed}/{task.total}"),
                   TimeRemainingColumn(), transient=True, disable=not progress, console=console)
    duration = max(1, round(1000 / fps))
    # Frames are streamed to a temporary file next to ``out`` (one frame in memory at a time)
    # and the file is renamed into place at the end: Ctrl-C or an error leaves the old file.
    with atomic_path(out, SUFFIXES, "an animation file") as tmp:
        writer = None
        gif = None
        prev: Optional[np.ndarray] = None
        try:
            if out.suffix.lower() == ".mp4":
                require("imageio_ffmpeg", "writing MP4")
                imageio = require("imageio.v2", "writing MP4")
                writer = imageio.get_writer(tmp, format="FFMPEG", fps=fps, codec="libx264", quality=7,
                                            macro_block_size=8)
            else:
                gif = open(tmp, "wb")
            with bar:
                task = bar.add_task(out.name, total=F)
                for k in range(F):
                    rgb = stage.frame(k)
                    if writer is not None:
                        writer.append_data(np.ascontiguousarray(rgb))
                    else:
                        assert gif is not None
                        _gif_frame(gif, rgb, duration, prev)
                        prev = rgb.copy()
                    bar.advance(task)
            if gif is not None:
                gif.write(b";")                     # GIF trailer
        finally:
            if writer is not None:
                writer.close()
            if gif is not None:
                gif.close()


def _gif_frame(f: Any, rgb: np.ndarray, duration: int, prev: Optional[np.ndarray]) -> None:
    """Append one frame to an open GIF file (the header before the first frame).

    Only the rectangle that changed since ``prev`` is stored (with its own 128-colour
    palette), as Pillow's own writer does, so a streamed GIF is as small as a buffered one.
    """
    require("PIL", "writing a GIF")
    from PIL import GifImagePlugin, Image

    x0 = y0 = 0
    if prev is not None:
        changed = np.any(rgb != prev, axis=-1)
        rows, cols = np.flatnonzero(changed.any(axis=1)), np.flatnonzero(changed.any(axis=0))
        if len(rows) == 0:
            rows, cols = np.array([0]), np.array([0])
        y0, y1, x0, x1 = int(rows[0]), int(rows[-1]) + 1, int(cols[0]), int(cols[-1]) + 1
        rgb = rgb[y0:y1, x0:x1]
    im = Image.fromarray(np.ascontiguousarray(rgb)).quantize(colors=128, method=Image.Quantize.FASTOCTREE)
    if prev is None:
        header, _ = GifImagePlugin.getheader(im, None, {"loop": 0, "duration": duration})
        f.write(b"".join(header))
    for chunk in GifImagePlugin.getdata(im, (x0, y0), duration=duration, include_color_table=True):
        f.write(chunk)
