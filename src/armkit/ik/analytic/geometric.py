"""The geometric family: every branch by subproblem decomposition, for any 6-joint arm whose axes allow it.

The six hand-written families (:data:`armkit.ik.analytic.FAMILIES`) are matched by DH patterns
and keep their fast kernels and branch names. This family answers the arms they miss: the same
kinds of arm written another way (a URDF whose axes point the other way, a calibrated file whose
axes only nearly meet, the Kinova Jaco), and the classes they never covered (the general
spherical wrist by a 1-D search, three parallel axes without intersecting ones, a spherical
wrist at the base). It works on the chain's product-of-exponentials form
(:mod:`armkit.ik.geometric.poe`), classified by :func:`armkit.ik.geometric.classify.classify`,
and solved by :mod:`armkit.ik.geometric.solvers`; a class named "inverted" is solved on the
reversed chain (tool to base) for the inverse target.

Branches are numbered in the order the solver finds them (``s1``, ``s2``, ...). A target for
which fewer real solutions exist than the class allows gets the remaining branches marked
unreachable (with the least-squares candidates where the solver gave some); every branch is
verified by FK of the true model in :func:`armkit.ik.analytic.solve_all`, which also wraps,
polishes and sorts them, exactly as for the other families. A single target of :func:`armkit.ik` or
:func:`armkit.ik_all` is solved, verified, wrapped and sorted in one compiled call
(:mod:`armkit.ik.geometric.one_call`, through :attr:`Geometric.geometry`) for the classes solved in
closed form, with the same results; the classes of the 1-D and 2-D searches solve in Python and
verify in one call.
"""

from __future__ import annotations

from typing import Any, Callable

import numpy as np
from numpy.typing import NDArray

from ...model.robot import Robot
from ._common import Raw, StandardForm

__all__ = ["Geometric", "solver_name"]

Array = NDArray[np.float64]

# class name without "-base" (the inverted classes are solved on the reversed chain) -> solver, branches
_CLASSES: dict[str, tuple[str, int]] = {
    "6R-spherical-wrist-two-intersecting": ("spherical_wrist", 8),
    "6R-spherical-wrist-two-parallel": ("spherical_wrist", 8),
    "6R-spherical-wrist": ("spherical_wrist", 8),
    "6R-three-parallel-two-intersecting": ("three_parallel_two_intersecting", 8),
    "6R-three-parallel": ("three_parallel", 8),
    "RRPRRR-spherical-wrist": ("spherical_two_intersecting", 8),
    "6R-two-intersecting": ("two_intersecting", 16),
    "6R-two-parallel": ("two_parallel", 16),
    "6R-spherical-middle": ("spherical_middle", 16),
    "6R-general": ("gen_six_dof", 16),
}


def solver_name(robot: Robot) -> tuple[str, int, bool, Any] | None:
    """``(solver, branches, inverted, class)`` for the robot's geometric class, or None when no solver here fits."""
    from ..geometric.classify import classify
    from ..geometric.solvers import _meets

    if robot.n != 6:
        return None
    cls = classify(robot)
    if cls.degenerate or cls.solver not in ("closed form", "1-D search", "2-D search"):
        return None
    key = cls.name.replace("-base", "")
    hit = _CLASSES.get(key)
    if hit is None:
        return None
    if hit[0] == "two_intersecting":      # the 1-D search here needs axes 5 and 6 to meet (1 and 2 reversed)
        from ..geometric.poe import poe
        from ..geometric.solvers import reverse

        form = poe(robot)
        if not _meets(reverse(form) if cls.inverted else form, 4, 5, 1e-6):
            return None
    return hit[0], hit[1], bool(cls.inverted), cls


_UNSET: Any = object()
_SINGULAR = "singular wrist: a family of solutions; this one keeps the free joint at its start value."


def _why(found: int, m: int) -> str:
    """Why a branch is out of reach when the target has ``found`` solutions (0: none) of the class's ``m``."""
    if found:
        return (f"this target has {found} solution{'s' if found > 1 else ''}; the arm's class allows "
                f"up to {m}, and this branch is not one of them.")
    return "no configuration of this arm reaches the target (the closest is shown)."


class Geometric:
    """A :class:`~armkit.ik.analytic.ClosedFormFamily` built on the subproblem solvers."""

    family = "geometric"
    pose_only = True
    target_kind = "pose"
    polish_above = 1e-12
    """The solvers check every solution on the true chain and polish what the ideal chain got only nearly
    right; what is left is the rounding of an ideal chain within ~1e-13 of the true one, so solve_all's
    Gauss-Newton touch-up (about 2 ms a call) runs only above 1e-12 (of the reach, and rad)."""

    def __init__(self, robot: Robot, solver: str, m: int, inverted: bool, chain_class: Any) -> None:
        from ..geometric import solvers
        from ..geometric.poe import poe

        self.robot = robot
        self.chain_class = chain_class
        self.solver = solver
        self.inverted = inverted
        form = poe(robot)
        self.form = solvers.reverse(form) if inverted else form
        self._solve: Callable[..., Any] = solvers.SOLVERS[solver]
        self.m = m
        self._geometry: Array | None = _UNSET
        self.branch_labels = tuple(f"s{k + 1}" for k in range(m))
        n = robot.n
        eye = np.eye(4)
        self.sf = StandardForm(np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n), eye, eye, eye, eye,
                               float(robot.reach), exact=True)   # the solvers polish on the true chain themselves

    @classmethod
    def detect(cls, sf: StandardForm | None, robot: Robot) -> "Geometric | None":
        found = solver_name(robot)
        if found is None:
            return None
        solver, m, inverted, chain_class = found
        return cls(robot, solver, m, inverted, chain_class)

    @property
    def geometry(self) -> Array | None:
        """The packed vector of the one-call kernel (:func:`armkit.ik.geometric.one_call.geometry`), built once,
        when that kernel serves this class (the closed forms, not the searches); else None.
        Read only by the one-call path of :func:`armkit.ik.analytic.single_call`, which runs with Numba only:
        reading it compiles the kernel on first use and registers it for the family."""
        if self._geometry is _UNSET:
            from ..geometric import one_call

            g = one_call.geometry(self.form, self.solver, self.m, self.inverted)
            self._geometry = g if g is not None and one_call.kernel() is not None else None
        return self._geometry

    def _batched(self, target: Array, q0phi: Array) -> tuple | None:
        """``(solver case, the arrays of :func:`armkit.ik.geometric.batched.solve`)``: the batch in one compiled
        call when Numba is there (as :func:`~armkit.ik.geometric.solvers.solve_batch` takes it) and the class is
        solved by a kernel of :data:`armkit.ik.geometric.solvers._CASES`; else None."""
        from ..geometric import solvers

        name = solvers.case_of(self.solver, self.form)
        if name not in solvers._CASES:
            return None
        from ..geometric import batched

        prep = solvers._prepare(self.form, name)
        out = batched.solve(prep, self.inverted, self.m, target, q0phi, solvers.SEARCH_N, solvers.TOL * prep.scale,
                            solvers.TOL)
        return None if out is None else (name, out)

    def reach_why(self, lateral_out: bool, rho: float, r: float, target: Array | None) -> str:
        """Why a branch is out of reach, from the one-call kernel's numbers: ``rho`` is the count of solutions the
        target has (0: none); the sentence :meth:`solve`'s ``why`` gives."""
        return _why(int(rho), self.m)

    def solve(self, target: Array, q0phi: Array) -> Raw:
        """Every branch for pose targets ``(B, 4, 4)``; ``q0phi`` ``(B, n)`` (the singular wrist's free joint)."""
        B, m, n = len(target), self.m, self.robot.n
        q = np.zeros((B, m, n))
        unreachable = np.zeros((B, m), dtype=bool)
        note = np.full((B, m), "", dtype=object)
        found = np.zeros(B, dtype=np.int64)
        R, p, ref = target[:, :3, :3], target[:, :3, 3], q0phi
        if self.inverted:      # the reversed chain, for the inverse target
            R = np.swapaxes(R, 1, 2)
            p = -np.einsum("bij,bj->bi", R, p)
            ref = ref[:, ::-1]
        from ..geometric import solvers

        rows: Any = range(B)
        fast = self._batched(target, q0phi)
        if fast is not None:   # one compiled call for the batch; only the targets it leaves go on below
            name, (q, unreachable, singular, found, redo) = fast
            for b, i in zip(*np.nonzero(singular)):
                note[b, i] = _SINGULAR
            rows = np.flatnonzero(redo)
            sols = [solvers._run(name, self.form, R[b], p[b], ref[b], None) for b in rows]
        else:
            sols = solvers.solve_batch(self.solver, self.form, R, p, ref)
        for b, sol in zip(rows, sols):
            qs = sol.q[:, ::-1] if self.inverted else sol.q
            k = min(len(qs), m)
            if k and not sol.ls.any():
                q[b, :k] = qs[:k]
                found[b] = k
                for i in np.flatnonzero(sol.singular[:k]):
                    note[b, i] = _SINGULAR
                q[b, k:] = qs[0]                 # padding, marked unreachable below
                unreachable[b, k:] = True
            else:                                # out of reach: the least-squares candidates, or the start
                if k:
                    q[b, :k] = qs[:k]
                    q[b, k:] = qs[0]
                else:
                    q[b] = q0phi[b]
                unreachable[b] = True
        label = np.broadcast_to(np.array(self.branch_labels, dtype=object), (B, m)).copy()

        def why(i: int) -> str:
            return _why(int(found[i // m]), m)
        missing = unreachable.copy()
        return Raw(q, label, unreachable, why, note, missing)
