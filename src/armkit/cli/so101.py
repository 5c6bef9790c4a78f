"""``armkit so101``: the SO-101 as LeRobot drives it (docs/so101.md, "Calibration and LeRobot").

``armkit so101 pose --calibration FILE --ticks T1 .. T5 [T6]`` turns servo readings (raw ticks,
or LeRobot's degrees / -100..100 values) into the bundled URDF's joint angles and the gripper
frame's pose, through a calibration file written by ``lerobot-calibrate`` (:mod:`armkit.lerobot`).
"""

from __future__ import annotations

import warnings
from typing import List

import numpy as np
import typer
from rich.table import Table

from ..kinematics import fk
from ..model import load
from ..spatial import rotation_to_rpy
from .common import N_, NUMERIC_ARGS, _, console, esc, fail, parse_numbers, pose_table, print_json, print_table, warn
from .common import JsonOut  # noqa: E402  (the shared options)

__all__ = ["register"]

so101_app = typer.Typer(help="The SO-101 with LeRobot: servo readings through a calibration file to joint angles "
                             "and the gripper's pose.\n\n"
                             "Example: armkit so101 pose --calibration examples/so101_calibration.json "
                             "--ticks 2048 2048 2048 2048 2048 2400",
                        no_args_is_help=True, rich_markup_mode="rich")


@so101_app.command(context_settings=NUMERIC_ARGS)
def pose(values: List[str] = typer.Argument(..., metavar="VALUE...",
                                            help="One value per motor in the file's order (shoulder_pan, "
                                                 "shoulder_lift, elbow_flex, wrist_flex, wrist_roll), the gripper "
                                                 "optional last."),
         calibration: str = typer.Option(..., "--calibration", "-c", help="Calibration JSON written by "
                                         "lerobot-calibrate (per motor: id, drive_mode, homing_offset, range_min, "
                                         "range_max)."),
         ticks: bool = typer.Option(False, "--ticks", help="The values are raw servo positions, 0..4095."),
         degrees: bool = typer.Option(False, "--degrees", help="The values are LeRobot's degrees (use_degrees=True; "
                                      "the gripper in 0..100)."),
         m100: bool = typer.Option(False, "--range-m100-100", help="The values are LeRobot's -100..100 (use_degrees="
                                   "False; the gripper in 0..100)."),
         json_out: JsonOut = False) -> None:
    """Joint angles and the gripper frame's pose of an SO-101 from its servo readings.

    Example: armkit so101 pose --calibration examples/so101_calibration.json --ticks 2048 2048 2048 2048 2048
    """
    from ..lerobot import ARM_MOTORS, GRIPPER, Calibration, CalibrationInputError, CalibrationRangeWarning

    chosen = [name for name, on in (("ticks", ticks), ("degrees", degrees), ("range_m100_100", m100)) if on]
    if len(chosen) != 1:
        fail(_("give the unit of the values: one of --ticks, --degrees or --range-m100-100"))
    mode = chosen[0]
    try:
        cal = Calibration.load(calibration)
    except CalibrationInputError as exc:          # one line in the user's language, exit 2
        fail(_(exc.template, **exc.fields))
    numbers = parse_numbers(values, N_("servo values"))
    names, arm = cal.motor_names, cal.arm_order
    if len(numbers) not in (len(names), len(arm)):
        fail(_("{file} has {n} motors ({names}): give {n} values, or {m} without the gripper; got {k}",
               file=calibration, n=len(names), names=", ".join(names), m=len(arm), k=len(numbers)))
    given = dict(zip(names if len(numbers) == len(names) else arm, numbers))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", CalibrationRangeWarning)
        try:
            ticks_of = cal.to_ticks(given, mode)
            q = cal.to_q(given, mode)
        except CalibrationInputError as exc:
            fail(_(exc.template, **exc.fields))
    notes = list(dict.fromkeys(_said(w.message) for w in caught if issubclass(w.category, CalibrationRangeWarning)))
    robot = load("so101")
    T = fk(robot, q)
    outside = [f"{n} {np.degrees(v):.1f}" for n, v, lo, hi in zip(ARM_MOTORS, q, robot.lower, robot.upper)
               if v < lo - 1e-12 or v > hi + 1e-12]
    gripper_pct = None if GRIPPER not in ticks_of else float(cal.normalize(GRIPPER, ticks_of[GRIPPER], "range_0_100"))
    rpy = np.degrees(rotation_to_rpy(T[:3, :3]))
    if json_out:
        print_json({"calibration": calibration, "mode": mode, "values": given,
                    "ticks": {k: float(v) for k, v in ticks_of.items()},
                    "q_rad": dict(zip(ARM_MOTORS, q)), "q_deg": dict(zip(ARM_MOTORS, np.degrees(q))),
                    "gripper_range_0_100": gripper_pct, "pose": T, "position": T[:3, 3], "rpy_deg": rpy,
                    "warnings": notes + ([_("outside the URDF's joint limits: {joints}", joints=", ".join(outside))]
                                         if outside else [])})
    else:
        unit = {"ticks": _("tick"), "degrees": "deg", "range_m100_100": "-100..100"}[mode]
        t = Table(title=_("SO-101 joints from {file}", file=esc(calibration)), header_style="bold")
        cols = (_("motor"), _("value ({unit})", unit=unit)) + (() if mode == "ticks" else (_("tick"),)) + ("q (deg)",)
        for col in cols:
            t.add_column(col, justify="right")

        def row(name: str, last: str) -> None:
            tick = () if mode == "ticks" else (f"{ticks_of[name]:.1f}",)
            t.add_row(esc(name), f"{given[name]:g}", *tick, last)

        for i, name in enumerate(ARM_MOTORS):
            row(name, f"{np.degrees(q[i]):.3f}")
        if gripper_pct is not None:
            row(GRIPPER, _("open: {pct} %", pct=f"{gripper_pct:.1f}"))
        print_table(t)
        p = T[:3, 3]
        console.print(_("end point: ({xyz}) {unit}", xyz=f"[bold]{p[0]:.4f}, {p[1]:.4f}, {p[2]:.4f}[/]", unit="m")
                      + f"   roll/pitch/yaw: ({rpy[0]:.3f}, {rpy[1]:.3f}, {rpy[2]:.3f}) deg")
        print_table(pose_table(T, "m", title="T_base_link_gripper_frame_link"))
    for note in notes:
        warn(note)
    if outside:
        warn(_("outside the URDF's joint limits: {joints}", joints=", ".join(outside)))


def _said(w: Warning | str) -> str:
    """A :class:`~armkit.errors.CalibrationRangeWarning` in the user's language, from its templates and fields."""
    template = getattr(w, "template", None)
    if template is None:
        return str(w)
    notes = "; ".join(_(t, **f) for t, f in getattr(w, "notes", ()))
    return _(template, **dict(getattr(w, "fields", {}), notes=notes))


def register(app: typer.Typer) -> None:
    app.add_typer(so101_app, name="so101")
