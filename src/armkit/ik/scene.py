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

from typing import Any, Callable

import numpy as np

from ..collision import Scene, as_scene, colliding_rows, row_messages
from ..model.robot import Robot
from .result import IKResult, _message

__all__ = ["mark", "nearest_free", "sort_branches", "retry_numeric", "scene_or_none"]


def scene_or_none(robot: Robot, scene: Any) -> Scene | None:
    """``scene`` as a Scene in the robot's unit (``"robot"``: its own surroundings), ``None`` for none."""
    if scene is None:
        return None
    return as_scene(robot, scene)


def mark(robot: Robot, res: IKResult, scene: Scene) -> IKResult:
    """``res`` with every successful but colliding configuration made a ``"collision"`` failure.

    Which configurations collide is the yes/no check's answer (:func:`armkit.collision.colliding_rows` with
    ``messages=False``); the sentences naming the pair and the depth (:func:`armkit.collision.row_messages`) are made
    when the result's ``message`` is first read (:meth:`IKResult._later`): a loop that reads ``success`` alone
    measures no depth.
    """
    ok = np.asarray(res.success, dtype=bool)
    if not ok.any():
        return res
    candidates = np.asarray(res.q)[ok]
    bad_rows, _ = colliding_rows(robot, candidates, scene, messages=False)
    if not len(bad_rows):
        return res
    where = np.argwhere(ok)
    return _collided(robot, res, [tuple(where[k]) for k in bad_rows], candidates[bad_rows], scene)


def nearest_free(robot: Robot, res: IKResult, scene: Scene) -> IKResult:
    """One target's answer from its branches ``res`` (fields ``(m, ...)``, sorted): the first successful branch
    that does not collide, as it is; where none, the first branch, a ``"collision"`` failure if it succeeded. What
    :func:`mark` then :func:`sort_branches` would put first, found by the yes/no check alone: no depth is measured
    and no sentence made for the branches passed over, and the first branch's is made when it is read."""
    ok = np.flatnonzero(np.asarray(res.success, dtype=bool))
    k, collides = 0, False
    if len(ok):
        bad, _ = colliding_rows(robot, np.asarray(res.q)[ok], scene, messages=False)
        hit = set(bad.tolist())
        free = [int(b) for i, b in enumerate(ok.tolist()) if i not in hit]   # the successful ones that do not
        k = free[0] if free else 0                                           # collide, in their order
        collides = not free and ok[0] == 0   # none free: the first branch collides if it succeeded
    one = res._map(lambda a: np.asarray(a)[k, ...], None)
    return _collided(robot, one, [()], np.asarray(one.q)[None], scene) if collides else one


def _collided(robot: Robot, res: IKResult, hit: list[tuple], hit_q: np.ndarray, scene: Scene) -> IKResult:
    """``res`` with the successful configurations at the indices ``hit`` (their joints ``hit_q (k, n)``, each found
    colliding) made ``"collision"`` failures; their sentences are made when ``message`` is first read."""
    success = np.array(res.success, dtype=bool, copy=True)
    reason = np.array(res.reason, dtype=object, copy=True)
    for idx in hit:
        success[idx] = False
        reason[idx] = "collision"

    def message() -> Any:
        texts = row_messages(robot, hit_q, scene)
        old = res.message
        out = np.array(old, dtype=object, copy=True)
        for idx, text in zip(hit, texts):
            out[idx] = text
        # each field keeps its kind: one target's message stays the text it is (a collision's keeps its template
        # and fields for every language), a batch's an array
        return _message(_like(old, out) if np.ndim(old) else out[()], success.shape)

    # an array (one target's a 0-d array) stays one
    ok_out: Any = success if isinstance(res.success, np.ndarray) else np.bool_(success[()])
    new = IKResult._later((res.q, ok_out, res.position_error, res.rotation_error, res.iterations, res.branch,
                           res.within_limits, _like(res.reason, reason), None), message)
    new.__dict__["trace"] = res.trace
    return new


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

    return res._map(take, res.trace)   # a message not made yet (mark) is sorted when it is made


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
