"""Plots of a trajectory (:class:`armkit.motion.Trajectory`): q(t), qd(t) and the tool path, or a GIF/MP4.

Moved from :mod:`armkit.motion.trajectory` (issue 21): the motion package computes, the viz
package draws. Matplotlib is imported when a function runs (:mod:`armkit._extras` names the
missing extra).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from .._extras import require
from .._io import atomic_path
from ..locale.fonts import plot_language, plot_text as _      # labels in Korean only with a Korean font
from ..locale.library import localize
from ..model.robot import Robot
from ..motion.trajectory import Trajectory

__all__ = ["plot_trajectory", "animate_trajectory"]


def plot_trajectory(traj: Trajectory, robot: Robot | None = None, out_path: str | Path | None = None) -> Any:
    """Three panels: q(t), qd(t) (degrees for revolute joints) and the tool path. Returns the figure."""
    matplotlib = require("matplotlib", "plotting a trajectory")
    if out_path is not None:
        matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    n = traj.q.shape[1]
    prism = robot.prismatic if robot is not None else np.zeros(n, bool)
    names = robot.joint_names if robot is not None else tuple(f"q{i + 1}" for i in range(n))
    conv = np.where(prism, 1.0, 180 / math.pi)
    fig = plt.figure(figsize=(12, 4))
    ax1 = fig.add_subplot(1, 3, 1)
    ax2 = fig.add_subplot(1, 3, 2)
    for j in range(n):
        ax1.plot(traj.t, traj.q[:, j] * conv[j], label=names[j])
        ax2.plot(traj.t, traj.qd[:, j] * conv[j], label=names[j])
    ax1.set(xlabel="t [s]", ylabel="q [deg]" if not prism.any() else _("q [deg | length]"), title=_("joint values"))
    ax2.set(xlabel="t [s]", ylabel="qd [deg/s]", title=_("joint rates"))
    ax1.legend(fontsize=7)
    ax1.grid(alpha=0.3)
    ax2.grid(alpha=0.3)
    unit = robot.unit if robot is not None else ""
    if traj.positions is not None:
        planar = np.allclose(traj.positions[:, 2], traj.positions[0, 2])
        if planar:
            ax3 = fig.add_subplot(1, 3, 3)
            ax3.plot(traj.positions[:, 0], traj.positions[:, 1], "b-", label=_("tool path"))
            if traj.targets is not None:
                ax3.plot(traj.targets[:, 0], traj.targets[:, 1], "r--", lw=1, label=_("desired"))
            ax3.set_aspect("equal", adjustable="datalim")
            ax3.set(xlabel=f"x [{unit}]", ylabel=f"y [{unit}]", title=_("tool path"))
        else:
            ax3 = fig.add_subplot(1, 3, 3, projection="3d")
            ax3.plot(*traj.positions.T, "b-", label=_("tool path"))
            if traj.targets is not None:
                ax3.plot(*traj.targets.T, "r--", lw=1, label=_("desired"))
            ax3.set(xlabel=f"x [{unit}]", ylabel=f"y [{unit}]", zlabel=f"z [{unit}]", title=_("tool path"))
        ax3.legend(fontsize=7)
    fig.suptitle(localize(traj.label, plot_language()))
    fig.tight_layout()
    if out_path is not None:
        with atomic_path(out_path, (".png", ".pdf", ".svg", ".jpg", ".jpeg"), "a picture file") as tmp:
            fig.savefig(tmp, dpi=110, format=Path(out_path).suffix.lower().lstrip("."))
    return fig


def animate_trajectory(traj: Trajectory, robot: Robot, out_path: str | Path, fps: int = 20,
                       title: str | None = None) -> Path:
    """Render ``traj`` as a GIF/MP4 with :func:`armkit.viz.animation.render_animation` (targets drawn)."""
    from .animation import render_animation   # matplotlib/imageio: says which extra is missing (armkit._extras)

    return render_animation(robot, traj.q, out_path, targets=traj.targets, fps=fps, trail=True,
                            title=title or f"{robot.name}: {localize(traj.label, plot_language())}", progress=False)
