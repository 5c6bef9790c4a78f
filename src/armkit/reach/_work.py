"""The units of work of a map build: pure functions of (robot, grid, parameters, block number).

Each block returns the cells its samples fell in, with how many (or, for IK blocks, the cells
whose centre IK solved) and the largest manipulability seen per voxel. A block is a pure
function of its arguments: run twice, on any worker, it gives the same answer. Merging is a
saturating sum and a maximum, which do not depend on order.

These functions run on Dask workers: they import only NumPy, Numba and armkit.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..ik import ik
from ..kinematics import fk, manipulability
from ..model.robot import Robot
from ._grid import Grid

__all__ = ["fk_block", "ik_block", "SUB_BATCH"]

SUB_BATCH = 65_536
"""Configurations evaluated at once inside a block. A worker's memory is this batch (about 12 MB
for a 7-joint arm) plus the distinct cells the block has hit so far (16 bytes each, folded every
8 batches): it follows the map's reachable cells, not the number of samples."""

MANIP_EVERY = 64
"""Manipulability (a Jacobian and an SVD, ~30x the cost of FK) is computed on every 64th sample:
with 32 samples per cell and 64 orientation bins, still ~32 values per voxel, at ~1/3 of the cost
of FK and binning instead of ~1.5x."""


def _block_rng(seed: int, block: int) -> np.random.Generator:
    return np.random.default_rng([int(seed), int(block)])


def _clearance_filter(robot: Robot, q: NDArray[np.float64], scene: Any) -> NDArray[np.bool_]:
    from ._scene import collision_free

    return collision_free(robot, q, scene)


def _fold(found: list[NDArray[np.int64]], found_n: list[NDArray[np.int64]]
          ) -> tuple[list[NDArray[np.int64]], list[NDArray[np.int64]]]:
    """Many (cells, counts) pieces -> one, counts summed and capped at 255."""
    cells_u, inverse = np.unique(np.concatenate(found), return_inverse=True)
    cnt = np.bincount(inverse, weights=np.concatenate(found_n), minlength=len(cells_u))
    return [cells_u], [np.minimum(cnt, 255).astype(np.int64)]


def fk_block(robot: Robot, grid_attrs: dict[str, Any], seed: int, block: int, samples: int,
             scene: Any = None) -> tuple[NDArray[Any], NDArray[Any], NDArray[Any], NDArray[np.float32]]:
    """Sample ``samples`` configurations (stream ``(seed, block)``), bin their poses.

    Returns
    -------
    cells, hits : int32 (int64 for maps over 2**31 cells), uint8 (k,)
        Sorted unique flat cell indices hit, and how many samples hit each (at most 255).
    voxels, manip : int32 or int64 (m,), float32 (m,)
        Voxels where manipulability was sampled and the largest value there.
    """
    grid = Grid.from_attrs(grid_attrs)
    rng = _block_rng(seed, block)
    found: list[NDArray[np.int64]] = []
    found_n: list[NDArray[np.int64]] = []
    vox_all: list[NDArray[np.int64]] = []
    man_all: list[NDArray[np.float64]] = []
    done = 0
    while done < samples:
        m = min(SUB_BATCH, samples - done)
        q = robot.random_q(m, rng=rng)
        done += m
        if scene is not None:
            q = q[_clearance_filter(robot, q, scene)]
        cells = grid.cells(fk(robot, q))
        keep = cells >= 0
        u, n = np.unique(cells[keep], return_counts=True)
        found.append(u)
        found_n.append(n)
        if sum(len(f) for f in found) > 8 * SUB_BATCH:      # fold: memory follows the cells hit, not the samples
            found, found_n = list(_fold(found, found_n))
        sub = np.arange(0, len(q), MANIP_EVERY)
        sub = sub[keep[sub]]
        if len(sub):
            vox_all.append(cells[sub] // grid.n_orient)
            man_all.append(manipulability(robot, q[sub]))
    if found:
        (cells_u,), (cnt,) = _fold(found, found_n)
    else:
        cells_u, cnt = np.zeros(0, np.int64), np.zeros(0, np.int64)
    small = np.int32 if grid.n_cells < 2**31 else np.int64      # a block's answer travels: keep it small
    cells_u, cnt = cells_u.astype(small), cnt.astype(np.uint8)
    if vox_all:
        vox = np.concatenate(vox_all)
        man = np.concatenate(man_all)
        order = np.lexsort((-man, vox))       # per voxel, the largest first
        vox, man = vox[order], man[order]
        first = np.ones(len(vox), dtype=bool)
        first[1:] = vox[1:] != vox[:-1]
        return cells_u, cnt, vox[first].astype(small), man[first].astype(np.float32)
    return cells_u, cnt, np.zeros(0, small), np.zeros(0, np.float32)


def ik_block(robot: Robot, grid_attrs: dict[str, Any], seed: int, block: int, slabs: int,
             restarts: int, scene: Any = None
             ) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.int64], NDArray[np.float32]]:
    """IK at the centre of every cell of the x-slabs ``block*slabs .. (block+1)*slabs - 1``.

    The closed form where the arm has one, otherwise Levenberg-Marquardt from the zero
    configuration with ``restarts`` seeded random restarts. Manipulability of each solution
    found, the maximum per voxel.
    """
    grid = Grid.from_attrs(grid_attrs)
    nx, ny, nz = grid.dims
    ix = np.arange(block * slabs, min(nx, (block + 1) * slabs))
    if len(ix) == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0, np.float32)
    centres = grid.voxel_centres(ix).reshape(-1, 3)          # (V, 3) in frame A
    A = grid.T_world_A
    first_vox = ix[0] * ny * nz
    if grid.position_only:
        targets = centres @ A[:3, :3].T + A[:3, 3]
        res = ik(robot, targets, seed=np.random.default_rng([int(seed), int(block)]), restarts=restarts, scene=False)
        ok = np.asarray(res.success).reshape(-1, 1)
        q = np.asarray(res.q).reshape(-1, robot.n)
    else:
        R = grid.orientation_centres()                           # (O, 3, 3)
        V, O = len(centres), grid.n_orient
        T = np.zeros((V, O, 4, 4))
        T[..., :3, :3] = A[:3, :3] @ R
        T[..., :3, 3] = (centres @ A[:3, :3].T + A[:3, 3])[:, None, :]
        T[..., 3, 3] = 1.0
        res = ik(robot, T, seed=np.random.default_rng([int(seed), int(block)]), restarts=restarts, scene=False)
        ok = np.asarray(res.success).reshape(V, O)
        q = np.asarray(res.q).reshape(-1, robot.n)
    if scene is not None:
        ok = ok & _clearance_filter(robot, q, scene).reshape(ok.shape)
    local = np.flatnonzero(ok.ravel())
    cells = first_vox * grid.n_orient + local
    ones = np.ones(len(cells), dtype=np.int64)
    v_ok = np.flatnonzero(ok.any(axis=1))
    if len(v_ok):
        man = manipulability(robot, q).reshape(ok.shape)
        man = np.where(ok, man, -np.inf).max(axis=1)[v_ok]
        return cells.astype(np.int64), ones, (first_vox + v_ok).astype(np.int64), man.astype(np.float32)
    return cells.astype(np.int64), ones, np.zeros(0, np.int64), np.zeros(0, np.float32)
