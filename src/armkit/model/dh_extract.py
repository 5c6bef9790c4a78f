"""An equivalent DH table for any serial chain (URDF arms, or a DH arm in the other convention).

The joint axes of the chain at ``q = 0`` are lines in space; DH frames are built on them
with the textbook rules, then each ``F_{i-1}^{-1} F_i`` is read as one DH row:

* frame ``0``: z along axis 1, origin at the foot of the robot's base origin on that
  axis, x the base frame's x made perpendicular to z (so an arm standing on its base
  gets ``base = identity``);
* frame ``i`` (standard DH; ``1 <= i < n``): z along axis ``i + 1``, x along the common
  normal from axis ``i`` to axis ``i + 1``, origin where that normal meets axis ``i + 1``.
  Degenerate cases:

  - **intersecting axes**: x is ``±(z_{i-1} × z_i)``, the sign that keeps x closest to the
    previous x (``|theta| <= 90 deg``), ``a_i = 0``;
  - **parallel axes**: the normal through the previous origin (``d_i = 0``);
  - **coincident axes**: x and the origin are kept (``a_i = alpha_i = d_i = 0``);
  - **prismatic joints**: only the direction of a sliding axis matters, so its line is
    placed through the previous axis at the point nearest the joint's own origin (it
    meets the previous axis: ``a = 0``), the first one through the base origin;

* frame ``n``: z along the last axis (``alpha_n = 0``), x towards the tool origin
  (``a_n`` = its distance from the axis), so that the tool holds only a rotation.

Modified DH (Craig) uses the same normals: frame ``i`` sits on axis ``i`` where the
normal to axis ``i + 1`` starts. ``base`` is frame 0 in the world, ``tool`` what is left
from frame ``n`` to the tool. The twin is checked: its joint axes at ``q = 0`` (direction
and line) and its tool pose must be the chain's to 1e-9 of the reach. By the product of
exponentials, ``T(q) = exp([S_1] q_1) ... exp([S_n] q_n) M``, two chains with the same axes
``S_i`` and home pose ``M`` have the same FK at every ``q``; tests/model/test_dh_twin.py
compares the FK itself (it agrees to rounding, ~1e-15, for every chain tested).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ..errors import RobotDefinitionError
from .axes import home_pose, joint_axes
from .robot import Joint, Robot

__all__ = ["chain_to_dh"]

Array = NDArray[np.float64]

PARALLEL_TOL = 1e-12     # |sin| of the angle between two axes below which they count as parallel
CHECK_TOL = 1e-9         # the twin's axes and tool pose must match to this fraction of the reach


def _axes_mismatch(a: Robot, b: Robot, scale: float) -> float:
    """How far FK of ``a`` can be from ``b``'s, in length units, from their joint axes at ``q = 0`` and tool poses.

    By the product of exponentials each joint's screw error moves the tool by at most about
    ``|q_i|`` times it: a revolute joint's by its direction error times ``scale`` (the reach)
    plus the distance of ``a``'s point from ``b``'s axis line, a prismatic joint's by its
    direction error. ``|q_i|`` is bounded by the joint's limits (``pi`` where a limit is
    infinite, the range :meth:`Robot.random_q` draws from).
    """
    (pa, ua), Ta = joint_axes(a), home_pose(a)
    (pb, ub), Tb = joint_axes(b), home_pose(b)
    d = pa - pb
    off = np.linalg.norm(d - np.sum(d * ub, axis=1)[:, None] * ub, axis=1)   # across b's axis line
    turn = np.linalg.norm(ua - ub, axis=1)
    prismatic = np.asarray(b.prismatic, dtype=bool)
    per_joint = np.where(prismatic, turn, turn * scale + off)
    lo = np.where(np.isfinite(b.lower), b.lower, -math.pi)
    hi = np.where(np.isfinite(b.upper), b.upper, math.pi)
    reach_q = np.maximum(np.abs(lo), np.abs(hi))
    tool = max(float(np.abs(Ta[:3, :3] - Tb[:3, :3]).max()) * scale, float(np.abs(Ta[:3, 3] - Tb[:3, 3]).max()))
    return float(np.sum(reach_q * per_joint)) + tool


def _unit(v: Array) -> Array:
    return np.asarray(v / np.linalg.norm(v), dtype=float)


def _perp(v: Array, z: Array) -> Array:
    return np.asarray(v - (v @ z) * z, dtype=float)


def _frame(origin: Array, x: Array, z: Array) -> Array:
    x = _unit(_perp(x, z))
    F = np.eye(4)
    F[:3, 0], F[:3, 1], F[:3, 2], F[:3, 3] = x, np.cross(z, x), z, origin
    return F


def _normal(o_a: Array, u_a: Array, p_b: Array, u_b: Array, x_prev: Array, ptol: float, ltol: float
            ) -> tuple[Array, Array, Array]:
    """The common normal of line ``a`` (through ``o_a``) and line ``b``: foot on a, foot on b, direction x."""
    # u_a x u_b, written so that nearly parallel axes keep full relative precision (u_b -+ u_a is small
    # and exact): the normal then stays perpendicular to both axes to rounding, not to 1e-16 / angle
    c = np.cross(u_a, u_b - u_a if u_a @ u_b >= 0 else u_b + u_a)
    s = float(np.linalg.norm(c))
    if s > ptol:                                      # skew or intersecting
        x = c / s
        gap = float((p_b - o_a) @ x)                  # distance between the lines (well conditioned)
        if abs(gap) <= ltol and np.linalg.norm(_perp(p_b - o_a, u_a)) <= ltol:
            return p_b, p_b, (x if x @ x_prev >= 0 else -x)   # b's point lies on a: that is where they meet
        w = o_a - p_b
        b_, d_, e_ = float(u_a @ u_b), float(u_a @ w), float(u_b @ w)
        denom = s * s
        foot_a = o_a + ((b_ * e_ - d_) / denom) * u_a
        foot_b = p_b + ((e_ - b_ * d_) / denom) * u_b
        if abs(gap) > ltol:
            x = x if gap > 0 else -x
        else:                                         # intersecting: one point, the sign nearest the previous x
            foot_b = foot_a
            x = x if x @ x_prev >= 0 else -x
        return foot_a, foot_b, x
    foot_a = o_a                                      # parallel: the normal through the previous origin
    foot_b = p_b + float((o_a - p_b) @ u_b) * u_b
    v = _perp(foot_b - foot_a, u_a)
    if np.linalg.norm(v) > ltol:
        return foot_a, foot_b, _unit(v)
    return foot_a, o_a, x_prev                        # coincident: keep the origin and x


def _frames(robot: Robot, ptol: float, ltol: float) -> tuple[list[Array], list[Array], Array]:
    """Standard and modified DH frames ``(n + 1)`` each, in the world, and the tool pose at q = 0."""
    (p, u), tip = joint_axes(robot), home_pose(robot)
    n = robot.n
    base = robot.base
    o_ref, x_ref = base[:3, 3], base[:3, 0]
    # a sliding axis has no position of its own: put it through the previous axis
    p = p.copy()
    for i in range(n):
        if robot.prismatic[i]:
            if i == 0:
                p[0] = o_ref
            else:   # the foot of its origin on the previous axis: the two lines meet there exactly
                p[i] = p[i - 1] + float((p[i] - p[i - 1]) @ u[i - 1]) * u[i - 1]
    o0 = p[0] + float((o_ref - p[0]) @ u[0]) * u[0]
    x0 = _perp(x_ref, u[0])
    if np.linalg.norm(x0) < 1e-6:
        x0 = _perp(base[:3, 1], u[0])
    std = [_frame(o0, x0, u[0])]
    mod = [std[0]]
    for i in range(n - 1):
        o_prev, x_prev = std[-1][:3, 3], std[-1][:3, 0]
        foot_a, foot_b, x = _normal(o_prev, u[i], p[i + 1], u[i + 1], x_prev, ptol, ltol)
        std.append(_frame(foot_b, x, u[i + 1]))
        mod.append(_frame(foot_a, x, u[i]))
    o_prev, x_prev = std[-1][:3, 3], std[-1][:3, 0]
    t = tip[:3, 3]
    foot = o_prev + float((t - o_prev) @ u[-1]) * u[-1]
    v = _perp(t - foot, u[-1])
    if np.linalg.norm(v) > ltol:
        x_last, o_last = _unit(v), t
    else:
        x_last, o_last = x_prev, foot
    std.append(_frame(o_last, x_last, u[-1]))
    mod.append(_frame(foot, x_last, u[-1]))
    return std, mod, tip


def _inv(T: Array) -> Array:
    out = np.eye(4)
    out[:3, :3] = T[:3, :3].T
    out[:3, 3] = -T[:3, :3].T @ T[:3, 3]
    return out


def _row_standard(M: Array) -> tuple[float, float, float, float]:
    """``M = Rz(theta) Tz(d) Tx(a) Rx(alpha)``: (theta, d, a, alpha)."""
    theta = math.atan2(M[1, 0], M[0, 0])
    alpha = math.atan2(M[2, 1], M[2, 2])
    a = M[0, 3] * math.cos(theta) + M[1, 3] * math.sin(theta)
    return theta, float(M[2, 3]), a, alpha


def _row_modified(M: Array) -> tuple[float, float, float, float]:
    """``M = Rx(alpha) Tx(a) Rz(theta) Tz(d)``: (theta, d, a, alpha)."""
    alpha = math.atan2(-M[1, 2], M[2, 2])
    theta = math.atan2(-M[0, 1], M[0, 0])
    d = -M[1, 3] * math.sin(alpha) + M[2, 3] * math.cos(alpha)
    return theta, d, float(M[0, 3]), alpha


def _clean(x: float, tol: float) -> float:
    return 0.0 if abs(x) <= tol else x


def chain_to_dh(robot: Robot, convention: str = "standard", parallel_tol: float = PARALLEL_TOL,
                length_tol: float = 1e-12, check: bool = True) -> Robot:
    """The DH twin of ``robot`` (see the module docstring for the rules).

    Parameters
    ----------
    robot : Robot
    convention : {"standard", "modified"}
    parallel_tol : float
        Axes whose angle has a sine below this count as parallel (1e-12: only exactly
        parallel ones). A larger value (closed-form detection uses 1e-4) gives the nearby
        *ideal* arm instead of an exact twin.
    length_tol : float
        Lengths below this fraction of the reach count as zero.
    check : bool
        Compare the joint axes and the tool pose of the twin with the original's and raise if
        they differ (equal axes and home pose: equal FK at every ``q``).
    """
    scale = max(robot.reach, 1e-300)
    ltol = length_tol * scale
    std, mod, tip = _frames(robot, parallel_tol, ltol)
    frames = std if convention == "standard" else mod
    read = _row_standard if convention == "standard" else _row_modified
    joints = []
    for i, j in enumerate(robot.joints):
        theta, d, a, alpha = read(_inv(frames[i]) @ frames[i + 1])
        theta, alpha = _clean(theta, 1e-15), _clean(alpha, 1e-15)
        joints.append(Joint(j.kind, theta, _clean(d, ltol), _clean(a, ltol), alpha, j.lower, j.upper, j.name))
    twin = Robot(joints, convention, robot.name, robot.unit, frames[0], _inv(frames[-1]) @ tip,
                 robot.description, robot.source, robot.link_names, ignored_joints=robot.ignored_joints)
    if check:
        err = _axes_mismatch(twin, robot, scale)
        if err > CHECK_TOL * max(scale, 1.0):
            if parallel_tol < 1e-6:   # nearly parallel axes blow the common normal up: try them as parallel
                try:
                    return chain_to_dh(robot, convention, 1e-6, length_tol, check)
                except RobotDefinitionError:
                    pass
            raise RobotDefinitionError.of("robot {robot!r}: no DH table reproduces this chain to {CHECK_TOL:g} of its "
                                          "reach (FK can differ by {err:.3g} {unit}); two consecutive joint axes are "
                                          "probably almost, but not exactly, parallel. Keep the chain as it is (every "
                                          "armkit function works on it).", robot=robot.name, CHECK_TOL=CHECK_TOL,
                                          err=err, unit=robot.unit)
    return twin
