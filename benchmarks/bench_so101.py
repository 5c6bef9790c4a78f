"""SO-101 (5 joints): the IK modes over N reachable and M unreachable targets each, and teleoperation beside placo.

Part 1, the modes. Targets are FK of ``--n`` (default 10,000) joint vectors drawn uniformly inside
the limits (seeded); ``--far`` (default 1,000) unreachable targets lie 1-30 cm beyond the reach
measured from the shoulder, in random directions. Modes:

* position only: Levenberg-Marquardt (``armkit.ik(arm, xyz, method="lm")``, what ``armkit.ik`` did by
  default before issue 20), the closed form (:func:`armkit.ik.analytic.yaw_pitch3.position_ik`: the member
  of the 1-D family nearest q0), and ``armkit.ik(arm, xyz)`` with its defaults, which routes a single
  SO-101 position to that closed form (LM for the few targets it leaves, and beyond the reach);
* position + tool pitch (``armkit.ik(arm, xyz, pitch=...)``: the yaw-pitch3 closed form, the
  roll joint kept at q0, which is given the roll the target came from), and ``ik_all``;
* position + pointing direction of the tool's z axis (``armkit.ik(arm, xyz, direction=...)``);
* 6-D poses turned by 20 deg about the tool's x axis (unreachable for 5 joints): how many
  fail honestly (reason "unreachable", "5 joints cannot reach ...") and the misses reported.

"wrong" counts answers flagged as success although an independent FK check fails (position
within 1e-9 m, pitch within 1e-9 rad, pointing direction within 1e-7 rad, joints within limits);
"honest" counts unreachable targets answered ``success=False`` with reason ``"unreachable"``.

Part 2, teleoperation: ``armkit.lerobot.RobotKinematics`` (the drop-in class) beside LeRobot's
own way of solving, placo (one weighted solver step per call, as LeRobot's
``lerobot.model.kinematics.RobotKinematics`` does; built here from placo's API on the same URDF),
in the same process: the time of one call (median and best of ``--calls``) for a target held still,
a 5 mm step with LeRobot's default weights (position 1, orientation 0.01), and position only; then
a sustained loop of ``--loop`` calls that follows a 5 cm circle, each answer fed back as
the next current joints (calls per second, and the worst distance between the gripper and the
commanded point). placo is optional: it pins an older pin, so ``make bench-so101`` gives it its own ``.venv-placo`` (armkit + placo).

Usage::

    make bench-so101     # a few minutes on 2 cores (.venv-placo); then LeRobot's own class: tests/peers/test_lerobot_peer.py
    .venv/bin/python benchmarks/bench_so101.py --n 1000 --far 100  # without placo: armkit alone
"""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import re
import time

import numpy as np

os.environ.setdefault("ARMKIT_JIT", "wait")   # compile in this process: time compiled kernels, never the NumPy stand-in

import armkit  # noqa: E402
from armkit.ik.analytic.yaw_pitch3 import pitch_of, position_ik, shoulder_reach  # noqa: E402
from armkit.ik.numeric import shoulder_distance  # noqa: E402
from armkit.lerobot import RobotKinematics  # noqa: E402
from armkit.model.files import BUNDLED_DIR  # noqa: E402

URDF = os.path.join(BUNDLED_DIR, "so101.urdf")
JOINTS = ["shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex", "wrist_roll", "gripper"]


def check(arm, q, p, pitch=None, direction=None):
    """Independent FK check of answers ``q`` (B, 5): position, pitch or direction, limits."""
    T = armkit.fk(arm, q)
    ok = np.linalg.norm(T[:, :3, 3] - p, axis=-1) <= 1e-9
    if pitch is not None:
        ok &= np.abs(np.remainder(pitch_of(arm, q, p) - pitch + math.pi, 2 * math.pi) - math.pi) <= 1e-9
    if direction is not None:
        ok &= np.arccos(np.clip(np.sum(T[:, :3, 2] * direction, axis=-1), -1.0, 1.0)) <= 1e-7
    return ok & np.all((q >= arm.lower - 1e-12) & (q <= arm.upper + 1e-12), axis=-1)


def timed(fn):
    t = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - t


def per_call(fn, k):
    """Median and best time (s) of ``fn(i)`` over ``i < k``."""
    times = []
    for i in range(k):
        t = time.perf_counter()
        fn(i)
        times.append(time.perf_counter() - t)
    return float(np.median(times)), float(np.min(times))


def far_targets(arm, m, rng):
    """``m`` points 1-30 cm beyond the reach from the shoulder (unreachable whatever the joints)."""
    sh = shoulder_reach(arm)
    c, reach = sh[0], sh[-1]
    d = rng.normal(size=(m, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    pts = c + d * (reach + 0.05 + rng.uniform(0.01, 0.30, m))[:, None]
    assert np.all(shoulder_distance(sh, pts) > reach)
    return pts


def modes(args) -> None:
    arm = armkit.load("so101")
    n, m = args.n, args.far
    q = arm.random_q(n, rng=args.seed)
    T = armkit.fk(arm, q)
    p, d = T[:, :3, 3], T[:, :3, 2]
    psi = pitch_of(arm, q)
    q0 = np.zeros_like(q)
    q0[:, 4] = q[:, 4]
    rng = np.random.default_rng(args.seed)
    far = far_targets(arm, m, rng)
    far_psi = rng.uniform(-math.pi, math.pi, m)
    far_dir = rng.normal(size=(m, 3))
    far_dir /= np.linalg.norm(far_dir, axis=1, keepdims=True)
    armkit.ik(arm, p[:50])                                   # warm-up (kernels loaded or compiled)
    armkit.ik(arm, p[:50], q0=q0[:50], pitch=psi[:50])
    armkit.ik(arm, p[0], q0=q0[0], pitch=psi[0])
    armkit.ik(arm, p[:50], direction=d[:50])
    rows = []

    res, t = timed(lambda: armkit.ik(arm, p, method="lm", seed=1))
    one = per_call(lambda i: armkit.ik(arm, p[i], method="lm", seed=1), args.single)[0]
    out = armkit.ik(arm, far, method="lm", seed=1)
    rows.append(("position (LM)", res.success, check(arm, res.q, p), t, one, out))

    # the closed form for a position alone (issue 20): position_ik (None: the general path, as armkit.ik goes)
    def closed(pts, q0=None):
        r = position_ik(arm, pts, q0)
        return r if r is not None else armkit.ik(arm, pts, q0)

    closed(p[:50])
    closed(p[0])
    res, t = timed(lambda: closed(p))
    one = per_call(lambda i: closed(p[i]), args.single)[0]
    out = closed(far)
    rows.append(("position (closed form)", res.success, check(arm, res.q, p), t, one, out))

    # armkit.ik(arm, xyz) with its defaults: a single target goes to the closed form (a batch: LM, as before);
    # its "batch" column is a Python loop of single calls over the targets
    armkit.ik(arm, p[0])
    qs, ok = np.empty((n, 5)), np.empty(n, dtype=bool)
    t0 = time.perf_counter()
    for i in range(n):
        r = armkit.ik(arm, p[i])
        qs[i], ok[i] = r.q, r.success
    t = time.perf_counter() - t0
    one = per_call(lambda i: armkit.ik(arm, p[i]), args.single)[0]
    out = armkit.ik(arm, far)
    rows.append(("position (armkit.ik default)", ok, check(arm, qs, p), t, one, out))

    res, t = timed(lambda: armkit.ik(arm, p, q0=q0, pitch=psi))
    one = per_call(lambda i: armkit.ik(arm, p[i], q0=q0[i], pitch=psi[i]), args.single)[0]
    out = armkit.ik(arm, far, pitch=far_psi)
    rows.append(("position + pitch (closed form)", res.success, check(arm, res.q, p, pitch=psi), t, one, out))

    every, t_all = timed(lambda: armkit.ik_all(arm, p, q0=q0, pitch=psi))
    ok_all = every.success
    wrong_all = 0
    for j in range(every.q.shape[1]):
        wrong_all += int(np.sum(ok_all[:, j] & ~check(arm, every.q[:, j], p, pitch=psi)))

    res, t = timed(lambda: armkit.ik(arm, p, direction=d, seed=2))
    one = per_call(lambda i: armkit.ik(arm, p[i], direction=d[i], seed=2), min(args.single, 50))[0]
    out = armkit.ik(arm, far, direction=far_dir, seed=2)
    rows.append(("position + direction", res.success, check(arm, res.q, p, direction=d), t, one, out))

    print(f"SO-101, {n:,} random reachable and {m:,} unreachable targets per mode (random numbers seeded with {args.seed})\n")
    print(f"{'mode':32} {'solved':>9} {'wrong':>6} {'batch us/target':>16} {'single us':>10} "
          f"{'unreachable: honest':>20}")
    for name, success, good, t, one, out in rows:
        wrong = int(np.sum(success & ~good))
        honest = int(np.sum(~out.success & (out.reason == "unreachable")))
        print(f"{name:32} {100 * success.mean():8.2f}% {wrong:6d} {t / n * 1e6:16.1f} {one * 1e6:10.1f} "
              f"{honest:>10,} of {m:,}")
    print(f"\nik_all with pitch: {100 * ok_all.any(axis=1).mean():.2f}% of targets with a branch, "
          f"{ok_all.sum(axis=1).mean():.2f} successful branches per target (of 4; the others break limits "
          f"or are out of reach), {wrong_all} wrong, {t_all / n * 1e6:.1f} us/target")

    k = min(n, 200)
    c, s = math.cos(math.radians(20)), math.sin(math.radians(20))
    turn = np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])
    res, t = timed(lambda: armkit.ik(arm, T[:k] @ turn, seed=3))
    honest = (~res.success) & (res.reason == "unreachable")
    miss = [float(mm.group(1)) for msg in res.message if (mm := re.search(r"misses by ([0-9.]+) deg", str(msg)))]
    print(f"\n6-D poses turned 20 deg about the tool's x ({k}): {int(res.success.sum())} flagged solved, "
          f"{int(honest.sum())} honest failures ('{str(res.message[0]).split(';')[0]}'), reported miss "
          f"{min(miss):.1f}-{max(miss):.1f} deg (median {np.median(miss):.1f}), {t / k * 1e3:.1f} ms/target")


# ---------------------------------------------------------------------------------------- teleoperation
class PlacoLikeLeRobot:
    """placo driven as LeRobot's ``RobotKinematics`` drives it: joints set from the current degrees, the
    frame task's target and weights set ("soft"), one ``solve(True)`` step, the joints read back."""

    def __init__(self, urdf: str, joint_names: list[str]):
        import placo

        with open(os.devnull, "w") as null, contextlib.redirect_stdout(null):   # its collision-pair notes
            self.robot = placo.RobotWrapper(urdf)
        self.solver = placo.KinematicsSolver(self.robot)
        self.solver.mask_fbase(True)
        self.joint_names = joint_names
        self.task = self.solver.add_frame_task("gripper_frame_link", np.eye(4))

    def forward_kinematics(self, deg):
        for name, v in zip(self.joint_names, np.radians(deg[: len(self.joint_names)])):
            self.robot.set_joint(name, v)
        self.robot.update_kinematics()
        return self.robot.get_T_world_frame("gripper_frame_link")

    def inverse_kinematics(self, current, T, position_weight=1.0, orientation_weight=0.01):
        for name, v in zip(self.joint_names, np.radians(current[: len(self.joint_names)])):
            self.robot.set_joint(name, v)
        self.task.T_world_frame = T
        self.task.configure("gripper_frame_link", "soft", position_weight, orientation_weight)
        self.solver.solve(True)
        self.robot.update_kinematics()
        out = np.array(current, dtype=float)
        out[: len(self.joint_names)] = np.degrees([self.robot.get_joint(nm) for nm in self.joint_names])
        return out


def teleop(args) -> None:
    arm = armkit.load("so101")
    solvers: dict[str, object] = {"armkit": RobotKinematics(URDF, joint_names=JOINTS)}
    try:
        solvers["placo (LeRobot's way)"] = PlacoLikeLeRobot(URDF, JOINTS)
    except ImportError:
        print("\nplaco is not installed here (pip install placo, or run with .venv-bench/bin/python): armkit alone")
    k = args.calls
    q = arm.random_q(k, rng=args.seed + 1)
    cur = np.concatenate([np.degrees(q), np.zeros((k, 1))], axis=1)
    held = armkit.fk(arm, q)
    step = held.copy()
    step[:, :3, 3] += np.array([0.005, 0.003, -0.002])
    print(f"\nTeleoperation: one inverse_kinematics call, us: median / best of {k} calls from random poses (the best\n"
          "is what a call costs where no other process shares the core)\n")
    cases = (("target held still (FK of the current joints)", held, 0.01),
             ("5 mm step, weights 1 / 0.01 (LeRobot's default)", step, 0.01),
             ("5 mm step, position only (orientation weight 0)", step, 0.0))
    names = list(solvers)
    print(f"{'case':50} " + " ".join(f"{nm + ' (median / best)':>32}" for nm in names)
          + ("  placo/armkit (median)" if len(names) > 1 else ""))
    for label, targets, w in cases:
        cells, med = [], []
        for nm in names:
            s = solvers[nm]
            for i in range(20):                                           # warm-up (kernels loaded or compiled)
                s.inverse_kinematics(cur[i], targets[i], orientation_weight=w)  # type: ignore[attr-defined]
            call = lambda i: s.inverse_kinematics(cur[i], targets[i], orientation_weight=w)  # type: ignore[attr-defined]  # noqa: B023, E731
            a, b = per_call(call, k)
            cells.append(f"{a * 1e6:8.1f} / {b * 1e6:6.1f}")
            med.append(a)
        ratio = f"  {med[1] / med[0]:.2f}x" if len(med) > 1 else ""
        print(f"{label:50} " + " ".join(f"{c:>32}" for c in cells) + ratio)
    stages: dict[str, int] = {}
    stage_times: dict[str, list[float]] = {}
    numpy_path = 0
    rk = solvers["armkit"]
    for i in range(k):
        t0 = time.perf_counter()
        rk.inverse_kinematics(cur[i], step[i])  # type: ignore[attr-defined]
        stage_times.setdefault(rk.last_stage, []).append(time.perf_counter() - t0)  # type: ignore[attr-defined]
        stages[rk.last_stage] = stages.get(rk.last_stage, 0) + 1  # type: ignore[attr-defined]
        numpy_path += bool(getattr(rk, "_numpy", False))
    print(f"armkit's stages on the 5 mm steps: {stages}; {numpy_path} of {k} took the NumPy path (LM for the "
          "position, or a failure's message), the others one compiled call")
    print("  median us per stage: " + ", ".join(f"{nm} {np.median(ts) * 1e6:.1f}" for nm, ts in stage_times.items())
          + " (a pitch or position answer comes after the direction was tried)")
    # the loop: a 5 cm circle in 0.5 mm steps, each answer is the next current joints
    n = args.loop
    radius = 0.05
    print(f"\nSustained loop: {n:,} calls following a {radius * 100:g} cm circle in {2 * math.pi * radius / n * 1e3:.2f} mm "
          "steps (orientation from the current pose, as LeRobot's EEReferenceAndDelta)\n")
    print(f"{'solver':24} {'IK calls/s':>11} {'median us':>10} {'p90 us':>8} {'whole loop/s':>13} {'worst miss (mm)':>16} "
          f"{'median miss (mm)':>17}  stages")
    start = np.array([0.0, -20.0, 30.0, 50.0, 0.0, 0.0])
    centre = solvers["armkit"].forward_kinematics(start)[:3, 3]  # type: ignore[attr-defined]
    ang = np.linspace(0, 2 * math.pi, n)
    points = centre + radius * np.stack([np.cos(ang) - 1, np.sin(ang), np.zeros(n)], axis=1)
    for nm in names:
        s = solvers[nm]
        c = start.copy()
        misses, calls = np.empty(n), np.empty(n)
        seen: dict[str, int] = {}
        t0 = time.perf_counter()
        for i in range(n):
            T = s.forward_kinematics(c)  # type: ignore[attr-defined]
            T[:3, 3] = points[i]
            a = time.perf_counter()
            c = s.inverse_kinematics(c, T)  # type: ignore[attr-defined]
            calls[i] = time.perf_counter() - a
            stage = getattr(s, "last_stage", None)
            if stage is not None:
                seen[stage] = seen.get(stage, 0) + 1
            misses[i] = np.linalg.norm(armkit.fk(arm, np.radians(c[:5]))[:3, 3] - points[i])
        dt = time.perf_counter() - t0
        print(f"{nm:24} {n / calls.sum():11,.0f} {np.median(calls) * 1e6:10.1f} {np.percentile(calls, 90) * 1e6:8.1f} "
              f"{n / dt:13,.0f} {misses.max() * 1e3:16.3g} {np.median(misses) * 1e3:17.3g}  {seen or ''}")
    print("(IK calls/s: the inverse_kinematics calls alone; whole loop: with one forward_kinematics call and an FK "
          "check per step)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=10_000)
    ap.add_argument("--far", type=int, default=1_000)
    ap.add_argument("--single", type=int, default=200)
    ap.add_argument("--calls", type=int, default=2_000)
    ap.add_argument("--loop", type=int, default=2_000)
    ap.add_argument("--seed", type=int, default=101)
    ap.add_argument("--teleop-only", action="store_true")
    args = ap.parse_args()
    print(f"load average at start: {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    if not args.teleop_only:
        modes(args)
    teleop(args)


if __name__ == "__main__":
    main()
