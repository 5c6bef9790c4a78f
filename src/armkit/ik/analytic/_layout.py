"""The packed geometry of the closed-form families: one float64 array per robot, read by the Numba kernels.

Each family's ``pack()`` (see :class:`armkit.ik.analytic.ClosedFormFamily`) builds it once per
robot (the solver is kept in the robot's cache); :mod:`._jit` reads it at the indices named
here. Every layout starts with the two frames every family needs:

================  =====  ==========================================================
index             size   value
================  =====  ==========================================================
``BASE_INV``      16     ``B'^-1`` row by row (see :mod:`._common`)
``TOOL_INV``      16     ``T'^-1`` row by row
================  =====  ==========================================================

followed by the family's lengths and signs (below, each with its own names). The joint
table of the wrap/pick/sort kernels is a separate ``(4, n)`` array (:data:`JOINT_ROWS`).
This module imports nothing, so the NumPy path can build the arrays without Numba.
"""

from __future__ import annotations

import numpy as np

BASE_INV, TOOL_INV, HEADER = 0, 16, 32

# planar-2r: the link lengths a_1 and ell, and the tool point's angle beta in the last link
P2_L1, P2_ELL, P2_BETA, P2_SIZE = 32, 33, 34, 35
# planar-3r: the link lengths a_1, a_2
P3_L1, P3_L2, P3_SIZE = 32, 33, 34
# yaw-pitch-pitch positioner (also the first part of spherical-wrist): see yaw_pitch_pitch.Positioner
POS_S1, POS_D1, POS_A1, POS_A2, POS_Z, POS_ELL, POS_BETA, POS_TINY, POS_SIZE = 32, 33, 34, 35, 36, 37, 38, 39, 40
# yaw-pitch-pitch: the positioner, then the sign of joint 3 (-1 where the DH table reverses it: YawPitchPitch solves
# the arm with it turned back)
YPP_F3, YPP_SIZE = 40, 41
# spherical-wrist: the positioner, then d_6, the twist signs s_4, s_5, cos/sin of alpha 1, 3, 4, 5 and the sign of
# joint 3 (-1 where the file reverses it: SphericalWrist solves the arm with it turned back)
SW_D6, SW_S4, SW_S5, SW_CS, SW_F3, SW_SIZE = 40, 41, 42, 43, 51, 52
# ur: twist signs s_1, s_4, s_5, the shoulder offset D, lengths d_1, d_4, d_5, d_6, a_2, a_3, zero length, and the
# signs of joints 3 and 4 (-1 where the DH table reverses them: ParallelAxes solves the arm with them turned back)
UR_S1, UR_S4, UR_S5, UR_D, UR_D1, UR_D4, UR_D5, UR_D6, UR_A2, UR_A3, UR_TINY, UR_F3, UR_F4, UR_SIZE = range(32, 46)

NEAREST, LABEL_SHIFT = 16, 5
"""In the return value of a one-call kernel (:mod:`._single`) with ``nearest`` (:func:`armkit.ik`), when the
nearest branch succeeds: the bit :data:`NEAREST` and that branch's label index shifted left by
:data:`LABEL_SHIFT` (the caller then reads nothing else from ``ib``; the buffers hold the same values as without).
Here, not in :mod:`._single`, so that the caller reads them without importing Numba."""

JOINT_THETA, JOINT_LOWER, JOINT_UPPER, JOINT_PRISMATIC, JOINT_ROWS = 0, 1, 2, 3, 4
"""Rows of the joint table ``(JOINT_ROWS, n)``: DH offset theta, lower and upper limit, 1.0 for prismatic."""


def header(size: int, base_inv: np.ndarray, tool_inv: np.ndarray) -> np.ndarray:
    """A zeroed geometry array of ``size`` values with the two frames written in."""
    g = np.zeros(size)
    g[BASE_INV:BASE_INV + 16] = np.asarray(base_inv, dtype=float).reshape(16)
    g[TOOL_INV:TOOL_INV + 16] = np.asarray(tool_inv, dtype=float).reshape(16)
    return g


def joint_table(theta: np.ndarray, lower: np.ndarray, upper: np.ndarray, prismatic: np.ndarray) -> np.ndarray:
    """The ``(JOINT_ROWS, n)`` joint table, read-only."""
    t = np.ascontiguousarray(np.stack([theta, lower, upper, np.asarray(prismatic, dtype=float)]), dtype=float)
    t.setflags(write=False)
    return t
