r"""Symbolic singularity analysis: det(J) factored, each factor named and checked numerically.

The determinant is taken of the task rows the arm can move:

* 6 joints, 6 rows: :math:`\det J`;
* a spatial 3-joint arm positioning its tool point (``fighter``): :math:`\det J_v` (3x3);
* a planar arm (only ``vx, vy, wz`` move): the 3x3 (or 2x2) planar Jacobian;
* as many moving rows as joints (a SCARA: ``vx, vy, vz, wz``): :math:`\det J_r` of those rows;
* anything else (redundant or short arms): :math:`\det(J_r J_r^T)` of the moving rows.

Neither a rotation of the reference frame nor the choice of the row set above changes
where the determinant vanishes, so ``J`` is first expressed in the frame of joint 1,
which takes ``q1`` out of most entries; a block-triangular ``J`` (a spherical wrist)
is split into two 3x3 determinants. The determinant is factored by expanding the
trigonometric terms into a polynomial in :math:`c_i, s_i`, factoring, and tidying each
factor again with the c12 short-hand form.

Each factor is then explained by geometry, tested numerically at configurations on its
zero set (found exactly for one-joint factors, by root finding otherwise):

* one joint, and the distance from the wrist point to the previous joint axis is
  extremal there: **stretched** (maximum) or **folded** (minimum) elbow;
* the wrist point lies on the axis of joint 1: **on the yaw axis** (shoulder singularity);
* two joint axes line up (collinear) or become parallel: **wrist** singularity.

SymPy and SciPy are imported here, Matplotlib only inside :func:`plot_manipulability`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from .._extras import require
from .._text import Fielded

require("sympy", "singularity analysis")
import sympy as sp  # noqa: E402 - after the check that names the missing extra

from ..errors import ArgumentError, LimitError
from ..kinematics import fk_frames, jacobian, manipulability
from ..model.robot import Robot
from ..symbolic.derive import SIMPLIFY_BUDGET, within_cpu_budget

__all__ = ["SingularFactor", "SingularityAnalysis", "analyze_singularities", "factor_trig",
           "plot_manipulability"]

ROW_NAMES = ("vx", "vy", "vz", "wx", "wy", "wz")


@dataclass(frozen=True)
class SingularFactor:
    """One factor of the determinant and the singular set where it vanishes.

    Attributes
    ----------
    expr : sympy.Expr
        The factor (parameters as symbols, e.g. ``a2*cos(q2) + a3*cos(q2 + q3)``).
    text : str
        ``expr`` in the c12 short-hand.
    joints : tuple of int
        1-based joints it depends on (empty for a constant factor).
    kind : str
        ``"constant"``, ``"elbow"``, ``"on-axis"``, ``"wrist"`` or ``"other"``.
    description : str
        The singular set in words, e.g. ``"elbow (q3) stretched or folded: sin(q3) = 0"``.
    solutions : tuple of (float, str)
        For one-joint factors: the joint values (rad, or length) in (-pi, pi] with a label
        (``"stretched"``/``"folded"`` for an elbow); empty otherwise.
    samples : ndarray, shape (k, n)
        Configurations on the zero set used for the numeric check.
    manipulability : ndarray, shape (k,)
        Manipulability at ``samples`` (0 up to rounding where the analysis is right).
    power : int
        Multiplicity in the determinant.
    """

    expr: sp.Expr
    text: str
    joints: tuple[int, ...]
    kind: str
    description: str
    solutions: tuple[tuple[float, str], ...] = ()
    samples: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    manipulability: np.ndarray = field(default_factory=lambda: np.zeros(0))
    power: int = 1


@dataclass(frozen=True)
class SingularityAnalysis:
    """Result of :func:`analyze_singularities`.

    Attributes
    ----------
    robot_name : str
    method : str
        ``"det(J)"``, ``"det(J_v)"``, ``"det(J_planar)"`` or ``"det(J J^T)"``.
    rows : tuple of str
        The task rows used (``vx .. wz``).
    determinant : sympy.Expr
        The factored determinant (constant times the product of the factors).
    constant : sympy.Expr
    factors : tuple of SingularFactor
    typical_manipulability : float
        Median manipulability over random configurations, for scale.
    values : dict
        Parameter values (symbol -> number).
    """

    robot_name: str
    method: str
    rows: tuple[str, ...]
    determinant: sp.Expr
    constant: sp.Expr
    factors: tuple[SingularFactor, ...]
    typical_manipulability: float
    values: dict

    @property
    def singular_factors(self) -> tuple[SingularFactor, ...]:
        """The factors that depend on the joints (constant factors cannot vanish)."""
        return tuple(f for f in self.factors if f.kind != "constant")


def factor_trig(expr: sp.Expr, params: Sequence[sp.Symbol] = (), expand_first: bool = True
                ) -> tuple[sp.Expr, list[tuple[sp.Expr, int]]]:
    """Factor a trigonometric polynomial: ``(constant, [(factor, power), ...])``.

    >>> q2, q3, a2, a3 = sp.symbols("q2 q3 a2 a3", real=True)
    >>> e = a2 * a3 * (sp.sin(q2) * sp.cos(q2 + q3) - sp.cos(q2) * sp.sin(q2 + q3))
    >>> factor_trig(e, (a2, a3))
    (-1, [(a2, 1), (a3, 1), (sin(q3), 1)])
    """
    from ..symbolic import simplify_entry

    params = tuple(params)
    const: sp.Expr = sp.Integer(1)
    out: list[tuple[sp.Expr, int]] = []

    def nonconst(fs: list) -> int:
        return sum(1 for fb, _ in fs if fb.free_symbols - set(params))

    def split(e: sp.Expr, power: int, depth: int) -> None:
        nonlocal const
        c, facs = sp.factor_list(e)
        const *= c ** power
        for b, k in facs:
            kp = k * power
            if not (b.free_symbols - set(params)):
                out.append((b, kp)) if b.free_symbols else None
                const *= 1 if b.free_symbols else b ** kp
                continue
            if depth < 4:
                # a product hidden by the angle-sum identities shows once everything is in c_i, s_i
                c2, f2 = sp.factor_list(sp.expand(sp.expand_trig(b)))
                if nonconst(f2) > 1:
                    const *= c2 ** kp
                    for fb, fk in f2:
                        split(simplify_entry(fb, params), fk * kp, depth + 1)
                    continue
                for cand in (simplify_entry(b, params), sp.trigsimp(b)):
                    parts = sp.Mul.make_args(sp.factor_terms(cand))
                    if sum(1 for p_ in parts if p_.free_symbols - set(params)) > 1:
                        split(cand, kp, depth + 1)
                        break
                else:
                    b = simplify_entry(b, params)
                    if b.could_extract_minus_sign():
                        b, const = -b, const * (-1) ** kp
                    out.append((b, kp))
                continue
            out.append((b, kp))

    # small determinants factor best as polynomials in c_i, s_i; a big 6x6 one is tidied first
    e = sp.expand(sp.expand_trig(expr)) if expand_first else simplify_entry(sp.expand(expr), params)
    if e == 0:
        return sp.Integer(0), []
    split(e, 1, 0)
    merged: dict[sp.Expr, int] = {}
    for b, k in out:
        if b != 1:
            merged[b] = merged.get(b, 0) + k
    res = sorted(merged.items(), key=lambda bk: (bool(bk[0].free_symbols - set(params)), sp.default_sort_key(bk[0])))
    return const, res


def _frame1_jacobian(d: Any) -> sp.Matrix:
    from ..symbolic import simplify_entry

    R = (d.base * d.links[0])[:3, :3].T
    simp = lambda e: simplify_entry(e, d.params)  # noqa: E731
    return (R * d.J[:3, :]).applyfunc(simp).col_join((R * d.J[3:, :]).applyfunc(simp))


def _task_matrix(d: Any) -> tuple[sp.Matrix, str, tuple[str, ...], list[sp.Matrix]]:
    n = d.n
    moving = [i for i in range(6) if any(d.J[i, j] != 0 for j in range(n))]
    if set(moving) <= {0, 1, 5}:                      # planar arm: vx, vy, wz
        rows = moving if len(moving) <= n else [0, 1]
        M = d.J.extract(rows, list(range(n)))
        method = "det(J_planar)" if M.shape[0] == n else "det(J J^T)"
        return M, method, tuple(ROW_NAMES[i] for i in rows), [M] if M.shape[0] == n else [M * M.T]
    Jf = _frame1_jacobian(d)
    if n == 6 and len(moving) == 6:
        blocks = [Jf]
        if all(Jf[i, j] == 0 for i in range(3) for j in range(3, 6)):   # spherical wrist at the tool point
            blocks = [Jf[:3, :3], Jf[3:, 3:]]
        return Jf, "det(J)", ROW_NAMES, blocks
    if n == 3 and all(i in moving for i in range(3)):
        M = Jf[:3, :]
        return M, "det(J_v)", ROW_NAMES[:3], [M]
    M = d.J.extract(moving, list(range(n)))
    if len(moving) == n:      # as many rows move as there are joints (a SCARA: vx, vy, vz, wz): det of those rows
        return M, "det(J)", tuple(ROW_NAMES[i] for i in moving), [M]
    return M, "det(J J^T)", tuple(ROW_NAMES[i] for i in moving), [M * M.T]


# ----------------------------------------------------------------------------- geometry of the sets
def _axes(robot: Robot, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Joint axes at ``q``: points ``(n, 3)`` and unit directions ``(n, 3)`` in the world frame."""
    F = fk_frames(robot, q)
    J = jacobian(robot, q)
    z = np.where(robot.prismatic[:, None], J[:3, :].T, J[3:, :].T)
    if robot.convention == "standard":
        pts = F[:-1, :3, 3]
    else:
        pts = np.concatenate([F[1:-1, :3, 3], (F[-1] @ np.linalg.inv(robot.tool))[None, :3, 3]])
    return pts, z


def _wrist_point(robot: Robot, q: np.ndarray) -> np.ndarray:
    """The common point of the last three revolute axes when they meet (spherical wrist), else the tool origin."""
    p_e = fk_frames(robot, q)[-1, :3, 3]
    if robot.n >= 6 and not robot.prismatic[-3:].any():
        pts, z = _axes(robot, q)
        A = np.zeros((3, 3))
        b = np.zeros(3)
        for p, u in zip(pts[-3:], z[-3:]):
            P = np.eye(3) - np.outer(u, u)
            A += P
            b += P @ p
        if np.linalg.matrix_rank(A) == 3:
            c = np.linalg.solve(A, b)
            if all(np.linalg.norm((np.eye(3) - np.outer(u, u)) @ (c - p)) < 1e-9 * max(1.0, robot.reach)
                   for p, u in zip(pts[-3:], z[-3:])):
                return c
    return p_e


def _dist_to_axis(x: np.ndarray, p: np.ndarray, u: np.ndarray) -> float:
    r = x - p
    return float(np.linalg.norm(r - np.dot(r, u) * u))


def _points(robot: Robot, q: np.ndarray, spherical: bool) -> list[tuple[str, np.ndarray]]:
    """Candidate 'wrist points' at ``q``: the spherical-wrist centre or the tool origin, then the axis points."""
    pts, _ = _axes(robot, q)
    first = (Fielded.of("wrist point"), _wrist_point(robot, q)) if spherical else \
        (Fielded.of("tool point"), fk_frames(robot, q)[-1, :3, 3])
    return [first] + [(Fielded.of("point on the axis of joint {k}", k=k + 1), pts[k]) for k in range(2, robot.n)]


def _said(meaning: Fielded, text: str) -> Fielded:
    """A singular set in words and its equation, ``MEANING: TEXT = 0``; the meaning keeps its template and fields."""
    return Fielded.of("{meaning}: {expression} = 0", meaning=meaning, expression=text)


def _rank(text: str) -> Fielded:
    return Fielded.of("the Jacobian loses rank where {expression} = 0", expression=text)


def _classify(robot: Robot, joints: tuple[int, ...], samples: np.ndarray, text: str, rng: np.random.Generator
              ) -> tuple[str, str, list[str]]:
    """Kind and words for a factor, from the geometry at configurations on its zero set."""
    scale = max(robot.reach, 1e-9)
    tol = 1e-7 * scale
    if len(samples) == 0:
        return "other", _rank(text), []
    q_ref = robot.random_q(rng=rng)
    spherical = robot.n >= 6 and not np.allclose(_wrist_point(robot, q_ref), fk_frames(robot, q_ref)[-1, :3, 3]) \
        or (robot.n >= 6 and _is_spherical(robot, q_ref))
    pts0, z0 = _axes(robot, q_ref)
    vertical = abs(abs(z0[0] @ robot.base[:3, 2]) - 1) < 1e-9 and abs(abs(z0[0] @ np.array([0, 0, 1.0])) - 1) < 1e-9

    # 1. a point of the arm on the axis of joint 1, or in the plane of axis 1 and axis 2 (shoulder offset)
    if not (len(joints) == 1 and joints[0] == 1):
        ref = _points(robot, q_ref, spherical)
        for idx in range(len(ref)):
            for test in ("axis", "plane"):
                def holds(q: np.ndarray) -> bool:
                    pts, z = _axes(robot, q)
                    x = _points(robot, q, spherical)[idx][1]
                    if test == "axis":
                        return _dist_to_axis(x, pts[0], z[0]) < tol
                    nrm = np.cross(z[0], z[1]) if robot.n > 1 else np.zeros(3)
                    if np.linalg.norm(nrm) < 1e-9:
                        return False
                    return abs((x - pts[0]) @ nrm / np.linalg.norm(nrm)) < tol
                if all(holds(q) for q in samples) and not holds(q_ref):
                    what = ref[idx][0]
                    axis = Fielded.of("the yaw axis (joint 1)") if vertical else Fielded.of("the axis of joint 1")
                    if test == "axis":
                        return "on-axis", _said(Fielded.of("{point} on {axis}", point=what, axis=axis), text), \
                            [Fielded.of("on axis")] * len(samples)
                    return "on-axis", _said(Fielded.of("{point} in the plane through {axis} parallel to the axis of "
                                                       "joint 2 (shoulder singularity)", point=what, axis=axis), text), \
                        [Fielded.of("shoulder plane")] * len(samples)
    # 2. one elbow joint: the distance from the previous axis to the next point is extremal
    if len(joints) == 1 and not robot.prismatic[joints[0] - 1] and joints[0] >= 2:
        k = joints[0] - 1
        labels: list[str] = []
        for q in samples:
            def dist(qk: float) -> float:
                qq = q.copy()
                qq[k] = qk
                pts, z = _axes(robot, qq)
                if spherical and k < robot.n - 3:
                    x = _wrist_point(robot, qq)
                elif k + 1 < robot.n:
                    x = pts[k + 1]
                else:
                    x = fk_frames(robot, qq)[-1, :3, 3]
                return _dist_to_axis(x, pts[k - 1], z[k - 1])
            h = 1e-3
            d0, dm, dp = dist(q[k]), dist(q[k] - h), dist(q[k] + h)
            curv = dm + dp - 2 * d0
            if abs(curv) < 1e-9 * scale or abs(dp - dm) > 1e-3 * abs(curv):
                labels = []
                break
            labels.append(Fielded.of("stretched") if curv < 0 else Fielded.of("folded"))
        if labels:
            name = robot.joint_names[k]
            return "elbow", _said(Fielded.of("stretched or folded elbow ({joint})", joint=name), text), labels
    # 3. two joint axes that line up or become parallel (only there)
    for q in samples[:1]:
        pts, z = _axes(robot, q)
        for i in range(robot.n):
            for j in range(i + 1, robot.n):
                if robot.prismatic[i] or robot.prismatic[j] or abs(abs(z[i] @ z[j]) - 1) > 1e-9:
                    continue
                if abs(abs(z0[i] @ z0[j]) - 1) < 1e-9:
                    continue          # parallel everywhere (e.g. shoulder and elbow): not this set
                collinear = _dist_to_axis(pts[j], pts[i], z[i]) < tol
                meaning = Fielded.of("axes of joints {i} ({a}) and {j} ({b}) line up" if collinear else
                                     "axes of joints {i} ({a}) and {j} ({b}) become parallel", i=i + 1,
                                     a=robot.joint_names[i], j=j + 1, b=robot.joint_names[j])
                return "wrist", _said(meaning, text), \
                    [Fielded.of("axes collinear") if collinear else Fielded.of("axes parallel")] * len(samples)
    if len(joints) == 1 and robot.prismatic[joints[0] - 1]:
        return "other", _said(Fielded.of("prismatic joint {joint} at zero extension",
                                          joint=robot.joint_names[joints[0] - 1]), text), []
    return "other", _rank(text), []


def _is_spherical(robot: Robot, q: np.ndarray) -> bool:
    pts, z = _axes(robot, q)
    c = _wrist_point(robot, q)
    return all(_dist_to_axis(c, p, u) < 1e-9 * max(1.0, robot.reach) for p, u in zip(pts[-3:], z[-3:]))


def _zero_set(f_num: Any, robot: Robot, joints: tuple[int, ...], rng: np.random.Generator,
              count: int = 4) -> np.ndarray:
    """Up to ``count`` configurations where ``f_num(q) = 0``, by root finding along one joint."""
    from scipy.optimize import brentq

    out: list[np.ndarray] = []
    grid = np.linspace(-math.pi, math.pi, 721)
    for _ in range(40):
        if len(out) >= count:
            break
        base = robot.random_q(rng=rng)
        for k in (j - 1 for j in joints):
            lo, hi = (grid if not robot.prismatic[k] else
                      np.linspace(max(robot.lower[k], -robot.reach), min(robot.upper[k], robot.reach), 721)), None
            Q = np.repeat(base[None], len(lo), 0)
            Q[:, k] = lo
            vals = np.array([f_num(x) for x in Q], dtype=float)
            if np.any(vals == 0):
                i = int(np.flatnonzero(vals == 0)[0])
                out.append(Q[i])
                break
            sgn = np.flatnonzero(np.sign(vals[:-1]) * np.sign(vals[1:]) < 0)
            if len(sgn):
                i = int(sgn[rng.integers(len(sgn))])

                def g(x: float) -> float:
                    qq = base.copy()
                    qq[k] = x
                    return float(f_num(qq))
                root = brentq(g, lo[i], lo[i + 1], xtol=1e-14)
                qq = base.copy()
                qq[k] = root
                out.append(qq)
                break
            del hi
    return np.array(out).reshape(-1, robot.n)


def analyze_singularities(robot: Robot, derivation: Any = None, samples: int = 4,
                          rng: np.random.Generator | int | None = 0,
                          budget: float | None = SIMPLIFY_BUDGET) -> SingularityAnalysis:
    """Factor the Jacobian determinant of ``robot`` and name the singular configurations.

    Parameters
    ----------
    robot : Robot
    derivation : armkit.symbolic.Derivation, optional
        Reused when given (otherwise :func:`armkit.symbolic.derive` is called; cached on disk).
    samples : int
        Configurations per factor used for the numeric check.
    rng : Generator or int, optional
    budget : float or None
        CPU seconds for the determinant and its factoring (default: the derivation's,
        :data:`armkit.symbolic.derive.SIMPLIFY_BUDGET`; None: no bound).
        An arm whose DH offsets and twists are not round numbers (a CAD export such as the SO-101's URDF)
        can keep sympy busy far longer: past the budget, :class:`~armkit.errors.LimitError` says so.

    Returns
    -------
    SingularityAnalysis

    Raises
    ------
    ArmkitError
        For arms with 7 or more joints (``det(J J^T)`` of a 6x7 Jacobian is too large to
        factor symbolically; use the numeric manipulability instead).
    LimitError
        When the determinant is not factored within ``budget`` CPU seconds.

    Examples
    --------
    >>> import armkit
    >>> res = analyze_singularities(armkit.load("planar2"))
    >>> res.determinant
    a1*a2*sin(q2)
    >>> [(round(float(np.degrees(v))), label) for v, label in res.singular_factors[0].solutions]
    [(0, 'stretched'), (180, 'folded')]
    """
    from ..symbolic import derive
    from ..symbolic.export import shorthand

    if robot.n >= 7:
        raise ArgumentError.of("robot {robot!r} has {n} joints: det(J J^T) of a 6x{n} Jacobian is too large to factor "
                               "symbolically; use armkit.manipulability numerically", robot=robot.name, n=robot.n)
    if budget is not None and not budget > 0:
        raise ArgumentError.of("budget must be a number of CPU seconds > 0 (or None: no bound), got {budget}",
                               budget=budget)
    g = np.random.default_rng(rng)
    d = derivation if derivation is not None else derive(robot)

    def factored() -> tuple[str, tuple[str, ...], sp.Expr, list[tuple[sp.Expr, int]]]:
        _, method, rows, blocks = _task_matrix(d)     # J in joint 1's frame, each entry simplified: in the budget too
        const: sp.Expr = sp.Integer(1)
        facs: list[tuple[sp.Expr, int]] = []
        for B in blocks:
            c, f = factor_trig(B.det(method="berkowitz"), d.params, expand_first=B.shape[0] <= 3)
            const *= c
            facs.extend(f)
        return method, rows, const, facs

    done = within_cpu_budget(factored, budget)
    if done is None:
        raise LimitError.of("the determinant of {robot!r} was not factored within {budget:g} s of CPU time (its DH "
                            "offsets and twists are not round numbers{partly}); raise the budget (armkit singular "
                            "--budget, 0: no limit) or use armkit.manipulability numerically", robot=robot.name,
                            budget=budget, partly=Fielded.of(", and its derivation was only partly simplified")
                            if d.meta.get("note") else "")
    method, rows, const, facs = done
    det = const * sp.Mul(*(b ** k for b, k in facs))
    typical = float(np.median(manipulability(robot, robot.random_q(64, rng=g))))
    out = []
    for b, k in facs:
        text = str(shorthand(b, d.q)[0])
        joints = tuple(sorted(d.q.index(s) + 1 for s in b.free_symbols if s in d.q))
        if not joints:
            out.append(SingularFactor(b, text, (), "constant",
                                      Fielded.of("{expression} (a constant of the arm, not zero)", expression=text),
                                      power=k))
            continue
        f_num = sp.lambdify([list(d.q)], b.subs(d.values), modules="numpy")
        sols: list[float] = []
        if len(joints) == 1:
            qk = d.q[joints[0] - 1]
            domain = sp.Interval.Lopen(-sp.pi, sp.pi) if robot.joint_types[joints[0] - 1] == "R" else sp.S.Reals
            try:
                sset = sp.solveset(b.subs(d.values), qk, domain)
                if isinstance(sset, sp.FiniteSet):
                    sols = sorted(float(v) for v in sset)
            except (NotImplementedError, TypeError, ValueError):  # solveset could not: fall back to root finding
                sols = []
        if sols:
            base = robot.random_q(rng=g)
            pts = np.repeat(base[None], len(sols), 0)
            pts[:, joints[0] - 1] = sols
        else:
            pts = _zero_set(f_num, robot, joints, g, samples)
        kind, words, labels = _classify(robot, joints, pts, text, g)
        w = manipulability(robot, pts) if len(pts) else np.zeros(0)
        solutions = tuple((v, labels[i] if i < len(labels) else "") for i, v in enumerate(sols))
        out.append(SingularFactor(b, text, joints, kind, words, solutions, pts, np.asarray(w), k))
    return SingularityAnalysis(robot.name, method, tuple(rows), det, const, tuple(out), typical, dict(d.values))


def plot_manipulability(robot: Robot, out_path: str | Path | None = None, joints: tuple[int, int] | None = None,
                        q_fixed: Sequence[float] | None = None, resolution: int = 181,
                        analysis: SingularityAnalysis | None = None) -> Any:
    """Manipulability over a grid of two joints (degrees on the axes), singular factors as lines.

    Parameters
    ----------
    robot : Robot
        Any arm; meant for 2-3 joints (the other joints stay at ``q_fixed``).
    out_path : path, optional
        Save the figure there (PNG, PDF, SVG); the figure is returned either way.
    joints : (int, int), optional
        1-based joints on the x and y axes; default the last two joints.
    q_fixed : sequence of float, shape (n,), optional
        Values of the other joints (rad); zeros by default.
    resolution : int
        Grid points per axis over [-180, 180] deg.
    analysis : SingularityAnalysis, optional
        Its one- and two-joint factors (in the plotted joints) are drawn as zero contours.

    Returns
    -------
    matplotlib.figure.Figure
    """
    matplotlib = require("matplotlib", "plotting manipulability")
    if out_path is not None:
        matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt


    if robot.n < 2:
        raise ArgumentError.of("robot {robot!r} has one joint; the manipulability map needs two", robot=robot.name)
    i, j = joints if joints is not None else (robot.n - 1, robot.n)
    for k in (i, j):
        if not 1 <= k <= robot.n or robot.prismatic[k - 1]:
            raise ArgumentError.of("joints must be two revolute joints in 1..{n}, got {got}", n=robot.n, got=(i, j))
    base = np.zeros(robot.n) if q_fixed is None else robot.check_q(q_fixed, "q_fixed")
    ax_vals = np.linspace(-math.pi, math.pi, resolution)
    A, B = np.meshgrid(ax_vals, ax_vals)
    Q = np.broadcast_to(base, A.shape + (robot.n,)).copy()
    Q[..., i - 1] = A
    Q[..., j - 1] = B
    W = manipulability(robot, Q)
    fig, ax = plt.subplots(figsize=(6.4, 5.2))
    im = ax.pcolormesh(np.degrees(A), np.degrees(B), W, shading="auto", cmap="viridis")
    from ..locale.fonts import plot_text     # the labels in the pictures' language

    fig.colorbar(im, ax=ax, label=plot_text("manipulability sqrt(det(J J^T))"))
    if analysis is not None:
        from ..symbolic import derive
        d = derive(robot)
        for f in analysis.singular_factors:
            if f.solutions and f.joints[0] in (i, j):      # one-joint factor: straight lines, edges included
                for v, lab in f.solutions:
                    line = ax.axhline if f.joints[0] == j else ax.axvline
                    line(math.degrees(v), color="red", lw=1.2)
                    for sign in ((-1, 1) if abs(abs(v) - math.pi) < 1e-9 else ()):
                        line(sign * 180.0, color="red", lw=2.4)
                continue
            fn = sp.lambdify([list(d.q)], f.expr.subs(d.values), modules="numpy")
            Z = np.broadcast_to(np.asarray(fn(np.moveaxis(Q, -1, 0)), dtype=float), A.shape)
            if np.nanmin(Z) < 0 < np.nanmax(Z):
                cs = ax.contour(np.degrees(A), np.degrees(B), Z, levels=[0.0], colors="red", linewidths=1.2)
                ax.clabel(cs, fmt={0.0: f.text}, fontsize=7)
    names = robot.joint_names
    ax.set_xlabel(f"q{i} ({names[i - 1]}) [deg]")
    ax.set_ylabel(f"q{j} ({names[j - 1]}) [deg]")
    ax.set_title(plot_text("{robot}: manipulability (red: det J = 0)", robot=robot.name))   # in the pictures' language
    fig.tight_layout()
    if out_path is not None:
        fig.savefig(out_path, dpi=120)
    return fig
