r"""6R arms with a spherical wrist (Pieper's case; the Puma 560): 8 branches.

Structure (standard DH after :func:`~._common.standard_form`): joint 1 vertical with a
+-90 deg twist, joints 2 and 3 parallel (``alpha_2 = 0``), ``alpha_3, alpha_4, alpha_5 = +-90``
deg and ``a_4 = a_5 = d_5 = 0``, so that axes 4, 5 and 6 meet in the wrist centre
``p_w``, the origin of frame 4 (``d_4`` along ``z_3``). Then

1. ``p_w = p - d_6 z`` (``p, z``: position and approach axis of the last turning frame);
2. joints 1-3 place ``p_w``: a yaw-pitch-pitch problem for the point
   ``v = (a_3, -s_3 d_4, d_3)`` of frame 2 (see :mod:`.yaw_pitch_pitch`), 4 branches
   (shoulder right/left x elbow up/down);
3. joints 4-6 give the rest of the rotation,
   ``M = R_{03}^T R = R_z(q_4) R_x(\alpha_4) R_z(q_5) R_x(\alpha_5) R_z(q_6)``, whose third column is
   ``(s_5 \sin q_5 \cos q_4,\ s_5 \sin q_5 \sin q_4,\ -s_4 s_5 \cos q_5)``: two branches (noflip:
   ``sin q_5 >= 0``; flip: ``sin q_5 <= 0``), and ``q_6`` from what remains.

At the wrist singularity (``sin q_5 = 0``) only ``q_4 +- q_6`` matters: the solver takes
``q_4`` from ``q0`` and says so.

A DH table may reverse joint 3 (axes 2 and 3 parallel but opposite, ``alpha_2 = 180`` deg: the Kinova
Jaco2's). The solver then works on the same arm with joint 3 turned back
(:meth:`~._common.StandardForm.reversed_joint`) and gives ``-phi_3``.

References
----------
D. L. Pieper, "The kinematics of manipulators under computer control", PhD thesis,
Stanford, 1968. R. P. Paul, B. Shimano and G. E. Mayer, "Kinematic control equations for
simple manipulators", IEEE Trans. SMC 11(6), 1981.
"""

from __future__ import annotations

import math
from functools import cached_property

import numpy as np

from . import _layout as L

from ._common import Array, Raw, StandardForm, add_messages, jit_kernels, rotate_back
from .yaw_pitch_pitch import Positioner

_LABELS = np.array([f"{s}/elbow-{e}/{w}" for s in ("left", "right") for e in ("down", "up")
                    for w in ("flip", "noflip")], dtype=object)
WRIST_SINGULAR = 1e-12
_W = np.array([1.0, -1.0])   # noflip, flip
_FRONT_FLIP = 4 * np.array([1, 1, 0, 0])[None, :, None] + (_W > 0).astype(int)[None, None, :]   # label index parts


class SphericalWrist:
    """Closed form for 6R arms whose first three joints form a Puma-like arm and whose
    last three axes meet in a point."""

    family = "spherical-wrist"
    branch_labels = tuple(_LABELS)
    pose_only = True
    target_kind = "pose"
    m = 8

    def __init__(self, sf: StandardForm, pos: Positioner, signs: tuple[int, int, int], unit: str, names,
                 work: StandardForm | None = None, turned_back: tuple[int, ...] = ()):
        self.sf, self.pos, self.unit, self.names = sf, pos, unit, names
        self.work = sf if work is None else work   # the arm solved: sf, or sf with joint 3 turned back
        self.turned_back = turned_back             # (3,) then (StandardForm.turned_back; armkit info names it)
        self.f3 = -1.0 if 3 in turned_back else 1.0   # phi_3 of sf = f3 * phi_3 of work
        self.s3, self.s4, self.s5 = signs
        self._cs = np.array([[math.cos(self.work.alpha[i]), math.sin(self.work.alpha[i])] for i in (0, 2, 3, 4)])

    @classmethod
    def detect(cls, sf: StandardForm, robot) -> "SphericalWrist | None":
        if sf.n != 6:
            return None
        turned = sf.turned_back((2,))   # joint 3 reversed in the table: solve the arm with it turned back
        if turned is not None:
            found = cls.detect(turned[0], robot)
            return None if found is None else cls(sf, found.pos, (found.s3, found.s4, found.s5), robot.unit,
                                                  robot.joint_names, *turned)
        twists = (sf.twist(2), sf.twist(3), sf.twist(4))
        if any(s not in (1, -1) for s in twists):
            return None
        signs = (int(twists[0] or 0), int(twists[1] or 0), int(twists[2] or 0))
        if not (sf.is_zero(sf.a[3]) and sf.is_zero(sf.a[4]) and sf.is_zero(sf.d[4])):
            return None
        v = np.array([sf.a[2], -signs[0] * sf.d[3], sf.d[2]])
        pos = Positioner.build(sf, v)
        return None if pos is None else cls(sf, pos, signs, robot.unit, robot.joint_names)

    @cached_property
    def geometry(self) -> Array:
        """The packed geometry of the Numba kernel (layout ``_layout.POS_*`` then ``SW_*``), built once."""
        g = self.pos.geometry(L.SW_SIZE, self.work)
        g[L.SW_D6], g[L.SW_S4], g[L.SW_S5], g[L.SW_F3] = self.work.d[5], self.s4, self.s5, self.f3
        g[L.SW_CS:L.SW_CS + 8] = self._cs.reshape(8)
        g.setflags(write=False)
        return g

    def _solve_numpy(self, target: Array, q0phi: Array) -> tuple[Array, Array, dict]:
        sf = self.work
        B = len(target)
        Tc = sf.to_chain(target)
        R = Tc[:, :3, :3]
        pw = Tc[:, :3, 3] - sf.d[5] * R[:, :, 2]
        sol = self.pos.solve(pw, q0phi[:, 0])
        phi = sol["phi"]                                                  # (B, 4, 3)
        # M = R03^T R, column by column: R03^T v = Rx(-alpha3) Rz(-(q2 + q3)) Rx(-alpha1) Rz(-q1) v
        zc = [R[:, None, i, 2] for i in range(3)]
        xc = [R[:, None, i, 0] for i in range(3)]
        back = lambda v: rotate_back(rotate_back(v, phi[..., 0], sf.alpha[0]),  # noqa: E731
                                     phi[..., 1] + phi[..., 2], sf.alpha[2])
        Mz, Mx = back(zc), back(xc)                                       # third and first columns of M
        h = np.hypot(Mz[0], Mz[1])
        w = _W
        phi5 = np.arctan2(w * h[..., None], (-self.s4 * self.s5 * Mz[2])[..., None])
        singular = h <= WRIST_SINGULAR
        phi4 = np.where(singular[..., None], q0phi[:, None, 3:4],
                        np.arctan2((w * self.s5) * Mz[1][..., None], (w * self.s5) * Mz[0][..., None]))
        # q6 from what is left: P^T M e1 = Rz(q6) e1 with P = Rz(q4) Rx(alpha4) Rz(q5) Rx(alpha5)
        rest = rotate_back(rotate_back([m[..., None] for m in Mx], phi4, sf.alpha[3]), phi5, sf.alpha[4])
        phi6 = np.arctan2(rest[1], rest[0])
        out = np.empty((B, 4, 2, 6))
        out[..., :3] = phi[:, :, None, :]
        out[..., 2] *= self.f3
        out[..., 3], out[..., 4], out[..., 5] = phi4, phi5, phi6
        return out, singular, sol

    def reach_why(self, lateral_out: bool, rho: float, r: float, target: Array | None) -> str:
        """Why a branch is out of reach, from the numbers of the kernel (:meth:`Positioner.reach_why`)."""
        return self.pos.reach_why(lateral_out, rho, r, self.unit, "the wrist centre", "first joint's")

    def branches(self, target: Array, q0phi: Array) -> tuple[Array, Array]:
        """:meth:`solve`'s DH angles ``(B, 8, 6)`` and label indices into :attr:`branch_labels` ``(B, 8)``, without
        its sentences and notes: what names another family's branches (``Geometric.name_branches``)."""
        B = len(target)
        jit = jit_kernels()
        if jit is not None:
            out, idx, _, _ = jit.spherical_wrist(np.ascontiguousarray(target), self.geometry,
                                                 np.ascontiguousarray(q0phi))
        else:
            out, _, sol = self._solve_numpy(target, q0phi)
            idx = _FRONT_FLIP + 2 * sol["up"].astype(int)[:, :, None]
        return out.reshape(B, 8, 6), idx.reshape(B, 8)

    def solve(self, target: Array, q0phi: Array) -> Raw:
        sf = self.sf
        B = len(target)
        jit = jit_kernels()
        if jit is not None:
            out, idx, singular, arrays = jit.spherical_wrist(np.ascontiguousarray(target), self.geometry,
                                                             np.ascontiguousarray(q0phi))
            sol = self.pos.as_dict(arrays)
        else:
            out, singular, sol = self._solve_numpy(target, q0phi)
            idx = _FRONT_FLIP + 2 * sol["up"].astype(int)[:, :, None]
        why4, note4 = self.pos.explain(sol, self.unit, "the wrist centre", "first joint's")
        why = lambda i: why4(i // 2)  # noqa: E731  (flat (B, 8) -> flat (B, 4))
        note = np.repeat(note4, 2, axis=1) if note4.any() else np.full((B, 8), "", dtype=object)
        unreachable = np.repeat(sol["unreachable"], 2, axis=1)
        n1, n4 = self.names[0], self.names[3]
        if sol["on_axis"].any():
            on_axis = np.repeat(sol["on_axis"][:, None], 8, axis=1)
            add_messages(note, on_axis & ~unreachable, lambda i: (
                f"the wrist centre is on the first joint's axis: {n1} is free; giving {n1} from q0."))
        if singular.any():
            sing = np.repeat(singular, 2, axis=1) & ~unreachable
            add_messages(note, sing, lambda i: (
                f"wrist singularity (axes 4 and 6 aligned): only {n4} +- {self.names[5]} is fixed; "
                f"giving {n4} from q0, and the flip and noflip branches coincide."))
        return Raw(out.reshape(B, 8, 6), _LABELS[idx.reshape(B, 8)], unreachable, why, note)
