"""Inverse kinematics (docs/ik.md): every closed-form branch, the numeric methods, and an honest failure.

Run: python examples/03_ik_methods.py
"""

import sys

import numpy as np

import armkit


def main(out_dir=None):
    arm = armkit.load("puma560")
    T = armkit.fk(arm, [0.4, -0.6, 0.3, 0.5, 0.7, -0.2])
    every = armkit.ik_all(arm, T)                    # all 8 closed-form branches
    for branch, ok, q in zip(every.branch, every.success, every.q):
        print(f"{branch:28s} {'ok ' if ok else 'no '} {np.degrees(q).round(1)}")
    for method in ("analytic", "lm", "newton"):
        res = armkit.ik(arm, T, q0=np.zeros(arm.n), method=method)
        print(f"{method:8s}: success {bool(res.success)}, position error {res.position_error:.1e} m")
    far = armkit.ik(arm, [5.0, 0.0, 0.0])            # well outside the reach: success=False, and why
    print("unreachable:", bool(far.success), far.reason, "-", far.message)
    batch = armkit.ik(arm, armkit.fk(arm, arm.random_q(200, np.random.default_rng(1))))  # (200, 4, 4) at once
    print(f"a batch of 200 poses: {int(batch.success.sum())} solved")
    assert every.success.any() and not far.success
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
