r"""The closed-form IK as equations a report can show: text or LaTeX (``armkit derive ROBOT --ik [--latex]``).

The equations are the ones :func:`armkit.symbolic.ik2r.derive_planar_2r_ik` derives with SymPy
from the FK equations (the same ones :mod:`armkit.symbolic.ik_export` turns into Python):

* a planar 2R arm (``planar2``):
  :math:`c_2 = (x^2 + y^2 - a_1^2 - a_2^2) / (2 a_1 a_2)`, :math:`s_2 = \pm\sqrt{1 - c_2^2}`,
  :math:`q_2 = \operatorname{atan2}(s_2, c_2)`,
  :math:`q_1 = \operatorname{atan2}(y (a_1 + a_2 c_2) - x a_2 s_2,\ x (a_1 + a_2 c_2) + y a_2 s_2)`;
* a yaw-pitch-pitch arm (``fighter``, ``examples/my_arm.toml``): the yaw
  :math:`q_1 = \operatorname{atan2}(y, x)` (front) or that plus :math:`\pi` (back), then the 2R
  solution in the arm's plane with :math:`r = \pm\sqrt{x^2 + y^2}`, :math:`s = z - d_1`. A tool
  offset along the last link's x axis is the last link's length (folded into :math:`a_3`).

Branch names are :func:`armkit.ik_all`'s (``IKResult.branch``); each branch says which sign of
the square root it takes. For a planar 2R arm ``ik_all`` names the branch by the picture
(elbow above or below the line from the shoulder to the target), so the sign that is
``elbow-down`` is :math:`s_2 \ge 0` for :math:`x \ge 0` and :math:`s_2 \le 0` for :math:`x < 0`.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..errors import ArgumentError
from ..model.robot import Robot
from .ik2r import derive_planar_2r_ik
from .ik_export import ik_export_kind

__all__ = ["IKEquations", "ik_equations", "equations_text", "equations_latex"]


@dataclass(frozen=True)
class IKEquations:
    """The closed-form IK of one arm as equations, each as text and as LaTeX.

    Attributes
    ----------
    robot_name, kind, unit : str
        ``kind`` is ``"planar-2r"`` or ``"yaw-pitch-pitch"``.
    steps : tuple of (str, str, str, str)
        ``(lhs, rhs, lhs_latex, rhs_latex)`` in the order a student computes them.
    branches : tuple of (str, str, str)
        ``(IKResult.branch name, the signs it takes as text, the same in LaTeX math)``.
    reachable : tuple of (str, str)
        Where a solution exists, as text and as LaTeX math.
    parameters : dict of str to float
        The lengths, in ``unit``.
    """

    robot_name: str
    kind: str
    unit: str
    steps: tuple[tuple[str, str, str, str], ...]
    branches: tuple[tuple[str, str, str], ...]
    reachable: tuple[str, str]
    parameters: dict[str, float]


def _folded_tool(robot: Robot) -> Robot:
    """``robot`` with a tool offset along the last link's x axis folded into its length ``a_n`` (standard DH)."""
    T = robot.tool
    if not (robot.is_dh and robot.convention == "standard" and np.allclose(T[:3, :3], np.eye(3))
            and np.allclose(T[1:3, 3], 0.0) and T[0, 3] != 0.0):
        return robot
    last = robot.joints[-1]
    try:
        return dataclasses.replace(robot, joints=(*robot.joints[:-1], dataclasses.replace(last, a=last.a + T[0, 3])),
                                   tool=np.eye(4))
    except (TypeError, ValueError):   # a robot that cannot be rebuilt this way keeps its tool
        return robot


def _step(lhs: str, rhs: sp.Expr | str, lhs_tex: str | None = None, rhs_tex: str | None = None
          ) -> tuple[str, str, str, str]:
    if isinstance(rhs, str):
        return lhs, rhs, lhs_tex or lhs, rhs_tex or rhs
    return lhs, sp.sstr(rhs), lhs_tex or sp.latex(sp.Symbol(lhs)), sp.latex(rhs)


def ik_equations(robot: Robot) -> IKEquations:
    """The closed-form IK equations of a planar 2R or a yaw-pitch-pitch arm.

    Raises
    ------
    ArgumentError
        The arm is neither (the message names the two layouts).

    Examples
    --------
    >>> import armkit
    >>> eq = ik_equations(armkit.load("planar2"))
    >>> [lhs for lhs, *_ in eq.steps]
    ['c2', 's2', 'q2', 'q1']
    """
    r = _folded_tool(robot)
    kind = ik_export_kind(r)
    if kind is None:
        raise ArgumentError.of("closed-form IK equations are written for planar 2R arms (like planar2) and "
                               "yaw-pitch-pitch arms (like fighter, or examples/my_arm.toml); robot {robot!r} is "
                               "neither (armkit ik solves it numerically or by its own closed form)", robot=robot.name)
    ik = derive_planar_2r_ik()
    c_s, s_s = ik.c2s2
    steps: tuple[tuple[str, str, str, str], ...]
    branches: tuple[tuple[str, str, str], ...]
    if kind == "planar-2r":
        params = {"a1": float(r.joints[0].a), "a2": float(r.joints[1].a)}
        steps = (_step("c2", ik.c2), _step("s2", "±sqrt(1 - c2**2)", "s_{2}", r"\pm\sqrt{1 - c_{2}^{2}}"),
                 _step("q2", sp.atan2(s_s, c_s)), _step("q1", ik.q1_compact))
        branches = (("elbow-down", "s2 = +sqrt(1 - c2**2) where x >= 0, -sqrt(1 - c2**2) where x < 0",
                     r"s_{2} = \sqrt{1 - c_{2}^{2}}\ (x \ge 0),\quad s_{2} = -\sqrt{1 - c_{2}^{2}}\ (x < 0)"),
                    ("elbow-up", "s2 = -sqrt(1 - c2**2) where x >= 0, +sqrt(1 - c2**2) where x < 0",
                     r"s_{2} = -\sqrt{1 - c_{2}^{2}}\ (x \ge 0),\quad s_{2} = \sqrt{1 - c_{2}^{2}}\ (x < 0)"))
        reach = ("|a1 - a2| <= sqrt(x**2 + y**2) <= a1 + a2",
                 r"\left|a_{1} - a_{2}\right| \le \sqrt{x^{2} + y^{2}} \le a_{1} + a_{2}")
        return IKEquations(robot.name, kind, robot.unit, steps, branches, reach, params)
    a2, a3 = sp.symbols("a2 a3", positive=True)
    rr, ss, c3, s3 = sp.symbols("r s c3 s3", real=True)
    sub = {ik.x: rr, ik.y: ss, ik.a1: a2, ik.a2: a3, c_s: c3, s_s: s3}
    params = {"d1": float(r.joints[0].d), "a2": float(r.joints[1].a), "a3": float(r.joints[2].a)}
    x, y = sp.symbols("x y", real=True)
    yaw = sp.latex(sp.atan2(y, x))
    steps = (_step("q1", "atan2(y, x)  (front)  or  atan2(y, x) + pi  (back)", "q_{1}",
                   rf"{yaw}\ \text{{(front)}}\ \text{{or}}\ {yaw} + \pi\ \text{{(back)}}"),
             _step("r", "+sqrt(x**2 + y**2)  (front)  or  -sqrt(x**2 + y**2)  (back)", "r",
                   r"\pm\sqrt{x^{2} + y^{2}}\ (+\ \text{front},\ -\ \text{back})"),
             _step("s", "z - d1", "s", "z - d_{1}"),
             _step("c3", ik.c2.xreplace(sub)), _step("s3", "±sqrt(1 - c3**2)", "s_{3}", r"\pm\sqrt{1 - c_{3}^{2}}"),
             _step("q3", sp.atan2(s3, c3)), _step("q2", ik.q1_compact.xreplace(sub)))
    root = r"\sqrt{1 - c_{3}^{2}}"
    branches = (("front/elbow-down", "front, s3 = +sqrt(1 - c3**2)", rf"\text{{front}},\ s_{{3}} = {root}"),
                ("front/elbow-up", "front, s3 = -sqrt(1 - c3**2)", rf"\text{{front}},\ s_{{3}} = -{root}"),
                ("back/elbow-up", "back, s3 = +sqrt(1 - c3**2)", rf"\text{{back}},\ s_{{3}} = {root}"),
                ("back/elbow-down", "back, s3 = -sqrt(1 - c3**2)", rf"\text{{back}},\ s_{{3}} = -{root}"))
    reach = ("|a2 - a3| <= sqrt(r**2 + s**2) <= a2 + a3",
             r"\left|a_{2} - a_{3}\right| \le \sqrt{r^{2} + s^{2}} \le a_{2} + a_{3}")
    return IKEquations(robot.name, kind, robot.unit, steps, branches, reach, params)


_INTRO = {"planar-2r": ("x = a1 c1 + a2 c12, y = a1 s1 + a2 s12",
                        r"$x = a_{1} c_{1} + a_{2} c_{12}$, $y = a_{1} s_{1} + a_{2} s_{12}$"),
          "yaw-pitch-pitch": ("r = a2 c2 + a3 c23, s = a2 s2 + a3 s23 in the arm's plane",
                              r"$r = a_{2} c_{2} + a_{3} c_{23}$, $s = a_{2} s_{2} + a_{3} s_{23}$ in the arm's plane")}


def equations_text(eq: IKEquations) -> str:
    """The equations as plain text, one per line, then the branches and where the arm reaches."""
    params = ", ".join(f"{k} = {v:g} {eq.unit}" for k, v in eq.parameters.items())
    lines = [f"Closed-form IK of {eq.robot_name} ({eq.kind}), derived with sympy.solve from {_INTRO[eq.kind][0]}",
             f"parameters: {params}", ""]
    lines += [f"  {lhs} = {rhs}" for lhs, rhs, _, _ in eq.steps]
    lines += ["", "branches (the names armkit ik gives them):"]
    lines += [f"  {name}: {signs}" for name, signs, _ in eq.branches]
    lines += ["", f"reachable where {eq.reachable[0]}", ""]
    return "\n".join(lines)


def equations_latex(eq: IKEquations, standalone: bool = True) -> str:
    r"""The equations as LaTeX (``align*``, needs ``amsmath``); ``standalone=False`` gives a fragment to paste into
    a report (no ``\documentclass``, no ``\begin{document}``)."""
    name = eq.robot_name.replace("_", r"\_")
    params = ", ".join(f"${sp.latex(sp.Symbol(k))} = {v:g}$ {eq.unit}" for k, v in eq.parameters.items())
    body = [f"% Closed-form IK of '{eq.robot_name}' ({eq.kind}), generated by armkit",
            r"\subsection*{Closed-form inverse kinematics of \texttt{" + name + "}}",
            f"Derived with SymPy from {_INTRO[eq.kind][1]}. Parameters: {params}.", r"\begin{align*}"]
    rows = [f"  {lt} &= {rt}" for _, _, lt, rt in eq.steps]
    body += [row + r" \\" for row in rows[:-1]] + [rows[-1], r"\end{align*}"]
    body += [r"Branches (the names \texttt{armkit ik} gives them):", r"\begin{itemize}"]
    body += [r"  \item \texttt{" + n + "}: $" + tex + "$" for n, _, tex in eq.branches]
    body += [r"\end{itemize}", f"Reachable where ${eq.reachable[1]}$.", ""]
    text = "\n".join(body)
    if not standalone:
        return text
    return "\\documentclass{article}\n\\usepackage{amsmath}\n\\begin{document}\n" + text + "\\end{document}\n"
