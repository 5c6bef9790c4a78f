"""IK with a scene: solutions that collide are not solutions.

On the ik floor, above collision (docs/architecture.md): it uses the collision package's
public API only (:func:`armkit.collision.colliding_rows`, :func:`armkit.collision.as_scene`), and
is imported by :mod:`armkit.ik.api` only when a ``scene=`` is given (the collision package is not
loaded at ``import armkit``).

:func:`mark` turns successful IK results whose configuration collides into failures with
``reason="collision"`` and a message naming the pair and the depth; :func:`sort_branches`
puts the collision-free branches of ``ik_all`` first again. :func:`retry_numeric` restarts a
numeric solver from random configurations for the targets whose answer collided.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Callable

import numpy as np

from ..collision import Scene, as_scene, colliding_rows
from ..model.robot import Robot
from .result import IKResult

__all__ = ["mark", "first_free", "sort_branches", "retry_numeric", "scene_or_none"]


def scene_or_none(robot: Robot, scene: Any) -> Scene | None:
    """``scene`` as a Scene in the robot's unit (``"robot"``: its own surroundings), ``None`` for none."""
    if scene is None:
        return None
    return as_scene(robot, scene)


def mark(robot: Robot, res: IKResult, scene: Scene) -> IKResult:
    """``res`` with every successful but colliding configuration made a ``"collision"`` failure."""
    ok = np.asarray(res.success, dtype=bool)
    if not ok.any():
        return res
    q = np.asarray(res.q)
    candidates = q[ok]
    bad_rows, messages = colliding_rows(robot, candidates, scene)   # one pass: rows, then pairs and depths
    if not len(bad_rows):
        return res
    success = ok.copy()
    reason = np.array(res.reason, dtype=object, copy=True)
    message = np.array(res.message, dtype=object, copy=True)
    where = np.argwhere(ok)
    for m, k in enumerate(bad_rows):
        idx = tuple(where[k])
        success[idx] = False
        reason[idx] = "collision"
        message[idx] = messages[m]
    # each field keeps its kind: an array (one target's a 0-d array) stays one, and one target's message stays the
    # text it is (a collision's keeps its template and fields for every language)
    ok_out: Any = success if isinstance(res.success, np.ndarray) else np.bool_(success[()])
    text = _like(res.message, message) if np.ndim(res.message) else message[()]
    return replace(res, success=ok_out, reason=_like(res.reason, reason), message=text)


def first_free(robot: Robot, res: IKResult, scene: Scene) -> int:
    """The index of the first successful branch of one target's branches ``res`` (fields ``(m, ...)``) that does
    not collide, or -1 where none: what :func:`mark` then :func:`sort_branches` would put first, found by the
    yes/no check alone (no depth measured, no sentence made for the branches that collide)."""
    ok = np.flatnonzero(np.asarray(res.success, dtype=bool))
    if not len(ok):
        return -1
    bad, _ = colliding_rows(robot, np.asarray(res.q)[ok], scene, messages=False)
    free = np.delete(ok, bad)      # the successful branches that do not collide, in their order
    return int(free[0]) if len(free) else -1


def _like(old: Any, new: np.ndarray) -> Any:
    o = np.asarray(old)
    if o.dtype.kind == "U":
        return new.astype(str)
    return new if o.ndim else new[()]


def sort_branches(res: IKResult) -> IKResult:
    """Branches ``(B, m)`` reordered so that successful ones come first (stable: the old order within each group)."""
    ok = np.asarray(res.success)
    if ok.ndim != 2:
        return res
    order = np.argsort(~ok, axis=1, kind="stable")
    rows = np.arange(ok.shape[0])[:, None]

    def take(a: Any) -> Any:
        return np.asarray(a)[rows, order]

    return IKResult(q=take(res.q), success=take(res.success), position_error=take(res.position_error),
                    rotation_error=take(res.rotation_error), iterations=take(res.iterations), branch=take(res.branch),
                    within_limits=take(res.within_limits), reason=take(res.reason), message=take(res.message),
                    trace=res.trace)


def retry_numeric(robot: Robot, res: IKResult, scene: Scene, solve: Callable[[np.ndarray, np.ndarray], IKResult],
                  seed: Any = None, rounds: int = 8) -> IKResult:
    """Numeric IK with a scene: targets whose solution collides are solved again from random starts.

    ``res`` holds flat results ``(B, ...)``; ``solve(q0, rows)`` solves the targets ``rows``
    from initial guesses ``q0``. A new solution replaces the old one only when it succeeds and
    is collision-free; what still collides after ``rounds`` restarts fails with reason
    ``"collision"``.
    """
    res = mark(robot, res, scene)
    rng = np.random.default_rng(seed if isinstance(seed, (int, np.integer)) else None if seed is None else 0)
    fields = {k: np.array(getattr(res, k), copy=True, dtype=object if k in ("reason", "message", "branch") else None)
              for k in ("q", "success", "position_error", "rotation_error", "iterations", "branch", "within_limits",
                        "reason", "message")}
    for _ in range(rounds):
        todo = np.flatnonzero(fields["reason"] == "collision")
        if not len(todo):
            break
        new = solve(robot.random_q(len(todo), rng=rng), todo)
        new = mark(robot, new, scene)
        good = np.asarray(new.success, dtype=bool)
        for k in fields:
            vals = np.asarray(getattr(new, k))
            fields[k][todo[good]] = vals[good]
    fields.update(branch=_like(res.branch, fields["branch"]), reason=_like(res.reason, fields["reason"]),
                  message=_like(res.message, fields["message"]))
    return IKResult(**fields, trace=res.trace)
