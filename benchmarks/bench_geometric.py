"""Time one IK solve of the subproblem solvers (armkit.ik.geometric.solvers) against the existing closed forms.

Run: ``.venv/bin/python benchmarks/bench_geometric.py [--targets 500] [--repeat 5]``. The Numba kernels
are compiled (or loaded from the cache) and warmed up first; each figure is the best of ``--repeat``
passes over ``--targets`` random reachable targets, in µs per call (one target per call, all solutions).

``--search-profile``: where the 1-D searches TI and TP spend their time (branch evaluations per target by the
part of the engine that asks for them, on 20 targets; the compiled grid scan alone against the whole search).

``--searches [--search-targets 200]``: only the 1-D searches (:mod:`armkit.ik.geometric.search`), one
random arm of each 1-D class per target, median milliseconds per target (one call, all solutions, FK
checked), as CPU time of this process and as wall time (the machine is shared: the CPU time is the
steadier figure), and the mean number of solutions. IK-Geo (Rust) publishes 0.13-0.33 ms for its 1-D
searches. Measured on the shared 2-core machine at load average ~9 (other sessions compiling):

=============================== ====================== ============ =============
class                           before: CPU (wall) ms  after: CPU   after: wall
=============================== ====================== ============ =============
6R-two-intersecting             30.7 (444)             2.05         17.6
6R-two-parallel                 30.0 (366)             1.80         19.5
6R-spherical-wrist, general     1.19 (1.41)            0.67         0.88
6R-spherical-middle (new)       no solver              0.88         1.33
=============================== ====================== ============ =============

Before: the searches of commit ab0a28d (720 samples, eigenvalue quartic), 10 targets per class
(/tmp script, same random arms); after: ``--searches --search-targets 200``, 240 samples, load
average 10.4 (the wall times of the first two rows include waits for the CPU).

Then (shared helpers in :mod:`armkit.ik.geometric._kernels`: no temporary arrays per sample, the
quartic's Newton polish in real arithmetic, distances between samples computed once, branch ends
bracketed early, 6 edge samples instead of 10; N, SUB_N unchanged), CPU ms per target, commit
eb5cee8 (a copy of it run beside this tree, same script) against this tree, back to back at load 4.4:

=============================== ============================== ==============================
class                           eb5cee8: call / again / search this tree: call / again / search
=============================== ============================== ==============================
6R-two-intersecting             1.66 / 1.12 / 1.05             1.05 / 0.60 / 0.56
6R-two-parallel                 1.62 / 1.30 / 1.20             1.20 / 0.81 / 0.77
6R-spherical-wrist (SW search)  0.30 / 0.06 / 0.19             0.52 / 0.09 / 0.18
6R-spherical-middle             0.66 / 0.23 / 0.20             0.66 / 0.19 / 0.15
=============================== ============================== ==============================

('call' includes the one-off preparation of a new arm, 0.3-0.8 ms, in solvers.py; the general spherical
wrist is closed form since eb5cee8, its 'search' column times the SW search on the same arm.) IK-Geo's
0.13-0.33 ms is met by SW and SM, not yet by TI and TP (about 500-550 branch evaluations a target:
241 samples, ~130-160 near branch ends, ~100-125 in sub-sampled steps).

Where the time goes (``--search-profile``, 20 targets, load 5): TI 454 evaluations a target (scan 241,
sub-sampled steps 93, branch ends 85, refinement 34), TP 458 (241, 101, 88, 27); the compiled scan alone
0.25 / 0.30 ms of a 0.68 / 0.81 ms search. So with N = 240 the scan alone is near the 0.3 ms goal: each
evaluation costs 0.9-1.2 µs, nearly all of it in SP6 (the 2 x 2 trigonometric system, the quartic
~150 ns of it; the branch rows after it matter for TI only at the 5 % level). Compiling with
``error_model="numpy"`` or ``fastmath`` changes nothing measurable. Removing, one at a time, the work of
the branch ends, refinement, extrema and sub-sampled steps frees 0.13, 0.05, 0.06-0.08 and 0.01-0.05 ms.
Tried and dropped: sub-sampling an ambiguous step in two levels of 4 (4 x, then 4 x again only in the
sub-steps that stay ambiguous and their neighbours) instead of 16 x at once: 4-5 % faster, the same roots
on 150 bench targets, but the dense-scan test of TI then loses 2 targets / 4 roots instead of 1 / 2
(close roots beside a branch end that the coarser level no longer brackets).

Two correctness fixes (issue 19: a closed turn, and roots exactly on a sample; see :mod:`.search`) cost
nothing measurable: the compiled ``_search`` of the tree before them (a copy loaded beside this one) against
this one, 80 random targets of each class, best of 3 per target, median thread CPU, load 11-14: TI 0.874 →
0.931 ms (median of the per-target ratios 1.02), TP 1.135 → 1.158 ms (1.01), the same number of roots on
every target. Before them, targets FK(q) with q's entries in {0, ±π/2, ±π} lost their generating q on 13
of 450 (TI, q1 = ±π or a root on the sample q1 = 0) and 22 of 450 (TP, q6 = ±π); after, none.
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


def _spherical_middle_arm(g: np.random.Generator) -> POE:
    """A random 6R arm whose axes 2, 3, 4 meet in one point."""
    H = g.normal(size=(6, 3))
    H /= np.linalg.norm(H, axis=1, keepdims=True)
    pts = g.normal(size=(6, 3)) * 0.5
    pts[1:4] = g.normal(size=3) * 0.5
    tool = pts[5] + g.normal(size=3) * 0.3
    return POE(H, np.vstack([pts[0], np.diff(pts, axis=0), tool - pts[5]]), np.eye(3), np.zeros(6, dtype=bool))


def _two_parallel_arm(g: np.random.Generator) -> POE:
    """A random 6R arm whose axes 2 and 3 are parallel."""
    H = g.normal(size=(6, 3))
    H /= np.linalg.norm(H, axis=1, keepdims=True)
    H[2] = H[1]
    pts = g.normal(size=(6, 3)) * 0.5
    tool = pts[5] + g.normal(size=3) * 0.3
    return POE(H, np.vstack([pts[0], np.diff(pts, axis=0), tool - pts[5]]), np.eye(3), np.zeros(6, dtype=bool))


def searches(n: int) -> None:
    """Median ms per target of each 1-D search (a new random arm of the class for every target)."""
    kinds = (("6R-two-intersecting (axes 5, 6 meet)", G.two_intersecting, lambda g: _random_arm(int(g.integers(1 << 30)), slice(4, 6))),
             ("6R-two-parallel (axes 2 ∥ 3)", G.two_parallel, _two_parallel_arm),
             ("6R-spherical-wrist, general", G.spherical, lambda g: _random_arm(int(g.integers(1 << 30)), slice(3, 6))),
             ("6R-spherical-middle (2, 3, 4)", G.spherical_middle, _spherical_middle_arm))
    print(f"1-D searches, {G.SEARCH_N} samples a turn, {n} targets each (one random arm per target)")
    print("CPU ms per target (thread time): 'call' the whole solver call on a new arm (its one-off preparation,")
    print("the search, completion, FK check), 'again' a second target on the same arm, 'search' the compiled")
    print("search alone (search._search) on that target")
    print(f"{'class':40s} {'call':>7s} {'again':>7s} {'search':>7s} {'wall':>7s}  solutions (mean)")
    from armkit.ik.geometric import search as S
    from armkit.ik.geometric.solvers import _prepare
    ek = S.kernels()
    names = {G.two_intersecting: ("two_intersecting", S.TI), G.two_parallel: ("two_parallel", S.TP),
             G.spherical: ("spherical", S.SW), G.spherical_middle: ("spherical_middle", S.SM)}
    T = time.thread_time
    for label, solver, make in kinds:
        g = np.random.default_rng(0)
        cpu, again, alone, wall, m = [], [], [], [], []
        name, kind = names[solver]
        roots = np.zeros((S.MAXROOT, 4))
        for i in range(n):
            form = make(g)
            R, p = form.fk(g.uniform(-np.pi, np.pi, 6))
            R2, p2 = form.fk(g.uniform(-np.pi, np.pi, 6))
            if i == 0:
                solver(form, R, p)           # compile or load the kernels
                form = make(g)
            t0, w0 = T(), time.perf_counter()
            sol = solver(form, R, p)
            cpu.append(T() - t0)
            wall.append(time.perf_counter() - w0)
            t0 = T()
            solver(form, R2, p2)
            again.append(T() - t0)
            m.append(len(sol.q))
            prep = _prepare(form, name)
            C = _search_target(kind, S, prep.Hi, prep.Pi, R2 @ np.asarray(form.R_nT).T, p2)
            t0 = T()
            ek._search(kind, prep.Hi, prep.Pi, C, G.SEARCH_N, roots)
            alone.append(T() - t0)
        print(f"{label:40s} {1e3 * np.median(cpu):7.3f} {1e3 * np.median(again):7.3f} {1e3 * np.median(alone):7.3f} "
              f"{1e3 * np.median(wall):7.3f}  {np.mean(m):.2f}")
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"(load average {load:.1f} on {os.cpu_count()} cores while measuring)")


def _search_target(kind: int, S, H: np.ndarray, P: np.ndarray, R06: np.ndarray, p: np.ndarray) -> np.ndarray:
    """The search's ``C (4, 3)`` for the ideal chain ``(H, P)`` and the target, as the solver cores set it."""
    C = np.zeros((4, 3))
    if kind == S.TI:
        C[0] = R06 @ H[5]
        C[1] = p - P[0] - R06 @ P[6]
    elif kind == S.SW:
        C[0] = p - P[0] - R06 @ P[6]
    else:
        C[:3] = R06
        C[3] = p
    return C


def search_profile(n: int) -> None:
    """Where a 1-D search spends its time: branch evaluations per target by the part of the engine that asks for
    them (counted on the plain Python engine, ``n`` targets of TI and TP), and the compiled grid scan alone
    (``_scan`` of the N + 1 samples) against the whole compiled ``_search`` (thread CPU, median)."""
    import collections
    import sys

    from armkit.ik.geometric import search as S
    from armkit.ik.geometric.solvers import _prepare

    ek = S.kernels()
    count: collections.Counter = collections.Counter()
    plain = S._eval

    def counted(*a):                      # the caller's name (through _pick: its caller's)
        f = sys._getframe(1)
        name = f.f_code.co_name
        if name == "_pick":
            name = sys._getframe(2).f_code.co_name
        count[name] += 1
        return plain(*a)

    kinds = ((S.TI, "two_intersecting", lambda g: _random_arm(int(g.integers(1 << 30)), slice(4, 6))),
             (S.TP, "two_parallel", _two_parallel_arm))
    print(f"1-D search profile, {S.N} samples a turn, {n} targets each: branch evaluations per target by caller,")
    print("CPU ms per target of the compiled grid scan alone and of the whole compiled search")
    T = time.thread_time
    for kind, name, make in kinds:
        g = np.random.default_rng(0)
        count.clear()
        scan, whole = [], []
        roots = np.zeros((S.MAXROOT, 4))
        xs = -np.pi + np.arange(S.N + 1) * (2 * np.pi / S.N)
        Sx = np.zeros((S.N + 1, 4, 3))
        E = np.zeros((S.N + 1, 4))
        cnt = np.zeros(S.N + 1, dtype=np.int64)
        for i in range(n):
            form = make(g)
            R, p = form.fk(g.uniform(-np.pi, np.pi, 6))
            prep = _prepare(form, name)
            C = _search_target(kind, S, prep.Hi, prep.Pi, R @ np.asarray(form.R_nT).T, p)
            S._eval = counted
            try:
                S._search(kind, prep.Hi, prep.Pi, C, S.N, roots)
            finally:
                S._eval = plain
            ek._search(kind, prep.Hi, prep.Pi, C, S.N, roots)      # compiled: warm
            t0 = T()
            ek._scan(kind, prep.Hi, prep.Pi, C, xs, Sx, E, cnt)
            t1 = T()
            ek._search(kind, prep.Hi, prep.Pi, C, S.N, roots)
            t2 = T()
            scan.append(t1 - t0)
            whole.append(t2 - t1)
        parts = ", ".join(f"{k.lstrip('_')} {v / n:.0f}" for k, v in count.most_common())
        print(f"{name:18s} evaluations {sum(count.values()) / n:.0f} ({parts}); scan {1e3 * np.median(scan):.3f} ms, "
              f"search {1e3 * np.median(whole):.3f} ms")
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"(load average {load:.1f} on {os.cpu_count()} cores while measuring)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--targets", type=int, default=500)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--searches", action="store_true", help="only the 1-D searches (median ms per target)")
    ap.add_argument("--search-targets", type=int, default=200)
    ap.add_argument("--search-profile", action="store_true",
                    help="where the 1-D searches TI, TP spend their time (evaluations by caller; scan against search)")
    args = ap.parse_args()
    if args.search_profile:
        G.kernels()
        search_profile(min(args.search_targets, 20))
        return
    if args.searches:
        G.kernels()
        searches(args.search_targets)
        return

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
