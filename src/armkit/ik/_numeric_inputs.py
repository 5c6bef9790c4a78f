"""The numerical solvers' inputs: the checked problem, per-robot constants, restart seeds.

:class:`Problem` normalises one call of :func:`armkit.ik.numeric.solve_lm` (or of Newton,
CCD, FABRIK): the targets as poses, the start configurations, the weight vector ``w``
(the mask), the tolerance and the joint limits in force. :func:`_constants` keeps the
per-robot arrays in the robot's cache; :func:`_seeds` derives the reproducible restart
seeds. Everything here is re-exported by :mod:`armkit.ik.numeric`.
"""

from __future__ import annotations

import math
from typing import Any, Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ArmkitError, ShapeError
from ..model.robot import Robot
from .result import default_tolerance

Array = NDArray[np.float64]

_TOL_FACTOR = 0.25     # iterate to a quarter of the tolerance, so that the FK check has margin


# ----------------------------------------------------------------------------------------- inputs
_W_POSE = np.ones(6)
_W_POSITION = np.array([1, 1, 1, 0, 0, 0.0])
_W_POSE.setflags(write=False)
_W_POSITION.setflags(write=False)


def _constants(robot: Robot) -> dict:
    """Per-robot arrays the solvers need on every call (computed once, kept in the robot's cache)."""
    c = robot.cache.get("lm_constants")
    if c is None:
        rev = ~robot.prismatic
        reach = robot.reach
        span = 2.0 * reach if np.isfinite(reach) and reach > 0 else 1.0
        free_lo = np.where(rev, -math.pi, -np.inf)
        free_hi = np.where(rev, math.pi, np.inf)
        lo, hi = robot.lower.astype(float), robot.upper.astype(float)
        c = dict(rev=rev, reach=reach, origin=robot.base[:3, 3].copy(),
                 limits=(lo, hi, np.where(np.isfinite(lo), lo, np.where(rev, -math.pi, -span)),
                         np.where(np.isfinite(hi), hi, np.where(rev, math.pi, span))),
                 free=(free_lo, free_hi, np.where(rev, -math.pi, -span), np.where(rev, math.pi, span)))
        c["origin xyz"] = tuple(c["origin"].tolist())
        # arms with a yaw joint and three parallel pitch joints (the SO-101): the reach is measured from the
        # shoulder (its nearest position over the yaw angle), which is tighter than from the base origin
        try:
            from .analytic.yaw_pitch3 import shoulder_reach

            c["shoulder"] = shoulder_reach(robot)
        except Exception:   # noqa: BLE001 - a robot without a standard form: the base-origin bound only
            c["shoulder"] = None
        c["reach from"] = "the base origin" if c["shoulder"] is None else "the shoulder"
        c["reach at most"] = reach if c["shoulder"] is None else c["shoulder"][-1]
        for key in ("limits", "free"):  # lower, upper, random-start low and high as one (4, n) array
            c["packed " + key] = np.ascontiguousarray(np.stack(c[key]))
        robot.cache["lm_constants"] = c
    return c


class Problem:
    """Normalised inputs shared by the numerical solvers (internal)."""

    def __init__(self, robot: Robot, target: ArrayLike, q0: ArrayLike, mask: Optional[ArrayLike],
                 tol: Optional[tuple[float, float]], enforce_limits: bool, what: str = "solve_lm") -> None:
        if not isinstance(robot, Robot):
            raise ArmkitError.of("{what}: robot must be an armkit.Robot, got {type}", what=what,
                                 type=type(robot).__name__)
        t = np.asarray(target, dtype=float)
        if t.ndim == 3 and t.shape[1:] == (4, 4):
            self.position_target = False
            poses = t
        elif t.ndim == 2 and t.shape[1] == 3:
            self.position_target = True
            poses = np.broadcast_to(np.eye(4), (t.shape[0], 4, 4)).copy()
            poses[:, :3, 3] = t
        else:
            raise ShapeError.of("{what}: target must have shape (B, 4, 4) or (B, 3), got {shape}", what=what,
                                shape=t.shape)
        if not np.all(np.isfinite(t)):
            raise ShapeError.of("{what}: target contains NaN or infinite values", what=what)
        B = t.shape[0]
        q = robot.check_q(q0, "q0")
        if q.shape != (B, robot.n):
            raise ShapeError.of("{what}: q0 must have shape ({B}, {n}) for {B} targets, got {shape}", what=what, B=B,
                                n=robot.n, shape=q.shape)
        if mask is None:
            w = _W_POSITION if self.position_target else _W_POSE
        else:
            w = np.asarray(mask, dtype=float)
            if w.shape != (6,) or not np.all(np.isfinite(w)) or np.any(w < 0) or not np.any(w > 0):
                raise ShapeError.of("{what}: mask must be 6 non-negative weights over (x, y, z, rx, ry, rz) with at "
                                    "least one positive, got {mask!r}", what=what, mask=mask)
            if self.position_target:
                w = w.copy()
                w[3:] = 0.0
                if not np.any(w > 0):
                    raise ShapeError.of("{what}: a position target needs a positive weight on x, y or z, got {mask!r}",
                                        what=what, mask=mask)
        self.robot = robot
        self.target = t
        self.poses = np.ascontiguousarray(poses)
        self.q0 = np.array(q, dtype=float)
        self.w = w
        self.B = B
        self.tol: tuple[float, float] = (float(tol[0]), float(tol[1])) if tol is not None and len(tol) == 2 \
            else default_tolerance(robot) if tol is None else (-1.0, -1.0)
        if min(self.tol) <= 0 or min(self.tol) <= 0:
            raise ShapeError.of("{what}: tol must be (position, rotation) > 0, got {tol!r}", what=what, tol=tol)
        self.enforce_limits = bool(enforce_limits)
        self.s = robot.unit_scale
        self.const = _constants(robot)
        # without limits revolute joints are wrapped into [-pi, pi] and prismatic joints are free
        self.lower, self.upper, self.rand_lo, self.rand_hi = self.const["limits" if enforce_limits else "free"]

        if w is _W_POSE or w is _W_POSITION:
            self.full_pose, self.position_only = w is _W_POSE, w is _W_POSITION
        else:
            self.full_pose = bool(np.all(w > 0))
            self.position_only = bool(np.all(w[:3] > 0) and not np.any(w[3:] > 0))

    @property
    def packed_limits(self) -> Array:
        """lower, upper, random-start low and high as one (4, n) array for the kernel (cached per robot)."""
        if self.lower is self.const["limits"][0]:
            return self.const["packed limits"]  # type: ignore[no-any-return]
        if self.lower is self.const["free"][0]:
            return self.const["packed free"]  # type: ignore[no-any-return]
        return np.ascontiguousarray(np.stack([self.lower, self.upper, self.rand_lo, self.rand_hi]))

    @property
    def internal_tol(self) -> tuple[float, float]:
        return self.tol[0] * self.s * _TOL_FACTOR, self.tol[1] * _TOL_FACTOR

    def unreachable(self) -> tuple[NDArray[np.bool_], Array]:
        """Targets whose position is provably beyond the reach, and their distances from where the reach is
        measured: ``const["reach from"]`` (the base origin, or the shoulder of a yaw-pitch3 arm such as the
        SO-101), the reach being ``const["reach at most"]``."""
        sh = self.const["shoulder"]
        if sh is not None:
            dist = shoulder_distance(sh, self.poses[:, :3, 3])
            if not (self.w[0] > 0 and self.w[1] > 0 and self.w[2] > 0):
                return np.zeros(self.B, bool), dist
            return dist > sh[-1] * (1.0 + 1e-9) + self.tol[0], dist
        if self.B == 1:
            o = self.const["origin"]
            P = self.poses[0]
            dist = np.array([math.sqrt((P[0, 3] - o[0]) ** 2 + (P[1, 3] - o[1]) ** 2 + (P[2, 3] - o[2]) ** 2)])
        else:
            d = self.poses[:, :3, 3] - self.const["origin"]
            dist = np.sqrt(np.einsum("bi,bi->b", d, d))
        if not (self.w[0] > 0 and self.w[1] > 0 and self.w[2] > 0):
            return np.zeros(self.B, bool), dist
        return dist > self.const["reach"] * (1.0 + 1e-9) + self.tol[0], dist


def shoulder_distance(sh: tuple, p: Array) -> Array:
    """Distance of points ``p`` ``(B, 3)`` from the circle ``sh = (centre (3,), axis (3,), radius, reach)`` that
    the shoulder runs on as the yaw joint turns (:func:`armkit.ik.analytic.yaw_pitch3.shoulder_reach`)."""
    c, u, rs = sh[0], sh[1], sh[2]
    w = p - c
    z = w @ u
    rh = np.sqrt(np.maximum(np.einsum("bi,bi->b", w, w) - z * z, 0.0))
    return np.hypot(rh - rs, z)


def _seed_base(seed: Any) -> int:
    """The first target's restart seed (0 <= base < 2**62), reproducible from ``seed``."""
    if seed is None:   # the default is seeded too: the same call gives the same answer every run
        seed = 0
    if type(seed) is int or isinstance(seed, (int, np.integer)) and not isinstance(seed, bool):
        return (int(seed) * 0x9E3779B97F4A7C15 + 0x632BE59BD9B4E019) % 2**62
    return int(np.random.default_rng(seed).integers(0, 2**62))


def _seeds(seed: Any, B: int) -> NDArray[np.uint64]:
    """One restart seed per target, reproducible from ``seed``: base, base + 1, ..."""
    return (np.uint64(_seed_base(seed)) + np.arange(B, dtype=np.uint64)).astype(np.uint64)



def _subproblem(prob: Problem, idx: NDArray[np.intp]) -> Problem:
    sub = object.__new__(Problem)
    sub.__dict__.update(prob.__dict__)
    sub.target, sub.poses, sub.q0, sub.B = prob.target[idx], prob.poses[idx], prob.q0[idx], len(idx)
    return sub
