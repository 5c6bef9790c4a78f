"""Peak memory of the requests that used to run away (issue 10), each in a fresh process.

Every case runs as its own child process (the ``armkit`` command or a short Python
snippet) and reports the child's peak resident memory (``ru_maxrss`` from ``wait4``),
its exit code and its wall time. Cases:

* ``workspace -n 100000000``: refused before allocating (it would need ~14 GiB);
* ``workspace -n 500000 --manipulability``: allowed, manipulability streamed in chunks;
* ``traj`` with 1e8 samples (``--dt 2e-8`` over 2 s): refused before allocating;
* ``traj`` with 1e6 samples: allowed;
* ``manipulability`` of 10,000,000 configurations through ``armkit.manipulability``;
* ``track --frames 1000`` written to a GIF: frames streamed to disk, one in memory at a time.

``--src DIR`` runs the same cases against another source tree (for a before/after table,
e.g. a ``git worktree`` of an older commit); cases that would exhaust memory there are
skipped unless ``--unsafe`` is given. A memory cap (``--cap-gb``, default 8) is set on
every child with ``RLIMIT_AS`` so a runaway case fails instead of taking the machine.

Usage::

    .venv/bin/python benchmarks/bench_memory.py                 # all cases, this tree
    .venv/bin/python benchmarks/bench_memory.py --quick         # skip the slow track and 10 M manipulability
    .venv/bin/python benchmarks/bench_memory.py --json out/bench_memory.json
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

MANIP_10M = ("import numpy as np, armkit; arm = armkit.load('puma560'); "
             "q = np.zeros((10_000_000, 6), dtype=float); q[:, 1] = 0.3; q[:, 2] = 0.4; "
             "w = armkit.manipulability(arm, q); print(w.shape, float(w[0]))")

CASES = [
    # (name, argv after 'armkit' or ['-c', code], quick, runaway before the fix)
    ("workspace -n 1e8 (refused)", ["workspace", "fighter", "-n", "100000000"], True, True),
    ("workspace -n 5e5 --manipulability", ["workspace", "puma560", "-n", "500000", "--manipulability"], True, False),
    ("traj 1e8 samples (refused)", ["traj", "fighter", "--joint", "0,0,0", "30,45,60", "--deg", "--duration", "2",
                                    "--dt", "2e-8"], True, True),
    ("traj --qdd-max 1e-9 (refused)", ["traj", "fighter", "--joint", "0,0,0", "30,45,60", "--deg",
                                       "--qdd-max", "1e-9"], True, True),
    ("traj 1e6 samples", ["traj", "fighter", "--joint", "0,0,0", "30,45,60", "--deg", "--duration", "2",
                          "--dt", "2e-6"], True, False),
    ("manipulability of 1e7 configurations", ["-c", MANIP_10M], False, False),
    ("track --frames 1000 -> GIF", ["track", "planar3", "--path", "circle", "--method", "analytic", "--frames", "1000",
                                    "-o", "{tmp}/track.gif"], False, False),
]


def run_case(argv: list[str], src: Path, cap_gb: float, tmp: str) -> dict:
    argv = [a.replace("{tmp}", tmp) for a in argv]
    if argv[0] == "-c":
        cmd = [sys.executable] + argv
    else:
        cmd = [sys.executable, "-c", "import sys; from armkit.cli import main; sys.argv[0] = 'armkit'; main()"] + argv
    env = dict(os.environ, PYTHONPATH=str(src / "src"), MPLBACKEND="Agg", COLUMNS="200")
    cap = int(cap_gb * 1024 ** 3)

    def limit() -> None:
        resource.setrlimit(resource.RLIMIT_AS, (cap, cap))

    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, preexec_fn=limit, cwd=tmp)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    out = (proc.stdout.read() + proc.stderr.read()).decode("utf-8", "replace") if proc.stdout and proc.stderr else ""
    code = os.waitstatus_to_exitcode(status)
    last = [ln for ln in out.strip().splitlines() if ln.strip()][-1:] or [""]
    return {"exit": code, "peak_mib": usage.ru_maxrss / 1024, "seconds": round(wall, 2), "last_line": last[0][:160]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--src", type=Path, default=ROOT, help="source tree to measure (default: this one)")
    ap.add_argument("--quick", action="store_true", help="skip the slow cases")
    ap.add_argument("--unsafe", action="store_true", help="with --src: also run the cases that ran away before")
    ap.add_argument("--cap-gb", type=float, default=8.0, help="address-space cap of every child (GiB)")
    ap.add_argument("--json", type=Path, help="also write the results as JSON")
    args = ap.parse_args()
    other = args.src.resolve() != ROOT
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, argv, quick, runaway in CASES:
            if args.quick and not quick:
                continue
            if other and runaway and not args.unsafe:
                print(f"{name:42s} skipped (ran away before the fix; --unsafe runs it under the cap)")
                continue
            res = run_case(argv, args.src, args.cap_gb, tmp)
            rows.append({"case": name, **res})
            print(f"{name:42s} exit {res['exit']:>3}  peak {res['peak_mib']:8.0f} MiB  {res['seconds']:7.2f} s  "
                  f"{res['last_line'][:90]}", flush=True)
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(rows, indent=2))


if __name__ == "__main__":
    main()
