r"""Symbolic forward kinematics and geometric Jacobian of an armkit :class:`~armkit.Robot`.

The DH table becomes SymPy matrices:

* joint variables ``q1 .. qn`` (real symbols, radians or length units);
* every non-zero link length or offset becomes a named parameter symbol
  (``a2``, ``d1``; Craig's ``a_{i-1}`` for modified DH) whose numeric value is kept in
  :attr:`Derivation.values`, so that the formulas read like the lecture notes;
* angles that are simple multiples of pi (``alpha = 90 deg``) become exact
  (``pi/2``), so ``cos(alpha)`` is exactly 0; other angles become parameters too.

Simplification never calls ``simplify`` on a whole product (slow for 6 joints). When every
twist and angle offset is an exact multiple of pi (every bundled DH arm), the products are
formed directly in the cumulative angles of the runs of parallel joints (``q2 + q3``), as
exact polynomials reduced by :math:`\sin^2 = 1 - \cos^2` (:mod:`._angle_sums`, no
``trigsimp``: a 6-joint arm in well under a second). Otherwise each entry is expanded, split
into coefficients of the parameter monomials, every coefficient (a pure trigonometric
polynomial in ``q``) goes through ``trigsimp`` (:func:`simplify_entry`). Either way common
factors are pulled out. The simplified results are cached on disk (pickle, keyed by the DH
model and the SymPy version), see :func:`cache_dir`.
"""

from __future__ import annotations

import hashlib
import math
import os
import pickle
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Callable, TypeVar

import numpy as np
import sympy as sp

from ..model.robot import Robot
from ._angle_sums import angle_basis, chain

__all__ = ["Derivation", "derive", "link_transform", "exact_angle", "simplify_entry", "cache_dir", "within_cpu_budget"]

_CACHE_VERSION = 3

_R = TypeVar("_R")


def exact_angle(x: float) -> sp.Expr | None:
    """``x`` (rad) as an exact multiple of pi when it is one with a small denominator, else None.

    >>> exact_angle(1.5707963267948966), exact_angle(-math.pi), exact_angle(0.3)
    (pi/2, -pi, None)
    """
    for den in (1, 2, 3, 4, 6, 12):
        k = x * den / math.pi
        if abs(k - round(k)) < 1e-12:   # typed angles (radians(90)) are exact to ~1e-16; 1e-11 off is geometry
            return sp.Rational(int(round(k)), den) * sp.pi
    return None


def _exact_number(x: float) -> sp.Expr:
    """A rotation-matrix entry as an exact number when it is a common one (0, 1/2, sqrt(2)/2, ...)."""
    for cand in (sp.Integer(0), sp.Integer(1), sp.Rational(1, 2), sp.sqrt(2) / 2, sp.sqrt(3) / 2):
        for sgn in (1, -1):
            if abs(x - sgn * float(cand)) < 1e-12:
                return sgn * cand
    return sp.Float(x, 15)


def _rot(axis: str, t: sp.Expr) -> sp.Matrix:
    c, s = sp.cos(t), sp.sin(t)
    if axis == "z":
        return sp.Matrix([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    return sp.Matrix([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]])


def _trans(axis: str, v: sp.Expr) -> sp.Matrix:
    T = sp.eye(4)
    T["xyz".index(axis), 3] = v
    return T


def link_transform(convention: str, theta: sp.Expr, d: sp.Expr, a: sp.Expr, alpha: sp.Expr) -> sp.Matrix:
    r"""One DH link transform as a SymPy 4x4 matrix.

    ``standard``: :math:`A_i = R_z(\theta_i) T_z(d_i) T_x(a_i) R_x(\alpha_i)`;
    ``modified`` (Craig): :math:`A_i = R_x(\alpha_{i-1}) T_x(a_{i-1}) R_z(\theta_i) T_z(d_i)`,
    where ``a`` and ``alpha`` are then the previous link's.

    >>> q, a = sp.symbols("q1 a1", real=True)
    >>> link_transform("standard", q, 0, a, sp.pi / 2)[:, 3].T
    Matrix([[a1*cos(q1), a1*sin(q1), 0, 1]])
    """
    if convention == "standard":
        return _rot("z", theta) * _trans("z", d) * _trans("x", a) * _rot("x", alpha)
    return _rot("x", alpha) * _trans("x", a) * _rot("z", theta) * _trans("z", d)


def _pose_matrix(T: np.ndarray, prefix: str, params: dict[sp.Symbol, float]) -> sp.Matrix:
    """A constant base/tool pose with exact rotation entries and named translation parameters."""
    M = sp.eye(4)
    for i in range(3):
        for j in range(3):
            M[i, j] = _exact_number(float(T[i, j]))
        v = float(T[i, 3])
        if v != 0.0:
            s = sp.Symbol(f"{prefix}_{'xyz'[i]}", real=True)
            params[s] = v
            M[i, 3] = s
    return M


def simplify_entry(e: sp.Expr, params: tuple[sp.Symbol, ...] = ()) -> sp.Expr:
    """Simplify one FK/Jacobian entry: trigsimp the coefficient of every parameter monomial.

    The coefficients are trigonometric polynomials in the joint variables; ``trigsimp``
    folds ``c1 c2 - s1 s2`` into ``cos(q1 + q2)``. Common factors are then pulled out
    (``c1 (a2 c2 + a3 c23)``).
    """
    e = sp.expand(e)
    if e.is_number or e == 0:
        return sp.nsimplify(e) if e.is_Float and abs(float(e)) < 1e-15 else e
    funcs = e.atoms(sp.Function)
    used = [p for p in params if e.has(p) and not any(f.has(p) for f in funcs)]   # angle parameters stay inside
    if used:
        poly = sp.Poly(e, *used)
        terms = [sp.trigsimp(coeff) * sp.Mul(*(p ** k for p, k in zip(used, mon)))
                 for mon, coeff in poly.terms()]
        e = sp.Add(*terms)
    else:
        e = sp.trigsimp(e)
    return sp.factor_terms(e)


@dataclass(frozen=True)
class Derivation:
    """The symbolic kinematics of one robot.

    Attributes
    ----------
    robot_name : str
    convention : {"standard", "modified"}
    q : tuple of sympy.Symbol, length n
        ``q1 .. qn``; the joint names of the robot are in :attr:`joint_names`.
    joint_names : tuple of str
    values : dict
        Parameter symbol -> numeric value (robot length unit or rad).
    links : tuple of sympy.Matrix
        ``A_1 .. A_n`` (each 4x4), simplified.
    base, tool : sympy.Matrix
        Constant 4x4 poses (identity when the robot has none).
    T : sympy.Matrix
        ``base · A_1 ··· A_n · tool``, simplified.
    J : sympy.Matrix
        Geometric Jacobian ``(6, n)``, rows ``(v, omega)`` in the base frame, ``v`` of the tool origin.
    frames : tuple of sympy.Matrix
        Positions and z axes needed for ``J``: ``base · A_1 ··· A_k`` for ``k = 0 .. n`` (not simplified).
    unit : str
    """

    robot_name: str
    convention: str
    q: tuple[sp.Symbol, ...]
    joint_names: tuple[str, ...]
    joint_types: str
    values: dict[sp.Symbol, float]
    links: tuple[sp.Matrix, ...]
    base: sp.Matrix
    tool: sp.Matrix
    T: sp.Matrix
    J: sp.Matrix
    unit: str = "m"
    meta: dict[str, Any] = field(default_factory=dict)

    @property
    def n(self) -> int:
        return len(self.q)

    @property
    def params(self) -> tuple[sp.Symbol, ...]:
        return tuple(self.values)

    def numeric(self, expr: sp.Expr | sp.Matrix) -> Any:
        """``expr`` with every parameter replaced by its value (exact when it is a simple number)."""
        return expr.subs({s: sp.nsimplify(v, rational=True) for s, v in self.values.items()})

    def lambdify(self, what: str = "T") -> Any:
        """A NumPy function of ``q`` (shape ``(n,)``) for ``"T"`` (4x4) or ``"J"`` (6xn), parameters substituted."""
        expr = getattr(self, what).xreplace(self.values)   # symbols by numbers: xreplace, 30-50x faster than subs
        return sp.lambdify([list(self.q)], expr, modules="numpy", cse=True)   # shared subexpressions: 3-4x faster to make


def _robot_key(robot: Robot) -> str:
    h = hashlib.sha256()
    h.update(repr((_CACHE_VERSION, sp.__version__, robot.convention, robot.unit, robot.joint_types)).encode())
    h.update(np.ascontiguousarray(robot.dh_table()).tobytes())
    h.update(np.ascontiguousarray(robot.base).tobytes())
    h.update(np.ascontiguousarray(robot.tool).tobytes())
    return h.hexdigest()[:24]


def cache_dir() -> Path | None:
    """Where simplified derivations are cached: ``$ARMKIT_CACHE_DIR`` or ``~/.cache/armkit/symbolic``.

    Set ``ARMKIT_CACHE_DIR=off`` to disable the cache.
    """
    env = os.environ.get("ARMKIT_CACHE_DIR")
    if env == "off":
        return None
    if env:
        return Path(env) / "symbolic"
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "armkit" / "symbolic"


def _symbols_for(robot: Robot) -> tuple[tuple[sp.Symbol, ...], dict[sp.Symbol, float], list[tuple]]:
    n = robot.n
    q = tuple(sp.Symbol(f"q{i + 1}", real=True) for i in range(n))
    params: dict[sp.Symbol, float] = {}
    rows = []
    modified = robot.convention == "modified"

    def length(name: str, v: float) -> sp.Expr:
        if v == 0.0:
            return sp.Integer(0)
        s = sp.Symbol(name, real=True)
        params[s] = float(v)
        return s

    def angle(name: str, v: float) -> sp.Expr:
        ex = exact_angle(v)
        if ex is not None:
            return ex
        s = sp.Symbol(name, real=True)
        params[s] = float(v)
        return s

    for i, j in enumerate(robot.joints, 1):
        prev = i - 1 if modified else i   # Craig's a_{i-1}, alpha_{i-1}
        a = length(f"a{prev}", j.a)
        alpha = angle(f"alpha{prev}", j.alpha)
        if j.is_prismatic:
            theta = angle(f"theta{i}", j.theta)
            d = q[i - 1] + length(f"d{i}", j.d)
        else:
            theta = q[i - 1] + angle(f"theta{i}", j.theta)
            d = length(f"d{i}", j.d)
        rows.append((theta, d, a, alpha))
    return q, params, rows


SIMPLIFY_BUDGET = 60.0
"""Seconds of CPU time :func:`derive` spends simplifying before it keeps the remaining entries as raw products
(CPU time, not wall time: the same arm gives the same result on a busy machine as on an idle one)."""


class _Timeout(BaseException):
    """Raised by the profiling timer inside sympy: a BaseException, so that no ``except Exception`` of sympy's
    swallows it and lets the entry run on past the budget."""


class _Simplifier:
    """``simplify_entry`` under a time budget: past it (or when one entry overruns it), entries stay raw.

    The budget is this process's CPU time (:func:`time.process_time`), so a loaded machine does not
    change the result. All the work on an entry (expanding it into its memo key, then simplifying it) runs
    under the budget: the deadline is checked before an entry is touched, and a single slow entry is
    interrupted with ``SIGPROF`` (a profiling timer, which counts the same CPU time) where that is available
    (the main thread of a Unix process); elsewhere the budget is checked between entries. Past the deadline an
    entry is returned as given, not even expanded (expanding the raw products of an arm with arbitrary twists
    alone took seconds per entry). The same entry recurs (a Jacobian's rotation rows are entries of T, 6R arms
    repeat whole products), so each result is kept by its expanded input: :func:`simplify_entry` depends on
    nothing else. :meth:`run` puts any other piece of work (the fast path of :func:`derive`) under the same budget.
    """

    def __init__(self, params: tuple[sp.Symbol, ...], budget: float | None):
        import time

        self.params = params
        self.clock = time.process_time
        self.deadline = None if budget is None else self.clock() + budget
        self.skipped = 0
        self.done: dict[sp.Expr, sp.Expr] = {}

    def __call__(self, e: sp.Expr) -> sp.Expr:
        if self.deadline is None:
            return self._work(e)
        found = self.run(lambda: self._work(e))
        if found is None:                 # past the budget: the entry stays raw, as given, and is not remembered
            self.skipped += 1
            return e
        return found

    def run(self, work: Callable[[], _R]) -> _R | None:
        """``work()`` under what is left of the budget; None when the budget runs out first (it is then spent)."""
        if self.deadline is None:
            return work()
        done, value = _timed(work, self.deadline - self.clock())
        if not done:
            self.deadline = self.clock()
        return value

    def _work(self, e: sp.Expr) -> sp.Expr:
        """The simplified ``e``: remembered by its expanded form, computed on the first sight of that form."""
        key = sp.expand(e)
        found = self.done.get(key)
        if found is None:
            found = simplify_entry(key, self.params)
            self.done[key] = found
        return found


REPEAT = 0.05
"""Seconds of CPU time between the profiling timer's later signals, once the budget is spent (see :func:`_timed`)."""


def _timed(work: Callable[[], _R], seconds: float | None) -> tuple[bool, _R | None]:
    """``(True, work())``, or ``(False, None)`` when ``seconds`` of this process's CPU time run out first (none
    left: not started). Interrupted with ``SIGPROF`` (a profiling timer, which counts the same CPU time) where that
    is available (the main thread of a Unix process); elsewhere ``work`` runs to its end.

    The timer goes on signalling every :data:`REPEAT` seconds once the budget is spent: a signal that arrives while
    Python runs a garbage collector's callback or a ``__del__`` has its exception printed and swallowed there (seen
    once under load: the derivation then ran on to its end, past its budget), and the next one stops the work.
    The handler raises only while the work runs (``armed``): the timer is stopped as the first step of leaving it,
    and a signal still pending then does nothing."""
    if seconds is None:
        return True, work()
    if seconds <= 0:
        return False, None
    import signal
    import threading

    if not hasattr(signal, "setitimer") or threading.current_thread() is not threading.main_thread():
        return True, work()
    armed = [True]

    def _alarm(signum: int, frame: Any) -> None:
        if armed[0]:
            raise _Timeout

    old = signal.signal(signal.SIGPROF, _alarm)
    try:
        try:
            signal.setitimer(signal.ITIMER_PROF, seconds, REPEAT)
            return True, work()
        finally:           # a signal here (before the timer stops) raises once more: the outer except takes it
            armed[0] = False
            signal.setitimer(signal.ITIMER_PROF, 0)
    except _Timeout:
        return False, None
    finally:
        signal.signal(signal.SIGPROF, old)


def within_cpu_budget(work: Callable[[], _R], seconds: float | None) -> _R | None:
    """``work()`` within ``seconds`` of this process's CPU time (None: no bound), or None when it runs out first:
    interrupted by a profiling timer where the platform has one (the main thread of a Unix process), otherwise
    ``work`` runs to its end. The bound :func:`derive` puts on its simplification, for other symbolic work.

    >>> within_cpu_budget(lambda: 6 * 7, 1.0)
    42
    """
    return _timed(work, seconds)[1]


def _fast_chain(robot: Robot, q: tuple[sp.Symbol, ...], rows: list[tuple], raw: list[sp.Matrix], base: sp.Matrix,
                tool: sp.Matrix, params: tuple[sp.Symbol, ...]) -> tuple[sp.Matrix, sp.Matrix] | None:
    """``T`` and ``J`` in the cumulative angles of the runs of parallel joints (:mod:`._angle_sums`), or None for an
    arm that path does not cover (a twist or an offset that is not an exact multiple of pi, float rotations)."""
    prismatic = [j.is_prismatic for j in robot.joints]
    basis = angle_basis(robot.convention, q, rows, prismatic)
    if basis is None:
        return None
    return chain(robot.convention, raw, base, tool, basis, params, [x for x, p in zip(q, prismatic) if p], prismatic)


def _general_chain(robot: Robot, links: tuple[sp.Matrix, ...], base: sp.Matrix, tool: sp.Matrix,
                   simp: Any) -> tuple[sp.Matrix, sp.Matrix]:
    """``T`` and ``J`` from the link transforms, every entry through ``simp`` (:func:`simplify_entry`, budgeted)."""
    # cumulative frames base·A1···Ak; simplified step by step so that the products stay small
    frames = [base]
    for A in links:
        frames.append((frames[-1] * A).applyfunc(simp))
    T = (frames[-1] * tool).applyfunc(simp)
    p_e = T[:3, 3]
    cols = []
    for i in range(robot.n):
        # joint i+1 moves about/along the z axis of the frame before its motion
        F = frames[i] if robot.convention == "standard" else frames[i + 1]
        z = F[:3, 2]
        p = F[:3, 3]
        if robot.joints[i].is_prismatic:
            col = list(z) + [0, 0, 0]
        else:
            v = z.cross(p_e - p)
            col = list(v) + list(z)
        cols.append([simp(c) for c in col])
    return T, sp.Matrix(6, robot.n, lambda r, c: cols[c][r])


def derive(robot: Robot, simplify: bool = True, cache: bool = True,
           simplify_budget: float | None = SIMPLIFY_BUDGET) -> Derivation:
    """Derive the symbolic link transforms, FK and geometric Jacobian of ``robot``.

    Parameters
    ----------
    robot : Robot
    simplify : bool
        Simplify every entry (in the angle sums of :mod:`._angle_sums` where the arm's twists and offsets are
        exact multiples of pi, else with :func:`simplify_entry`); off gives the raw products.
    cache : bool
        Read/write the on-disk cache (:func:`cache_dir`) for simplified derivations.
    simplify_budget : float or None
        CPU seconds of simplification at most (default :data:`SIMPLIFY_BUDGET`, None: no bound).
        Arms with arbitrary offsets can take sympy very long; past the budget the remaining
        entries stay raw products (still exact), ``meta["note"]`` says so and nothing is cached.

    Returns
    -------
    Derivation

    Examples
    --------
    >>> import armkit
    >>> d = derive(armkit.load("planar2"), cache=False)
    >>> d.T[0, 3], d.T[1, 3]
    (a1*cos(q1) + a2*cos(q1 + q2), a1*sin(q1) + a2*sin(q1 + q2))
    >>> d.J[5, :]
    Matrix([[1, 1]])

    A URDF arm is derived through its exact standard-DH twin (:meth:`Robot.to_dh`): the
    same FK for every ``q``, written as DH rows.
    """
    if not robot.is_dh:
        robot = robot.to_dh()
    where = cache_dir() if (cache and simplify) else None
    path = where / f"{robot.name}-{_robot_key(robot)}.pkl" if where is not None else None
    if path is not None and path.exists():
        try:
            with path.open("rb") as f:
                found = pickle.load(f)
            if isinstance(found, Derivation):
                # unpickling rebuilds -(a + b) as -a - b: pull the common factors out again
                tidy = lambda M: M.applyfunc(sp.factor_terms)  # noqa: E731
                return replace(found, links=tuple(tidy(A) for A in found.links), T=tidy(found.T), J=tidy(found.J))
        except Exception:  # a corrupt or foreign cache file: derive again and overwrite it
            pass
    q, params, rows = _symbols_for(robot)
    base = _pose_matrix(np.asarray(robot.base), "b", params)
    tool = _pose_matrix(np.asarray(robot.tool), "t", params)
    psyms = tuple(params)
    simplifier = _Simplifier(psyms, simplify_budget) if simplify else None
    simp = simplifier if simplifier is not None else (lambda e: e)
    raw = [link_transform(robot.convention, *r) for r in rows]
    links = tuple(A.applyfunc(simp) for A in raw)
    fast = None
    if simplifier is not None:            # the fast path, under the same budget: past it, the entries stay raw
        fast = simplifier.run(lambda: _fast_chain(robot, q, rows, raw, base, tool, psyms))
    if fast is not None:
        T, J = fast
    else:
        T, J = _general_chain(robot, links, base, tool, simp)
    d = Derivation(robot.name, robot.convention, q, robot.joint_names, robot.joint_types, params, links,
                   base, tool, T, J, robot.unit)
    if simplifier is not None and simplifier.skipped:
        d.meta["note"] = (f"simplification stopped after its {simplify_budget:g} s budget: {simplifier.skipped} "
                          "entries are raw (exact, longer) products; derive(..., simplify_budget=None) or "
                          "`armkit derive --budget 0` waits for all")
        path = None   # a partial simplification is not cached
    if path is not None:
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            tmp = path.with_suffix(f".{os.getpid()}.tmp")
            with tmp.open("wb") as f:
                pickle.dump(d, f)
            tmp.replace(path)
        except OSError:  # a read-only home: the cache is an optimisation only
            pass
    return d
