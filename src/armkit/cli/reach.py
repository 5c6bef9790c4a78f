"""``armkit reach``: build, show and query reachability maps, and place a base (docs/reachability.md).

Dask, Zarr and matplotlib are imported inside the commands; messages in English or Korean
(``--lang``, default from the locale like ``armkit shell``).
"""

from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import Any, List, Optional

import numpy as np
import typer
from rich.markup import escape
from rich.table import Table

from .._io import atomic_path
from ..spatial import rpy_to_rotation
from .common import (EXIT_FAILED, LANG, NUMERIC_ARGS, N_, _, console, current_language, fail,
                     get_robot, parse_numbers, parse_vector, print_json)
from .common import print_table
from .common import Deg, JsonOut, Lang, RobotArg, Seed, check_lang  # noqa: E402  (the shared options)
from .._extras import require   # optional dependencies, naming the missing extra

__all__ = ["register", "MESSAGES"]

reach_app = typer.Typer(help="Reachability maps: where the arm reaches, in which orientations, where its base "
                             "should go.\n\nExample: armkit reach build ur5 -o ur5.zarr --resolution 0.05",
                        no_args_is_help=True, rich_markup_mode="rich")

MESSAGES: dict[str, str] = {     # English here, Korean in the catalogue (armkit/locale, docs/languages.md)
    "building": N_("building the {robot} map"),
    "built": N_("map written to {path}: {cells} cells, {reachable} reachable, {seconds:.1f} s"),
    "resumed": N_("resuming: {done} of {total} blocks already done"),
    "interrupted": N_("interrupted; run the same command again to resume from {path}"),
    "reachable": N_("reachable"),
    "unreachable": N_("not reachable"),
    "index": N_("reachability index (fraction of orientations)"),
    "picture": N_("picture: {path}"),
    "base_title": N_("best base poses for {k} task poses"),
    "base_none": N_("no candidate base pose reaches any task pose"),
    "summary": N_("reachability map"),
    "ik_check": N_("checked by IK"),
    "by_map": N_("by the map"),
}


def _msg(key: str, lang: str, **kw: Any) -> str:
    from ..locale import translate

    return translate(MESSAGES[key], lang, **kw)


def _lang(lang: Optional[str]) -> str:
    code = check_lang(lang)
    if code is None:
        return current_language()
    LANG["lang"] = code
    return code


def _open_map(path: str) -> Any:
    from ..reach import ReachabilityMap

    return ReachabilityMap.open(path)   # MapFileError is an ArmkitError: one line, exit 2


# ------------------------------------------------------------------ build
@reach_app.command()
def build(robot: RobotArg,
          output: str = typer.Option(..., "-o", "--output", help="Zarr store to write (a folder, e.g. map.zarr)."),
          resolution: Optional[float] = typer.Option(None, "--resolution", help="Voxel edge in the robot's "
                                                     "length unit (default reach/20)."),
          orientations: Optional[int] = typer.Option(None, "--orientations", help="Approach directions per voxel "
                                                     "(default 64; 1 = position only, the default below 6 joints)."),
          rolls: Optional[int] = typer.Option(None, "--rolls", help="Roll bins per direction (default 1 when the "
                                              "last joint rolls the tool freely, else 8)."),
          method: str = typer.Option("fk", "--method", help="fk (sample joint space, default) or ik (IK per cell)."),
          samples: Optional[int] = typer.Option(None, "--samples", help="FK samples in all (default 32 per cell)."),
          seed: Seed = 0,
          coverage: float = typer.Option(0.1, "--coverage", help="A sampled cell is reachable when its sample "
                                         "density is at least this fraction of its densest neighbour (0: any "
                                         "sample)."),
          block_size: Optional[int] = typer.Option(None, "--block-size", help="FK samples per unit of work "
                                                   "(default 1,000,000); IK: x-slabs per unit."),
          scheduler: Optional[str] = typer.Option(None, "--scheduler", help="Dask scheduler, e.g. "
                                                  "tcp://host:8786 (default: ARMKIT_SCHEDULER, else this machine)."),
          workers: Optional[int] = typer.Option(None, "--workers", help="Local worker processes (default: one per "
                                                "CPU; this process on a machine of at most 2 cores)."),
          overwrite: bool = typer.Option(False, "--overwrite", help="Discard an existing map store at --output "
                                         "(only an armkit map store is ever deleted)."),
          dashboard: bool = typer.Option(False, "--dashboard", help="With --workers: serve Dask's dashboard on "
                                         "127.0.0.1 and print its URL."),
          as_json: JsonOut = False,
          lang: Lang = None) -> None:
    """Build a reachability map and write it as a Zarr store (re-running resumes an interrupted build).

    Example: armkit reach build ur5 -o ur5.zarr --resolution 0.05 --orientations 64

    Example: armkit reach build panda -o panda.zarr --scheduler tcp://10.0.0.5:8786
    """
    import time

    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn, \
        TimeRemainingColumn

    from ..reach import reachability

    lg = _lang(lang)
    if method not in ("fk", "ik"):
        fail(_("--method must be fk or ik, got {value!r}", value=method))
    if not output.strip():
        fail(_("--output must name a folder for the Zarr store, e.g. map.zarr"))
    out = Path(output)
    if out.exists() and not out.is_dir():
        fail(_("--output {path!r} exists and is a file; a Zarr store is a folder", path=output))
    if not out.parent.exists() if str(out.parent) else False:
        fail(_("--output: folder {path!r} does not exist", path=str(out.parent)))
    r = get_robot(robot)
    t0 = time.perf_counter()
    bar = Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                   TimeElapsedColumn(), TextColumn(_("ETA")), TimeRemainingColumn(), console=console,
                   disable=as_json, transient=False)
    state: dict[str, Any] = {}

    def progress(done: int, total: int) -> None:
        if "task" not in state:
            state["task"] = bar.add_task(escape(_msg("building", lg, robot=r.name)), total=total, completed=done)
            if done:
                console.print(escape(_msg("resumed", lg, done=done, total=total)))
        bar.update(state["task"], completed=done)

    try:
        with bar:
            m = reachability(r, resolution=resolution, orientations=orientations, rolls=rolls,
                             method=method, samples=samples, seed=seed,  # type: ignore[arg-type]
                             coverage=coverage, block_size=block_size,
                             path=output, overwrite=overwrite, scheduler=scheduler, workers=workers,
                             dashboard=dashboard, progress=progress)
    except KeyboardInterrupt:
        console.print(escape(_msg("interrupted", lg, path=output)))
        raise SystemExit(130) from None
    info = m.summary()
    if as_json:
        print_json({**info, "path": output, "seconds": time.perf_counter() - t0})
        return
    console.print(escape(_msg("built", lg, path=output, cells=f"{info['cells']:,}",
                              reachable=f"{info['reachable_cells']:,}", seconds=time.perf_counter() - t0)))


# ------------------------------------------------------------------ show
def _summary_table(m: Any, lg: str) -> Table:
    t = Table(title=escape(f"{_msg('summary', lg)}: {m.robot.name}"), show_header=False)
    t.add_column("", style="bold")
    t.add_column("")
    for k, v in m.summary().items():
        shown = (_("true") if v else _("false")) if isinstance(v, bool) else \
            f"{v:,}" if isinstance(v, (int, np.integer)) and k != "seed" else v   # counts: 1,000,000
        t.add_row(escape(_(_SUMMARY.get(k, k))), escape(str(shown)))
    return t


_SUMMARY = {"robot": N_("robot"), "unit": N_("unit"), "method": N_("method"), "resolution": N_("voxel size"),
            "voxels": N_("voxels"), "directions": N_("approach directions"), "rolls": N_("roll bins"),
            "orientations": N_("orientations per voxel"), "yaw_symmetric": N_("symmetric about the yaw axis"),
            "cells": N_("cells"), "reachable_cells": N_("reachable cells"), "reachable_voxels": N_("reachable voxels"),
            "samples": N_("samples"), "seed": N_("seed"), "armkit_version": N_("armkit version")}
"""Row labels of the map summary (the keys of ``ReachabilityMap.summary()``, which ``--json`` prints)."""


def _cloud_panel(ax3: Any, m: Any, C: Any, idx: Any, _: Any) -> None:
    """The reach map's third panel: the reachable voxels in 3-D, coloured by index (a yaw-symmetric map revolved)."""
    g, unit = m.grid, m.robot.unit
    sel = idx > 0
    P, V = C[sel], idx[sel]
    if g.symmetric and len(P):     # revolve the half-plane about the axis
        A = g.T_world_A
        local = (P - A[:3, 3]) @ A[:3, :3]
        th = np.linspace(0, 2 * np.pi, 24, endpoint=False)
        pts = np.stack([local[:, 0][:, None] * np.cos(th), local[:, 0][:, None] * np.sin(th),
                        np.repeat(local[:, 2][:, None], len(th), axis=1)], axis=-1).reshape(-1, 3)
        P = pts @ A[:3, :3].T + A[:3, 3]
        V = np.repeat(V, len(th))
    if len(P) > 40_000:
        keep = np.random.default_rng(0).choice(len(P), 40_000, replace=False)
        P, V = P[keep], V[keep]
    ax3.scatter(P[:, 0], P[:, 1], P[:, 2], c=V, cmap="viridis", vmin=0, vmax=1, s=2, alpha=0.5)
    ax3.set_xlabel(f"x ({unit})")
    ax3.set_ylabel(f"y ({unit})")
    ax3.set_zlabel(f"z ({unit})")
    ax3.set_title(_("reachable voxels, coloured by index"))


def _picture(m: Any, path: Path) -> None:
    matplotlib = require("matplotlib", "armkit reach pictures")
    from ..locale.fonts import plot_text as _     # the picture's labels (Korean only with a Korean font)

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    g = m.grid
    idx = m.reachability_index                                  # (nx, ny, nz)
    C = m.voxel_centres()
    unit = m.robot.unit
    fig = plt.figure(figsize=(15, 5))
    ax1 = fig.add_subplot(1, 3, 1)
    if g.symmetric:
        sec = idx[:, 0, :]
        r = np.arange(g.dims[0]) * g.resolution + g.lo[0]
        z = np.arange(g.dims[2]) * g.resolution + g.lo[2]
        full = np.concatenate([sec[::-1], sec], axis=0)
        xs = np.concatenate([-(r[::-1] + g.resolution), r])
        im = ax1.pcolormesh(xs, z, full.T, cmap="viridis", vmin=0, vmax=1, shading="auto")
        ax1.set_title(_("section through the first joint axis (r, z)"))
    else:
        iy = g.dims[1] // 2
        sec = idx[:, iy, :]
        x = np.arange(g.dims[0]) * g.resolution + g.lo[0]
        z = np.arange(g.dims[2]) * g.resolution + g.lo[2]
        im = ax1.pcolormesh(x, z, sec.T, cmap="viridis", vmin=0, vmax=1, shading="auto")
        ax1.set_title(_("section y = 0 (frame of the first joint)"))
    ax1.set_aspect("equal")
    ax1.set_xlabel(f"x ({unit})")
    ax1.set_ylabel(f"z ({unit})")
    fig.colorbar(im, ax=ax1, label=_("reachability index"))
    ax2 = fig.add_subplot(1, 3, 2)
    if g.symmetric:
        prof = idx[:, 0, :].max(axis=1)
        ax2.plot(np.arange(g.dims[0]) * g.resolution + g.resolution / 2, prof)
        ax2.set_xlabel(f"r ({unit})")
        ax2.set_ylabel(_("best index over z"))
        ax2.set_title(_("index against distance from the axis"))
    else:
        iz = int(np.argmax(idx.sum(axis=(0, 1))))
        sec = idx[:, :, iz]
        x = np.arange(g.dims[0]) * g.resolution + g.lo[0]
        y = np.arange(g.dims[1]) * g.resolution + g.lo[1]
        im2 = ax2.pcolormesh(x, y, sec.T, cmap="viridis", vmin=0, vmax=1, shading="auto")
        ax2.set_aspect("equal")
        ax2.set_xlabel(f"x ({unit})")
        ax2.set_ylabel(f"y ({unit})")
        ax2.set_title(_("section z = {z} {unit} (frame of joint 1)", z=f"{g.lo[2] + (iz + 0.5) * g.resolution:.3g}",
                         unit=unit))
        fig.colorbar(im2, ax=ax2, label=_("reachability index"))
    _cloud_panel(fig.add_subplot(1, 3, 3, projection="3d"), m, C, idx, _)
    fig.suptitle(_("{robot}: {n} orientations per voxel, {size} {unit} voxels", robot=m.robot.name, n=g.n_orient,
                    size=f"{g.resolution:g}", unit=unit))
    fig.tight_layout()

    try:
        with atomic_path(path, None, "--output") as tmp:
            fig.savefig(tmp, dpi=110, format=path.suffix.lstrip(".").lower() or None)
    finally:
        plt.close(fig)


@reach_app.command()
def show(map_path: str = typer.Argument(..., metavar="MAP", help="Zarr store written by armkit reach build."),
         output: Optional[str] = typer.Option(None, "-o", "--output", help="Picture (.png, .pdf, .svg): sections "
                                              "and a 3-D view coloured by the reachability index."),
         as_json: JsonOut = False,
         lang: Lang = None) -> None:
    """Summary of a map, and a picture of it.

    Example: armkit reach show ur5.zarr -o reach.png
    """
    lg = _lang(lang)
    out = None
    if output is not None:
        out = Path(output)
        if out.suffix.lower() not in (".png", ".pdf", ".svg"):
            fail(_("--output must end in .png, .pdf or .svg, got {path!r}", path=output))
        if str(out.parent) and not out.parent.is_dir():
            fail(_("--output: folder {path!r} does not exist", path=str(out.parent)))
    m = _open_map(map_path)
    if as_json:
        print_json({**m.summary(), "picture": output})
    else:
        print_table(_summary_table(m, lg))
    if out is not None:
        _picture(m, out)
        if not as_json:
            console.print(escape(_msg("picture", lg, path=str(out))))


# ------------------------------------------------------------------ query
@reach_app.command(context_settings=NUMERIC_ARGS)
def query(map_path: str = typer.Argument(..., metavar="MAP", help="Zarr store written by armkit reach build."),
          xyz: List[str] = typer.Argument(..., metavar="X Y Z", help="Tool position in the robot's length unit."),
          rpy: Optional[str] = typer.Option(None, "--rpy", metavar="R,P,Y",
                                            help="Tool orientation roll pitch yaw (rad, or deg with --deg): "
                                                 "180,0,0 or 180 0 0; default: the identity."),
          deg: Deg = False,
          as_json: JsonOut = False,
          lang: Lang = None) -> None:
    """Is this tool pose reachable? Exit 0 if the map says yes, 1 if no.

    Example: armkit reach query ur5.zarr 0.4 0.1 0.3 --rpy 180,0,0 --deg
    """
    lg = _lang(lang)
    p = parse_numbers(xyz, N_("position"))
    if p.shape != (3,):
        fail(_("position needs 3 numbers X Y Z, got {k}", k=len(p)))
    T = np.eye(4)
    T[:3, 3] = p
    if rpy is not None:
        ang = parse_vector(rpy, 3, "--rpy", "roll pitch yaw")
        T[:3, :3] = rpy_to_rotation(ang, degrees=deg)
    m = _open_map(map_path)
    ok = bool(m.reachable(T))
    idx = float(m.index(p))
    if as_json:
        print_json({"reachable": ok, "index": idx, "position": p, "rotation": T[:3, :3],
                    "position_only": m.grid.position_only})
    else:
        word = _msg("reachable" if ok else "unreachable", lg)
        console.print(f"[{'green' if ok else 'red'}]{escape(word)}[/]  {escape(_msg('index', lg))}: {idx:.3f}")
    if not ok:
        raise SystemExit(EXIT_FAILED)


# ------------------------------------------------------------------ base
def read_tasks(path: str) -> np.ndarray:
    """Task poses from a CSV file: ``x,y,z`` or ``x,y,z,roll,pitch,yaw`` (degrees) per row.

    A first row that is not numbers is a header; blank lines and ``#`` lines are skipped.
    Bad rows exit 2 naming the file, the line and the field.
    """
    p = Path(path)
    if not p.is_file():
        fail(_("task file {path!r} not found", path=path))
    try:
        text = p.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        fail(_("cannot read task file {path!r}: {reason}", path=path, reason=exc))
    rows: list[np.ndarray] = []
    names = ("x", "y", "z", "roll", "pitch", "yaw")
    for lineno, row in enumerate(csv.reader(text.splitlines()), start=1):
        cells = [c.strip() for c in row]
        if not cells or not any(cells) or cells[0].startswith("#"):
            continue
        vals: list[float] = []
        for i, c in enumerate(cells):
            try:
                v = float(c)
            except ValueError:
                if not rows and lineno == 1 or (not rows and all(not _isnum(x) for x in cells)):
                    vals = []
                    break
                fail(_("{path}:{line}: field {field}: {value!r} is not a number", path=path, line=lineno,
                       field=names[i] if i < 6 else i + 1, value=c))
            if not math.isfinite(v):
                fail(_("{path}:{line}: field {field}: {value!r} is not a finite number", path=path, line=lineno,
                       field=names[i] if i < 6 else i + 1, value=c))
            vals.append(v)
        if not vals:
            continue
        if len(vals) not in (3, 6):
            fail(_("{path}:{line}: a task row has 3 (x,y,z) or 6 (x,y,z,roll,pitch,yaw in degrees) numbers, "
                   "got {k}", path=path, line=lineno, k=len(vals)))

        T = np.eye(4)
        T[:3, 3] = vals[:3]
        if len(vals) == 6:
            T[:3, :3] = rpy_to_rotation(vals[3:], degrees=True)
        rows.append(T)
    if not rows:
        fail(_("task file {path!r} has no task rows (x,y,z[,roll,pitch,yaw])", path=path))
    return np.stack(rows)


def _isnum(s: str) -> bool:
    try:
        float(s)
        return True
    except ValueError:
        return False


@reach_app.command()
def base(map_path: str = typer.Argument(..., metavar="MAP", help="Zarr store written by armkit reach build."),
         tasks: str = typer.Argument(..., metavar="TASKS.csv",
                                     help="Task poses, one per row: x,y,z or x,y,z,roll,pitch,yaw (degrees)."),
         top: int = typer.Option(5, "--top", help="How many base poses to check with IK and list."),
         floor_z: float = typer.Option(0.0, "--floor-z", help="Height of the floor plane the base stands on."),
         step: Optional[float] = typer.Option(None, "--step", help="Candidate spacing (default: map resolution)."),
         yaws: Optional[int] = typer.Option(None, "--yaws", help="Base headings tried (default 1 when the map is "
                                            "yaw-symmetric, else 8)."),
         as_json: JsonOut = False,
         lang: Lang = None) -> None:
    """Where to put the base: rank floor positions by how many task poses the arm reaches, checked by IK.

    Example: armkit reach base ur5.zarr tasks.csv --top 3
    """
    from ..reach import base_placement

    lg = _lang(lang)
    if top < 1:
        fail(_("--top must be at least 1, got {value}", value=top))
    if step is not None and not (math.isfinite(step) and step > 0):
        fail(_("--step must be a positive length, got {value}", value=step))
    if yaws is not None and yaws < 1:
        fail(_("--yaws must be at least 1, got {value}", value=yaws))

    T = read_tasks(tasks)
    m = _open_map(map_path)
    best = base_placement(m, T, floor_z=floor_z, step=step, yaws=yaws, top=top)
    rows = [{"x": b.pose[0, 3], "y": b.pose[1, 3], "z": b.pose[2, 3],
             "yaw_deg": math.degrees(math.atan2(b.pose[1, 0], b.pose[0, 0])),
             "map_reached": b.map_count, "ik_reached": b.ik_count, "tasks": len(T)} for b in best]
    if as_json:
        print_json(rows)
    else:
        t = Table(title=escape(_msg("base_title", lg, k=len(T))))
        for h in ("#", f"x ({m.robot.unit})", f"y ({m.robot.unit})", "yaw (deg)", _msg("by_map", lg),

                  _msg("ik_check", lg)):
            t.add_column(escape(h), justify="right")
        for i, r in enumerate(rows, 1):
            t.add_row(str(i), f"{r['x']:.4g}", f"{r['y']:.4g}", f"{r['yaw_deg']:.1f}",
                      f"{r['map_reached']}/{len(T)}", f"{r['ik_reached']}/{len(T)}")
        print_table(t)
    if not best or best[0].ik_count == 0:
        if not as_json:
            console.print(escape(_msg("base_none", lg)))
        raise SystemExit(EXIT_FAILED)


def register(app: typer.Typer) -> None:
    app.add_typer(reach_app, name="reach")
