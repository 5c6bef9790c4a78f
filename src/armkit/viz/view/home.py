"""The view's first pose: :func:`home_pose`, and the conditioning limits the page warns at.

Re-exported by :mod:`armkit.viz.view.server` (and :mod:`armkit.viz.view`).
"""

from __future__ import annotations

import itertools
import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...errors import ArmkitError
from ...kinematics import condition_number
from ...model import Robot

__all__ = ["home_pose", "NEAR_SINGULAR", "SINGULAR", "HOME_STEPS"]

Array = NDArray[np.float64]
NEAR_SINGULAR = 100.0        # condition number above which the panel warns
SINGULAR = 1e12              # above it the page says "singular" (the number itself is rounding noise)
HOME_STEPS = (math.pi / 6, -math.pi / 6, math.pi / 3, -math.pi / 3)   # joint offsets tried for a home pose


def home_pose(robot: Robot, scene: Any = None) -> Array:
    """A home pose of ``robot``, shape ``(n,)``: zeros (moved inside the limits) unless that pose is singular.

    Most arms are singular at zero (stretched out, or a wrist lined up). Then the joints after
    the first are moved by +-30 deg or +-60 deg (revolute joints only), fewest joints first,
    and the best-conditioned pose among the fewest wins: within the limits, condition number
    of the task Jacobian below ``NEAR_SINGULAR / 2`` and clear of ``scene`` and of itself
    (``scene`` as in :func:`armkit.collisions`; ``False``: no collision check). Where no pose near
    zeros qualifies, the search starts again with the slides at the middle of their strokes. The search is
    deterministic (the same pose every time) and costs a few milliseconds.

    Parameters
    ----------
    robot : Robot
    scene : Scene, None or False
        Surroundings the pose must be clear of (None: the robot's own).

    Returns
    -------
    ndarray, shape (n,)
        The pose; zeros moved inside the limits when no candidate qualifies.
    """
    zero = np.clip(np.zeros(robot.n), robot.lower, robot.upper)
    for start in _starts(robot, zero):
        found = _search(robot, start, scene)
        if found is not None:
            return found
    return zero


def _starts(robot: Robot, zero: Array) -> list[Array]:
    """Where the search starts: zeros; then, for an arm with slides, each slide at the middle of its stroke (a
    SCARA's quill fully up puts its tip at the elbow)."""
    starts = [zero]
    slides = [k for k in range(robot.n) if robot.joints[k].is_prismatic
              and math.isfinite(robot.lower[k]) and math.isfinite(robot.upper[k])]
    if slides:
        mid = zero.copy()
        mid[slides] = 0.5 * (robot.lower[slides] + robot.upper[slides])
        starts.append(mid)
    return starts


def _search(robot: Robot, zero: Array, scene: Any) -> Array | None:
    """The best pose of :func:`home_pose`'s search from ``zero``, or None."""
    from ...collision import collisions

    free = [k for k in range(1, robot.n) if not robot.joints[k].is_prismatic]
    limit = NEAR_SINGULAR / 2
    for moved in range(0, len(free) + 1):
        rows = []
        for joints in itertools.combinations(free, moved):
            for offsets in itertools.product(HOME_STEPS, repeat=moved):
                q = zero.copy()
                q[list(joints)] += offsets
                rows.append(q)
        Q = np.array(rows).reshape(-1, robot.n)
        Q = Q[robot.within_limits(Q)]
        if len(Q) == 0:
            continue
        c = np.asarray(condition_number(robot, Q), dtype=float)
        good = np.isfinite(c) & (c < limit)
        if not good.any():
            continue
        Q, c = Q[good], c[good]
        order = np.argsort(c, kind="stable")
        Q = Q[order]
        if scene is not False:
            try:
                clear = ~np.asarray(collisions(robot, Q, None if scene is None else scene).colliding)
            except ArmkitError:        # a robot whose geometry cannot be checked: conditioning alone
                clear = np.ones(len(Q), dtype=bool)
            Q = Q[clear]
        if len(Q):
            return Q[0].copy()
    return None
