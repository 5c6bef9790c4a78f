"""Time one IK solve of the subproblem solvers (armkit.ik.geometric.solvers) against the existing closed forms.

Run: ``.venv/bin/python benchmarks/bench_geometric.py [--targets 500] [--repeat 5]``. The Numba kernels
are compiled (or loaded from the cache) and warmed up first; each figure is the best of ``--repeat``
passes over ``--targets`` random reachable targets, in µs per call (one target per call, all solutions).
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

os.environ.setdefault("ARMKIT_JIT", "wait")

import armkit  # noqa: E402
from armkit.ik.geometric import solvers as G  # noqa: E402
from armkit.ik.geometric.poe import POE, poe  # noqa: E402


def _random_arm(seed: int, meet: slice) -> POE:
    """A random 6R arm whose axes ``meet`` share one point, no other special axes (the 1-D search solvers)."""
    g = np.random.default_rng(seed)
    H = g.normal(size=(6, 3))
    H /= np.linalg.norm(H, axis=1, keepdims=True)
    pts = g.normal(size=(6, 3)) * 0.5
    c = g.normal(size=3) * 0.5
    pts[meet] = c
    tool = pts[5] + g.normal(size=3) * 0.3
    P = np.vstack([pts[0], np.diff(pts, axis=0), tool - pts[5]])
    return POE(H, P, np.eye(3), np.zeros(6, dtype=bool))


def _per_call(fn, targets, repeat: int) -> float:
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        for R, p in targets:
            fn(R, p)
        best = min(best, (time.perf_counter() - t0) / len(targets))
    return best * 1e6


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--targets", type=int, default=500)
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()

    t0 = time.perf_counter()
    G.kernels()
    cases = []
    for name, solver in (("puma560", G.spherical_wrist), ("puma560", G.spherical_two_intersecting),
                         ("ur5", G.three_parallel_two_intersecting), ("ur5", G.three_parallel),
                         ("stanford", G.spherical_wrist)):
        robot = armkit.load(name)
        cases.append((name, solver, poe(robot), robot))
    cases.append(("random spherical-wrist arm", G.spherical, _random_arm(1, slice(3, 6)), None))
    cases.append(("random arm, axes 5, 6 meet", G.two_intersecting, _random_arm(2, slice(4, 6)), None))
    for _, solver, form, _ in cases:   # compile / load the kernels, warm up
        solver(form, *form.fk(np.zeros(6)))
    print(f"kernels ready in {time.perf_counter() - t0:.1f} s (compiled or loaded from Numba's cache)")
    print(f"{'robot':28s} {'solver':34s} {'µs/call':>9s}  solutions (mean)")
    g = np.random.default_rng(0)
    for name, solver, form, robot in cases:
        qs = robot.random_q(args.targets, rng=g) if robot is not None else g.uniform(-3, 3, (args.targets, 6))
        targets = [form.fk(q) for q in qs]
        few = targets if robot is not None else targets[:max(args.targets // 10, 10)]   # the searches are slow
        us = _per_call(lambda R, p: solver(form, R, p), few, args.repeat)
        m = np.mean([len(solver(form, R, p).q) for R, p in targets[:50]])
        print(f"{name:28s} {solver.__name__:34s} {us:9.1f}  {m:.2f}")
        if name in ("puma560", "ur5") and solver in (G.spherical_wrist, G.three_parallel_two_intersecting):
            T = np.stack([armkit.fk(robot, q) for q in qs])
            armkit.ik_all(robot, T[0], enforce_limits=False)
            ref = _per_call(lambda R, p: armkit.ik_all(robot, _pose(R, p), enforce_limits=False, check=False),
                            targets, args.repeat)
            print(f"{name:28s} {'armkit.ik_all (existing closed form)':34s} {ref:9.1f}")
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"(load average {load:.1f} on {os.cpu_count()} cores while measuring)")


def _pose(R, p):
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = p
    return T


if __name__ == "__main__":
    main()
