"""Reachability maps (docs/reachability.md): build a small map, ask it about poses, store it, rank base spots.

Run: python examples/06_reachability.py [OUT_DIR]   (writes OUT_DIR/planar3.zarr, default out/)
"""

import sys
from pathlib import Path

import numpy as np

import armkit


def main(out_dir="out"):
    path = Path(out_dir) / "planar3.zarr"
    m = armkit.reachability("planar3", resolution=0.1, orientations=8, samples=200_000, path=path,
                            overwrite=True, workers=1)
    print(m.summary())
    T = armkit.fk(m.robot, m.robot.random_q(5, np.random.default_rng(0)))   # poses the arm reaches
    print("reachable (poses from FK):", m.reachable(T).tolist())
    print("a point far outside:", bool(m.index(np.array([9.0, 0.0, 0.0])) > 0))
    again = armkit.ReachabilityMap.open(path)        # the stored map, as built
    print("reopened map agrees:", bool(np.array_equal(again.reachable(T), m.reachable(T))))
    best = armkit.base_placement(m, T[:3], top=2)
    print("best base:", np.round(best[0].pose[:3, 3], 3), "reaches", best[0].ik_count, "of 3 poses")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
