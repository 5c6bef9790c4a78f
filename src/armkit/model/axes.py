"""The joint axes of a robot in the world: the one ``joint_axes`` of armkit.

Joint ``k``'s axis is the z axis of the frame ``F_{k-1} · pre_k`` of the compiled chain
(:class:`armkit.model.robot.Chain`; ``F_0`` is the base): a line through that frame's origin,
pointing the way the joint moves positively. Only NumPy: the model floor walks its own chain,
so the DH twin (:mod:`armkit.model.dh_extract`), the workspace (:mod:`armkit.analysis.workspace`)
and the pictures read the same axes.

>>> import armkit
>>> points, directions = joint_axes(armkit.load("planar2"))
>>> directions.round(12).tolist(), points[:, 0].round(6).tolist()
([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]], [0.0, 1.0])
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ShapeError
from .robot import Joint, Robot

__all__ = ["joint_axes", "joint_motion", "home_pose", "with_axes_reversed"]

Array = NDArray[np.float64]


def joint_motion(value: float, prismatic: bool) -> Array:
    """``M(q)`` ``(4, 4)`` of the compiled chain (:class:`~armkit.model.robot.Chain`): a turn about, or a slide
    along, the local z axis."""
    M = np.eye(4)
    if prismatic:
        M[2, 3] = value
    else:
        c, s = math.cos(value), math.sin(value)
        M[:2, :2] = [[c, -s], [s, c]]
    return M


def joint_axes(robot: Robot, q: ArrayLike | None = None) -> tuple[Array, Array]:
    """Joint axes in the world frame at one configuration: points ``(n, 3)`` on them and unit directions ``(n, 3)``.

    Parameters
    ----------
    robot : Robot
    q : array_like, shape (n,), optional
        The joint values; zeros by default (the home configuration, where the product-of-exponentials form and the
        DH twin read the axes).

    Returns
    -------
    points, directions : ndarray, shape (n, 3)
        The origin of joint ``k``'s frame, and its z axis (the sign of the joint's positive motion).
    """
    c = robot.chain
    if q is None:
        qv = np.zeros(robot.n)
    else:
        qv = robot.check_q(q)
        if qv.shape != (robot.n,):
            raise ShapeError.of("q must be one configuration of shape ({n},), got {shape}", n=robot.n, shape=qv.shape)
    X = c.base.copy()
    points = np.empty((robot.n, 3))
    directions = np.empty((robot.n, 3))
    for k in range(robot.n):
        A = X @ c.pre[k]                     # joint k's frame: its z axis is the joint axis
        points[k], directions[k] = A[:3, 3], A[:3, 2]
        X = A @ joint_motion(float(qv[k]), bool(c.prismatic[k])) @ c.post[k]
    return points, directions


def home_pose(robot: Robot) -> Array:
    """The tool pose at ``q = 0`` (the home pose ``M`` of the product of exponentials), shape ``(4, 4)``."""
    c = robot.chain
    T = np.eye(4)
    for F in c.fixed:                        # base·pre_1, post_1·pre_2, ..., post_n·tool: every M_i is 1 at q = 0
        T = T @ F
    return T


def with_axes_reversed(robot: Robot, joints: Sequence[int] = (0,)) -> Robot:
    """The same arm written as a URDF-convention robot whose listed joints turn (or slide) the other way.

    Joint ``k`` in ``joints`` (0-based) gets the axis ``(0, 0, -1)`` in its own frame, so ``q_k`` of the new robot
    is ``-q_k`` of the old one, and its limits become ``[-upper, -lower]``; every other joint, the base and the
    tool stay as they are. The geometry is unchanged, which makes it the test of anything that must not depend
    on which way an axis points (the closed-form classes, ``armkit info``).

    Parameters
    ----------
    robot : Robot
    joints : sequence of int
        Indices of the joints to reverse, 0-based (joint 1 by default).

    Returns
    -------
    Robot
        Named ``<name>-flipped``; ``fk(new, q') == fk(robot, q)`` where ``q'`` is ``q`` with the listed entries
        negated.

    >>> import armkit, numpy as np
    >>> ur5 = armkit.load("ur5")
    >>> flipped = with_axes_reversed(ur5)
    >>> q = np.array([0.3, -1.0, 0.5, 0.2, 1.1, -0.4])
    >>> bool(np.allclose(armkit.fk(flipped, q * [-1, 1, 1, 1, 1, 1]), armkit.fk(ur5, q), atol=1e-12))
    True
    """
    flip = {int(k) for k in joints}
    bad = sorted(k for k in flip if not 0 <= k < robot.n)
    if bad:
        raise ShapeError.of("there is no joint {k}: the joints are numbered from 0 to {last}", k=bad[0], last=robot.n - 1)
    c = robot.chain
    new: list[Joint] = []
    X, prev = c.base.copy(), np.eye(4)
    for k, j in enumerate(robot.joints):
        A = X @ c.pre[k]                     # joint k's frame in the world: its z axis is the joint axis
        origin = tuple(tuple(float(v) for v in row) for row in np.linalg.inv(prev) @ A)
        lower, upper = (-j.upper, -j.lower) if k in flip else (j.lower, j.upper)
        new.append(Joint(name=j.name, kind=j.kind, lower=lower, upper=upper, origin=origin,
                         axis=(0.0, 0.0, -1.0 if k in flip else 1.0)))
        X, prev = A @ c.post[k], A
    return Robot(new, convention="urdf", name=robot.name + "-flipped", unit=robot.unit,
                 tool=np.linalg.inv(prev) @ X @ c.tool)
