"""Performance (docs/performance.md): one batched call against a Python loop, and the two back ends.

Run: python examples/05_performance.py   (prints ratios; the numbers depend on the machine)
"""

import sys
import time

import numpy as np

import armkit


def best(fn, repeat=3):
    fn()
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return min(times)


def main(out_dir=None):
    arm = armkit.load("ur5")
    q = arm.random_q(20_000, np.random.default_rng(0))
    armkit.warmup()                                   # compile (or load) the Numba kernels once
    one = best(lambda: [armkit.fk(arm, qi) for qi in q[:2000]], 1) / 2000
    print(f"fk one configuration per call:          {one * 1e6:6.2f} us per configuration")
    for backend in ("numpy", "numba"):
        armkit.set_backend(backend)
        batched = best(lambda: armkit.fk(arm, q)) / len(q)
        print(f"fk of {len(q):,} in one call, {backend:5s} back end: {batched * 1e6:6.2f} us per configuration "
              f"({one / batched:.1f}x the one-per-call rate)")
    armkit.set_backend("auto")
    T = armkit.fk(arm, q[:200])
    looped = best(lambda: [armkit.ik(arm, Ti) for Ti in T], 1) / len(T)
    batched = best(lambda: armkit.ik(arm, T), 1) / len(T)
    print(f"closed-form ik: {looped * 1e6:.0f} us per pose one by one, {batched * 1e6:.0f} us per pose in one call "
          f"({looped / batched:.1f}x)")
    print("the back end in use now:", armkit.get_backend())
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
