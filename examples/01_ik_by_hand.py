"""Inverse kinematics by hand: a damped least-squares loop on fk, jacobian and spatial, then armkit.ik.

Run: python examples/01_ik_by_hand.py
The loop moves q by dq = J^T (J J^T + lambda^2 I)^-1 e, where e is the pose error twist
(position error, then the rotation vector of R_target R^T, both in the base frame).
"""

import sys

import numpy as np

import armkit
from armkit import spatial


def main(out_dir=None):
    arm = armkit.load("puma560")
    T_goal = armkit.fk(arm, [0.3, -0.5, 0.4, 0.2, 0.6, -0.3])   # a pose we know is reachable
    q = np.zeros(arm.n)
    for i in range(100):
        T = armkit.fk(arm, q)
        e = np.concatenate([T_goal[:3, 3] - T[:3, 3],
                            spatial.so3_log(T_goal[:3, :3] @ T[:3, :3].T)])   # (v, omega), base frame
        if np.linalg.norm(e) < 1e-10:
            break
        J = armkit.jacobian(arm, q)                                           # (6, n), base frame
        q = q + J.T @ np.linalg.solve(J @ J.T + 1e-4 * np.eye(6), e)          # damping lambda = 0.01
        if i % 5 == 0:
            print(f"iteration {i:2d}: |e| = {np.linalg.norm(e):.3e}")
    dp, dr = spatial.pose_error(armkit.fk(arm, q), T_goal)
    print(f"by hand: {i} iterations, position error {dp:.1e} m, rotation error {dr:.1e} rad")
    res = armkit.ik(arm, T_goal, q0=np.zeros(arm.n), method="lm")
    print(f"armkit.ik (lm): {int(res.iterations)} iterations, position error {res.position_error:.1e} m, "
          f"success {bool(res.success)}")
    assert dp < 1e-9 and dr < 1e-9 and res.success
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
