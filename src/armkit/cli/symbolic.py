"""Commands for symbolic derivation, singularities, velocity kinematics and trajectories.

derive, singular, velocity, traj. SymPy, SciPy and Matplotlib load inside the command bodies.
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path
from typing import Annotated, Any, List, Optional

import numpy as np
import typer
from rich.table import Table

from .._io import atomic_path
from ..errors import ArgumentError, UnreachableError
from .common import (EXIT_FAILED, NUMERIC_ARGS, console, esc, fail, name_list, output_path, get_robot, parse_numbers, parse_q, print_json,
                     checked_line, count, message, q_display, scene_option, sig, warn)

from .common import err_console, print_table  # noqa: E402
from .common import N_, _, current_language  # noqa: E402
from .common import Deg, JsonOut, NoScene, RobotArg  # noqa: E402  (the shared options)


def _local(text: str) -> str:
    """A sentence or label of the library (a singular set, a trajectory's label) in the user's language."""
    from ..locale.library import localize

    return localize(text, current_language())



def _matrix_table(M, title: str, row_labels=None, col_labels=None) -> Table:
    t = Table(title=title, show_header=col_labels is not None, header_style="bold", show_lines=False)
    if row_labels is not None:
        t.add_column("")
    for j in range(M.shape[1]):
        t.add_column(esc(col_labels[j]) if col_labels else "", overflow="fold")
    for i in range(M.shape[0]):
        cells = [esc(M[i, j]) for j in range(M.shape[1])]
        t.add_row(*(([row_labels[i]] if row_labels is not None else []) + cells))
    return t


def _derive_outputs(latex: bool, python: bool, ik_export: bool, output: Optional[Path], png: Optional[Path],
                    budget: float, fragment: bool = False) -> tuple[Optional[Path], Optional[Path]]:
    """Check ``derive``'s options; returns ``(png, output)`` (``-o fk.png`` without a text format is the picture)."""
    if latex and python:
        fail(_("choose one of --latex and --python"))
    if fragment and not latex:
        fail(_("--fragment is the body of the --latex output, to paste into a report: add --latex"))
    if ik_export and png is not None:
        fail(_("--png draws the forward kinematics and the Jacobian; it does not go with --ik"))
    text = latex or python or ik_export
    if output is not None and not text and png is None and output.suffix.lower() in (".png", ".pdf", ".svg"):
        png, output = output, None      # derive ROBOT -o fk.png: the picture, as --png does
    if output is not None and not text:
        fail(_("--output writes the --python, --latex or --ik text, or a picture (.png, .pdf, .svg); got {name!r}",
               name=output.name))
    if output is not None:
        output_path(output, (".py",) if python else (".tex",) if latex else (".txt", ".md"), "--output")
    _check_budget(budget)
    return png, output


Budget = Annotated[float, typer.Option("--budget", help="CPU seconds of symbolic work at most (simplifying the "
                                       "derivation; for singular also factoring the determinant); past it the "
                                       "remaining entries stay raw (exact) products, and singular stops. 0: no "
                                       "limit.")]


def _check_budget(budget: float) -> None:
    if not budget >= 0 or budget == float("inf"):
        fail(_("--budget must be a number of seconds >= 0 (0: no limit), got {value}", value=budget))


def derive(robot: RobotArg,
           latex: bool = typer.Option(False, "--latex", help="Print a LaTeX document (link transforms, FK, J)."),
           python: bool = typer.Option(False, "--python", help="Print an importable NumPy module (fk, jacobian)."),
           ik_export: bool = typer.Option(False, "--ik", help="The closed-form IK instead of the FK (planar 2R and "
                                                              "yaw-pitch-pitch arms): its equations as text, as "
                                                              "LaTeX with --latex, or one Python function per branch "
                                                              "with --python."),
           fragment: bool = typer.Option(False, "--fragment", help="With --latex: only the part to paste into a "
                                                                   "report (no \\documentclass, no document "
                                                                   "environment; needs amsmath)."),
           output: Optional[Path] = typer.Option(None, "-o", "--output", help="Write the --python or --latex text "
                                                                              "to this file instead of printing it; "
                                                                              "a .png/.pdf/.svg name: the picture "
                                                                              "(as --png)."),
           png: Optional[Path] = typer.Option(None, "--png", help="Also render the FK and Jacobian entries to a PNG."),
           links: bool = typer.Option(False, "--links", help="Also print every link transform."),
           no_cache: bool = typer.Option(False, "--no-cache", help="Derive again, ignoring the on-disk cache."),
           budget: Budget = 60.0,
           json_out: JsonOut = False) -> None:
    """Symbolic FK, Jacobian (and 2R closed-form IK) with the c12 = cos(q1 + q2) short-hand.

    Example: armkit derive planar2
    Example: armkit derive fighter --latex > fk.tex
    Example: armkit derive puma560 --python > puma_fk.py

    Example: armkit derive fighter --ik --python -o fighter_ik.py

    Example: armkit derive fighter --ik   (the closed-form IK equations as text)

    Example: armkit derive examples/my_arm.toml --ik --latex --fragment > ik.tex   (to paste into a report)
    """
    from ..symbolic import derive as do_derive
    from ..symbolic.export import to_latex, to_numpy_source, to_text

    png, output = _derive_outputs(latex, python, ik_export, output, png, budget, fragment)
    r = get_robot(robot)
    if png is not None:
        output_path(png, (".png", ".pdf", ".svg"), "--png")
    if ik_export:
        from ..symbolic.ik_equations import equations_latex, equations_text, ik_equations
        from ..symbolic.ik_export import to_ik_source

        try:
            text = to_ik_source(r) if python else (equations_latex(ik_equations(r), standalone=not fragment)
                                                   if latex else equations_text(ik_equations(r)))
        except ArgumentError as exc:
            fail(str(exc))
        _write_text(text, output)
        return
    t0 = time.perf_counter()
    d = do_derive(r, cache=not no_cache, simplify_budget=budget if budget > 0 else None)
    elapsed = time.perf_counter() - t0
    if d.meta.get("note"):
        warn(d.meta["note"])
    if latex or python:
        _write_text(to_latex(d, standalone=not fragment) if latex else to_numpy_source(d), output)
        return
    if png is not None:
        from ..symbolic.export import render_png

        with atomic_path(png, (".png", ".pdf", ".svg"), "--png") as tmp:
            render_png(d, tmp)
    txt = to_text(d, ("links", "T", "J") if links else ("T", "J"))
    ik = _planar_2r_ik(r)
    if json_out:
        out = {"robot": r.name, "convention": r.convention, "unit": r.unit, "joint_names": list(r.joint_names),
               "parameters": {str(k): v for k, v in d.values.items()},
               "shorthand": {str(s): str(f) for f, s in txt["legend"].items()},
               "T": [[str(e) for e in row] for row in txt["T"].tolist()],
               "J": [[str(e) for e in row] for row in txt["J"].tolist()], "seconds": elapsed}
        if ik is not None:
            out["ik"] = ik
        print_json(out)
        return
    names = esc(name_list([f"q{i + 1} = {n}" for i, n in enumerate(r.joint_names) if n != f"q{i + 1}"]))
    console.print(_("{robot}: {n} joints {types}, {convention} DH", robot=f"[bold]{esc(r.name)}[/]", n=r.n,
                    types=r.joint_types, convention=_(r.convention)) + (f" ({names})" if names else ""))
    if d.values:
        console.print(_("parameters:") + " " + ", ".join(
            f"{s} = {v:g}" + ("" if s.name.startswith(("alpha", "theta")) else f" {r.unit}")
            for s, v in d.values.items()))
    if txt["legend"]:
        console.print(_("short-hand:") + " " + ", ".join(f"{s} = {f}" for f, s in txt["legend"].items()))
    if links:
        for i, A in enumerate(txt["links"], 1):
            print_table(_matrix_table(A, _("A{i} (frame {a} -> {b})", i=i, a=i - 1, b=i)))
    print_table(_matrix_table(txt["T"], _("T = base · A1 ··· A{n} · tool  (pose of the tool)", n=r.n)))
    cols = [f"q{i + 1}" for i in range(r.n)]
    print_table(_matrix_table(txt["J"], _("geometric Jacobian J(q), rows (v, w), base frame"),
                                ["vx", "vy", "vz", "wx", "wy", "wz"], cols))
    if ik is not None:
        console.print("[bold]" + _("closed-form IK") + "[/] " + _("(derived with {function} from {equations}):",
                                                                   function="sympy.solve",
                                                                   equations="x = a1 c1 + a2 c12, y = a1 s1 + a2 s12"))

        console.print(f"  c2 = {ik['c2']}")
        console.print(f"  q1 = {ik['q1']}")
        for b in ik["branches"]:
            console.print(f"  {b['label']}: s2 = {b['s2']},  q2 = atan2(s2, c2)")
        console.print("  " + _("reachable where {condition}", condition="-1 <= c2 <= 1, i.e. |a1 - a2| <= "
                                                                         "sqrt(x^2 + y^2) <= a1 + a2"))
    cached = _("partly simplified, not cached") if d.meta.get("note") else (
        _("not cached") if no_cache else _("cached on disk for next time"))
    console.print("[dim]" + _("derived in {seconds} s ({cached})", seconds=f"{elapsed:.2f}", cached=cached) + "[/]")


def _write_text(text: str, output: Optional[Path]) -> None:
    """Print ``text``, or write it to ``output`` (atomically)."""
    if output is None:
        sys.stdout.write(text)
        return

    with atomic_path(output, (output.suffix,), "--output") as tmp:
        tmp.write_text(text, encoding="utf-8")
    err_console.print(_("wrote {path}", path=esc(output)))


def _planar_2r_ik(r) -> Optional[dict]:
    """The derived 2R IK as text when ``r`` is a planar 2R arm (two revolute joints, parallel axes)."""
    if r.n != 2 or r.joint_types != "RR":
        return None
    r = r if r.is_dh else r.to_dh()
    if any(abs(math.sin(j.alpha)) > 1e-12 for j in r.joints) or any(j.d != 0 or j.theta != 0 for j in r.joints):
        return None
    from ..symbolic.ik2r import derive_planar_2r_ik
    ik = derive_planar_2r_ik()
    return {"c2": str(ik.c2), "q1": str(ik.q1_compact),
            "branches": [{"label": "elbow down (q2 >= 0)", "s2": "+sqrt(1 - c2**2)"},
                         {"label": "elbow up (q2 <= 0)", "s2": "-sqrt(1 - c2**2)"}],
            "a1": float(r.joints[0].a), "a2": float(r.joints[1].a)}


def singular(robot: RobotArg,
             plot: Optional[Path] = typer.Option(None, "-o", "--output",
                                                 help="Save a manipulability map over two joints (PNG)."),
             plot_alias: Optional[Path] = typer.Option(None, "--plot", hidden=True),
             budget: Budget = 60.0,
             json_out: JsonOut = False) -> None:
    """Singularities: det(J) factored, each factor named (stretched, folded, on the yaw axis, wrist) and checked.

    Example: armkit singular fighter
    Example: armkit singular planar2 -o manip.png
    """
    from ..analysis.singularity import analyze_singularities, plot_manipulability

    r = get_robot(robot)
    plot = plot if plot is not None else plot_alias     # --plot: the old spelling of --output
    if plot is not None:
        output_path(plot, (".png", ".pdf", ".svg"), "--output")
    _check_budget(budget)
    limit = budget if budget > 0 else None
    from ..symbolic import derive as do_derive

    d = do_derive(r, simplify_budget=limit)
    res = analyze_singularities(r, d, budget=limit)
    if json_out:
        print_json({"robot": r.name, "method": res.method, "rows": list(res.rows),
                    "determinant": str(res.determinant),
                    "factors": [{"factor": f.text, "kind": f.kind, "description": f.description, "power": f.power,
                                 "joints": list(f.joints),
                                 "solutions_deg": [[math.degrees(v) if not r.prismatic[f.joints[0] - 1] else v, lab]
                                                   for v, lab in f.solutions],
                                 "max_manipulability_on_set": float(f.manipulability.max()) if len(f.manipulability)
                                 else None} for f in res.factors],
                    "typical_manipulability": res.typical_manipulability})
    else:
        from ..symbolic.export import shorthand
        console.print(_("{robot}: {method} over rows ({rows})", robot=f"[bold]{esc(r.name)}[/]", method=res.method,
                        rows=", ".join(res.rows)))
        console.print(f"  = {shorthand(res.determinant, d.q)[0]}")
        t = Table(title=_("singular configurations (where a factor vanishes)"), header_style="bold")
        for col in (N_("factor"), N_("meaning"), N_("solutions"), N_("check: max manipulability there")):
            t.add_column(_(col), overflow="fold")
        for f in res.singular_factors:
            if f.solutions:
                k = f.joints[0] - 1
                sol = ", ".join((f"{q_display(r, np.eye(r.n)[k] * v)[k]}") + (f" ({_local(lab)})" if lab else "")
                                for v, lab in f.solutions)
            else:
                sol = _("a curve/surface in joint space")
            w = f"{f.manipulability.max():.1e}" if len(f.manipulability) else "-"
            power = "" if f.power == 1 else " " + _("(power {k})", k=f.power)
            meaning = getattr(f.description, "fields", {}).get("meaning", f.description)   # the words, not "= 0"
            t.add_row(esc(f.text + power), esc(_local(meaning)), esc(sol), w)
        print_table(t)
        consts = [f.text for f in res.factors if f.kind == "constant" and f.expr != 1]
        if consts:
            console.print(_("constant factors (never zero): {factors}", factors=", ".join(consts)))
        console.print(_("typical manipulability away from them: {value}",
                        value=f"{res.typical_manipulability:.3g}"))
    if plot is not None:
        if r.n > 3:
            warn(_("the manipulability map is for 2-3 joint arms; {robot} has {n}: plotting joints 2 and 3",
                   robot=r.name, n=r.n))
        joints = (1, 2) if r.n == 2 else (2, 3)

        with atomic_path(plot, (".png", ".pdf", ".svg"), "--output") as tmp:
            fig = plot_manipulability(r, tmp, joints=joints, analysis=res)
        from ..viz._mpl import pyplot

        pyplot().close(fig)
        if not json_out:
            console.print(_("wrote {path}", path=esc(plot)))


def velocity(robot: RobotArg,
             q: List[str] = typer.Argument(..., metavar="Q... [V...]",
                                           help="Joint values, then (optionally) the rest of --ee-vel/--q-vel."),
             deg: Deg = False,
             ee_vel: Optional[str] = typer.Option(None, "--ee-vel",
                                                  help="Desired tool velocity: 2 (vx vy), 3 (v) or 6 (v, w) values."),
             q_vel: Optional[str] = typer.Option(None, "--q-vel", help="Joint rates, one per joint: prints the twist."),
             method: str = typer.Option("pinv", "--method", help="'pinv' (pseudo-inverse) or 'dls' (damped)."),
             damping: Optional[float] = typer.Option(None, "--damping",
                                                     help="DLS lambda in metres (default: automatic schedule)."),
             json_out: JsonOut = False) -> None:
    """Velocity kinematics: joint rates for a tool velocity (pseudo-inverse / DLS), or the twist of joint rates.

    Example: armkit velocity planar2 30 45 --deg --ee-vel 0.1 0
    Example: armkit velocity fighter 30 45 60 --deg --q-vel 10 0 0
    """
    from ..motion.velocity import joint_rates, twist

    r = get_robot(robot)
    words = list(q)
    if len(words) < r.n:
        fail(_("robot {robot!r} has {n} joints ({names}); got {k} value(s)", robot=r.name, n=r.n,
               names=name_list(r.joint_names), k=len(words)))
    qv = parse_q(r, words[:r.n], deg)
    extra = [w for v in words[r.n:] for w in v.split(",") if w]
    if (ee_vel is None) == (q_vel is None):
        fail(_("give exactly one of --ee-vel (tool velocity -> joint rates) and --q-vel (joint rates -> twist)"))
    given = ee_vel if ee_vel is not None else (q_vel or "")
    vals = parse_numbers([w for w in given.split(",") if w] + extra, "--ee-vel" if ee_vel is not None else "--q-vel")
    if method not in ("pinv", "dls"):
        fail(_("--method must be 'pinv' or 'dls', got {value!r}", value=method))
    if q_vel is not None:
        if len(vals) != r.n:
            fail(_("--q-vel needs {n} joint rates, got {k}", n=r.n, k=len(vals)))
        qd = np.where(r.prismatic, vals, np.radians(vals)) if deg else vals
        tw = twist(r, qv, qd)
        if json_out:
            print_json({"robot": r.name, "q_rad": qv, "qd_rad_s": qd, "twist": tw, "rows": ["vx", "vy", "vz", "wx",
                                                                                           "wy", "wz"]})
            return
        console.print(_("{robot} at q = ({q}), joint rates ({rates}) {unit}", robot=f"[bold]{esc(r.name)}[/]",
                        q=", ".join(q_display(r, qv)), rates=", ".join(f"{v:g}" for v in vals),
                        unit="deg/s" if deg else "rad/s"))
        console.print(_("tool velocity v = ({v}) {unit}/s", v=", ".join(sig(v) for v in tw[:3]), unit=r.unit))
        console.print(_("angular velocity w = ({w}) rad/s = ({w_deg}) deg/s", w=", ".join(sig(v) for v in tw[3:]),
                        w_deg=", ".join(sig(math.degrees(v)) for v in tw[3:])))
        return
    if len(vals) not in (2, 3, 6):
        fail(_("--ee-vel needs 2 (vx vy), 3 (vx vy vz) or 6 (vx vy vz wx wy wz) values, got {k}", k=len(vals)))
    res = joint_rates(r, qv, vals, method=method, damping="auto" if damping is None else damping)  # type: ignore[arg-type]
    qd_show = np.where(r.prismatic, res.qd, np.degrees(res.qd))
    if json_out:
        print_json({"robot": r.name, "q_rad": qv, "requested": vals, "rows": list(res.rows), "qd_rad_s": res.qd,
                    "achieved": res.achieved, "residual": res.residual, "sigma_min_m": res.sigma_min,
                    "singular": res.singular, "singular_direction": res.direction, "damping_m2": res.damping,
                    "method": res.method, "message": res.message})
        return
    console.print(_("{robot} at q = ({q}); requested ({values}) ({unit}/s, rad/s)", robot=f"[bold]{esc(r.name)}[/]",
                    q=", ".join(q_display(r, qv)), values=", ".join(f"{n} {v:g}" for n, v in zip(res.rows, vals)),
                    unit=r.unit))
    t = Table(title=_("joint rates ({method})", method=_("pseudo-inverse") if method == "pinv" else
                      _("damped least squares")),
              header_style="bold")
    for col in ("joint", "rad/s", "deg/s"):
        t.add_column(col, justify="right")
    for name, v, p in zip(r.joint_names, res.qd, r.prismatic):
        t.add_row(esc(name), sig(v) + (f" {r.unit}/s" if p else ""), "" if p else sig(math.degrees(v)))
    print_table(t)
    console.print(_("achieved: ({values}), residual {residual}", values=", ".join(sig(v) for v in res.achieved),
                    residual=f"{res.residual:.3g}")
                  + (_(", damping lambda^2 = {value} m^2", value=f"{res.damping:.3g}") if res.damping else ""))
    if res.singular:
        warn(_local(res.message))
    else:
        console.print(f"[dim]{esc(_local(res.message))}[/]")

    del qd_show


def _points(words: List[str], what: str) -> np.ndarray:
    pts = []
    for w in words:
        nums = parse_numbers([x for x in w.split(",") if x], what)
        pts.append(nums)
    if len({len(p) for p in pts}) > 1:
        fail(_("{what}: every point needs the same number of values, got {counts}", what=what,
               counts=[len(p) for p in pts]))
    return np.array(pts)


def _compute_traj(r: Any, P: np.ndarray, joint: bool, line: bool, arc: Optional[float], deg: bool, profile: str,
                  duration: Optional[float], qd_max: Optional[float], qdd_max: Optional[float], dt: float,
                  cart: dict[str, Any]) -> Any:
    """The trajectory ``traj`` asked for (``cart``: the Cartesian options blend, blend_shape, speed, steps, method)."""
    from ..motion.trajectory import cartesian_arc, cartesian_waypoints, joint_trajectory

    try:
        if joint:
            if P.shape[1] != r.n:
                fail(_("joint waypoints need {n} values each for {robot!r} ({names}), got {k}", n=r.n, robot=r.name,
                       names=name_list(r.joint_names), k=P.shape[1]))
            W = np.where(r.prismatic, P, np.radians(P)) if deg else P
            scale = math.pi / 180 if deg else 1.0
            if duration is None and qd_max is None and qdd_max is None:
                duration = 2.0
            tr = joint_trajectory(W, profile, duration=duration,
                                  qd_max=None if qd_max is None else qd_max * scale,
                                  qdd_max=None if qdd_max is None else qdd_max * scale, dt=dt, robot=r)
        elif line:
            if len(P) < 2:
                fail(_("--line needs at least two points (start ... end), got {n}", n=len(P)))
            if not cart["blend"] >= 0 or cart["blend_shape"] not in ("circular", "parabolic"):
                fail(_("--blend must be 0 or more and --blend-shape circular or parabolic, got {blend:g} and "
                       "{shape!r}", blend=cart["blend"], shape=cart["blend_shape"]))
            if cart["speed"] is not None and not cart["speed"] > 0:
                fail(_("--speed must be positive, got {speed:g}", speed=cart["speed"]))
            scale = math.pi / 180 if deg else 1.0
            tr = cartesian_waypoints(r, P, blend=cart["blend"], blend_shape=cart["blend_shape"],
                                     steps=cart["steps"], duration=duration or 2.0, method=cart["method"],
                                     speed=cart["speed"],
                                     qd_max=None if qd_max is None else qd_max * scale)
        else:
            if len(P) != 2:
                fail(_("--arc needs two points (centre start), got {k}", k=len(P)))
            tr = cartesian_arc(r, P[0], P[1], math.radians(float(arc)), steps=cart["steps"],  # type: ignore[arg-type]
                               duration=duration or 2.0, method=cart["method"], speed=cart["speed"])
    except UnreachableError as exc:
        fail(_("unreachable: {reason}", reason=_local(str(exc))), EXIT_FAILED)
    return tr


def _collision_note(r: Any, tr: Any, scene: Any, refuse: bool, summary: dict[str, Any]) -> tuple[Optional[str], str]:
    """Flag the samples of ``tr`` where the arm collides (armkit.collision): ``(note for JSON, text to show)``;
    with ``refuse`` a collision is a failure (exit 1, nothing written). Adds its counts to ``summary``."""
    hit_note, hit_text = None, ""
    if scene is not None:   # flag the samples where the arm collides (armkit.collision)

        from ..collision import collisions, in_collision

        hits = in_collision(r, tr.q, scene)
        summary["samples_in_collision"] = int(hits.sum())
        if hits.any():
            k = int(np.argmax(hits))
            what = collisions(r, tr.q[k], scene).message()
            hit_note = (f"{int(hits.sum())} of {len(tr)} samples collide; the first at t = {tr.t[k]:.3g} s: "
                        + what)                                        # JSON: as the library says it
            summary["first_collision"] = {"sample": k, "t": float(tr.t[k]), "message": hit_note}
            hit_text = _("{k} of {n} samples collide; the first at t = {t} s: {message}", k=int(hits.sum()),
                         n=len(tr), t=f"{tr.t[k]:.3g}", message=_local(what))
            if refuse:
                fail(hit_text + " " + _("(nothing written)"), EXIT_FAILED)
    return hit_note, hit_text


def traj(robot: RobotArg,
         points: List[str] = typer.Argument(..., metavar="POINT...",
                                            help="Comma-separated waypoints (joint values, or x,y[,z] for --line)."),
         joint: bool = typer.Option(False, "--joint", help="POINTs are joint-space waypoints."),
         line: bool = typer.Option(False, "--line", help="Two or more POINTs (x,y[,z]): straight lines of the tool "
                                                         "point through them, start to end."),
         blend: float = typer.Option(0.0, "--blend", help="--line corners: blend radius (length unit); the path "
                                                          "passes within it of each interior POINT. 0: sharp."),
         blend_shape: str = typer.Option("circular", "--blend-shape", help="--line corners: circular or parabolic."),
         speed: Optional[float] = typer.Option(None, "--speed", help="Cartesian paths: tool speed limit "
                                                                    "(length unit/s); lengthens the duration."),
         arc: Optional[float] = typer.Option(None, "--arc",
                                             help="Arc angle (deg): POINTs are the centre and the start point."),
         deg: Deg = False,
         profile: str = typer.Option("quintic", "--profile", help="cubic, quintic or trapezoid (joint space)."),
         duration: Optional[float] = typer.Option(None, "--duration",
                                                  help="Total time in seconds (default 2 s, or from the limits)."),
         qd_max: Optional[float] = typer.Option(None, "--qd-max", help="Joint speed limit (deg/s with --deg, else rad/s)."),
         qdd_max: Optional[float] = typer.Option(None, "--qdd-max", help="Joint acceleration limit (deg/s^2 or rad/s^2)."),
         steps: int = typer.Option(100, "--steps", help="Samples along a Cartesian path."),
         method: str = typer.Option("ik", "--method", help="Cartesian paths: 'ik' or 'rate' (resolved rate)."),
         dt: float = typer.Option(0.02, "--dt", help="Sample time for joint-space profiles (s)."),
         out: Optional[Path] = typer.Option(None, "-o", "--output",
                                          help="Write .png (plots), .gif/.mp4 (animation) or .csv."),
         out_alias: Optional[Path] = typer.Option(None, "--out", hidden=True),
         scene_file: Optional[str] = typer.Option(
             None, "--scene", help="Scene file (docs/scene.md): samples where the arm collides with it, its body or "
                                   "itself are counted. Default: the robot's own surroundings, if any."),
         no_scene: NoScene = False,
         refuse_collisions: bool = typer.Option(False, "--refuse-collisions",
                                                help="Exit 1 (and write nothing) when a sample collides."),
         json_out: JsonOut = False) -> None:
    """Trajectories: joint-space profiles through waypoints, or Cartesian lines and arcs (IK or resolved rate).

    Example: armkit traj fighter --joint 0,0,0 30,45,60 --deg --profile quintic --duration 2 -o traj.png
    Example: armkit traj planar2 --line 1.2,0.2 0.6,0.9 --steps 100 -o line.gif

    Example: armkit traj planar2 --line 1.2,0.2 1.0,0.8 0.4,1.0 --blend 0.1 -o corners.png
    """
    from ..viz.trajectory import animate_trajectory, plot_trajectory

    r = get_robot(robot)
    out = out if out is not None else out_alias         # --out: the old spelling of --output
    if out is not None:
        output_path(out, (".png", ".pdf", ".svg", ".gif", ".mp4", ".csv"), "--output")
    modes = sum([joint, line, arc is not None])
    if modes != 1:
        fail(_("choose exactly one of --joint, --line and --arc"))
    P = _points(points, "POINT")
    tr = _compute_traj(r, P, joint, line, arc, deg, profile, duration, qd_max, qdd_max, dt,
                       {"blend": blend, "blend_shape": blend_shape, "speed": speed, "steps": steps, "method": method})
    for note in tr.notes:
        warn(_local(note))          # a note built from its template and fields: in the user's language
    within = bool(np.all(r.within_limits(tr.q)))
    summary = {"robot": r.name, "label": tr.label, "samples": len(tr), "duration_s": tr.duration,
               "q_start_rad": tr.q[0], "q_end_rad": tr.q[-1], "max_abs_qd": np.abs(tr.qd).max(axis=0),
               "max_abs_qdd": np.abs(tr.qdd).max(axis=0), "within_limits": within,
               "max_deviation": None if tr.deviation is None else float(tr.deviation.max())}
    scene = scene_option(r, scene_file, no_scene)
    hit_note, hit_text = _collision_note(r, tr, scene, refuse_collisions, summary)
    if scene is not None:
        from ..collision import checked_against

        summary["checked_against"] = list(checked_against(r, scene))
    if out is not None:
        suffix = out.suffix.lower()
        if suffix == ".csv":
            tr.to_csv(out, r.joint_names)
        elif suffix in (".gif", ".mp4"):
            animate_trajectory(tr, r, out)
        elif suffix in (".png", ".pdf", ".svg"):
            plot_trajectory(tr, r, out)
        else:
            fail(_("-o must end in .png, .pdf, .svg, .gif, .mp4 or .csv, got {name!r}", name=out.name))
        summary["written"] = str(out)
    if json_out:
        print_json(summary)
        return
    console.print(_("{robot}: {label}, {n} samples over {seconds} s", robot=f"[bold]{esc(r.name)}[/]",
                    label=esc(_local(tr.label)), n=count(len(tr)), seconds=f"{tr.duration:.3g}"))
    console.print(_("start q = ({start}), end q = ({end})", start=", ".join(q_display(r, tr.q[0])),
                    end=", ".join(q_display(r, tr.q[-1]))))
    peak = np.where(r.prismatic, summary["max_abs_qd"], np.degrees(summary["max_abs_qd"]))
    console.print(_("peak joint speed:") + " " + esc(name_list([f"{n} {v:.4g}" for n, v in zip(r.joint_names, peak)]))
                  + " " + _("(deg/s or {unit}/s)", unit=r.unit))

    if tr.deviation is not None:
        message(_("largest deviation from the path: {value} {unit}", value=f"{tr.deviation.max():.3g}",
                  unit=r.unit))
    if not within:
        warn(_("the trajectory leaves the joint limits"))
    if hit_note is not None:
        warn(hit_text)
    if scene is not None:
        message(esc(checked_line(r, scene)))

    if out is not None:
        console.print(_("wrote {path}", path=esc(out)))



def register(app: typer.Typer) -> None:
    app.command()(derive)
    app.command()(singular)
    app.command(context_settings=NUMERIC_ARGS)(velocity)
    app.command(context_settings=NUMERIC_ARGS)(traj)
