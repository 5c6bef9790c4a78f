r"""6R arms with three parallel middle axes (the Universal Robots family): 8 branches.

Structure (standard DH after :func:`~._common.standard_form`): ``alpha = (+-90, 0, 0, +-90, +-90)``
deg for joints 1-5 (signs ``s_1, s_4, s_5``), ``a_1 = a_4 = a_5 = 0``, ``a_2, a_3, d_6`` non-zero.
Joints 2, 3 and 4 turn about parallel axes ``z_1``; every frame from 1 to 5 keeps the same
offset ``D = d_2 + d_3 + d_4`` along ``z_1``. With ``p`` and ``z`` the position and approach
axis of the last turning frame and ``p_5 = p - d_6 z`` (origin of frame 5):

1. ``s_1 (x_5 \sin q_1 - y_5 \cos q_1) = D`` gives ``q_1 = \psi + \arcsin(s_1 D / \rho)`` (right) or
   ``\psi + \pi - \arcsin(s_1 D / \rho)`` (left), ``\psi = atan2(y_5, x_5)``, ``\rho = |(x_5, y_5)|``;
2. ``z_6 \cdot z_1 = -s_4 s_5 \cos q_5`` and ``|z_6 \times z_1| = |\sin q_5|`` give ``q_5`` up to
   its sign: two branches, wrist up (``q_5 >= 0``) and down;
3. ``z_1`` seen from the last frame is ``(s_4 \sin q_5 \cos q_6, -s_4 \sin q_5 \sin q_6, \cdot)``: ``q_6``;
4. frame 4 is then known; removing joint 1 and the constant part of link 4 leaves
   ``R_z(q_2) T_x(a_2) R_z(q_3) T_x(a_3) R_z(q_4)``: a two-link problem (elbow up/down) and
   ``q_4 = (q_2 + q_3 + q_4) - q_2 - q_3``.

At the wrist singularity (``sin q_5 = 0``) axes 2, 3, 4 and 6 are parallel and only
``q_2 + q_3 + q_4 \pm q_6`` is fixed by the orientation; ``q_6`` is taken from ``q0`` when
that reaches the target. It does not always: as ``q_6`` turns, the point on joint 4's axis
moves on a circle of radius ``d_5`` in the arm's plane, so its distance from the shoulder
changes. Where the ``q0`` choice leaves the two-link reach, ``q_6`` is moved (by the least
angle) to the edge of the band of ``q_6`` that brings that point within reach
(:meth:`ParallelAxes._fix_wrist_singular`). On the base axis (``rho = 0`` with ``D = 0``)
``q_1`` is taken from ``q0``.

A DH table may point axis 3 or 4 against axis 2 (a twist of 180 deg between two of the parallel axes). The
solver then works on the same arm with joint 3 and/or 4 turned back (:meth:`~._common.StandardForm.reversed_joint`,
from joint 3 on) and gives their DH angles negated.

References
----------
K. P. Hawkins, "Analytic inverse kinematics for the Universal Robots UR-5/UR-10 arms",
Georgia Institute of Technology technical report, 2013.
"""

from __future__ import annotations

import math
from functools import cached_property

import numpy as np

from . import _layout as L

from ._common import LENGTH_TOL, Array, Raw, StandardForm, add_messages, elbow_up, forward_sign, jit_kernels, two_link

_LABELS = np.array([f"{s}/wrist-{w}/elbow-{e}" for s in ("left", "right") for w in ("down", "up")
                    for e in ("down", "up")], dtype=object)
WRIST_SINGULAR = 1e-12
_BRANCH = 4 * np.array([0, 1])[None, :, None, None] + 2 * np.array([0, 1])[None, None, :, None]


class ParallelAxes:
    """Closed form for UR-type 6R arms."""

    family = "ur"
    branch_labels = tuple(_LABELS)
    pose_only = True
    target_kind = "pose"
    m = 8

    def __init__(self, sf: StandardForm, signs: tuple[int, int, int], unit: str, names,
                 work: StandardForm | None = None, turned_back: tuple[int, ...] = ()):
        self.sf, self.unit, self.names = sf, unit, names
        self.work = sf if work is None else work   # the arm solved: sf, or sf with joints 3, 4 turned back
        self.turned_back = turned_back             # those joints, from 1 (StandardForm.turned_back; armkit info)
        # phi_3, phi_4 of sf = f3, f4 times those of work
        self.f3, self.f4 = (-1.0 if j in turned_back else 1.0 for j in (3, 4))
        self.s1, self.s4, self.s5 = signs
        self.D = float(self.work.d[1] + self.work.d[2] + self.work.d[3])

    @classmethod
    def detect(cls, sf: StandardForm, robot) -> "ParallelAxes | None":
        # axis 3 or 4 reversed in the table: turn joint 3, then joint 4, back where a twist before it is 180 deg
        turned = sf.turned_back((2, 3)) if sf.n == 6 else None
        if turned is not None:
            found = cls.detect(turned[0], robot)
            return None if found is None else cls(sf, (found.s1, found.s4, found.s5), robot.unit, robot.joint_names,
                                                  *turned)
        if sf.n != 6 or sf.twist(1) != 0 or sf.twist(2) != 0:
            return None
        signs = (sf.twist(0), sf.twist(3), sf.twist(4))
        if any(s not in (1, -1) for s in signs):
            return None
        zero = [sf.a[0], sf.a[3], sf.a[4]]
        nonzero = [sf.a[1], sf.a[2], sf.d[5]]
        if not all(sf.is_zero(x) for x in zero) or any(sf.is_zero(x) for x in nonzero):
            return None
        return cls(sf, signs, robot.unit, robot.joint_names)  # type: ignore[arg-type]

    @cached_property
    def geometry(self) -> Array:
        """The packed geometry of the Numba kernel (layout ``_layout.UR_*``), built once."""
        sf = self.work
        g = L.header(L.UR_SIZE, sf.base_inv, sf.tool_inv)
        g[L.UR_S1], g[L.UR_S4], g[L.UR_S5], g[L.UR_D] = self.s1, self.s4, self.s5, self.D
        g[L.UR_D1], g[L.UR_D4], g[L.UR_D5], g[L.UR_D6] = sf.d[0], sf.d[3], sf.d[4], sf.d[5]
        g[L.UR_A2], g[L.UR_A3], g[L.UR_TINY] = sf.a[1], sf.a[2], LENGTH_TOL * sf.scale
        g[L.UR_F3], g[L.UR_F4] = self.f3, self.f4
        g.setflags(write=False)
        return g

    def _solve_numpy(self, target: Array, q0phi: Array, want_xy: bool = False) -> tuple:
        sf, s1, s4, s5, D = self.work, self.s1, self.s4, self.s5, self.D
        d1, d4, d5, d6 = sf.d[0], sf.d[3], sf.d[4], sf.d[5]
        a2, a3 = sf.a[1], sf.a[2]
        B = len(target)
        Tc = sf.to_chain(target)
        R, p = Tc[:, :3, :3], Tc[:, :3, 3]
        p5 = p - d6 * R[:, :, 2]
        rho = np.hypot(p5[:, 0], p5[:, 1])
        on_axis = (rho <= LENGTH_TOL * sf.scale) & (abs(D) <= LENGTH_TOL * sf.scale)
        psi = np.where(on_axis, q0phi[:, 0], np.arctan2(p5[:, 1], p5[:, 0]))
        ratio = np.divide(s1 * D, rho, out=np.zeros_like(rho), where=rho > 0)
        lateral_out = np.abs(ratio) > 1.0
        asn = np.arcsin(np.clip(ratio, -1.0, 1.0))
        phi1 = np.stack([psi + math.pi - asn, psi + asn], axis=-1)         # (B, 2): left, right
        sin1, cos1 = np.sin(phi1), np.cos(phi1)
        z1x, z1y = s1 * sin1, -s1 * cos1                                   # z_1 in the base, (B, 2)
        # z_6 . z_1 = -s4 s5 cos q5 and |z_6 x z_1| = |sin q5|: atan2 keeps q5 accurate near 0 and pi
        # (the position form p . z_1 = D + d6 z_6 . z_1 is the same equation once q1 is chosen)
        z6 = R[:, None, :, 2]
        cos5 = -s4 * s5 * (z1x * z6[..., 0] + z1y * z6[..., 1])
        sin5 = np.hypot(z6[..., 2], z1x * z6[..., 1] - z1y * z6[..., 0])
        a5 = np.arctan2(sin5, cos5)                                        # (B, 2), in [0, pi]
        wsign = np.array([-1.0, 1.0])                                      # down, up
        phi5 = a5[..., None] * wsign                                       # (B, 2, 2)
        wx = R[:, None, 0, 0] * z1x + R[:, None, 1, 0] * z1y               # z_1 in the last frame
        wy = R[:, None, 0, 1] * z1x + R[:, None, 1, 1] * z1y
        singular = np.abs(np.sin(phi5)) <= WRIST_SINGULAR
        k = s4 * wsign
        phi6 = np.where(singular, q0phi[:, None, None, 5],
                        np.arctan2(-wy[..., None] * k, wx[..., None] * k))
        # frame 4 seen from the last turning frame: (A5 A6)^-1, written out (no 4x4 products)
        c5, sn5, c6, sn6 = np.cos(phi5), np.sin(phi5), np.cos(phi6), np.sin(phi6)
        x4 = (c6 * c5, -sn6 * c5, s5 * sn5)                               # x axis of frame 4
        y4 = (c6 * sn5, -sn6 * sn5, -s5 * c5)                              # y axis of frame 4
        o3 = (-s5 * d5 * sn6 - s4 * d4 * y4[0], -s5 * d5 * c6 - s4 * d4 * y4[1], -d6 - s4 * d4 * y4[2])
        Rb, pb = R[:, None, None], p[:, None, None]                        # (B, 1, 1, 3, 3), (B, 1, 1, 3)
        xw = [Rb[..., i, 0] * x4[0] + Rb[..., i, 1] * x4[1] + Rb[..., i, 2] * x4[2] for i in range(3)]
        ow = [pb[..., i] + Rb[..., i, 0] * o3[0] + Rb[..., i, 1] * o3[1] + Rb[..., i, 2] * o3[2] for i in range(3)]
        # into frame 1 (A1^-1 = Rx(-alpha1) Tz(-d1) Rz(-q1)): in-plane components (cos q1 v0 + sin q1 v1, s1 v2)
        cq1, sq1 = cos1[:, :, None], sin1[:, :, None]
        x = cq1 * ow[0] + sq1 * ow[1]
        y = s1 * (ow[2] - d1)
        total = np.arctan2(s1 * xw[2], cq1 * xw[0] + sq1 * xw[1])
        t1, t2, c, r = two_link(x, y, a2, a3)                              # (B, 2, 2, 2)
        out = np.empty((B, 2, 2, 2, 6))
        out[..., 0] = phi1[:, :, None, None]
        out[..., 1], out[..., 2] = t1, self.f3 * t2
        out[..., 3] = self.f4 * (total[..., None] - t1 - t2)
        out[..., 4] = phi5[..., None]
        out[..., 5] = phi6[..., None]
        up = elbow_up(forward_sign(x)[..., None], s1, a2, a3, np.array([0, 1]))
        elbow_out = (c > 1.0) | (c < -1.0)
        unreachable = (lateral_out[:, None, None, None] | elbow_out[..., None]
                       ) & np.ones((1, 1, 2, 2), dtype=bool)
        if want_xy:
            return x + 1j * y                                              # (B, 2, 2): joint 4's axis point
        return out, up, unreachable, lateral_out, rho, r, on_axis, singular

    def _fix_wrist_singular(self, target: Array, q0phi: Array, out: Array, idx: Array, unreachable: Array,
                            singular: Array) -> None:
        """At the wrist singularity, move ``q6`` so that joint 4's axis point comes within the arm's reach.

        ``out`` (B, 2, 2, 2, 6), ``idx`` and ``unreachable`` (B, 2, 2, 2) are updated in place for the
        (target, shoulder, wrist) branches that are singular and out of reach with ``q6`` from ``q0``.
        """
        need = np.asarray(singular, dtype=bool) & unreachable.any(axis=-1)  # (B, 2, 2)
        rows = np.flatnonzero(need.any(axis=(1, 2)))
        if len(rows) == 0:
            return
        a2, a3 = abs(float(self.sf.a[1])), abs(float(self.sf.a[2]))
        inner2, outer2 = (a2 - a3) ** 2, (a2 + a3) ** 2
        T, q0 = target[rows], q0phi[rows].copy()
        samples: list[np.ndarray] = []
        for v in (0.0, 0.5 * math.pi, math.pi):                             # the point is c + A cos q6 + B sin q6
            q0[:, 5] = v
            samples.append(np.asarray(self._solve_numpy(T, q0, want_xy=True)))
        c = 0.5 * (samples[0] + samples[2])
        A, Bv = 0.5 * (samples[0] - samples[2]), samples[1] - c
        # |c + A cos + B sin|^2 = |c|^2 + rho^2 + 2 m cos(q6 - theta) on a circle (|A| = |B|, A . B = 0)
        ca, cb = (c.conjugate() * A).real, (c.conjugate() * Bv).real
        m = np.hypot(ca, cb)
        theta = np.arctan2(cb, ca)
        base = np.abs(c) ** 2 + 0.5 * (np.abs(A) ** 2 + np.abs(Bv) ** 2)
        with np.errstate(divide="ignore", invalid="ignore"):
            lo = (inner2 * (1 + 1e-12) - base) / (2 * m)
            hi = (outer2 * (1 - 1e-12) - base) / (2 * m)
        q6_0 = q0phi[rows, 5][:, None, None]
        cur = np.cos(q6_0 - theta)
        feasible = (m > 0) & (lo <= hi) & (hi >= -1.0) & (lo <= 1.0)
        want = np.clip(np.clip(cur, lo, hi), -1.0, 1.0)
        side = np.where(np.sin(q6_0 - theta) < 0, -1.0, 1.0)
        q6 = theta + side * np.arccos(want)                                 # (R, 2, 2)
        q6 = np.remainder(q6 + math.pi, 2 * math.pi) - math.pi
        for sh in range(2):
            for wr in range(2):
                pick = need[rows, sh, wr] & feasible[:, sh, wr]
                if not pick.any():
                    continue
                sub = rows[pick]
                q0s = q0phi[sub].copy()
                q0s[:, 5] = q6[pick, sh, wr]
                o, up, unr, *_ = self._solve_numpy(target[sub], q0s)
                out[sub, sh, wr] = o[:, sh, wr]
                unreachable[sub, sh, wr] = unr[:, sh, wr]
                idx[sub, sh, wr] = _BRANCH[0, sh, wr] + up[:, sh, wr].astype(int)

    def reach_why(self, lateral_out: bool, rho: float, r: float, target: Array | None) -> str:
        """Why a branch is out of reach, from the numbers of the kernel: the wrist point beside the base axis
        (``lateral_out``) at ``rho`` from it, or the point on joint 4's axis at ``r`` from the shoulder."""
        u, a2, a3 = self.unit, self.sf.a[1], self.sf.a[2]
        if lateral_out:
            return (f"the wrist point (on joint 5's axis) is {rho:.6g} {u} from the base axis, closer "
                    f"than the shoulder offset {abs(self.D):.6g} {u}.")
        return (f"the point on joint 4's axis is {r:.6g} {u} from the shoulder; the arm "
                f"reaches {abs(a2) + abs(a3):.6g} {u} (outer) and {abs(abs(a2) - abs(a3)):.6g} {u} (inner).")

    def branches(self, target: Array, q0phi: Array) -> tuple[Array, Array] | None:
        """:meth:`solve`'s DH angles ``(B, 8, 6)`` and label indices into :attr:`branch_labels` ``(B, 8)``, without
        its sentences and notes (what names another family's branches, ``Geometric.name_branches``); None where
        :meth:`solve` must answer (no Numba, or a singular wrist, whose branches it fixes)."""
        jit = jit_kernels()
        if jit is None:
            return None
        B = len(target)
        out, idx, _, _, _, _, _, singular = jit.ur(np.ascontiguousarray(target), self.geometry,
                                                   np.ascontiguousarray(q0phi))
        if np.any(singular):
            return None
        return out.reshape(B, 8, 6), idx.reshape(B, 8)

    def solve(self, target: Array, q0phi: Array) -> Raw:
        B = len(target)
        jit = jit_kernels()
        if jit is not None:
            out, idx, unreachable, lateral_out, rho, r, on_axis, singular = jit.ur(
                np.ascontiguousarray(target), self.geometry, np.ascontiguousarray(q0phi))
        else:
            out, up, unreachable, lateral_out, rho, r, on_axis, singular = self._solve_numpy(target, q0phi)
            idx = _BRANCH + up.astype(int)
        if np.any(singular):
            out, idx, unreachable = (np.array(out).reshape(B, 2, 2, 2, 6), np.array(idx).reshape(B, 2, 2, 2),
                                     np.array(unreachable).reshape(B, 2, 2, 2))
            self._fix_wrist_singular(target, q0phi, out, idx, unreachable, np.asarray(singular).reshape(B, 2, 2))
        note = np.full((B, 2, 2, 2), "", dtype=object)
        full = lambda a: np.broadcast_to(a, (B, 2, 2, 2)).reshape(-1)  # noqa: E731

        def reason(i: int) -> str:   # i: flat index into (B, 2, 2, 2) = (target, shoulder, wrist, elbow)
            return self.reach_why(bool(lateral_out[i // 8]), rho[i // 8], r.reshape(-1)[i // 2], None)

        n1, n6 = self.names[0], self.names[5]
        if on_axis.any():
            add_messages(note, full(on_axis[:, None, None, None]).reshape(B, 2, 2, 2) & ~unreachable, lambda i: (
                f"the wrist is on the base axis: {n1} is free; giving {n1} from q0."))
        if singular.any():
            add_messages(note, full(singular[..., None]).reshape(B, 2, 2, 2) & ~unreachable, lambda i: (
                f"wrist singularity (q5 = 0 or 180 deg: axes 2, 3, 4 and 6 parallel): {n6} is free here; "
                f"giving {n6} from q0 (moved where needed to reach the target), and the wrist-up and wrist-down "
                "branches coincide."))
        return Raw(out.reshape(B, 8, 6), _LABELS[idx.reshape(B, 8)], unreachable.reshape(B, 8),
                   reason, note.reshape(B, 8))
