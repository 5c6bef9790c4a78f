"""Time the 2-D search for the general 6R (armkit.ik.geometric.search2d.gen_six_dof), median ms per target.

Run: ``.venv/bin/python benchmarks/bench_search2d.py [--arms 3] [--targets 20] [--samples 100]``. The Numba
kernels are compiled (or loaded from the cache) and warmed up first. Beside it: IK-Geo's published figure for
its 2-D search (Rust, 6.6-8.5 ms per target, Elias and Wen 2022), and, when the ``ik_geo`` Python package (the
Rust build) imports, its ``gen_six_dof`` on the same arms and targets, timed the same way, with how many of its
answers pass FK at 1e-6 and whether the target's true q is among them (its answers are not polished).
Wall-clock and CPU time (``time.thread_time``, the calling thread's: both searches run on it) medians; on a
shared machine compare the ratio of the two searches, not the absolute figures.
"""

from __future__ import annotations

import argparse
import math
import os
import time

import numpy as np

os.environ.setdefault("ARMKIT_JIT", "wait")

from armkit.ik.geometric import search2d as S  # noqa: E402
from armkit.ik.geometric.poe import POE  # noqa: E402

PUBLISHED_MS = (6.6, 8.5)


def random_arm(g: np.random.Generator) -> POE:
    H = g.normal(size=(6, 3))
    H /= np.linalg.norm(H, axis=1, keepdims=True)
    P = g.normal(size=(7, 3)) * 0.4
    return POE(H, P, np.eye(3), np.zeros(6, dtype=bool))


def wrapped(a: np.ndarray) -> np.ndarray:
    return (a + np.pi) % (2 * np.pi) - np.pi


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--arms", type=int, default=3)
    ap.add_argument("--targets", type=int, default=20)
    ap.add_argument("--samples", type=int, default=S.N)
    args = ap.parse_args()
    try:
        import ik_geo
    except ImportError:
        ik_geo = None
    g = np.random.default_rng(0)
    S.kernels()
    warm = random_arm(g)
    R, p = warm.fk(np.zeros(6))
    S.gen_six_dof(warm, R, p, samples=args.samples, jit=True)
    ours: list[float] = []
    theirs: list[float] = []
    ours_cpu: list[float] = []
    theirs_cpu: list[float] = []
    n_ours = n_theirs_ok = n_theirs = hit_ours = hit_theirs = 0
    for _ in range(args.arms):
        form = random_arm(g)
        peer = ik_geo.Robot.gen_six_dof(np.asarray(form.H).tolist(), np.asarray(form.P).tolist()) if ik_geo else None
        for _ in range(args.targets):
            q = g.uniform(-math.pi, math.pi, 6)
            R, p = form.fk(q)
            t0, c0 = time.perf_counter(), time.thread_time()
            sol = S.gen_six_dof(form, R, p, samples=args.samples, jit=True)
            ours.append(time.perf_counter() - t0)
            ours_cpu.append(time.thread_time() - c0)
            n_ours += len(sol.q)
            hit_ours += any(np.abs(wrapped(s - q)).max() < 1e-6 for s in sol.q)
            if peer is not None:
                t0, c0 = time.perf_counter(), time.thread_time()
                out = peer.get_ik(R.T.tolist(), p.tolist())     # ik_geo reads the rotation transposed
                theirs.append(time.perf_counter() - t0)
                theirs_cpu.append(time.thread_time() - c0)
                for s, _ls in out:
                    n_theirs += 1
                    Rq, pq = form.fk(np.asarray(s))
                    n_theirs_ok += bool(np.linalg.norm(pq - p) < 1e-6 and np.linalg.norm(Rq - R) < 1e-6)
                hit_theirs += any(np.abs(wrapped(np.asarray(s) - q)).max() < 1e-3 for s, _ in out)
    total = args.arms * args.targets
    print(f"general 6R, {total} targets ({args.arms} random arms), grid {S.resolution(args.samples)}")
    print(f"  armkit search2d : median {np.median(ours) * 1e3:7.2f} ms/target "
          f"(CPU {np.median(ours_cpu) * 1e3:.2f} ms), {n_ours / total:.1f} solutions/target "
          f"(all FK-verified at 1e-9), true q found {hit_ours}/{total}")
    print(f"  IK-Geo (Rust)   : published {PUBLISHED_MS[0]}-{PUBLISHED_MS[1]} ms/target (Elias and Wen 2022)")
    if theirs:
        print(f"  ik_geo here     : median {np.median(theirs) * 1e3:7.2f} ms/target "
              f"(CPU {np.median(theirs_cpu) * 1e3:.2f} ms), {n_theirs / total:.1f} answers/target, "
              f"{n_theirs_ok} of {n_theirs} pass FK at 1e-6, true q within 1e-3 rad {hit_theirs}/{total}")
        print(f"  ratio armkit / ik_geo: {np.median(ours) / np.median(theirs):.2f}")


if __name__ == "__main__":
    main()
