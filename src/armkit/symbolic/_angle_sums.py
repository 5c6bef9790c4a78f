r"""The fast path of :func:`~armkit.symbolic.derive`: the chain products in angle-sum variables, no ``trigsimp``.

Consecutive joints with parallel axes (a twist of exactly 0 or pi between them) turn about the same direction,
so their rotations add up: :math:`R_z(q_2) R_z(q_3) = R_z(q_2 + q_3)`. The forward kinematics of such an arm is
a polynomial, of degree at most one in each cosine/sine pair, of the *cumulative* angles
:math:`\varphi_k = \varphi_{k-1} \pm \theta_k` of each run of parallel joints (``q2``, ``q2 + q3``,
``q2 + q3 + q4`` for a UR arm), of the link lengths and of the prismatic joint variables.

This module computes in those variables directly: every cumulative angle gets a new variable
:math:`\psi_k`, a joint variable is rewritten as the difference :math:`q_k = \pm(\psi_k - \psi_{k-1}) - \text{offset}`,
the link transforms become polynomials in :math:`C_k = \cos\psi_k`, :math:`S_k = \sin\psi_k` and the lengths,
and the frames, the tool pose and the Jacobian are products and differences of such polynomials, each reduced by
:math:`S_k^2 = 1 - C_k^2` right after it is made. A polynomial that is of degree at most one in each pair
(:math:`1, C, S, CS`: linearly independent functions) has exactly one such reduced form, so the result is the
multilinear form whenever there is one; it is printed with :math:`C_k \to \cos\varphi_k`, grouped by the
monomial of the lengths as :func:`~armkit.symbolic.simplify_entry` groups it, with the common factors pulled out.
With irrational coefficients (a base or tool turned by 30 deg about z) a pair ``sqrt(3)/2 C - 1/2 S`` is printed
as the one cosine ``cos(phi + pi/6)``, as ``trigsimp`` writes it.

Every step is exact polynomial arithmetic (rational or algebraic coefficients); arms it does not cover (a twist
or offset that is not an exact multiple of pi, floating-point base/tool rotations) go through
:func:`~armkit.symbolic.simplify_entry` as before.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Sequence

import sympy as sp
from sympy.polys.polyerrors import BasePolynomialError
from sympy.polys.rings import PolyElement

__all__ = ["AngleBasis", "angle_basis", "chain"]



@dataclass(frozen=True)
class AngleBasis:
    """The cumulative-angle variables of an arm.

    Attributes
    ----------
    to_psi : dict
        Revolute joint variable ``q_k`` -> its expression in the new angles (``psi_k - psi_{k-1}``, signed, less the
        offset).
    from_psi : dict
        New angle ``psi_k`` -> the cumulative angle it stands for, in the joint variables (``q2 + q3``).
    cos, sin : dict
        New angle -> the polynomial variable of its cosine / sine.
    """

    to_psi: dict[sp.Symbol, sp.Expr]
    from_psi: dict[sp.Symbol, sp.Expr]
    cos: dict[sp.Symbol, sp.Symbol]
    sin: dict[sp.Symbol, sp.Symbol]


def angle_basis(convention: str, q: Sequence[sp.Symbol], rows: Sequence[tuple], prismatic: Sequence[bool]
                ) -> AngleBasis | None:
    """The cumulative angles of the runs of parallel joints, or None when a twist or offset is not exact.

    ``rows`` are the symbolic DH rows ``(theta, d, a, alpha)`` of :func:`~armkit.symbolic.derive`; for the modified
    convention row ``k`` holds the twist before joint ``k`` (Craig's ``alpha_{k-1}``). Joints ``k`` and ``k+1``
    belong to the same run when the twist between them is exactly 0 (the angles add) or pi (the rotation flips:
    the next angle is subtracted); a prismatic joint's constant angle is carried along.

    >>> q1, q2 = sp.symbols("q1 q2", real=True)
    >>> b = angle_basis("standard", (q1, q2), [(q1, 0, 1, 0), (q2, 0, 1, 0)], (False, False))
    >>> sorted(map(str, b.from_psi.values()))
    ['q1', 'q1 + q2']
    """
    n = len(rows)
    if any(sp.sympify(r[3]).free_symbols for r in rows):
        return None
    # the twist between joint k and k + 1: after the joint (standard), before the next joint (modified)
    seps = [rows[k][3] if convention == "standard" else rows[k + 1][3] for k in range(n - 1)]
    to_psi: dict[sp.Symbol, sp.Expr] = {}
    from_psi: dict[sp.Symbol, sp.Expr] = {}
    cos: dict[sp.Symbol, sp.Symbol] = {}
    sin: dict[sp.Symbol, sp.Symbol] = {}
    sign, run_q, run_psi = 1, sp.Integer(0), sp.Integer(0)     # the run's sign and cumulative angle so far
    for k in range(n):
        theta = sp.sympify(rows[k][0])
        if prismatic[k]:
            if theta.free_symbols:
                return None
            run_q, run_psi = run_q + sign * theta, run_psi + sign * theta
        else:
            offset = theta - q[k]
            if offset.free_symbols:
                return None
            psi = sp.Dummy(f"psi{k + 1}", real=True)
            to_psi[q[k]] = sign * (psi - run_psi) - offset
            from_psi[psi] = run_q + sign * theta
            cos[psi] = sp.Dummy(f"C{k + 1}", real=True)
            sin[psi] = sp.Dummy(f"S{k + 1}", real=True)
            run_q, run_psi = from_psi[psi], psi
        if k < n - 1:
            c = sp.cos(seps[k])
            if c == -1:
                sign = -sign
            elif c != 1:                         # not parallel: the next joint starts a new run
                sign, run_q, run_psi = 1, sp.Integer(0), sp.Integer(0)
    return AngleBasis(to_psi, from_psi, cos, sin)


class _Ring:
    """Exact polynomials in the cosines/sines of the new angles, the lengths and the prismatic joint variables."""

    def __init__(self, basis: AngleBasis, params: Sequence[sp.Symbol], others: Sequence[sp.Symbol]):
        self.basis = basis
        self.trig = [s for psi in basis.from_psi for s in (basis.cos[psi], basis.sin[psi])]
        self.params = list(params)
        self.gens = self.trig + self.params + list(others)
        self.pairs = [(2 * i, 2 * i + 1) for i in range(len(basis.from_psi))]
        self.n_trig = len(self.trig)
        self.n_params = len(self.params)
        self.ring: Any = None

    def to_poly_exprs(self, exprs: Sequence[sp.Expr]) -> list[sp.Expr] | None:
        """``exprs`` rewritten in the new angles as polynomial expressions in the generators, None if one is not."""
        b = self.basis
        repl: dict[sp.Expr, sp.Expr] = {}
        for psi in b.from_psi:
            repl[sp.cos(psi)] = b.cos[psi]
            repl[sp.sin(psi)] = b.sin[psi]
        out = []
        allowed = set(self.gens)
        for e in exprs:
            f = sp.expand(sp.expand_trig(sp.sympify(e).xreplace(b.to_psi))).xreplace(repl)
            if f.atoms(sp.Function) or not f.free_symbols <= allowed:
                return None
            out.append(f)
        return out

    def make(self, exprs: Sequence[sp.Expr]) -> list[PolyElement] | None:
        """The ring elements of ``exprs`` (one ring for all of them), None when their coefficients are not exact."""
        polys = self.to_poly_exprs(exprs)
        if polys is None:
            return None
        try:
            ring, elems = sp.sring(polys, *self.gens, extension=True)
        except BasePolynomialError:              # not a polynomial in these generators after all
            return None
        dom = ring.domain
        if not (dom.is_ZZ or dom.is_QQ or dom.is_AlgebraicField):
            return None                          # floats or unknown numbers: the general path keeps them exact
        self.ring = ring
        return [self.reduce(e) for e in elems]

    def reduce(self, p: PolyElement) -> PolyElement:
        """``p`` with every ``S**2`` replaced by ``1 - C**2``: at most one power of each sine."""
        if all(m[s] < 2 for m in p for _, s in self.pairs):
            return p
        zero = self.ring.domain.zero
        acc: dict[tuple, Any] = {}
        stack = list(p.items())
        while stack:
            mon, c = stack.pop()
            for ic, is_ in self.pairs:
                if mon[is_] >= 2:
                    m = list(mon)
                    m[is_] -= 2
                    stack.append((tuple(m), c))
                    m[ic] += 2
                    stack.append((tuple(m), -c))
                    break
            else:
                acc[mon] = acc.get(mon, zero) + c
        return self.ring.from_dict({m: c for m, c in acc.items() if c})

    def to_expr(self, p: PolyElement) -> sp.Expr:
        """``p`` as a SymPy expression: ``cos``/``sin`` of the cumulative angles, grouped by the length monomial."""
        b = self.basis
        trig_of = []
        for psi in b.from_psi:
            trig_of += [sp.cos(b.from_psi[psi]), sp.sin(b.from_psi[psi])]
        gens_expr = trig_of + self.gens[self.n_trig:]
        dom = self.ring.domain
        split = self.n_trig + self.n_params
        by_len: dict[tuple, list[sp.Expr]] = {}
        items: list[tuple[tuple, Any, sp.Expr]] = [(m, dom.to_sympy(c), sp.Integer(1)) for m, c in p.items()]
        if not (dom.is_ZZ or dom.is_QQ):          # sqrt(3)/2 cos + 1/2 sin (a base turned by 30 deg): one cosine
            items = self._shifted(items, trig_of)
        for mon, c, extra in items:
            factors = [c, extra]
            factors += [g ** k for g, k in zip(gens_expr[:self.n_trig], mon[:self.n_trig]) if k]
            factors += [g ** k for g, k in zip(gens_expr[split:], mon[split:]) if k]
            by_len.setdefault(mon[self.n_trig:split], []).append(sp.Mul(*factors))
        terms = [sp.Add(*parts) * sp.Mul(*(s ** k for s, k in zip(self.params, key) if k))
                 for key, parts in by_len.items()]
        return sp.factor_terms(sp.Add(*terms))


    def _shifted(self, items: list[tuple[tuple, Any, sp.Expr]], trig_of: list[sp.Expr]
                 ) -> list[tuple[tuple, Any, sp.Expr]]:
        """Pairs of terms ``m (a C_k + b S_k)`` with ``a = r cos(delta)``, ``b = -r sin(delta)``, ``r`` rational and
        ``delta`` a rational multiple of pi, written ``r m cos(phi_k + delta)`` (a turned base or tool, whose angle
        is not a joint's)."""
        b = self.basis
        phis = list(b.from_psi.values())
        for k, (ic, is_) in enumerate(self.pairs):
            by_rest: dict[tuple, dict[int, int]] = {}
            for i, (mon, _, extra) in enumerate(items):
                if extra == 1 and (mon[ic], mon[is_]) in ((1, 0), (0, 1)):
                    rest = mon[:ic] + (0, 0) + mon[is_ + 1:]
                    by_rest.setdefault(rest, {})[ic if mon[ic] else is_] = i
            drop: set[int] = set()
            new: list[tuple[tuple, Any, sp.Expr]] = []
            for rest, where in by_rest.items():
                if len(where) != 2:
                    continue
                a, s = items[where[ic]][1], items[where[is_]][1]
                r = sp.sqrt(sp.expand(a ** 2 + s ** 2))
                if not r.is_Rational:
                    continue
                delta = sp.atan2(-s / r, a / r)
                if not (delta / sp.pi).is_Rational or delta == 0:
                    continue
                drop.update(where.values())
                new.append((rest, r, sp.cos(phis[k] + delta)))
            items = [it for i, it in enumerate(items) if i not in drop] + new
        return items


def _matmul(A: list[list[PolyElement]], B: list[list[PolyElement]],
            reduce: Callable[[PolyElement], PolyElement]) -> list[list[PolyElement]]:
    """``A B`` of two 4x4 matrices of ring elements, every entry reduced."""
    return [[reduce(sum((A[i][k] * B[k][j] for k in range(4)), A[i][0].ring.zero)) for j in range(4)]
            for i in range(4)]


def chain(convention: str, links: Sequence[sp.Matrix], base: sp.Matrix, tool: sp.Matrix, basis: AngleBasis,
          params: Sequence[sp.Symbol], prismatic_q: Sequence[sp.Symbol], prismatic: Sequence[bool]
          ) -> tuple[sp.Matrix, sp.Matrix] | None:
    """``T = base A_1 ... A_n tool`` and the geometric Jacobian, simplified in the angle sums; None if not covered.

    The Jacobian is the one of :func:`~armkit.symbolic.derive`: column ``k`` is ``(z x (p_e - p), z)`` of the frame
    before joint ``k``'s motion (``(z, 0)`` for a prismatic joint), rows ``(v, omega)`` in the base frame.
    """
    ring = _Ring(basis, params, prismatic_q)
    mats = [base, *links, tool]
    flat = ring.make([e for M in mats for e in M])
    if flat is None:
        return None
    P = [[[flat[16 * m + 4 * i + j] for j in range(4)] for i in range(4)] for m in range(len(mats))]
    frames = [P[0]]
    for A in P[1:-1]:
        frames.append(_matmul(frames[-1], A, ring.reduce))
    T = _matmul(frames[-1], P[-1], ring.reduce)
    p_e = [T[i][3] for i in range(3)]
    cols = []
    for k in range(len(links)):
        F = frames[k] if convention == "standard" else frames[k + 1]
        z = [F[i][2] for i in range(3)]
        if prismatic[k]:
            cols.append(z + [ring.ring.zero] * 3)
            continue
        r = [p_e[i] - F[i][3] for i in range(3)]
        v = [z[1] * r[2] - z[2] * r[1], z[2] * r[0] - z[0] * r[2], z[0] * r[1] - z[1] * r[0]]
        cols.append([ring.reduce(x) for x in v] + z)
    Te = sp.Matrix(4, 4, lambda i, j: ring.to_expr(T[i][j]))
    J = sp.Matrix(6, len(links), lambda i, j: ring.to_expr(cols[j][i]))
    return Te, J
