"""Robot files (docs/robot-files.md): write an arm as TOML by hand, load it, save it back, see a file error.

Run: python examples/07_robot_files.py [OUT_DIR]   (writes OUT_DIR/my_arm.toml and my_arm_saved.toml)
"""

import sys
from pathlib import Path

import numpy as np

import armkit

MY_ARM = """\
name = "my_arm"
description = "a 3-DOF arm measured with calipers"
unit = "mm"
angle_unit = "deg"

[[joints]]
name = "yaw"
d = 36
alpha = 90

[[joints]]
name = "shoulder"
a = 77.2

[[joints]]
name = "elbow"
a = 100
limits = [-150, 150]
"""


def main(out_dir="out"):
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    (out / "my_arm.toml").write_text(MY_ARM)
    arm = armkit.load(out / "my_arm.toml")
    print(arm.name, arm.n, "joints, unit", arm.unit, "- elbow limits (deg):", np.degrees([arm.lower[2], arm.upper[2]]).round(1))
    print("tool at (30, 45, 60) deg:", armkit.fk(arm, np.radians([30, 45, 60]))[:3, 3].round(3), arm.unit)
    saved = armkit.save(arm, out / "my_arm_saved.toml")
    print("saved and loaded again, the same value:", armkit.load(saved) == arm)
    (out / "broken.toml").write_text(MY_ARM.replace("a = 100", "a = 'long'"))
    try:
        armkit.load(out / "broken.toml")
    except armkit.RobotFileError as exc:            # names the file, the line and the field
        print("a mistake in a file:", exc)
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
