"""The cells of a reachability map and the one function that puts a pose into a cell.

A map is a grid of position voxels times a set of orientation bins, all expressed in the
frame ``A`` of the first joint at ``q1 = 0`` (``T_world_A``, the robot's base pose times
the first joint's fixed transform):

* **Yaw symmetry.** When the first joint is revolute with a range of at least 2 pi, a pose
  is reachable exactly when the same pose turned about that joint's axis is. The map then
  stores only the half-plane ``(r, z)`` (``ny = 1``): a pose is rotated by ``-atan2(y, x)``
  about the axis (position *and* orientation) before it is binned. Otherwise the grid is the
  full box ``(x, y, z)``.
* **Approach directions.** The tool's z axis (in the canonical frame) goes to the nearest of
  ``directions`` points of a Fibonacci sphere (Voronoi cells of nearly equal area).
* **Roll.** The angle of the tool's x axis about the approach direction, measured in a fixed
  tangent frame of the direction's centre, split into ``rolls`` equal bins. ``rolls = 1``
  ignores the roll: exact when the last joint turns the tool about its own z axis through
  2 pi.
* ``directions = 1`` makes a position-only map (arms with fewer than 6 joints).

The same Numba kernel :func:`bin_poses` bins FK samples while building and bins queries, so
a query lands in exactly the cell that a sample with that pose would have filled.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numba import njit
from numpy.typing import NDArray

__all__ = ["Grid", "bin_poses", "fibonacci_directions", "tangent_frames"]

Array = NDArray[np.float64]


def fibonacci_directions(n: int) -> Array:
    """``n`` unit vectors spread evenly on the sphere (golden-angle spiral), shape ``(n, 3)``.

    >>> d = fibonacci_directions(64)
    >>> d.shape, bool(np.allclose(np.linalg.norm(d, axis=1), 1.0))
    ((64, 3), True)
    """
    if n == 1:
        return np.array([[0.0, 0.0, 1.0]])
    i = np.arange(n, dtype=float) + 0.5
    z = 1.0 - 2.0 * i / n
    rho = np.sqrt(np.maximum(0.0, 1.0 - z * z))
    phi = i * math.pi * (3.0 - math.sqrt(5.0))
    return np.stack([rho * np.cos(phi), rho * np.sin(phi), z], axis=1)


def tangent_frames(dirs: Array) -> tuple[Array, Array]:
    """Fixed unit vectors ``e1, e2`` ``(n, 3)`` orthogonal to each direction (``e2 = d x e1``)."""
    ref = np.where(np.abs(dirs[:, :1]) < 0.9, np.array([[1.0, 0.0, 0.0]]), np.array([[0.0, 1.0, 0.0]]))
    e1 = ref - np.sum(ref * dirs, axis=1, keepdims=True) * dirs
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    e2 = np.cross(dirs, e1)
    return e1, e2


@njit(cache=True, nogil=True)
def _bin_kernel(T, Ainv, box, orient, out):  # pragma: no cover - compiled
    """Flat cell of each pose ``T[k]`` into ``out[k]`` (-1 outside).

    ``box = (lo (3,), h, dims (3,) int, symmetric)``: the voxel box in frame A (``Ainv`` maps
    world to A); ``orient = (dirs (nd, 3), e1 (nd, 3), e2 (nd, 3), n_roll)``: the orientation bins.
    Packed in two tuples (Numba passes them as structs, no copy) to keep the signature short.
    """
    lo, h, dims, symmetric = box
    dirs, e1, e2, n_roll = orient
    nx, ny, nz = dims[0], dims[1], dims[2]
    nd = dirs.shape[0]
    n_orient = nd * n_roll
    two_pi = 2.0 * math.pi
    for k in range(T.shape[0]):
        # p_A = Ainv @ p;  x_A, z_A = Ainv[:3, :3] @ (tool x, tool z axes)
        t0, t1, t2 = T[k, 0, 3], T[k, 1, 3], T[k, 2, 3]
        px = Ainv[0, 0] * t0 + Ainv[0, 1] * t1 + Ainv[0, 2] * t2 + Ainv[0, 3]
        py = Ainv[1, 0] * t0 + Ainv[1, 1] * t1 + Ainv[1, 2] * t2 + Ainv[1, 3]
        pz = Ainv[2, 0] * t0 + Ainv[2, 1] * t1 + Ainv[2, 2] * t2 + Ainv[2, 3]
        a0, a1, a2 = T[k, 0, 0], T[k, 1, 0], T[k, 2, 0]
        xx = Ainv[0, 0] * a0 + Ainv[0, 1] * a1 + Ainv[0, 2] * a2
        xy = Ainv[1, 0] * a0 + Ainv[1, 1] * a1 + Ainv[1, 2] * a2
        xz = Ainv[2, 0] * a0 + Ainv[2, 1] * a1 + Ainv[2, 2] * a2
        a0, a1, a2 = T[k, 0, 2], T[k, 1, 2], T[k, 2, 2]
        zx = Ainv[0, 0] * a0 + Ainv[0, 1] * a1 + Ainv[0, 2] * a2
        zy = Ainv[1, 0] * a0 + Ainv[1, 1] * a1 + Ainv[1, 2] * a2
        zz = Ainv[2, 0] * a0 + Ainv[2, 1] * a1 + Ainv[2, 2] * a2
        if symmetric:   # turn by -atan2(py, px) about z: position to (r, 0, z), both axes with it
            r = math.hypot(px, py)
            if r > 0.0:
                c, s = px / r, py / r
            else:
                c, s = 1.0, 0.0
            xx, xy = c * xx + s * xy, -s * xx + c * xy
            zx, zy = c * zx + s * zy, -s * zx + c * zy
            px, py = r, 0.0
        fx = (px - lo[0]) / h
        fy = (py - lo[1]) / h
        fz = (pz - lo[2]) / h
        if not (fx >= 0.0 and fy >= 0.0 and fz >= 0.0):
            out[k] = -1
            continue
        ix, iy, iz = int(fx), int(fy), int(fz)
        if ix >= nx or iy >= ny or iz >= nz:
            out[k] = -1
            continue
        io = 0
        if nd > 1:
            best, bd = -2.0, 0
            for d in range(nd):
                v = dirs[d, 0] * zx + dirs[d, 1] * zy + dirs[d, 2] * zz
                if v > best:
                    best, bd = v, d
            io = bd * n_roll
        if n_roll > 1:
            d = io // n_roll
            u = e1[d, 0] * xx + e1[d, 1] * xy + e1[d, 2] * xz
            w = e2[d, 0] * xx + e2[d, 1] * xy + e2[d, 2] * xz
            ang = math.atan2(w, u) + math.pi        # [0, 2 pi]
            ir = int(ang / two_pi * n_roll)
            if ir >= n_roll:
                ir = n_roll - 1
            io += ir
        out[k] = ((ix * ny + iy) * nz + iz) * n_orient + io


@dataclass(frozen=True)
class Grid:
    """Geometry of a map: frame, symmetry, voxel box and orientation bins.

    Attributes
    ----------
    T_world_A : ndarray, shape (4, 4)
        Frame of the first joint at ``q1 = 0``; cells are expressed in it.
    symmetric : bool
        Exact yaw symmetry used: positions ``(r, 0, z)``, ``ny = 1``.
    lo : ndarray, shape (3,)
        Lower corner of the voxel box in frame A (robot length unit).
    resolution : float
        Voxel edge (robot length unit).
    dims : tuple of int
        ``(nx, ny, nz)`` voxels.
    directions, rolls : int
        Approach directions and roll bins; ``directions * rolls`` orientation bins per voxel.
    """

    T_world_A: Array
    symmetric: bool
    lo: Array
    resolution: float
    dims: tuple[int, int, int]
    directions: int
    rolls: int
    # the orientation tables, computed on first use: a declared field outside equality and repr
    _tables_cache: tuple[Array, Array, Array] | None = field(default=None, init=False, repr=False, compare=False)

    @property
    def n_orient(self) -> int:
        return self.directions * self.rolls

    @property
    def shape(self) -> tuple[int, int, int, int]:
        return (*self.dims, self.n_orient)

    @property
    def n_cells(self) -> int:
        return int(np.prod(self.shape))

    @property
    def position_only(self) -> bool:
        return self.directions == 1 and self.rolls == 1

    @classmethod
    def build(cls, T_world_A: Array, symmetric: bool, extent: float, resolution: float,
              directions: int, rolls: int) -> "Grid":
        """A grid covering every point within ``extent`` of the origin of frame A."""
        h = float(resolution)
        n_side = int(math.ceil(extent / h))
        # the origin of frame A sits at a voxel centre (a planar arm's plane z = 0 is inside one layer)
        if symmetric:
            lo = np.array([0.0, -0.5 * h, -(n_side + 0.5) * h])
            dims = (n_side + 1, 1, 2 * n_side + 1)
        else:
            lo = np.array([-(n_side + 0.5) * h] * 3)
            dims = (2 * n_side + 1, 2 * n_side + 1, 2 * n_side + 1)
        return cls(np.array(T_world_A, dtype=float), bool(symmetric), lo, h, dims, int(directions), int(rolls))

    # ------------------------------------------------------------------ binning
    def _tables(self) -> tuple[Array, Array, Array]:
        cache = self._tables_cache
        if cache is None:
            dirs = fibonacci_directions(self.directions)
            e1, e2 = tangent_frames(dirs)
            cache = (np.ascontiguousarray(dirs), np.ascontiguousarray(e1), np.ascontiguousarray(e2))
            object.__setattr__(self, "_tables_cache", cache)
        return cache

    def cells(self, T: Array) -> NDArray[np.int64]:
        """Flat cell index of each pose ``T`` ``(N, 4, 4)`` (world frame), ``-1`` outside the box."""
        T = np.ascontiguousarray(T, dtype=float)
        out = np.empty(T.shape[0], dtype=np.int64)
        dirs, e1, e2 = self._tables()
        Ainv = np.ascontiguousarray(np.linalg.inv(self.T_world_A))
        box = (np.asarray(self.lo, dtype=float), float(self.resolution), np.array(self.dims, dtype=np.int64),
               bool(self.symmetric))
        _bin_kernel(T, Ainv, box, (dirs, e1, e2, int(self.rolls)), out)
        return out

    # ------------------------------------------------------------------ centres
    def voxel_centres(self, ix: NDArray[np.int64]) -> Array:
        """Centres in frame A of the voxels in x-slabs ``ix``, shape ``(len(ix), ny, nz, 3)``."""
        nx, ny, nz = self.dims
        h = self.resolution
        X, Y, Z = np.meshgrid(np.asarray(ix), np.arange(ny), np.arange(nz), indexing="ij")
        c = np.stack([X, Y, Z], axis=-1) * h + self.lo + 0.5 * h
        if self.symmetric:
            c[..., 1] = 0.0
        return c

    def orientation_centres(self) -> Array:
        """Rotation (frame A, canonical) at the centre of each orientation bin, shape ``(n_orient, 3, 3)``."""
        dirs, e1, e2 = self._tables()
        R = np.empty((self.n_orient, 3, 3))
        for d in range(self.directions):
            for r in range(self.rolls):
                ang = (r + 0.5) / self.rolls * 2 * math.pi - math.pi if self.rolls > 1 else 0.0
                x = math.cos(ang) * e1[d] + math.sin(ang) * e2[d]
                z = dirs[d]
                R[d * self.rolls + r] = np.stack([x, np.cross(z, x), z], axis=1)
        return R

    def direction_neighbours(self, k: int = 6) -> NDArray[np.int64]:
        """Orientation bins next to each bin, shape ``(n_orient, m)``: the ``k`` nearest directions
        at the same roll, and the two neighbouring rolls at the same direction (cyclic)."""
        dirs, _, _ = self._tables()
        nd, nr = self.directions, self.rolls
        k = min(k, nd - 1)
        if k > 0:     # a k-d tree, not the nd x nd table of dot products (20,000 directions: 3.2 GB)
            from scipy.spatial import cKDTree

            _, near = cKDTree(dirs).query(dirs, k=k + 1)
            near = np.asarray(near)[:, 1:]
        else:
            near = np.zeros((nd, 0), int)
        rows = []
        for d in range(nd):
            for r in range(nr):
                nb = [int(e) * nr + r for e in near[d]]
                if nr > 1:
                    nb += [d * nr + (r + 1) % nr, d * nr + (r - 1) % nr]
                rows.append(nb)
        return np.array(rows, dtype=np.int64).reshape(self.n_orient, -1)

    # ------------------------------------------------------------------ storage
    def to_attrs(self) -> dict[str, Any]:
        return {"T_world_A": self.T_world_A.tolist(), "symmetric": self.symmetric, "lo": self.lo.tolist(),
                "resolution": self.resolution, "dims": list(self.dims), "directions": self.directions,
                "rolls": self.rolls}

    @classmethod
    def from_attrs(cls, a: dict[str, Any]) -> "Grid":
        return cls(np.array(a["T_world_A"], dtype=float), bool(a["symmetric"]), np.array(a["lo"], dtype=float),
                   float(a["resolution"]), tuple(int(v) for v in a["dims"]),  # type: ignore[arg-type]
                   int(a["directions"]), int(a["rolls"]))
