"""SO-101 (5 joints): the IK modes a user of a 5-DOF arm has, over N random reachable targets each.

Targets are FK of ``--n`` (default 10,000) joint vectors drawn uniformly inside the limits
(seeded). Modes:

* position only (``armkit.ik(arm, xyz)``: Levenberg-Marquardt);
* position + tool pitch (``armkit.ik(arm, xyz, pitch=...)``: the yaw-pitch3 closed form, the
  roll joint kept at q0, which is given the roll the target came from), and ``ik_all``;
* position + pointing direction of the tool's z axis (``armkit.ik(arm, xyz, direction=...)``: LM);
* 6-D poses turned by 20 deg about the tool's x axis (unreachable for 5 joints): how many
  fail honestly (reason "unreachable", "5 joints cannot reach ...") and the misses reported.

"wrong" counts answers flagged as success although an independent FK check fails (position
within 1e-9 m, pitch within 1e-9 rad, pointing direction within 1e-7 rad, joints within limits).
Times: one call for the whole batch / N, and single calls (median over ``--single`` targets).

Usage::

    .venv/bin/python benchmarks/bench_so101.py            # about a minute on 2 cores
    .venv/bin/python benchmarks/bench_so101.py --n 1000
"""

from __future__ import annotations

import argparse
import math
import re
import time

import numpy as np

import os

os.environ.setdefault("ARMKIT_JIT", "wait")   # compile in this process: time compiled kernels, never the NumPy stand-in

import armkit  # noqa: E402
from armkit.ik.analytic.yaw_pitch3 import pitch_of


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


def single(fn, k):
    times = []
    for i in range(k):
        t = time.perf_counter()
        fn(i)
        times.append(time.perf_counter() - t)
    return float(np.median(times))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=10_000)
    ap.add_argument("--single", type=int, default=200)
    ap.add_argument("--seed", type=int, default=101)
    args = ap.parse_args()
    arm = armkit.load("so101")
    n = args.n
    q = arm.random_q(n, rng=args.seed)
    T = armkit.fk(arm, q)
    p, d = T[:, :3, 3], T[:, :3, 2]
    psi = pitch_of(arm, q)
    q0 = np.zeros_like(q)
    q0[:, 4] = q[:, 4]
    armkit.ik(arm, p[:50])                                   # warm-up (kernels loaded or compiled)
    armkit.ik(arm, p[:50], q0=q0[:50], pitch=psi[:50])
    armkit.ik(arm, p[:50], direction=d[:50])
    rows = []

    res, t = timed(lambda: armkit.ik(arm, p, seed=1))
    one = single(lambda i: armkit.ik(arm, p[i], seed=1), args.single)
    rows.append(("position (LM)", res.success, check(arm, res.q, p), t, one))

    res, t = timed(lambda: armkit.ik(arm, p, q0=q0, pitch=psi))
    one = single(lambda i: armkit.ik(arm, p[i], q0=q0[i], pitch=psi[i]), args.single)
    rows.append(("position + pitch (closed form)", res.success, check(arm, res.q, p, pitch=psi), t, one))

    every, t_all = timed(lambda: armkit.ik_all(arm, p, q0=q0, pitch=psi))
    ok_all = every.success
    wrong_all = 0
    for j in range(every.q.shape[1]):
        wrong_all += int(np.sum(ok_all[:, j] & ~check(arm, every.q[:, j], p, pitch=psi)))

    res, t = timed(lambda: armkit.ik(arm, p, direction=d, seed=2))
    one = single(lambda i: armkit.ik(arm, p[i], direction=d[i], seed=2), args.single)
    rows.append(("position + direction (LM)", res.success, check(arm, res.q, p, direction=d), t, one))

    print(f"SO-101, {n:,} random reachable targets per mode (seed {args.seed})\n")
    print(f"{'mode':34} {'solved':>9} {'wrong':>6} {'batch us/target':>16} {'single ms':>10}")
    for name, success, good, t, one in rows:
        wrong = int(np.sum(success & ~good))
        print(f"{name:34} {100 * success.mean():8.2f}% {wrong:6d} {t / n * 1e6:16.1f} {one * 1e3:10.3f}")
    print(f"\nik_all with pitch: {100 * ok_all.any(axis=1).mean():.2f}% of targets with a branch, "
          f"{ok_all.sum(axis=1).mean():.2f} successful branches per target (of 4; the others break limits "
          f"or are out of reach), {wrong_all} wrong, {t_all / n * 1e6:.1f} us/target")

    k = min(n, 200)
    c, s = math.cos(math.radians(20)), math.sin(math.radians(20))
    turn = np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])
    res, t = timed(lambda: armkit.ik(arm, T[:k] @ turn, seed=3))
    honest = (~res.success) & (res.reason == "unreachable")
    miss = [float(m.group(1)) for msg in res.message if (m := re.search(r"misses by ([0-9.]+) deg", str(msg)))]
    print(f"\n6-D poses turned 20 deg about the tool's x ({k}): {int(res.success.sum())} flagged solved, "
          f"{int(honest.sum())} honest failures ('{str(res.message[0]).split(';')[0]}'), reported miss "
          f"{min(miss):.1f}-{max(miss):.1f} deg (median {np.median(miss):.1f}), {t / k * 1e3:.1f} ms/target")


if __name__ == "__main__":
    main()
