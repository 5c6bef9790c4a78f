"""Before/after speed of one change, in one run: two source trees timed alternately.

Each tree is imported in its own Python process (``PYTHONPATH=<tree>/src``,
``ARMKIT_JIT=wait``, so the compiled kernels are timed, never the NumPy stand-in). Both
processes warm every case up first; then, for each repeat, each case is timed in one
tree and right after in the other (the order alternating between repeats), so that a
busy machine slows both alike. Printed: the median per case and tree over the repeats and
the ratio after / before (above 1: the change is slower).

Cases: FK single call and batch of 10,000 (panda, ur5), Jacobian batch of 10,000 (panda,
ur5), ``ik_all`` on 10,000 targets (ur5, puma560, fighter), ``ik(method="lm")`` on 1,000
targets (panda), the overhead of one single-target ``ik`` call (ur5 closed form, panda
LM from a nearby start), and the collision check of a scene with a cylinder (``in_collision``
and ``clearance`` on 1,000 ur5 configurations, one ``ik(..., scene=)`` call).

Usage::

    git worktree add /tmp/armkit-before <commit>
    .venv/bin/python benchmarks/bench_before_after.py --before /tmp/armkit-before --after . --repeats 5
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

# ------------------------------------------------------------------------------ worker
WORKER = r'''
import json, sys, time
import numpy as np
import armkit

def setup():
    cases = {}
    arms = {name: armkit.load(name) for name in ("panda", "ur5", "puma560", "fighter")}
    for name in ("panda", "ur5"):
        arm = arms[name]
        q1 = arm.random_q(rng=0)
        Q = np.ascontiguousarray(arm.random_q(10_000, rng=1))
        cases[f"fk single {name}"] = (lambda arm=arm, q1=q1: armkit.fk(arm, q1))
        cases[f"fk batch 10k {name}"] = (lambda arm=arm, Q=Q: armkit.fk(arm, Q))
        cases[f"jacobian batch 10k {name}"] = (lambda arm=arm, Q=Q: armkit.jacobian(arm, Q))
    for name in ("ur5", "puma560", "fighter"):
        arm = arms[name]
        T = armkit.fk(arm, arm.random_q(10_000, rng=2))
        target = T if arm.n == 6 else np.ascontiguousarray(T[:, :3, 3])
        cases[f"ik_all batch 10k {name}"] = (lambda arm=arm, t=target: armkit.ik_all(arm, t))
    panda = arms["panda"]
    Q = panda.random_q(1_000, rng=3)
    T = armkit.fk(panda, Q)
    Q0 = np.clip(Q + 0.1, panda.lower, panda.upper)
    cases["ik lm batch 1k panda"] = lambda: armkit.ik(panda, T, Q0, method="lm", seed=0)
    ur5 = arms["ur5"]
    T1 = armkit.fk(ur5, ur5.random_q(rng=4))
    cases["ik single ur5 (closed form)"] = lambda: armkit.ik(ur5, T1)
    Tp, q0p = T[0], Q0[0]
    cases["ik single panda (lm)"] = lambda: armkit.ik(panda, Tp, q0p, method="lm", seed=0)
    # issue 21: a scene with a cylinder (a pole beside a table on the ground); before, any cylinder sent every pair
    # of the check to the slow path
    R = ur5.reach
    pole = armkit.Scene([armkit.Scene.plane([0, 0, 1], -0.05 * R, name="ground"),
                         armkit.Scene.box([0.6 * R, 0, 0.2 * R], [0.4 * R, 0.8 * R, 0.4 * R], name="table"),
                         armkit.Scene.cylinder([-0.5 * R, 0.5 * R, 0.5 * R], 0.05 * R, R, name="pole")])
    Qc = ur5.random_q(1_000, rng=5)
    from armkit.collision import clearance, in_collision

    cases["in_collision 1k ur5 cylinder"] = lambda: in_collision(ur5, Qc, pole)
    cases["clearance 1k ur5 cylinder"] = lambda: clearance(ur5, Qc, pole)
    cases["ik single ur5 cylinder scene"] = lambda: armkit.ik(ur5, T1, scene=pole)
    return cases

def per_call(fn, budget):
    n, t0 = 0, time.perf_counter()
    while True:
        fn()
        n += 1
        t = time.perf_counter() - t0
        if t >= budget:
            return t / n

cases = setup()
for fn in cases.values():      # warm-up: compile or load every kernel, fill every cache
    for _ in range(3):
        fn()
print(json.dumps({"ready": list(cases), "file": armkit.__file__}), flush=True)
for line in sys.stdin:
    name, budget = line.rstrip("\n").rsplit(" ", 1)
    print(json.dumps(per_call(cases[name], float(budget))), flush=True)
'''


def start(tree: Path, threads: int) -> subprocess.Popen:
    env = dict(os.environ, PYTHONPATH=str(tree.resolve() / "src"), ARMKIT_JIT="wait", ARMKIT_BACKEND="auto")
    if threads:
        env["NUMBA_NUM_THREADS"] = str(threads)
    return subprocess.Popen([sys.executable, "-c", WORKER], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                            text=True, env=env)


def ask(proc: subprocess.Popen, name: str, budget: float) -> float:
    assert proc.stdin is not None and proc.stdout is not None
    proc.stdin.write(f"{name} {budget}\n")
    proc.stdin.flush()
    return float(json.loads(proc.stdout.readline()))


def fmt(seconds: float) -> str:
    if seconds < 1e-3:
        return f"{seconds * 1e6:9.2f} us"
    return f"{seconds * 1e3:9.2f} ms"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--before", type=Path, default=Path("/tmp/armkit-before"))
    ap.add_argument("--after", type=Path, default=Path(__file__).resolve().parent.parent)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--budget", type=float, default=0.3, help="seconds of calls per case and measurement")
    ap.add_argument("--cases", default="", help="only the cases whose name contains one of these (comma-separated)")
    ap.add_argument("--threads", type=int, default=0,
                    help="NUMBA_NUM_THREADS of both trees (1: batches without the noise of a shared machine's threads)")
    args = ap.parse_args()
    t0 = time.perf_counter()
    procs = {"before": start(args.before, args.threads), "after": start(args.after, args.threads)}
    names = None
    for label, proc in procs.items():
        assert proc.stdout is not None
        hello = json.loads(proc.stdout.readline())
        print(f"{label}: {hello['file']}", flush=True)
        names = hello["ready"]
    assert names is not None
    if args.cases:
        names = [n for n in names if any(c.strip() in n for c in args.cases.split(","))]
    print(f"warm-up done in {time.perf_counter() - t0:.0f} s; load average {os.getloadavg()[0]:.1f}", flush=True)
    times: dict[str, dict[str, list[float]]] = {n: {"before": [], "after": []} for n in names}
    for r in range(args.repeats):
        for name in names:
            order = ("before", "after") if r % 2 == 0 else ("after", "before")
            for label in order:
                times[name][label].append(ask(procs[label], name, args.budget))
    for proc in procs.values():
        assert proc.stdin is not None
        proc.stdin.close()
        proc.wait()
    print(f"\n{args.repeats} repeats, medians; load average at the end {os.getloadavg()[0]:.1f} "
          f"({os.cpu_count()} CPUs); Numba threads: {args.threads or 'all'}")
    print(f"{'case':30s} {'before':>12s} {'after':>12s}  after/before  (min: before, after, ratio)")
    for name in names:
        b, a = statistics.median(times[name]["before"]), statistics.median(times[name]["after"])
        bm, am = min(times[name]["before"]), min(times[name]["after"])
        print(f"{name:30s} {fmt(b)} {fmt(a)}  {a / b:6.2f}        {fmt(bm)} {fmt(am)} {am / bm:6.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
