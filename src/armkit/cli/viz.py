"""Picture commands: plot, shell, workspace, maps, track (matplotlib is imported inside the commands)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, List, Optional

import numpy as np
import typer

from ..ik import closed_form_family, ik_all
from ..kinematics import fk
from .common import (EXIT_FAILED, NUMERIC_ARGS, console, esc, fail, get_robot, parse_numbers, parse_q, name_list, output_path,
                     checked_line, count, message, parse_vector, print_json, scene_off, scene_option, warn)

from .common import N_, _, current_language  # noqa: E402
from .common import Deg, JsonOut, Lang, NoScene, Picture, RobotArg, Seed, Strict, check_lang  # noqa: E402  (the shared options)
from ..locale.library import localize  # noqa: E402
from .._limits import check_memory  # noqa: E402
from .._text import Fielded  # noqa: E402

from .ik import _explain  # noqa: E402

IMAGE_SUFFIXES = (".png", ".pdf", ".svg", ".jpg")


def _out(path: str, allowed: tuple[str, ...], what: str) -> Path:
    """The output file, checked before any work (suffix, folder, permissions): exit 2 if it cannot be written."""
    return output_path(path, allowed, what)


def plot(robot: RobotArg,
         q: Optional[List[str]] = typer.Argument(None, help="Joint values, one per joint (rad, or deg with --deg).",
                                                 metavar="[Q...]"),
         deg: Deg = False,
         all_branches: Optional[str] = typer.Option(
             None, "--all-branches", metavar="X,Y[,Z]",
             help="Instead of joint values: overlay every closed-form IK branch for this target position "
                  "(100,50,80 or 100 50 80, in the robot's length unit)."),
         output: Picture = 'arm.png',
         no_frames: bool = typer.Option(False, "--no-frames", help="Do not draw the link frames."),
         scene_file: Optional[str] = typer.Option(
             None, "--scene", help="With --all-branches: branches that collide with this scene file (docs/scene.md), "
                                   "the robot's body or itself are not drawn. Default: the robot's own surroundings, "
                                   "if any (the fighter's torso and ground)."),
         no_scene: bool = typer.Option(False, "--no-scene", help="With --all-branches: no collision check."),
         strict: Strict = False) -> None:
    """Draw the arm (3D, or 2D for a planar arm) with its joint frames, and write a picture.

    Example: armkit plot fighter 30 45 60 --deg -o arm.png

    Example: armkit plot fighter --all-branches 100,50,80 -o branches.png
    """
    from ..viz.arm import plot_arm
    from ..viz.plots import save_figure

    r = get_robot(robot)
    out = _out(output, IMAGE_SUFFIXES, "--output")
    if all_branches is not None:
        if q:
            fail(_("give either joint values or --all-branches, not both"))
        from ..analysis.workspace import is_planar

        planar = is_planar(r)
        target = parse_vector(all_branches, (2, 3), "--all-branches", "x y z")
        if len(target) != (2 if planar else 3):
            fail(_("--all-branches needs {form} for robot {robot!r}, got {k} value(s)", form="x,y" if planar else
                   "x,y,z", robot=r.name, k=len(target)))
        scene = scene_option(r, scene_file, no_scene)
        res = ik_all(r, target, scene=scene_off(scene))   # the one collision rule: colliding branches are not drawn
        ok = np.asarray(res.success)
        if not ok.any():
            first = {k: np.asarray(getattr(res, k)).reshape(-1)[0] for k in ("reason", "message", "position_error")}
            if scene is not None:
                message(esc(checked_line(r, scene)))
            fail(_("no branch reaches the target: {reason}", reason=_explain(r, first)), EXIT_FAILED)

        qs = np.asarray(res.q)[ok]
        labels = [str(b) for b in np.asarray(res.branch)[ok]]
        from ..viz._mpl import angle_text

        labels = [f"{b}: {angle_text(r, qq, names=False)}" for b, qq in zip(labels, qs)]
        tp = np.append(target, 0.0) if planar else target
        if planar:
            tp[2] = fk(r, qs[0])[2, 3]
        unit = r.unit
        from ..locale.fonts import plot_text

        title = plot_text(N_("{robot}: {n} IK branches for target ({xyz}) {unit}"), robot=r.name, n=len(qs),
                          xyz=", ".join(f"{v:g}" for v in target), unit=unit)
        fig = plot_arm(r, qs, frames=not no_frames, labels=labels, targets=tp, title=title)
        path = save_figure(fig, out)
        message(_("{n} branch(es): {names}", n=len(qs), names=", ".join(str(b) for b in np.asarray(res.branch)[ok])))
        if scene is not None:
            for b, why, msg in zip(np.asarray(res.branch)[~ok], np.asarray(res.reason)[~ok], np.asarray(res.message)[~ok]):
                if str(why) == "collision":
                    message(_("not drawn: {branch}: {text}", branch=esc(str(b)),
                              text=esc(localize(str(msg), current_language()))))
            message(esc(checked_line(r, scene)))
        console.print(_("wrote {path}", path=esc(path)))
        return
    if not q:
        fail(_("give {n} joint values ({names}) or --all-branches X,Y,Z", n=r.n, names=name_list(r.joint_names)))
    qv = parse_q(r, q, deg, strict)
    fig = plot_arm(r, qv, frames=not no_frames)
    path = save_figure(fig, out)
    console.print(_("wrote {path}", path=esc(path)))


def shell(robot: RobotArg,
          lang: Lang = None,
          no_plot: bool = typer.Option(False, "--no-plot", help="Do not draw the arm after each command."),
          png: bool = typer.Option(False, "--png", help="Write a PNG per step even when a display exists."),
          out_dir: str = typer.Option("out/shell", "--out-dir", help="Folder for the PNG pictures."),
          units: str = typer.Option("deg", "--units", help="Angle units: deg or rad."),
          ik_mode: bool = typer.Option(True, "--ik/--fk", help="Numbers typed alone are an IK target (--ik, the "
                                                               "club's second program) or joint values (--fk); "
                                                               "'mode ik' / 'mode fk' switches inside."),
          view: bool = typer.Option(False, "--view", help="Also serve the live browser view (armkit view) and move "
                                                          "the arm there after every command; no PNGs unless --png.")
          ) -> None:
    """Interactive shell: set joints, move to targets, see the arm after every command.

    Commands inside: theta1 = 30; theta2 = 45 | q 30 45 60 | goto 100 50 80 | [100 50 80] | branch NAME |
    limits | units deg|rad | lang ko|en | help | exit. Nothing typed is evaluated as code.

    Example: armkit shell fighter --lang ko

    Example: armkit shell fighter --ik   (then type 100 50 80: the end point goes there)
    """
    from .shell import Shell

    lang = check_lang(lang)
    if units not in ("deg", "rad"):
        fail(_("--units must be deg or rad, got {value!r}", value=units))
    r = get_robot(robot)
    mode = "none" if no_plot or (view and not png) else ("png" if png else "auto")
    sh = Shell(r, lang=lang, units=units, plot=mode, out_dir=out_dir, console=console, session=True,
               mode="ik" if ik_mode else "fk")
    if view:
        from .view import attach_view

        viewing: Any = attach_view(sh, r, lang)   # a context manager (typed object in cli.view)
        with viewing:
            raise typer.Exit(sh.run())
    raise typer.Exit(sh.run())


def workspace(robot: RobotArg,
              samples: int = typer.Option(200_000, "--samples", "-n", help="Random joint vectors to sample."),
              seed: Seed = 0,
              ground: Optional[float] = typer.Option(None, "--ground", help="Exclude configurations with any link "
                                                                            "point below this z (length units)."),
              box: Optional[List[str]] = typer.Option(
                  None, "--box", metavar="X0,Y0,Z0,X1,Y1,Z1",
                  help="Exclude configurations with a link inside this box (corners; repeatable)."),
              manip: bool = typer.Option(False, "--manipulability", help="Colour the points by manipulability."),
              output: Optional[str] = typer.Option(None, "-o", "--output", help="Picture file (.png, .pdf, .svg)."),
              scene_file: Optional[str] = typer.Option(
                  None, "--scene", help="Scene file (docs/scene.md): drop samples where the arm collides with it, "
                                        "the robot's body or itself. Default: the robot's own surroundings, if any."),
              no_scene: NoScene = False,
              json_out: JsonOut = False) -> None:
    """Sample the reachable workspace: boundaries, volume (area for planar arms) with its error, picture.

    Example: armkit workspace fighter -o ws.png --ground 0
    """
    from ..analysis.workspace import Exclusion, format_measure
    from ..analysis.workspace import workspace as sample

    r = get_robot(robot)
    out = _out(output, IMAGE_SUFFIXES, "--output") if output else None
    if samples < 100:
        fail(_("--samples must be at least 100, got {value}", value=samples))
    if seed < 0:
        fail(_("--seed must be a non-negative integer, got {value}", value=seed))
    boxes = []
    for b in box or []:
        v = parse_vector(b, 6, "--box", "x0 y0 z0 x1 y1 z1")
        lo, hi = np.minimum(v[:3], v[3:]), np.maximum(v[:3], v[3:])
        boxes.append((lo, hi))
    exclusion = Exclusion(ground_z=ground, boxes=tuple(boxes)) if ground is not None or boxes else None
    scene = scene_option(r, scene_file, no_scene)
    ws = sample(r, samples=samples, seed=seed, exclusion=exclusion, manipulability=manip, scene=scene_off(scene))
    data = {"robot": r.name, "unit": r.unit, "samples": ws.samples, "kept": len(ws.points), "excluded": ws.excluded,
            "centre": ws.centre, "outer_radius": ws.outer_radius, "inner_radius": ws.inner_radius,
            "has_inner_boundary": ws.has_inner_boundary, ws.measure_name: ws.volume,
            f"{ws.measure_name}_error": ws.volume_error, "voxel_size": ws.voxel_size,
            "checked_against": list(ws.checked_against)}
    path = None
    if out is not None:
        from ..viz.plots import plot_workspace, save_figure

        path = save_figure(plot_workspace(ws), out)
        data["picture"] = str(path)
    if json_out:
        print_json(data)
        return
    c = ", ".join(f"{v:.4g}" for v in ws.centre)
    body = _("its body and itself")
    why = ([exclusion.describe(r.unit)] if exclusion else []) + (
        [_("collisions with {names}", names=esc(", ".join([s.name for s in scene] + [body])))]
        if scene is not None else [])

    message(_("{robot} workspace from {n} samples ({k} excluded{why})", robot=f"[bold]{esc(r.name)}[/]",
              n=f"{ws.samples:,}", k=f"{ws.excluded:,}", why=(": " + "; ".join(why)) if why else ""))
    console.print("  " + _("outer boundary: {radius} {unit} from the shoulder ({centre})",
                           radius=f"{ws.outer_radius:.4g}", unit=r.unit, centre=c))
    console.print("  " + (_("inner boundary: {radius} {unit}", radius=f"{ws.inner_radius:.4g}", unit=r.unit)
                          if ws.has_inner_boundary else
                          _("inner boundary: none (the end point reaches the shoulder)")))
    console.print("  " + _("{measure}: {value} {unit} (voxel {voxel} {length}; the ± is a bound, see "
                           "docs/visualisation.md)", measure=_(ws.measure_name),
                           value=format_measure(ws.volume, ws.volume_error), unit=ws.measure_unit,
                           voxel=f"{ws.voxel_size:.3g}", length=r.unit))
    if scene is not None:
        message("  " + esc(checked_line(r, scene)))
    if path is not None:
        console.print(_("wrote {path}", path=esc(path)))


def _range(text: str, what: str, scale: float, steps: int) -> np.ndarray:
    """``start:stop`` (``steps`` values) or ``start:stop:step`` (both ends included) as a grid, times ``scale``."""
    parts = [w.strip() for w in text.split(":")]
    if len(parts) not in (2, 3) or not all(parts):
        fail(_("{what} takes start:stop or start:stop:step, got {text!r}", what=what, text=text))
    v = parse_numbers(parts, what)
    if not v[1] > v[0]:
        fail(_("{what}: stop must be larger than start, got {text!r}", what=what, text=text))
    if len(v) == 2:
        return np.linspace(v[0], v[1], steps) * scale
    count = math.floor((v[1] - v[0]) / v[2] + 1e-9) + 1 if v[2] > 0 else 0
    if not 2 <= count <= 2001:
        fail(_("{what}: the step must give 2 to 2001 values from start to stop, got {text!r}", what=what, text=text))
    return (v[0] + v[2] * np.arange(count)) * scale


def _tutorial_layout(r: Any) -> bool:
    """planar2-like arms (two revolute joints in the xy plane) get the symbolic 2-link tutorial's maps by default."""
    from ..analysis.workspace import is_planar

    return r.n == 2 and is_planar(r) and not r.prismatic.any()


def maps(robot: RobotArg,
         output: Picture = 'maps.png',
         steps: int = typer.Option(121, "--steps", help="Grid points per axis (where no :step is given)."),
         joints: Optional[str] = typer.Option(None, "--joints", metavar="I,J",
                                              help="The two joints of the FK maps (1-based; default 1,2 for planar "
                                                   "arms, 2,3 otherwise)."),
         q1: Optional[str] = typer.Option(None, "--q1", metavar="START:STOP[:STEP]",
                                          help="Grid of the first FK joint (deg; length unit if prismatic); "
                                               "planar2 default 0:90, else its limits."),
         q2: Optional[str] = typer.Option(None, "--q2", metavar="START:STOP[:STEP]",
                                          help="Grid of the second FK joint; planar2 default -180:180."),
         x: Optional[str] = typer.Option(None, "--x", metavar="START:STOP[:STEP]",
                                         help="IK target grid along x (length unit); planar2 default 0:1.5:0.01, "
                                              "else the reach around the shoulder."),
         y: Optional[str] = typer.Option(None, "--y", metavar="START:STOP[:STEP]", help="IK target grid along y."),
         branch: Optional[str] = typer.Option(None, "--branch", help="Only this IK branch, named as armkit ik "
                                                                     "names it (elbow-up or elbow-down for planar2, "
                                                                     "front/elbow-up for fighter)."),
         z: Optional[float] = typer.Option(None, "--z", help="Height of the IK target grid for a spatial arm "
                                                             "(default: the shoulder height)."),
         phi: float = typer.Option(0.0, "--phi", help="End angle (deg) of the IK targets of a planar 3R arm."),
         no_ik: bool = typer.Option(False, "--no-ik", help="Only the FK maps.")) -> None:
    """Contour maps (as in the symbolic 2-link tutorial): FK maps over a joint grid, IK maps per branch over a target grid.

    Example: armkit maps planar2 -o maps.png

    Example: armkit maps planar2 --q1 0:90 --q2=-180:180 --x 0:1.5:0.01 --y 0:1.5:0.01 --branch elbow-down
    """
    from ..analysis.maps import fk_maps, ik_maps
    from ..analysis.workspace import is_planar, shoulder_point
    from ..viz.plots import plot_maps, save_figure

    r = get_robot(robot)
    out = _out(output, IMAGE_SUFFIXES, "--output")
    if not 5 <= steps <= 1001:
        fail(_("--steps must be between 5 and 1001, got {steps}", steps=steps))
    if r.n < 2:
        fail(_("maps need at least 2 joints; {name!r} has {n}", name=r.name, n=r.n))
    planar, tutorial = is_planar(r), _tutorial_layout(r)
    if joints is None:
        jj = (0, 1) if planar or r.n == 2 else _parallel_pair(r)
    else:
        v = parse_numbers([w for w in joints.split(",") if w], "--joints")
        if len(v) != 2 or not all(float(x).is_integer() and 1 <= x <= r.n for x in v) or v[0] == v[1]:
            fail(_("--joints needs two different joint numbers in 1..{n}, got {joints!r}", n=r.n, joints=joints))
        jj = (int(v[0]) - 1, int(v[1]) - 1)
    grids = []
    for k, text, what, default in zip(jj, (q1, q2), ("--q1", "--q2"), ("0:90", "-180:180")):
        scale = 1.0 if r.prismatic[k] else math.pi / 180
        if text is None and tutorial:
            text = default
        if text is None:
            lo, hi = r.joints[k].lower, r.joints[k].upper
            lo = lo if math.isfinite(lo) else -math.pi
            hi = hi if math.isfinite(hi) else math.pi
            grids.append(np.linspace(lo, hi, steps))
        else:
            grids.append(_range(text, what, scale, steps))
    ik_grid = None
    if not no_ik:
        from ..ik.analytic.held import position_solver

        if (closed_form_family(r) is None or r.n > 3) and position_solver(r) is None:   # a held wrist: a SCARA
            warn(_("robot {name!r} has no closed-form position IK with named branches; drawing the FK maps only",
                   name=r.name))
        else:
            c, R = shoulder_point(r), r.reach
            span = [f"0:{R:g}:{R / 150:g}"] * 2 if tutorial else [f"{c[i] - R:g}:{c[i] + R:g}" for i in (0, 1)]
            gx = _range(x if x is not None else span[0], "--x", 1.0, steps)
            gy = _range(y if y is not None else span[1], "--y", 1.0, steps)
            needs_phi = closed_form_family(r) == "planar-3r"
            ik_kw: dict[str, Any] = dict(z=z, phi=math.radians(phi) if needs_phi else None,
                                         continuous=_old_branch_name(branch))
            ik_grid = (gx, gy, ik_kw)
    elif branch is not None:
        fail(_("--branch is for the IK maps; drop --no-ik"))
    # before any map is computed: matplotlib's filled contours hold about 80 bytes a grid point of each panel
    # (measured: the fighter's 15 panels of 1001 x 1001 points peaked at 1.3 GB); the maps themselves are computed
    # in bounded chunks (armkit.analysis.maps)
    points = len(grids[0]) * len(grids[1]) * 3
    if ik_grid is not None:   # the IK panels: one per branch and joint (the branches counted on one target)
        probe = ik_maps(r, ik_grid[0][:1], ik_grid[1][:1], **ik_grid[2])
        points += len(ik_grid[0]) * len(ik_grid[1]) * probe.q.shape[-2] * probe.q.shape[-1]
        ik_grid[2]["z"] = probe.z      # a spatial arm's default height (a workspace sample) found once
    check_memory(80.0 * points, Fielded.of("pictures of {points:,} map points", points=points),
                 Fielded.of("use fewer --steps or a larger :step"))
    fm = fk_maps(r, grids[0], grids[1], joints=jj)
    im = None
    if ik_grid is not None:
        im = ik_maps(r, ik_grid[0], ik_grid[1], **ik_grid[2])
        if branch is not None:
            im = _one_branch(im, branch)
    path = save_figure(plot_maps(fm, im), out)
    console.print(_("wrote {path}", path=esc(path)))


def _parallel_pair(r: Any) -> tuple[int, int]:
    """The FK maps' default joints of a spatial arm: its first two consecutive parallel turning axes, the plane
    the tutorial's two links move in (the fighter's and the Puma's 2 and 3, a SCARA's 1 and 2), else 2 and 3."""
    from ..ik.geometric.classify import classify

    for run in classify(r).parallel:
        for a, b in zip(run, run[1:]):
            if not (r.prismatic[a - 1] or r.prismatic[b - 1]):
                return a - 1, b - 1
    return 1, 2


OLD_BRANCH_NAMES = {"q2+": "elbow-down", "q2-": "elbow-up"}
"""The maps' branch names before issue 22 (the sign of q2), and the ``armkit ik`` name they match where x >= 0."""


def _old_branch_name(branch: Optional[str]) -> bool:
    """True for an old map branch name (``q2+``, ``q2-``): the map of that sign of q2 is drawn, with a note giving
    the one name every command uses now. The maps name branches as :func:`armkit.ik_all` does (``IKResult.branch``),
    so that ``armkit maps``, ``ik``, ``plot``, the shell and the view say the same name for the same solution."""
    if branch is None or branch.strip().lower() not in OLD_BRANCH_NAMES:
        return False
    from .common import say

    say(_("note:"), "cyan", _("--branch {old} is the old name (the sign of q2); armkit ik and the maps call this "
                              "branch {name} where x >= 0 (--branch {name})", old=branch.strip(),
                              name=OLD_BRANCH_NAMES[branch.strip().lower()]))
    return True


def _one_branch(im: Any, branch: str) -> Any:
    """The IK maps of one branch: its exact name, or the one name that contains ``branch``."""
    import dataclasses

    names = list(im.branches)
    hits = [b for b in names if b == branch] or [b for b in names if branch.lower() in b.lower()]
    if len(hits) != 1:
        fail(_("--branch must name one of {names}, got {branch!r}", names=name_list(names), branch=branch))
    b = names.index(hits[0])
    return dataclasses.replace(im, q=im.q[:, :, b:b + 1], branches=(hits[0],), reachable=im.reachable[:, :, b:b + 1])


def track(robot: RobotArg,
          path: str = typer.Option("random", "--path", help="random, circle, figure8 or a CSV file of x,y[,z] rows."),
          method: str = typer.Option("ccd", "--method", help="IK per frame: ccd, fabrik, lm, newton or analytic."),
          frames: int = typer.Option(200, "--frames", help="Frames of a generated path."),
          fps: int = typer.Option(20, "--fps", help="Frames per second of the animation."),
          seed: Seed = 0,
          output: Optional[str] = typer.Option("track.gif", "-o", "--output",
                                               help="Animation file: .gif or .mp4 (by extension)."),
          no_animation: bool = typer.Option(False, "--no-animation", help="Only the statistics."),
          scene_file: Optional[str] = typer.Option(
              None, "--scene", help="Scene file (docs/scene.md): frames where the arm collides with it, its body "
                                    "or itself are counted. Default: the robot's own surroundings, if any."),
          no_scene: NoScene = False,
          refuse_collisions: bool = typer.Option(False, "--refuse-collisions",
                                                 help="Exit 1 (and write nothing) when a frame collides."),
          json_out: JsonOut = False) -> None:
    """Target tracking (as in the CCD graphics assignment): a target moves, the arm follows with one warm-started IK step per frame; writes an animation.

    Example: armkit track planar3 --path random --method ccd -o track.gif

    Example: armkit track fighter --path circle --method analytic -o track.mp4
    """
    from ..viz.tracking import PATHS, TRACK_METHODS
    from ..viz.tracking import track as follow

    r = get_robot(robot)
    if method not in TRACK_METHODS:
        fail(_("--method must be one of {choices}; got {value!r}", choices=", ".join(TRACK_METHODS), value=method))
    if path not in PATHS and not Path(path).is_file():
        fail(_("--path must be one of {choices} or an existing CSV file, got {value!r}", choices=", ".join(PATHS),
               value=path))
    if not 2 <= frames <= 5000:
        fail(_("--frames must be between 2 and 5000, got {value}", value=frames))
    if not 1 <= fps <= 120:
        fail(_("--fps must be between 1 and 120, got {value}", value=fps))
    if seed < 0:
        fail(_("--seed must be a non-negative integer, got {value}", value=seed))
    out = None if no_animation or not output else _out(output, (".gif", ".mp4"), "--output")
    scene = scene_option(r, scene_file, no_scene)
    res = follow(r, path=path, method=method, frames=frames, seed=seed, scene=scene_off(scene))
    st = res.stats()
    if res.colliding is not None and res.colliding.any():
        from ..collision import collisions

        k = int(np.argmax(res.colliding))
        st["first_collision"] = {"frame": k, "message": collisions(r, res.q[k], scene).message()}
        if refuse_collisions:
            fail(_("{k} of {n} frames collide; the first, frame {first}: {message} (nothing written)",
                   k=int(res.colliding.sum()), n=len(res.q), first=k,
                   message=localize(st["first_collision"]["message"], current_language())),
                 EXIT_FAILED)
    written = None
    if out is not None:
        from ..viz.animation import render_animation

        from ..locale.fonts import plot_text

        title = plot_text(N_("{robot} follows a {path} target ({method})"), robot=r.name, path=res.path,
                          method=method)
        written = render_animation(r, res.q, out, targets=res.targets, fps=fps, title=title,
                                   progress=not json_out and console.is_terminal, console=console)
        st["animation"] = str(written)
    if json_out:
        print_json(st)
    else:
        u = r.unit
        message(_("{robot} tracking a {path} target with {method}: {n} frames", robot=f"[bold]{esc(r.name)}[/]",
                  path=res.path, method=method, n=count(st["frames"])))
        # why frames were missed: the same counts for every method where the closed form decides (armkit.viz.track)
        parts = [_("reached: {reached}   out of reach: {out}", reached=count(st["frames_reached"]),
                   out=count(st["frames_out_of_reach"]))]
        if st["frames_outside_limits"]:
            parts.append(_("only outside the joint limits: {k}", k=count(st["frames_outside_limits"])))
        if st["frames_every_solution_collides"]:
            parts.append(_("every solution collides: {k}", k=count(st["frames_every_solution_collides"])))
        parts.append(_("not converged: {failed}", failed=count(st["frames_not_converged"])))
        console.print("  " + "   ".join(parts))
        if st["frames_reached"]:
            console.print("  " + _("error on reached frames: mean {mean} {unit}, max {max} {unit} (tolerance {tol} "
                                   "{unit}); worst frame {worst} {unit}", mean=f"{st['mean_error']:.3g}",
                                   max=f"{st['max_error']:.3g}", tol=f"{st['tolerance']:.3g}",
                                   worst=f"{st['max_error_all_frames']:.3g}", unit=u))
        else:
            console.print("  " + _("no frame reached its target (tolerance {tol} {unit}); worst frame {worst} {unit}",
                                   tol=f"{st['tolerance']:.3g}", worst=f"{st['max_error_all_frames']:.3g}", unit=u))
        console.print("  " + _("branch changes: {k}   largest joint step: {step} deg   mean iterations: {iters}",
                               k=st["branch_changes"], step=f"{st['largest_joint_step_deg']:.2f}",
                               iters=f"{st['mean_iterations']:.1f}"))
        if "frames_in_collision" in st:
            first = st.get("first_collision")
            console.print("  " + _("in collision: {k} frames", k=count(st["frames_in_collision"]))
                          + (" " + _("(first: frame {frame}, {message})", frame=first["frame"],
                                     message=esc(localize(first["message"], current_language()))) if first else ""))
        if scene is not None:
            message("  " + esc(checked_line(r, scene)))
        if written is not None:
            console.print(_("wrote {path}", path=esc(written)))
    if st["frames_reached"] < st["frames"] and path in ("circle", "figure8"):
        raise typer.Exit(EXIT_FAILED)


def register(app: typer.Typer) -> None:
    app.command(context_settings=NUMERIC_ARGS)(plot)
    app.command()(shell)
    app.command()(workspace)
    app.command()(maps)
    app.command()(track)


__all__ = ["register", "plot", "shell", "workspace", "maps", "track"]
