"""First-call times on a fresh install (issue 15): before and after, each in a fresh process with an empty cache.

Every cold measurement runs in a new Python process whose ``NUMBA_CACHE_DIR`` is a new empty
temp directory, so nothing compiled earlier helps; "before" runs the same code against the
armkit sources of an older commit (``--before``, extracted with ``git archive`` into a temp
directory and put first on ``PYTHONPATH``), "after" against the working tree. Measured:

* ``first fk``: ``import armkit; armkit.fk(arm, q)`` with one configuration (import not included);
* ``first ik``: the first call of the process is ``armkit.ik(arm, T)`` for one pose;
* ``first ik x5000``: the first call of the process is ``armkit.ik`` of 5,000 poses;
* ``fk, ik, ik x5000 in a row``: the issue's session: the three calls in one process;
* ``compiled after``: (after only) seconds until the background warm-up's kernels are in use;
* warm: after everything is compiled and cached, median of single ``fk``/``jacobian``/``ik``
  calls (µs) and of ``ik`` of 5,000 poses (ms).
* ``first batched fk of 1,000,000 vs later`` (``--first-batch``; issue 19): in a fresh process with a
  warm cache, after one single ``fk`` (which imports and sets up Numba, 1-4 s of its own: the "first fk"
  row), the first ``fk`` of 1,000,000 configurations against the next three (ratio printed), split
  into its parts: loading the threaded kernel from the cache, starting Numba's threads, and touching the
  fresh 128 MB output. The same with the output's memory recycled (the process touched and freed 128 MB
  first), after a 5 s pause, and with ``out=`` reusing one buffer.

Targets are the FK of random joint vectors inside the limits (seeded), computed here with the
NumPy back end. For puma560 ``ik`` is the closed form; for panda Levenberg-Marquardt. The
background warm-up process a cold "after" run starts is stopped when the measurement ends (it
would otherwise load the machine during the next one). Times on a shared machine move with the
load: each number is the median of ``--repeat`` runs, and the load average is printed.

Usage::

    .venv/bin/python benchmarks/bench_first_call.py                       # before = a8d5fc6^, after = tree
    .venv/bin/python benchmarks/bench_first_call.py --robots panda --repeat 5
    .venv/bin/python benchmarks/bench_first_call.py --before none         # after only
    .venv/bin/python benchmarks/bench_first_call.py --first-batch          # only the first big batch
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
BEFORE = "a8d5fc6^"  # the last commit before issue 15's work

_CHILD = r"""
import json, os, sys, time
t0 = time.perf_counter()
import numpy as np
import armkit
t_import = time.perf_counter() - t0
arm = armkit.load(ROBOT)
data = np.load(DATA)
q, T, TT, Q = data["q"], data["T"], data["TT"], data["Q"]
out = {"import": t_import}

def timed(name, fn):
    t = time.perf_counter()
    fn()
    out[name] = time.perf_counter() - t

for step in STEPS:
    if step == "fk":
        timed("fk", lambda: armkit.fk(arm, q))
    elif step == "ik":
        timed("ik", lambda: armkit.ik(arm, T))
    elif step == "ik5000":
        timed("ik5000", lambda: armkit.ik(arm, TT))
    elif step == "switch":
        while armkit.get_backend() != "numba":
            armkit.fk(arm, q)
            time.sleep(0.02)
        out["switch"] = time.perf_counter() - t0
    elif step == "warm":
        if hasattr(armkit, "warmup"):
            armkit.warmup()
        armkit.fk(arm, q); armkit.jacobian(arm, q); armkit.ik(arm, T); armkit.ik(arm, TT); armkit.fk(arm, Q)

        def per_call(fn, n):
            best = []
            for _ in range(7):
                t = time.perf_counter()
                for _ in range(n):
                    fn()
                best.append((time.perf_counter() - t) / n)
            return sorted(best)[3]

        out["warm fk us"] = 1e6 * per_call(lambda: armkit.fk(arm, q), 2000)
        out["warm jacobian us"] = 1e6 * per_call(lambda: armkit.jacobian(arm, q), 2000)
        out["warm ik us"] = 1e6 * per_call(lambda: armkit.ik(arm, T), 50)
        out["warm ik x5000 ms"] = 1e3 * per_call(lambda: armkit.ik(arm, TT), 1)
        out["warm fk x100000 ms"] = 1e3 * per_call(lambda: armkit.fk(arm, Q), 1)
        out["backend"] = armkit.get_backend()
try:
    from armkit import _jit_loader
    if _jit_loader._worker is not None and "switch" not in STEPS:
        _jit_loader._worker.kill()      # do not load the machine during the next measurement
        _jit_loader._worker.wait()
except ImportError:
    pass
print(json.dumps(out))
"""


def _targets(robot: str, path: Path) -> None:
    import armkit

    armkit.set_backend("numpy")
    arm = armkit.load(robot)
    q = arm.random_q(rng=0)
    Q5 = arm.random_q(5000, rng=1)
    np.savez(path, q=q, T=armkit.fk(arm, arm.random_q(rng=2)), TT=armkit.fk(arm, Q5), Q=arm.random_q(100_000, rng=3))


def _run(src: Path, robot: str, data: Path, steps: list[str], cache: Path | None, timeout: float) -> dict:
    code = _CHILD.replace("ROBOT", repr(robot)).replace("DATA", repr(str(data))).replace("STEPS", repr(steps))
    env = {k: v for k, v in os.environ.items() if not k.startswith(("ARMKIT_", "NUMBA_CACHE_DIR"))}
    env["PYTHONPATH"] = str(src)
    own = None
    if cache is None:
        own = tempfile.TemporaryDirectory(prefix="armkit-bench-cache-")
        cache = Path(own.name)
    env["NUMBA_CACHE_DIR"] = str(cache)
    try:
        res = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=timeout)
    finally:
        if own is not None:
            own.cleanup()
    if res.returncode != 0:
        raise RuntimeError(f"measurement failed ({steps}):\n{res.stderr[-2000:]}")
    return json.loads(res.stdout.strip().splitlines()[-1])


def _extract(rev: str, into: Path) -> Path:
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", rev, "src/armkit"], capture_output=True, check=True)
    tar = into / "src.tar"
    tar.write_bytes(archive.stdout)
    with tarfile.open(tar) as t:
        t.extractall(into, filter="data")
    return into / "src"


def _load() -> str:
    try:
        return "load average " + " ".join(f"{x:.1f}" for x in os.getloadavg())
    except OSError:
        return ""


def measure(src: Path, robot: str, data: Path, repeat: int, after: bool, timeout: float) -> dict[str, float]:
    runs: dict[str, list[float]] = {}

    def add(d: dict) -> None:
        for k, v in d.items():
            if isinstance(v, (int, float)):
                runs.setdefault(k, []).append(float(v))

    for _ in range(repeat):
        add({"first " + k: v for k, v in _run(src, robot, data, ["fk"], None, timeout).items() if k == "fk"})
        add({"first ik": _run(src, robot, data, ["ik"], None, timeout)["ik"]})
        add({"first ik x5000": _run(src, robot, data, ["ik5000"], None, timeout)["ik5000"]})
        seq = _run(src, robot, data, ["fk", "ik", "ik5000"] + (["switch"] if after else []), None, timeout)
        add({"import": seq["import"], "row: fk": seq["fk"], "row: ik": seq["ik"], "row: ik x5000": seq["ik5000"]})
        if after:
            add({"compiled after": seq["switch"]})
    with tempfile.TemporaryDirectory(prefix="armkit-bench-warm-") as warm:
        for _ in range(max(1, repeat)):
            add(_run(src, robot, data, ["warm"], Path(warm), timeout * 4))
    return {k: statistics.median(v) for k, v in runs.items()}


_FIRST_BATCH = r"""
import json, resource, sys, time
import numpy as np
import armkit
from armkit import _jit_loader
arm = armkit.load(ROBOT)
Q = arm.random_q(COUNT, rng=3)
armkit.fk(arm, Q[0])   # Numba imported and set up, the single-call kernel loaded: only the big batch is new
out = {}
if MODE == "split":   # the parts of the first call, one by one, before it
    import numba
    from numba import typeof
    jit = _jit_loader.module("kinematics._jit")
    F = armkit.kinematics.packed(arm)[0]
    t = time.perf_counter(); jit._fk_parallel.compile((typeof(F), typeof(Q), typeof(np.empty((1, 4, 4)))))
    out["load threaded kernel"] = time.perf_counter() - t
    t = time.perf_counter(); numba.get_num_threads()   # starts the threading layer
    out["start threads"] = time.perf_counter() - t
    t = time.perf_counter(); a = np.empty((COUNT, 4, 4)); a.fill(0.0)
    out["touch fresh 128 MB"] = time.perf_counter() - t
    t = time.perf_counter(); a.fill(0.0)
    out["touch it again"] = time.perf_counter() - t
    del a
if MODE == "recycled":   # the process touched and freed as much memory as the output just before
    a = np.empty((COUNT, 4, 4)); a.fill(0.0); del a

def timed(fn):
    r0 = resource.getrusage(resource.RUSAGE_SELF)
    t = time.perf_counter()
    T = fn()
    dt = time.perf_counter() - t
    r1 = resource.getrusage(resource.RUSAGE_SELF)
    return dt, r1.ru_stime - r0.ru_stime

out["calls"], out["sys"] = [], []
for _ in range(4):
    dt, st = timed(lambda: armkit.fk(arm, Q))
    out["calls"].append(dt); out["sys"].append(st)
time.sleep(5.0)
out["after 5 s pause"] = timed(lambda: armkit.fk(arm, Q))[0]
buf = np.empty((COUNT, 4, 4))
out["out="] = [timed(lambda: armkit.fk(arm, Q, out=buf))[0] for _ in range(3)]
print(json.dumps(out))
"""


def first_batch(robot: str, repeat: int, timeout: float, count: int = 1_000_000) -> None:
    """The first batched ``fk`` of ``count`` configurations in a fresh process against the later ones (issue 19)."""
    with tempfile.TemporaryDirectory(prefix="armkit-bench-first-batch-") as cache:
        env = {k: v for k, v in os.environ.items() if not k.startswith(("ARMKIT_", "NUMBA_CACHE_DIR"))}
        # compile on first use (no background warm-up), here only the kernels this measurement calls
        env.update(PYTHONPATH=str(ROOT / "src"), NUMBA_CACHE_DIR=cache, ARMKIT_JIT="wait")
        warm = (f"import armkit; arm = armkit.load({robot!r}); armkit.fk(arm, arm.random_q(rng=0)); "
                "armkit.fk(arm, arm.random_q(5000, rng=1))")
        subprocess.run([sys.executable, "-c", warm], env=env, check=True, capture_output=True, timeout=timeout * 4)
        print(f"\nfirst batched fk of {count:,} vs later ({robot}, warm cache, fresh process each; {_load()})")
        rows: dict[str, list[float]] = {}
        for _ in range(repeat):
            for mode in ("fresh", "recycled", "split"):
                code = (_FIRST_BATCH.replace("ROBOT", repr(robot)).replace("COUNT", str(count))
                        .replace("MODE", repr(mode)))
                res = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                                     timeout=timeout)
                if res.returncode != 0:
                    raise RuntimeError(f"measurement failed ({mode}):\n{res.stderr[-2000:]}")
                d = json.loads(res.stdout.strip().splitlines()[-1])
                first, later = d["calls"][0], statistics.median(d["calls"][1:])
                rows.setdefault(f"{mode}: first call s", []).append(first)
                rows.setdefault(f"{mode}: later calls s", []).append(later)
                rows.setdefault(f"{mode}: first / later", []).append(first / later)
                rows.setdefault(f"{mode}: first call sys s", []).append(d["sys"][0])
                rows.setdefault(f"{mode}: later calls sys s", []).append(statistics.median(d["sys"][1:]))
                if mode == "fresh":
                    rows.setdefault("after a 5 s pause / later", []).append(d["after 5 s pause"] / later)
                    rows.setdefault("out= (one buffer) / later", []).append(statistics.median(d["out="]) / later)
                for k in ("load threaded kernel", "start threads", "touch fresh 128 MB", "touch it again"):
                    if k in d:
                        rows.setdefault(f"part: {k} s", []).append(d[k])
        for k, v in rows.items():
            print(f"  {k:36s} {statistics.median(v):8.3f}   (runs: {', '.join(f'{x:.3f}' for x in v)})")
        print(f"  ({_load()})", flush=True)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--robots", nargs="+", default=["puma560", "panda"])
    ap.add_argument("--repeat", type=int, default=3, help="cold runs per measurement (median)")
    ap.add_argument("--before", default=BEFORE, help=f"git revision to compare with (default {BEFORE}); 'none': skip")
    ap.add_argument("--timeout", type=float, default=300.0, help="seconds per measurement process")
    ap.add_argument("--json", type=Path, help="also write the results here")
    ap.add_argument("--first-batch", action="store_true",
                    help="only the first batched fk of 1,000,000 against the later ones (issue 19)")
    args = ap.parse_args(argv)
    print(f"{_load()}; cpus {os.cpu_count()}; python {sys.version.split()[0]}", flush=True)
    if args.first_batch:
        for robot in args.robots:
            first_batch(robot, args.repeat, args.timeout)
        return 0
    results: dict = {}
    with tempfile.TemporaryDirectory(prefix="armkit-bench-") as tmp:
        before_src = None if args.before == "none" else _extract(args.before, Path(tmp))
        for robot in args.robots:
            data = Path(tmp) / f"{robot}.npz"
            _targets(robot, data)
            row = {}
            if before_src is not None:
                t = time.perf_counter()
                row["before"] = measure(before_src, robot, data, args.repeat, False, args.timeout)
                print(f"  {robot}: before measured in {time.perf_counter() - t:.0f} s ({_load()})", flush=True)
            t = time.perf_counter()
            row["after"] = measure(ROOT / "src", robot, data, args.repeat, True, args.timeout)
            print(f"  {robot}: after measured in {time.perf_counter() - t:.0f} s ({_load()})", flush=True)
            results[robot] = row
            keys = list(dict.fromkeys([*row.get("before", {}), *row["after"]]))
            print(f"\n{robot} (median of {args.repeat}; cold rows in s)")
            print(f"  {'measurement':28s} {'before':>10s} {'after':>10s}")
            for k in keys:
                b = row.get("before", {}).get(k)
                a = row["after"].get(k)
                print(f"  {k:28s} {'-' if b is None else f'{b:10.3f}':>10s} {'-' if a is None else f'{a:10.3f}':>10s}")
            print(flush=True)
    first_batch(args.robots[0], args.repeat, args.timeout)
    print(_load())
    if args.json:
        args.json.write_text(json.dumps(results, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
