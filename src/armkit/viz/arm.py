"""Pictures of the arm: :func:`plot_arm` draws one or several configurations."""

from __future__ import annotations

import math
from typing import Any, Optional, Sequence

import numpy as np
from numpy.typing import ArrayLike

from ..analysis.workspace import is_planar, joint_axes, skeleton
from ..errors import ShapeError
from ..kinematics import fk_frames
from ..model.robot import Robot
from ..locale.fonts import plot_text as _      # the pictures' labels, in Korean only with a Korean font

from ._mpl import AXIS_COLORS, COLORS, angle_text, pyplot

__all__ = ["plot_arm", "draw_arm", "setup_axes"]


def view_box(robot: Robot) -> tuple[np.ndarray, float]:
    """Centre ``(3,)`` and half-width of a box that holds every configuration of the arm."""
    from ..analysis.workspace import shoulder_point

    c = shoulder_point(robot)
    fixed = float(np.linalg.norm(c - robot.base[:3, 3]))
    R = robot.reach - fixed if robot.reach > 2 * fixed else robot.reach
    R = 1.06 * R if R > 0 else 1.0
    return c, R


def setup_axes(robot: Robot, ax: Any = None, planar: Optional[bool] = None, figsize: tuple = (7.0, 6.5)) -> Any:
    """A fresh 2D (planar arm) or 3D axes with equal scaling and axis labels in the robot's unit."""
    plt = pyplot()
    planar = is_planar(robot) if planar is None else planar
    if ax is None:
        fig = plt.figure(figsize=figsize)
        ax = fig.add_subplot(111) if planar else fig.add_subplot(111, projection="3d")
        if not planar:
            fig.subplots_adjust(left=0.0, right=0.95, bottom=0.03, top=0.9)
    c, R = view_box(robot)
    ax.set_xlabel(f"x ({robot.unit})")
    ax.set_ylabel(f"y ({robot.unit})")
    if planar:
        ax.set_xlim(c[0] - R, c[0] + R)
        ax.set_ylim(c[1] - R, c[1] + R)
        ax.set_aspect("equal", adjustable="box")
        ax.grid(True, alpha=0.3)
    else:
        ax.set_zlabel(f"z ({robot.unit})")
        ax.set_xlim(c[0] - R, c[0] + R)
        ax.set_ylim(c[1] - R, c[1] + R)
        ax.set_zlim(c[2] - R, c[2] + R)
        ax.set_box_aspect((1, 1, 1))
    return ax


def draw_arm(ax: Any, robot: Robot, q: np.ndarray, color: str, label: Optional[str], frames: bool,
             index: int = 0, joint_labels: bool = False, alpha: float = 1.0, lw: float = 3.2,
             ls: str = "-") -> None:
    """Draw one configuration ``q`` ``(n,)`` on ``ax`` (2D or 3D).

    Artists carry gids for tests and tools: ``arm:<index>`` (the link polyline),
    ``joints:<index>`` (circles where the joint axes are), ``origins:<index>`` (dots at the
    :func:`armkit.fk_frames` origins, in order) and
    ``end:<index>`` (the end point). With ``frames`` and ``joint_labels`` each frame is labelled
    ``{0}`` ... ``{n}`` (the textbook's frame numbers) with the joint that moves it as a second
    line (``base`` for ``{0}``; ``+ tool`` when the last frame carries a tool offset); frames whose
    origins coincide share one label (``{0} {1}``). Their gid is ``frame-label:<k>`` (``k`` the
    first frame of the label).
    """
    planar = ax.name != "3d"
    F = fk_frames(robot, q)
    pts = skeleton(robot, F)
    org = F[:, :3, 3]
    dims = (0, 1) if planar else (0, 1, 2)
    (line,) = ax.plot(*(pts[:, i] for i in dims), ls, color=color, lw=lw, alpha=alpha,
                      solid_capstyle="round", label=label, zorder=3)
    line.set_gid(f"arm:{index}")
    jp = joint_axes(robot, q)[0]

    (j,) = ax.plot(*(jp[:, i] for i in dims), "o", color="white", mec=color, mew=2.0, ms=8, alpha=alpha, zorder=4)
    j.set_gid(f"joints:{index}")
    (o,) = ax.plot(*(org[:, i] for i in dims), ".", color="black", ms=4, alpha=alpha, zorder=5)
    o.set_gid(f"origins:{index}")
    (e,) = ax.plot(*([org[-1, i]] for i in dims), "*", color=color, mec="black", mew=0.6, ms=14, alpha=alpha,
                   zorder=5)
    e.set_gid(f"end:{index}")
    if frames:
        L = 0.12 * (robot.reach or 1.0)
        for k, T in enumerate(F):
            for a in range(2 if planar else 3):
                seg = np.stack([T[:3, 3], T[:3, 3] + L * T[:3, a]])
                ax.plot(*(seg[:, i] for i in dims), "-", color=AXIS_COLORS[a], lw=1.2, alpha=0.85 * alpha,
                        zorder=2)
    if joint_labels and frames:
        _frame_labels(ax, robot, org, planar)
    elif joint_labels:
        groups: list[tuple[np.ndarray, list[str]]] = [(org[0], ["base"])]
        for name, p in zip(robot.joint_names, jp):
            for g in groups:
                if np.linalg.norm(g[0] - p) < 1e-6 * (robot.reach or 1.0):
                    g[1].append(name)
                    break
            else:
                groups.append((p, [name]))
        end = _("end")
        groups.append((org[-1], [end]))
        off = 0.04 * (robot.reach or 1.0)
        for p, names in groups:
            text = " / ".join(names)
            if planar:
                ax.annotate(text, (p[0], p[1]), xytext=(8, 6) if text == end else (7, -13),
                            textcoords="offset points", fontsize=8, color="0.2")
            else:
                ax.text(p[0] + off, p[1] + off, p[2], text, fontsize=8, color="0.2")


def _frame_labels(ax: Any, robot: Robot, org: np.ndarray, planar: bool) -> None:
    """Label frame ``k`` at its origin ``org[k]`` as ``{k}``, with the joint that moves it on a second line."""
    tool = not np.allclose(robot.tool, np.eye(4))
    groups: list[tuple[np.ndarray, list[int]]] = []
    for k, p in enumerate(org):
        for g in groups:
            if np.linalg.norm(g[0] - p) < 1e-6 * (robot.reach or 1.0):
                g[1].append(k)
                break
        else:
            groups.append((p, [k]))
    off = 0.04 * (robot.reach or 1.0)
    for p, ks in groups:
        names = [_("base") if k == 0 else robot.joint_names[k - 1] for k in ks]
        if tool and ks[-1] == robot.n:
            names[-1] += " + " + _("tool")
        text = " ".join(f"{{{k}}}" for k in ks) + "\n" + " / ".join(names)
        if planar:
            t = ax.annotate(text, (p[0], p[1]), xytext=(7, -22), textcoords="offset points", fontsize=8,
                            color="0.15", linespacing=1.1)
        else:
            t = ax.text(p[0] + off, p[1] + off, p[2], text, fontsize=8, color="0.15", linespacing=1.1)
        t.set_gid(f"frame-label:{ks[0]}")


def plot_arm(robot: Robot, q: ArrayLike, ax: Any = None, frames: bool = True,
             labels: Optional[Sequence[str]] = None, *, title: Optional[str] = None, deg: bool = True,
             targets: Optional[ArrayLike] = None, figsize: tuple = (7.0, 6.5)) -> Any:
    """Draw the arm at one or several configurations.

    Planar arms (every joint axis parallel to z) are drawn in 2D, others in 3D, with equal
    axis scaling and the robot's length unit on the axes.

    Parameters
    ----------
    robot : Robot
    q : array_like, shape (n,) or (k, n)
        One configuration, or ``k`` to overlay (e.g. every IK branch), each in its own
        colour and legend entry.
    ax : matplotlib Axes, optional
        Draw into this axes (3D axes for a spatial arm); a new figure otherwise.
    frames : bool
        Draw each link frame as x/y/z axes (red/green/blue); for an overlay only on the
        first configuration.
    labels : sequence of str, optional
        Legend labels, one per configuration (default: the joint values).
    title : str, optional
        Default: the robot's name and the joint values in degrees.
    deg : bool
        Show revolute joint values in degrees (else radians).
    targets : array_like, shape (3,) or (t, 3), optional
        Points to mark with a red cross (e.g. an IK target).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import numpy as np, armkit
    >>> from armkit.viz import plot_arm
    >>> fig = plot_arm(armkit.load("planar2"), np.radians([30, 45]))
    >>> fig.axes[0].get_xlabel()
    'x (m)'
    """
    Q = robot.check_q(q)
    single = Q.ndim == 1
    Q = Q.reshape(-1, robot.n)
    if labels is not None and len(labels) != len(Q):
        raise ShapeError.of("labels must have one entry per configuration ({n}), got {got}", n=len(Q), got=len(labels))
    ax = setup_axes(robot, ax, figsize=figsize)
    planar = ax.name != "3d"
    shapes: list[np.ndarray] = []
    names: list[str] = []
    for i, qi in enumerate(Q):
        lab = labels[i] if labels is not None else (None if single else angle_text(robot, qi, deg, names=False))
        shape = skeleton(robot, fk_frames(robot, qi))
        same = [names[k] for k, sh in enumerate(shapes)
                if sh.shape == shape.shape and np.allclose(sh, shape, atol=1e-9 * (robot.reach or 1.0))]
        if lab is not None and same:
            short = same[0].split(":")[0]
            lab = _("{label} (same links as {other})", label=lab, other=short)
        shapes.append(shape)
        names.append(lab or "")
        # overlays: each later arm thinner and in another dash pattern, so coinciding arms stay visible
        lw = 3.2 if single else max(1.4, 5.6 - 1.3 * i)
        ls = "-" if single else ("-", "--", "-.", ":")[i % 4]
        draw_arm(ax, robot, qi, COLORS[i % len(COLORS)], lab, frames and i == 0, index=i,
                 joint_labels=single and robot.n <= 4, lw=lw, ls=ls)
    if targets is not None:
        tp = np.asarray(targets, dtype=float).reshape(-1, 3)
        dims = (0, 1) if planar else (0, 1, 2)
        ax.plot(*(tp[:, i] for i in dims), "x", color="red", ms=11, mew=2.5, label=_("target"), zorder=6)
    if title is None:
        if single:
            p = fk_frames(robot, Q[0])[-1, :3, 3]
            end = ", ".join(f"{v:.4g}" for v in (p[:2] if planar else p))
            parts = angle_text(robot, Q[0], deg).split(", ")
            lines = [", ".join(parts[i:i + 3]) for i in range(0, len(parts), 3)]
            title = f"{robot.name}: " + ",\n".join(lines) + "\n" + _("end point ({xyz}) {unit}", xyz=end,
                                                                       unit=robot.unit)
        else:
            title = _("{robot}: {n} configurations", robot=robot.name, n=len(Q))
    ax.set_title(title, fontsize=11)
    if not single or targets is not None or frames:
        from matplotlib.lines import Line2D

        handles, labs = ax.get_legend_handles_labels()
        if frames:
            handles += [Line2D([], [], color=c, lw=1.5) for c in AXIS_COLORS[: 2 if planar else 3]]
            labs += [_("frame {axis}", axis=a) for a in "xyz"][: 2 if planar else 3]

        ax.legend(handles, labs, loc="upper center", bbox_to_anchor=(0.5, -0.1 if planar else -0.02), fontsize=8,
                  ncol=1 if max(map(len, labs), default=0) > 40 else 2, framealpha=0.85)   # below: never on the arm
    return ax.figure
