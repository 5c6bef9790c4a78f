"""Velocity kinematics and trajectories (docs/motion.md): joint rates, a quintic joint path, a Cartesian line.

Run: python examples/04_motion.py [OUT_DIR]   (writes OUT_DIR/trajectory.csv and trajectory.png, default out/)
"""

import sys
from pathlib import Path

import numpy as np

import armkit
from armkit.motion import cartesian_line, joint_rates, joint_trajectory
from armkit.viz import plot_trajectory


def main(out_dir="out"):
    out = Path(out_dir)
    arm = armkit.load("planar2")
    r = joint_rates(arm, [0.3, 1.2], [0.1, 0.0])     # joint rates for a tool velocity (vx, vy)
    print("joint rates for vx = 0.1 m/s:", np.round(r.qd, 4), "residual", f"{r.residual:.1e}")
    r = joint_rates(arm, [0.3, 0.0], [0.1, 0.0], method="dls")   # stretched out: a singularity
    print("stretched:", r.message)
    tr = joint_trajectory([[0.0, 0.0], [1.0, -1.0], [0.5, 0.5]], "quintic", duration=3.0, robot=arm)
    print(f"joint trajectory: {len(tr.t)} samples over {tr.t[-1]:.1f} s, largest speed "
          f"{np.abs(tr.qd).max():.3f} rad/s")
    tr.to_csv(out / "trajectory.csv", arm.joint_names)
    line = cartesian_line(arm, [1.2, 0.2], [0.6, 0.9], steps=50)
    print(f"Cartesian line: {len(line.t)} samples, deviation from the line {line.deviation.max():.1e} m")
    plot_trajectory(line, arm, out / "trajectory.png")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
