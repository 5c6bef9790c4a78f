"""Numba kernels of the yaw-pitch3 family (the SO-101): :meth:`armkit.lerobot.RobotKinematics.inverse_kinematics`
in one compiled call.

:func:`teleop` tries, nearest the current joints, the desired pose, else the position and pointing
direction, else the position and the pitch (the kernels of :mod:`._yaw_pitch3_jit`); :func:`teleop_call`
adds LeRobot's units (degrees, extra joints) and the input checks, :func:`teleop_ctx` takes its constants
in one array (:func:`pack_context`). Every name here is also importable from :mod:`._yaw_pitch3_jit`
(``_jit_loader.module("ik.analytic._yaw_pitch3_jit").teleop_ctx``), where these kernels used to live.
"""

from __future__ import annotations

import math

import numpy as np

from ... import _jit_loader

_jit_loader.install_cache_fallback()  # before the first cache=True: read-only installs cache elsewhere

from numba import njit  # noqa: E402

from ._yaw_pitch3_jit import (DIRECTION, G_LOWER, G_PAN, G_SIZE, G_UPPER, LM, NUMPY, PITCH, POSE,  # noqa: E402
                              POSITION, _closed_form, _cross, _fk, _nearest, _pitch, _polish_branch,
                              _rotation_angle, _solve4, _within, direction_branches)

__all__ = ["teleop", "teleop_call", "teleop_ctx", "pack_context", "INVALID", "C_TOL", "C_INDEX", "C_SIZE"]


@njit(cache=True)
def _position_newton(g, q, p, tol0, X, Z, P):
    """The position ``p`` alone from ``q`` (in place, inside the limits): minimum-norm Newton steps on the five
    joints, a joint that would leave its limits held at the limit from then on. Returns the position error (``X``
    holds the FK of ``q``); more than ``tol0`` where it did not converge (the caller takes LM)."""
    J = np.empty((3, 5))
    free = np.ones(5, dtype=np.bool_)
    A = np.empty((3, 3))
    y = np.empty(3)
    e = np.empty(3)
    dp = np.inf
    for _ in range(30):
        _fk(g, q, X, Z, P)
        for i in range(3):
            e[i] = p[i] - X[i, 3]
        dp = math.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2])
        if dp <= 1e-3 * tol0:
            return dp
        for j in range(5):
            v = _cross(Z[j, 0], Z[j, 1], Z[j, 2], X[0, 3] - P[j, 0], X[1, 3] - P[j, 1], X[2, 3] - P[j, 2])
            f = 1.0 if free[j] else 0.0
            J[0, j], J[1, j], J[2, j] = v[0] * f, v[1] * f, v[2] * f
        for i in range(3):
            for k in range(3):
                s = 0.0
                for j in range(5):
                    s += J[i, j] * J[k, j]
                A[i, k] = s + (1e-12 if i == k else 0.0)
            y[i] = e[i]
        _solve4(A, y, 3)
        big = 0.0
        for j in range(5):
            dq = J[0, j] * y[0] + J[1, j] * y[1] + J[2, j] * y[2]
            big = max(big, abs(dq))
            q[j] += dq
            lo, hi = g[G_LOWER + j], g[G_UPPER + j]
            if q[j] < lo or q[j] > hi:
                q[j] = min(max(q[j], lo), hi)
                free[j] = False
        if big > 0.5:
            return np.inf        # a long way from the current joints: LM decides
    _fk(g, q, X, Z, P)
    dx, dy, dz = p[0] - X[0, 3], p[1] - X[1, 3], p[2] - X[2, 3]
    return math.sqrt(dx * dx + dy * dy + dz * dz)


@njit(cache=True)
def teleop(g, T, q0, orient, tol0, tol1, q_out, info):
    """:meth:`armkit.lerobot.RobotKinematics.inverse_kinematics` of a 5-joint yaw-pitch3 arm, in one call.

    ``T`` (4, 4) the desired pose, ``q0`` (5,) the current joints (rad, inside the limits),
    ``orient``: whether orientation counts. Tries, nearest ``q0``: the whole pose (a direction
    solution whose tool x axis matches too), the position and the pointing direction (the
    target's z axis), the position and that direction's pitch (the roll of ``q0``); with
    ``orient`` False the position with the current tool pitch (the roll of ``q0``). Writes the
    answer to ``q_out`` (5,) and ``info`` = (position error, angle to the whole pose, the stage's
    own error (pitch or direction, rad), the label index); returns the stage code
    (:data:`POSE` ... :data:`POSITION`), :data:`LM` (neither the pose, nor the direction, nor the
    pitch is reachable from here: solve the position alone, numerically) or :data:`NUMPY` (a case
    the NumPy path handles: a vertical direction, a target on the yaw axis, a stretched elbow).
    """
    p = np.empty(3)
    d = np.empty(3)
    for i in range(3):
        p[i] = T[i, 3]
        d[i] = T[i, 2]
    X = np.empty((3, 4))
    Z = np.empty((5, 3))
    P = np.empty((5, 3))
    ah = np.empty(6)
    _fk(g, q0, X, Z, P)
    dx, dy, dz = p[0] - X[0, 3], p[1] - X[1, 3], p[2] - X[2, 3]
    dp0 = math.sqrt(dx * dx + dy * dy + dz * dz)
    if orient and dp0 <= tol0 and _within(g, q0):   # holding still: the current joints are the nearest answer
        ang = _rotation_angle(X, T)
        if ang <= tol1:
            for k in range(5):
                q_out[k] = q0[k]
            info[0], info[1], info[2], info[3] = dp0, ang, ang, -1.0
            return POSE
    if orient:
        Qd = np.empty((16, 5))
        DPd = np.empty(16)
        DAd = np.empty(16)
        OKd = np.empty(16, dtype=np.bool_)
        LABd = np.empty(16, dtype=np.int64)
        ROLLd = np.empty(16)
        STd = np.empty(16, dtype=np.bool_)
        ANGd = np.empty(16)
        m = direction_branches(g, p, d, T, q0, tol0, tol1, Qd, DPd, DAd, OKd, LABd, ROLLd, STd, ANGd)
        if m < 0:
            return NUMPY
        if m > 0:
            POKd = np.zeros(16, dtype=np.bool_)
            for i in range(m):
                POKd[i] = OKd[i] and ANGd[i] <= tol1   # ANGd: measured by FK of the polished candidate
            stage = POSE
            best = _nearest(Qd, POKd, m, q0)
            if best < 0:
                stage = DIRECTION
                best = _nearest(Qd, OKd, m, q0)
            if best >= 0:
                for k in range(5):
                    q_out[k] = Qd[best, k]
                info[0], info[1], info[2], info[3] = DPd[best], ANGd[best], DAd[best], float(LABd[best])
                return stage
        # the pitch of the direction, measured as RobotKinematics._pitch_of does (about the pan point)
        ox, oy = p[0] - g[G_PAN], p[1] - g[G_PAN + 1]
        r = math.hypot(ox, oy)
        if r < 1e-9:
            return NUMPY
        psi = math.atan2(d[2], (d[0] * ox + d[1] * oy) / r)
        stage = PITCH
    else:
        _fk(g, q0, X, Z, P)
        psi, _, _ = _pitch(g, q0, X, p[0], p[1], p[2], ah)
        stage = POSITION
    Qp = np.empty((4, 5))
    DPp = np.empty(4)
    DRp = np.empty(4)
    OKp = np.empty(4, dtype=np.bool_)
    WIp = np.empty(4, dtype=np.bool_)
    LABp = np.empty(4, dtype=np.int64)
    # pitch_branches(..., enforce=True, margin=1e-6) but for the FK of a branch outside the limits by more than
    # 1e-6 rad: it is not polished, so it cannot succeed
    flags = _closed_form(g, p, psi, q0, Qp, LABp)
    if flags != 0:
        return NUMPY
    keep = np.empty(5)
    for j in range(4):
        OKp[j] = False
        if _within(g, Qp[j], 1e-6):
            DPp[j], DRp[j], WIp[j], OKp[j] = _polish_branch(g, Qp[j], p, psi, j, tol0, tol1, True, 1e-6, True,
                                                            X, Z, P, ah, keep)
    best = _nearest(Qp, OKp, 4, q0)
    if best < 0:
        # the position alone, from the current joints (the NumPy path's last stage): LM where this fails
        for k in range(5):
            q_out[k] = q0[k]
        dp = _position_newton(g, q_out, p, tol0, X, Z, P)
        if dp > tol0 or not _within(g, q_out):
            return LM
        info[0], info[1], info[2], info[3] = dp, _rotation_angle(X, T), 0.0, -1.0
        return POSITION
    for k in range(5):
        q_out[k] = Qp[best, k]
    _fk(g, q_out, X, Z, P)
    info[0], info[1], info[2], info[3] = DPp[best], _rotation_angle(X, T), DRp[best], float(LABp[best])
    return stage


INVALID = -2


@njit(cache=True)
def teleop_call(g, cur_deg, index, T, orient, tol0, tol1, out_deg, info):
    """:func:`teleop` from LeRobot's units: ``cur_deg`` (k,) the current joint values in degrees (the
    chain's at ``index`` (5,)), ``T`` (4, 4) the desired pose; writes ``out_deg`` (k,) (``cur_deg`` with
    the chain's joints replaced) and ``info`` (9,): :func:`teleop`'s four values, then ``q`` (5,) rad.

    Returns :func:`teleop`'s code, or :data:`INVALID` for input the NumPy path must reject with its
    message (NaN or infinite values; ``T`` not a rigid transform to 1e-6, or its last row not
    exactly 0, 0, 0, 1).
    """
    for i in range(cur_deg.shape[0]):
        if not math.isfinite(cur_deg[i]):
            return INVALID
    for i in range(4):
        for j in range(4):
            if not math.isfinite(T[i, j]):
                return INVALID
    if T[3, 0] != 0.0 or T[3, 1] != 0.0 or T[3, 2] != 0.0 or T[3, 3] != 1.0:
        return INVALID
    for i in range(3):
        for j in range(3):
            s = T[0, i] * T[0, j] + T[1, i] * T[1, j] + T[2, i] * T[2, j]
            if abs(s - (1.0 if i == j else 0.0)) > 1e-6:
                return INVALID
    det = (T[0, 0] * (T[1, 1] * T[2, 2] - T[1, 2] * T[2, 1]) - T[0, 1] * (T[1, 0] * T[2, 2] - T[1, 2] * T[2, 0])
           + T[0, 2] * (T[1, 0] * T[2, 1] - T[1, 1] * T[2, 0]))
    if abs(det - 1.0) > 1e-6:
        return INVALID
    q0 = np.empty(5)
    for k in range(5):
        q0[k] = min(max(math.radians(cur_deg[index[k]]), g[G_LOWER + k]), g[G_UPPER + k])
    q = np.empty(5)
    code = teleop(g, T, q0, orient, tol0, tol1, q, info)
    if code >= 0:
        for i in range(cur_deg.shape[0]):
            out_deg[i] = cur_deg[i]
        for k in range(5):
            if q[k] != math.radians(cur_deg[index[k]]):   # a joint left where it was keeps its value exactly
                out_deg[index[k]] = math.degrees(q[k])
            info[4 + k] = q[k]
    return code


C_TOL = G_SIZE          # context of teleop_ctx: the geometry, then the tolerances (2) and the chain's indices (5)
C_INDEX = G_SIZE + 2
C_SIZE = G_SIZE + 7


def pack_context(g: np.ndarray, tol: tuple[float, float], index: np.ndarray) -> np.ndarray:
    """The one array :func:`teleop_ctx` reads: geometry ``g`` (:func:`pack`), ``tol`` and the chain's ``index`` (5,)."""
    ctx = np.empty(C_SIZE)
    ctx[:G_SIZE] = g
    ctx[C_TOL], ctx[C_TOL + 1] = tol
    ctx[C_INDEX:C_INDEX + 5] = index
    ctx.setflags(write=False)
    return ctx


@njit(cache=True)
def teleop_ctx(ctx, cur_deg, T, orient, out_deg, info):
    """:func:`teleop_call` with its constant arguments in one array (:func:`pack_context`): fewer arguments
    for the dispatcher to check on every call of ``RobotKinematics.inverse_kinematics``."""
    index = np.empty(5, dtype=np.int64)
    for k in range(5):
        index[k] = int(ctx[C_INDEX + k])
    return teleop_call(ctx, cur_deg, index, T, orient, ctx[C_TOL], ctx[C_TOL + 1], out_deg, info)


# the kernels above inline helpers of these files: their cache follows them
_jit_loader.forget_stale_cache(globals(), ("ik/analytic/_yaw_pitch3_jit.py", "ik/analytic/_jit.py"))
