"""The textbook arms with prismatic joints, and a gimbal: every inverse-kinematics branch in closed form.

Run: python examples/18_textbook_arms.py
A textbook's chapter on arm types shows the Cartesian (PPP), cylindrical (RPP), spherical (RRP) and SCARA
(RRPR) arms. Each is written here as DH rows (a prismatic joint slides along z: its d is the joint
variable), and armkit names its class from the axes and solves it: every branch, each checked by FK, with
the slides in metres and the angles in degrees. A branch that needs a slide outside its stroke says so.
"""

import math
import sys

import numpy as np

import armkit
from armkit import Joint, Robot
from armkit.ik.geometric.classify import classify, describe

HALF = math.pi / 2


def arms():
    """(robot, target) pairs: DH rows (theta, d, a, alpha) with the joint's own limits."""
    cartesian = Robot([Joint("prismatic", lower=0.0, upper=1.0, name="x"),
                       Joint("prismatic", theta=-HALF, alpha=-HALF, lower=0.0, upper=1.0, name="y"),
                       Joint("prismatic", alpha=-HALF, lower=0.0, upper=1.0, name="z")], "modified", name="cartesian")
    cylindrical = Robot([Joint("revolute", d=0.3, lower=-math.pi, upper=math.pi, name="turn"),
                         Joint("prismatic", alpha=-HALF, lower=0.0, upper=0.5, name="lift"),
                         Joint("prismatic", lower=0.1, upper=0.6, name="reach")], name="cylindrical")
    spherical = Robot([Joint("revolute", d=0.4, alpha=-HALF, lower=-math.pi, upper=math.pi, name="waist"),
                       Joint("revolute", alpha=HALF, lower=-math.pi, upper=math.pi, name="shoulder"),
                       Joint("prismatic", lower=0.2, upper=0.8, name="boom")], name="spherical")
    scara = Robot([Joint("revolute", d=0.4, a=0.35, lower=-2.5, upper=2.5, name="shoulder"),
                   Joint("revolute", a=0.3, alpha=math.pi, lower=-2.5, upper=2.5, name="elbow"),
                   Joint("prismatic", lower=0.0, upper=0.3, name="quill"),
                   Joint("revolute", d=0.05, lower=-math.pi, upper=math.pi, name="wrist")], name="scara")
    gimbal = Robot([Joint("revolute", axis=(0, 0, 1), name="yaw"), Joint("revolute", axis=(0, 1, 0), name="pitch"),
                    Joint("revolute", axis=(1, 0, 0), name="roll")], "urdf", name="gimbal")
    scara_pose = armkit.fk(scara, np.array([0.6, -1.1, 0.12, 0.4]))         # a pose the SCARA can reach
    gimbal_pose = armkit.fk(gimbal, np.radians([30.0, -20.0, 45.0]))
    return [(cartesian, np.array([0.3, 0.5, 0.2])), (cylindrical, np.array([0.2, 0.3, 0.5])),
            (spherical, np.array([0.3, -0.2, 0.6])), (scara, scara_pose), (gimbal, gimbal_pose)]


def show(robot, target):
    cls = classify(robot)
    print(f"\n{robot.name} ({robot.joint_types}): class {cls.name!r}: {describe(cls)}")
    res = armkit.ik_all(robot, target)
    slides = np.asarray(robot.chain.prismatic)
    head = "  branch " + "".join(f"{name + (' m' if s else ' deg'):>14}" for name, s in zip(robot.joint_names, slides))
    print(head + "   pos. error   result")
    for b in range(len(res.q)):
        q = np.where(slides, res.q[b], np.degrees(res.q[b]))
        print(f"  {res.branch[b]:<6} " + "".join(f"{v:14.4f}" for v in q)
              + f"   {float(res.position_error[b]):9.1e}   {res.reason[b]}")
    ok = np.asarray(res.success)
    reached = armkit.fk(robot, res.q[ok])
    goal = target if target.shape == (4, 4) else None
    err = (np.abs(reached - goal).max() if goal is not None else np.abs(reached[:, :3, 3] - target).max()) if ok.any() else 0
    print(f"  {int(ok.sum())} of {len(res.q)} branches solve it; the largest FK difference of those: {err:.1e}")
    return int(ok.sum())


def main(out_dir=None):
    solved = [show(robot, target) for robot, target in arms()]
    assert all(solved), solved
    # the cylindrical arm by hand: its tool is at (-d3 sin q1, d3 cos q1, 0.3 + d2), so for (0.2, 0.3, 0.5)
    # d2 = 0.2, d3 = sqrt(0.2² + 0.3²) and q1 = atan2(-0.2, 0.3)
    robot, target = arms()[1]
    best = armkit.ik(robot, target)
    hand = np.array([math.atan2(-0.2, 0.3), 0.2, math.hypot(0.2, 0.3)])
    print(f"\ncylindrical by hand: q1 = {math.degrees(hand[0]):.4f} deg, d2 = {hand[1]:.4f} m, d3 = {hand[2]:.4f} m;"
          f" armkit.ik agrees to {np.abs(best.q - hand).max():.1e}")
    assert np.allclose(best.q, hand, atol=1e-12)
    # the SCARA given a position alone: its wrist turns the tool about the tool point and never moves it, so it is
    # held where it starts (q0) and the first three joints give both elbow branches in closed form
    robot = arms()[3][0]
    point = np.array([0.45, 0.25, 0.2])
    start = np.array([0.0, 0.0, 0.0, 0.7])
    every = armkit.ik_all(robot, point, q0=start)
    print(f"\nscara, a position alone {point.tolist()} m: {every.message[0]}")
    for b in range(len(every.q)):
        print(f"  {every.branch[b]:<6} shoulder {math.degrees(every.q[b, 0]):9.4f} deg, elbow "
              f"{math.degrees(every.q[b, 1]):9.4f} deg, quill {every.q[b, 2]:.4f} m, wrist "
              f"{math.degrees(every.q[b, 3]):.4f} deg: {every.reason[b]}")
    assert every.success.all() and np.all(every.q[:, 3] == 0.7)
    assert np.allclose(armkit.fk(robot, every.q)[:, :3, 3], point, atol=1e-12)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
