"""Which joint axes of a serial chain meet or are parallel, and so which closed form (if any) solves it.

The classes follow the kinematic families of IK-Geo (Elias and Wen, "IK-Geo: Unified robot inverse
kinematics using subproblem decomposition", 2022): a 6R arm with three consecutive axes meeting in a
point (a spherical joint) or three consecutive parallel axes is solved in closed form, one with two
intersecting or two parallel axes by a 1-D search, any other 6R arm by a 2-D search; a 7R arm is
solved by sweeping one joint whose locking leaves a closed-form 6R arm. Arms with fewer joints get
their own small classes (planar, elbow, yaw + three parallel pitches + roll, ...).

Everything here depends only on the geometry of the axes (lines, and directions for prismatic
joints) in the product-of-exponentials form of :mod:`.poe`, never on how the robot file wrote them:
reversing an axis (URDF ``axis="0 0 -1"``) or moving a joint frame along its axis gives the same class.

Two axes are *parallel* when the angle between them is below ``tol`` (radians); two lines *intersect*
when they are not parallel and their distance is below ``tol * scale`` (``scale`` is the size of the
arm, the sum of the offsets ``|P_1| + ... + |P_n|``), or when they are parallel and coincident. A
relation accepted within the tolerance but not exactly is reported in :attr:`ChainClass.near`: a
solver that assumes it exactly then needs a polish step (a few Newton iterations on the true chain).

Only relations that hold in every configuration are reported: consecutive axes keep their relation
(one rigid link joins them); axes ``i`` and ``i + 2`` are called intersecting only when they meet for
every value of joint ``i + 1``.

>>> import armkit
>>> c = classify(armkit.load("puma560"))
>>> c.name, c.solver, c.max_solutions
('6R-spherical-wrist-two-intersecting', 'closed form', 8)
>>> describe(c)
'6R: axes 1-2 meet, axes 4-5-6 meet in a point (spherical wrist), axes 2 ∥ 3; closed form, up to 8 solutions'
"""

from __future__ import annotations

import math

from dataclasses import dataclass, field
from typing import Any, Sequence, Union

import numpy as np
from numpy.typing import NDArray

from ..._text import Fielded
from ...errors import ArgumentError
from ...model.robot import Robot
from .poe import POE, poe
from .subproblems import rotm

__all__ = ["ChainClass", "classify", "describe", "described", "parallel", "intersect", "axis_points", "DEFAULT_TOL"]

Array = NDArray[np.float64]

DEFAULT_TOL = 1e-6
"""Default tolerance: radians for parallel axes, a fraction of the arm's size for distances."""

EXACT = 1e-12
"""Deviations at or below this (relative) count as exact: rounding of the chain's own arithmetic."""

_SWEEP = (-2.3, -0.9, 0.9, 2.3)
"""Generic joint values (symmetric, so that reversing an axis samples the same configurations)."""


# ------------------------------------------------------------------ geometry helpers
def axis_points(P: Array) -> Array:
    """A point on each joint axis, ``(n, 3)``: the cumulative sums of the offsets ``P[0] .. P[k]``."""
    P = np.asarray(P, dtype=float)
    return np.cumsum(P[:-1], axis=0)


def _angle(a: Array, b: Array) -> float:
    """The angle (radians, in [0, pi/2]) between the lines of directions ``a`` and ``b`` (unit vectors)."""
    return float(np.arctan2(np.linalg.norm(np.cross(a, b)), abs(float(np.dot(a, b)))))


def _line_distance(ha: Array, pa: Array, hb: Array, pb: Array, tol: float) -> float:
    """Distance between the lines ``pa + t ha`` and ``pb + s hb`` (unit directions)."""
    d = pb - pa
    c = np.cross(ha, hb)
    s = float(np.linalg.norm(c))
    if s < max(tol, 1e-12):          # parallel: distance of pb from line a
        return float(np.linalg.norm(d - np.dot(d, ha) * ha))
    return abs(float(np.dot(d, c))) / s


def _scale(P: Array) -> float:
    """The arm's size: the sum of the offsets between axes and to the tool (``P[0]``, the base offset, left out)."""
    s = float(np.sum(np.linalg.norm(np.asarray(P, dtype=float)[1:], axis=1)))
    return s if s > 0.0 else 1.0


def parallel(H: Array, i: int, j: int, tol: float = DEFAULT_TOL) -> bool:
    """True when axes ``i`` and ``j`` (0-based rows of ``H``) are parallel within ``tol`` radians (either sense)."""
    H = np.asarray(H, dtype=float)
    return _angle(H[i], H[j]) < tol


def intersect(H: Array, P: Array, i: int, j: int, tol: float = DEFAULT_TOL) -> bool:
    """True when the lines of axes ``i`` and ``j`` (0-based) meet at q = 0: not parallel and closer than
    ``tol * scale``, or parallel and coincident (same tolerance)."""
    H = np.asarray(H, dtype=float)
    pts = axis_points(P)
    return _line_distance(H[i], pts[i], H[j], pts[j], tol) < tol * _scale(P)


def common_point(H: Array, pts: Array, idx: Sequence[int]) -> tuple[Array, float]:
    """The point nearest to all the lines ``idx`` (least squares) and its largest distance to one of them."""
    A = np.zeros((3, 3))
    b = np.zeros(3)
    for k in idx:
        M = np.eye(3) - np.outer(H[k], H[k])
        A += M
        b += M @ pts[k]
    x = np.asarray(np.linalg.lstsq(A, b, rcond=1e-10)[0], dtype=float)
    worst = max(float(np.linalg.norm((np.eye(3) - np.outer(H[k], H[k])) @ (x - pts[k]))) for k in idx)
    return x, worst


# ------------------------------------------------------------------ relations of one geometry
@dataclass
class _Relations:
    """What holds between the axes of one geometry (0-based indices), with the deviations accepted."""

    n: int
    par: list[bool]                 # par[i]: axes i, i+1 parallel
    inter: list[bool]               # inter[i]: axes i, i+1 intersect (both revolute)
    inter2: list[bool]              # inter2[i]: axes i, i+2 intersect for every q_{i+1} (all revolute)
    groups: list[tuple[int, ...]]   # maximal runs of >= 2 consecutive revolute axes through one point
    near: float = 0.0

    def concurrent(self, *idx: int) -> bool:
        """True when the axes ``idx`` (consecutive, 0-based) all pass through one point."""
        s = set(idx)
        return any(s <= set(g) for g in self.groups)

    def runs(self) -> list[tuple[int, ...]]:
        """Maximal runs of consecutive parallel axes (0-based)."""
        out: list[tuple[int, ...]] = []
        i = 0
        while i < self.n - 1:
            if self.par[i]:
                j = i
                while j < self.n - 1 and self.par[j]:
                    j += 1
                out.append(tuple(range(i, j + 1)))
                i = j
            else:
                i += 1
        return out

    def three_parallel(self, a: int) -> bool:
        return self.par[a] and self.par[a + 1]


def _relations(H: Array, P: Array, prismatic: NDArray[np.bool_], tol: float) -> _Relations:
    """Consecutive and every-configuration relations of the chain ``(H, P)`` at q = 0."""
    H = np.asarray(H, dtype=float)
    P = np.asarray(P, dtype=float)
    n = H.shape[0]
    scale = _scale(P)
    pts = axis_points(P)
    rev = [not bool(p) for p in prismatic]
    near = 0.0
    par, inter = [], []
    for i in range(n - 1):
        ang = _angle(H[i], H[i + 1])
        p = ang < tol
        par.append(p)
        if p:
            near = max(near, ang)
        if rev[i] and rev[i + 1]:
            dist = _line_distance(H[i], pts[i], H[i + 1], pts[i + 1], tol) / scale
            ok = dist < tol
            if ok:
                near = max(near, dist)
        else:
            ok = False
        inter.append(ok)
    # maximal concurrent runs of consecutive intersecting axes
    groups: list[tuple[int, ...]] = []
    for a in range(n - 1):
        if not inter[a]:
            continue
        b = a + 1
        best = b
        dev = 0.0
        while b < n:
            if b > a + 1:
                if not inter[b - 1]:
                    break
                _, worst = common_point(H, pts, range(a, b + 1))
                if worst / scale >= tol:
                    break
                dev = max(dev, worst / scale)
            best = b
            b += 1
        g = tuple(range(a, best + 1))
        if not any(set(g) <= set(h) for h in groups):
            groups.append(g)
            near = max(near, dev)
    # axes i, i+2 meeting for every generic value of joint i+1 (sampled at symmetric values; at special
    # values they may be parallel, meeting at infinity, like two lines in one plane)
    inter2 = []
    for i in range(n - 2):
        j, k = i + 1, i + 2
        ok = rev[i] and rev[j] and rev[k]
        dev = 0.0
        if ok:
            for t in _SWEEP:
                Rj = rotm(H[j], t)
                hk = Rj @ H[k]
                pk = pts[j] + Rj @ (pts[k] - pts[j])
                d = _line_distance(H[i], pts[i], hk, pk, tol) / scale
                if d >= tol:
                    ok = False
                    break
                dev = max(dev, d)
        if ok:
            near = max(near, dev)
        inter2.append(ok)
    return _Relations(n, par, inter, inter2, groups, near)


def _merge(rels: Sequence[_Relations]) -> _Relations:
    """What holds in every one of several geometries of the same chain (e.g. several values of a locked joint)."""
    r0 = rels[0]
    par = [all(r.par[i] for r in rels) for i in range(r0.n - 1)]
    inter = [all(r.inter[i] for r in rels) for i in range(r0.n - 1)]
    inter2 = [all(r.inter2[i] for r in rels) for i in range(r0.n - 2)]
    groups: list[tuple[int, ...]] = []
    for g in r0.groups:      # keep the largest sub-runs concurrent in every geometry
        for size in range(len(g), 1, -1):
            for s in range(0, len(g) - size + 1):
                sub = g[s:s + size]
                if all(r.concurrent(*sub) for r in rels) and not any(set(sub) <= set(h) for h in groups):
                    groups.append(sub)
    near = max(r.near for r in rels)
    return _Relations(r0.n, par, inter, inter2, groups, near)


def _sampled_scale(P: Array, prismatic: NDArray[np.bool_]) -> float:
    """The size of the chain at the configurations the rank checks draw: its offsets, and the slides' values
    (drawn like the angles, up to pi) where it has slides, so that a chain of slides alone is not of size 0."""
    return _scale(P) + (math.pi if np.any(prismatic) else 0.0)


def _rank_deficient(H: Array, P: Array, prismatic: NDArray[np.bool_]) -> bool:
    """True when the chain's Jacobian has rank below ``min(n, 6)`` at generic configurations."""
    n = H.shape[0]
    scale = _sampled_scale(P, prismatic)
    rng = np.random.default_rng(20240611)
    best = 0
    for _ in range(3):
        q: Array = np.asarray(rng.uniform(-np.pi, np.pi, size=n), dtype=float)
        R = np.eye(3)
        p = np.asarray(P[0], dtype=float).copy()
        J = np.zeros((6, n))
        for k in range(n):
            w = R @ H[k]
            if prismatic[k]:
                J[3:, k] = w / scale
                p = p + q[k] * w
            else:
                J[:3, k] = w
                J[3:, k] = np.cross(p, w) / scale
                R = R @ rotm(H[k], float(q[k]))
            p = p + R @ P[k + 1]
        s = np.linalg.svd(J, compute_uv=False)
        best = max(best, int(np.sum(s > 1e-9 * max(s[0], 1e-300))))
    return best < min(n, 6)


# ------------------------------------------------------------------ the class
@dataclass(frozen=True)
class ChainClass:
    """The geometric class of a serial chain.

    ``intersecting`` and ``parallel`` hold 1-based joint numbers: runs of consecutive axes through one
    point (``(4, 5, 6)`` is a spherical wrist), pairs ``(i, i + 2)`` that meet for every value of the
    joint between, and runs of consecutive parallel axes. ``name`` is a stable machine name
    (``"6R-three-parallel-two-intersecting"``), ``solver`` one of ``"closed form"``, ``"1-D search"``,
    ``"2-D search"``, ``"sweep joint k"`` or ``"numeric"``; ``max_solutions`` an upper bound on the
    number of IK solutions of the class (per value of the swept joint for a 7R arm; ``None`` where no
    finite bound is claimed). ``inverted``: the closed form applies to the chain read from tool to base.
    ``locked``: for a 7R arm the joint (1-based) whose locking leaves the 6R class ``locked_class``.
    ``near``: the largest deviation (radians, or a fraction of the arm's size) of a relation taken as
    exact; above ~1e-12 the solutions of a solver that assumes it need a polish step.
    """

    n: int
    joint_types: str
    intersecting: tuple[tuple[int, ...], ...]
    parallel: tuple[tuple[int, ...], ...]
    name: str
    solver: str
    max_solutions: int | None
    near: float = 0.0
    inverted: bool = False
    locked: int | None = None
    locked_class: str | None = None
    tol: float = DEFAULT_TOL
    degenerate: bool = False
    alternatives: tuple[str, ...] = field(default=())

    def as_dict(self) -> dict:
        """The class as plain JSON-ready values."""
        return {"name": self.name, "solver": self.solver, "intersecting": [list(g) for g in self.intersecting],
                "parallel": [list(g) for g in self.parallel], "max_solutions": self.max_solutions,
                "near": self.near, "inverted": self.inverted, "locked": self.locked,
                "locked_class": self.locked_class, "joint_types": self.joint_types,
                "alternatives": list(self.alternatives)}


# (name, solver, max_solutions, inverted) of the 6R families, best first
def _six_r_families(r: _Relations) -> list[tuple[str, str, int | None, bool]]:
    sph_w = r.concurrent(3, 4, 5)
    sph_b = r.concurrent(0, 1, 2)
    out: list[tuple[str, str, int | None, bool]] = []
    # closed form, quadratic
    if sph_w and r.inter[0]:
        out.append(("6R-spherical-wrist-two-intersecting", "closed form", 8, False))
    if sph_w and r.par[1]:
        out.append(("6R-spherical-wrist-two-parallel", "closed form", 8, False))
    if sph_b and r.inter[4]:
        out.append(("6R-spherical-wrist-base-two-intersecting", "closed form", 8, True))
    if sph_b and r.par[3]:
        out.append(("6R-spherical-wrist-base-two-parallel", "closed form", 8, True))
    if r.three_parallel(1) and r.inter[4]:
        out.append(("6R-three-parallel-two-intersecting", "closed form", 8, False))
    if r.three_parallel(2) and r.inter[0]:
        out.append(("6R-three-parallel-two-intersecting", "closed form", 8, True))
    # closed form, quartic
    if sph_w:
        out.append(("6R-spherical-wrist", "closed form", 8, False))
    if sph_b:
        out.append(("6R-spherical-wrist-base", "closed form", 8, True))
    if r.three_parallel(1):
        out.append(("6R-three-parallel", "closed form", 8, False))
    if r.three_parallel(2):
        out.append(("6R-three-parallel", "closed form", 8, True))
    # 1-D search
    if r.concurrent(1, 2, 3) or r.concurrent(2, 3, 4):     # solved with axes 2-3-4 meeting (3-4-5: reversed)
        out.append(("6R-spherical-middle", "1-D search", 16, not r.concurrent(1, 2, 3)))
    if r.inter[4]:
        out.append(("6R-two-intersecting", "1-D search", 16, False))
    if r.inter[0]:
        out.append(("6R-two-intersecting", "1-D search", 16, True))
    if r.par[1]:
        out.append(("6R-two-parallel", "1-D search", 16, False))
    if r.par[3]:
        out.append(("6R-two-parallel", "1-D search", 16, True))
    # no 1-D search here for axes i, i + 2 that always meet, one intersecting pair in the middle (2-3, 3-4, 4-5)
    # or a parallel pair 3 ∥ 4: fixing any one joint leaves products of two unknown rotations (no SP5 / SP6), so
    # such arms are the general class (2-D search). 1 ∥ 2 (5 ∥ 6 reversed) would allow one (q3 searched, SP6 in
    # q4, q6), not written yet: the general class answers them too.
    out.append(("6R-general", "2-D search", 16, False))
    if r.inter2[3]:
        out.append(("6R-two-intersecting-nonconsecutive", "2-D search", 16, False))
    if r.inter2[0]:
        out.append(("6R-two-intersecting-nonconsecutive", "2-D search", 16, True))
    return out


_POSITION_CLASSES = frozenset({"1R", "2R-planar", "2R-intersecting", "2R-general", "3R-elbow", "3R-two-parallel",
                               "3R-general"})
"""The classes of 1 to 3 revolute joints whose closed form is for a position."""
_TARGET_CLASSES = _POSITION_CLASSES | {"3R-planar", "3R-spherical"}
"""... and those whose target turns the tool too (3R-planar takes the end angle, 3R-spherical an orientation)."""


def _small_family(r: _Relations, H: Array, tol: float) -> tuple[str, str, int | None, bool]:
    """Classes of all-revolute arms with 1 to 5 joints (their IK is for the pose components they control)."""
    n = r.n
    allpar = all(r.par)
    if n == 1:
        return ("1R", "closed form", 1, False)
    if n == 2:
        if allpar:
            return ("2R-planar", "closed form", 2, False)
        if r.inter[0]:
            return ("2R-intersecting", "closed form", 2, False)
        return ("2R-general", "closed form", 2, False)
    if n == 3:
        if allpar:
            return ("3R-planar", "closed form", 2, False)
        if r.concurrent(0, 1, 2):
            return ("3R-spherical", "closed form", 2, False)
        if r.inter[0] and r.par[1]:
            return ("3R-elbow", "closed form", 4, False)
        if r.par[1] or r.par[0]:
            return ("3R-two-parallel", "closed form", 4, False)
        return ("3R-general", "closed form", 4, False)
    # yaw + three parallel pitch axes (+ roll): the yaw-pitch3 family, whose yaw (and roll) axes are perpendicular
    # to the pitch axes (within the 1e-4 rad its ideal arm snaps, as a URDF's rounded rpy needs); a yaw axis at
    # another angle has no closed form here
    right = math.sin(max(tol, 1e-4))
    across = abs(float(H[0] @ H[1])) < right
    if n == 4:
        if allpar:
            return ("4R-planar", "numeric", None, False)
        if r.three_parallel(1) and across:
            return ("4R-yaw-three-parallel", "closed form", 4, False)
        return ("4R-general", "numeric", None, False)
    # n == 5
    if r.three_parallel(1) and across and abs(float(H[3] @ H[4])) < right:
        return ("5R-yaw-three-parallel-roll", "closed form", 4, False)
    return ("5R-general", "numeric", None, False)


def _display(r: _Relations) -> tuple[tuple[tuple[int, ...], ...], tuple[tuple[int, ...], ...]]:
    """The relations as 1-based tuples: concurrent runs, then pairs (i, i+2) not inside a run; parallel runs."""
    inter = [tuple(k + 1 for k in g) for g in r.groups]
    for i, ok in enumerate(r.inter2):
        if ok and not r.concurrent(i, i + 1, i + 2):
            inter.append((i + 1, i + 3))
    inter.sort()
    par = [tuple(k + 1 for k in g) for g in r.runs()]
    return tuple(inter), tuple(par)


def _lock(H: Array, P: Array, prismatic: NDArray[np.bool_], k: int, t: float) -> tuple[Array, Array, NDArray]:
    """The chain with joint ``k`` (0-based) locked at ``t``: one axis fewer, later axes turned (a revolute joint)
    or moved along its axis (a prismatic one)."""
    pts = axis_points(P)
    n = H.shape[0]
    if prismatic[k]:
        shift = t * H[k]
        allp = np.vstack([[pts[m] if m < k else pts[m] + shift for m in range(n) if m != k],
                          (pts[-1] + P[-1] + shift)[None, :]])
        return (np.delete(H, k, axis=0), np.vstack([allp[:1], np.diff(allp, axis=0)]),
                np.delete(np.asarray(prismatic, dtype=bool), k))
    Rk = rotm(H[k], t)
    H2 = np.array([H[m] if m < k else Rk @ H[m] for m in range(n) if m != k])
    tip = pts[-1] + P[-1]
    newpts = [pts[m] if m < k else pts[k] + Rk @ (pts[m] - pts[k]) for m in range(n) if m != k]
    newtip = pts[k] + Rk @ (tip - pts[k])
    allp = np.vstack([newpts, newtip[None, :]])
    P2 = np.vstack([allp[:1], np.diff(allp, axis=0)])
    return H2, P2, np.delete(np.asarray(prismatic, dtype=bool), k)


def _classify_poe(H: Array, P: Array, prismatic: NDArray[np.bool_], tol: float, size: float | None = None
                  ) -> ChainClass:
    """The class of the chain ``(H, P)``; ``size``: the arm's size for the tool point's rank (the robot's reach;
    default: the offsets, :func:`_sampled_scale`)."""
    H = np.asarray(H, dtype=float)
    H = H / np.linalg.norm(H, axis=1, keepdims=True)
    P = np.asarray(P, dtype=float)
    prismatic = np.asarray(prismatic, dtype=bool)
    n = H.shape[0]
    types = "".join("P" if p else "R" for p in prismatic)
    rel = _relations(H, P, prismatic, tol)
    inter, par = _display(rel)
    base = dict(n=n, joint_types=types, intersecting=inter, parallel=par, tol=tol)
    prefix = f"{n}R" if not prismatic.any() else types
    if _rank_deficient(H, P, prismatic):
        return ChainClass(**base, name=f"{prefix}-degenerate", solver="numeric", max_solutions=None,
                          near=rel.near, degenerate=True)
    if n == 7 and int(prismatic.sum()) == 1:        # a 6R arm on a rail (or with a slide elsewhere): lock the slide
        return _seven_r(H, P, prismatic, tol, rel, base)
    if prismatic.any():
        return _prismatic_class(H, P, prismatic, rel, base, prefix, n, size)
    if n <= 5:
        name, solver, m, inv = _small_family(rel, H, tol)
        if name in _TARGET_CLASSES and _position_rank(H, P, prismatic, size, name not in _POSITION_CLASSES) < n:
            # the joints cannot move the tool in every direction of the class's target (a tool point on the last
            # axis, two axes on one line, a link of length ~0): a curve of solutions or none
            return ChainClass(**base, name=f"{n}R-degenerate", solver="numeric", max_solutions=None, near=rel.near,
                              degenerate=True)
        return ChainClass(**base, name=name, solver=solver, max_solutions=m, near=rel.near, inverted=inv)
    if n == 6:
        fams = _six_r_families(rel)
        name, solver, m, inv = fams[0]
        alts = tuple(dict.fromkeys(f[0] for f in fams[1:] if f[0] != name))
        return ChainClass(**base, name=name, solver=solver, max_solutions=m, near=rel.near, inverted=inv,
                          alternatives=alts)
    if n == 7:
        return _seven_r(H, P, prismatic, tol, rel, base)
    return ChainClass(**base, name=f"{n}R-redundant", solver="numeric", max_solutions=None, near=rel.near)


_RANK = {"closed form": 0, "1-D search": 1, "2-D search": 2}


def _seven_r(H: Array, P: Array, prismatic: NDArray[np.bool_], tol: float, rel: _Relations,
             base: dict) -> ChainClass:
    """A 7R arm: the joint whose locking (at any value) leaves the best 6R class. With one prismatic joint (a 6R arm on
    a rail) that joint: moving it moves the rest of the chain along it, so one value tells the class."""
    cands = []
    slide = [k for k in range(7) if prismatic[k]]
    for k in (slide or range(7)):
        locked = [_lock(H, P, prismatic, k, t) for t in ((0.0,) if slide else _SWEEP)]
        if any(_rank_deficient(*g) for g in locked):
            continue          # e.g. locking the elbow between two spherical joints
        r6 = _merge([_relations(*g, tol) for g in locked])
        fam = _six_r_families(r6)[0]
        quartic = fam[0] in ("6R-spherical-wrist", "6R-spherical-wrist-base", "6R-three-parallel")
        # best solver, then quadratic over quartic, then nearest the middle joint, then the lower one
        cands.append(((_RANK[fam[1]], quartic, abs(k - 3), k), k, fam, r6.near))
    head = base["joint_types"] if slide else "7R"       # PRRRRRR-lock-1-...: the rail held
    if not cands:
        return ChainClass(**base, name=f"{head}-degenerate", solver="numeric", max_solutions=None, near=rel.near,
                          degenerate=True)
    cands.sort(key=lambda c: c[0])
    _, k, (name6, solver6, m, inv), near6 = cands[0]
    alts = tuple(f"{head}-lock-{c[1] + 1}-{c[2][0][3:]}" for c in cands[1:] if c[2][1] == "closed form")
    if solver6 != "closed form":
        return ChainClass(**base, name=f"{head}-general", solver="numeric", max_solutions=None,
                          near=max(rel.near, near6), locked=k + 1, locked_class=name6, alternatives=alts)
    return ChainClass(**base, name=f"{head}-lock-{k + 1}-{name6[3:]}", solver=f"sweep joint {k + 1}", max_solutions=m,
                      near=max(rel.near, near6), inverted=inv, locked=k + 1, locked_class=name6,
                      alternatives=alts)


def _prismatic_class(H: Array, P: Array, prismatic: NDArray[np.bool_], rel: _Relations, base: dict, prefix: str,
                     n: int, size: float | None = None) -> ChainClass:
    """Chains with prismatic joints: a spherical wrist on three revolute joints at either end of a 6-joint chain
    leaves a 3-joint positioning problem, closed form (at most a quartic) with at most 4 × 2 solutions; a chain of
    1 to 3 joints is itself such a positioning problem (:mod:`armkit.ik.analytic.geometric_prismatic`) where its
    joints move the tool point in every direction they can (``n`` of them)."""
    if n == 6 and (rel.concurrent(3, 4, 5) or rel.concurrent(0, 1, 2)):
        at_base = not rel.concurrent(3, 4, 5)
        if at_base:                               # the chain read from the tool: its wrist is then at the end
            H, P, prismatic = -H[::-1], -P[::-1], prismatic[::-1]
        pts = axis_points(P)
        centre, _ = common_point(H, pts, (3, 4, 5))
        # the first three joints move the wrist centre: the positioning problem of a 3-joint chain
        Hs, Ps, slides = H[:3], np.vstack([P[:3], centre - pts[2]]), prismatic[:3]
        if _position_rank(Hs, Ps, slides, size) < 3:
            return ChainClass(**base, name=f"{prefix}-degenerate", solver="numeric", max_solutions=None,
                              near=rel.near, degenerate=True)
        kinds = "".join("P" if k else "R" for k in slides)
        m = _positioner(Hs, slides, _relations(Hs, Ps, slides, base["tol"]), kinds, base["tol"])[1]
        return ChainClass(**base, name=f"{prefix}-spherical-wrist{'-base' if at_base else ''}", solver="closed form",
                          max_solutions=2 * m, near=rel.near, inverted=at_base)
    if n <= 3:
        if _position_rank(H, P, prismatic, size) < n:
            return ChainClass(**base, name=f"{prefix}-degenerate", solver="numeric", max_solutions=None,
                              near=rel.near, degenerate=True)
        name, m = _positioner(H, prismatic, rel, prefix, base["tol"])
        return ChainClass(**base, name=name, solver="closed form", max_solutions=m, near=rel.near)
    if n == 4 and int(prismatic.sum()) == 1 and all(rel.par):
        # a SCARA in any order: three parallel turns and a slide along them, for a position and the turn about
        # them (the tool's Jacobian has rank 4)
        if _position_rank(H, P, prismatic, size, turning=True) < 4:
            return ChainClass(**base, name=f"{prefix}-degenerate", solver="numeric", max_solutions=None,
                              near=rel.near, degenerate=True)
        return ChainClass(**base, name=f"{prefix}-scara", solver="closed form", max_solutions=2, near=rel.near)
    return ChainClass(**base, name=f"{prefix}-general", solver="numeric", max_solutions=None, near=rel.near)


def _positioner(H: Array, prismatic: NDArray[np.bool_], rel: _Relations, prefix: str, tol: float
                ) -> tuple[str, int]:
    """The class name and the most solutions of a position target for 1 to 3 joints with a prismatic one: the
    textbook names where the axes fit them (Cartesian: three perpendicular slides; cylindrical: a turn, a slide
    along it and one across; spherical: two meeting axes and a slide across the second; SCARA: all three
    parallel), else the joint types; 1 solution without a revolute joint, 2 with one, 4 with two (2 for the
    SCARA, whose slide along the axes is fixed by the height). ``tol``: as for parallel axes (rad)."""
    right = math.sin(tol)                         # |cos| of an angle within tol of 90 deg
    turns = int((~prismatic).sum())
    if turns == 0:
        perpendicular = len(H) == 3 and abs(np.linalg.det(H)) > math.cos(tol)
        return (f"{prefix}-cartesian" if perpendicular else prefix), 1
    if turns == 1:
        if prefix == "RPP":
            along = [abs(float(H[0] @ H[k])) > math.cos(tol) for k in (1, 2)]
            across = [abs(float(H[0] @ H[k])) < right for k in (1, 2)]
            if (along[0] and across[1]) or (along[1] and across[0]):
                return "RPP-cylindrical", 2
        return (f"{prefix}-general" if len(H) == 3 else prefix), 2
    if prefix == "RRP":
        if all(rel.par):
            return "RRP-scara", 2
        if rel.inter[0] and abs(float(H[1] @ H[2])) < right:
            return "RRP-spherical", 4
    return f"{prefix}-general", 4


POSITION_RANK_TOL = 1e-4
"""A direction the tool point moves in by less than this (per rad or per unit of slide, in units of the arm's size)
does not count: a tool point this close to an axis, or two slides this close to parallel, leave a curve of
solutions within rounding (the geometric families' ``PARALLEL_TOL``: they solve on the ideal chain below it)."""


def _position_rank(H: Array, P: Array, prismatic: NDArray[np.bool_], size: float | None = None,
                   turning: bool = False) -> int:
    """The rank of the tool point's Jacobian ``(3, n)`` at generic configurations (:data:`POSITION_RANK_TOL`), its
    columns in units of ``size`` (default: :func:`_sampled_scale`); ``turning``: of the tool's whole Jacobian
    ``(6, n)``, its turning too (a planar 3R's end angle, a gimbal's orientation)."""
    n = H.shape[0]
    scale = size if size is not None and size > 0 else _sampled_scale(P, prismatic)
    rng = np.random.default_rng(20240611)
    best = 0
    for _ in range(3):
        q: Array = np.asarray(rng.uniform(-np.pi, np.pi, size=n), dtype=float)
        q[prismatic] *= scale / np.pi             # slides over the arm's size, in any unit
        R = np.eye(3)
        p = np.zeros(3)                           # from axis 1's point (P[0], the base offset, would only round)
        axes = []                                 # (joint, direction, a point on its axis) at q
        for k in range(n):
            w = R @ H[k]
            if prismatic[k]:
                p = p + q[k] * w
            else:
                R = R @ rotm(H[k], float(q[k]))
            axes.append((k, w, p))
            p = p + R @ P[k + 1]
        J = np.zeros((6 if turning else 3, n))    # a slide moves the point along w, a turn by w × (p - o)
        for k, w, o in axes:                      # (per unit of slide; per rad, in units of the arm's size)
            J[:3, k] = w if prismatic[k] else np.cross(w, p - o) / scale
            if turning and not prismatic[k]:
                J[3:, k] = w
        s = np.linalg.svd(J, compute_uv=False)       # columns of about 1 (a tool point on every axis: all ~0)
        best = max(best, int(np.sum(s > POSITION_RANK_TOL * max(s[0], 1.0))))
    return best


def classify(robot_or_poe: Union[Robot, POE], tol: float = DEFAULT_TOL) -> ChainClass:
    """The geometric class of a robot (or of a chain already in :class:`~.poe.POE` form).

    ``tol``: radians for parallel axes, a fraction of the arm's size for distances between axes.

    >>> import armkit
    >>> classify(armkit.load("ur5")).name
    '6R-three-parallel-two-intersecting'
    >>> c = classify(armkit.load("iiwa14"))
    >>> c.name, c.solver
    ('7R-lock-3-spherical-wrist-two-intersecting', 'sweep joint 3')
    """
    form = robot_or_poe if isinstance(robot_or_poe, POE) else poe(robot_or_poe)
    if not (tol > 0 and np.isfinite(tol)):
        raise ArgumentError.of("tol must be a positive number, got {tol!r}", tol=tol)
    size = float(robot_or_poe.reach) if isinstance(robot_or_poe, Robot) else None
    return _classify_poe(np.asarray(form.H), np.asarray(form.P), np.asarray(form.prismatic), float(tol), size)


# ------------------------------------------------------------------ one line for users
def N_(text: str) -> str:
    """Mark ``text`` for the catalogue (:func:`armkit.locale.N_`, without importing the language machinery here)."""
    return text


TEXTS = (
    N_("axes {axes} meet"),
    N_("axes {axes} meet in a point"),
    N_("spherical wrist"),
    N_("spherical shoulder"),
    N_("axes {a} and {b} always meet"),
    N_("axes {axes}"),
    N_("no axes meet or are parallel"),
    N_("closed form"),
    N_("1-D search"),
    N_("2-D search"),
    N_("up to {n} solutions"),
    N_("one solution"),
    N_("no closed form, numeric IK"),
    N_("degenerate (the axes cannot move the tool in every direction), numeric IK only"),
    N_("locking joint {k} leaves a closed form ({cls!r}): sweep joint {k}, up to {n} solutions per value"),
    N_("relations snapped by up to {dev}: polish the solutions"),
    N_("one joint sampled {n} times, {step} deg apart, then refined"),
    N_("two joints on a {n} x {n} grid, {step} deg apart, then refined"),
)
"""Every English phrase :func:`describe` writes, marked for the gettext catalogue (``babel.cfg`` reads this file)."""


def _english(text: str, /, **fields: object) -> str:
    return text.format(**fields)


def _join(g: Sequence[int], sep: str) -> str:
    return sep.join(str(k) for k in g)


def describe(cls: ChainClass, tr=None) -> str:
    """One short line: which axes meet or are parallel, and how the class is solved.

    ``tr(text, **fields)`` translates each phrase (one of :data:`TEXTS`) and fills in its fields;
    English by default (the command line passes its gettext function).

    >>> import armkit
    >>> describe(classify(armkit.load("ur5")))
    '6R: axes 1-2 meet, axes 4-5 meet, axes 5-6 meet, axes 2 ∥ 3 ∥ 4; closed form, up to 8 solutions'
    """
    t = tr or _english
    parts = []
    for g in cls.intersecting:
        if len(g) == 2 and g[1] - g[0] == 2:
            parts.append(t("axes {a} and {b} always meet", a=g[0], b=g[1]))
        elif len(g) >= 3:
            text = t("axes {axes} meet in a point", axes=_join(g, "-"))
            if g == (cls.n - 2, cls.n - 1, cls.n) and cls.n >= 5:
                text += f" ({t('spherical wrist')})"
            elif g[0] == 1 and len(g) == 3 and cls.n >= 6:
                text += f" ({t('spherical shoulder')})"
            parts.append(text)
        else:
            parts.append(t("axes {axes} meet", axes=_join(g, "-")))
    for g in cls.parallel:
        parts.append(t("axes {axes}", axes=_join(g, " ∥ ")))
    head = f"{cls.n}R" if "P" not in cls.joint_types else cls.joint_types
    text = f"{head}: " + (", ".join(parts) if parts else t("no axes meet or are parallel"))
    if cls.degenerate:
        text += "; " + t("degenerate (the axes cannot move the tool in every direction), numeric IK only")
    elif cls.solver == "numeric":
        text += "; " + t("no closed form, numeric IK")
    elif cls.solver.startswith("sweep"):
        text += "; " + t("locking joint {k} leaves a closed form ({cls!r}): sweep joint {k}, up to {n} solutions "
                         "per value", k=cls.locked, cls=cls.locked_class, n=cls.max_solutions)
    else:
        text += "; " + t(cls.solver)
        if cls.solver in ("1-D search", "2-D search"):     # the search's resolution, stated by its module
            from . import search, search2d

            n = search.N if cls.solver == "1-D search" else search2d.N
            text += " (" + t("one joint sampled {n} times, {step} deg apart, then refined" if cls.solver == "1-D search"
                             else "two joints on a {n} x {n} grid, {step} deg apart, then refined",
                             n=n, step=f"{360.0 / n:.2g}") + ")"
        if cls.max_solutions == 1:
            text += ", " + t("one solution")
        elif cls.max_solutions is not None:
            text += ", " + t("up to {n} solutions", n=cls.max_solutions)
    if cls.near > EXACT:
        text += " (" + t("relations snapped by up to {dev}: polish the solutions", dev=f"{cls.near:.1e}") + ")"
    return text


def described(cls: ChainClass) -> Fielded:
    """:func:`describe`'s line as a sentence that keeps its parts' templates and fields, so that an error holding it
    is shown in the user's language (:func:`armkit.locale.library.localize` renders each phrase of :data:`TEXTS`
    from the catalogue; the glue between them, ``6R: ``, ``, ``, ``; ``, is punctuation). Its English is
    ``describe(cls)``.

    >>> import armkit
    >>> line = described(classify(armkit.load("ur5")))
    >>> line == describe(classify(armkit.load("ur5"))), line.fields["p0"].template
    (True, 'axes {axes} meet')
    """
    parts: dict[str, Fielded] = {}

    def part(text: str, /, **fields: Any) -> str:
        key = f"p{len(parts)}"
        parts[key] = Fielded.of(text, **fields)
        return "\x00" + key + "\x00"

    line = describe(cls, part)
    template = "".join(("{" + piece + "}") if i % 2 else piece.replace("{", "{{").replace("}", "}}")
                       for i, piece in enumerate(line.split("\x00")))
    fields: dict[str, Any] = dict(parts)
    return Fielded.of(template, **fields)
