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

from ... import _jit_loader
from ..._text import Fielded
from ...kinematics import fk, packed
from ...model.robot import Robot
from ._common import Raw, StandardForm

__all__ = ["Geometric", "GeometricGimbal", "across", "chain_form", "solver_name", "three_axes"]

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
    if hit[0] == "spherical_two_intersecting" and "P" in cls.joint_types:
        from ..geometric.poe import poe      # the Stanford arm's layout: axes 1 and 2 meet (else geometric-prismatic-wrist)

        if not _meets(poe(robot), 0, 1, 1e-6):
            return None
    if hit[0] == "two_intersecting":      # the 1-D search here needs axes 5 and 6 to meet (1 and 2 reversed)
        from ..geometric.poe import poe
        from ..geometric.solvers import reverse

        form = poe(robot)
        if not _meets(reverse(form) if cls.inverted else form, 4, 5, 1e-6):
            return None
    return hit[0], hit[1], bool(cls.inverted), cls


def chain_form(robot: Robot, exact: bool) -> StandardForm:
    """The :class:`StandardForm` of a family that solves the robot's product-of-exponentials chain itself: no DH
    offsets, identity base and tool, the robot's reach as the scale; ``exact`` False where it solves a nearby ideal
    chain (:func:`armkit.ik.analytic.solve_all` then polishes the branches on the robot)."""
    eye = np.eye(4)
    zero = np.zeros(robot.n)
    return StandardForm(zero, zero, zero, zero, eye, eye, eye, eye, float(robot.reach), exact=exact)


_UNSET: Any = object()
_SINGULAR = "singular wrist: a family of solutions; this one keeps the free joint at its start value."


def _why(found: int, m: int) -> str:
    """Why a branch is out of reach when the target has ``found`` solutions (0: none) of the class's ``m``: a sentence
    that keeps its template and fields (rendered in the user's language)."""
    if found == 1:
        return Fielded.of("this target has 1 solution; the arm's class allows up to {m}, and this branch is not one "
                          "of them.", m=m)
    if found:
        return Fielded.of("this target has {count} solutions; the arm's class allows up to {m}, and this branch is "
                          "not one of them.", count=found, m=m)
    return Fielded.of("no configuration of this arm reaches the target (the closest is shown).")


def _turns(q: Array, other: Array) -> Array:
    """Squared distances ``(B, k, m)`` of branches ``q`` ``(B, k, n)`` from ``other`` ``(B, m, n)``, each joint's
    difference less its nearest whole turns (into [-pi, pi]; a remainder, as before 2026-12-07, costs ~4x)."""
    diff = q[:, :, None, :] - other[:, None, :, :]
    diff -= 2.0 * np.pi * np.rint(diff / (2.0 * np.pi))
    return np.einsum("bkmn,bkmn->bkm", diff, diff)


def _kernel_branches(robot: Robot, target: Array) -> Array | None:
    """Every branch ``(B, m, n)`` of the pose targets ``(B, 4, 4)`` as :func:`armkit.ik_all` answers them (the
    robot's one-call kernel, every row by the batch driver: wrapped near the default start, touched up, sorted),
    for :meth:`Geometric.name_branches` of fewer than ``m`` branches a target; None where the one-call path does
    not serve (no record or kernel, Numba off) or a target's call asks for the batched path. One target's branches
    took ~35 µs by :meth:`Geometric.solve`, ~3 this way (the driver called here: through :func:`._batch_from_rows`,
    whose result, kept sets and marks a field needs not, reading one ``ik``'s branch took 8 µs more)."""
    c = robot.cache.get("ik_fast")
    if not c or c.kernel is None or not c.address or _jit_loader._ACTIVE is None:
        return None
    B = len(target)
    FB, IB, BB = np.empty((B,) + c.fshape), np.empty((B, c.isize), np.int64), np.empty((B, c.bsize), np.bool_)
    marks, q = np.empty(B, np.int64), np.empty((B, c.m, c.n))
    flat = np.ascontiguousarray(target, dtype=float).reshape(B, -1)
    pending = c.kernels.rows_entry(False)(c.address, flat, c.q0.reshape(1, -1), False, c.ctx, FB, IB, BB,
                                          c.wk.reshape(1, -1), marks, q.reshape(B, -1), np.empty((B, c.m), np.bool_))
    if pending < 0 or pending >> 32:   # (a target to reject, or rows for the batched path)
        return None
    return q


_NAME_KINDS = {"spherical-wrist": 0, "ur": 1}
"""The naming families with a compiled naming core (``_single.name_rows``: ``NAME_WRIST``, ``NAME_UR``)."""


def _named_compiled(robot: Robot, names: Any, ideal: Robot, flat: Array, k: int
                    ) -> tuple[NDArray[np.int64], NDArray[np.bool_]] | None:
    """:meth:`Geometric.name_branches`'s index into ``names.branch_labels`` of each branch ``flat`` (R, n) (``k`` a
    target), and whether a target got one index twice, by one compiled call (``_single.name_rows``), or None
    where the Numba back end is not in use, the naming family has no compiled core here, or its kernel leaves a
    branch to its ``solve`` (a UR wrist singular): the NumPy steps then answer, with the same rules. The steps
    took ~40 µs to name one target's 8 branches and 12 µs a target in a batch (the rounded Puma, 2026-12-07)."""
    kind = _NAME_KINDS.get(names.family)
    if kind is None:
        return None
    kernels = _jit_loader.kernels("ik.analytic._single")
    if kernels is None:
        return None
    consts = robot.cache.get("naming_consts")
    if consts is None or consts[0] is not names:   # (the geometry copied: the kernels take writable arrays)
        consts = robot.cache["naming_consts"] = (names, packed(ideal)[0], np.array(names.geometry),
                                                 np.ascontiguousarray(names.sf.theta, dtype=float))
    _, F, g, theta = consts
    first = np.empty(len(flat), np.int64)
    dup = np.empty(len(flat) // k, np.bool_)
    if not kernels.name_entry(len(flat))(flat, theta, F, g, kind, k, first, dup):
        return None
    return first, dup


def _family_branches(names: Any, target: Array, q0phi: Array) -> tuple[Array, NDArray[np.int64]]:
    """The DH angles ``(B, m, n)`` of the naming family ``names``'s branches of ``target`` and their indices into its
    ``branch_labels`` ``(B, m)``: its lean ``branches`` (no sentences) where it has one that answers, else its
    ``solve`` (:meth:`Geometric.name_branches`)."""
    lean = getattr(names, "branches", None)
    got = lean(target, q0phi) if lean is not None else None
    if got is not None:
        return got  # type: ignore[no-any-return]
    raw = names.solve(target, q0phi)
    index = {name: i for i, name in enumerate(names.branch_labels)}
    return raw.q, np.vectorize(index.__getitem__, otypes=[np.int64])(np.asarray(raw.label, dtype=object))


SETTLE_TIE = 1e-12
"""Squared distances (rad²) within this times ``1 + nearest`` of the nearest are a tie for :func:`_settle` (a
target's branches come in pairs as far from a padded branch up to rounding, whose last bits depend on the order of
the sum: ``np.einsum`` adds the six joints in two lanes, the compiled twin in one)."""


def _settle(named: NDArray[np.object_], q: Array, ideal: Array, label: NDArray[np.object_]) -> None:
    """Names given twice in one target's branches settled, in place (where Numba is off; else its compiled twin
    ``_single.settle_rows``, the same steps on the names' indices): ``named`` ``(k,)`` the names of branches ``q``
    ``(k, n)`` by the rule, ``ideal`` ``(m, n)`` the naming family's branches of the target with names ``label``
    ``(m,)``. A name given once stays; the branches that share a name, and the names no branch kept, are paired
    nearest first (angles modulo 2 pi, each branch against the family's branch of that name; a tie goes to the
    branch first in the order of their joint values, then to the name first in ``label``), so the pairing does not
    depend on the order the branches come in."""
    count: dict = {}
    for name in named:
        count[name] = count.get(name, 0) + 1
    shared = [i for i, name in enumerate(named) if count[name] > 1]
    # in the order of their joint values (to 1e-9 rad, modulo 2 pi), not the order they come in; identical ones
    # keep theirs (a stable sort: the sorted branches keep the order of the raw ones where their keys tie)
    key = np.round(np.remainder(q[shared] + np.pi, 2.0 * np.pi) * 1e9)
    shared = [shared[i] for i in np.lexsort(key.T[::-1])]
    free = [j for j, name in enumerate(label) if count.get(name, 0) != 1]
    d = _turns(q[None, shared], ideal[None, free])[0]
    for _ in range(len(shared)):   # the nearest pair (the first in row order within SETTLE_TIE of it)
        near = d.min()
        i, j = np.unravel_index(int(np.argmax(d <= near + SETTLE_TIE * (1.0 + near))), d.shape)
        named[shared[i]] = label[free[j]]
        d[i, :] = np.inf
        d[:, j] = np.inf


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
        self.sf = chain_form(robot, exact=True)   # the solvers polish on the true chain themselves
        self.names_from: Any = None
        """The hand-written family whose branch names this arm's branches take (:meth:`name_branches`; it solves
        the arm's ideal DH twin), or None: the branches are ``s1``, ``s2``, ... (set by
        :func:`armkit.ik.analytic.closed_form`)."""

    @classmethod
    def detect(cls, sf: StandardForm | None, robot: Robot) -> "Geometric | None":
        found = solver_name(robot)
        if found is None:
            return None
        solver, m, inverted, chain_class = found
        return cls(robot, solver, m, inverted, chain_class)

    def solves_exactly(self) -> bool:
        """Whether the one-call kernel serves this class (a closed form, not a search) on the arm's own axes (its
        ideal chain is the true one up to rounding): then no branch needs a touch-up. Compiles nothing."""
        from ..geometric import one_call

        g = one_call.geometry(self.form, self.solver, self.m, self.inverted)
        return g is not None and g[one_call.EXACT] == 1.0

    def name_branches(self, q: Array, target: Array) -> NDArray[np.object_]:
        """The names ``(B, k)`` of branches ``q`` ``(B, k, n)`` (joint values) of the pose targets ``(B, 4, 4)``.

        With :attr:`names_from` (a hand-written family solving the arm's ideal DH twin, within ~1e-5 of this arm):
        a branch ``q`` takes the name that family gives ``q`` itself as a solution of the pose its ideal arm reaches
        at ``q`` (its sign rules: ``noflip`` where ``sin q5 >= 0``, ...), so a file that rounds its numbers names
        the branches it solves on its own axes as its exact DH table names them (``left/elbow-up/noflip``). Where
        that would give one target two branches of one name (a branch that does not reach the target, padded with
        another's values; a hair from the ideal arm's fold), those branches and the names left over are paired by
        distance to the family's branches of the target (:func:`_settle`), in any order of the branches the same;
        fewer than ``m`` branches of a target (:func:`armkit.ik`'s one) take the names they have among all of
        them. Without it: ``s1``, ``s2``, ... in the solver's order.

        Examples
        --------
        >>> from dataclasses import replace
        >>> import armkit
        >>> from armkit.ik.analytic import closed_form
        >>> puma = armkit.load("puma560")   # a file that writes its 90 deg twists rpy="1.5708" (3.7e-6 off):
        >>> file = armkit.Robot([replace(j, alpha=j.alpha + np.copysign(3.7e-6, j.alpha) if j.alpha else 0.0)
        ...                      for j in puma.joints], name="puma560, rounded")
        >>> closed_form(file).family, closed_form(file).names_from.family
        ('geometric', 'spherical-wrist')
        >>> q = np.array([0.3, -0.8, 0.4, 0.5, 0.9, -0.2])
        >>> def name_of(arm):   # the name of the branch at q
        ...     r = armkit.ik_all(arm, armkit.fk(arm, q))
        ...     return r.branch[np.argmin(np.abs(r.q - q).sum(axis=1))]
        >>> name_of(file), name_of(file) == name_of(puma)
        ('right/elbow-down/noflip', True)
        """
        names = self.names_from
        B, k, n = q.shape
        if names is None:
            return np.broadcast_to(np.array(self.branch_labels, dtype=object)[:k], (B, k)).copy()
        target = np.ascontiguousarray(target, dtype=float)
        if k < self.m:   # among every branch of the target: the one-call kernel's (named as ik_all names them),
            every = _kernel_branches(self.robot, target)   # else solve's
            if every is not None:
                pick = _turns(q, every).argmin(axis=-1)
                return np.take_along_axis(self.name_branches(every, target), pick, axis=1)
            raw = self.solve(target, q[:, 0])
            pick = _turns(q, raw.q).argmin(axis=-1)
            return np.take_along_axis(np.asarray(raw.label, dtype=object), pick, axis=1)
        ideal = self.robot.cache.get("ideal_arm")
        if ideal is None:   # the ideal arm as a DH table (the naming family's): its FK for the same joint values
            ideal = self.robot.cache["ideal_arm"] = names.sf.as_robot(self.robot, f"{self.robot.name}, ideal arm")
        flat = np.ascontiguousarray(q.reshape(B * k, n))
        theta = names.sf.theta
        got = _named_compiled(self.robot, names, ideal, flat, k)
        if got is not None:
            first, dup = got
            twice = np.flatnonzero(dup)
        else:
            poses, start = fk(ideal, flat), flat + theta
            angles, table = _family_branches(names, poses, start)
            # the family's branch at q: the nearest; where several are as near (to 1e-7 rad: on a fold, where two
            # branches meet and rounding of 1e-16 moves them by its square root), the first of them in the family's
            # table, whatever rounding says
            d = _turns(flat[:, None, :], angles - theta)[:, 0]
            tie = d <= d.min(axis=1, keepdims=True) + 1e-14
            first = np.where(tie, table, len(names.branch_labels)).min(axis=1)
            idx = np.sort(first.reshape(B, k), axis=1)
            twice = np.flatnonzero((idx[:, 1:] == idx[:, :-1]).any(axis=1))
        labels = np.array(names.branch_labels, dtype=object)
        if len(twice):   # the family's branches of those targets, to settle the names given twice
            own, own_table = _family_branches(names, target[twice], q[twice, 0] + theta)
            if got is not None:   # (one compiled call: ~35 µs a target by the steps below, 2026-12-07)
                first = first.reshape(B, k)
                kernels = _jit_loader.kernels("ik.analytic._single")
                kernels.settle_rows(first, flat.reshape(B, k, n), twice, np.ascontiguousarray(own - theta),
                                    np.ascontiguousarray(own_table, dtype=np.int64), len(labels), SETTLE_TIE)
                return labels[first]
            named = labels[first].reshape(B, k)
            for r, b in enumerate(twice):
                _settle(named[b], q[b], own[r] - theta, labels[own_table[r]])
            return named
        return labels[first].reshape(B, k)

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

        if batched.kernels() is None:
            return None

        prep = solvers._prepare(self.form, name)
        out = batched.solve(prep, self.inverted, self.m, target, q0phi, solvers.SEARCH_N, solvers.TOL * prep.scale,
                            solvers.TOL, packed(self.robot)[0], self.sf.theta)
        return None if out is None else (name, out)

    def reach_why(self, lateral_out: bool, rho: float, r: float, target: Array | None) -> str:
        """Why a branch is out of reach, from the one-call kernel's numbers: ``rho`` is the count of solutions the
        target has (0: none); the sentence :meth:`solve`'s ``why`` gives."""
        return _why(int(rho), self.m)

    def solve(self, target: Array, q0phi: Array, named: bool = True) -> Raw:
        """Every branch for pose targets ``(B, 4, 4)``; ``q0phi`` ``(B, n)`` (the singular wrist's free joint).
        ``named`` False: the labels ``s1``, ``s2``, ... in the solver's order even where :meth:`name_branches` names
        them (the batched paths make the names when they are read)."""
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
        label = self.name_branches(q, target) if named else \
            np.broadcast_to(np.array(self.branch_labels, dtype=object), (B, m)).copy()

        def why(i: int) -> str:
            return _why(int(found[i // m]), m)
        missing = unreachable.copy()
        return Raw(q, label, unreachable, why, note, missing)


PARALLEL_TOL = 1e-4
"""Two axes of a 3R arm whose directions differ by less than this (rad) are solved as parallel (and polished)."""
MEET_TOL = 1e-9
"""Two axes of a 3R arm closer than this times the arm's size are solved as meeting. Axes that only nearly meet
go to SP5, which slides its point along axis 2 away from axis 1 and stays well conditioned there; solving them as
meeting and polishing lost solutions (hypothesis found an arm whose axes 1, 2 missed by 6e-5 of its size)."""


class Geometric3R:
    """Every branch of a position target for a 3R arm the hand-written families do not match: the classes
    ``3R-general``, ``3R-two-parallel`` and ``3R-elbow`` of :func:`armkit.ik.geometric.classify.classify` (an arm
    with offsets, axes that only meet or lie parallel in the geometry, not in the DH pattern; the fighter's
    family answers the fighter itself).

    The tool point is ``p = p_01 + rot(h1, q1) (p_12 + rot(h2, q2) (p_23 + rot(h3, q3) p_3T))`` (the chain's
    product-of-exponentials form, :mod:`armkit.ik.geometric.poe`), solved as the spherical wrist's position
    part is (:func:`armkit.ik.geometric.solvers_wrist._pos_general`): SP5 (a quartic, up to 4 solutions) in
    general, SP4 then SP3 and SP1 where axes 2 ∥ 3, and where axes 1 ∥ 2 the mirror of that: the component
    along axis 1 fixes q3 (SP4), the distance from axis 1 then q2 (SP3), and q1 turns the rest onto the target
    (SP1) (:func:`_first_two_parallel`). Where axes 1 and 2 meet, the distance from their common point fixes q3
    (SP3) and SP2 gives q1, q2; where axes 2 and 3 meet, the distance from theirs fixes q1 (SP3) and SP2 gives
    q2, q3 (:func:`_second_two_meet`). Axes that are nearly parallel are solved on the nearest ideal chain and
    polished on the robot. Every branch is verified by FK of the robot (:func:`armkit.ik.analytic.solve_all`); a
    target out of reach gets the least-squares candidates, marked unreachable.
    """

    family = "geometric-3r"
    pose_only = False
    target_kind = "position"
    polish_above = 1e-12
    m = 4
    m_joints = 3
    branch_labels: tuple[str, ...] = ("s1", "s2", "s3", "s4")
    geometry = None      # no one-call kernel of its own: the one-call path verifies the solve's branches in one call

    classes: tuple[str, ...] = ("3R-general", "3R-two-parallel", "3R-elbow")
    """The classes of :func:`armkit.ik.geometric.classify.classify` this family answers."""

    def __init__(self, robot: Robot, form: Any, chain_class: Any) -> None:
        from ..geometric.solvers_chain import align

        self.robot = robot
        self.chain_class = chain_class
        # axes parallel within PARALLEL_TOL are made exactly parallel (the ideal chain); its branches are then
        # polished by Newton steps on the robot itself (solve_all, as for the other families' ideal arms)
        size = _size(robot)
        near = _parallel_pairs(form)
        meet = [] if near else [i for i in range(robot.n - 1) if _meet(form, i, size)]
        ideal, dev = align(form, tuple((i, i + 1) for i in meet[:1]), tuple((i, i + 1) for i in near[:1]))
        self.H = np.array(ideal.H, dtype=float, order="C")     # writable copies: one signature of the kernel
        self.P = np.array(ideal.P, dtype=float, order="C")
        self.case = (f"{near[0] + 1} || {near[0] + 2}" if near else f"{meet[0] + 1}, {meet[0] + 2} meet" if meet
                     else "general")
        self.sf = chain_form(robot, exact=dev < 1e-13)

    @classmethod
    def detect(cls, sf: StandardForm | None, robot: Robot) -> Any:
        """The family for an all-revolute arm of :attr:`classes`, else None. Where the tool point lies on the last
        axis (the last joint does not move it) or two parallel axes lie on one line (they turn the arm as one
        joint), a position has a curve of solutions: ``classify`` calls such an arm degenerate (the tool point's
        Jacobian, :data:`~armkit.ik.geometric.classify.POSITION_RANK_TOL`). (A planar 3R has a curve of solutions
        for a position, and three concurrent axes move the point on a sphere: their classes are not among these.)"""
        if not cls._shape(robot):
            return None
        from ..geometric.classify import classify
        from ..geometric.poe import poe

        chain_class = classify(robot)
        if chain_class.degenerate or not cls._takes(chain_class):
            return None
        return cls(robot, poe(robot), chain_class)

    @classmethod
    def _shape(cls, robot: Robot) -> bool:
        """Whether :meth:`detect` classifies the robot at all: :attr:`m_joints` revolute joints."""
        return robot.n == cls.m_joints and not any(robot.chain.prismatic)

    @classmethod
    def _takes(cls, chain_class: Any) -> bool:
        """Whether the family answers a (not degenerate) class: one of :attr:`classes`."""
        return chain_class.name in cls.classes

    def reach_why(self, lateral_out: bool, rho: float, r: float, target: Array | None) -> str:
        return _why(int(rho), self.m)

    def _candidates(self, p0W: Array, Q: Array, LS: NDArray[np.bool_], K: Any) -> int:
        """The solutions of ``p0W = p - p_01`` (least-squares ones flagged in ``LS``) into the rows of ``Q (8, 3)``;
        their count. ``K``: the compiled solvers (None: their Python functions)."""
        from ..geometric import solvers

        if self.case == "1 || 2":
            return _first_two_parallel(self.H, self.P, p0W, Q, LS)
        if self.case == "2, 3 meet":
            return _second_two_meet(self.H, self.P, p0W, Q, LS)
        if self.case == "1, 2 meet":
            meet12 = K._pos_two_intersecting if K is not None else solvers._pos_two_intersecting
            w = np.empty((19, 3))   # its work rows, and the cosines and sines of the angles (unused here)
            return int(meet12(self.H, self.P, False, p0W, Q, LS, w[:3], w[3:11], w[11:]))
        position = K._pos_general if K is not None else solvers._pos_general    # SP5, or SP4-SP3-SP1 (2 ∥ 3)
        return int(position(self.H, self.P, p0W, solvers.SEARCH_N, Q, LS, np.empty((5, 3))))   # its work rows

    buffer = (8, 3)
    """The shape of the candidates' buffer ``Q`` that :meth:`_candidates` fills (rows: candidates)."""

    def _candidates_of(self, target: Array, Q: Array, LS: NDArray[np.bool_], K: Any) -> int:
        """:meth:`_candidates` for one target: a position ``(3,)`` or the position of a pose ``(4, 4)``."""
        p = target[:3, 3] if target.ndim == 2 else target
        return self._candidates(np.ascontiguousarray(p - self.P[0], dtype=float), Q, LS, K)

    def solve(self, target: Array, q0phi: Array) -> Raw:
        """Every branch for position targets ``(B, 3)`` (or the positions of poses ``(B, 4, 4)``; the families of
        a pose, the gimbal's and the prismatic ones', read the whole pose in :meth:`_candidates_of`)."""
        from ..geometric import solvers

        B, m, n = len(target), self.m, self.robot.n
        batch = self._candidates_many(target) if B >= MANY else None
        if batch is not None:                    # a family with a whole-batch form (the SCARA's), many targets
            q, unreachable, found = _assemble(*batch, m, n, q0phi)
        else:
            q, unreachable, found = self._one_by_one(target, q0phi, solvers.kernels() if solvers._use_jit(None)
                                                     else None)
        label = np.broadcast_to(np.array(self.branch_labels, dtype=object), (B, m)).copy()

        def why(i: int) -> str:
            return _why(int(found[i // m]), m)
        return Raw(q, label, unreachable, why, np.full((B, m), "", dtype=object), unreachable.copy())

    def _candidates_many(self, target: Array) -> tuple[Array, NDArray[np.bool_], NDArray[np.int64]] | None:
        """:meth:`_candidates_of` for a whole batch at once, ``(Q (B, C, n), LS (B, C), count (B,))`` with ``C >= m``,
        where a family has such a form (the SCARA's: :class:`.geometric_prismatic.GeometricScara`); None here, and
        :meth:`solve` goes target by target."""
        return None

    def _one_by_one(self, target: Array, q0phi: Array, K: Any) -> tuple[Array, NDArray[np.bool_], NDArray[np.int64]]:
        """:meth:`solve`'s ``(q (B, m, n), unreachable (B, m), found (B,))``, target by target
        (:meth:`_candidates_of`; ``K``: the compiled solvers or None)."""
        B, m, n = len(target), self.m, self.robot.n
        q = np.zeros((B, m, n))
        unreachable = np.zeros((B, m), dtype=bool)
        found = np.zeros(B, dtype=np.int64)
        Qp = np.zeros(self.buffer)
        LSp = np.zeros(self.buffer[0], dtype=np.bool_)
        for b in range(B):
            c = self._candidates_of(target[b], Qp, LSp, K)
            exact = np.flatnonzero(~LSp[:c])[:m]  # a root of q1 may give a least-squares rest while another solves
            if len(exact):
                k = len(exact)
                q[b, :k] = Qp[exact, :n]
                found[b] = k
                q[b, k:] = Qp[exact[0], :n]      # padding, marked unreachable below
                unreachable[b, k:] = True
            else:                                # out of reach: the least-squares candidates, or the start
                k = min(c, m)
                q[b] = Qp[0, :n] if k else q0phi[b]
                q[b, :k] = Qp[:k, :n]
                unreachable[b] = True
        return q, unreachable, found


def has_batch_form(solver: object) -> bool:
    """Whether ``solver``'s family solves a whole batch at once: its class overrides
    :meth:`Geometric3R._candidates_many` (the SCARA's)."""
    form = getattr(type(solver), "_candidates_many", None)
    return form is not None and form is not Geometric3R._candidates_many


MANY = 8
"""From this many targets :meth:`Geometric3R.solve` takes a family's whole-batch form (``_candidates_many``, the
SCARA's) instead of its target-by-target one: the batch form costs ~0.3 ms of NumPy calls whatever the count, more
than the loop below ~8 targets (cobra600, this project's 2-core machine: 0.31 ms against 0.33 at 8 targets)."""


def _assemble(Q: Array, LS: NDArray[np.bool_], count: NDArray[np.int64], m: int, n: int, q0phi: Array
              ) -> tuple[Array, NDArray[np.bool_], NDArray[np.int64]]:
    """What :meth:`Geometric3R._one_by_one` makes of each target's candidates, for a whole batch at once: the
    candidates ``Q (B, C, n)`` (``C >= m``; the first ``count (B,)`` rows hold), least-squares flags ``LS (B, C)``
    -> ``(q (B, m, n), unreachable (B, m), found (B,))``: the exact candidates first in their order, padded with
    the first of them (marked unreachable); where none is exact, the candidates (all unreachable), padded with
    the first, or the start ``q0phi (B, n)`` where there is none."""
    B, C = LS.shape
    exact = (np.arange(C) < count[:, None]) & ~LS
    nex = np.minimum(exact.sum(axis=1), m)
    order = np.argsort(~exact, axis=1, kind="stable")[:, :m]      # the exact ones first, in their order
    j = np.arange(m)[None, :]
    padded_exact = np.where(j < nex[:, None], order, order[:, :1])
    padded_rest = np.where(j < np.minimum(count, m)[:, None], j, 0)
    pick = np.where((nex > 0)[:, None], padded_exact, padded_rest)
    q = Q[np.arange(B)[:, None], pick, :n]
    none = count == 0
    if none.any():
        q[none] = q0phi[none][:, None, :n]
    unreachable = j >= nex[:, None]
    return q, unreachable, nex.astype(np.int64)


def _first_two_parallel(H: Array, P: Array, p0W: Array, Q: Array, LS: NDArray[np.bool_]) -> int:
    """The positions of a 3R chain whose axes 1 and 2 are parallel, ``p0W = rot(h1, q1) (p_12 + rot(h2, q2)
    (p_23 + rot(h3, q3) p_3T))``: turning about axes 1 and 2 keeps the component along them, so
    ``h1 · p0W = h1 · (p_12 + p_23 + rot(h3, q3) p_3T)`` fixes q3 (SP4); then ``|p_12 + rot(h2, q2) w| = |p0W|``
    fixes q2 (SP3) and ``rot(h1, q1) u = p0W`` q1 (SP1). Up to 4 candidates into ``Q (8, 3)``, each flagged in
    ``LS`` when a subproblem had only a least-squares answer; returns their count."""
    from ..geometric.subproblems import rot, sp1, sp3, sp4

    h1, h2, h3 = H[0], H[1], H[2]
    t3, n3, ls3 = sp4(h1, P[3], h3, float(h1 @ p0W - h1 @ (P[1] + P[2])))
    reach = float(np.linalg.norm(p0W))
    m = 0
    for i in range(n3):
        w = P[2] + rot(h3, t3[i], P[3])
        t2, n2, ls2 = sp3(w, -P[1], h2, reach)
        for j in range(n2):
            u = P[1] + rot(h2, t2[j], w)
            t1, ls1 = sp1(u, p0W, h1)
            Q[m] = (t1, t2[j], t3[i])
            LS[m] = bool(ls3) or bool(ls2) or bool(ls1)
            m += 1
    return m


def _size(robot: Robot) -> float:
    return max(float(robot.reach), 1e-300)


def _parallel_pairs(form: Any) -> list[int]:
    """The ``i`` (0-based) whose axes ``i`` and ``i + 1`` are parallel within :data:`PARALLEL_TOL`."""
    return [i for i in range(form.n - 1) if np.linalg.norm(np.cross(form.H[i], form.H[i + 1])) < PARALLEL_TOL]


def _meet(form: Any, i: int, size: float) -> bool:
    """Whether axes ``i`` and ``i + 1`` (0-based) of the chain ``form`` meet, within :data:`MEET_TOL` of its size."""
    n = np.cross(form.H[i], form.H[i + 1])
    return bool(abs(float(n @ form.P[i + 1])) < MEET_TOL * size * float(np.linalg.norm(n)))


def _second_two_meet(H: Array, P: Array, p0W: Array, Q: Array, LS: NDArray[np.bool_]) -> int:
    """The positions of a 3R chain whose axes 2 and 3 meet (``p_23 = 0``): ``p0W = rot(h1, q1) p_12 +
    rot(h1, q1) rot(h2, q2) rot(h3, q3) p_3T``, so the tool point's distance from the common point,
    ``|p0W - rot(h1, q1) p_12| = |p_3T|``, fixes q1 (SP3), and ``rot(h2, q2) rot(h3, q3) p_3T = rot(h1, -q1) p0W -
    p_12`` gives q2, q3 (SP2). Up to 4 candidates into ``Q (8, 3)`` (``LS``: a least-squares answer); their count."""
    from ..geometric.subproblems import rot, sp2, sp3

    h1, h2, h3 = H[0], H[1], H[2]
    t1, n1, ls1 = sp3(P[1], p0W, h1, float(np.linalg.norm(P[3])))
    m = 0
    for i in range(n1):
        v = rot(h1, -t1[i], p0W) - P[1]
        a, b, n2, ls2 = sp2(v, P[3], -h2, h3)
        for j in range(n2):
            Q[m] = (t1[i], a[j], b[j])
            LS[m] = bool(ls1) or bool(ls2)
            m += 1
    return m


def across(h: Array) -> Array:
    """A unit vector perpendicular to the unit vector ``h`` (3,)."""
    other = np.eye(3)[int(np.argmin(np.abs(h)))]
    v = np.cross(h, other)
    return v / np.linalg.norm(v)


def three_axes(Rw: Array, H: Array, v: Array) -> list[tuple[float, float, float, bool]]:
    """The angles of three axes through one point with ``rot(H[0], a) rot(H[1], b) rot(H[2], c) = Rw`` (3, 3), as
    ``(a, b, c, ls)`` (up to 2; ``ls``: only a least-squares answer): where axis 3 goes fixes ``a`` and ``b``
    (SP2), and ``c`` turns ``v``, a vector across axis 3 (:func:`across`), onto where it must go (SP1)."""
    from ..geometric.subproblems import rot, sp1, sp2

    h1, h2, h3 = H[0], H[1], H[2]
    ta, tb, count, ls2 = sp2(Rw @ h3, h3, -h1, h2)
    out = []
    for j in range(count):
        w = rot(h2, -tb[j], rot(h1, -ta[j], Rw @ v))
        tc, ls1 = sp1(v, w, h3)
        out.append((float(ta[j]), float(tb[j]), float(tc), bool(ls2) or bool(ls1)))
    return out


class GeometricGimbal(Geometric3R):
    """Both branches of an orientation for three revolute axes through one point (class ``3R-spherical``: a
    camera gimbal, a spherical wrist on its own). The target is a pose: its rotation gives the angles by SP2 and
    SP1 (:func:`three_axes`), and its position must be where that rotation puts the tool (every branch is
    verified by FK; a position elsewhere is unreachable, with the distance in ``position_error``). Axes that only
    nearly meet are solved on the ideal chain and polished on the robot."""

    family = "geometric-gimbal"
    pose_only = True
    target_kind = "pose"
    m = 2
    branch_labels = ("s1", "s2")
    classes = ("3R-spherical",)     # three revolute joints (Geometric3R's detect)

    def __init__(self, robot: Robot, form: Any, chain_class: Any) -> None:
        from ..geometric.solvers_chain import align

        self.robot = robot
        self.chain_class = chain_class
        ideal, dev = align(form, ((0, 1, 2),))
        self.form = ideal
        self.H = np.array(ideal.H, dtype=float)
        self.P = np.array(ideal.P, dtype=float)
        self._across3 = across(self.H[2])
        self.case = "concurrent"
        self.sf = chain_form(robot, exact=dev < 1e-13)

    def _candidates_of(self, target: Array, Q: Array, LS: NDArray[np.bool_], K: Any) -> int:
        """Both branches of one pose ``(4, 4)`` into the rows of ``Q (8, 3)``; their count."""
        found = three_axes(target[:3, :3] @ self.form.R_nT.T, self.H, self._across3)
        for i, (a, b, c, ls) in enumerate(found):
            Q[i] = (a, b, c)
            LS[i] = ls
        return len(found)


class Geometric2R(Geometric3R):
    """Every branch of a position target for a spatial 2R arm (classes ``2R-general`` and ``2R-intersecting``: a
    pan-tilt head, a shoulder with an offset; the planar 2R has a family of its own).

    The tool point is ``p = p_01 + rot(h1, q1) (p_12 + rot(h2, q2) p_2T)``: where the axes meet (``p_12 = 0`` on the
    ideal chain) SP2 gives both angles; otherwise the distance from axis 1's point, ``|p - p_01| = |p_12 + rot(h2,
    q2) p_2T|``, gives q2 (SP3) and SP1 q1. Two joints reach a surface, not every point: a target off it gets the
    least-squares candidates, marked unreachable, with the distance left in ``position_error``.
    """

    family = "geometric-2r"
    m = 2
    m_joints = 2
    branch_labels: tuple[str, ...] = ("s1", "s2")
    classes: tuple[str, ...] = ("2R-general", "2R-intersecting")

    def _candidates(self, p0W: Array, Q: Array, LS: NDArray[np.bool_], K: Any) -> int:
        from ..geometric.subproblems import rot, sp1, sp2, sp3

        h1, h2 = self.H[0], self.H[1]
        P = self.P
        if self.case == "1, 2 meet":
            a, b, n, ls = sp2(p0W, P[2], -h1, h2)      # rot(h1, q1) rot(h2, q2) p_2T = p0W
            for j in range(n):
                Q[j, :2] = (a[j], b[j])
                LS[j] = bool(ls)
            return int(n)
        t2, n2, ls2 = sp3(P[2], -P[1], h2, float(np.linalg.norm(p0W)))
        for j in range(n2):
            t1, ls1 = sp1(P[1] + rot(h2, t2[j], P[2]), p0W, h1)
            Q[j, :2] = (t1, t2[j])
            LS[j] = bool(ls1) or bool(ls2)
        return int(n2)


class Geometric1R(Geometric2R):
    """The one branch of a position target for a single revolute joint (class ``1R``): the tool point turns on a
    circle about the axis, ``p = p_01 + rot(h1, q1) p_1T``, and SP1 gives q1; a target off the circle is reported
    unreachable with the nearest angle."""

    family = "geometric-1r"
    m = 1
    m_joints = 1
    branch_labels = ("s1",)
    classes = ("1R",)

    def _candidates(self, p0W: Array, Q: Array, LS: NDArray[np.bool_], K: Any) -> int:
        from ..geometric.subproblems import sp1

        t, ls = sp1(self.P[1], p0W, self.H[0])
        Q[0, 0] = t
        LS[0] = bool(ls)
        return 1

