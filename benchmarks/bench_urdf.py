"""URDF loading and FK speed: a 50-joint file, and arms loaded from URDF against their DH twins.

Run: ``.venv/bin/python benchmarks/bench_urdf.py`` (or ``make bench``). Prints:

* the time to load a generated 50-joint URDF (first load in a fresh process, including
  the one-time import of yourdfpy/lxml, and warm loads), goal < 0.2 s;
* FK per call (single q) and per configuration (batch of 100,000) for UR5 and Panda read
  from their description URDFs, beside the same arms written as DH tables, and the ratio;
* with Pinocchio installed (``.venv-bench``): the largest FK/Jacobian difference over
  1,000 random q for UR5, Panda, SO-101.
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

import os

os.environ.setdefault("ARMKIT_JIT", "wait")   # compile in this process: time compiled kernels, never the NumPy stand-in

import armkit  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "core"))
from test_urdf import REAL, load_real, urdf_text  # noqa: E402


def _chain(n: int) -> str:
    rng = np.random.default_rng(0)
    joints = []
    for i in range(n):
        axis = rng.normal(size=3)
        joints.append({"type": "fixed" if i % 5 == 4 else "revolute", "xyz": rng.uniform(-0.1, 0.1, 3),
                       "rpy": rng.uniform(-3, 3, 3), "axis": axis / np.linalg.norm(axis), "lower": -3, "upper": 3})
    return urdf_text(joints, name="chain50")


def load_times(path: Path) -> tuple[float, float]:
    code = ("import time; t = time.perf_counter(); import armkit; t1 = time.perf_counter(); "
            f"armkit.load({str(path)!r}); print(time.perf_counter() - t1)")
    cold = statistics.median(float(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                                                  check=True).stdout) for _ in range(3))
    armkit.load(path)
    warm = []
    for _ in range(20):
        t = time.perf_counter()
        armkit.load(path)
        warm.append(time.perf_counter() - t)
    return cold, statistics.median(warm)


def fk_times(robot: armkit.Robot) -> tuple[float, float]:
    q1 = robot.random_q(rng=0)
    qb = robot.random_q(100_000, rng=0)
    armkit.fk(robot, q1)
    armkit.fk(robot, qb[:10])   # compile/warm the kernels before timing
    single = []
    for _ in range(5):
        t = time.perf_counter()
        for _ in range(2000):
            armkit.fk(robot, q1)
        single.append((time.perf_counter() - t) / 2000)
    batch = []
    for _ in range(5):
        t = time.perf_counter()
        armkit.fk(robot, qb)
        batch.append((time.perf_counter() - t) / len(qb))
    return min(single), min(batch)


def main() -> None:
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "chain50.urdf"
        path.write_text(_chain(50))
        r = armkit.load(path)
        cold, warm = load_times(path)
        print(f"50-joint URDF ({r.n} moving, {50 - r.n} fixed): first load in a fresh process {cold * 1e3:.1f} ms "
              f"(after `import armkit`; includes importing yourdfpy+trimesh once), warm {warm * 1e3:.2f} ms "
              f"(goal < 200 ms)")
    print(f"\nFK speed, backend {armkit.get_backend()}: URDF arm vs its DH twin (same arm)")
    print(f"{'arm':8} {'single URDF':>12} {'single DH':>10} {'ratio':>6} {'batch URDF':>11} {'batch DH':>9} {'ratio':>6}")
    for name in ("ur5", "panda"):
        path, base, tip = REAL[name]
        if not path.is_file():
            print(f"{name}: example-robot-data not installed")
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = armkit.load(path, base=base, tip=tip)
        twin = r.to_dh()
        su, bu = fk_times(r)
        sd, bd = fk_times(twin)
        print(f"{name:8} {su * 1e6:9.2f} us {sd * 1e6:7.2f} us {su / sd:6.2f} {bu * 1e9:8.1f} ns {bd * 1e9:6.1f} ns "
              f"{bu / bd:6.2f}")
    try:
        import pinocchio  # noqa: F401
    except ImportError:
        print("\nPinocchio not installed: comparison skipped (make bench installs it in .venv-bench)")
        return
    from test_urdf_pinocchio import _compare  # noqa: E402 (tests/peers)

    print("\nagainst Pinocchio (1,000 random q each): max |FK diff|, max |Jacobian diff|")
    for name in REAL:
        path, r, _, tip = load_real(name)
        fk_err, jac_err = _compare(path, r, tip, 1000, seed=3)
        print(f"  {name:6} {fk_err:.2e} {jac_err:.2e}")


if __name__ == "__main__":
    sys.path.insert(0, str(ROOT / "tests" / "peers"))
    main()
