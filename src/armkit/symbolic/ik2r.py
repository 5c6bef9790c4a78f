r"""Closed-form IK of the planar 2R arm, derived by solving the FK equations with SymPy.

The equations are :math:`x = a_1 c_1 + a_2 c_{12}`, :math:`y = a_1 s_1 + a_2 s_{12}`.

1. Square and add: :math:`x^2 + y^2 = a_1^2 + a_2^2 + 2 a_1 a_2 c_2`; ``sympy.solve`` gives
   :math:`c_2`, and :math:`s_2 = \pm\sqrt{1 - c_2^2}` gives the two branches
   (``+``: elbow down for a counter-clockwise arm, ``q2 > 0``; ``-``: elbow up).
2. With :math:`q_2` known the equations are linear in :math:`c_1, s_1`:
   :math:`x = (a_1 + a_2 c_2) c_1 - a_2 s_2 s_1`, :math:`y = a_2 s_2 c_1 + (a_1 + a_2 c_2) s_1`;
   ``sympy.solve`` gives both, and :math:`q_1 = \operatorname{atan2}(s_1, c_1)` (the common
   positive denominator :math:`x^2 + y^2` cancels).
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

__all__ = ["PlanarIK", "derive_planar_2r_ik"]


@dataclass(frozen=True)
class PlanarIK:
    """Both IK branches of a planar 2R arm.

    Attributes
    ----------
    x, y, a1, a2 : sympy.Symbol
    c2 : sympy.Expr
        :math:`\\cos q_2` as a function of ``x, y``.
    branches : tuple of (str, sympy.Expr, sympy.Expr)
        ``(label, q1, q2)`` for ``q2 >= 0`` ("elbow down", ``s2 = +sqrt(1 - c2^2)``) and ``q2 <= 0`` ("elbow up").
    reachable : sympy.Expr
        The condition :math:`|a_1 - a_2| \\le \\sqrt{x^2 + y^2} \\le a_1 + a_2` (as ``c2**2 <= 1``).
    q1_compact : sympy.Expr
        :math:`q_1` in terms of the symbols ``c2, s2`` (``c2s2``), as a student writes it:
        ``atan2(y (a1 + a2 c2) - x a2 s2, x (a1 + a2 c2) + y a2 s2)``.
    """

    x: sp.Symbol
    y: sp.Symbol
    a1: sp.Symbol
    a2: sp.Symbol
    c2: sp.Expr
    branches: tuple[tuple[str, sp.Expr, sp.Expr], ...]
    reachable: sp.Expr
    q1_compact: sp.Expr
    c2s2: tuple[sp.Symbol, sp.Symbol]

    def numeric(self, a1: float, a2: float):
        """NumPy functions ``f(x, y) -> (q1, q2)`` for each branch (NaN where unreachable)."""
        out = []
        for label, q1, q2 in self.branches:
            f = sp.lambdify((self.x, self.y), (q1.subs({self.a1: a1, self.a2: a2}),
                                               q2.subs({self.a1: a1, self.a2: a2})), modules="numpy")
            out.append((label, f))
        return out


def derive_planar_2r_ik() -> PlanarIK:
    """Solve :math:`x = a_1 c_1 + a_2 c_{12},\\ y = a_1 s_1 + a_2 s_{12}` for both branches.

    Examples
    --------
    >>> ik = derive_planar_2r_ik()
    >>> ik.c2
    (-a1**2 - a2**2 + x**2 + y**2)/(2*a1*a2)
    >>> [label for label, _, _ in ik.branches]
    ['elbow down (q2 >= 0)', 'elbow up (q2 <= 0)']
    """
    x, y = sp.symbols("x y", real=True)
    a1, a2 = sp.symbols("a1 a2", positive=True)
    c1, s1, c2, s2 = sp.symbols("c1 s1 c2 s2", real=True)
    # FK with cos(q1 + q2) = c1 c2 - s1 s2 and sin(q1 + q2) = s1 c2 + c1 s2
    ex = a1 * c1 + a2 * (c1 * c2 - s1 * s2) - x
    ey = a1 * s1 + a2 * (s1 * c2 + c1 * s2) - y
    # step 1: x^2 + y^2 with c1^2 + s1^2 = 1 and c2^2 + s2^2 = 1 eliminates q1
    r2 = sp.expand((ex + x) ** 2 + (ey + y) ** 2)
    r2 = sp.expand(r2.subs(s1 ** 2, 1 - c1 ** 2).subs(s2 ** 2, 1 - c2 ** 2))
    (c2_sol,) = sp.solve(sp.Eq(r2, x ** 2 + y ** 2), c2)
    c2_sol = sp.factor(c2_sol)
    # step 2: with c2, s2 kept as symbols the equations are linear in c1, s1
    lin = sp.solve([ex, ey], [c1, s1], dict=True)[0]
    den = sp.factor(sp.denom(sp.together(lin[c1])))          # x**2 + y**2 after using c2**2 + s2**2 = 1
    num_s1 = sp.collect(sp.expand(sp.numer(sp.together(lin[s1]))), [x, y])
    num_c1 = sp.collect(sp.expand(sp.numer(sp.together(lin[c1]))), [x, y])
    # the denominator a1**2 + 2 a1 a2 c2 + a2**2 = x**2 + y**2 is positive: it cancels inside atan2
    q1_compact = sp.atan2(num_s1, num_c1)
    branches = []
    for label, sign in (("elbow down (q2 >= 0)", 1), ("elbow up (q2 <= 0)", -1)):
        s2_sol = sign * sp.sqrt(1 - c2_sol ** 2)
        q2 = sp.atan2(s2_sol, c2_sol)
        q1 = q1_compact.subs({c2: c2_sol, s2: s2_sol})
        branches.append((label, q1, q2))
    del den
    reachable = sp.Le(c2_sol ** 2, 1)
    return PlanarIK(x, y, a1, a2, c2_sol, tuple(branches), reachable, q1_compact, (c2, s2))
