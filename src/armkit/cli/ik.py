"""The ``armkit ik`` command: every closed-form branch as a table, or one numeric solution."""

from __future__ import annotations

import math
from typing import Any, List, Optional

import numpy as np
import typer
from rich.table import Table

from ..errors import ArmkitError
from ..ik import ik as solve, ik_all
from ..ik.api import _analytic_solver
from ..spatial import make_pose, quaternion_to_rotation, rpy_to_rotation
from .common import (EXIT_BAD_INPUT, EXIT_FAILED, NUMERIC_ARGS, N_, _, console, esc, fail, get_robot, parse_numbers,
                     checked_line, message, parse_vector, print_json, scene_off, scene_option, warn)

from ..locale import SOURCE, current_language  # noqa: E402
from .common import print_table  # noqa: E402
from .common import Deg, JsonOut, NoScene, RobotArg  # noqa: E402  (the shared options)
METHOD_CHOICES = ("auto", "analytic", "lm", "newton", "ccd", "fabrik")


def _target(robot, coords: List[str], rpy, quat, deg: bool, phi: Optional[float]):
    """(target array, phi in rad or None, a short description) from the command-line words."""
    p = parse_numbers(coords, N_("target coordinates"))
    if len(p) not in (2, 3):
        fail(_("give the target as X Y (planar arms) or X Y Z in {unit}; got {k} number(s)", unit=robot.unit,
               k=len(p)))
    if rpy is not None and quat is not None:
        fail(_("give the orientation with --rpy or with --quat, not both"))
    where = "(" + ", ".join(f"{v:g}" for v in p) + f") {robot.unit}"
    if len(p) == 2:
        if rpy is not None or quat is not None:
            fail(_("--rpy/--quat need X Y Z; for a planar arm give the end angle with --phi"))
        if phi is None:
            return p, None, where
        ph = math.radians(phi) if deg else phi
        return p, ph, where + _(", end angle {angle} deg", angle=f"{math.degrees(ph):g}")
    if phi is not None:
        fail(_("--phi is the end angle of a planar X Y target; with X Y Z use --rpy or --quat"))
    if rpy is not None:
        R = rpy_to_rotation(np.array(rpy, dtype=float), degrees=deg)
        shown = np.array(rpy) if deg else np.degrees(rpy)
        return make_pose(R, p), None, where + ", roll/pitch/yaw (" + ", ".join(f"{v:g}" for v in shown) + ") deg"
    if quat is not None:
        qv = np.array(quat, dtype=float)
        if not np.all(np.isfinite(qv)) or np.linalg.norm(qv) < 1e-12:
            fail(_("--quat must be a non-zero quaternion x y z w, got {value}", value=tuple(quat)))
        return (make_pose(quaternion_to_rotation(qv / np.linalg.norm(qv)), p), None,
                where + _(", quaternion ({xyzw})", xyzw=", ".join(f"{v:g}" for v in qv)))
    return p, None, where + _(" (position only)")


def _rows(robot, res) -> list[dict]:
    q = np.atleast_2d(res.q)
    fields = [np.atleast_1d(np.asarray(getattr(res, f))) for f in
              ("success", "position_error", "rotation_error", "iterations", "branch", "within_limits", "reason",
               "message")]
    out = []
    for k in range(len(q)):
        s, dp, dr, it, br, wl, rs, msg = (f[k] for f in fields)
        out.append({"branch": str(br), "success": bool(s), "q_rad": q[k] + 0.0,
                    "q_deg": np.where(robot.prismatic, q[k], np.degrees(q[k])) + 0.0,
                    "position_error": float(dp), "rotation_error": float(dr), "within_limits": bool(wl),
                    "reason": str(rs), "message": str(msg), "iterations": int(it)})
    return out


def _deg(v: float) -> str:
    return f"{0.0 if abs(v) < 5e-5 else v:.4f}"


def _table(robot, rows: list[dict], title: Optional[str], position_only: bool, compact: bool = False) -> Table:
    """The branches as a table: joint names as headers (the units are in the title), numbers never wrapped.

    Text columns (branch, result) are cut with an ellipsis rather than wrapped; the rotation
    error of a position target (always 0) is left out. ``compact``: no outer edge and no
    vertical lines, and no limits column when every branch is within them, for narrow terminals.
    """
    from rich import box

    t = Table(title=title, header_style="bold", box=box.SIMPLE_HEAD if compact else box.HEAVY_HEAD,
              show_edge=not compact, pad_edge=not compact)
    limits = not compact or not all(r["within_limits"] for r in rows)   # compact: no column of all "ok"
    t.add_column(_("branch"), no_wrap=True, overflow="ellipsis", min_width=6)
    for name in robot.joint_names:
        t.add_column(esc(name), justify="right", no_wrap=True)
    t.add_column(_("pos. error"), justify="right", no_wrap=True)
    if not position_only:
        t.add_column(_("rot. error"), justify="right", no_wrap=True)
    if limits:
        t.add_column(_("limits"), justify="center", no_wrap=True)
    t.add_column(_("result"), no_wrap=True, overflow="ellipsis", min_width=6)
    for r in rows:
        result = "[green]" + _("solved") + "[/]" if r["success"] else "[red]" + esc(_(r["reason"])) + "[/]"
        t.add_row(esc(r["branch"]), *(_deg(v) for v in r["q_deg"]), f"{r['position_error']:.1e}",
                  *(() if position_only else (f"{math.degrees(r['rotation_error']):.1e}",)),
                  *((_("ok") if r["within_limits"] else "[red]" + _("no") + "[/]",) if limits else ()), result)

    return t


def _units_title(robot, title: str, position_only: bool) -> str:
    """``title`` followed by the units of the table's columns (kept out of the headers so that they stay short)."""
    ang = _("joint angles in deg") if not robot.prismatic.any() else _("joints in deg or {unit}", unit=robot.unit)
    rot = "" if position_only else _(", rotation error in deg")
    return _("{title}; {angles}, position error in {unit}{rotation}", title=title, angles=ang, unit=robot.unit,
             rotation=rot)


def _records(robot, rows: list[dict], title: str, position_only: bool, width: int) -> Any:
    """The branches one record each (for terminals too narrow for the table): every number whole."""
    from rich.console import Group
    from rich.text import Text

    lines: list[Any] = [Text.from_markup(title, style="bold")]
    for r in rows:
        head = Text.assemble((r["branch"], "bold"), ": ",
                             (_("solved"), "green") if r["success"] else (_(r["reason"]), "red"),
                             "" if r["within_limits"] or r["reason"] == "joint limits"
                             else ("  " + _("(outside the joint limits)"), "red"))
        lines.append(head)
        items = [f"{name} {_deg(v)}{' ' + robot.unit if pris else '°'}"
                 for name, v, pris in zip(robot.joint_names, r["q_deg"], robot.prismatic)]
        items.append(_("position error {error} {unit}", error=f"{r['position_error']:.1e}", unit=robot.unit))
        if not position_only:
            items.append(_("rotation error {error}°", error=f"{math.degrees(r['rotation_error']):.1e}"))
        line = "  "
        for item in items:          # wrap between items, never inside one
            if line.strip() and len(line) + 2 + len(item) > width:
                lines.append(Text(line.rstrip()))
                line = "  "
            line += item + "  "
        lines.append(Text(line.rstrip()))
    return Group(*lines)


def _print_rows(robot, rows: list[dict], title: str, position_only: bool) -> None:
    """The branches as the widest layout that fits: a table, a compact table, or one record per branch."""
    from .common import SafeConsole, natural_width, out_width

    width = out_width()
    out = console if width == console.width else SafeConsole(highlight=False, width=width)
    full = _units_title(robot, title, position_only)
    for compact in (False, True):
        if natural_width(_table(robot, rows, None, position_only, compact)) <= width:
            out.print(_table(robot, rows, full, position_only, compact))
            return
    out.print(_records(robot, rows, title, position_only, width), soft_wrap=False)


def _trace_table(trace) -> Table:
    tr = np.asarray(trace, dtype=float)
    if tr.ndim == 2 and tr.shape[0] == 1:
        tr = tr[0]
    t = Table(title=_("iterations (error after each step)"), header_style="bold")
    t.add_column(_("iteration"), justify="right")
    if tr.ndim == 1:
        t.add_column(_("error"), justify="right")
        for i, v in enumerate(tr):
            if np.isfinite(v):
                t.add_row(str(i + 1), f"{v:.3e}")
    else:
        for j in range(tr.shape[1]):
            t.add_column(_("error {k}", k=j + 1), justify="right")
        for i, row in enumerate(tr):
            t.add_row(str(i + 1), *(f"{v:.3e}" for v in row))
    return t


def _partial_target(r, target, where: str, pitch: Optional[float], direction, deg: bool, method: str,
                    seed: Optional[int], json_out: bool, scene: Any = None) -> None:
    """``--pitch`` (every closed-form branch) or ``--direction`` (LM): a position plus part of an orientation."""
    if target.ndim != 1 or len(target) != 3:
        fail(_("--pitch and --direction go with an X Y Z position (no --rpy/--quat/--phi)"))
    if pitch is not None and direction is not None:
        fail(_("give --pitch or --direction, not both"))
    if pitch is not None:
        p = math.radians(pitch) if deg else pitch
        where += _(", tool pitch {angle} deg", angle=f"{math.degrees(p):g}")
        if method in ("auto", "analytic"):
            res, used = ik_all(r, target, pitch=p, scene=scene_off(scene)), _("closed form (position + pitch)")
        else:
            res, used = solve(r, target, method=method, pitch=p, seed=seed,  # type: ignore[arg-type]
                              scene=scene_off(scene)), method
    else:
        d = np.asarray(direction, dtype=float)
        if not np.all(np.isfinite(d)) or np.linalg.norm(d) == 0:
            fail(_("--direction must be a non-zero finite vector, got {value}", value=tuple(float(v) for v in d)))
        where += _(", tool z along ({xyz})", xyz=", ".join(f"{v:g}" for v in d))
        from ..ik.partial import _pitch_solver

        if method in ("auto", "analytic") and _pitch_solver(r) is not None:   # a yaw-pitch3 arm: every branch
            res, used = ik_all(r, target, direction=d, scene=scene_off(scene)), _("closed form (position + direction)")
        else:
            res = solve(r, target, method="lm" if method in ("auto", "analytic") else method, direction=d,  # type: ignore[arg-type]
                        seed=seed, scene=scene_off(scene))
            used = _("lm (position + direction)")
    rows = _rows(r, res)
    solved = any(row["success"] for row in rows)
    if json_out:
        print_json({"robot": r.name, "unit": r.unit, "method": used, "target": np.asarray(target),
                    "solved": solved, "solutions": rows, "checked_against": list(res.checked_against)})
    else:
        _print_rows(r, rows, _("IK of {robot} for {target}, {method}", robot=esc(r.name), target=esc(where),
                               method=used), False)
        if scene is not None:
            message(esc(checked_line(r, scene)))
        if solved and len(rows) > 1:
            console.print(_("{k} of {n} branches solve the target.", k=sum(row["success"] for row in rows),
                            n=len(rows)))
    if not solved:
        fail(_explain(r, rows[0]), EXIT_FAILED)


def _fixed_values(robot, words: List[str], deg: bool) -> Optional[dict]:
    """``--fixed NAME=VALUE`` (repeated) as ``{name: value}`` in rad (lengths for a prismatic joint), or None."""
    out: dict = {}
    for word in words:
        name, eq, text = word.partition("=")
        name = name.strip()
        if not eq or not name:
            fail(_("--fixed takes NAME=VALUE (e.g. {example}), got {value!r}",
                   example=f"{robot.joint_names[-1]}=0.5", value=word))
        value = parse_numbers([text], N_("--fixed value"))
        if len(value) != 1:
            fail(_("--fixed takes one number after {name}=, got {value!r}", name=name, value=text))
        if name in out:
            fail(_("--fixed names joint {name} twice", name=name))
        k = robot.joint_names.index(name) if name in robot.joint_names else -1
        out[name] = math.radians(value[0]) if deg and not (k >= 0 and robot.prismatic[k]) else float(value[0])
    return out or None


def _locked(r, target, where: str, fixed: Optional[dict], sweep: Optional[int], json_out: bool, scene: Any) -> None:
    """``--sweep`` / ``--fixed`` (a 7-joint arm): every verified branch of :func:`armkit.ik_all` with held or swept
    joints, the swept joint's value first; exit 1 when none is found."""
    from ..ik.geometric.locked import DEFAULT_SWEEP, resolve

    position_only = np.ndim(target) == 1
    res = ik_all(r, target, fixed=fixed, sweep=sweep, scene=scene_off(scene))
    solver = resolve(r, fixed, sweep, position_only)
    swept = getattr(solver, "swept", None)
    every = _rows(r, res)
    rows = [every[i] for i in np.flatnonzero(np.atleast_1d(res.success))]
    if swept is not None:   # in the order of the swept value (stable: nearest q = 0 first among equals)
        rows.sort(key=lambda row: float(row["q_rad"][swept[0]]))
    shown = lambda k, v: v if r.prismatic[k] else math.degrees(v)  # noqa: E731
    unit = lambda k: r.unit if r.prismatic[k] else "deg"  # noqa: E731
    if swept is not None:
        k, values = swept
        what = _("{joint} swept over {count} values from {lo} to {hi} {unit}", joint=r.joint_names[k],
                 count=f"{len(values):,}", lo=f"{shown(k, float(values[0])):.4g}",
                 hi=f"{shown(k, float(values[-1])):.4g}", unit=unit(k))
    else:
        held = ", ".join(f"{nm} = {shown(r.joint_names.index(nm), v):.6g} {unit(r.joint_names.index(nm))}"
                         for nm, v in (fixed or {}).items())
        what = _("held: {joints}", joints=held)
    found = _("{what}; branches found: {count} (each checked by FK).", what=what, count=f"{len(rows):,}")
    if json_out:
        print_json({"robot": r.name, "unit": r.unit, "method": getattr(solver, "family", ""),
                    "target": np.asarray(target), "swept": None if swept is None else {
                        "joint": r.joint_names[swept[0]], "values": len(swept[1]),
                        "from_rad": float(swept[1][0]), "to_rad": float(swept[1][-1])},
                    "fixed_rad": fixed, "solved": bool(rows), "branches_found": len(rows), "solutions": rows})
    elif rows:
        from .common import SafeConsole, out_width

        order = ([swept[0]] if swept is not None else []) + list(range(r.n))
        t = Table(title=_("IK of {robot} for {target}; joint angles in deg, position error in {unit}, rotation error "
                          "in deg", robot=esc(r.name), target=esc(where), unit=r.unit), show_lines=False)
        for j, k in enumerate(order):
            t.add_column(_("swept {joint}", joint=esc(r.joint_names[k])) if (j == 0 and swept is not None)
                         else esc(r.joint_names[k]), justify="right", no_wrap=True)
        t.add_column(_("position error"), justify="right", no_wrap=True)
        t.add_column(_("rotation error"), justify="right", no_wrap=True)
        for row in rows:
            t.add_row(*[_deg(float(row["q_deg"][k])) for k in order], f"{row['position_error']:.1e}",
                      f"{math.degrees(row['rotation_error']):.1e}")
        width = max(out_width(), 80)
        SafeConsole(highlight=False, width=max(width, 12 * (len(order) + 2))).print(t)
    if not rows:
        first = every[0] if every else None
        why = "" if first is None else _explain(r, first)
        fail(_("no branch found ({what}){why}", what=what, why=f": {why}" if why else ""), EXIT_FAILED)
    if json_out:
        return
    message(esc(found))
    if sweep is None and swept is not None and len(swept[1]) == DEFAULT_SWEEP:
        message(_("(--sweep N takes more values of {joint}; --fixed NAME=VALUE holds joints at your values)",
                  joint=r.joint_names[swept[0]]))


def ik(robot: RobotArg,
       coords: List[str] = typer.Argument(..., help="Target position X Y [Z] in the robot's unit.", metavar="X Y [Z]"),
       rpy: Optional[str] = typer.Option(
           None, "--rpy", metavar="R,P,Y", help="Target orientation roll pitch yaw (R = Rz(y) Ry(p) Rx(r); rad, or "
                                               "deg with --deg): 180,0,0 or 180 0 0."),
       quat: Optional[str] = typer.Option(
           None, "--quat", metavar="X,Y,Z,W", help="Target orientation as a quaternion x y z w (scalar last)."),
       deg: Deg = False,
       method: str = typer.Option("auto", "--method",
                                  help="auto (closed form when the arm has one, else lm), analytic, lm, newton, "
                                       "ccd or fabrik."),
       branch: Optional[str] = typer.Option(None, "--branch", help="Only this closed-form branch, e.g. elbow-up."),
       all_branches: bool = typer.Option(False, "--all", help="Every closed-form branch (the default when the "
                                                              "arm has a closed form)."),
       seed: Optional[int] = typer.Option(None, "--seed", help="Random seed of the numeric restarts."),
       phi: Optional[float] = typer.Option(None, "--phi", help="End angle of a planar arm for an X Y target."),
       pitch: Optional[float] = typer.Option(None, "--pitch", help="Tool pitch for an X Y Z target of a yaw + "
                                             "three pitch joints arm such as the SO-101 (0 level, -90 straight "
                                             "down; rad, or deg with --deg): every closed-form branch."),
       direction: Optional[str] = typer.Option(
           None, "--direction", metavar="DX,DY,DZ", help="Point the tool's z axis along DX DY DZ at an X Y Z target (rotation about it "
                                     "free; closed form on a yaw + three pitch joints arm such as the SO-101, "
                                     "else numeric): what a 5-joint arm can do instead of a full pose."),
       trace: bool = typer.Option(False, "--trace", help="Numeric methods: print the error at every iteration."),
       scene_file: Optional[str] = typer.Option(
           None, "--scene", help="Scene file (TOML, docs/scene.md): solutions that collide with it, the robot's "
                                 "body or the arm itself fail with reason 'collision'. Default: the robot's own "
                                 "surroundings, if its file has any (the fighter's torso and ground)."),
       no_scene: NoScene = False,
       sweep: Optional[int] = typer.Option(
           None, "--sweep", metavar="N", help="7-joint arms: sweep the joint whose locking leaves a closed form over N "
                                             "values of its range (default 32) and list every branch found."),
       fixed: Optional[List[str]] = typer.Option(
           None, "--fixed", metavar="NAME=VALUE", help="Hold a joint at a value (rad, deg with --deg; repeat for "
                                                       "more) and solve the rest in closed form."),
       json_out: JsonOut = False) -> None:
    """Inverse kinematics: joint angles that put the tool at a target.

    Every branch is listed for arms that `armkit info ROBOT` gives a class with a solver:
    every arm of 1-3 joints (planar3 with --phi), 6-joint arms in closed form (a spherical
    wrist, three parallel axes: puma560, ur5, stanford, a Kinova Jaco URDF) or by a 1-D or
    2-D search, the SCARA (cobra600), and 7-joint arms with --all (a sweep) or --fixed.
    Otherwise, or with --method, a numeric solver gives one answer.
    Exit code 0: solved, 1: no solution (the reason is printed), 2: bad input.

    Example: armkit ik fighter 24.861 14.353 187.181

    Example: armkit ik planar2 1.2 0.3 --branch elbow-up

    Example: armkit ik panda 0.4 0.1 0.5 --rpy 180 0 0 --deg --method lm --seed 3

    Example: armkit ik so101 0.25 0.05 0.1 --pitch -60 --deg   (position + tool pitch, every branch)

    Example: armkit ik so101 0.25 0 0.1 --direction 1 0 -1   (position + pointing direction, every branch)

    Example: armkit ik panda 0.4 0.1 0.5 --rpy 180 0 0 --deg --all --sweep 64   (7 joints: every branch of a sweep)

    Example: armkit ik panda 0.4 0.1 0.5 --rpy 180 0 0 --deg --fixed panda_joint7=45
    """
    from ..ik.analytic import closed_form
    from ..ik.analytic.held import Held

    if method not in METHOD_CHOICES:
        fail(_("--method must be one of {choices}; got {value!r}", choices=", ".join(METHOD_CHOICES), value=method))
    try:
        r = get_robot(robot)
        rpy_v = None if rpy is None else parse_vector(rpy, 3, "--rpy", "roll pitch yaw")
        quat_v = None if quat is None else parse_vector(quat, 4, "--quat", "x y z w")
        direction_v = None if direction is None else parse_vector(direction, 3, "--direction", "dx dy dz")
        target, ph, where = _target(r, coords, rpy_v, quat_v, deg, phi)
        solver = closed_form(r)
        scene = scene_option(r, scene_file, no_scene)
        if pitch is not None or direction_v is not None:
            return _partial_target(r, target, where, pitch, direction_v, deg, method, seed, json_out, scene)
        position_only = target.ndim == 1 and ph is None
        answer = _analytic_solver(r, position_only, None)   # armkit.ik's rule: the closed form that takes this target
        closed_ok = answer is not None                      # (a held wrist for a position; yaw-pitch3 needs pitch=)
        solver = answer if closed_ok else solver
        if fixed or sweep is not None or (all_branches and not closed_ok and r.n == 7):
            if method not in ("auto", "analytic") or branch is not None:
                fail(_("--sweep and --fixed list the closed-form branches; they do not go with --branch or a "
                       "numeric --method"))
            if position_only and not fixed and r.n == 7:   # the sweep's closed form solves a pose
                fail(_("--all and --sweep on a 7-joint arm sweep a joint for a pose (add --rpy or --quat); for a "
                       "position alone hold joints with --fixed NAME=VALUE (1 to 3 left), or use --method lm"))
            return _locked(r, target, where, _fixed_values(r, fixed or [], deg), sweep, json_out, scene)
        if all_branches and (method not in ("auto", "analytic") or branch is not None):
            fail(_("--all lists the closed-form branches; it does not go with --branch or a numeric --method"))
        if all_branches and not closed_ok and solver is not None and position_only and solver.pose_only:
            fail(_("--all: the closed form of robot {robot!r} ({family}) is for a pose; add the tool's orientation "
                   "(--rpy or --quat), or try --method lm", robot=r.name, family=solver.family))
        if all_branches and not closed_ok:
            fail(_("--all needs a closed form; robot {robot!r} has none for this target (try --method lm)",
                   robot=r.name))
        listing = method in ("auto", "analytic") and branch is None and closed_ok
        if seed is not None and (listing or (method in ("auto", "analytic") and closed_ok)):
            warn(_("--seed only matters for the numeric methods; the closed form ignores it"))
        if trace and (listing or method == "analytic" or (method == "auto" and closed_ok)):
            warn(_("--trace shows the iterations of a numeric method; the closed form has none"))
        closed = None if solver is None else _("closed form ({family}) with {joints} held", family=solver.inner.family,
                                                 joints=", ".join(r.joint_names[k] for k in sorted(solver.held))) \
            if isinstance(solver, Held) else _("closed form ({family})", family=solver.family)
        if listing:
            res = ik_all(r, target, phi=ph, scene=scene_off(scene))
            used = closed
        else:
            res = solve(r, target, method=method, branch=branch, phi=ph, seed=seed, trace=trace,  # type: ignore[arg-type]
                        scene=scene_off(scene))
            used = closed if (method in ("auto", "analytic") and closed_ok) else (
                "lm" if method == "auto" else method)
    except ArmkitError as exc:
        fail(str(exc), EXIT_BAD_INPUT)
    rows = _rows(r, res)
    solved = any(row["success"] for row in rows)
    if json_out:
        print_json({"robot": r.name, "unit": r.unit, "method": used, "target": np.asarray(target),
                    "phi_rad": ph, "solved": solved, "solutions": rows,
                    "trace": None if res.trace is None else np.asarray(res.trace),
                    "checked_against": list(res.checked_against)})
    else:
        _print_rows(r, rows, _("IK of {robot} for {target}, {method}", robot=esc(r.name), target=esc(where),
                               method=used), position_only)
        notes = list(dict.fromkeys(_explain(r, row) for row in rows if row["success"] and row["message"]))
        for note in notes:
            message(_("note: {text}", text=esc(note)))
        if scene is not None:
            for row in rows:
                if row["reason"] == "collision" and solved:
                    message(_("collision: {branch}: {text}", branch=esc(row["branch"]),
                              text=esc(_explain(r, row))))
            message(esc(checked_line(r, scene)))
        if trace and res.trace is not None:
            print_table(_trace_table(res.trace))
        if solved:
            ok_count = sum(row["success"] for row in rows)
            if len(rows) > 1:
                console.print(_("{k} of {n} branches solve the target (the first is nearest to q = 0).", k=ok_count,
                                n=len(rows)) if ok_count > 1 else
                              _("{k} of {n} branches solve the target.", k=ok_count, n=len(rows)))
    if not solved:
        first = rows[0]
        msg = _explain(r, first)
        if not msg.startswith(first["reason"]) and current_language() == SOURCE:
            msg = f"{first['reason']}: {msg}"
        fail(msg, EXIT_FAILED)


def _explain(robot, row: dict) -> str:
    """A branch's explanation in the user's language: the solver's English sentence, or in Korean the sentence
    rebuilt from its reason code and numbers (:func:`armkit.locale.library.ik_explanation`)."""
    from ..locale.library import ik_explanation

    return ik_explanation(row["reason"], row["message"], row["position_error"], robot.unit, current_language())



def register(app: typer.Typer) -> None:
    app.command(context_settings=NUMERIC_ARGS)(ik)
