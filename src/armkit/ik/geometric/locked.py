"""Arms with more joints than a closed form takes: hold joints at given values, solve the rest (7-joint arms).

Holding joint ``k`` at ``t`` turns it into part of a rigid link: in the product-of-exponentials
form (:mod:`.poe`) its rotation ``rot(h_k, t)`` is pushed through the rest of the chain, which
turns every later axis and offset by it (and the tool rotation ``R_nT``); a held prismatic joint
adds ``t h_k`` to the next offset (:func:`lock`). What is left is a chain of ``n - 1`` joints with
its own geometric class (:func:`~.classify.classify`); when that is a 6R class with a solver in
:mod:`.solvers`, every branch follows in closed form, and the held value goes back in its place.

A 7R arm without a held joint is *swept*: the classifier names the joint whose locking leaves a
closed-form 6R class at every value (the Panda's joint 6, the iiwa's joint 3), and that joint
takes :data:`DEFAULT_SWEEP` values evenly spaced over its limits (both ends included; one turn
for a joint without limits). Each value gives up to 8 branches; the result holds them all,
labelled ``"<joint>=<value>/s<k>"``, and the message of each successful branch names the swept
joint and its value. The arm has infinitely many solutions (a one-parameter family per branch);
the sweep returns the members at those values, each verified by FK of the true model.

:class:`Locked` is a :class:`~armkit.ik.analytic.ClosedFormFamily`, so
:func:`armkit.ik.analytic.solve_all` wraps, verifies, messages and sorts its branches like any
other family's (without the Gauss-Newton touch-up, which would move the held joints: the
subproblem solvers polish on the true chain themselves).

>>> import armkit, numpy as np
>>> panda = armkit.load("panda")
>>> q = np.array([0.3, -0.5, 0.2, -2.0, 0.4, 1.6, 0.7])
>>> res = armkit.ik_all(panda, armkit.fk(panda, q), fixed={"panda_joint6": 1.6})
>>> bool(res.success.any()), bool(np.all(res.q[..., 5] == 1.6))
(True, True)
>>> bool(np.allclose(armkit.fk(panda, res.q[res.success]), armkit.fk(panda, q), atol=1e-9))
True
"""

from __future__ import annotations

import math
from typing import Any, Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

from ... import _jit_loader
from ..._checks import short_repr
from ..._text import Fielded
from ...errors import IKInputError
from ...kinematics import fk, jacobian
from ...spatial import so3_log
from ..analytic._common import Built
from ...model.robot import Robot
from .poe import POE, poe
from .subproblems import rotm

__all__ = ["lock", "Locked", "held_solver", "sweep_solver", "sweep_values", "DEFAULT_SWEEP", "MAX_SWEEP"]

Array = NDArray[np.float64]

DEFAULT_SWEEP = 32
"""Values of the swept joint of a 7-joint arm (``ik_all(..., sweep=)`` changes it)."""
MAX_SWEEP = 10_000
"""The most values a sweep takes (labels keep 4 decimals: values stay distinct)."""
_CACHE_KEY = "locked_solvers"
_CACHE_MAX = 64


def lock(form: POE, k: int, value: float) -> POE:
    """The chain with joint ``k`` (0-based) held at ``value``: ``n - 1`` joints, the same FK.

    ``lock(form, k, t).fk(np.delete(q, k)) == form.fk(q)`` whenever ``q[k] == t``.

    Parameters
    ----------
    form : POE
        The chain (``H (n, 3)``, ``P (n + 1, 3)``).
    k : int
        The joint to hold, 0-based.
    value : float
        Its value (rad, or a length for a prismatic joint).
    """
    H = np.asarray(form.H, dtype=float)
    P = np.asarray(form.P, dtype=float)
    n = H.shape[0]
    if not 0 <= k < n:
        raise IndexError(f"joint index {k} out of range for a chain of {n} joints")
    pts = np.cumsum(P, axis=0)              # points on axes 1..n (rows 0..n-1), then the tool origin (row n)
    R_nT = np.array(form.R_nT, dtype=float)
    H2 = H.copy()
    if form.prismatic[k]:
        pts[k + 1:] += value * H[k]
    else:
        Rk = rotm(H[k], float(value))
        H2[k + 1:] = H[k + 1:] @ Rk.T
        pts[k + 1:] = pts[k] + (pts[k + 1:] - pts[k]) @ Rk.T
        R_nT = Rk @ R_nT
    keep = np.array([m for m in range(n + 1) if m != k])
    pts2 = pts[keep]
    P2 = np.vstack([pts2[:1], np.diff(pts2, axis=0)])
    return POE(np.ascontiguousarray(np.delete(H2, k, axis=0)), np.ascontiguousarray(P2), R_nT,
               np.delete(np.asarray(form.prismatic, dtype=bool), k))


def sweep_values(robot: Robot, k: int, count: int = DEFAULT_SWEEP) -> Array:
    """``count`` values of joint ``k`` (0-based) evenly spaced over its limits, both ends included.

    A revolute joint without finite limits (or whose range is a turn or more) takes ``count`` values a
    ``2 pi / count`` apart over one turn, from its lower limit (or -pi); a prismatic one without finite limits
    takes them over plus and minus the arm's reach.
    """
    lo, hi = float(robot.lower[k]), float(robot.upper[k])
    if robot.prismatic[k]:        # a slide (a rail): over its stroke, or as far as the arm reaches either way
        lo = lo if math.isfinite(lo) else -float(robot.reach)
        hi = hi if math.isfinite(hi) else float(robot.reach)
        return np.array([0.5 * (lo + hi)]) if count == 1 else np.linspace(lo, hi, count)
    if not (math.isfinite(lo) and math.isfinite(hi)) or hi - lo >= 2.0 * math.pi:
        start = lo if math.isfinite(lo) else -math.pi
        return np.asarray(start + 2.0 * math.pi * np.arange(count) / count, dtype=float)
    if count == 1:
        return np.array([0.5 * (lo + hi)])
    return np.linspace(lo, hi, count)


def _solver_for(cls: Any) -> tuple[str, int] | None:
    """``(solver, branches)`` of :mod:`.solvers` for a 6R class, or None."""
    from ..analytic.geometric import _CLASSES

    if cls.degenerate or cls.n != 6:
        return None
    return _CLASSES.get(cls.name.replace("-base", ""))


class Locked(Built):
    """Every branch of an arm with some joints held (``fixed``) and at most one swept over given values.

    Parameters
    ----------
    robot : Robot
    held : mapping of int to float
        0-based joint index -> value, held in every branch.
    swept : (int, ndarray of shape (V,)) or None
        A joint (0-based) and its values; each value gives one group of branches.
    """

    family: str
    branch_labels: tuple[str, ...]
    m: int
    sf: Any
    pose_only = True
    target_kind = "pose"

    def __init__(self, robot: Robot, held: Mapping[int, float], swept: tuple[int, Array] | None) -> None:
        from ..analytic import closed_form
        from ..analytic._common import StandardForm
        from . import solvers
        from .classify import classify

        self.robot = robot
        self.held = {int(k): float(v) for k, v in held.items()}
        self.swept = swept
        base = poe(robot)
        for k in sorted(self.held, reverse=True):
            base = lock(base, k, self.held[k])
        free = [j for j in range(robot.n) if j not in self.held]
        self.values: Array = np.array([math.nan]) if swept is None else np.asarray(swept[1], dtype=float)
        if swept is None:
            forms = [base]
        else:
            sweep_k = free.index(swept[0])
            forms = [lock(base, sweep_k, float(v)) for v in self.values]
        # the class: of the chain left at the held values; for a sweep, the classifier's class of the locked joint
        # (it holds at every value), checked on the first value's chain
        cls = classify(forms[0])
        if swept is not None:
            full = classify(robot)
            if full.locked == swept[0] + 1 and full.locked_class is not None and not self.held:
                cls = _with_name(cls, full.locked_class, full.inverted)
        self.chain_class = cls
        found = _solver_for(cls)
        if found is None:
            raise LookupError(cls)
        self.solver, self.m6 = found
        self.inverted = bool(cls.inverted)
        self.forms = [solvers.reverse(f) if self.inverted else f for f in forms]
        if self.solver == "spherical_wrist":     # which of its cases: the same at every value
            self.solver = solvers._wrist_case(self.forms[0])
        self.preps: list[Any] = []
        self.stack: tuple[Any, ...] | None = None
        if self.solver in solvers._CASES:
            try:                    # the solver's own checks of each chain (e.g. SP5's parallel axes)
                self.preps = [solvers._prepare(f, self.solver) for f in self.forms]
            except ValueError:
                if swept is None:
                    raise LookupError(cls) from None
                self.preps = []
        if self.preps:              # every value's chain stacked for the compiled sweep (solvers._sweep)
            pr = self.preps
            c = np.ascontiguousarray
            self.stack = (solvers._WHICH[pr[0].solve], pr[0].kind, c([x.Hi for x in pr]), c([x.Pi for x in pr]),
                          c([x.RnT for x in pr]), pr[0].prism, c([x.Ht for x in pr]), c([x.Pt for x in pr]),
                          c([solvers.TOL * x.scale for x in pr]))
        # candidates that fail the check only because the target is out of reach are polished (Python Newton
        # steps, ~10 ms) only when the robot's own relations are approximate (a calibrated file)
        self.polish_unreachable = bool(classify(robot).near > 1e-12) if swept is not None else cls.near > 1e-12
        self.free = np.array([j for j in free if swept is None or j != swept[0]], dtype=np.int64)
        self._held_idx = np.array(sorted(self.held), dtype=np.int64)     # the compiled layout's (locked_jit.layout)
        self._held_val = np.array([self.held[k] for k in sorted(self.held)], dtype=float)
        self.V = len(forms)
        self.m = self.V * self.m6
        names = robot.joint_names
        if swept is None:
            self.family = "geometric, " + ", ".join(names[k] for k in sorted(self.held)) + " held"
            self.branch_labels = tuple(f"s{j + 1}" for j in range(self.m6))
        else:
            self.family = f"geometric, sweep {names[swept[0]]}"
            self.branch_labels = tuple(f"{names[swept[0]]}={v:.4f}/s{j + 1}" for v in self.values
                                       for j in range(self.m6))
        self.notes = self._notes()
        self._labels = np.array(self.branch_labels, dtype=object)
        own = closed_form(robot)     # the joint table of solve_all is kept per robot: use the same DH offsets
        theta = np.zeros(robot.n) if own is None else np.asarray(own.sf.theta, dtype=float)
        eye = np.eye(4)
        z = np.zeros(robot.n)
        self.sf = StandardForm(theta, z, z, z, eye, eye, eye, eye, float(robot.reach), exact=True)

    def _notes(self) -> NDArray[np.object_]:
        """Each branch's note: the held joints and values, and for a sweep the value of this branch; sentences that
        keep their templates and fields (shown in the user's language)."""
        names = self.robot.joint_names
        held = Fielded.of("{joints} held at {values}", joints=", ".join(names[k] for k in sorted(self.held)),
                          values=", ".join(f"{self.held[k]:.6g}" for k in sorted(self.held)))
        out = np.empty(self.m, dtype=object)
        if self.swept is None:
            out[...] = held   # the sentence itself in every cell (np.full would make it a plain str)
            return out
        k = self.swept[0]
        lo, hi = float(self.values[0]), float(self.values[-1])
        for v in range(self.V):
            text = Fielded.of("{joint} swept over {count} values from {lo} to {hi}: this branch holds it at {value} "
                              "({index} of {count})", joint=names[k], count=self.V, lo=f"{lo:.4f}", hi=f"{hi:.4f}",
                              value=f"{self.values[v]:.6g}", index=v + 1)
            out[v * self.m6:(v + 1) * self.m6] = Fielded.of("{note}, {held}", note=text, held=held) if self.held \
                else text
        return out

    def _candidates(self, R: Array, p: Array, ref: Array, target: Array, q0: Array
                    ) -> tuple[Array, NDArray[np.int64], NDArray[np.int64]]:
        """Every value's solutions for every target: ``Q (V, B, MAXSOL, 6)`` (the reduced chain's joints, in
        the order of :attr:`forms`), ``good (V, B)`` (solutions that pass the check come first) and
        ``cand (V, B)`` (else: out-of-reach candidates, least squares)."""
        from . import solvers

        V, B, M = self.V, len(R), solvers.MAXSOL
        Q = np.zeros((V, B, M, 6))
        good = np.zeros((V, B), dtype=np.int64)
        cand = np.zeros((V, B), dtype=np.int64)
        K = solvers.kernels() if self.stack is not None and solvers._use_jit(None) else None
        if K is not None and not self.polish_unreachable:
            LS = np.zeros((V, B, M), dtype=np.bool_)
            SG = np.zeros((V, B, M), dtype=np.bool_)
            ST = np.zeros((V, B, M), dtype=np.int64)
            NF = np.zeros((V, B), dtype=np.int64)
            assert self.stack is not None
            which, kind, Hi, Pi, RnT, prism, Ht, Pt, tol_p = self.stack
            K._sweep(which, kind, Hi, Pi, RnT, prism, Ht, Pt, R, p, ref, solvers.SEARCH_N, tol_p, solvers.TOL,
                     Q, LS, SG, ST, good, NF)
            cand[:] = NF
            # candidates that failed the check while the target is in reach (a value where the ideal chain is
            # only nearly the true one): Newton steps on the full arm, all of them in one batch
            lj = _layout_kernels()
            if lj is None or lj.near_count(LS, good, NF):
                idx = np.arange(M)
                near = ~LS & (idx >= good[..., None]) & (idx < (good + NF)[..., None])
                if near.any():
                    self._polish_near(Q, good, near, target, q0)
            return Q, good, cand
        for v in range(V):            # without the compiled kernels: the solvers one target at a time
            for b in range(B):
                try:
                    sol = solvers._run(self.solver, self.forms[v], R[b], p[b], ref[b], None) if self.preps else \
                        solvers.solve_batch(self.solver, self.forms[v], R[b:b + 1], p[b:b + 1], ref[b:b + 1])[0]
                except ValueError:    # the class's solver does not take this value's chain (a special value)
                    continue
                c = min(len(sol.q), M)
                Q[v, b, :c] = sol.q[:c]
                good[v, b], cand[v, b] = (c, 0) if not sol.ls.any() else (0, c)
        return Q, good, cand

    def _full(self, v: NDArray[np.int64], qr: Array, q0: Array) -> Array:
        """Full configurations ``(K, n)`` from reduced ones ``qr (K, 6)`` (order of :attr:`forms`) of values ``v``."""
        q = q0.copy()
        q[:, self.free] = qr[:, ::-1] if self.inverted else qr
        for k, x in self.held.items():
            q[:, k] = x
        if self.swept is not None:
            q[:, self.swept[0]] = self.values[v]
        return q

    def _polish_near(self, Q: Array, good: NDArray[np.int64], near: NDArray[np.bool_], target: Array,
                     q0: Array) -> None:
        """Newton steps on the free joints of the full arm (its compiled FK and Jacobian) for the candidates
        ``near (V, B, M)``; those that then pass the solvers' check join the good solutions in ``Q`` (in place)."""
        from . import solvers

        v, b, i = np.nonzero(near)
        q = self._full(v, Q[v, b, i], q0[b])
        tgt = target[b]
        free = self.free
        for step in range(4):      # Newton converges quadratically from ~1e-9: two or three steps
            T = fk(self.robot, q)
            E = tgt[:, :3, :3] @ np.swapaxes(T[:, :3, :3], -1, -2)
            if step == 0 and np.abs(E - np.eye(3)).max() > 1e-3:
                w = so3_log(E)     # far off (rare): the exact rotation vector
            else:                  # small rotation: its vector from the skew part (first order is enough here)
                w = 0.5 * np.stack([E[:, 2, 1] - E[:, 1, 2], E[:, 0, 2] - E[:, 2, 0], E[:, 1, 0] - E[:, 0, 1]], axis=-1)
            e = np.concatenate([tgt[:, :3, 3] - T[:, :3, 3], w], axis=-1)
            if step and np.abs(e).max() < 1e-14 * max(self.sf.scale, 1.0):
                break
            J = jacobian(self.robot, q)[:, :, free]
            try:
                dq = np.linalg.solve(J, e[..., None])[..., 0] if J.shape[-1] == 6 else None
            except np.linalg.LinAlgError:
                dq = None
            if dq is None or not np.all(np.isfinite(dq)):
                dq = np.einsum("kij,kj->ki", np.linalg.pinv(J, rcond=1e-10), e)
            q[:, free] += dq
        T = fk(self.robot, q)
        dp = np.linalg.norm(T[:, :3, 3] - tgt[:, :3, 3], axis=-1)
        dr = np.linalg.norm(T[:, :3, :3] - tgt[:, :3, :3], axis=(-2, -1)) / math.sqrt(2.0)
        assert self.stack is not None
        ok = (dp <= self.stack[8][v]) & (dr <= solvers.TOL)
        qr = q[:, free][:, ::-1] if self.inverted else q[:, free]
        qr = np.where(self.forms[0].prismatic, qr, (qr + math.pi) % (2 * math.pi) - math.pi)
        for j in np.flatnonzero(ok):
            vj, bj = v[j], b[j]
            g = int(good[vj, bj])
            d = np.abs(Q[vj, bj, :g] - qr[j])
            d = np.where(self.forms[0].prismatic, d, np.minimum(d, 2 * math.pi - d))
            if g < Q.shape[2] and not (g and (d.max(axis=-1) < 1e-8).any()):
                Q[vj, bj, g] = qr[j]
                good[vj, bj] = g + 1

    def solve(self, target: Array, q0phi: Array) -> Any:
        """Every branch for pose targets ``(B, 4, 4)``; ``q0phi`` ``(B, n)`` is ``q0`` plus ``sf.theta``."""
        from ..analytic._common import Raw

        B, m, m6, V = len(target), self.m, self.m6, self.V
        theta = self.sf.theta
        q0 = q0phi - theta
        R, p = target[:, :3, :3], target[:, :3, 3]
        ref = q0[:, self.free]
        if self.inverted:
            R = np.swapaxes(R, 1, 2)
            p = -np.einsum("bij,bj->bi", R, p)
            ref = ref[:, ::-1]
        R, p, ref = (np.ascontiguousarray(a, dtype=float) for a in (R, p, ref))
        Q, good, cand = self._candidates(R, p, ref, target, q0)
        lj = _layout_kernels()
        if lj is not None:      # the layout below in one compiled call (the same values)
            q = np.empty((B, m, self.robot.n))
            unreachable = np.empty((B, m), dtype=np.bool_)
            found = np.empty((B, V), dtype=np.int64)
            lj.layout(Q, good, cand, m6, self.inverted, self.free, self._held_idx, self._held_val,
                      -1 if self.swept is None else self.swept[0], self.values, q0phi, theta, q, unreachable, found)
            label = np.repeat(self._labels[None], B, axis=0)    # (B, m), writable (np.broadcast_to + copy: ~2x slower)
            note = np.repeat(self.notes[None], B, axis=0)
            return Raw(q, label, unreachable, self._why(found), note, unreachable.copy())
        Q = np.swapaxes(Q[:, :, :m6], 0, 1)              # (B, V, m6, 6)
        if self.inverted:
            Q = Q[..., ::-1]
        good, cand = good.T, cand.T                      # (B, V)
        count = np.minimum(np.maximum(good, cand), m6)
        idx = np.arange(m6)
        sol = np.where((idx < count[..., None])[..., None], Q, np.where((count > 0)[..., None, None], Q[:, :, :1],
                                                                      q0[:, None, None, self.free]))
        q = np.repeat(q0[:, None, :], m, axis=1)
        q[:, :, self.free] = sol.reshape(B, m, -1)
        for k, x in self.held.items():
            q[:, :, k] = x
        if self.swept is not None:
            q[:, :, self.swept[0]] = np.repeat(self.values, m6)[None, :]
        unreachable = ~(idx < np.minimum(good, m6)[..., None]).reshape(B, m)
        label = np.repeat(self._labels[None], B, axis=0)    # (B, m), writable (np.broadcast_to + copy: ~2x slower)
        note = np.repeat(self.notes[None], B, axis=0)
        return Raw(q + theta, label, unreachable, self._why(np.minimum(good, m6)), note, unreachable.copy())

    def _why(self, found: NDArray[np.int64]) -> Any:
        """``why(i)`` of :class:`~armkit.ik.analytic._common.Raw`: ``found (B, V)`` solutions per target and value."""
        names = self.robot.joint_names
        m6, m, V = self.m6, self.m, self.V
        held = ", ".join(f"{names[k]} = {x:.6g}" for k, x in sorted(self.held.items()))
        memo: dict[tuple[int, int], str] = {}

        def why(i: int) -> str:
            b, j = divmod(i, m)
            v = j // m6
            text = memo.get((b, v))
            if text is not None:
                return text
            # sentences that keep their templates and fields (rendered in the user's language)
            if self.swept is None:
                where = Fielded.of("with {held}", held=held)
            elif held:
                where = Fielded.of("with {joint} = {value} and {held}", joint=names[self.swept[0]],
                                   value=f"{self.values[v]:.6g}", held=held)
            else:
                where = Fielded.of("with {joint} = {value}", joint=names[self.swept[0]], value=f"{self.values[v]:.6g}")
            c = int(found[b, v])
            if c == 1:
                text = Fielded.of("{where} this target has 1 solution; the class allows up to {m}, and this branch "
                                  "is not one of them.", where=where, m=m6)
            elif c:
                text = Fielded.of("{where} this target has {count} solutions; the class allows up to {m}, and this "
                                  "branch is not one of them.", where=where, count=c, m=m6)
            elif self.swept is not None and found[b].any():
                text = Fielded.of("{where} no configuration reaches the target (other values of the sweep do).",
                                  where=where)
            elif V > 1:
                text = Fielded.of("{where} no configuration reaches the target (nor at any of the {count} swept "
                                  "values).", where=where, count=V)
            else:
                text = Fielded.of("{where} no configuration reaches the target (the closest is shown).", where=where)
            memo[(b, v)] = text
            return text
        return why


def _layout_kernels() -> Any:
    """:mod:`.locked_jit` while the Numba back end serves, else None (the NumPy layout of :meth:`Locked.solve`)."""
    return _jit_loader.kernels("ik.geometric.locked_jit")


def _with_name(cls: Any, name: str, inverted: bool) -> Any:
    from dataclasses import replace

    return replace(cls, name=name, inverted=inverted)


def _cached(robot: Robot, key: tuple, make: Any) -> Any:
    store = robot.cache.setdefault(_CACHE_KEY, {})
    hit = store.get(key)
    if hit is None:
        if len(store) >= _CACHE_MAX:
            store.clear()
        hit = store[key] = make()
    return hit


def held_solver(robot: Robot, held: Mapping[int, float]) -> Locked:
    """The solver of ``robot`` with the joints ``held`` (0-based index -> value) fixed.

    Raises
    ------
    LookupError
        With the class (:class:`~.classify.ChainClass`) of the chain left when it has no solver here
        (not 6 joints, or no closed form / 1-D search for its class).
    """
    key = ("held",) + tuple(sorted((int(k), float(v)) for k, v in held.items()))
    return _cached(robot, key, lambda: Locked(robot, held, None))  # type: ignore[no-any-return]


def sweep_solver(robot: Robot, count: int = DEFAULT_SWEEP, joint: int | None = None) -> Locked | None:
    """The sweep solver of a 7-joint arm: its lockable joint (the classifier's, or ``joint``, 0-based) over
    ``count`` values of its range; None when locking leaves no closed form."""
    from .classify import classify

    def make() -> Locked | None:
        k = joint
        if k is None:
            cls = classify(robot)
            if cls.locked is None or not cls.solver.startswith("sweep"):
                return None
            k = cls.locked - 1
        try:
            return Locked(robot, {}, (k, sweep_values(robot, k, count)))
        except LookupError:
            return None
    return _cached(robot, ("sweep", joint, int(count)), make)  # type: ignore[no-any-return]


def joint_indices(robot: Robot, names: Sequence[str]) -> list[int]:
    """0-based indices of joints given by name; an unknown name raises KeyError listing the valid ones."""
    out = []
    for nm in names:
        if nm not in robot.joint_names:
            raise KeyError(nm)
        out.append(robot.joint_names.index(nm))
    return out


def resolve(robot: Robot, fixed: Any, sweep: Any, position_only: bool) -> Any:
    """The solver ``ik_all(robot, ..., fixed=, sweep=)`` uses, or None (no ``fixed``/``sweep``, not a sweepable arm).

    For a position target with ``fixed``: the joints left in closed form for a position
    (:class:`armkit.ik.analytic.held.Held`, :func:`held_position`); otherwise a :class:`Locked`.

    Raises :class:`~armkit.errors.IKInputError` for bad ``fixed``/``sweep`` values, a position target of a sweep,
    or a chain that holding the joints does not make solvable; the message says which and why.
    """
    from .classify import classify, described

    if fixed is not None and not isinstance(fixed, Mapping):
        raise IKInputError.of("fixed must be a dict of joint name -> value (rad, or a length for a prismatic joint), "
                              "e.g. {{{joint!r}: 0.5}}; got {got}", joint=robot.joint_names[0],
                              got=short_repr(fixed))
    if fixed is not None and len(fixed) == 0:
        fixed = None
    if sweep is not None:
        if isinstance(sweep, bool) or not isinstance(sweep, (int, np.integer)) or not 1 <= sweep <= MAX_SWEEP:
            raise IKInputError.of("sweep must be an integer between 1 and {MAX_SWEEP:,} (values of the swept joint), "
                                  "got {got}", MAX_SWEEP=MAX_SWEEP, got=short_repr(sweep))
        if fixed is not None:
            raise IKInputError.of("give fixed= (hold joints at your values) or sweep= (the number of values of the "
                                  "swept joint), not both")
    if fixed is None and sweep is None and robot.n != 7:
        return None
    if position_only and fixed is not None:   # a position: the joints left (1 to 3) by a position closed form
        return held_position(robot, fixed)
    if position_only:
        raise IKInputError.of("the sweep of a 7-joint arm needs a pose target (4, 4): the closed form of the joints "
                              "left solves a full pose; for a position alone hold joints with fixed= (1 to 3 left) "
                              "or use armkit.ik (method='lm')")
    if fixed is None:
        solver = sweep_solver(robot, DEFAULT_SWEEP if sweep is None else int(sweep))
        if solver is None:
            if sweep is None:
                return None
            cls = classify(robot)
            raise IKInputError.of("sweep= is for 7-joint arms with a joint whose locking leaves a closed form; robot "
                                  "{robot!r} is {chain}. Hold joints with fixed= instead, or use armkit.ik "
                                  "(method='lm')", robot=robot.name, chain=described(cls))
        return solver
    held = held_values(robot, fixed)
    try:
        return held_solver(robot, held)
    except LookupError as exc:
        cls = exc.args[0]
        left = robot.n - len(held)
        need = " (the closed forms here are for 6 joints)" if left != 6 else ""
        raise IKInputError.of("holding {names} leaves a {left}-joint chain{need} without a closed form in armkit: "
                              "{chain}; use armkit.ik (method='lm')",
                              names=', '.join(robot.joint_names[k] for k in sorted(held)), left=left, need=need,
                              chain=described(cls)) from None


def held_values(robot: Robot, fixed: Mapping[str, Any]) -> dict[int, float]:
    """``fixed=`` as ``{0-based joint index: value}``, each name and value checked; raises
    :class:`~armkit.errors.IKInputError` naming the joints or the value at fault."""
    held: dict[int, float] = {}
    for name, value in fixed.items():
        if not isinstance(name, str) or name not in robot.joint_names:
            raise IKInputError.of("fixed: no joint named {name} in robot {robot!r}; the joints are {names}",
                                  name=short_repr(name), robot=robot.name, names=", ".join(robot.joint_names))
        try:
            v = float(value)
        except (TypeError, ValueError):
            raise IKInputError.of("fixed: the value of {name!r} must be a number, got {got}", name=name,
                                  got=short_repr(value)) from None
        if isinstance(value, bool) or np.ndim(value) != 0 or not math.isfinite(v):
            raise IKInputError.of("fixed: the value of {name!r} must be a finite number, got {got}", name=name,
                                  got=short_repr(value))
        held[robot.joint_names.index(name)] = v
    if len(held) >= robot.n:
        raise IKInputError.of("fixed holds every joint of robot {robot!r}; leave some free (use armkit.fk to see where "
                              "the held values put the tool)", robot=robot.name)
    return held


def held_position(robot: Robot, fixed: Mapping[str, Any]) -> Any:
    """The solver of a position target with the joints ``fixed`` (name -> value, already a non-empty mapping)
    held: the joints left, 1 to 3, by a closed form for a position (:func:`armkit.ik.analytic.held.held_solver`).
    Raises :class:`~armkit.errors.IKInputError` when they have none (too many left, or a class without one)."""
    from ..analytic.held import MAX_LEFT, held_solver
    from .classify import classify, described

    held = held_values(robot, fixed)
    try:
        return held_solver(robot, held)
    except LookupError as exc:
        left = robot.n - len(held)
        raise IKInputError.of("holding {names} leaves {left} joints ({chain}) without a closed form for a position "
                              "(a position fixes {most} joints: hold more, or use armkit.ik with method='lm')",
                              names=", ".join(robot.joint_names[k] for k in sorted(held)), left=left, most=MAX_LEFT,
                              chain=described(classify(exc.args[0]))) from None
