"""Core commands: robots, info, fk, jacobian."""

from __future__ import annotations

import math
from typing import List, Optional

import numpy as np
import typer
from rich.table import Table

from .common import NUMERIC_ARGS, console, esc, get_robot, parse_q, pose_table, print_json, q_display

ROBOT_HELP = "Bundled robot name (see `armkit robots`) or path of a .toml robot file."


def robots(json_out: bool = typer.Option(False, "--json", help="Print JSON instead of a table.")) -> None:
    """List the bundled robots.

    Example: armkit robots
    """
    from ..model import bundled_robots, load

    rows: list[dict[str, str | int]] = []
    for name in bundled_robots():
        robot = load(name)
        rows.append({"name": name, "dof": robot.n, "joints": robot.joint_types, "convention": robot.convention,
                     "unit": robot.unit, "description": robot.description, "source": " ".join(robot.source.split())})
    if json_out:
        print_json(rows)
        return
    t = Table(title="Bundled robots (armkit info NAME for details)", header_style="bold")
    for col in ("name", "DOF", "joints", "convention", "unit"):
        t.add_column(col, no_wrap=True)
    t.add_column("description and source (full text: armkit info NAME)")
    for row in rows:
        src = str(row["source"])
        short = src if len(src) <= 70 else src[:69].rsplit(" ", 1)[0] + " …"
        t.add_row(*(esc(row[k]) for k in ("name", "dof", "joints")), f"{row['convention']} DH", esc(row["unit"]),
                  f"{esc(row['description'])}\n[dim]{esc(short)}[/]")
    console.print(t)


def info(robot: str = typer.Argument(..., help=ROBOT_HELP),
         json_out: bool = typer.Option(False, "--json", help="Print JSON instead of tables.")) -> None:
    """Show a robot's DH table (degrees), joint limits, base and tool.

    Example: armkit info fighter
    """
    r = get_robot(robot)
    deg = 180.0 / math.pi
    if json_out:
        print_json({"name": r.name, "description": r.description, "source": r.source, "convention": r.convention,
                    "unit": r.unit, "joints": [
                        {"name": j.name, "type": j.kind, "theta_deg": j.theta * deg, "d": j.d, "a": j.a,
                         "alpha_deg": j.alpha * deg,
                         "limits": [j.lower, j.upper] if j.is_prismatic else [j.lower * deg, j.upper * deg]}
                        for j in r.joints], "base": r.base, "tool": r.tool})
        return
    console.print(f"[bold]{esc(r.name)}[/]: {esc(r.description)}")
    conv = ("standard DH: A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)" if r.convention == "standard"
            else "modified (Craig) DH: A_i = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i)")
    t = Table(title=f"DH table ({conv}); * marks the joint variable", header_style="bold")
    alpha_h = "alpha (deg)" if r.convention == "standard" else "alpha_{i-1} (deg)"
    a_h = f"a ({r.unit})" if r.convention == "standard" else f"a_{{i-1}} ({r.unit})"
    for col in ("i", "joint", "type", "theta (deg)", f"d ({r.unit})", a_h, alpha_h, "limits"):
        t.add_column(col, justify="right")
    for i, j in enumerate(r.joints, 1):
        theta = f"q{i}*" + (f" {j.theta * deg:+g}" if j.theta else "") if not j.is_prismatic else f"{j.theta * deg:g}"
        d = f"q{i}*" + (f" {j.d:+g}" if j.d else "") if j.is_prismatic else f"{j.d:g}"
        lim = (f"[{j.lower:g}, {j.upper:g}] {r.unit}" if j.is_prismatic
               else f"[{j.lower * deg:g}, {j.upper * deg:g}] deg")
        t.add_row(str(i), esc(j.name), j.kind, theta, d, f"{j.a:g}", f"{j.alpha * deg:g}", lim)
    console.print(t)
    for which in ("base", "tool"):
        T = getattr(r, which)
        if not np.allclose(T, np.eye(4)):
            console.print(pose_table(T, r.unit, title=which))
        else:
            console.print(f"{which}: identity")
    if r.source:
        console.print(f"[dim]source: {esc(' '.join(r.source.split()))}[/]")


def fk(robot: str = typer.Argument(..., help=ROBOT_HELP),
       q: List[str] = typer.Argument(..., help="Joint values, one per joint (rad, or deg with --deg).",
                                     metavar="Q..."),
       deg: bool = typer.Option(False, "--deg", help="Joint angles are in degrees."),
       strict: bool = typer.Option(False, "--strict", help="A joint outside its limits is an error."),
       json_out: bool = typer.Option(False, "--json", help="Print JSON.")) -> None:
    """Forward kinematics: the tool pose and every joint origin.

    Example: armkit fk fighter 30 45 60 --deg
    """
    from ..kinematics import fk_frames
    from ..spatial import rotation_to_rpy

    r = get_robot(robot)
    qv = parse_q(r, q, deg, strict)
    F = fk_frames(r, qv)
    T = F[-1]
    rpy = np.degrees(rotation_to_rpy(T[:3, :3]))
    if json_out:
        print_json({"robot": r.name, "unit": r.unit, "q_rad": qv, "pose": T, "position": T[:3, 3],
                    "rpy_deg": rpy, "frames": [{"name": n, "origin": f[:3, 3]}
                                               for n, f in zip(r.link_names, F)]})
        return
    console.print(f"[bold]{esc(r.name)}[/] at q = ({', '.join(q_display(r, qv))})")
    p = T[:3, 3]
    console.print(f"end point: ([bold]{p[0]:.3f}, {p[1]:.3f}, {p[2]:.3f}[/]) {r.unit}   "
                  f"roll/pitch/yaw: ({rpy[0]:.3f}, {rpy[1]:.3f}, {rpy[2]:.3f}) deg")
    console.print(pose_table(T, r.unit, title="T_world_tool"))
    t = Table(title=f"frame origins ({r.unit})", header_style="bold")
    for col in ("frame", "link", "x", "y", "z"):
        t.add_column(col, justify="right")
    for k, (name, f) in enumerate(zip(r.link_names, F)):
        label = "base" if k == 0 else (f"{k} + tool" if k == r.n else str(k))
        t.add_row(label, esc(name), *(f"{v:.3f}" for v in f[:3, 3]))
    console.print(t)


def jacobian(robot: str = typer.Argument(..., help=ROBOT_HELP),
             q: List[str] = typer.Argument(..., help="Joint values (rad, or deg with --deg).", metavar="Q..."),
             frame: str = typer.Option("base", "--frame", help="Express J in the 'base' or the 'tool' frame."),
             deg: bool = typer.Option(False, "--deg", help="Joint angles are in degrees."),
             strict: bool = typer.Option(False, "--strict", help="A joint outside its limits is an error."),
             json_out: bool = typer.Option(False, "--json", help="Print JSON.")) -> None:
    """Geometric Jacobian (rows vx vy vz wx wy wz), manipulability and condition number.

    Example: armkit jacobian ur5 0.1 -1 1 0 0.5 0 --frame tool
    """
    from ..kinematics import SINGULAR_THRESHOLD, condition_number, is_singular, jacobian as jac, manipulability
    from .common import fail

    if frame not in ("base", "tool"):
        fail(f"--frame must be 'base' or 'tool', got {frame!r}")
    r = get_robot(robot)
    qv = parse_q(r, q, deg, strict)
    J = jac(r, qv, frame=frame)  # type: ignore[arg-type]
    w, c, s = float(manipulability(r, qv)), float(condition_number(r, qv)), bool(is_singular(r, qv))
    if json_out:
        print_json({"robot": r.name, "frame": frame, "q_rad": qv, "jacobian": J, "manipulability": w,
                    "condition_number": c, "singular": s, "singular_threshold": SINGULAR_THRESHOLD})
        return
    t = Table(title=f"geometric Jacobian of {esc(r.name)} in the {frame} frame "
                    f"(v rows in {r.unit}/rad, w rows dimensionless)", header_style="bold")
    t.add_column("row")
    for name, kind in zip(r.joint_names, r.joint_types):
        t.add_column(f"{esc(name)} ({kind})", justify="right")
    for label, row in zip(("vx", "vy", "vz", "wx", "wy", "wz"), J):
        t.add_row(label, *(f"{v: .6f}" for v in row))
    console.print(t)
    console.print(f"manipulability sqrt(det(J J^T)) = {w:.6g}   condition number = {c:.6g}   "
                  + ("[bold red]SINGULAR[/]" if s else "not singular")
                  + f" (threshold: smallest singular value < {SINGULAR_THRESHOLD:g}, lengths in m)")


def register(app: typer.Typer) -> None:
    app.command()(robots)
    app.command()(info)
    app.command(context_settings=NUMERIC_ARGS)(fk)
    app.command(context_settings=NUMERIC_ARGS)(jacobian)
