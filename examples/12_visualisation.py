"""Seeing the arm (docs/visualisation.md): the arm at a few configurations, its workspace, a tracking GIF.

Run: python examples/12_visualisation.py [OUT_DIR]   (writes three pictures into OUT_DIR, default out/)
"""

import sys
from pathlib import Path

import numpy as np

import armkit
from armkit.analysis.workspace import workspace
from armkit.viz import plot_arm, plot_workspace, render_animation, save_figure, track


def main(out_dir="out"):
    out = Path(out_dir)
    arm = armkit.load("fighter")
    q = np.radians([[0, 30, 60], [45, 60, -30], [-90, 90, 0]])
    save_figure(plot_arm(arm, q, labels=["rest", "reach", "side"]), out / "fighter_arms.png")
    ws = workspace(arm, samples=20_000)
    print("workspace:", ws.summary())
    save_figure(plot_workspace(ws), out / "fighter_workspace.png")
    res = track(armkit.load("planar3"), path="circle", method="ccd", frames=40)
    print(f"tracking a circle with CCD: {int(res.reached.sum())} of {len(res.q)} frames reached, largest error "
          f"{res.error.max():.2g} m")
    render_animation(res.robot, res.q, out / "planar3_track.gif", targets=res.targets, fps=10, progress=False)
    print("wrote", ", ".join(p.name for p in sorted(out.glob("*.png")) + sorted(out.glob("*.gif"))))
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
