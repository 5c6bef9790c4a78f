"""The result of a numerical solve: the FK check, the notes on failures, the :class:`IKResult`.

:func:`check` decides success (:func:`armkit.ik.verify`, or its masked form),
:func:`assemble` turns the final configurations into an :class:`IKResult` with a
``reason`` and a ``message`` built from fields, and :func:`_trace_array` pads the error
traces. Used by :mod:`armkit.ik.numeric`, :mod:`armkit.ik.ccd` and :mod:`armkit.ik.fabrik`
(through the re-exports of :mod:`armkit.ik.numeric`).
"""

from __future__ import annotations

from typing import Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._text import Fielded
from ._numeric_inputs import Problem
from ._numeric_numpy import _errors, _evaluate
from .result import IKResult, verify

Array = NDArray[np.float64]


def check(prob: Problem, q: Array) -> tuple[Array, Array, NDArray[np.bool_], NDArray[np.bool_]]:
    """The FK check: :func:`armkit.ik.verify`, or its masked form when only some axes count.

    With a partial mask the reported errors are the norms of the masked residual (position
    in length units over the weighted world axes, rotation in rad over the weighted target axes).
    """
    robot = prob.robot
    if prob.full_pose or prob.position_only:
        return verify(robot, q, prob.target, prob.position_only or prob.position_target, prob.tol,
                      prob.enforce_limits)
    e, _, _ = _evaluate(prob, q, np.arange(len(q)))
    dp, dr = _errors(prob, e)
    dp = dp / prob.s
    within = robot.within_limits(q)
    ok = (dp <= prob.tol[0]) & (dr <= prob.tol[1])
    if prob.enforce_limits:
        ok &= within
    return dp, dr, ok, within


def _fmt(x: float) -> str:
    return f"{x:.2e}" if (x != 0 and (abs(x) < 1e-3 or abs(x) >= 1e4)) else f"{x:.4g}"


def unreachable_note(distance: str, reach: str, origin: str) -> Fielded:
    """Why a target is out of reach (``distance`` and ``reach`` with their unit), measured from ``origin``
    (``const["reach from"]``: the base origin, or the shoulder); its template and fields go with it."""
    if origin == "the shoulder":
        return Fielded.of("target is {distance} from the shoulder; the arm reaches at most {reach}; q is the closest "
                          "configuration found", distance=distance, reach=reach)
    return Fielded.of("target is {distance} from the base origin; the arm reaches at most {reach}; q is the closest "
                      "configuration found", distance=distance, reach=reach)


def residual_note(dp: float, dr: float | None, unit: str) -> Fielded:
    """``position error ... [, rotation error ... rad]``, in words that keep their fields."""
    if dr is None:
        return Fielded.of("position error {error}", error=f"{_fmt(dp)} {unit}")
    return Fielded.of("position error {error}, rotation error {rotation}", error=f"{_fmt(dp)} {unit}",
                      rotation=f"{_fmt(dr)} rad")


def assemble(prob: Problem, q: Array, iterations: ArrayLike, branch: str, failure_reasons: dict[int, tuple[str, str]],
             trace: Optional[Array] = None, note: str = "") -> IKResult:
    """Build the :class:`IKResult`: success from :func:`check`, reasons and messages.

    ``failure_reasons`` maps a target index to ``(reason, sentence)`` for failures whose
    cause the solver knows; other failures get "max iterations" (or "joint limits" when
    the pose is met but the limits are not). The messages are made when ``message`` is first read
    (:meth:`IKResult._later`, from the numbers of this call): a few µs a target, a fifth of the Panda's
    ``armkit.ik`` of 1,000 targets, for a field most callers never read.
    """
    dp, dr, ok, within = check(prob, q)
    B = prob.B
    unit = prob.robot.unit
    its: NDArray[np.int64] = np.broadcast_to(np.asarray(iterations, np.int64), (B,)).copy()
    reason = np.empty(B, dtype=object)
    rot = not (prob.position_only or prob.position_target)
    dpl, drl, itl = dp.tolist(), dr.tolist(), its.tolist()
    known = dict(failure_reasons)     # the caller's dict may change before the messages are made
    okl, wl = ok.tolist(), within.tolist()
    for i in range(B):                # the reason now; its sentence (by the same reason) when message is read
        if okl[i]:
            reason[i] = "converged"
        elif i in known:
            reason[i] = known[i][0]
        elif prob.enforce_limits and not wl[i]:
            reason[i] = "joint limits"
        else:
            reason[i] = "max iterations"

    def messages() -> NDArray[np.object_]:
        message = np.empty(B, dtype=object)
        for i in range(B):
            resid = residual_note(dpl[i], drl[i] if rot else None, unit)
            if okl[i]:
                message[i] = Fielded.of("converged in {n} iterations: {residual}.", n=itl[i], residual=resid)
            elif i in known:
                message[i] = Fielded.of("{text}; {residual}.", text=known[i][1], residual=resid)
            elif reason[i] == "joint limits":
                message[i] = Fielded.of("the configuration breaks the joint limits; {residual}.", residual=resid)
            else:
                message[i] = Fielded.of("no solution within {n} iterations; best {residual}.", n=itl[i],
                                        residual=resid)
            if note:
                message[i] = Fielded.of("{message} {note}", message=message[i], note=note)
        return message

    res = IKResult._later((q, ok, dp, dr, its, np.full(B, branch, dtype=object), within, reason.astype(str), None),
                          messages)
    res.__dict__["trace"] = trace
    return res


def _trace_array(rows: list) -> Optional[Array]:
    if not rows:
        return None
    width = max(1, max(len(r) for r in rows))
    out = np.full((len(rows), width), np.nan)
    for i, r in enumerate(rows):
        out[i, :len(r)] = r
        if len(r) and len(r) < width:   # a finished target keeps its last error
            out[i, len(r):] = r[-1]
    return out
