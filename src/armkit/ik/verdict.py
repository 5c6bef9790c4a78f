"""What the closed form says about targets a numeric method missed: the reason a failure is given.

LM, Newton, CCD and FABRIK are local: after their starts are spent they know that they found nothing,
not whether anything exists. Where the arm has a closed form with every branch for the kind of target
(an exact class: no search, at most 6 joints), :func:`closed_form_verdict` settles it for each target:
solutions inside the limits (the method missed them), solutions only outside the limits, or none at all
(out of reach). The solvers' diagnoses (:func:`armkit.ik.numeric._diagnose`, :func:`armkit.ik.ccd._reasons`)
and the tracker (:func:`armkit.viz.track`) say why from it, the same for every method.
"""

from __future__ import annotations

from typing import Any, NamedTuple, Optional

import numpy as np
from numpy.typing import NDArray

from .._text import Fielded
from ..errors import ArmkitError
from ..model.robot import Robot
from .api import _analytic_solver, ik_all

__all__ = ["Verdict", "closed_form_verdict", "of_problem", "reason_of", "settle", "settles", "SOLVABLE", "LIMITS", "UNREACHABLE"]

SOLVABLE, LIMITS, UNREACHABLE = 0, 1, 2


class Verdict(NamedTuple):
    """Per target: ``code`` (B,) one of SOLVABLE (an in-limit solution exists), LIMITS (solutions only outside
    the joint limits), UNREACHABLE (none); ``inside`` (B,) the number of in-limit solutions; ``broken`` (B,) the
    joints outside their limits of the nearest solution (LIMITS; "" otherwise); ``family`` the closed form's name."""
    code: NDArray[np.int64]
    inside: NDArray[np.int64]
    broken: NDArray[np.object_]
    family: str


def _exact_solver(robot: Robot, position_only: bool) -> Any:
    """The closed form that answers this kind of target with every branch, exactly (no search, no sweep), or None."""
    if robot.n > 6:
        return None
    solver = _analytic_solver(robot, position_only, None)
    if solver is None:
        return None
    for part in (solver, getattr(solver, "inner", None)):
        kind = getattr(getattr(part, "chain_class", None), "solver", "closed form")
        if kind != "closed form":
            return None
    return solver


def settles(robot: Robot, position_only: bool) -> bool:
    """Whether the closed form settles the failures of a numeric method on this kind of target (:func:`settle`):
    then a failure's reason "unreachable" or "joint limits" means that no in-limit solution exists."""
    return _exact_solver(robot, position_only) is not None


def closed_form_verdict(robot: Robot, target: Any, position_only: bool,
                        tol: Optional[tuple[float, float]] = None, enforce_limits: bool = True) -> Optional[Verdict]:
    """Whether the closed form reaches each target ``(B, 4, 4)`` or ``(B, 3)`` (a position), inside the limits or
    only outside them; None where the arm has no exact closed form for that kind of target (the caller keeps its
    own reasons).

    >>> import armkit, numpy as np
    >>> v = closed_form_verdict(armkit.load("planar2"), np.array([[0.2, 0, 0], [1.2, 0.3, 0]]), True)
    >>> v.code.tolist(), v.inside.tolist(), v.family      # inside the inner hole (radius 0.5), and reachable
    ([2, 0], [0, 2], 'planar-2r')
    """
    solver = _exact_solver(robot, position_only)
    if solver is None:
        return None
    t = np.asarray(target, dtype=float)
    B = t.shape[0]
    try:
        res = ik_all(robot, t, tol=tol, scene=False, enforce_limits=enforce_limits)
    except ArmkitError:
        return None
    ok = np.asarray(res.success).reshape(B, -1)
    reason = np.asarray(res.reason).reshape(B, -1)
    q = np.asarray(res.q).reshape(B, ok.shape[1], robot.n)
    outside = reason == "joint limits"
    code = np.where(ok.any(axis=1), SOLVABLE, np.where(outside.any(axis=1), LIMITS, UNREACHABLE))
    broken = np.full(B, "", dtype=object)
    for i in np.flatnonzero(code == LIMITS):
        names = [robot.limit_violations(q[i, b]) for b in np.flatnonzero(outside[i])]
        fewest = min(range(len(names)), key=lambda k: len(names[k]))   # the branch that breaks the fewest limits
        broken[i] = ", ".join(names[fewest])
    return Verdict(code.astype(np.int64), ok.sum(axis=1).astype(np.int64), broken, str(solver.family))


def of_problem(prob: Any, which: NDArray[np.intp]) -> Optional[Verdict]:
    """:func:`closed_form_verdict` for the targets ``which`` of a numeric solver's problem
    (:class:`armkit.ik._numeric_inputs.Problem`) whose weights ask for a whole position or pose; None otherwise
    (a partial mask: some directions free)."""
    w = prob.w
    if not np.all(w[:3] > 0):
        return None
    if prob.position_target or not np.any(w[3:] > 0):
        t = prob.target[which] if prob.position_target else prob.target[which, :3, 3]
        position_only = True
    elif np.all(w[3:] > 0):
        t, position_only = prob.target[which], False
    else:
        return None
    return closed_form_verdict(prob.robot, t, position_only, prob.tol, prob.enforce_limits)


def reason_of(v: Verdict, j: int, missed: tuple[str, str]) -> tuple[str, str]:
    """The reason and message of target ``j`` that a method missed (its own ``missed`` reason and message), from
    the closed form's verdict: out of reach, only outside the limits, or the method's own words with the number
    of solutions it missed."""
    code, family = int(v.code[j]), v.family
    if code == UNREACHABLE:
        return "unreachable", Fielded.of("no configuration reaches the target: the closed form ({family}) finds none; "
                                         "q is the closest configuration found", family=family)
    if code == LIMITS:
        return "joint limits", Fielded.of("the closed form ({family}) reaches the target only outside the joint "
                                          "limits ({broken}); q is the best configuration found inside them",
                                          family=family, broken=v.broken[j])
    # solutions exist inside the limits: the method missed them (its budget spent), whatever it found outside
    return ("max iterations" if missed[0] == "joint limits" else missed[0],
            Fielded.of("{missed}; the closed form ({family}) finds {k} inside the limits (method 'auto' gives them)",
                       missed=missed[1], family=family, k=int(v.inside[j])))


def settle(prob: Any, reasons: dict[int, tuple[str, str]]) -> None:
    """Replace, in place, the reasons of a numeric solver's failed targets (``reasons``: index -> (reason,
    message)) by what the closed form says (:func:`reason_of`), where the arm has one for the problem's kind of
    target. Targets already out of reach (beyond ``robot.reach``, or more to meet than joints) keep theirs."""
    which = np.array(sorted(i for i, (r, _) in reasons.items() if r != "unreachable"), dtype=np.intp)
    if which.size == 0:
        return
    verdict = of_problem(prob, which)
    if verdict is not None:
        for j, i in enumerate(which.tolist()):
            reasons[i] = reason_of(verdict, j, reasons[i])
