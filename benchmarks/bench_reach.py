"""Reachability maps: accuracy against IK ground truth, construction time, query time, scaling.

For each arm it builds a map (FK sampling, the default) and judges it on 10,000 poses
(``--n``), half of each kind:

* **FK poses**: FK of uniform random in-limit joint vectors, so reachable by construction;
  a "no" from the map here is a false negative;
* **box poses**: positions uniform in the box that holds the arm's FK positions, orientations
  uniform on SO(3) (positions only for the position-only arms). Ground truth by IK: every
  closed-form branch (UR5, fighter: exact) or LM with 50 seeded restarts (Panda, SO-101: "IK
  finds it", so a pose LM misses counts as unreachable and may inflate the false positives).

Reported: accuracy (agreement with IK over all poses), false-positive rate (poses the map calls
reachable that IK cannot reach, over all poses, as RichMap reports it, and over the unreachable
poses), false-negative rate, build time and throughput (samples/s), query time per pose
(batched and single), and 1 -> 2 worker scaling on the embedded Dask cluster.

Usage::

    .venv/bin/python benchmarks/bench_reach.py                      # every arm, defaults
    .venv/bin/python benchmarks/bench_reach.py --robots ur5 --n 2000
    .venv/bin/python benchmarks/bench_reach.py --robots panda --resolution 0.05 --orientations 64 --scaling
"""

from __future__ import annotations

import argparse
import json
import time
from typing import Any

import numpy as np

import armkit
from armkit.reach import ReachabilityMap, reachability


def random_rotations(n: int, rng: np.random.Generator) -> np.ndarray:
    """Uniform rotations on SO(3) from normalised Gaussian quaternions, shape (n, 3, 3)."""
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
        np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
        np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1)], axis=1)


def test_poses(robot: armkit.Robot, n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """``n // 2`` FK poses and ``n - n // 2`` box poses; (n, 4, 4) and a bool 'from FK' mask."""
    rng = np.random.default_rng(seed)
    k = n // 2
    T_fk = armkit.fk(robot, robot.random_q(k, rng=rng))
    p = armkit.fk(robot, robot.random_q(200_000, rng=rng))[:, :3, 3]
    lo, hi = p.min(axis=0), p.max(axis=0)
    T_box = np.tile(np.eye(4), (n - k, 1, 1))
    T_box[:, :3, 3] = rng.uniform(lo, hi, size=(n - k, 3))
    T_box[:, :3, :3] = random_rotations(n - k, rng)
    return np.concatenate([T_fk, T_box]), np.arange(n) < k


def ground_truth(robot: armkit.Robot, T: np.ndarray, position_only: bool, seed: int) -> np.ndarray:
    """Whether IK reaches each pose: every closed-form branch where there is one, else LM with restarts."""
    target = T[:, :3, 3] if position_only else T
    from armkit.ik.api import closed_form_family

    fam = closed_form_family(robot)
    if fam is not None:
        try:
            return np.asarray(armkit.ik_all(robot, target).success).any(axis=-1)
        except armkit.ArmkitError:
            pass
    out = np.zeros(len(T), dtype=bool)
    for s in range(0, len(T), 500):
        res = armkit.ik(robot, target[s:s + 500], method="lm", seed=np.random.default_rng([seed, s]), restarts=50)
        out[s:s + 500] = np.asarray(res.success)
    return out


def accuracy(m: ReachabilityMap, n: int, seed: int) -> dict[str, Any]:
    T, from_fk = test_poses(m.robot, n, seed)
    t = time.perf_counter()
    truth = ground_truth(m.robot, T, m.grid.position_only, seed)
    t_ik = time.perf_counter() - t
    said = m.reachable(T)
    fp = said & ~truth
    fn = ~said & truth
    neg = max(1, int((~truth).sum()))
    t = time.perf_counter()
    ref = m.reachable(T, refine=True, seed=seed)
    t_ref = time.perf_counter() - t
    c = m.cells(T)
    doubt = (c >= 0) & m.boundary.reshape(-1)[np.maximum(c, 0)]
    return {"poses": n, "truth_reachable": int(truth.sum()), "accuracy": float(np.mean(said == truth)),
            "fp_rate_all": float(fp.mean()), "fp_rate_of_unreachable": float(fp.sum() / neg),
            "fn_rate_all": float(fn.mean()), "fn_rate_fk_poses": float(fn[from_fk].mean()),
            "accuracy_box_poses": float(np.mean(said[~from_fk] == truth[~from_fk])),
            "fk_poses_truth_ok": float(truth[from_fk].mean()), "ground_truth_seconds": t_ik,
            "refine_accuracy": float(np.mean(ref == truth)), "refine_fp_rate_all": float((ref & ~truth).mean()),
            "refine_fn_rate_all": float((~ref & truth).mean()), "refine_fraction_ik": float(doubt.mean()),
            "refine_us_per_query": t_ref / n * 1e6}


def query_times(m: ReachabilityMap, seed: int) -> dict[str, float]:
    T, _ = test_poses(m.robot, 100_000, seed + 7)
    m.reachable(T[:10])
    t = time.perf_counter()
    m.reachable(T)
    batched = (time.perf_counter() - t) / len(T)
    single = []
    for i in range(2000):
        t = time.perf_counter()
        m.reachable(T[i])
        single.append(time.perf_counter() - t)
    return {"query_us_batched": batched * 1e6, "query_us_single_median": float(np.median(single)) * 1e6}


def memory(robot: str, sizes: tuple[int, ...] = (100_000, 1_000_000, 4_000_000)) -> dict[str, float]:
    """Peak memory (MB, NumPy allocations traced by tracemalloc) of one FK block of each size (5 cm, 64)."""
    import tracemalloc

    from armkit.reach._build import _make_grid
    from armkit.reach._work import fk_block

    r = armkit.load(robot)
    g = _make_grid(r, 0.05, 64, 1)
    fk_block(r, g.to_attrs(), 0, 0, 1000)
    out = {}
    for n in sizes:
        tracemalloc.start()
        fk_block(r, g.to_attrs(), 0, 1, n)
        out[f"block_{n}_MB"] = tracemalloc.get_traced_memory()[1] / 2**20
        tracemalloc.stop()
    return out


def build(robot: str, args: argparse.Namespace, workers: int, scheduler: Any = None) -> tuple[ReachabilityMap, float]:
    t = time.perf_counter()
    kw: dict[str, Any] = {"seed": args.seed, "workers": workers, "scheduler": scheduler}
    if args.resolution:
        kw["resolution"] = args.resolution
    if args.orientations:
        kw["orientations"] = args.orientations
    if args.rolls:
        kw["rolls"] = args.rolls
    if args.samples:
        kw["samples"] = args.samples
    m = reachability(robot, **kw)
    return m, time.perf_counter() - t


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--robots", nargs="+", default=["fighter", "ur5", "panda", "so101"])
    ap.add_argument("--n", type=int, default=10_000)
    ap.add_argument("--resolution", type=float, default=None, help="default: per arm, 0.05 m for m-arms, reach/20 else")
    ap.add_argument("--orientations", type=int, default=None)
    ap.add_argument("--rolls", type=int, default=None)
    ap.add_argument("--samples", type=int, default=None)
    ap.add_argument("--workers", type=int, default=1)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--scaling", action="store_true", help="also time 1 and 2 workers (embedded Dask cluster)")
    ap.add_argument("--memory", action="store_true", help="worker memory per FK block size (fresh processes)")
    ap.add_argument("--no-accuracy", action="store_true", help="skip the accuracy and query measurements")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    rows = []
    for name in args.robots:
        try:
            robot = armkit.load(name)
        except armkit.ArmkitError as exc:
            print(f"{name}: skipped ({exc})")
            continue
        if args.resolution is None and robot.unit == "m":
            args_r = argparse.Namespace(**{**vars(args), "resolution": 0.05})
        else:
            args_r = args
        m, t_build = build(name, args_r, args.workers)
        samples = m.parameters.get("samples") or m.grid.n_cells
        row: dict[str, Any] = {"robot": name, **m.summary(), "build_seconds": t_build,
                               "samples_per_second": samples / t_build}
        if not args.no_accuracy:
            row.update(accuracy(m, args.n, args.seed + 1))
            row.update(query_times(m, args.seed))
        if args.memory:
            row.update(memory(name))
        if args.scaling:
            from distributed import Client, LocalCluster

            times: dict[int, float] = {}
            for w in (1, 2):      # a started, warmed cluster of w worker processes: the compute alone
                with LocalCluster(n_workers=w, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=":0", silence_logs=40) as cluster, Client(cluster) as client:
                    reachability(name, resolution=args_r.resolution, orientations=args.orientations,
                                 rolls=args.rolls, samples=2 * w * 100_000, block_size=100_000, scheduler=client)
                    t = time.perf_counter()
                    m2, _ = build(name, args_r, w, scheduler=client)
                    times[w] = time.perf_counter() - t
                assert np.array_equal(m2.hits, m.hits), "map differs between worker counts"
            row["scaling_1_worker_s"] = times[1]
            row["scaling_2_workers_s"] = times[2]
            row["scaling_efficiency"] = times[1] / (2 * times[2])
        rows.append(row)
        if args.json:
            print(json.dumps(row), flush=True)
        elif not args.no_accuracy:
            print(f"{name}: {m!r}")
            print(f"  build {t_build:.1f} s, {row['samples_per_second'] / 1e6:.2f} M samples/s; "
                  f"accuracy {row['accuracy'] * 100:.2f} %, FP {row['fp_rate_all'] * 100:.2f} % of all "
                  f"({row['fp_rate_of_unreachable'] * 100:.2f} % of unreachable), FN {row['fn_rate_all'] * 100:.2f} % "
                  f"(FK poses {row['fn_rate_fk_poses'] * 100:.2f} %); truth reachable {row['truth_reachable']}/{args.n}; "
                  f"query {row['query_us_batched']:.2f} us batched, {row['query_us_single_median']:.1f} us single", flush=True)
            print(f"  refine=True: accuracy {row['refine_accuracy'] * 100:.2f} %, FP {row['refine_fp_rate_all'] * 100:.2f} %, "
                  f"FN {row['refine_fn_rate_all'] * 100:.2f} %, IK on {row['refine_fraction_ik'] * 100:.1f} % of poses, "
                  f"{row['refine_us_per_query']:.1f} us per query", flush=True)
            if args.scaling:
                print(f"  warm cluster: 1 worker {row['scaling_1_worker_s']:.1f} s, 2 workers {row['scaling_2_workers_s']:.1f} s, "
                      f"efficiency {row['scaling_efficiency'] * 100:.0f} %", flush=True)


if __name__ == "__main__":
    main()
