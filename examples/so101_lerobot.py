"""The SO-101 with LeRobot (docs/lerobot.md): servo ticks -> joint angles -> the gripper's path, and one teleop step.

Reads the calibration file ``lerobot-calibrate`` wrote (examples/so101_calibration.json) and a
recorded trajectory in raw STS3215 ticks (examples/so101_recording.csv, 10 Hz), turns every
sample into the gripper's pose, draws the path (PNG into the folder given), then moves the
gripper 2 cm up with the drop-in ``RobotKinematics`` and says what it met.

Run: python examples/so101_lerobot.py [output folder]
"""

import sys
from pathlib import Path

import numpy as np

import armkit
from armkit.lerobot import Calibration, RobotKinematics

HERE = Path(__file__).resolve().parent


def main(out_dir="out"):
    cal = Calibration.load(HERE / "so101_calibration.json")
    rec = np.loadtxt(HERE / "so101_recording.csv", delimiter=",", skiprows=2)   # time_s, then the 6 motors
    t, ticks = rec[:, 0], rec[:, 1:]
    q = cal.to_q(ticks, mode="ticks")                 # (41, 5) rad: the bundled URDF's joint angles
    arm = armkit.load("so101")                        # so101_new_calib.urdf, the URDF LeRobot's calibration fits
    T = armkit.fk(arm, q)                             # (41, 4, 4) gripper poses, metres
    path = T[:, :3, 3]
    print(f"{len(t)} samples over {t[-1]:.1f} s; first joints (deg): {np.degrees(q[0]).round(1)}")
    print(f"gripper path: from {path[0].round(3)} to {path[-1].round(3)} m, "
          f"{np.linalg.norm(np.diff(path, axis=0), axis=1).sum() * 100:.1f} cm long")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    fig = plt.figure(figsize=(6, 5))
    ax = fig.add_subplot(projection="3d")
    ax.plot(*path.T, "-o", ms=2, label="gripper (gripper_frame_link)")
    ax.quiver(*path[::5].T, *(0.03 * T[::5, :3, 2]).T, color="tab:red", label="approach axis (z)")
    ax.scatter([0], [0], [0], color="k", label="base")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)")
    ax.set_title("SO-101: a recording in servo ticks, as gripper poses")
    ax.legend(loc="upper left", fontsize=8)
    png = out / "so101_path.png"
    fig.savefig(png, dpi=100)
    plt.close(fig)
    print("wrote", png)

    # one teleoperation step, as a LeRobot script calls it: degrees in and out, the jaw carried along
    kin = RobotKinematics(str(Path(armkit.model.files.BUNDLED_DIR) / "so101.urdf"))
    current = np.append(np.degrees(q[-1]), 20.0)
    desired = kin.forward_kinematics(current)
    desired[2, 3] += 0.02                             # 2 cm up, the orientation kept
    goal = kin.inverse_kinematics(current, desired)
    print(f"2 cm up: stage {kin.last_stage!r}, success {bool(kin.last_result.success)}, position error "
          f"{kin.last_pose_error[0]:.1e} m, joints (deg) {goal.round(2)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
