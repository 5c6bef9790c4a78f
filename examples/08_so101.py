"""The SO-101 arm (docs/so101.md): position, position + tool pitch, a pointing direction, an honest failure.

Run: python examples/08_so101.py
"""

import math
import sys

import numpy as np

import armkit
from armkit.ik import closed_form_family


def main(out_dir=None):
    arm = armkit.load("so101")                        # a bundled URDF arm, 5 joints, metres
    print(arm.joint_names, "- closed form:", closed_form_family(arm))
    target = [0.2, 0.05, 0.05]
    res = armkit.ik(arm, target)
    print("position only:   ", bool(res.success), np.degrees(res.q).round(2))
    res = armkit.ik(arm, target, pitch=-math.pi / 2)  # pick from above
    print("pitch -90 deg:   ", bool(res.success), res.branch, np.degrees(res.q).round(2))
    res = armkit.ik(arm, [0.25, 0.0, 0.1], direction=[1, 0, -1])
    print("pointing down 45:", bool(res.success), "tool z axis", armkit.fk(arm, res.q)[:3, 2].round(4))
    T = armkit.fk(arm, np.radians([20, 10, 30, 40, 0])) @ armkit.spatial.rotx(0.3)
    res = armkit.ik(arm, T)                          # 5 joints cannot reach every orientation
    print("a full pose:     ", bool(res.success), res.reason, "-", res.message[:90], "...")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
