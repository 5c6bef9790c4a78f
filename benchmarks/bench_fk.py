"""Forward kinematics and Jacobian speed: armkit against its peers, in one run.

For each arm (default: puma560, ur5, panda) it measures

* single-call latency of FK and of the geometric Jacobian (median over many calls),
* batched FK throughput on ``--batch`` configurations (default 1,000,000) and the peak
  memory that call adds beyond its output (``tracemalloc``), also with ``out=`` (one reused buffer),

for armkit (Numba and NumPy back ends) and, when installed (``pip install -e '.[bench]'``
or ``make bench``), Pinocchio, RTB (Python ``DHRobot`` and its C++ ``ETS``), ikpy and
pytorch_kinematics. Peers without a batched FK are timed in a Python loop over a subset
(``--loop``) and the rate is reported per configuration. Before timing a peer its FK (and
Jacobian) is checked against armkit's at random configurations; a mismatch is printed and
that peer is skipped. Ratios are peer time / armkit (Numba) time: above 1 means armkit is
faster.

Single-call latencies are measured interleaved (round-robin over all libraries, median over
rounds), so that a busy machine slows every library alike.

Usage::

    .venv-bench/bin/python benchmarks/bench_fk.py                  # full run (a few minutes)
    .venv-bench/bin/python benchmarks/bench_fk.py --quick          # smaller batches, fewer repeats
    .venv-bench/bin/python benchmarks/bench_fk.py --robots ur5 --json out/bench_fk.json
"""

from __future__ import annotations

import argparse
import gc
import json
import os
import platform
import statistics
import sys
import time
import tracemalloc
import warnings
from pathlib import Path
from typing import Callable

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _peers  # noqa: E402

os.environ.setdefault("ARMKIT_JIT", "wait")   # compile in this process: time compiled kernels, never the NumPy stand-in
import armkit  # noqa: E402
from armkit import kinematics  # noqa: E402

warnings.filterwarnings("ignore")


# ------------------------------------------------------------------------ measuring
def latencies(calls: dict[str, Callable[[], object]], rounds: int = 41, chunk: float = 0.002) -> dict[str, float]:
    """Median time of one call of each function, in seconds.

    The functions are measured *interleaved*: each round times a short chunk (``chunk``
    seconds) of calls of every function in turn, so that a busy machine (shared cores)
    slows all of them alike and the ratios stay fair; the result is the median over rounds.
    """
    number = {}
    for key, f in calls.items():
        f()
        t0 = time.perf_counter()
        f()
        f()
        one = max((time.perf_counter() - t0) / 2, 1e-7)
        number[key] = max(1, int(chunk / one))
    times: dict[str, list[float]] = {key: [] for key in calls}
    for _ in range(rounds):
        for key, f in calls.items():
            n = number[key]
            t0 = time.perf_counter()
            for _ in range(n):
                f()
            times[key].append((time.perf_counter() - t0) / n)
    return {key: statistics.median(v) for key, v in times.items()}


def throughput(run: Callable[[], object], count: int, repeats: int) -> tuple[float, float]:
    """``(configurations per second (median of repeats), peak extra bytes of one run)``."""
    gc.collect()
    tracemalloc.start()
    result = run()
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    del result
    times = []
    for _ in range(repeats):
        gc.collect()
        t0 = time.perf_counter()
        result = run()
        times.append(time.perf_counter() - t0)
        del result
    return count / statistics.median(times), float(peak)


def looped(f: Callable[[np.ndarray], object], Q: np.ndarray) -> Callable[[], list]:
    return lambda: [f(q) for q in Q]


# ---------------------------------------------------------------------------- rows
class Row:
    def __init__(self, library: str, fk: float | None = None, jac: float | None = None,
                 rate: float | None = None, memory: float | None = None, note: str = "",
                 jac_rate: float | None = None):
        self.library, self.fk, self.jac, self.rate, self.memory, self.note = library, fk, jac, rate, memory, note
        self.jac_rate = jac_rate


def agree(robot, peer: _peers.Peer, rng: np.random.Generator) -> str:
    """'' when the peer's FK (and Jacobian) equal armkit's at random q, else what differs."""
    scale = max(1.0, robot.reach)
    tol = 1e-6 if peer.name == "pytorch_kinematics" else 1e-9  # pk parses URDF angles as float32
    kinematics.set_backend("numpy")
    try:
        for q in robot.random_q(5, rng=rng):
            dT = np.abs(np.asarray(peer.fk(q)) - armkit.fk(robot, q)).max() / scale
            if not dT <= tol:
                return f"FK differs by {dT:.2e} (relative to reach) at q={np.round(q, 4).tolist()}"
            if peer.jacobian is not None:
                dJ = np.abs(np.asarray(peer.jacobian(q)) - armkit.jacobian(robot, q)).max() / scale
                if not dJ <= tol:
                    return f"Jacobian differs by {dJ:.2e} at q={np.round(q, 4).tolist()}"
        if peer.fk_batch is not None:
            Q = robot.random_q(64, rng=rng)
            dT = np.abs(peer.fk_batch(Q) - armkit.fk(robot, Q)).max() / scale
            if not dT <= tol:
                return f"batched FK differs by {dT:.2e}"
    except Exception as exc:  # a peer that cannot even run this arm is reported, not fatal
        return f"{type(exc).__name__}: {exc}"
    finally:
        kinematics.set_backend("auto")
    return ""


def bench_robot(name: str, batch: int, loop: int, repeats: int, rounds: int) -> list[Row]:
    robot = armkit.load(name)
    rng = np.random.default_rng(7)
    q = robot.random_q(rng=rng)
    Q = robot.random_q(batch, rng=rng)

    peers = []
    for peer in _peers.peers_for(robot):
        problem = agree(robot, peer, rng)
        if problem:
            print(f"  [{name}] {peer.name}: MISMATCH, not timed: {problem}")
        else:
            peers.append(peer)

    # single calls, interleaved; the back end is switched inside the call for armkit
    def armkit_call(backend: str, f: Callable) -> Callable[[], object]:
        if backend == "numba":
            return lambda: f(robot, q)

        def call() -> object:
            kinematics.set_backend("numpy")
            try:
                return f(robot, q)
            finally:
                kinematics.set_backend("auto")
        return call

    calls: dict[str, Callable[[], object]] = {}
    for backend in ("numba", "numpy"):
        calls[f"armkit ({backend}) fk"] = armkit_call(backend, armkit.fk)
        calls[f"armkit ({backend}) jac"] = armkit_call(backend, armkit.jacobian)
    for peer in peers:
        calls[f"{peer.name} fk"] = lambda peer=peer: peer.fk(q)
        if peer.jacobian is not None:
            calls[f"{peer.name} jac"] = lambda peer=peer: peer.jacobian(q)
    lat = latencies(calls, rounds=rounds)

    rows = []
    for backend in ("numba", "numpy"):
        kinematics.set_backend(backend)
        armkit.fk(robot, Q[:5000])  # loads the threaded kernel too, so that no compile is traced
        rate, mem = throughput(lambda: armkit.fk(robot, Q), batch, repeats)
        QJ = Q[: batch // 4]  # Jacobians are (6, n) each: a quarter of the batch is plenty
        armkit.jacobian(robot, QJ[:5000])
        jac_rate, _ = throughput(lambda: armkit.jacobian(robot, QJ), len(QJ), max(1, repeats // 2))
        rows.append(Row(f"armkit ({backend})", lat[f"armkit ({backend}) fk"], lat[f"armkit ({backend}) jac"],
                        rate, mem, f"batch of {batch:,} (Jacobians: {len(QJ):,})", jac_rate))
        if backend == "numba":   # out=: one buffer for every call, no fresh output memory to allocate and touch
            buf, bufJ = np.empty((batch, 4, 4)), np.empty((len(QJ), 6, robot.n))
            rate, mem = throughput(lambda: armkit.fk(robot, Q, out=buf), batch, repeats)
            jac_rate, _ = throughput(lambda: armkit.jacobian(robot, QJ, out=bufJ), len(QJ), max(1, repeats // 2))
            rows.append(Row("armkit (numba, out=)", None, None, rate, mem + batch * 16 * 8,
                            "the same batches into one reused buffer", jac_rate))
            del buf, bufJ
    kinematics.set_backend("auto")

    for peer in peers:
        if peer.fk_batch is not None:
            rate, _ = throughput(lambda: peer.fk_batch(Q), batch, max(1, repeats // 2))
            note = f"batched call on {batch:,}"  # memory: torch's and RTB's C++ allocations are not traced
        else:
            slow = peer.name in ("rtb DHRobot", "ikpy")
            count = min(batch, loop // 20 if slow else loop)
            rate, _ = throughput(looped(peer.fk, Q[:count]), count, 1)
            note = f"Python loop over {count:,}"
        rows.append(Row(peer.name, lat[f"{peer.name} fk"], lat.get(f"{peer.name} jac"), rate, None, note))
    return rows


# -------------------------------------------------------------------------- output
def _us(x: float | None) -> str:
    return "-" if x is None else f"{x * 1e6:,.2f}"


def _ratio(x: float | None, ref: float | None, inverse: bool = False) -> str:
    if x is None or ref is None:
        return ""
    r = (ref / x) if inverse else (x / ref)
    return f" ({r:.2g}x)"


def table(name: str, rows: list[Row], out_bytes: int) -> list[list[str]]:
    ref = rows[0]
    lines = []
    for r in rows:
        mem = "-" if r.memory is None else f"{(r.memory - out_bytes) / 2**20:,.1f}"
        lines.append([name, r.library,
                      _us(r.fk) + ("" if r is ref else _ratio(r.fk, ref.fk)),
                      _us(r.jac) + ("" if r is ref else _ratio(r.jac, ref.jac)),
                      ("-" if r.rate is None else f"{r.rate / 1e6:,.3f}") + ("" if r is ref else _ratio(r.rate, ref.rate, True)),
                      mem,
                      ("-" if r.jac_rate is None else f"{r.jac_rate / 1e6:,.3f}")
                      + ("" if r is ref or r.jac_rate is None else _ratio(r.jac_rate, ref.jac_rate, True)),
                      r.note])
    return lines


HEADER = ["arm", "library", "FK µs", "Jacobian µs", "batched FK M/s", "extra MiB", "batched J M/s", "how"]


def print_table(lines: list[list[str]]) -> None:
    try:
        from rich.console import Console
        from rich.table import Table
    except ImportError:
        print(" | ".join(HEADER))
        for line in lines:
            print(" | ".join(line))
        return
    t = Table(title="armkit vs peers (ratio in brackets: peer time / armkit-numba time)")
    for h in HEADER:
        t.add_column(h, justify="left" if h in ("arm", "library", "how") else "right")
    for line in lines:
        t.add_row(*line)
    Console(width=160).print(t)


def markdown(lines: list[list[str]]) -> str:
    out = ["| " + " | ".join(HEADER) + " |", "|" + "---|" * len(HEADER)]
    out += ["| " + " | ".join(line) + " |" for line in lines]
    return "\n".join(out)


def machine() -> str:
    import numba

    from importlib import metadata

    versions = [f"python {platform.python_version()}", f"numpy {np.__version__}", f"numba {numba.__version__}"]
    for dist in ("pin", "roboticstoolbox-python", "ikpy", "torch", "pytorch-kinematics"):
        try:
            versions.append(f"{dist} {metadata.version(dist)}")
        except metadata.PackageNotFoundError:
            versions.append(f"{dist} (not installed)")
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as fh:
            cpu = next(line.split(":", 1)[1].strip() for line in fh if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return (f"{cpu}, {os.cpu_count()} cores, numba threads {numba.get_num_threads()}; "
            + ", ".join(versions))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--robots", nargs="+", default=["puma560", "ur5", "panda"])
    ap.add_argument("--batch", type=int, default=1_000_000, help="configurations in the batched FK")
    ap.add_argument("--loop", type=int, default=100_000, help="configurations for peers timed in a Python loop")
    ap.add_argument("--repeats", type=int, default=5, help="timed runs of each batched call (median)")
    ap.add_argument("--rounds", type=int, default=41, help="interleaved rounds of the single-call timings")
    ap.add_argument("--quick", action="store_true", help="batch 100,000, loop 10,000, fewer repeats and rounds")
    ap.add_argument("--json", type=Path, help="also write the results here")
    ap.add_argument("--markdown", action="store_true", help="also print the table as Markdown")
    args = ap.parse_args(argv)
    if args.quick:
        args.batch, args.loop, args.repeats, args.rounds = 100_000, 10_000, 3, 15

    print(machine())
    lines, results = [], {}
    for name in args.robots:
        t0 = time.perf_counter()
        rows = bench_robot(name, args.batch, args.loop, args.repeats, args.rounds)
        lines += table(name, rows, args.batch * 16 * 8)
        results[name] = [vars(r) for r in rows]
        print(f"  {name}: measured in {time.perf_counter() - t0:.0f} s")
    print_table(lines)
    if args.markdown:
        print(markdown(lines))
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps({"machine": machine(), "batch": args.batch, "results": results}, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
