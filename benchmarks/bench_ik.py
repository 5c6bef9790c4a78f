"""Inverse kinematics, TRAC-IK style: success rate, wrong answers and time, armkit against its peers.

For each arm (default: puma560, ur5, panda, fighter, planar3) it draws ``--n`` (default
10,000) joint vectors uniformly inside the limits (seeded), takes their FK as targets
(full poses for 6- and 7-DOF arms, positions for the 3-DOF fighter and planar3) and
solves them from the zero initial guess with

* armkit ``method="auto"`` (the closed form where the structure admits one) and ``"lm"``,
  one call per target (single-call latency: ``armkit.ik`` on one (4, 4) pose or (3,) point, ``solve_lm`` on a
  batch of one) and one call for the whole batch;
* the peers when importable (run under ``.venv-bench/bin/python``): RTB ``ETS.ik_LM``
  (C++, tolerance set tight), ikpy, pytorch_kinematics ``PseudoInverseIK`` (batched) and a
  Pinocchio damped-least-squares loop (the library's own example algorithm). Slow
  Python peers get a subset (``--peer-n``), said in the table.

Every answer is judged by armkit's own FK check (position error <= 1e-9 m, or 1e-6 mm for
the mm arm, rotation error <= 1e-9 rad, joints within limits). "wrong" counts answers the
solver flagged as success although the check fails. Times are per target: median and p95
of single calls, and batch time / number of targets. Ratios are peer / armkit lm.

Usage::

    .venv-bench/bin/python benchmarks/bench_ik.py                 # full run
    .venv-bench/bin/python benchmarks/bench_ik.py --n 1000 --robots ur5 panda
    .venv-bench/bin/python benchmarks/bench_ik.py --n 2000 --peer-n 100 --pk-n 300   # a few minutes
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path
from typing import Any, Callable, Optional

import numpy as np

import os

os.environ.setdefault("ARMKIT_JIT", "wait")   # compile in this process: time compiled kernels, never the NumPy stand-in

import armkit  # noqa: E402
from armkit.ik.numeric import solve_lm
from armkit.ik.result import default_tolerance
from armkit.spatial import pose_error

sys.path.insert(0, str(Path(__file__).resolve().parent))
try:
    import _peers  # noqa: E402
except ImportError:  # pragma: no cover
    _peers = None

ROBOTS = ("puma560", "ur5", "panda", "fighter", "planar3")
POSITION_ONLY = ("fighter", "planar3")


class Row:
    def __init__(self, robot: str, solver: str, n: int, ok: np.ndarray, flagged: Optional[np.ndarray],
                 single: Optional[np.ndarray], batch: Optional[float], note: str = "") -> None:
        self.robot, self.solver, self.n, self.note = robot, solver, n, note
        self.success = float(np.mean(ok)) if len(ok) else float("nan")
        self.wrong = int(np.sum(flagged & ~ok)) if flagged is not None else None
        self.median = float(np.median(single)) if single is not None and len(single) else None
        self.p95 = float(np.percentile(single, 95)) if single is not None and len(single) else None
        self.batch = batch


def judge(robot: armkit.Robot, q: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """armkit's FK check of answers q (B, n) against targets (B, 4, 4) or (B, 3)."""
    tp, tr = default_tolerance(robot)
    q = np.asarray(q, dtype=float)
    good = np.all(np.isfinite(q), axis=-1)
    q = np.where(good[:, None], q, 0.0)
    T = armkit.fk(robot, q)
    if targets.shape[-1] == 3 and targets.ndim == 2:
        dp = np.linalg.norm(T[:, :3, 3] - targets, axis=-1)
        dr = np.zeros_like(dp)
    else:
        dp, dr = pose_error(T, targets)
    return good & (dp <= tp) & (dr <= tr) & robot.within_limits(q, tol=1e-9)


def own_fk_note(robot: armkit.Robot, peer_fk: Callable[[np.ndarray], np.ndarray], q: np.ndarray,
                targets: np.ndarray) -> str:
    """Success judged by the peer's own FK model (same tolerance): separates solver failures from model drift."""
    tp, tr = default_tolerance(robot)
    T = np.stack([peer_fk(np.asarray(x, dtype=float)) for x in q])
    if targets.ndim == 2:
        ok = np.linalg.norm(T[:, :3, 3] - targets, axis=-1) <= tp
    else:
        dp, dr = pose_error(T, targets)
        ok = (dp <= tp) & (dr <= tr)
    ok &= robot.within_limits(np.asarray(q, dtype=float), tol=1e-9)
    return f"{100 * ok.mean():.1f} % by its own FK"


def timed_loop(fn: Callable[[int], Any], count: int) -> tuple[list, np.ndarray]:
    out, times = [], np.empty(count)
    for i in range(count):
        t0 = time.perf_counter()
        out.append(fn(i))
        times[i] = time.perf_counter() - t0
    return out, times


# ------------------------------------------------------------------------------- armkit
def bench_armkit(robot: armkit.Robot, targets: np.ndarray, single_n: int, seed: int) -> list[Row]:
    rows = []
    B, n = len(targets), robot.n
    zeros = np.zeros((B, n))
    try:
        from armkit.ik import ik as ik_api
    except ImportError:
        ik_api = None
    solvers: list[tuple[str, Callable]] = []
    if ik_api is not None:
        solvers.append(("armkit auto", lambda t, q0: ik_api(robot, t, q0, method="auto", seed=seed)))
    else:
        print("  (armkit.ik dispatcher not importable: 'auto' skipped)")
    solvers.append(("armkit lm", lambda t, q0: solve_lm(robot, t, q0, seed=seed)))
    solvers.append(("armkit lm restarts=50", lambda t, q0: solve_lm(robot, t, q0, seed=seed, restarts=50)))
    for name, solve in solvers:
        # Warm up every route the timed calls take, so no JIT compile lands inside a timing (issue 10):
        # a single call, a small batch and a batch as large as the timed one (large batches take the
        # one-pass kernels), and report the first (cold) call separately.
        t0 = time.perf_counter()
        solve(targets[:1], zeros[:1])
        cold = time.perf_counter() - t0
        if name == "armkit auto":
            solve(targets[0], zeros[0])
        solve(targets[:2], zeros[:2])
        solve(targets, zeros)
        t0 = time.perf_counter()
        res = solve(targets, zeros)
        batch = (time.perf_counter() - t0) / B
        ok = judge(robot, res.q, targets)
        flagged = np.asarray(res.success)
        m = min(single_n, B)
        if name == "armkit auto":   # armkit.ik: one target as a user passes it, a (4, 4) pose or (3,) point
            singles, times = timed_loop(lambda i: solve(targets[i], zeros[i]), m)
        else:                       # solve_lm takes batches: a batch of one
            singles, times = timed_loop(lambda i: solve(targets[i:i + 1], zeros[i:i + 1]), m)
        ok_s = judge(robot, np.concatenate([np.asarray(r.q).reshape(-1, n) for r in singles]), targets[:m])
        fl_s = np.concatenate([np.asarray(r.success).reshape(-1) for r in singles])
        note = ("" if m == B else f"single calls on {m}") + f" first call {1e3 * cold:.0f} ms"
        if np.any(ok_s != ok[:m]):
            note += f" single!=batch on {int(np.sum(ok_s != ok[:m]))}"
        row = Row(robot.name, name, B, ok, flagged, times, batch, note.strip())
        row.wrong = (row.wrong or 0) + int(np.sum(fl_s & ~ok_s))   # wrong answers of batch and single calls
        rows.append(row)
        if name == "armkit lm":
            reasons = dict(zip(*np.unique(res.reason, return_counts=True)))
            print(f"  armkit lm reasons: {reasons}; iterations median {np.median(res.iterations):.0f}, "
                  f"p99 {np.percentile(res.iterations, 99):.0f}")
    return rows


# -------------------------------------------------------------------------------- peers
def bench_rtb(robot: armkit.Robot, targets: np.ndarray, count: int) -> Optional[Row]:
    built = _peers.build_rtb(robot)
    if built is None:
        return None
    ets = built[1].model
    n = robot.n
    position = targets.ndim == 2
    mask = np.array([1, 1, 1, 0, 0, 0.0]) if position else None
    Ts = [_as_pose(t) for t in targets[:count]]
    kw = dict(q0=np.zeros(n), tol=1e-20, joint_limits=True)
    if mask is not None:
        kw["mask"] = mask
    ets.ik_LM(Ts[0], **kw)
    out, times = timed_loop(lambda i: ets.ik_LM(Ts[i], **kw), count)
    q = np.array([o.q if hasattr(o, "q") else o[0] for o in out])
    flagged = np.array([bool(o.success if hasattr(o, "success") else o[1]) for o in out])
    ok = judge(robot, q, targets[:count])
    return Row(robot.name, "RTB ETS.ik_LM (C++)", count, ok, flagged, times, None, "tol=1e-20 (residual E)")


def _as_pose(t: np.ndarray) -> np.ndarray:
    if t.shape == (3,):
        T = np.eye(4)
        T[:3, 3] = t
        return T
    return t


def bench_ikpy(robot: armkit.Robot, targets: np.ndarray, count: int) -> Optional[Row]:
    peer = _peers.build_ikpy(robot)
    if peer is None:
        return None
    chain = peer.model
    n = robot.n
    position = targets.ndim == 2
    init = np.zeros(n + 2)

    def one(i: int) -> np.ndarray:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            if position:
                sol = chain.inverse_kinematics(targets[i], initial_position=init)
            else:
                sol = chain.inverse_kinematics_frame(targets[i], initial_position=init, orientation_mode="all")
        return sol[1:-1]

    out, times = timed_loop(one, count)
    ok = judge(robot, np.array(out), targets[:count])
    return Row(robot.name, "ikpy", count, ok, None, times, None,
               "no success flag; " + own_fk_note(robot, peer.fk, np.array(out), targets[:count]))


def bench_pytorch_kinematics(robot: armkit.Robot, targets: np.ndarray, count: int) -> Optional[Row]:
    peer = _peers.build_pytorch_kinematics(robot)
    if peer is None:
        return None
    import pytorch_kinematics as pk
    import torch

    chain = peer.model
    lim = torch.tensor(np.stack([robot.lower, robot.upper], axis=-1), dtype=torch.float64)
    Ts = np.stack([_as_pose(t) for t in targets[:count]])
    position = targets.ndim == 2
    solver = pk.PseudoInverseIK(chain, max_iterations=100, num_retries=10, joint_limits=lim,
                                early_stopping_any_converged=True, early_stopping_no_improvement="all",
                                pos_tolerance=1e-9 * (1000 if robot.unit == "mm" else 1),
                                rot_tolerance=1e-9 if not position else 1e9, debug=False, lr=0.2)
    t0 = time.perf_counter()
    sol = solver.solve(pk.Transform3d(matrix=torch.from_numpy(Ts)))
    batch = (time.perf_counter() - t0) / count
    conv = sol.converged.numpy()
    # pick the first converged retry, else the retry with the smallest position error
    err = sol.err_pos.numpy()
    pick = np.where(conv.any(1), conv.argmax(1), err.argmin(1))
    q = sol.solutions.numpy()[np.arange(count), pick]
    ok = judge(robot, q, targets[:count])
    return Row(robot.name, "pytorch_kinematics", count, ok, conv.any(1), None, batch,
               "PseudoInverseIK, 10 retries; " + own_fk_note(robot, peer.fk, q, targets[:count]))


def bench_pinocchio(robot: armkit.Robot, targets: np.ndarray, count: int) -> Optional[Row]:
    peer = _peers.build_pinocchio(robot)
    if peer is None:
        return None
    import pinocchio as pin

    model, data, fid = peer.model
    position = targets.ndim == 2
    eps = default_tolerance(robot)[0] * 0.5
    lo, hi = robot.lower, robot.upper

    def one(i: int) -> tuple[np.ndarray, bool]:  # the DLS loop of Pinocchio's documentation, frame version
        T = _as_pose(targets[i])
        oMdes = pin.SE3(T[:3, :3].copy(), T[:3, 3].copy())
        q = np.zeros(robot.n)
        for _ in range(1000):
            pin.forwardKinematics(model, data, q)
            oMf = pin.updateFramePlacement(model, data, fid)
            if position:
                err = oMf.translation - oMdes.translation
                if np.linalg.norm(err) < eps:
                    return q, True
                J = pin.computeFrameJacobian(model, data, q, fid, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)[:3]
            else:
                iMd = oMf.actInv(oMdes)
                err = pin.log(iMd).vector
                if np.linalg.norm(err) < eps:
                    return q, True
                J = -pin.Jlog6(iMd.inverse()) @ pin.computeFrameJacobian(model, data, q, fid)
            v = -J.T @ np.linalg.solve(J @ J.T + 1e-8 * np.eye(J.shape[0]), err)  # example: 1e-12; 1e-8 so
            # that the singular start of a position-only 3-DOF arm does not raise
            q = np.clip(pin.integrate(model, q, v * 0.5), lo, hi)
        return q, False

    out, times = timed_loop(one, count)
    q = np.array([o[0] for o in out])
    ok = judge(robot, q, targets[:count])
    return Row(robot.name, "pinocchio DLS loop", count, ok, np.array([o[1] for o in out]), times, None,
               "Python loop, clamped limits; " + own_fk_note(robot, peer.fk, q, targets[:count]))


# -------------------------------------------------------------------------------- report
def ms(x: Optional[float]) -> str:
    return "-" if x is None else f"{x * 1e3:.4f}"


def print_table(rows: list[Row]) -> None:
    head = f"{'robot':9} {'solver':24} {'targets':>7} {'success %':>9} {'wrong':>5} {'single med ms':>13} " \
           f"{'p95 ms':>8} {'batch ms/target':>15}  note"
    print(head)
    print("-" * len(head))
    for r in rows:
        wrong = "-" if r.wrong is None else str(r.wrong)
        print(f"{r.robot:9} {r.solver:24} {r.n:7d} {100 * r.success:9.2f} {wrong:>5} {ms(r.median):>13} "
              f"{ms(r.p95):>8} {ms(r.batch):>15}  {r.note}")
    print("\nratios (peer time / armkit lm time; above 1 means armkit is faster):")
    for robot in dict.fromkeys(r.robot for r in rows):
        base = next((r for r in rows if r.robot == robot and r.solver == "armkit lm"), None)
        if base is None:
            continue
        for r in rows:
            if r.robot != robot or r is base:
                continue
            parts = []
            if r.median is not None and base.median:
                parts.append(f"single {r.median / base.median:.2f}x")
            if r.batch is not None and base.batch:
                parts.append(f"batch {r.batch / base.batch:.2f}x")
            if parts:
                print(f"  {robot:9} {r.solver:24} " + ", ".join(parts))


def main(argv: Optional[list[str]] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=10_000, help="targets per robot (default 10000)")
    ap.add_argument("--single", type=int, default=None, help="targets solved one call at a time (default: all)")
    ap.add_argument("--peer-n", type=int, default=300, help="targets for slow Python-loop peers (ikpy, Pinocchio)")
    ap.add_argument("--pk-n", type=int, default=1000, help="targets for pytorch_kinematics (slow on CPU)")
    ap.add_argument("--robots", nargs="+", default=list(ROBOTS))
    ap.add_argument("--seed", type=int, default=2026)
    args = ap.parse_args(argv)
    print(f"armkit {armkit.__version__}, backend {armkit.get_backend()}, numpy {np.__version__}, "
          f"python {sys.version.split()[0]}")
    if _peers is None:
        print("benchmarks/_peers.py not importable: peers skipped")
    rows: list[Row] = []
    for name in args.robots:
        robot = armkit.load(name)
        q = robot.random_q(args.n, args.seed)
        T = armkit.fk(robot, q)
        targets = T[:, :3, 3].copy() if name in POSITION_ONLY else T
        kind = "positions" if name in POSITION_ONLY else "poses"
        print(f"\n{name}: {args.n} reachable target {kind} from FK of random in-limit q (seed {args.seed}), q0 = 0")
        rows += bench_armkit(robot, targets, args.single or args.n, args.seed)
        if _peers is None:
            continue
        for label, fn, count in (("RTB", bench_rtb, args.n),
                                 ("pytorch_kinematics", bench_pytorch_kinematics, min(args.pk_n, args.n)),
                                 ("ikpy", bench_ikpy, min(args.peer_n, args.n)),
                                 ("pinocchio", bench_pinocchio, min(args.peer_n, args.n))):
            try:
                row = fn(robot, targets, count)
            except Exception as exc:  # a peer's failure must not stop the benchmark; say what happened
                print(f"  {label}: failed ({type(exc).__name__}: {exc}); skipped")
                continue
            if row is None:
                print(f"  {label}: not installed; skipped")
            else:
                rows.append(row)
    print()
    print_table(rows)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
