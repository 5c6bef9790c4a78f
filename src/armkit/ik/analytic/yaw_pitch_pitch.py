r"""Yaw-pitch-pitch arms (the fighter arm of the club's fighting-robot report): 4 branches, front/back x elbow-up/down.

Geometry (standard DH after :func:`~._common.standard_form`): joint 1 turns about the
vertical axis ``z0`` and its twist is +-90 deg (sign ``s``), joints 2 and 3 are parallel
(``alpha_2 = 0``). A point ``v`` fixed in the last turning frame (the tool point, or the
Puma's wrist centre) then obeys

.. math::

    p = R_z(\varphi_1) \begin{pmatrix} a_1 + X \\ -s Z \\ d_1 + s Y \end{pmatrix},\qquad
    (X, Y) = a_2 e(\varphi_2) + \ell e(\varphi_2 + \varphi_3 + \beta)

with the lateral offset ``Z = d_2 + v_z`` and ``(v_x, v_y) = \ell e(\beta)``. So with
``rho = |(p_x, p_y)|``: ``a_1 + X = +-sqrt(rho^2 - Z^2)`` (front/back),
``phi_1 = atan2(p_y, p_x) - atan2(-s Z, a_1 + X)``, ``Y = s (p_z - d_1)``, and ``(X, Y)`` is
a planar two-link problem (:func:`~._common.two_link`).

On the yaw axis (``rho = 0`` with no lateral offset) every yaw angle works: the solver
returns the family member with the yaw of ``q0`` and says so.

A DH table may reverse joint 3 (``alpha_2 = 180`` deg: the two pitch axes parallel but opposite, as a club's
table gets them when it points ``z_2`` the other way). The solver then works on the same arm with joint 3 turned
back (:meth:`~._common.StandardForm.reversed_joint`) and gives ``-phi_3``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from . import _layout as L

from ._common import (LENGTH_TOL, Array, Raw, StandardForm, add_messages, elbow_edge, elbow_up, forward_sign,
                      jit_kernels, out_of_reach, two_link)

_FRONT = np.array([True, True, False, False])
_LABELS = np.array(["back/elbow-down", "back/elbow-up", "front/elbow-down", "front/elbow-up"], dtype=object)


@dataclass(frozen=True)
class Positioner:
    """The three-joint positioning geometry shared by the fighter arm and Pieper arms."""

    s1: int
    d1: float
    a1: float
    a2: float
    Z: float
    ell: float
    beta: float
    scale: float

    @classmethod
    def build(cls, sf: StandardForm, v: Array) -> "Positioner | None":
        s1 = sf.twist(0)
        if s1 not in (1, -1) or sf.twist(1) != 0:
            return None
        ell = math.hypot(v[0], v[1])
        if sf.is_zero(sf.a[1]) or sf.is_zero(ell):
            return None
        return cls(s1, float(sf.d[0]), float(sf.a[0]), float(sf.a[1]), float(sf.d[1] + v[2]), ell,
                   math.atan2(v[1], v[0]), sf.scale)

    def geometry(self, size: int, sf: StandardForm) -> Array:
        """A packed geometry array of ``size`` values (``_layout``) with the frames and the ``POS_*`` values."""
        g = L.header(size, sf.base_inv, sf.tool_inv)
        g[L.POS_S1], g[L.POS_D1], g[L.POS_A1], g[L.POS_A2] = self.s1, self.d1, self.a1, self.a2
        g[L.POS_Z], g[L.POS_ELL], g[L.POS_BETA], g[L.POS_TINY] = self.Z, self.ell, self.beta, LENGTH_TOL * self.scale
        return g

    @property
    def outer(self) -> float:
        return abs(self.a2) + self.ell

    @property
    def inner(self) -> float:
        return abs(abs(self.a2) - self.ell)

    def solve(self, p: Array, yaw0: Array) -> dict:
        """Joint angles (DH angles, offsets included) reaching point(s) ``p`` ``(B, 3)``.

        Returns a dict with ``phi`` ``(B, 4, 3)`` ordered (front, e0), (front, e1),
        (back, e0), (back, e1), ``front`` ``(4,)``, ``up`` ``(B, 4)`` elbow-up flags,
        ``unreachable`` ``(B, 4)``, ``c`` (the two-link cosine, ``(B, 2)``), ``r`` ``(B, 2)``,
        ``rho`` ``(B,)``, ``lateral_out`` ``(B,)`` and ``on_axis`` ``(B,)``.
        """
        x, y, z = p[:, 0], p[:, 1], p[:, 2]
        rho = np.hypot(x, y)
        h2 = rho * rho - self.Z * self.Z
        lateral_out = h2 < 0.0
        Xf = np.sqrt(np.maximum(h2, 0.0))
        on_axis = (rho <= LENGTH_TOL * self.scale) & (abs(self.Z) <= LENGTH_TOL * self.scale)
        psi = np.where(on_axis, yaw0, np.arctan2(y, x))
        Xs = Xf[:, None] * np.array([1.0, -1.0])                       # (B, 2): front, back
        phi1 = psi[:, None] - np.arctan2(-self.s1 * self.Z, Xs)
        X = Xs - self.a1
        Y = np.broadcast_to((self.s1 * (z - self.d1))[:, None], X.shape)
        t1, t2, c, r = two_link(X, Y, self.a2, self.ell)               # (B, 2, 2)
        B = len(p)
        phi = np.empty((B, 2, 2, 3))
        phi[..., 0] = phi1[:, :, None]
        phi[..., 1] = t1
        phi[..., 2] = t2 - self.beta
        fwd = forward_sign(X, np.array([1.0, -1.0]))                   # (B, 2)
        up = elbow_up(fwd[:, :, None], self.s1, self.a2, self.ell, np.array([0, 1]))
        unreachable = (c > 1.0) | (c < -1.0) | lateral_out[:, None]    # (B, 2)
        return {"phi": phi.reshape(B, 4, 3), "front": _FRONT,
                "up": up.reshape(B, 4), "unreachable": np.repeat(unreachable, 2, axis=1),
                "c": c, "r": r, "rho": rho, "lateral_out": lateral_out, "on_axis": on_axis}

    @staticmethod
    def as_dict(arrays: tuple) -> dict:
        """The arrays of the Numba kernel (:mod:`._jit`) as :meth:`solve` returns them."""
        phi, up, unreachable, c, r, rho, lateral_out, on_axis, edge, label = arrays
        return {"phi": phi, "front": _FRONT, "up": up, "unreachable": unreachable, "c": c, "r": r, "rho": rho,
                "lateral_out": lateral_out, "on_axis": on_axis, "edge": edge, "label": label}

    def reach_why(self, lateral_out: bool, rho: float, r: float, unit: str, what: str, first_axis: str) -> str:
        """Why a branch is out of reach: ``what`` beside the first axis (``lateral_out``) at ``rho`` from it, or
        at ``r`` from the shoulder."""
        if lateral_out:
            return (f"{what} is {rho:.6g} {unit} from the {first_axis} axis, closer than the arm's "
                    f"sideways offset of {abs(self.Z):.6g} {unit}.")
        return out_of_reach(what, r, unit, self.outer, self.inner)

    def explain(self, sol: dict, unit: str, what: str, first_axis: str):
        """``why`` (flat index into ``(B, 4)`` -> sentence) and ``note`` ``(B, 4)`` for a :meth:`solve` result."""
        B = len(sol["rho"])
        note = np.full((B, 4), "", dtype=object)
        c, r, rho = sol["c"], sol["r"], sol["rho"]

        def reach(i: int) -> str:
            b, k = divmod(i, 4)
            return self.reach_why(bool(sol["lateral_out"][b]), rho[b], r[b, k // 2], unit, what, first_axis)

        edge = sol["edge"] if "edge" in sol else np.abs(np.abs(c) - 1.0) <= 1e-9
        if edge.any():
            edge = np.repeat(edge & ~sol["unreachable"][:, ::2], 2, axis=1)
            add_messages(note, edge, lambda i: elbow_edge(c.reshape(-1)[i // 2]))
        return reach, note


class YawPitchPitch:
    """Closed form for 3R arms with a yaw joint followed by two parallel pitch joints."""

    family = "yaw-pitch-pitch"
    branch_labels = tuple(_LABELS)
    pose_only = False
    target_kind = "position"
    m = 4

    def __init__(self, sf: StandardForm, pos: Positioner, robot_unit: str, yaw_name: str,
                 work: StandardForm | None = None, turned_back: tuple[int, ...] = ()):
        self.sf, self.pos, self.unit, self.yaw_name = sf, pos, robot_unit, yaw_name
        self.work = sf if work is None else work   # the arm solved: sf, or sf with joint 3 turned back
        self.turned_back = turned_back             # (3,) then (StandardForm.turned_back; armkit info names it)
        self.f3 = -1.0 if 3 in turned_back else 1.0   # phi_3 of sf = f3 * phi_3 of work

    @classmethod
    def detect(cls, sf: StandardForm, robot) -> "YawPitchPitch | None":
        if sf.n != 3:
            return None
        turned = sf.turned_back((2,))   # joint 3 reversed in the table: solve the arm with it turned back
        if turned is not None:
            found = cls.detect(turned[0], robot)
            return None if found is None else cls(sf, found.pos, robot.unit, robot.joint_names[0], *turned)
        v = sf.tool[:3, 3] + np.array([0.0, 0.0, sf.d[2]])
        pos = Positioner.build(sf, v)
        return None if pos is None else cls(sf, pos, robot.unit, robot.joint_names[0])

    @cached_property
    def geometry(self) -> Array:
        """The packed geometry of the Numba kernel (layout ``_layout.POS_*``, then ``YPP_F3``), built once."""
        g = self.pos.geometry(L.YPP_SIZE, self.work)
        g[L.YPP_F3] = self.f3
        g.setflags(write=False)
        return g

    def reach_why(self, lateral_out: bool, rho: float, r: float, target: Array | None) -> str:
        """Why a branch is out of reach, from the numbers of the kernel (:meth:`Positioner.reach_why`)."""
        return self.pos.reach_why(lateral_out, rho, r, self.unit, "target", "yaw")

    def solve(self, target: Array, q0phi: Array) -> Raw:
        pts = target[:, :3, 3] if target.ndim == 3 else target
        jit = jit_kernels()
        if jit is not None:
            sol = self.pos.as_dict(jit.yaw_pitch_pitch(np.ascontiguousarray(pts), self.geometry,
                                                       np.ascontiguousarray(q0phi[:, 0])))
        else:
            sol = self.pos.solve(self.work.point_to_chain(pts), q0phi[:, 0])
            sol["phi"][..., 2] *= self.f3
        idx = sol["label"] if "label" in sol else 2 * sol["front"].astype(int) + sol["up"].astype(int)
        why, note = self.pos.explain(sol, self.unit, "target", "yaw")
        if not sol["on_axis"].any():
            return Raw(sol["phi"], _LABELS[idx], sol["unreachable"], why, note)
        on_axis = np.repeat(sol["on_axis"][:, None], 4, axis=1)
        yaw = sol["phi"][:, :, 0] - self.sf.theta[0]
        add_messages(note, on_axis & ~sol["unreachable"], lambda i: (
            f"on the yaw axis: any yaw angle works ({self.yaw_name} is free); giving "
            f"{self.yaw_name} = {math.degrees(math.remainder(yaw.reshape(-1)[i], 2 * math.pi)):.6g} deg "
            "(from q0, 0 by default)."), first=True)
        return Raw(sol["phi"], _LABELS[idx], sol["unreachable"], why, note)
