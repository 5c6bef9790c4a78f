"""Exact symmetries of an arm that a reachability map may use, each checked numerically.

* yaw: the first joint is revolute with a range of at least 2 pi, so every pose reachable
  at one angle about its axis is reachable at every angle (RM4D's reduction). Panda
  (first joint +-166 deg) does not qualify: its map keeps the full (x, y, z) box.
* roll: the last joint is revolute with a range of at least 2 pi and turns the tool about
  the tool's own z axis, so the roll about the approach direction is free.

Both are checked on the robot's own forward kinematics (not on its name or DH values), so a
URDF arm qualifies or not by what it does.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ..kinematics import fk
from ..model.robot import Robot

__all__ = ["yaw_frame", "yaw_symmetric", "roll_symmetric"]

_TWO_PI = 2.0 * math.pi - 1e-9


def _rz(t: float) -> NDArray[np.float64]:
    c, s = math.cos(t), math.sin(t)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])


def yaw_frame(robot: Robot) -> NDArray[np.float64]:
    """``T_world_A``: the frame in which the first joint moves along / about z at ``q1 = 0``."""
    return np.array(robot.chain.fixed[0], dtype=float)


def _full_turn(robot: Robot, i: int) -> bool:
    j = robot.joints[i]
    return (not j.is_prismatic) and (j.upper - j.lower >= _TWO_PI)


def yaw_symmetric(robot: Robot) -> bool:
    """True when turning the first joint by any angle turns the tool pose about a fixed axis."""
    if not _full_turn(robot, 0):
        return False
    A = yaw_frame(robot)
    Ainv = np.linalg.inv(A)
    q = robot.random_q(8, rng=12345)
    dq = np.zeros(robot.n)
    dq[0] = 0.731
    lhs = fk(robot, q + dq)
    rhs = A @ _rz(0.731) @ Ainv @ fk(robot, q)
    scale = max(robot.reach, 1e-12)
    return bool(np.allclose(lhs[..., :3, :3], rhs[..., :3, :3], atol=1e-9)
                and np.allclose(lhs[..., :3, 3], rhs[..., :3, 3], atol=1e-9 * scale))


def roll_symmetric(robot: Robot) -> bool:
    """True when turning the last joint turns the tool about its own z axis (through 2 pi)."""
    if not _full_turn(robot, robot.n - 1):
        return False
    q = robot.random_q(8, rng=54321)
    dq = np.zeros(robot.n)
    dq[-1] = 0.731
    lhs = fk(robot, q + dq)
    rhs = fk(robot, q) @ _rz(0.731)
    scale = max(robot.reach, 1e-12)
    return bool(np.allclose(lhs[..., :3, :3], rhs[..., :3, :3], atol=1e-9)
                and np.allclose(lhs[..., :3, 3], rhs[..., :3, 3], atol=1e-9 * scale))
