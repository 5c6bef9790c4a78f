"""One-off: decimate the SO-101 STL meshes into src/armkit/robots/so101_assets/ (small, binary STL).

Source: TheRobotStudio/SO-ARM100, Simulation/SO101/assets/*.stl (Apache-2.0), read from a git
checkout (or bare clone) of that repository. Needs trimesh and fast-simplification, which are
NOT armkit dependencies (pip install trimesh fast-simplification). Run from the repository root:

    python tools/decimate_so101_meshes.py /path/to/SO-ARM100 [--faces 2500]

Each mesh keeps at most ``--faces`` triangles; the total stays under 2 MB. The CAD exports are
full of sliver triangles on which quadric decimation stalls (28,796 -> 14,120 triangles for a
2,500 target), so the vertices are first clustered on a 0.5 mm grid, then decimated by quadrics
(fast-simplification); the volume changes by under 1 %.
"""

from __future__ import annotations

import argparse
import io
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
URDF = ROOT / "src" / "armkit" / "robots" / "so101.urdf"
OUT = ROOT / "src" / "armkit" / "robots" / "so101_assets"
SRC = "Simulation/SO101/assets"


def read_blob(repo: Path, name: str) -> bytes:
    """The file from the repository's HEAD (works on a bare clone too)."""
    git_dir = repo / ".git" if (repo / ".git").exists() else repo
    return subprocess.run(["git", "--git-dir", str(git_dir), "show", f"HEAD:{SRC}/{name}"],
                          check=True, capture_output=True).stdout


def cluster(vertices, faces, cell: float):
    """Vertex clustering: vertices in one ``cell``-sized grid box become their mean; collapsed faces go."""
    import numpy as np

    key = np.round(vertices / cell).astype(np.int64)
    _, inv = np.unique(key, axis=0, return_inverse=True)
    inv = inv.ravel()
    v = np.zeros((inv.max() + 1, 3))
    np.add.at(v, inv, vertices)
    v /= np.bincount(inv)[:, None]
    f = inv[faces]
    f = f[(f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 0] != f[:, 2])]
    _, first = np.unique(np.sort(f, axis=1), axis=0, return_index=True)
    return v, f[np.sort(first)]


def main() -> int:
    import fast_simplification
    import trimesh

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("repo", type=Path, help="checkout or bare clone of TheRobotStudio/SO-ARM100")
    ap.add_argument("--faces", type=int, default=2500, help="most triangles per mesh (default 2500)")
    args = ap.parse_args()
    names = sorted(set(re.findall(r'filename="(?:assets|so101_assets)/([^"]+\.stl)"', URDF.read_text())))
    OUT.mkdir(exist_ok=True)
    total = 0
    for name in names:
        mesh = trimesh.load(io.BytesIO(read_blob(args.repo, name)), file_type="stl")
        before = len(mesh.faces)
        if before > args.faces:
            v, f = cluster(mesh.vertices, mesh.faces, 0.5e-3)
            v, f = fast_simplification.simplify(v, f, target_count=args.faces, agg=7)
            mesh = trimesh.Trimesh(v, f)
        data = mesh.export(file_type="stl")
        (OUT / name).write_bytes(data)
        total += len(data)
        print(f"{name}: {before} -> {len(mesh.faces)} triangles, {len(data) / 1024:.0f} KiB")
    print(f"total {total / 1024 / 1024:.2f} MiB in {OUT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
