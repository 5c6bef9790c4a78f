r"""Planar arms: 2R, and 3R with the end angle phi.

The 2R arm is the one of the symbolic 2-link tutorial and the homogeneous-transform seminar;
the 3R arm that of the CCD graphics assignment and the modified-DH lecture.

2R: the tool point ``v`` (fixed in the last turning frame; a tool offset simply makes the
second link longer or bent) obeys ``(x, y) = a_1 e(q_1') + \ell e(q_1' + q_2' + \beta)``,
the two-link problem with both elbow branches:

.. math::

    \cos q_2 = \frac{x^2 + y^2 - a_1^2 - \ell^2}{2 a_1 \ell},\qquad
    q_1 = \operatorname{atan2}(y, x) - \operatorname{atan2}(\ell \sin q_2,\ a_1 + \ell \cos q_2)

(the homogeneous-transform seminar writes the second ``atan2`` with its arguments swapped; that is wrong).

3R: the target pose fixes the end angle ``phi = q_1 + q_2 + q_3``; removing the tool and
the last link gives the wrist point, a 2R problem for the first two links.

Labels: ``elbow-up`` when the elbow lies above the line from the shoulder to the
target (to the wrist point for 3R), "above" meaning +y of the arm's base frame; for a
target with ``x >= 0`` that is ``sin q_2 < 0``.
"""

from __future__ import annotations

import math
from functools import cached_property

import numpy as np

from ...kinematics import fk
from . import _layout as L

from ._common import (ANGLE_TOL, Array, Raw, StandardForm, add_messages, elbow_edge, elbow_up, forward_sign, jit_kernels,
                      out_of_reach, two_link)

_LABELS = np.array(["elbow-down", "elbow-up"], dtype=object)


def _explain(c: Array, r: Array, l1: float, l2: float, unit: str, what: str, flags: tuple | None = None):
    """``unreachable`` ``(B, 2)``, ``why`` and ``note`` ``(B, 2)``; ``flags``: (unreachable, stretched or
    folded ``(B,)``) when the Numba kernel has computed them."""
    B = len(c)
    if flags is not None:
        unreachable, edge1 = flags
    else:
        unreachable = np.repeat(((c > 1.0) | (c < -1.0))[:, None], 2, axis=1)
        edge1 = (np.abs(np.abs(c) - 1.0) <= 1e-9) & ~unreachable[:, 0]
    note = np.full((B, 2), "", dtype=object)
    outer, inner = abs(l1) + abs(l2), abs(abs(l1) - abs(l2))
    why = lambda i: out_of_reach(what, r[i // 2], unit, outer, inner)  # noqa: E731
    if edge1.any():
        add_messages(note, np.repeat(edge1[:, None], 2, axis=1), lambda i: elbow_edge(c[i // 2]))
    return unreachable, why, note


class Planar2R:
    """Closed form for 2R arms with parallel axes."""

    family = "planar-2r"
    branch_labels = tuple(_LABELS)
    pose_only = False
    target_kind = "position"
    m = 2

    def __init__(self, sf: StandardForm, ell: float, beta: float, unit: str, sign: int = 1):
        self.sf, self.ell, self.beta, self.unit = sf, ell, beta, unit
        self.sign = sign     # -1: antiparallel axes (alpha_1 = 180 deg), joint 2 turns the other way
        self.turned_back = (2,) if sign < 0 else ()   # the joints solved turned back (from 1; armkit info)

    @classmethod
    def detect(cls, sf: StandardForm, robot) -> "Planar2R | None":
        if sf.n != 2 or sf.is_zero(sf.a[0]):
            return None
        # parallel axes (alpha_1 = 0), or antiparallel (alpha_1 = 180 deg): Rx(pi) Rz(q2) = Rz(-q2) Rx(pi),
        # so it is the same 2R arm with q2 negated and the tool point mirrored (x, -y)
        anti = abs(abs(math.remainder(float(sf.alpha[0]), 2 * math.pi)) - math.pi) < ANGLE_TOL
        if sf.twist(0) != 0 and not anti:
            return None
        v = sf.tool[:3, 3]
        ell = math.hypot(v[0], v[1])
        sign = -1 if anti else 1
        if sf.is_zero(ell):
            return None
        solver = cls(sf, ell, math.atan2(sign * v[1], v[0]), robot.unit, sign)

        solver.z_plane = float(sf.point_to_chain(fk(robot, np.zeros(robot.n))[:3, 3])[2])   # the arm's plane in B'
        return solver

    z_plane: float | None = None

    @cached_property
    def geometry(self) -> Array:
        """The packed geometry of the Numba kernel (layout ``_layout.P2_*``), built once."""
        g = L.header(L.P2_SIZE, self.sf.base_inv, self.sf.tool_inv)
        g[L.P2_L1], g[L.P2_ELL], g[L.P2_BETA] = self.sf.a[0], self.ell, self.beta
        g.setflags(write=False)
        return g

    def _with_offset(self, why, pts: Array):
        """``why(i)`` plus how far target ``i // 2`` lies off the arm's plane, when it does."""
        z_plane = self.z_plane
        if z_plane is None:
            return why

        def explain(i: int) -> str:
            return self._off_plane(why(i), pts[i // 2])

        return explain

    def _off_plane(self, text: str, pt: Array) -> str:
        """``text`` plus how far point ``pt`` lies off the arm's plane, when it does."""
        if self.z_plane is None:
            return text
        off = abs(float(self.sf.point_to_chain(pt)[2]) - self.z_plane)
        if off > 1e-9 * max(1.0, self.sf.scale):
            text += f" The target is also {off:.6g} {self.unit} off the arm's plane."
        return text

    def reach_why(self, lateral_out: bool, rho: float, r: float, target: Array | None) -> str:
        """Why a branch is out of reach, from the target's distance ``r`` from the shoulder (the kernel's number)
        and the target ``(4, 4)`` or ``(3,)`` itself (how far off the arm's plane)."""
        text = out_of_reach("target", r, self.unit, abs(self.sf.a[0]) + abs(self.ell),
                            abs(abs(self.sf.a[0]) - abs(self.ell)))
        assert target is not None
        return self._off_plane(text, target[:3, 3] if target.ndim == 2 else target)

    def solve(self, target: Array, q0phi: Array) -> Raw:
        pts = target[:, :3, 3] if target.ndim == 3 else target
        jit = jit_kernels()
        if jit is not None:
            q, idx, c, r, unreachable, edge = jit.planar2(np.ascontiguousarray(pts), self.geometry)
            if self.sign < 0:
                q = np.array(q)
                q[..., 1] *= -1.0
            _, why, note = _explain(c, r, self.sf.a[0], self.ell, self.unit, "target", (unreachable, edge))
            return Raw(q, _LABELS[idx], unreachable, self._with_offset(why, pts), note)
        p = self.sf.point_to_chain(pts)
        t1, t2, c, r = two_link(p[:, 0], p[:, 1], self.sf.a[0], self.ell)
        q = np.stack([t1, self.sign * (t2 - self.beta)], axis=-1)            # (B, 2, 2)
        up = elbow_up(forward_sign(p[:, 0])[:, None], 1.0, self.sf.a[0], self.ell, np.array([0, 1]))
        unreachable, why, note = _explain(c, r, self.sf.a[0], self.ell, self.unit, "target")
        return Raw(q, _LABELS[up.astype(int)], unreachable, self._with_offset(why, pts), note)


class Planar3R:
    """Closed form for 3R arms with parallel axes; the target fixes the end angle."""

    family = "planar-3r"
    branch_labels = tuple(_LABELS)
    pose_only = True
    target_kind = "pose"       # or phi= (armkit.ik)
    m = 2

    def __init__(self, sf: StandardForm, unit: str):
        self.sf, self.unit = sf, unit

    @classmethod
    def detect(cls, sf: StandardForm, robot) -> "Planar3R | None":
        if sf.n != 3 or sf.twist(0) != 0 or sf.twist(1) != 0 or sf.is_zero(sf.a[0]) or sf.is_zero(sf.a[1]):
            return None
        return cls(sf, robot.unit)

    @cached_property
    def geometry(self) -> Array:
        """The packed geometry of the Numba kernel (layout ``_layout.P3_*``), built once."""
        g = L.header(L.P3_SIZE, self.sf.base_inv, self.sf.tool_inv)
        g[L.P3_L1], g[L.P3_L2] = self.sf.a[0], self.sf.a[1]
        g.setflags(write=False)
        return g

    WHAT = "for this end angle, the wrist point (target minus tool and last link)"

    def reach_why(self, lateral_out: bool, rho: float, r: float, target: Array | None) -> str:
        """Why a branch is out of reach, from the wrist point's distance ``r`` from the shoulder (the kernel's number)."""
        l1, l2 = float(self.sf.a[0]), float(self.sf.a[1])
        return out_of_reach(self.WHAT, r, self.unit, abs(l1) + abs(l2), abs(abs(l1) - abs(l2)))

    def solve(self, target: Array, q0phi: Array) -> Raw:
        l1, l2 = float(self.sf.a[0]), float(self.sf.a[1])
        what = self.WHAT
        jit = jit_kernels()
        if jit is not None:
            q, idx, c, r, unreachable, edge = jit.planar3(np.ascontiguousarray(target), self.geometry)
            _, why, note = _explain(c, r, l1, l2, self.unit, what, (unreachable, edge))
            return Raw(q, _LABELS[idx], unreachable, why, note)
        Tc = self.sf.to_chain(target)
        phi = np.arctan2(Tc[:, 1, 0], Tc[:, 0, 0])
        x, y = Tc[:, 0, 3], Tc[:, 1, 3]
        t1, t2, c, r = two_link(x, y, l1, l2)
        q = np.stack([t1, t2, phi[:, None] - t1 - t2], axis=-1)              # (B, 2, 3)
        up = elbow_up(forward_sign(x)[:, None], 1.0, l1, l2, np.array([0, 1]))
        unreachable, why, note = _explain(c, r, l1, l2, self.unit, what)
        return Raw(q, _LABELS[up.astype(int)], unreachable, why, note)
