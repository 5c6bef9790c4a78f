"""Inverse reachability: where to put the base so that the arm reaches the task poses.

Every candidate base pose ``T_task_base`` (a grid on a floor plane, or a given set) turns the
task poses into poses in the robot's frame, ``T_base_task = inv(T_task_base) @ T_task``; the
map says which of them it reaches. Candidates are ranked by that count, then by the mean
reachability index at the task points (more orientation slack), then by their order. The
best ``top`` are checked pose by pose with IK, and the answer reports both counts.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ArgumentError, ShapeError
from ..ik import ik
from ._map import ReachabilityMap

__all__ = ["BasePlacement", "base_placement"]

Array = NDArray[np.float64]


@dataclass(frozen=True)
class BasePlacement:
    """One ranked base pose.

    Attributes
    ----------
    pose : ndarray, shape (4, 4)
        ``T_task_base``: where the robot's world frame goes, in the task frame.
    map_reached : ndarray of bool, shape (K,)
        The task poses the map calls reachable from here.
    ik_reached : ndarray of bool, shape (K,)
        The task poses IK actually reaches from here (the check).
    """

    pose: Array
    map_reached: NDArray[np.bool_]
    ik_reached: NDArray[np.bool_]

    @property
    def map_count(self) -> int:
        return int(self.map_reached.sum())

    @property
    def ik_count(self) -> int:
        return int(self.ik_reached.sum())


def _floor_candidates(m: ReachabilityMap, tasks: Array, floor_z: float, step: float, yaws: int) -> Array:
    from .._limits import check_memory

    reach = m.robot.reach
    lo = tasks[:, :2, 3].min(axis=0) - reach
    hi = tasks[:, :2, 3].max(axis=0) + reach
    n = float(np.prod(np.floor((hi - lo) / step) + 2)) * float(yaws)     # candidates, counted before allocating
    # each candidate: its pose and inverse (2 x 128 B), the meshgrid (3 x 8 B), its reached row (K B) and index
    check_memory(n * (3 * 128 + 32 + len(tasks)), f"{n:,.0f} candidate base poses",
                 "use a larger step= (--step) or fewer yaws= (--yaws)")
    xs = np.arange(lo[0], hi[0] + 0.5 * step, step)
    ys = np.arange(lo[1], hi[1] + 0.5 * step, step)
    th = np.arange(yaws) * (2 * math.pi / yaws)
    X, Y, TH = np.meshgrid(xs, ys, th, indexing="ij")
    B = np.zeros(X.shape + (4, 4))
    c, s = np.cos(TH), np.sin(TH)
    B[..., 0, 0], B[..., 0, 1], B[..., 1, 0], B[..., 1, 1] = c, -s, s, c
    B[..., 2, 2] = B[..., 3, 3] = 1.0
    B[..., 0, 3], B[..., 1, 3], B[..., 2, 3] = X, Y, floor_z
    return B.reshape(-1, 4, 4)


def _yaw_free(m: ReachabilityMap) -> bool:
    """Turning the base about the floor normal changes nothing: yaw-symmetric about a vertical axis
    through the origin."""
    A = m.grid.T_world_A
    return m.grid.symmetric and bool(np.allclose(A[:3, 2], [0, 0, 1], atol=1e-12)) \
        and bool(np.allclose(A[:2, 3], 0.0, atol=1e-12 * max(1.0, m.robot.reach)))


def base_placement(map: ReachabilityMap, task_poses: ArrayLike, candidates: ArrayLike | None = None, *,
                   floor_z: float = 0.0, step: float | None = None, yaws: int | None = None, top: int = 5,
                   seed: int = 0) -> list[BasePlacement]:
    """Rank base poses by how many task poses the arm reaches from them; check the best with IK.

    Parameters
    ----------
    map : ReachabilityMap
    task_poses : array_like, shape (K, 4, 4)
        Tool poses to reach, in the task (floor) frame and the robot's length unit.
    candidates : array_like, shape (M, 4, 4), optional
        Base poses ``T_task_base`` to rank. Default: a grid on the plane ``z = floor_z``
        around the tasks (``step``, default the map's resolution) with ``yaws`` headings
        (default 1 when the map is yaw-symmetric about a vertical axis, since the heading
        then changes nothing, else 8).
    top : int
        How many of the best to check with IK and return.
    seed : int
        Seeds the numerical IK restarts of the check.

    Returns
    -------
    list of BasePlacement
        Best first: by the IK count, then the map count, then the map rank.
    """
    if not isinstance(map, ReachabilityMap):
        raise ArgumentError.of("map must be an armkit.ReachabilityMap, got {type}", type=type(map).__name__)
    T = np.asarray(task_poses, dtype=float)
    if T.ndim == 2 and T.shape == (4, 4):
        T = T[None]
    if T.ndim != 3 or T.shape[1:] != (4, 4) or len(T) == 0:
        raise ShapeError.of("task_poses must have shape (K, 4, 4) with K >= 1, got {shape}",
                            shape=np.shape(task_poses))
    if not np.all(np.isfinite(T)):
        raise ShapeError.of("task_poses contain NaN or infinite values")
    if isinstance(top, bool) or not isinstance(top, (int, np.integer)) or top < 1:
        raise ArgumentError.of("top must be a positive integer, got {top!r}", top=top)
    if candidates is None:
        h = map.grid.resolution if step is None else float(step)
        if not (math.isfinite(h) and h > 0):
            raise ArgumentError.of("step must be a positive length, got {step!r}", step=step)
        ny = (1 if _yaw_free(map) else 8) if yaws is None else int(yaws)
        if ny < 1:
            raise ArgumentError.of("yaws must be a positive integer, got {yaws!r}", yaws=yaws)
        B = _floor_candidates(map, T, float(floor_z), h, ny)
    else:
        B = np.asarray(candidates, dtype=float)
        if B.ndim != 3 or B.shape[1:] != (4, 4) or len(B) == 0:
            raise ShapeError.of("candidates must have shape (M, 4, 4) with M >= 1, got {shape}", shape=B.shape)
        if not np.all(np.isfinite(B)):
            raise ShapeError.of("candidates contain NaN or infinite values")
    Binv = np.linalg.inv(B)
    reached = np.zeros((len(B), len(T)), dtype=bool)
    index = np.zeros(len(B))
    step_m = max(1, 2_000_000 // len(T))                               # poses per pass: bounded memory
    for s in range(0, len(B), step_m):
        local = Binv[s:s + step_m, None] @ T[None]                     # (m, K, 4, 4)
        reached[s:s + step_m] = map.reachable(local)
        index[s:s + step_m] = map.index(local[..., :3, 3]).mean(axis=1)
    count = reached.sum(axis=1)
    order = np.lexsort((np.arange(len(B)), -index, -count))[:int(top)]
    out = []
    for i in order:
        local_i = Binv[i] @ T
        target = local_i[..., :3, 3] if map.grid.position_only else local_i
        res = ik(map.robot, target, seed=seed, scene=False)   # the map decides collisions (its scene=)
        out.append(BasePlacement(B[i], reached[i].copy(), np.asarray(res.success, dtype=bool).reshape(-1)))
    rank = {id(p): r for r, p in enumerate(out)}
    out.sort(key=lambda p: (-p.ik_count, -p.map_count, rank[id(p)]))
    return out
