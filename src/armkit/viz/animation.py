"""Animations of the arm moving through a sequence of configurations: GIF (Pillow) or MP4 (ffmpeg)."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Optional

import numpy as np
from numpy.typing import ArrayLike

from ..analysis.workspace import skeleton_batch
from .._extras import require
from ..errors import ArgumentError, ShapeError
from ..kinematics import fk_frames
from ..model.robot import Robot
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
        raise ArgumentError(f"animation file must end in .gif or .mp4, got {out.name!r}")
    Q = robot.check_q(q, "q")
    if Q.ndim != 2 or len(Q) == 0:
        raise ShapeError(f"q must have shape (frames, {robot.n}), got {Q.shape}")
    F = len(Q)
    T = None
    if targets is not None:
        T = np.asarray(targets, dtype=float)
        if T.shape != (F, 3):
            raise ShapeError(f"targets must have shape ({F}, 3) to match q, got {T.shape}")
    if not isinstance(fps, (int, np.integer)) or fps < 1:
        raise ArgumentError(f"fps must be a positive integer, got {fps!r}")
    require("matplotlib", "writing an animation")
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from ..analysis.workspace import is_planar
    from .arm import setup_axes

    planar = is_planar(robot)
    fig = Figure(figsize=size, dpi=dpi)
    canvas = FigureCanvasAgg(fig)
    ax = fig.add_subplot(111) if planar else fig.add_subplot(111, projection="3d")
    setup_axes(robot, ax, planar=planar)
    if not planar:
        fig.subplots_adjust(left=0.0, right=0.96, bottom=0.04, top=0.86)
    else:
        fig.subplots_adjust(left=0.13, right=0.97, bottom=0.1, top=0.86)
    frames = fk_frames(robot, Q)                                  # (F, n+1, 4, 4)
    sk = skeleton_batch(robot, frames)                            # (F, m, 3)
    joints = (frames[:, :-1] @ robot.chain.pre)[..., :3, 3]       # (F, n, 3) points on the joint axes
    ends = frames[:, -1, :3, 3]
    dims = (0, 1) if planar else (0, 1, 2)

    def put(artist: Any, pts: np.ndarray) -> None:
        if planar:
            artist.set_data(pts[:, 0], pts[:, 1])
        else:
            artist.set_data_3d(pts[:, 0], pts[:, 1], pts[:, 2])

    empty: list[list[float]] = [[] for _ in dims]
    (trail_line,) = ax.plot(*empty, "-", color="#ff7f0e", lw=1.3, alpha=0.8, label="end-point trail" if trail else None)
    (arm,) = ax.plot(*empty, "-", color=COLORS[0], lw=3.2, solid_capstyle="round", label=robot.name)
    (jts,) = ax.plot(*empty, "o", color="white", mec=COLORS[0], mew=2.0, ms=7)
    (end,) = ax.plot(*empty, "*", color=COLORS[0], mec="black", mew=0.6, ms=13)
    (tgt,) = ax.plot(*empty, "x", color="red", ms=11, mew=2.5, label="target" if T is not None else None)
    if not trail:
        trail_line.set_visible(False)
    if T is None:
        tgt.set_visible(False)
    ax.legend(loc="upper left", fontsize=8, framealpha=0.85)
    fig.suptitle(title or f"{robot.name}", fontsize=11)
    info = fig.text(0.5, 0.895, "", ha="center", fontsize=8, color="0.25")
    dynamic = [trail_line, arm, jts, end, tgt, info]
    for a in dynamic:
        a.set_animated(True)
    canvas.draw()                                   # the static picture once; frames are blitted on it
    background = canvas.copy_from_bbox(fig.bbox)

    from .._io import atomic_path
    from rich.progress import BarColumn, Progress, TextColumn, TimeRemainingColumn

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
            if suffix == ".mp4":
                require("imageio_ffmpeg", "writing MP4")
                imageio = require("imageio.v2", "writing MP4")
                writer = imageio.get_writer(tmp, format="FFMPEG", fps=int(fps), codec="libx264", quality=7,
                                            macro_block_size=8)
            else:
                gif = open(tmp, "wb")
            with bar:
                task = bar.add_task(out.name, total=F)
                for k in range(F):
                    put(arm, sk[k])
                    put(jts, joints[k])
                    put(end, ends[k:k + 1])
                    if trail:
                        put(trail_line, ends[max(0, k - trail_length):k + 1])
                    if T is not None:
                        put(tgt, T[k:k + 1] if np.all(np.isfinite(T[k])) else np.empty((0, 3)))
                    info.set_text(f"frame {k + 1}/{F}: {angle_text(robot, Q[k])}")
                    canvas.restore_region(background)
                    for a in dynamic:
                        if a.get_visible():
                            fig.draw_artist(a)
                    rgb = np.asarray(canvas.buffer_rgba())[..., :3]
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
    return out


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
