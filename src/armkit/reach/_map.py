"""The :class:`ReachabilityMap`: cells, queries and its Zarr store.

Store layout (a Zarr v3 group, every chunk written atomically: temporary file + rename):

``counts``          uint8 ``(nx, ny, nz, orientations)``: FK samples that fell in the cell (saturating at 255;
                    method "ik": 1 where IK solved the cell's centre)
``hits``            bool ``(nx, ny, nz, orientations)``: the cell is reachable (:func:`decide` of the counts)
``manipulability``  float32 ``(nx, ny, nz)``: largest Yoshikawa manipulability seen in the voxel (0: none)
``index``           float32 ``(nx, ny, nz)``: reachability index, the fraction of orientation bins reachable

and attributes ``format``, ``armkit_version``, ``robot`` (name), ``robot_toml`` (the robot file
text) and ``robot_sha256`` (its fingerprint), ``grid`` and ``parameters``, ``status`` (``"building"``
or ``"complete"``), and ``checksums`` (SHA-256 of each array: a deleted chunk would otherwise
read as zeros). Opening checks all of it first (:mod:`._store`) and never writes a file.

While building, the store holds ``counts_G`` and ``manipulability_G`` of generation ``G`` and the
attributes ``generation`` and ``blocks_done`` (the finished units of work). A flush writes
generation ``G + 1`` in full, then commits it by rewriting the attributes (one file, replaced
atomically), then deletes generation ``G``: a crash at any moment leaves one complete,
consistent generation, and the resumed build skips exactly the blocks merged into it.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._extras import require
from ..errors import ArmkitError, MapFileError, ShapeError
from ..ik import ik, ik_all
from ..ik.api import closed_form_family
from ..model import dumps
from ..model.files import _parse
from ..model.robot import Robot
from ..spatial import check_transform
from ._grid import Grid
from ._store import FORMAT, grid_of, load_arrays, read_attrs, robot_of

__all__ = ["ReachabilityMap", "MapFileError", "FORMAT"]

Array = NDArray[np.float64]


def robot_from_toml(text: str, name: str) -> Robot:
    """The robot of a robot file's text; no file is written (the text may come from a downloaded map)."""
    return _parse(text, f"{name or 'robot'} (stored robot)")


def robot_to_toml(robot: Robot) -> str:
    return dumps(robot)


DEFAULT_COVERAGE = 0.1
"""A sampled cell counts as reachable when its sample density is at least this fraction of the
densest cell around it (neighbouring voxels and orientation bins): a cell at the edge of the
reachable set, only partly inside it, gets fewer samples than its full neighbours, and is
called reachable only when enough of it is (see docs/reachability.md for the study)."""


def decide(counts: NDArray[np.uint8], grid: Grid, coverage: float) -> NDArray[np.bool_]:
    """Reachable cells from FK hit counts ``(nx, ny, nz, orientations)`` (see ``DEFAULT_COVERAGE``).

    ``coverage = 0`` keeps every cell with a sample (the plain RM4D rule).
    """
    c = np.asarray(counts)
    if coverage <= 0:
        return c > 0
    dens = c.astype(np.float32)
    if grid.symmetric:    # a ring of radius r holds ~ r samples per unit density
        dens /= (np.arange(grid.dims[0], dtype=np.float32) + 0.5)[:, None, None, None]
    ref = neighbourhood(dens, grid, np.maximum)
    return (c > 0) & (dens >= np.float32(coverage) * ref)


def neighbourhood(a: NDArray[Any], grid: Grid, op: Any) -> NDArray[Any]:
    """``op`` (``np.maximum`` or ``np.minimum``) of ``a`` over each cell's neighbourhood: the 3x3x3
    voxels around it (edges: those that exist) times its orientation bin and the neighbouring bins."""
    ref = a.copy()
    nb = grid.direction_neighbours()
    for j in range(nb.shape[1]):
        op(ref, a[..., nb[:, j]], out=ref)
    for axis in range(3):
        if a.shape[axis] > 1:
            out = ref.copy()
            lo = [slice(None)] * 4
            hi = [slice(None)] * 4
            lo[axis], hi[axis] = slice(1, None), slice(None, -1)
            op(out[tuple(lo)], ref[tuple(hi)], out=out[tuple(lo)])
            op(out[tuple(hi)], ref[tuple(lo)], out=out[tuple(hi)])
            ref = out
    return ref


@dataclass(frozen=True, eq=False)
class ReachabilityMap:
    """Where an arm reaches, in which orientations, and how well.

    Built by :func:`armkit.reachability`, reopened with :meth:`open`. Everything is in the
    robot's world frame (the frame of ``armkit.fk``), lengths in the robot's unit.

    Attributes
    ----------
    robot : Robot
    grid : Grid
        Voxels, orientation bins, symmetry (see :mod:`armkit.reach._grid`).
    hits : ndarray of bool, shape (nx, ny, nz, orientations)
    manipulability : ndarray of float32, shape (nx, ny, nz)
    parameters : dict
        How it was built (method, resolution, samples, seed, coverage, ...).
    counts : ndarray of uint8, shape (nx, ny, nz, orientations), optional
        FK samples per cell (saturating at 255); ``hits`` is :func:`decide` of them.
    path : str or None
        The Zarr store, if any.
    """

    robot: Robot
    grid: Grid
    hits: NDArray[np.bool_]
    manipulability: NDArray[np.float32]
    parameters: dict[str, Any]
    counts: NDArray[np.uint8] | None = None
    path: str | None = None
    # derived from ``hits`` (set once in __post_init__) and the boundary, computed on first use: declared
    # fields outside equality and repr, the one way a frozen armkit value keeps what it derived
    _flat: NDArray[np.bool_] = field(init=False, repr=False, compare=False)
    _voxel_index: NDArray[np.float32] = field(init=False, repr=False, compare=False)
    _boundary: NDArray[np.bool_] | None = field(default=None, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        hits = np.ascontiguousarray(self.hits, dtype=bool)
        hits.setflags(write=False)
        object.__setattr__(self, "hits", hits)
        object.__setattr__(self, "_flat", hits.reshape(-1))
        idx = hits.reshape(-1, self.grid.n_orient).mean(axis=1, dtype=np.float64).astype(np.float32)
        idx.setflags(write=False)
        object.__setattr__(self, "_voxel_index", idx)

    # ------------------------------------------------------------------ summary
    @property
    def reachability_index(self) -> NDArray[np.float32]:
        """Fraction of orientation bins reached in each voxel, shape ``(nx, ny, nz)``."""
        return self._voxel_index.reshape(self.grid.dims)

    @property
    def orientations(self) -> int:
        return self.grid.n_orient

    def summary(self) -> dict[str, Any]:
        """Counts and parameters as plain data (for ``--json`` and the docs)."""
        g = self.grid
        vox = int(np.count_nonzero(self._voxel_index))
        return {"robot": self.robot.name, "unit": self.robot.unit, "method": self.parameters.get("method"),
                "resolution": g.resolution, "voxels": list(g.dims), "directions": g.directions, "rolls": g.rolls,
                "orientations": g.n_orient, "yaw_symmetric": g.symmetric, "cells": g.n_cells,
                "reachable_cells": int(np.count_nonzero(self._flat)), "reachable_voxels": vox,
                "samples": self.parameters.get("samples"), "seed": self.parameters.get("seed"),
                "armkit_version": self.parameters.get("armkit_version")}

    def __repr__(self) -> str:
        g = self.grid
        return (f"ReachabilityMap({self.robot.name!r}, {g.dims[0]}x{g.dims[1]}x{g.dims[2]} voxels of "
                f"{g.resolution:g} {self.robot.unit} x {g.n_orient} orientations, "
                f"{'yaw-symmetric' if g.symmetric else 'full box'}, {int(self._flat.sum())} reachable cells)")

    # ------------------------------------------------------------------ queries
    def _poses(self, poses: ArrayLike, what: str) -> tuple[Array, tuple[int, ...]]:
        T = check_transform(poses, what=what)
        return T.reshape(-1, 4, 4), T.shape[:-2]

    def cells(self, poses: ArrayLike) -> NDArray[np.int64]:
        """Flat cell index of each pose ``(..., 4, 4)`` (world frame), ``-1`` outside the map; shape ``(...)``."""
        T, lead = self._poses(poses, "poses")
        return self.grid.cells(T).reshape(lead)

    @property
    def boundary(self) -> NDArray[np.bool_]:
        """Cells whose neighbourhood (see :func:`neighbourhood`) holds both reachable and unreachable
        cells: there the answer may differ from one pose to another inside the cell. Shape as ``hits``."""
        b = self._boundary
        if b is None:
            h = self.hits.view(np.uint8)
            b = neighbourhood(h, self.grid, np.maximum) != neighbourhood(h, self.grid, np.minimum)
            b.setflags(write=False)
            object.__setattr__(self, "_boundary", b)
        return b  # type: ignore[no-any-return]

    def _ik_reachable(self, T: Array, seed: int) -> NDArray[np.bool_]:
        target = T[:, :3, 3] if self.grid.position_only else T
        if closed_form_family(self.robot) is not None:
            try:
                ok: NDArray[np.bool_] = np.asarray(ik_all(self.robot, target, scene=False).success, dtype=bool)
                return np.asarray(ok.reshape(len(T), -1).any(axis=1), dtype=bool)
            except ArmkitError:     # the closed form does not take this kind of target: numeric below
                pass
        res = ik(self.robot, target, method="lm", seed=np.random.default_rng(seed), restarts=20, scene=False)
        return np.asarray(res.success, dtype=bool).reshape(len(T))

    def reachable(self, poses: ArrayLike, refine: bool = False, seed: int = 0) -> NDArray[np.bool_]:
        """Whether the map calls each pose reachable.

        Parameters
        ----------
        poses : array_like, shape (..., 4, 4)
            Tool poses ``T_world_tool`` in the robot's world frame and unit. For a
            position-only map (arms with fewer than 6 joints) only the position counts.
        refine : bool
            Poses in :attr:`boundary` cells (where a cell is only partly reachable) are
            decided by IK instead (every closed-form branch, or LM with 20 seeded restarts):
            the map answers the clear cases in microseconds, IK the doubtful ones.
        seed : int
            Seeds the LM restarts of ``refine``.

        Returns
        -------
        ndarray of bool, shape (...)

        Examples
        --------
        >>> import armkit, numpy as np
        >>> m = armkit.reachability("planar2", resolution=0.05, samples=200_000)
        >>> T = np.eye(4); T[:3, 3] = [1.2, 0.3, 0.0]
        >>> bool(m.reachable(T)), bool(m.reachable(np.eye(4)))     # the 2R annulus is 0.5 <= r <= 1.5
        (True, False)
        """
        T, lead = self._poses(poses, "poses")
        c = self.grid.cells(T)
        out = np.zeros(len(c), dtype=bool)
        ok = c >= 0
        out[ok] = self._flat[c[ok]]
        if refine:
            doubt = np.zeros(len(c), dtype=bool)
            doubt[ok] = self.boundary.reshape(-1)[c[ok]]
            if doubt.any():
                out[doubt] = self._ik_reachable(T[doubt], seed)
        return out.reshape(lead)

    def index(self, points: ArrayLike) -> NDArray[np.float32]:
        """Reachability index (fraction of orientation bins reached) at points ``(..., 3)``; shape ``(...)``.

        0 outside the map. For a position-only map it is 1 where the point is reachable.
        """
        try:
            p = np.asarray(points, dtype=float)
        except (TypeError, ValueError):
            raise ShapeError.of("points must be numeric, got {points!r}", points=points) from None
        if p.ndim < 1 or p.shape[-1] != 3:
            raise ShapeError.of("points must have shape (..., 3), got {shape}", shape=p.shape)
        if not np.all(np.isfinite(p)):
            raise ShapeError.of("points contain NaN or infinite values")
        lead = p.shape[:-1]
        T = np.zeros((int(np.prod(lead, dtype=np.int64)), 4, 4))
        T[:, :3, :3] = np.eye(3)
        T[:, 3, 3] = 1.0
        T[:, :3, 3] = p.reshape(-1, 3)
        c = self.grid.cells(T)
        out = np.zeros(len(c), dtype=np.float32)
        ok = c >= 0
        out[ok] = self._voxel_index[c[ok] // self.grid.n_orient]
        return out.reshape(lead)

    def voxel_centres(self) -> Array:
        """Centres of every voxel in the world frame, shape ``(nx, ny, nz, 3)`` (``y = 0`` plane when yaw-symmetric)."""
        c = self.grid.voxel_centres(np.arange(self.grid.dims[0]))
        A = self.grid.T_world_A
        return c @ A[:3, :3].T + A[:3, 3]

    # ------------------------------------------------------------------ storage
    @classmethod
    def open(cls, path: str | os.PathLike[str]) -> "ReachabilityMap":
        """Reopen a map written by :func:`armkit.reachability` (``path=``) or ``armkit reach build``.

        Raises
        ------
        MapFileError
            The path is missing, is not an armkit map (or one of an older format), holds an
            unfinished build (run the same build again to resume it), or is damaged: a stored
            robot that does not match its fingerprint, a grid that is not valid or needs more than
            ``ARMKIT_MEMORY_LIMIT``, an array missing, of another dtype or shape, or not matching
            its checksum (deleted or damaged chunks). The store is never modified.
        """
        zarr = require("zarr", "reading a reachability map")
        p = os.fspath(path)
        attrs = read_attrs(p)                 # format, status, attribute types; nothing else read yet
        robot = robot_of(attrs, p)            # parsed from text, checked against its fingerprint
        grid = grid_of(attrs, p)              # valid, and within the memory budget
        try:
            g: Any = zarr.open_group(p, mode="r")
        except Exception as exc:   # zarr raises several types for a damaged store
            raise MapFileError.of("{path!r} is not a readable Zarr store ({type})", path=p,
                                  type=type(exc).__name__) from None
        arrays = load_arrays(g, attrs, grid, p)   # presence, dtype, shape, checksum
        params = {**dict(attrs["parameters"]), "armkit_version": attrs.get("armkit_version")}
        return cls(robot, grid, arrays["hits"], arrays["manipulability"], params, arrays["counts"], p)
