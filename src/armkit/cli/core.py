"""Core commands: robots, info, convert, fk, jacobian."""

from __future__ import annotations

import math
from typing import Optional

import numpy as np
import typer
from rich.table import Table

from ..kinematics import (SINGULAR_THRESHOLD, condition_number, fk as fk_pose, fk_frames, is_singular, jacobian as jac,
                          manipulability)
from ..model import bundled_robots, load, save
from ..model.robot import Joint, Robot
from ..spatial import inverse, rotation_to_rpy
from .common import (NOISE, NUMERIC_ARGS, N_, _, console, current_language, esc, fail, fixed, get_robot, message,
                     natural_width,
                     out_width, parse_q, pose_table, print_fitted, print_json, print_records, print_table, q_display)
from .common import Deg, JointValues, JsonOut, RobotArg, Strict  # noqa: E402  (the shared options)


def robots(json_out: JsonOut = False) -> None:
    """List the bundled robots.

    Example: armkit robots
    """
    rows: list[dict[str, str | int]] = []
    for name in bundled_robots():
        robot = load(name)
        rows.append({"name": name, "dof": robot.n, "joints": robot.joint_types, "convention": robot.convention,
                     "unit": robot.unit, "description": robot.description, "source": " ".join(robot.source.split())})
    if json_out:
        print_json(rows)
        return
    print_fitted(_robots_table(rows, wide=True), _robots_table(rows, wide=False))


def _robots_table(rows: list[dict], wide: bool) -> Table:
    """The bundled robots; ``wide=False`` (narrow terminals): the description without the source."""
    t = Table(title=_("Bundled robots (armkit info NAME for details)"), header_style="bold")
    for col in (N_("name"), N_("DOF"), N_("joints"), N_("convention") if wide else N_("model"), N_("unit")):
        t.add_column(_(col), no_wrap=True)
    t.add_column(_("description and source (full text: armkit info NAME)") if wide else _("description"), ratio=1)
    for row in rows:
        src = str(row["source"])
        short = src if len(src) <= 70 else src[:69].rsplit(" ", 1)[0] + " …"
        conv = "URDF" if row["convention"] == "urdf" else (_(str(row["convention"])) + " DH" if wide else
                                                          {"standard": "std DH", "modified": "mod DH"}.get(
                                                              str(row["convention"]), str(row["convention"])))
        t.add_row(*(esc(row[k]) for k in ("name", "dof", "joints")), conv, esc(row["unit"]),
                  f"{esc(row['description'])}\n[dim]{esc(short)}[/]" if wide else esc(row["description"]))
    return t


def _dh_rows_table(r: Robot, wide: bool = True) -> Table:
    """The DH table of a DH robot as a Rich table (degrees, the robot's unit; units in the title).

    ``wide=False`` leaves out the type column (the ``*`` already marks the joint variable).
    """
    deg = 180.0 / math.pi
    conv = (_("standard DH: {formula}", formula="A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)")
            if r.convention == "standard"
            else _("modified (Craig) DH: {formula}", formula="A_i = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i)"))
    t = Table(title=_("DH table ({conv}); angles in deg, lengths in {unit}; * marks the joint variable", conv=conv,
                      unit=esc(r.unit)), header_style="bold")
    t.add_column("i", justify="right", no_wrap=True)
    t.add_column(_("joint"), no_wrap=True)
    if wide:
        t.add_column(_("type"), no_wrap=True)
    for col in (*dh_columns(r.convention), _("limits")):
        t.add_column(col, justify="right", no_wrap=True)
    for i, j in enumerate(r.joints, 1):
        t.add_row(str(i), esc(j.name), *((_(j.kind),) if wide else ()), *_dh_cells(r, i, j),
                  _limits_text(r, j, units=False))
    return t


def dh_columns(convention: str) -> tuple[str, ...]:
    """The DH table's parameter columns in the textbook's order: standard ``theta_i d_i a_i alpha_i``; modified in
    Craig's order ``alpha_{i-1} a_{i-1} d_i theta_i`` (the order of his link transform, read left to right)."""
    if convention == "modified":
        return ("alpha_{i-1}", "a_{i-1}", "d_i", "theta_i")
    return ("theta_i", "d_i", "a_i", "alpha_i")


def _dh_cells(r: Robot, i: int, j: Joint) -> tuple[str, ...]:
    """Row ``i`` of the DH table in :func:`dh_columns`' order (angles in deg; ``q{i}*`` marks the joint variable)."""
    deg = 180.0 / math.pi
    theta = (f"q{i}*" + (f" {j.theta * deg:+.6g}" if abs(j.theta * deg) >= NOISE else "") if not j.is_prismatic
             else _num(j.theta * deg))
    d = f"q{i}*" + (f" {j.d:+.6g}" if abs(j.d) >= NOISE else "") if j.is_prismatic else _num(j.d)
    cells = (theta, d, _num(j.a), _num(j.alpha * deg))
    return cells[::-1] if r.convention == "modified" else cells


def _num(v: float, digits: int = 6) -> str:
    """A table number: rounding noise (below :data:`common.NOISE` in its unit) shown as 0."""
    return f"{(0.0 if abs(v) < NOISE else v) + 0.0:.{digits}g}"


def _limits_text(r: Robot, j: Joint, units: bool = True) -> str:
    """A joint's limits; ``units=False``: revolute limits without "deg" (a table whose title gives the units)."""
    if j.is_continuous:
        return _("continuous")
    if j.is_prismatic:
        return f"[{j.lower:g}, {j.upper:g}] {r.unit}"
    return f"[{math.degrees(j.lower):g}, {math.degrees(j.upper):g}]" + (" deg" if units else "")


def _urdf_joints_table(r: Robot) -> Table:
    """The moving joints of a URDF chain: origin (fixed joints folded in) and axis."""
    t = Table(title=_("joints (origin in the previous moving link's frame, fixed joints folded in)"),
              header_style="bold")
    for col in ("i", _("joint"), _("type"), _("origin xyz ({unit})", unit=r.unit), _("origin rpy (deg)"), _("axis"),
                _("limits")):
        t.add_column(col, justify="right")
    for i, j in enumerate(r.joints, 1):
        O = j.origin_matrix()
        rpy = rotation_to_rpy(O[:3, :3], degrees=True)
        kind = _("continuous" if j.is_continuous else j.kind)
        t.add_row(str(i), esc(j.name), kind, " ".join(_num(v, 5) for v in O[:3, 3]),
                  " ".join(_num(v, 5) for v in rpy), " ".join(_num(v, 4) for v in j.axis_vector()),
                  _limits_text(r, j))
    return t


def _urdf_joints_records(r: Robot) -> None:
    """The joints of a URDF chain one record each (terminals too narrow for the table)."""
    records = []
    for i, j in enumerate(r.joints, 1):
        O = j.origin_matrix()
        rpy = rotation_to_rpy(O[:3, :3], degrees=True)
        kind = _("continuous" if j.is_continuous else j.kind)
        records.append((f"{i} {j.name} ({kind})",
                        [_("origin xyz ({xyz}) {unit}", xyz=", ".join(_num(v, 5) for v in O[:3, 3]), unit=r.unit),
                         f"rpy ({', '.join(_num(v, 5) for v in rpy)}) deg",
                         _("axis ({xyz})", xyz=" ".join(_num(v, 4) for v in j.axis_vector())),
                         _("limits {limits}", limits=_limits_text(r, j))]))
    print_records(_("joints (origin in the previous moving link's frame, fixed joints folded in)"), records)


def _dh_records(r: Robot) -> None:
    """The DH rows one record each (terminals too narrow for the table)."""
    records = []
    for i, j in enumerate(r.joints, 1):
        units = {"theta": "" if not j.is_prismatic else " deg", "d": "" if j.is_prismatic else f" {r.unit}",
                 "a": f" {r.unit}", "alpha": " deg"}
        records.append((f"{i} {j.name} ({_(j.kind)})",
                        [f"{name} {cell}{units[name.split('_')[0]]}"
                         for name, cell in zip(dh_columns(r.convention), _dh_cells(r, i, j))]
                        + [_("limits {limits}", limits=_limits_text(r, j))]))
    print_records(_("DH table ({convention} DH); * marks the joint variable", convention=_(r.convention)), records)


def _chain_class(r: Robot):
    """Which axes of ``r`` meet or are parallel, and the closed-form class that follows (see ik/geometric)."""
    from ..ik.geometric.classify import classify

    return classify(r)


def _class_line(r: Robot) -> str:
    """One line: the class's machine name and which axes meet or are parallel, in the current language."""
    from ..ik.geometric.classify import describe

    cls = _chain_class(r)
    return _("geometric class {name!r}: {line}", name=cls.name,
             line=esc(describe(cls, lambda text, **fields: _(text, **fields))))


def _closed_form(r: Robot):
    """The closed-form family's solver for ``r`` (:func:`armkit.ik.analytic.closed_form`), or None."""
    from ..ik.analytic import closed_form

    return closed_form(r)


def _family_line(r: Robot) -> str:
    """Which closed-form family answers ``armkit ik`` on ``r`` (and the joints it solves turned back), or ""."""
    cf = _closed_form(r)
    if cf is None:
        return ""
    line = _("armkit ik: closed form, family {family}, {m} branches", family=cf.family, m=cf.m)
    back = getattr(cf, "turned_back", ())
    if back:
        line += _("; solved with {joints} turned back (the DH table points each against the axis before it: a "
                  "twist of 180 deg)", joints=", ".join(esc(r.joint_names[j - 1]) for j in back))
    if not cf.sf.exact:
        line += _("; solved on the file's ideal arm (its twists and offsets are rounded or calibrated a little off "
                  "it), every branch then touched up on the true arm")
    named = getattr(cf, "names_from", None)
    if named is not None:
        line += _("; solved on the file's own axes, its branches named as family {family} names them on the arm's "
                  "DH table", family=named.family)
    return line


def _held_position(r: Robot):
    """The closed form of a position target with the arm's idle wrist held at q0 (:mod:`armkit.ik.analytic.held`),
    or None."""
    from ..ik.analytic.held import position_solver

    return position_solver(r)


def info(robot: RobotArg,
         json_out: JsonOut = False,
         dh: bool = typer.Option(False, "--dh", help="Show the equivalent DH table of a URDF arm "
                                 "(or of a DH arm in the other convention, with --convention)."),
         convention: str = typer.Option("standard", "--convention", help="DH convention for --dh: standard or "
                                        "modified.")) -> None:
    """Show a robot's joints (DH table in degrees, or URDF origins and axes), limits, base and tool.

    Example: armkit info fighter;  armkit info arm.urdf --tip tool0 --dh
    """
    r = get_robot(robot)
    if convention not in ("standard", "modified"):
        fail(_("--convention must be 'standard' or 'modified', got {value!r}", value=convention))
    shown = r.to_dh(convention) if dh else r  # type: ignore[arg-type]
    deg = 180.0 / math.pi
    if json_out:
        joints: list[dict] = []
        for j in shown.joints:
            row: dict = {"name": j.name, "type": "continuous" if j.is_continuous else j.kind,
                         "limits": [j.lower, j.upper] if j.is_prismatic else [j.lower * deg, j.upper * deg]}
            if shown.is_dh:
                row.update(theta_deg=j.theta * deg, d=j.d, a=j.a, alpha_deg=j.alpha * deg)
            else:
                row.update(origin=j.origin_matrix(), axis=j.axis_vector())
            joints.append(row)
        cls = _chain_class(r)
        held = _held_position(r)
        cf = _closed_form(r)
        print_json({"name": shown.name, "description": shown.description, "source": shown.source,
                    "convention": shown.convention, "unit": shown.unit, "joints": joints, "base": shown.base,
                    "tool": shown.tool, "links": [lk.name for lk in r.links],
                    "ignored_joints": list(r.ignored_joints),
                    "class": {"name": cls.name, "solver": cls.solver,
                              "intersecting": [list(g) for g in cls.intersecting],
                              "parallel": [list(g) for g in cls.parallel], "max_solutions": cls.max_solutions,
                              "near": cls.near, "locked": cls.locked},
                    "closed_form": None if cf is None else {
                        "family": cf.family, "branches": cf.m,
                        "turned_back": [r.joint_names[j - 1] for j in getattr(cf, "turned_back", ())],
                        "ideal_arm": not cf.sf.exact,
                        "names_from": getattr(getattr(cf, "names_from", None), "family", None)},
                    "position_held": None if held is None else {
                        "held": [r.joint_names[k] for k in sorted(held.held)], "family": held.inner.family,
                        "max_solutions": held.m}})
        return
    from ..locale.library import localize   # a URDF's own description is built from fields (its name)

    console.print(f"[bold]{esc(r.name)}[/]: {esc(localize(r.description, current_language()))}")
    if shown.is_dh:
        if shown is not r:
            console.print(_("equivalent {convention} DH table (same FK for every q; base and tool absorb the rest):",
                            convention=_(convention)))
        narrow = _dh_rows_table(shown, wide=False)
        if natural_width(narrow) <= out_width():
            print_fitted(_dh_rows_table(shown), narrow)
        else:
            _dh_records(shown)
    else:
        table = _urdf_joints_table(shown)
        if natural_width(table) <= out_width():
            print_table(table)
        else:
            _urdf_joints_records(shown)
    console.print(_class_line(r))
    family = _family_line(r)
    if family:
        console.print(family)
    held = _held_position(r)
    if held is not None:
        console.print(_("a position alone: closed form ({family}) with {joints} held at q0 (turning about the tool "
                        "point, they never move it), up to {n} solutions",
                        family=held.inner.family, joints=esc(", ".join(r.joint_names[k] for k in sorted(held.held))),
                        n=held.m))
    for which in ("base", "tool"):
        T = getattr(shown, which)
        if not np.allclose(T, np.eye(4)):
            print_table(pose_table(T, shown.unit, title=_(which)))
        else:
            console.print(_("{which}: identity", which=_(which)))
    if not r.is_dh:
        chain = [lk.name for lk in r.links if lk.joint not in set(r.ignored_joints)]
        console.print(_("chain: {chain}  ({n} moving joints, {k} fixed)", chain=esc(" -> ".join(chain)), n=r.n,
                        k=len(chain) - 1 - r.n))
        with_geo = sum(1 for lk in r.links if lk.visuals or lk.collisions)
        meshes = [s for lk in r.links for s in lk.visuals + lk.collisions if s.kind == "mesh"]
        found = sum(1 for s in meshes if s.mesh_path)
        console.print(_("geometry: {k} links with shapes; meshes found {found} of {n}", k=with_geo, found=found,
                        n=len(meshes)))
        if r.ignored_joints:
            console.print(_("joints off the chain (ignored): {names}", names=esc(", ".join(r.ignored_joints))))
        if not dh:
            console.print("[dim]" + _("armkit info ... --dh shows the equivalent DH table") + "[/]")
    if r.source:
        console.print("[dim]" + _("source: {text}", text=esc(" ".join(localize(r.source, current_language()).split())))
                      + "[/]")


def convert(src: str = typer.Argument(..., help="Robot to read: bundled name, .toml or .urdf (--base/--tip for "
                                      "a URDF chain)."),
            dst: str = typer.Argument(..., help="File to write: .urdf (URDF, metres) or .toml (DH table)."),
            convention: Optional[str] = typer.Option(
                None, "--convention", metavar="standard|modified",
                help="DH convention of the TOML written: standard or modified (Craig). Default: the robot's own "
                     "(standard for a URDF chain).")) -> None:
    """Convert a robot between URDF and TOML (a URDF chain becomes its equivalent DH table).

    Example: armkit convert ur5.urdf ur5.toml --tip tool0;  armkit convert fighter fighter.urdf;
    armkit convert fighter fighter_craig.toml --convention modified
    """
    if convention is not None and convention not in ("standard", "modified"):
        fail(_("--convention must be 'standard' or 'modified', got {value!r}", value=convention))
    to_urdf = dst.lower().endswith((".urdf", ".xml"))
    if convention is not None and to_urdf:
        fail(_("--convention chooses the DH table of a TOML file; a URDF file has no DH table"))
    r = get_robot(src)
    out = r
    if not to_urdf and (not r.is_dh or (convention is not None and convention != r.convention)):
        out = r.to_dh(convention or "standard")  # type: ignore[arg-type]
    path = save(out, dst)
    what = _("URDF (metres)") if dst.lower().endswith((".urdf", ".xml")) else _("TOML ({convention} DH)",
                                                                               convention=_(out.convention))
    console.print(_("wrote {path}: {robot}, {n} joints, as {what}", path=esc(str(path)), robot=esc(r.name), n=r.n,
                    what=what))
    if not r.is_dh and out is not r:
        console.print("[dim]" + _("the DH table reproduces the URDF chain's FK for every q; link geometry is not "
                                  "kept in TOML") + "[/]")
    elif out is not r:
        console.print("[dim]" + _("the {convention} DH table reproduces the {original} DH table's FK for every q",
                                  convention=_(out.convention), original=_(r.convention)) + "[/]")
    if r.unit != "m" and dst.lower().endswith((".urdf", ".xml")):
        console.print("[dim]" + _("lengths converted from {unit} to metres (URDF is always in metres)",
                                  unit=r.unit) + "[/]")


def fk(robot: RobotArg,
       q: JointValues,
       deg: Deg = False,
       strict: Strict = False,
       link: Optional[str] = typer.Option(None, "--link", help="Pose of this link instead of the tool (a URDF "
                                          "link name, or link0..linkN of a DH arm; `armkit info` lists them)."),
       links: bool = typer.Option(False, "--links", help="Also print each link transform A_i (frame {i-1} -> {i}) "
                                                         "as a numeric 4x4 matrix."),
       json_out: JsonOut = False) -> None:
    """Forward kinematics: the tool pose and every joint origin (with --links every A_i as numbers).

    Example: armkit fk fighter 30 45 60 --deg;  armkit fk so101 0 0 0 0 0 --link wrist_link

    Example: armkit fk fighter 30 45 60 --deg --links   (A_1, A_2, A_3 for a homework check)
    """
    r = get_robot(robot)
    qv = parse_q(r, q, deg, strict)
    F = fk_frames(r, qv)
    T = F[-1] if link is None else fk_pose(r, qv, link=link)
    rpy = np.degrees(rotation_to_rpy(T[:3, :3]))
    A = link_transforms(r, F) if links else None
    if json_out:
        print_json({"robot": r.name, "unit": r.unit, "q_rad": qv, "link": link, "pose": T, "position": T[:3, 3],
                    "rpy_deg": rpy, "frames": [{"name": n, "origin": f[:3, 3]} for n, f in zip(r.link_names, F)],
                    **({} if A is None else {"links": A, "base": r.base, "tool": r.tool})})
        return
    console.print(_("{robot} at q = ({q})", robot=f"[bold]{esc(r.name)}[/]", q=", ".join(q_display(r, qv))))
    if A is not None:
        _print_links(r, qv, A)
    p = T[:3, 3]
    rpy_text = f"roll/pitch/yaw: ({fixed(rpy[0])}, {fixed(rpy[1])}, {fixed(rpy[2])}) deg"
    if link is not None:
        console.print(_("link {link}: origin ({xyz}) {unit}", link=esc(link),
                        xyz=f"[bold]{fixed(p[0])}, {fixed(p[1])}, {fixed(p[2])}[/]", unit=r.unit) + "   " + rpy_text)
        print_table(pose_table(T, r.unit, title=f"T_world_{esc(link)}"))
        return
    console.print(_("end point: ({xyz}) {unit}", xyz=f"[bold]{fixed(p[0])}, {fixed(p[1])}, {fixed(p[2])}[/]", unit=r.unit)
                  + "   " + rpy_text)
    print_table(pose_table(T, r.unit, title="T_world_tool"))
    t = Table(title=_("frame origins ({unit})", unit=r.unit), header_style="bold")
    for col in (_("frame"), _("link"), "x", "y", "z"):
        t.add_column(col, justify="right")
    for k, (name, f) in enumerate(zip(r.link_names, F)):
        label = _("base") if k == 0 else (_("{k} + tool", k=k) if k == r.n else str(k))
        t.add_row(label, esc(name), *(fixed(v) for v in f[:3, 3]))
    print_table(t)


def link_transforms(r: Robot, F: np.ndarray) -> np.ndarray:
    """The link transforms ``A_i = T_{i-1,i}`` ``(n, 4, 4)`` from the frames of :func:`armkit.fk_frames` ``(n+1, 4, 4)``.

    ``F[0]`` is the base and ``F[n]`` has the tool applied, so ``A_1 = F[0]^-1 F[1]``, ``A_i = F[i-1]^-1 F[i]`` and
    ``A_n = F[n-1]^-1 F[n] tool^-1``: then ``base A_1 ... A_n tool`` is the tool pose. For a DH arm ``A_i`` is the
    DH link transform of row ``i``; for a URDF chain, the fixed joints before moving joint ``i`` folded in.
    """
    A = inverse(F[:-1]) @ F[1:]
    A[-1] = A[-1] @ inverse(r.tool)
    return np.asarray(A)


def _print_links(r: Robot, q: np.ndarray, A: np.ndarray) -> None:
    """Each ``A_i`` as a 4x4 table (rotation dimensionless, translation in the robot's unit), then the product."""
    shown = q_display(r, q)
    formula = (_("standard DH: {formula}", formula="A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)")
               if r.convention == "standard" else
               _("modified (Craig) DH: {formula}", formula="A_i = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i)")
               if r.convention == "modified" else _("URDF: joint origin (fixed joints folded in) times the joint motion"))
    message(_("link transforms, each from one frame to the next: {formula}", formula=esc(formula)))
    for i, (Ai, j) in enumerate(zip(A, r.joints), 1):
        title = _("A{i} = T_{a}_{b}  ({joint}, q{i} = {value})", i=i, a=i - 1, b=i, joint=esc(j.name),
                  value=shown[i - 1])
        print_table(pose_table(Ai, r.unit, title=title, full=True))
    base = "" if np.allclose(r.base, np.eye(4)) else "base · "
    tool = "" if np.allclose(r.tool, np.eye(4)) else " · tool"
    message(_("pose of the tool = {product} (base and tool: armkit info)", product=f"{base}A1 ··· A{r.n}{tool}")
            if base or tool else _("pose of the tool = {product}", product=f"A1 ··· A{r.n}"))


def _jacobian_table(r: Robot, J: np.ndarray, frame: str, compact: bool) -> Table:
    """The Jacobian as a table: joint names and 6 decimals, or (compact) q1..qn and 4 significant digits."""
    t = Table(title=_("geometric Jacobian of {robot} in the {frame} frame (v rows in {unit}/rad, w rows "
                      "dimensionless)", robot=esc(r.name), frame=_(frame), unit=r.unit), header_style="bold")
    t.add_column(_("row"))
    for i, (name, kind) in enumerate(zip(r.joint_names, r.joint_types), 1):
        t.add_column(f"q{i}" if compact else f"{esc(name)} ({kind})", justify="right")
    for label, row in zip(("vx", "vy", "vz", "wx", "wy", "wz"), J):
        row = np.where(np.abs(row) < 5e-13, 0.0, row)         # no "-0.000000" from rounding noise
        t.add_row(label, *((f"{v:.4g}" if compact else f"{v: .6f}") for v in row))
    return t


def jacobian(robot: RobotArg,
             q: JointValues,
             frame: str = typer.Option("base", "--frame", help="Express J in the 'base' or the 'tool' frame."),
             deg: Deg = False,
             strict: Strict = False,
             json_out: JsonOut = False) -> None:
    """Geometric Jacobian (rows vx vy vz wx wy wz), manipulability and condition number.

    Example: armkit jacobian ur5 0.1 -1 1 0 0.5 0 --frame tool
    """
    from .common import fail

    if frame not in ("base", "tool"):
        fail(_("--frame must be 'base' or 'tool', got {value!r}", value=frame))
    r = get_robot(robot)
    qv = parse_q(r, q, deg, strict)
    J = jac(r, qv, frame=frame)  # type: ignore[arg-type]
    w, c, s = float(manipulability(r, qv)), float(condition_number(r, qv)), bool(is_singular(r, qv))
    if json_out:
        print_json({"robot": r.name, "frame": frame, "q_rad": qv, "jacobian": J, "manipulability": w,
                    "condition_number": c, "singular": s, "singular_threshold": SINGULAR_THRESHOLD})
        return
    print_fitted(_jacobian_table(r, J, frame, compact=False), _jacobian_table(r, J, frame, compact=True))
    in_m = "" if r.unit == "m" else " " + _("(J's {unit} rows converted to m, divided by {scale})", unit=r.unit,
                                            scale=f"{1 / r.unit_scale:g}")
    message(_("manipulability sqrt(det(J J^T)) = {w}   condition number = {c}   both with lengths in m{converted}",
              w=f"{w:.6g}", c=f"{c:.6g}", converted=in_m)
            + "; " + ("[bold red]" + _("SINGULAR") + "[/]" if s else _("not singular")) + " "
            + _("(threshold: smallest singular value < {threshold}, lengths in m)",
                threshold=f"{SINGULAR_THRESHOLD:g}"))



def register(app: typer.Typer) -> None:
    app.command()(robots)
    app.command()(info)
    app.command()(convert)
    app.command(context_settings=NUMERIC_ARGS)(fk)
    app.command(context_settings=NUMERIC_ARGS)(jacobian)
