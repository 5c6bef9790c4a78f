"""Every branch of a position target for a chain of 1 to 3 joints with prismatic ones: the textbook arms.

Cartesian (PPP), cylindrical (RPP), spherical (RRP, the Stanford arm's first three joints), a SCARA's
RRP and every other order of revolute (R) and prismatic (P) joints, as long as the joints can move the
tool point in every direction (:func:`armkit.ik.geometric.classify.classify` says "degenerate"
otherwise, and the numeric solvers answer).

The tool point is ``p = p_01 + F_1(p_12 + F_2(p_23 + F_3 p_3T))``, where ``F_k x = rot(h_k, q_k) x`` for a
revolute joint and ``F_k x = q_k h_k + x`` for a prismatic one (the chain's product-of-exponentials form,
:mod:`armkit.ik.geometric.poe`). One revolute joint ``l`` is chosen, and the chain is cut there:
``rot(h_l, q_l) A = B``, with ``A`` what comes after the joint and ``B`` the target taken back through
what comes before it. A turn about ``h_l`` keeps two things, the component along ``h_l`` and the
length, so

* ``h_l · A = h_l · B``, linear in the slides, and
* ``|A|² = |B|²``, quadratic in them,

and ``q_l`` turns ``A`` onto ``B`` (SP1). With one revolute joint the two equations are a line and a
conic in the two slides (at most 2 solutions); with two, ``l`` is the one nearer the slide, so that the
other joint's angle ``θ`` appears only through ``cos θ`` and ``sin θ`` of a fixed vector: the linear
equation gives the slide as a function of ``θ`` and the quadratic becomes a quartic in ``tan(θ / 2)``
(at most 4; where the slide is perpendicular to ``h_l`` the linear one gives ``θ`` directly and the
quadratic the slide). Without a revolute joint the slides solve a linear system.

Every branch is verified by FK of the robot in :func:`armkit.ik.analytic.solve_all`, wrapped into the
limits and sorted there, as for every family; a slide outside its stroke is a branch outside the joint
limits.

Two more families build on these equations: :class:`GeometricPrismaticWrist` (six joints: such a
positioning part and a spherical wrist, solved for the wrist centre and then as a gimbal) and
:class:`GeometricScara` (four joints: three parallel turns and a slide along them, for a pose).
They solve in NumPy, one target at a time (docs/ik.md gives their cost); the SCARA's also a whole batch at once
(:meth:`GeometricScara._candidates_many`, from :data:`armkit.ik.analytic.geometric.MANY` targets).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...model.robot import Robot
from ..geometric.subproblems import TOL, _quartic_roots, _trig1, sp1
from .geometric import Geometric3R, across, chain_form, three_axes

__all__ = ["GeometricPrismatic", "GeometricPrismaticWrist", "GeometricScara", "Positioner"]

Array = NDArray[np.float64]

_C, _S = 3, 4
"""Columns of ``cos θ`` and ``sin θ`` in an expression; 0 is the constant, 1 and 2 the slides."""


class Positioner:
    """The position equations of a chain of 1 to 3 joints with a slide, ``H (n, 3)``, ``P (n + 1, 3)`` and the
    slide flags ``(n,)`` of its product-of-exponentials form; ``size``: a length typical of the arm."""

    def __init__(self, H: Array, P: Array, slide: NDArray[np.bool_], size: float) -> None:
        self.H = np.array(H, dtype=float)
        self.P = np.array(P, dtype=float)
        self.slide = np.asarray(slide, dtype=bool).copy()
        self.n = n = len(self.H)
        self.size = max(float(size), 1e-300)
        turns = [k for k in range(n) if not self.slide[k]]
        slides = [k for k in range(n) if self.slide[k]]
        self.column = {k: 1 + i for i, k in enumerate(slides)}
        # the joint to cut at: with two revolute joints the one nearer the slide (the other is then never
        # between them, so a slide is never turned by the unknown angle θ); with one, that one
        self.cut = (min(turns, key=lambda k: (abs(k - slides[0]), k)) if len(turns) == 2 else
                    turns[0] if turns else -1)
        self.other = next((k for k in turns if k != self.cut), -1)
        if not turns:
            self._dirs = self.H[slides].T
            self._pinv = np.linalg.pinv(self._dirs)
        else:   # A does not depend on the target and B is affine in it: both made once
            self._A, self._B0 = self.sides(np.zeros(3))
            self._Bt = np.stack([self.sides(e)[1] - self._B0 for e in np.eye(3)])    # (3, 3, 5): d B / d t_i
            self._hA = self.H[self.cut] @ self._A
            self._AtA = self._A.T @ self._A

    def sides(self, t: Array) -> tuple[Array, Array]:
        """``A`` and ``B`` as ``(3, 5)`` expressions (columns: 1, slide 1, slide 2, cos θ, sin θ) for the target
        ``t`` taken from axis 1's point."""
        H, P, n, cut = self.H, self.P, self.n, self.cut
        A = np.zeros((3, 5))
        A[:, 0] = P[n]
        for k in range(n - 1, cut, -1):           # A = P_{cut+1} + F_{cut+1}(P_{cut+2} + ... F_n P_nT)
            if self.slide[k]:
                A[:, self.column[k]] += H[k]
            else:
                A = _turned(H[k], A[:, 0], 1.0)
            A[:, 0] += P[k]
        B = np.zeros((3, 5))
        B[:, 0] = t
        for k in range(cut):                      # B = F_cut^-1 ... taken back through the joints before
            if self.slide[k]:
                B[:, self.column[k]] -= H[k]
            else:
                B = _turned(H[k], B[:, 0], -1.0)
            B[:, 0] -= P[k + 1]
        return A, B

    def solutions(self, p0W: Array) -> list[tuple[Array, bool]]:
        """Every ``(q (n,), ls)`` for the point ``p0W = p - p_01``; ``ls``: only a least-squares answer."""
        n = self.n
        scale = max(self.size, float(np.linalg.norm(p0W)))
        if self.cut < 0:                          # slides only: a linear system
            rest = p0W - self.P[1:].sum(axis=0)
            x = self._pinv @ rest
            return [(x, bool(np.linalg.norm(self._dirs @ x - rest) > TOL * scale))]
        A = self._A                               # = self.sides(p0W), from the parts made once
        B = self._B0 + np.tensordot(p0W, self._Bt, 1)
        h = self.H[self.cut]
        line = self._hA - h @ B                   # h · A - h · B, over (1, slide 1, slide 2, cos, sin)
        M = self._AtA - B.T @ B                   # |A|² - |B|² = mᵀ M m for m = (1, slide 1, slide 2, cos, sin)
        if self.other >= 0:
            found = _one_slide_one_angle(line, M, scale)
        elif len(self.column) == 2:
            found = _two_slides(line, M, scale)
        else:
            found = _one_slide(line, M, float(h @ B[:, 0]), scale)
        out = []
        for mono, ls in found[:8]:
            qv = np.zeros(n)
            for k, col in self.column.items():
                qv[k] = mono[col]
            if self.other >= 0:
                qv[self.other] = math.atan2(mono[_S], mono[_C])
            qv[self.cut], ls1 = sp1(A @ mono, B @ mono, h)
            out.append((qv, bool(ls) or bool(ls1)))
        return out


class GeometricPrismatic(Geometric3R):
    """Every branch of a position target for a chain of 1 to 3 joints with at least one prismatic joint (the
    classes ``PPP-cartesian``, ``RPP-cylindrical``, ``RRP-spherical``, ``RRP-scara``, ``RP``, ... of
    :func:`armkit.ik.geometric.classify.classify`); see the module docstring for the method."""

    family = "geometric-prismatic"
    m_joints = 3

    def __init__(self, robot: Robot, form: Any, chain_class: Any) -> None:
        self.robot = robot
        self.chain_class = chain_class
        self.P = np.array(form.P, dtype=float)
        self.chain = Positioner(form.H, form.P, form.prismatic, float(robot.reach))
        self.m = int(chain_class.max_solutions)
        self.branch_labels = tuple(f"s{k + 1}" for k in range(self.m))
        self.case = robot.joint_types
        self.sf = chain_form(robot, exact=True)

    @classmethod
    def _shape(cls, robot: Robot) -> bool:
        """1 to 3 joints, one of them prismatic."""
        return 1 <= robot.n <= cls.m_joints and any(robot.chain.prismatic)

    @classmethod
    def _takes(cls, chain_class: Any) -> bool:
        """Any class of such a chain that classify solves in closed form."""
        return chain_class.solver == "closed form" and bool(chain_class.max_solutions)

    def _candidates(self, p0W: Array, Q: Array, LS: NDArray[np.bool_], K: Any) -> int:
        """The solutions for ``p0W = p - p_01`` into the rows of ``Q (8, 3)`` (least-squares ones flagged in
        ``LS``); their count."""
        found = self.chain.solutions(p0W)
        for i, (qv, ls) in enumerate(found):
            Q[i, :len(qv)] = qv
            LS[i] = ls
        return len(found)


class GeometricPrismaticWrist(GeometricPrismatic):
    """Every branch of a pose for six joints: three positioning joints with a slide and a spherical wrist (axes
    4, 5, 6 meet in a point; the classes ``PRRRRR-spherical-wrist``, ``RPRRRR-spherical-wrist``, ... of
    :func:`armkit.ik.geometric.classify.classify`, and ``...-spherical-wrist-base`` solved on the reversed
    chain). The Stanford arm's own layout (axes 1 and 2 meet) keeps the compiled solver of the
    :class:`~armkit.ik.analytic.geometric.Geometric` family.

    Where the wrist axes meet, ``p = c(q1, q2, q3) + R_06 p_6T``: the wrist centre ``c`` is the tool point of
    the first three joints (:class:`Positioner`, up to 4 solutions), and ``rot(h4, q4) rot(h5, q5) rot(h6, q6) =
    R_03ᵀ R_06`` gives q4 and q5 by SP2 (where axis 6 goes) and q6 by SP1: up to twice as many branches. Wrist
    axes that only nearly meet are solved on the ideal chain and polished on the robot (solve_all)."""

    family = "geometric-prismatic-wrist"
    pose_only = True
    target_kind = "pose"
    m_joints = 6
    buffer = (8, 6)

    def __init__(self, robot: Robot, form: Any, chain_class: Any) -> None:
        from ..geometric.solvers_chain import align, reverse

        self.robot = robot
        self.chain_class = chain_class
        self.inverted = bool(chain_class.inverted)
        ideal, dev = align(reverse(form) if self.inverted else form, ((3, 4, 5),))
        self.form = ideal
        self.P = np.array(ideal.P, dtype=float)
        self.chain = Positioner(ideal.H[:3], ideal.P[:4], ideal.prismatic[:3], float(robot.reach))
        self.m = int(chain_class.max_solutions)
        self.branch_labels = tuple(f"s{k + 1}" for k in range(self.m))
        self.case = robot.joint_types
        self._across6 = across(ideal.H[5])
        self.sf = chain_form(robot, exact=dev < 1e-13)

    @classmethod
    def _shape(cls, robot: Robot) -> bool:
        """Six joints with a slide (among the first three, or the last three: the chain is read reversed)."""
        return robot.n == cls.m_joints and any(robot.chain.prismatic)

    @classmethod
    def _takes(cls, chain_class: Any) -> bool:
        """A spherical wrist that the :class:`~armkit.ik.analytic.geometric.Geometric` family (registered first)
        does not solve."""
        return super()._takes(chain_class) and "spherical-wrist" in chain_class.name

    def _candidates_of(self, target: Array, Q: Array, LS: NDArray[np.bool_], K: Any) -> int:
        """Every branch of one pose ``(4, 4)`` into the rows of ``Q (8, 6)``; their count."""
        from ..geometric.subproblems import rotm

        form = self.form
        R, p = target[:3, :3], target[:3, 3]
        if self.inverted:                         # the reversed chain, for the inverse target
            R = R.T
            p = -R @ p
        R06 = R @ form.R_nT.T
        centre = p - R06 @ form.P[6] - form.P[0]
        count = 0
        for q3, ls in self.chain.solutions(centre):
            R03 = np.eye(3)
            for k in range(3):
                if not form.prismatic[k]:
                    R03 = R03 @ rotm(form.H[k], float(q3[k]))
            for t4, t5, t6, ls3 in three_axes(R03.T @ R06, form.H[3:6], self._across6):
                if count < len(Q):
                    row = (*q3, t4, t5, t6)
                    Q[count] = row[::-1] if self.inverted else row
                    LS[count] = ls or ls3
                    count += 1
        return count


class GeometricScara(GeometricPrismatic):
    """Both branches of a pose for four joints: three revolute axes parallel to one direction ``h`` and a slide
    along it, in any order (the SCARA: two arm joints, a vertical quill, a wrist turn; class ``RRPR-scara`` and
    the other orders of :func:`armkit.ik.geometric.classify.classify`). Such an arm controls the tool position
    and its turn about ``h``; the target is a pose, whose rotation must be such a turn (else no branch reaches
    it, and the error says by how much).

    Every turn is about ``h``, so they add up: the pose's rotation gives the sum ``ψ`` of the signed angles
    (SP1), the component of the position along ``h`` gives the slide, and across ``h`` the offsets after the
    first, second and third turn make a planar two-link problem (SP3 for the elbow, SP1 for the shoulder); the
    third angle is what is left of ``ψ``."""

    family = "geometric-scara"
    pose_only = True
    target_kind = "pose"
    m = 2
    m_joints = 4
    buffer = (8, 4)

    def __init__(self, robot: Robot, form: Any, chain_class: Any) -> None:
        self.robot = robot
        self.chain_class = chain_class
        self.form = form
        self.P = np.array(form.P, dtype=float)
        self.m = 2
        self.branch_labels = ("s1", "s2")
        self.case = robot.joint_types
        slide = np.asarray(form.prismatic, dtype=bool)
        self.turns = [k for k in range(4) if not slide[k]]
        self.slide_joint = int(np.flatnonzero(slide)[0])
        h = np.array(form.H[self.turns[0]], dtype=float)
        self.h = h
        # each turn's direction along h (named not `sign`, which is planar-2r's option in the one-call path)
        self.turn_sign = np.array([1.0 if float(form.H[k] @ h) > 0 else -1.0 for k in self.turns])
        self.slide_along = float(form.H[self.slide_joint] @ h)
        # the offsets P[1..4] grouped by how many turns come before them (the slide's own vector is along h)
        self.A = np.zeros((4, 3))
        for k in range(1, 5):
            self.A[sum(1 for t in self.turns if t < k)] += form.P[k]
        self._across = across(h)
        # axes parallel only within classify's tolerance (a URDF's rounding): solved as parallel to h, then
        # polished on the robot by solve_all
        dev = max(float(np.linalg.norm(np.cross(form.H[k], h))) for k in range(4))
        self.tilt_tol = max(TOL, 100.0 * dev)      # a pose turned off h by more than this is out of reach
        self.sf = chain_form(robot, exact=dev < 1e-13)

    @classmethod
    def _shape(cls, robot: Robot) -> bool:
        """Four joints, one a slide."""
        return robot.n == cls.m_joints and sum(robot.chain.prismatic) == 1

    @classmethod
    def _takes(cls, chain_class: Any) -> bool:
        """Its axes all parallel: the class ``...-scara``."""
        return chain_class.name.endswith("-scara")

    def _candidates_of(self, target: Array, Q: Array, LS: NDArray[np.bool_], K: Any) -> int:
        """Both branches of one pose ``(4, 4)`` into the rows of ``Q (8, 4)``; their count."""
        from ..geometric.subproblems import rot, sp3

        h, A = self.h, self.A
        Rw = target[:3, :3] @ self.form.R_nT.T             # = rot(h, ψ) where the pose is one this arm reaches
        turned = Rw @ self._across
        psi, _ = sp1(self._across, turned, h)
        ls_psi = abs(float(h @ turned)) > self.tilt_tol     # the pose tilts the tool off h: no branch reaches it
        t = target[:3, 3] - self.P[0] - rot(h, psi, A[3]) - A[0]
        slide = float(h @ (t - A[1] - A[2])) / self.slide_along
        u = t - float(h @ t) * h                             # across h: rot(h, φ1) (A1 + rot(h, δ) A2)
        a1, a2 = A[1] - float(h @ A[1]) * h, A[2] - float(h @ A[2]) * h
        deltas, count, ls3 = sp3(a2, -a1, h, float(np.linalg.norm(u)))
        for i in range(count):
            phi1, ls1 = sp1(a1 + rot(h, deltas[i], a2), u, h)
            q = np.zeros(4)
            q[self.slide_joint] = slide
            q[self.turns] = np.array([phi1, deltas[i], psi - phi1 - deltas[i]]) * self.turn_sign
            Q[i] = q
            LS[i] = bool(ls_psi) or bool(ls3) or bool(ls1)
        return int(count)

    def _candidates_many(self, target: Array) -> tuple[Array, NDArray[np.bool_], NDArray[np.int64]] | None:
        """:meth:`_candidates_of` for a batch of poses ``(B, 4, 4)`` at once (:mod:`..geometric.subproblems_many`,
        the same steps on arrays): ``(Q (B, 2, 4), LS (B, 2), count (B,))``."""
        from ..geometric.subproblems_many import _dot, rot_many, sp1_many, sp3_many

        h, A, ac, RnT = self.h, self.A, self._across, self.form.R_nT
        B = len(target)
        turned = (target[:, :3, :3] @ RnT.T) @ ac
        psi, _ = sp1_many(ac, turned, h)
        ls_psi = np.abs(_dot(h, turned)) > self.tilt_tol
        t = target[:, :3, 3] - self.P[0] - rot_many(h, psi, A[3]) - A[0]
        slide = _dot(h, t - A[1] - A[2]) / self.slide_along
        u = t - _dot(h, t)[:, None] * h
        a1, a2 = A[1] - float(h @ A[1]) * h, A[2] - float(h @ A[2]) * h
        deltas, count, ls3 = sp3_many(a2, -a1, h, np.sqrt(_dot(u, u)))
        Q = np.zeros((B, 2, 4))
        LS = np.zeros((B, 2), dtype=bool)
        for i in range(2):
            phi1, ls1 = sp1_many(a1 + rot_many(h, deltas[:, i], a2), u, h)
            Q[:, i, self.slide_joint] = slide
            for col, sign, angle in zip(self.turns, self.turn_sign, (phi1, deltas[:, i], psi - phi1 - deltas[:, i])):
                Q[:, i, col] = angle * sign
            LS[:, i] = ls_psi | ls3 | ls1
        return Q, LS, count


def _turned(h: Array, v: Array, sign: float) -> Array:
    """``rot(h, sign θ) v`` as a ``(3, 5)`` expression: ``(h·v) h + cos θ (v - (h·v) h) + sign sin θ (h × v)``."""
    E = np.zeros((3, 5))
    along = float(h @ v) * h
    E[:, 0] = along
    E[:, _C] = v - along
    E[:, _S] = sign * np.cross(h, v)
    return E


def _mono(x1: float = 0.0, x2: float = 0.0, c: float = 0.0, s: float = 0.0) -> Array:
    return np.array([1.0, x1, x2, c, s])


def _quadratic(a: float, b: float, c: float, size: float) -> tuple[list[float], bool]:
    """The real roots of ``a x² + b x + c``; where there is none, the vertex, with ``ls`` True where the value
    there is above ``TOL · size`` (``size``: of ``c``, a squared length)."""
    big = max(abs(a), abs(b), abs(c), 1e-300)
    if abs(a) <= 1e-12 * big:
        if abs(b) <= 1e-12 * big:
            return [0.0], abs(c) > TOL * size
        return [-c / b], False
    disc = b * b - 4.0 * a * c
    # a double root within rounding (whose two roots would lie ~1e-7 of the size apart, both half wrong), or
    # none (least squares): the vertex
    if disc <= 4e-14 * abs(a) * size:
        vertex = -b / (2.0 * a)
        return [vertex], -disc / (4.0 * abs(a)) > TOL * size
    root = math.sqrt(disc)
    q = -0.5 * (b + math.copysign(root, b))        # the stable pair of roots
    x1 = q / a
    x2 = c / q if q != 0.0 else x1
    return ([x1] if abs(x1 - x2) <= 1e-15 * max(abs(x1), 1.0) else [x1, x2]), False


def _one_slide(line: Array, M: Array, hB: float, scale: float) -> list[tuple[Array, bool]]:
    """One revolute joint, one slide (two joints, a position target: the arm reaches a surface). The slide
    from the linear equation where it appears there, else from the quadratic; ``ls`` where the other
    equation is not met (a target off the surface). Where the slide is perpendicular to the axis, the surface
    is a plane across it (less a disc): the target is first moved along the axis onto that plane (``hB``: its
    component along the axis), so that an unreachable target gets the nearest point."""
    L0, L1 = float(line[0]), float(line[1])
    a, b, c = float(M[1, 1]), 2.0 * float(M[0, 1]), float(M[0, 0])
    if abs(L1) > 1e-9:
        x = -L0 / L1
        return [(_mono(x), abs(a * x * x + b * x + c) > TOL * scale * scale)]
    # |B + L0 h|² = |B|² + 2 L0 (h · B) + L0²: the target moved onto the plane
    roots, ls = _quadratic(a, b, c - 2.0 * L0 * hB - L0 * L0, scale * scale)
    off = abs(L0) > TOL * scale
    return [(_mono(x), ls or off) for x in roots]


def _two_slides(line: Array, M: Array, scale: float) -> list[tuple[Array, bool]]:
    """One revolute joint, two slides: the line ``L0 + L1 x1 + L2 x2 = 0`` meets the conic
    ``(1, x1, x2) M (1, x1, x2)ᵀ = 0`` in at most two points."""
    L = line[1:3]
    nL = float(np.hypot(L[0], L[1]))
    v = np.array([-L[1], L[0]]) / nL
    x0 = -float(line[0]) * L / (nL * nL)
    Mx, g = M[1:3, 1:3], M[1:3, 0]
    a = float(v @ Mx @ v)
    b = 2.0 * float(v @ (Mx @ x0 + g))
    c = float(x0 @ Mx @ x0 + 2.0 * g @ x0 + M[0, 0])
    roots, ls = _quadratic(a, b, c, scale * scale)
    return [(_mono(*(x0 + s * v)), ls) for s in roots]


def _times(a: tuple[float, float, float], b: tuple[float, float, float]) -> Array:
    """The product of ``a0 + a1 cos θ + a2 sin θ`` and the same of ``b``, as coefficients of
    ``(1, cos, sin, cos², cos sin, sin²)``."""
    return np.array([a[0] * b[0], a[0] * b[1] + a[1] * b[0], a[0] * b[2] + a[2] * b[0], a[1] * b[1],
                     a[1] * b[2] + a[2] * b[1], a[2] * b[2]])


ISOTROPIC = 1e-12
"""A trigonometric quadratic whose ``cos²`` and ``sin²`` coefficients agree and whose ``cos sin`` one vanishes to this
fraction of its largest coefficient is solved as the linear ``a cos θ + b sin θ = c``."""


def _trig_value(k: Array, t: float) -> tuple[float, float]:
    """``f(θ) = k · (1, c, s, c², cs, s²)`` and ``f'(θ)``."""
    c, s = math.cos(t), math.sin(t)
    f = k[0] + k[1] * c + k[2] * s + k[3] * c * c + k[4] * c * s + k[5] * s * s
    df = -k[1] * s + k[2] * c - 2.0 * k[3] * c * s + k[4] * (c * c - s * s) + 2.0 * k[5] * s * c
    return f, df


def _trig_roots(k: Array) -> tuple[list[float], float]:
    """The angles where ``k · (1, cos θ, sin θ, cos² θ, cos θ sin θ, sin² θ) = 0``: the quartic in ``tan(θ / 2)``
    (and θ = π, its root at infinity), near-real roots polished by Newton steps. Also the angle of the smallest
    ``|f|`` among the candidates (for a target out of reach)."""
    # the roots do not change with the scale of k: divided by its largest entry, tiny coefficients keep their digits
    # (hypothesis: entries of 8e-162, whose squares lose digits below the smallest normal float, gave a root 0.8 %
    # of |k| off; the polish of a root stops at 1e-9 of |k|)
    big = float(np.max(np.abs(k)))
    if 0.0 < big < math.inf:
        k = np.asarray(k, dtype=float) / big
    k0, kc, ks, kcc, kcs, kss = (float(v) for v in k)
    size = max(abs(k0), abs(kc), abs(ks), abs(kcc), abs(kcs), abs(kss), 1e-300)
    if abs(kcc - kss) <= ISOTROPIC * size and abs(kcs) <= ISOTROPIC * size:
        # the quadratic part is kcc (cos² + sin²) = kcc (a SCARA's slide along its turns): kc cos θ + ks sin θ =
        # -(k0 + kcc), at most two roots in closed form (SP4's equation), no quartic
        ts, count, ls = _trig1(kc, ks, -(k0 + kcc), size)
        # a root is a zero to 1e-9 of |k|, as the quartic's polished roots below (SP4's equation takes 1e-8: a
        # near-tangent line 1e-8 short of the circle gave a "root" the quartic path does not)
        roots1 = [] if ls else [float(t) for t in ts[:count] if abs(_trig_value(k, float(t))[0]) <= 1e-9 * size]
        return roots1, float(ts[0])
    roots = _quartic_roots(k0 - kc + kcc, 2.0 * ks - 2.0 * kcs, 2.0 * k0 - 2.0 * kcc + 4.0 * kss,
                           2.0 * ks + 2.0 * kcs, k0 + kc + kcc)
    cands = [(2.0 * math.atan(r.real), abs(r.imag) <= 1e-5 * (1.0 + abs(r))) for r in roots]
    cands.append((math.pi, True))
    out: list[float] = []
    best, best_t = math.inf, 0.0
    for t, real in cands:
        f, _ = _trig_value(k, t)
        if abs(f) < best:
            best, best_t = abs(f), t
        if not real:
            continue
        for _ in range(6):
            f, df = _trig_value(k, t)
            if df == 0.0 or abs(f) > 0.5 * abs(df):   # a step over 0.5 rad (compared so that f / df cannot overflow)
                break
            step = f / df
            t -= step
            if abs(step) < 1e-16:
                break
        f, _ = _trig_value(k, t)
        if abs(f) > 1e-9 * size:
            continue
        t = math.remainder(t, 2.0 * math.pi)
        if all(abs(math.remainder(t - u, 2.0 * math.pi)) > 1e-7 for u in out):
            out.append(t)
    return out, best_t


def _one_slide_one_angle(line: Array, M: Array, scale: float) -> list[tuple[Array, bool]]:
    """Two revolute joints and a slide: ``L0 + α x + Lc cos θ + Ls sin θ = 0`` and the quadratic ``mᵀ M m = 0``
    in ``m = (1, x, cos θ, sin θ)``."""
    L0, alpha, Lc, Ls = float(line[0]), float(line[1]), float(line[_C]), float(line[_S])
    lin = (L0, Lc, Ls)
    # the quadratic in x: xx x² + x (x0 + xc c + xs s) + (rest: a trig polynomial of degree 2)
    xx = float(M[1, 1])
    xlin = (2.0 * float(M[0, 1]), 2.0 * float(M[1, _C]), 2.0 * float(M[1, _S]))
    rest = np.array([M[0, 0], 2.0 * M[0, _C], 2.0 * M[0, _S], M[_C, _C], 2.0 * M[_C, _S], M[_S, _S]], dtype=float)
    found: list[tuple[Array, bool]] = []
    if abs(alpha) > 1e-9:
        # x = -u / α with u = L0 + Lc c + Ls s; α² times the quadratic: xx u² - α u xlin + α² rest = 0
        k = xx * _times(lin, lin) - alpha * _times(lin, xlin) + alpha * alpha * rest
        angles, best = _trig_roots(k)
        ls = not angles
        for t in angles or [best]:
            c, s = math.cos(t), math.sin(t)
            found.append((_mono(-(L0 + Lc * c + Ls * s) / alpha, 0.0, c, s), ls))
        return found
    # the slide does not change the component along h_l: the linear equation gives θ, the quadratic x
    ts, count, ls = _trig1(Lc, Ls, -L0, scale)
    for i in range(count):
        c, s = math.cos(ts[i]), math.sin(ts[i])
        b = xlin[0] + xlin[1] * c + xlin[2] * s
        r = rest @ np.array([1.0, c, s, c * c, c * s, s * s])
        xs, lsx = _quadratic(xx, b, r, scale * scale)
        found.extend((_mono(x, 0.0, c, s), bool(ls) or lsx) for x in xs)
    return found
