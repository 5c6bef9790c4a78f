"""The main job (`make demo`): the bundled fighter arm of the club's fighting-robot report, end to end.

Prints its DH table, forward kinematics at a few configurations (checked against the
point worked out by hand from the report's DH table; the report itself prints no number), the Jacobian and manipulability, every closed-form IK branch for a
target, and writes pictures into ``out/``. IK, the workspace and the tracking GIF honour the
fighter's own surroundings (its torso and the ground), as the command line does.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table

import armkit

console = Console(highlight=False)


def main(out_dir: str = "out") -> int:
    arm = armkit.load("fighter")
    console.rule(f"[bold]armkit demo: {arm.name}[/]")
    console.print(arm.description)
    from armkit.cli.core import info

    info(arm.name, json_out=False, dh=False, convention="standard")

    t = Table(title="Forward kinematics: end point (mm) for joint angles (deg)", header_style="bold")
    for col in ("theta1", "theta2", "theta3", "x", "y", "z", "manipulability (m³)"):
        t.add_column(col, justify="right")
    configs = np.array([[0, 0, 0], [30, 45, 60], [90, 90, 0], [-45, 30, -120]], dtype=float)
    T = armkit.fk(arm, np.radians(configs))
    w = armkit.manipulability(arm, np.radians(configs))
    for qd, Ti, wi in zip(configs, T, w):
        t.add_row(*(f"{v:g}" for v in qd), *(f"{v:.3f}" for v in Ti[:3, 3]), f"{wi:.3g}" if wi > 1e-12 else "0 (singular)")
    console.print(t)
    p = T[1, :3, 3]
    ok = np.allclose(p, [24.861, 14.353, 187.181], atol=5e-4)
    console.print(f"worked out by hand from the report's DH table: (30, 45, 60) deg -> (24.861, 14.353, 187.181) mm; armkit: "
                  f"({p[0]:.3f}, {p[1]:.3f}, {p[2]:.3f}) mm [{'green' if ok else 'red'}]{'match' if ok else 'MISMATCH'}[/]")

    if hasattr(armkit, "ik_all"):
        res = armkit.ik_all(arm, p)   # scene=None: the robot's own surroundings (torso, ground)
        t = Table(title=f"Every closed-form IK branch for the target ({p[0]:.3f}, {p[1]:.3f}, {p[2]:.3f}) mm",
                  header_style="bold")
        t.add_column("branch", no_wrap=True)
        for col in ("theta1 (deg)", "theta2 (deg)", "theta3 (deg)", "position error (mm)", "ok"):
            t.add_column(col, justify="right")
        for k in range(res.q.shape[0]):
            t.add_row(str(res.branch[k]), *(f"{v:.3f}" for v in np.degrees(res.q[k])),
                      f"{res.position_error[k]:.2e}", "yes" if res.success[k] else f"no ({res.reason[k]})")
        console.print(t)
        console.print(f"checked against: {', '.join(res.checked_against)}")

    try:
        from armkit.viz import write_demo_pictures
    except ImportError:
        return 0
    console.print(f"writing pictures into {out_dir}/ ...")
    report: list[str] = []
    paths = write_demo_pictures(out_dir, progress=False, report=report)
    for line in report:
        console.print(line, soft_wrap=True)
    for path in paths:
        console.print(f"  wrote {Path(path)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
