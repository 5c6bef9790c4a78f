"""A chain in product-of-exponentials form at q = 0: the joint axes and the offsets between them.

This is the form in which the subproblem solvers think (the convention of IK-Geo, Elias and Wen,
"IK-Geo: Unified robot inverse kinematics using subproblem decomposition", 2022), and it is the
same whatever the robot file was written in (standard DH, modified DH or URDF)::

    R_0T(q) = rot(h_1, q_1) · rot(h_2, q_2) ··· rot(h_n, q_n) · R_nT
    p_0T(q) = p_01 + R_01 p_12 + R_02 p_23 + ··· + R_0n p_nT          with R_0k = rot(h_1, q_1) ··· rot(h_k, q_k)

for revolute joints; a prismatic joint k adds ``q_k h_k`` to the position at its place instead
of turning. Every vector is expressed in the robot's world frame at q = 0: ``H[k]`` is joint
k's unit axis, ``P[0]`` goes from the world origin to a point on axis 1, ``P[k]`` from a point
on axis k to a point on axis k + 1, and ``P[n]`` from a point on axis n to the tool origin.
The points are where the chain's joint frames sit at q = 0 (the solvers may slide them along
their axes).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ...model.robot import Robot
from .subproblems import rotm

__all__ = ["POE", "poe"]

Array = NDArray[np.float64]


@dataclass(frozen=True)
class POE:
    """Axes ``H`` (n, 3), offsets ``P`` (n + 1, 3), tool rotation ``R_nT`` (3, 3), prismatic flags (n,)."""

    H: Array
    P: Array
    R_nT: Array
    prismatic: NDArray[np.bool_]

    @property
    def n(self) -> int:
        return int(self.H.shape[0])

    def fk(self, q: Array) -> tuple[Array, Array]:
        """Rotation (3, 3) and position (3,) of the tool for one q (n,): the formula above, for tests."""
        R = np.eye(3)
        p = self.P[0].copy()
        for k in range(self.n):
            if self.prismatic[k]:
                p = p + q[k] * (R @ self.H[k])
            else:
                R = R @ rotm(self.H[k], float(q[k]))
            p = p + R @ self.P[k + 1]
        return R @ self.R_nT, p


def poe(robot: Robot) -> POE:
    """The robot's chain at q = 0 in product-of-exponentials form (see the module docstring).

    Examples
    --------
    >>> import armkit, numpy as np
    >>> r = armkit.load("puma560")
    >>> form = poe(r)
    >>> q = np.array([0.1, -0.4, 0.3, 1.0, 0.5, -0.2])
    >>> R, p = form.fk(q)
    >>> T = armkit.fk(r, q)
    >>> bool(np.allclose(R, T[:3, :3]) and np.allclose(p, T[:3, 3]))
    True
    """
    c = robot.chain
    n = robot.n
    H = np.empty((n, 3))
    points = np.empty((n, 3))
    X = c.base.copy()
    for k in range(n):
        A = X @ c.pre[k]                     # joint k's frame: its z axis is the joint axis
        H[k] = A[:3, 2] / np.linalg.norm(A[:3, 2])
        points[k] = A[:3, 3]
        X = A @ c.post[k]
    E = X @ c.tool
    P = np.empty((n + 1, 3))
    P[0] = points[0]
    P[1:n] = points[1:] - points[:-1]
    P[n] = E[:3, 3] - points[n - 1]
    for x in (H, P):
        x.setflags(write=False)
    R_nT = E[:3, :3].copy()
    R_nT.setflags(write=False)
    prismatic = np.array(c.prismatic, dtype=bool)
    prismatic.setflags(write=False)
    return POE(H, P, R_nT, prismatic)
