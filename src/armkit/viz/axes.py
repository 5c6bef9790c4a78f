"""Pictures of a chain's joint axes, coloured by the relations that decide its IK class.

:func:`plot_axes` draws each joint axis at q = 0 as a line through its point (the
product-of-exponentials form, :mod:`armkit.ik.geometric.poe`), the links between the points, a
star where a group of axes meets in one point, and one colour per group of parallel axes; the
title is the class name and its solver (:func:`armkit.ik.geometric.classify.classify`).
:func:`class_gallery` draws one panel per class on one figure: the picture in ``docs/ik.md``.

>>> import armkit
>>> fig = plot_axes(armkit.load("puma560")).figure
>>> len(fig.axes[0].lines) >= 6          # one line per joint axis, then the links
True
"""

from __future__ import annotations

from typing import Any, Optional, Sequence, Union

import numpy as np

from ..model import load
from ..ik.geometric.classify import ChainClass, axis_points, classify, common_point
from ..ik.geometric.poe import POE, poe
from ..locale import N_
from ..locale.fonts import plot_text as _
from ..model.robot import Robot
from ._mpl import COLORS, pyplot

__all__ = ["plot_axes", "class_gallery", "random_chain", "GALLERY"]

_PLAIN = "#7f7f7f"   # an axis in no relation
_MEET = "#d62728"    # the star where axes meet


LEGEND = N_("each line is a joint axis at q = 0 (dashed: a sliding joint); one colour: parallel axes; "
            "★ axes that meet in one point; black: the links")
"""The gallery's caption."""


def _form(robot_or_poe: Union[Robot, POE]) -> POE:
    return robot_or_poe if isinstance(robot_or_poe, POE) else poe(robot_or_poe)


def _colours(cls: ChainClass) -> list[str]:
    """One colour per joint: a group of parallel axes shares one; the others are grey."""
    out = [_PLAIN] * cls.n
    for k, group in enumerate(cls.parallel):
        for j in group:
            out[j - 1] = COLORS[(k + 2) % len(COLORS)]
    return out


def plot_axes(robot_or_poe: Union[Robot, POE], ax: Any = None, title: Optional[str] = None) -> Any:
    """Draw the joint axes of a chain at q = 0 and name its class; returns the 3-D axes.

    Parameters
    ----------
    robot_or_poe : Robot or POE
        The chain (a :class:`~armkit.ik.geometric.poe.POE` for an arm that exists only as axes).
    ax : matplotlib 3-D axes, optional
        Drawn into when given; else a new figure.
    title : str, optional
        The first title line (default: the robot's name, or the class name for a bare chain).
    """
    form = _form(robot_or_poe)
    cls = classify(form)
    H, P = np.asarray(form.H, dtype=float), np.asarray(form.P, dtype=float)
    pts = axis_points(P)                                   # (n, 3): a point on each axis
    tip = pts[-1] + P[-1]
    size = float(np.sum(np.linalg.norm(P, axis=1))) or 1.0
    half = 0.18 * size
    if ax is None:
        fig = pyplot().figure(figsize=(4.2, 4.2))
        ax = fig.add_subplot(projection="3d")
    colours = _colours(cls)
    for j in range(cls.n):
        a, b = pts[j] - half * H[j], pts[j] + half * H[j]
        style = "--" if form.prismatic[j] else "-"
        ax.plot(*np.stack([a, b]).T, style, color=colours[j], lw=2.4)
        ax.text(*(b + 0.03 * size * H[j]), str(j + 1), color=colours[j], fontsize=9)
    chain = np.vstack([np.zeros(3), pts, tip])
    ax.plot(*chain.T, color="black", lw=1.0, alpha=0.55, marker="o", ms=2.5)
    for group in cls.intersecting:
        if len(group) == 2 and group[1] - group[0] == 2:
            continue                                       # "always meet" pairs: shown in the title line only
        c, _dist = common_point(H, pts, [g - 1 for g in group])
        ax.scatter(*c, marker="*", s=140, color=_MEET, zorder=5)
    every = np.vstack([chain, pts - half * H, pts + half * H])     # what is drawn: a cube around all of it
    lo, hi = every.min(0), every.max(0)
    mid, span = (lo + hi) / 2, float(np.max(hi - lo)) / 2 or 1.0
    ax.set_xlim(mid[0] - span, mid[0] + span)
    ax.set_ylim(mid[1] - span, mid[1] + span)
    ax.set_zlim(mid[2] - span, mid[2] + span)
    ax.set_xticks([]), ax.set_yticks([]), ax.set_zticks([])
    head = title if title is not None else (robot_or_poe.name if isinstance(robot_or_poe, Robot) else cls.name)
    solver = _("sweep joint {k}", k=cls.locked) if cls.solver.startswith("sweep") else _(cls.solver)
    ax.set_title(f"{head}\n{cls.name}\n{solver}", fontsize=8)
    return ax


def random_chain(seed: int, meet: Sequence[Sequence[int]] = (), parallel: Sequence[Sequence[int]] = ()) -> POE:
    """A random 6R chain (seeded) whose listed groups of axes (0-based) meet in a point or are parallel.

    Every other relation is generic, so the chain's class is decided by the groups alone.
    """
    g = np.random.default_rng(seed)
    H = g.normal(size=(6, 3))
    H /= np.linalg.norm(H, axis=1, keepdims=True)
    for group in parallel:
        H[list(group)] = H[group[0]]
    pts = g.normal(size=(6, 3)) * 0.4
    for group in meet:
        pts[list(group)] = pts[group[0]]
    P = np.vstack([pts[0], np.diff(pts, axis=0), g.normal(size=3) * 0.2])
    return POE(H=H, P=P, R_nT=np.eye(3), prismatic=np.zeros(6, dtype=bool))


GALLERY: tuple[tuple[str, Optional[str], tuple[tuple[int, ...], ...], tuple[tuple[int, ...], ...]], ...] = (
    ("puma560", "puma560", (), ()),
    ("ur5", "ur5", (), ()),
    ("stanford", "stanford", (), ()),
    (N_("spherical wrist, generic"), None, ((3, 4, 5),), ()),
    (N_("two intersecting"), None, ((4, 5),), ()),
    (N_("two parallel"), None, (), ((1, 2),)),
    (N_("general 6R"), None, (), ()),
    ("panda", "panda", (), ()),
    ("cobra600", "cobra600", (), ()),
)
"""The panels of :func:`class_gallery`: (title, bundled robot or None, meeting groups, parallel groups); a panel
without a robot draws :func:`random_chain` with those groups (0-based joints)."""


def class_gallery(seed: int = 3) -> Any:
    """One figure, one panel per class in :data:`GALLERY` (bundled arms and random chains); returns it."""
    plt = pyplot()
    cols = 5
    rows = -(-len(GALLERY) // cols)
    fig = plt.figure(figsize=(16, 3.5 * rows))
    for k, entry in enumerate(GALLERY):
        ax = fig.add_subplot(rows, cols, k + 1, projection="3d")
        title, name, meet, par = entry
        if name is not None:
            plot_axes(load(name), ax=ax)
        else:
            plot_axes(random_chain(seed + k, meet, par), ax=ax, title=_(title))
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    fig.text(0.5, 0.01, _(LEGEND), ha="center", fontsize=9)
    return fig
