"""Figures of analysis results: :func:`plot_workspace` and :func:`plot_maps`, and :func:`save_figure`."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Optional

import numpy as np

from .._io import atomic_path
from ..analysis.maps import FKMaps, IKMaps
from ..analysis.workspace import WorkspaceResult
from ..errors import ArgumentError
from ..locale.fonts import plot_text as _      # the pictures' labels, in Korean only with a Korean font
from ._mpl import pyplot

__all__ = ["plot_workspace", "plot_maps", "save_figure", "IMAGE_SUFFIXES"]

IMAGE_SUFFIXES = (".png", ".pdf", ".svg", ".jpg", ".jpeg")



_SUPERSCRIPT = str.maketrans("⁻⁰¹²³⁴⁵⁶⁷⁸⁹", "-0123456789")


def _mathtext_power(text: str) -> str:
    """``× 10⁷`` as matplotlib mathtext ``$\\times 10^{7}$``: a Korean font has no superscript digits (a box
    was drawn for ⁷), mathtext draws the exponent with its own font in every language."""
    head, sep, power = text.rpartition("× 10")
    if not sep or not power:
        return text
    return f"{head}$\\times 10^{{{power.translate(_SUPERSCRIPT)}}}$"

def save_figure(fig: Any, path: str | Path, dpi: int = 110) -> Path:
    """Write ``fig`` to ``path`` (format from the extension), create the folder, close the figure.

    The picture is written to a temporary file in the same folder and renamed into place
    (:func:`armkit._io.atomic_path`): an error or Ctrl-C leaves any old file intact and
    raises :class:`~armkit.errors.WriteError` / :class:`~armkit.errors.WriteInterrupted`.
    """
    out = Path(path)
    try:
        with atomic_path(out, IMAGE_SUFFIXES, "a picture file") as tmp:
            fig.savefig(tmp, dpi=dpi, format=out.suffix.lower().lstrip("."), bbox_inches="tight", pad_inches=0.15)
    finally:
        pyplot().close(fig)
    return out


def _circle(ax: Any, c: tuple[float, float], r: float, **kw: Any) -> None:
    t = np.linspace(0, 2 * math.pi, 361)
    ax.plot(c[0] + r * np.cos(t), c[1] + r * np.sin(t), **kw)


def _boundaries(ax: Any, ws: WorkspaceResult, c: tuple[float, float]) -> None:
    u = ws.unit
    _circle(ax, c, ws.outer_radius, color="black", lw=1.4, ls="--",
            label=_("outer boundary r = {r} {unit}", r=f"{ws.outer_radius:.4g}", unit=u))
    if ws.has_inner_boundary:
        _circle(ax, c, ws.inner_radius, color="#d62728", lw=1.4, ls="--",
                label=_("inner boundary r = {r} {unit}", r=f"{ws.inner_radius:.4g}", unit=u))


def _colouring(ws: WorkspaceResult, idx: np.ndarray) -> tuple[np.ndarray, str]:
    if ws.manipulability is not None:
        return ws.manipulability[idx], _("manipulability w = sqrt(det J Jᵀ)")
    dims = [0, 1] if ws.planar else [0, 1, 2]
    return (np.linalg.norm(ws.points[idx][:, dims] - ws.centre[dims], axis=1),
            _("distance from the shoulder ({unit})", unit=ws.unit))


def plot_workspace(ws: WorkspaceResult, max_points: int = 20_000, seed: int = 0) -> Any:
    """Reach cloud, sections and boundaries of a :func:`armkit.analysis.workspace` result.

    Spatial arm: the 3D cloud, a horizontal section (slab through the shoulder, seen from
    above) and a vertical section (slab through the shoulder in the x-z plane), with the
    inner/outer boundary circles and any exclusion. Planar arm: the cloud in the plane and
    a histogram of the distance from the shoulder. Points are coloured by manipulability
    when the result has it, else by distance.

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = pyplot()
    rng = np.random.default_rng(seed)
    N = len(ws.points)
    idx = rng.choice(N, size=min(N, max_points), replace=False)
    colour, clabel = _colouring(ws, idx)
    P = ws.points[idx]
    u, c = ws.unit, ws.centre
    from ..analysis.workspace import format_measure

    title = _("{robot} workspace: {measure} {value} {unit}  ({kept} of {n} samples kept{excluded})",
              robot=ws.robot.name, measure=_(ws.measure_name), value=_mathtext_power(format_measure(ws.volume, ws.volume_error)),
              unit=ws.measure_unit, kept=f"{len(ws.points):,}", n=f"{ws.samples:,}",
              excluded=_("; excluded: {what}", what=ws.exclusion.describe(u)) if ws.exclusion is not None else "")
    if ws.planar:
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(12.5, 5.8), gridspec_kw={"width_ratios": [1.25, 1]})
        sc = a1.scatter(P[:, 0], P[:, 1], c=colour, s=1.5, cmap="viridis", rasterized=True)
        _boundaries(a1, ws, (c[0], c[1]))
        a1.set_aspect("equal", adjustable="datalim")
        a1.set(xlabel=f"x ({u})", ylabel=f"y ({u})", title=_("reachable end points"))
        a1.legend(loc="upper right", fontsize=8)
        fig.colorbar(sc, ax=a1, label=clabel, shrink=0.85)
        r = np.linalg.norm(ws.points[:, :2] - c[:2], axis=1)
        a2.hist(r, bins=80, color="#1f77b4", alpha=0.8)
        a2.axvline(ws.outer_radius, color="black", ls="--", label=_("outer {r} {unit}", r=f"{ws.outer_radius:.4g}",
                                                                     unit=u))
        if ws.has_inner_boundary:
            a2.axvline(ws.inner_radius, color="#d62728", ls="--", label=_("inner {r} {unit}",
                                                                          r=f"{ws.inner_radius:.4g}", unit=u))
        a2.set(xlabel=_("distance from the shoulder ({unit})", unit=u), ylabel=_("samples"),
               title=_("distance of the samples from the shoulder"))
        a2.legend(fontsize=8)
        fig.suptitle(title, fontsize=11)
        fig.tight_layout()
        return fig
    fig = plt.figure(figsize=(17, 5.8))
    fig.subplots_adjust(left=0.01, right=0.9, wspace=0.32, top=0.86, bottom=0.1)
    a0 = fig.add_subplot(1, 3, 1, projection="3d")
    n3 = max_points // 2
    sc = a0.scatter(P[:n3, 0], P[:n3, 1], P[:n3, 2], c=colour[:n3], s=0.8, cmap="viridis", rasterized=True)
    R = ws.outer_radius * 1.08
    a0.set(xlim=(c[0] - R, c[0] + R), ylim=(c[1] - R, c[1] + R), zlim=(c[2] - R, c[2] + R),
           xlabel=f"x ({u})", ylabel=f"y ({u})", zlabel=f"z ({u})")
    a0.set_title(_("reach cloud"), fontsize=10)
    a0.set_box_aspect((1, 1, 1))
    slab = max(2.0 * ws.voxel_size, 0.02 * ws.outer_radius)
    sections = [(2, (0, 1), _("horizontal section |z - {z}| < {slab} {unit} (from above)", z=f"{c[2]:.4g}",
                              slab=f"{slab:.2g}", unit=u)),
                (1, (0, 2), _("vertical section |y - {y}| < {slab} {unit}", y=f"{c[1]:.4g}", slab=f"{slab:.2g}",
                              unit=u))]
    for k, (axis, (i, j), name) in enumerate(sections):
        ax = fig.add_subplot(1, 3, 2 + k)
        sel = np.abs(ws.points[:, axis] - c[axis]) < slab
        S = ws.points[sel][:max_points]
        col = (ws.manipulability[sel][:max_points] if ws.manipulability is not None
               else np.linalg.norm(S - c, axis=1))
        ax.scatter(S[:, i], S[:, j], c=col, s=1.0, cmap="viridis", rasterized=True,
                   vmin=colour.min(), vmax=colour.max())
        _boundaries(ax, ws, (c[i], c[j]))
        if ws.exclusion is not None:
            _draw_exclusion(ax, ws, i, j)
        ax.set_aspect("equal", adjustable="datalim")
        ax.set(xlabel=f"{'xyz'[i]} ({u})", ylabel=f"{'xyz'[j]} ({u})", title=name)
        ax.title.set_fontsize(9)
        ax.legend(loc="upper right", fontsize=7, framealpha=0.85)
    cax = fig.add_axes((0.92, 0.15, 0.012, 0.65))
    fig.colorbar(sc, cax=cax, label=clabel)
    fig.suptitle(title, fontsize=11)
    return fig


def _draw_exclusion(ax: Any, ws: WorkspaceResult, i: int, j: int) -> None:
    from matplotlib.patches import Rectangle

    ex = ws.exclusion
    assert ex is not None
    if ex.ground_z is not None and j == 2:
        ax.axhline(ex.ground_z, color="#8c564b", lw=2, label=_("ground z = {z} {unit}", z=f"{ex.ground_z:g}",
                                                               unit=ws.unit))
    for b, (lo, hi) in enumerate(ex.boxes):
        ax.add_patch(Rectangle((lo[i], lo[j]), hi[i] - lo[i], hi[j] - lo[j], fill=True, alpha=0.25,
                               color="#8c564b", label=_("body (excluded)") if b == 0 else None))


def _panel(fig: Any, ax: Any, gx: np.ndarray, gy: np.ndarray, Z: np.ndarray, label: str, unit: str, scale: float,
           levels: int) -> None:
    """One contour panel of ``Z`` (shape ``(len(gx), len(gy))``): filled contours with levels and a colour bar
    over the data's own range; a constant panel (spread within ``1e-9 * scale``, rounding noise) as text; an
    empty one (all NaN) as text."""
    finite = Z[np.isfinite(Z)]
    if finite.size == 0:
        ax.text(0.5, 0.5, _("no reachable target"), ha="center", va="center", transform=ax.transAxes)
        return
    if unit == "deg" and _wraps(Z) and not _wraps(np.mod(Z, 360.0)):
        Z = np.mod(Z, 360.0)             # an angle near +-180 deg: drawn over 0..360 deg, continuous
        finite = Z[np.isfinite(Z)]
    lo, hi = float(finite.min()), float(finite.max())
    if hi - lo <= 1e-9 * max(scale, 1e-12):
        value = 0.0 if abs(0.5 * (lo + hi)) <= 1e-9 * max(scale, 1e-12) else 0.5 * (lo + hi)
        ax.pcolormesh(gx, gy, np.where(np.isfinite(Z.T), 0.0, np.nan), cmap="Greys", vmin=-1, vmax=8,
                      shading="nearest")
        ax.text(0.5, 0.5, _("{label} constant = {value} {unit}", label=label, value=f"{value:.6g}", unit=unit),
                ha="center", va="center",
                transform=ax.transAxes, fontsize=10, bbox={"facecolor": "white", "alpha": 0.85, "edgecolor": "0.6"})
        return
    if unit == "deg" and hi - lo > 270 and _wraps(Z):
        # an angle that wraps at +-180 deg (the yaw around the base): a cyclic colour map, cells not contours,
        # so that the wrap draws no seam
        cs = ax.pcolormesh(gx, gy, Z.T, cmap="twilight", vmin=-180, vmax=180, shading="nearest")
        fig.colorbar(cs, ax=ax, label=_("{label} ({unit}, cyclic)", label=label, unit=unit),
                     ticks=[-180, -90, 0, 90, 180])
        return
    lv = np.linspace(lo, hi, levels)
    cs = ax.contourf(gx, gy, Z.T, levels=lv, cmap="viridis")
    ax.contour(gx, gy, Z.T, levels=lv, colors="k", linewidths=0.3, alpha=0.5)
    bar = fig.colorbar(cs, ax=ax, label=f"{label} ({unit})")
    bar.ax.set_ylim(lo, hi)


def _wraps(Z: np.ndarray) -> bool:
    """Neighbouring cells differ by more than 180 deg: the angle wraps around inside the panel."""
    jumps = [np.abs(np.diff(Z, axis=a)) for a in (0, 1)]
    return any(bool(np.nanmax(j, initial=0.0) > 180.0) for j in jumps)


def plot_maps(fk: Optional[FKMaps] = None, ik: Optional[IKMaps] = None, levels: int = 21) -> Any:
    """Contour maps (as in the symbolic 2-link tutorial): FK maps over the joint grid and IK maps per branch.

    One panel per quantity and branch, each with a colour bar in its unit (degrees for
    joint angles, the robot's length unit for positions) that spans the panel's data. The
    FK maps put the first joint on the horizontal axis (the tutorial's layout). A panel
    whose values do not vary (beyond rounding noise, 1e-9 of the reach or of 360 deg) says
    "constant = value" instead of contouring the noise. Unreachable targets are ``NaN`` in
    the data and stay blank.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if fk is None and ik is None:
        raise ArgumentError("plot_maps needs fk maps, ik maps or both")
    plt = pyplot()
    fk_panels: list[tuple[str, np.ndarray]] = []
    if fk is not None:
        fk_panels = [("x", fk.x), ("y", fk.y)]
        if np.ptp(fk.z) > 1e-9 * (fk.robot.reach or 1.0):
            fk_panels.append(("z", fk.z))
    m = 0 if ik is None else ik.q.shape[-2]
    n = 0 if ik is None else ik.q.shape[-1]
    ncols = max(len(fk_panels), n, 1)
    nrows = (1 if fk is not None else 0) + m
    fig, axes = plt.subplots(nrows, ncols, figsize=(4.6 * ncols, 3.9 * nrows), squeeze=False)
    row = 0
    if fk is not None:
        r = fk.robot
        names = [r.joint_names[k] for k in fk.joints]
        g = [np.degrees(v) if not r.prismatic[k] else v for v, k in zip((fk.q1, fk.q2), fk.joints)]
        gu = ["deg" if not r.prismatic[k] else r.unit for k in fk.joints]
        for col, (what, Z) in enumerate(fk_panels):
            ax = axes[0, col]
            _panel(fig, ax, g[0], g[1], Z, what, r.unit, r.reach or 1.0, levels)
            ax.set(xlabel=f"{names[0]} ({gu[0]})", ylabel=f"{names[1]} ({gu[1]})")
            ax.set_title(_("FK: {what}({a}, {b})", what=what, a=names[0], b=names[1]), fontsize=10)
        for col in range(len(fk_panels), ncols):
            axes[0, col].axis("off")
        row = 1
    if ik is not None:
        r = ik.robot
        for b in range(m):
            for k in range(ncols):
                ax = axes[row + b, k]
                if k >= n:
                    ax.axis("off")
                    continue
                Z = ik.q[:, :, b, k]
                unit = r.unit if r.prismatic[k] else "deg"
                Z = Z if r.prismatic[k] else np.degrees(Z)
                _panel(fig, ax, ik.x, ik.y, Z, r.joint_names[k], unit, (r.reach or 1.0) if r.prismatic[k] else 360.0,
                       levels)
                ax.set_aspect("equal", adjustable="box")
                ax.set_xlim(ik.x[0], ik.x[-1])
                ax.set_ylim(ik.y[0], ik.y[-1])
                ax.set(xlabel=f"x ({r.unit})", ylabel=f"y ({r.unit})")
                lab = ik.branches[b]
                if lab[-1:] in "+-" and lab[:-1]:      # a branch named by the elbow's sign (analysis.maps)
                    lab = f"{lab[:-1]} {'≥' if lab[-1] == '+' else '≤'} 0"
                ax.set_title(_("IK {branch}: {joint}(x, y)", branch=lab, joint=r.joint_names[k]), fontsize=9)
    robot = (fk or ik).robot  # type: ignore[union-attr]
    where = _("; IK targets at z = {z} {unit}", z=f"{ik.z:.4g}", unit=robot.unit) if ik is not None and \
        ik.z is not None else ""
    fig.suptitle(_("{robot}: contour maps (blank = out of reach{where})", robot=robot.name, where=where),
                 fontsize=12)

    fig.tight_layout(rect=(0, 0, 1, 0.975))
    return fig
