"""Contour-map data (as in the symbolic 2-link tutorial): end point over a joint grid, joint values over a target grid.

:func:`fk_maps` evaluates ``x(q1, q2)``, ``y(q1, q2)`` (and ``z``) on a grid of two joints;
:func:`ik_maps` evaluates every closed-form IK branch on a grid of targets, ``NaN``
where a branch does not reach. Plotting is separate: :func:`armkit.viz.plot_maps`.

Examples
--------
>>> import numpy as np, armkit
>>> from armkit.analysis import fk_maps
>>> m = fk_maps(armkit.load("planar2"), np.radians([0, 90]), np.radians([0, 90]))
>>> np.round(m.x, 6) + 0.0          # x = L1 cos q1 + L2 cos(q1 + q2), rows q1, columns q2
array([[ 1.5,  1. ],
       [ 0. , -0.5]])
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._limits import CHUNK, check_memory
from .._text import Fielded
from ..errors import ArgumentError, ShapeError
from ..ik import closed_form_family, ik_all
from ..kinematics import fk
from ..model.robot import Robot

__all__ = ["fk_maps", "ik_maps", "FKMaps", "IKMaps"]

Array = NDArray[np.float64]


def _grid(values: ArrayLike, what: str) -> Array:
    g = np.asarray(values, dtype=float)
    if g.ndim != 1 or len(g) < 1:
        raise ShapeError.of("{what} must be a 1-D array of grid values, got shape {shape}", what=what, shape=g.shape)
    if not np.all(np.isfinite(g)):
        raise ShapeError.of("{what} contains NaN or infinite values", what=what)
    return g


@dataclass(frozen=True)
class FKMaps:
    """End point over a grid of two joints. Arrays are ``(len(q1), len(q2))`` ("ij" indexing).

    Attributes
    ----------
    robot : Robot
    joints : tuple of int
        The two joints varied (0-based).
    q1, q2 : ndarray, shapes (A,) and (B,)
        Grid values (rad, or length units for a prismatic joint).
    x, y, z : ndarray, shape (A, B)
        End-point coordinates in the robot's length unit.
    q_rest : ndarray, shape (n,)
        Values of the other joints.
    """

    robot: Robot
    joints: tuple
    q1: Array
    q2: Array
    x: Array
    y: Array
    z: Array
    q_rest: Array


@dataclass(frozen=True)
class IKMaps:
    """Joint values of every IK branch over a target grid; ``NaN`` where the branch fails.

    Attributes
    ----------
    robot : Robot
    x, y : ndarray, shapes (A,) and (B,)
        Target grid (length units); ``z`` the target height for a spatial arm.
    q : ndarray, shape (A, B, m, n)
        Joint values of each of ``m`` branches, ``NaN`` where it does not reach (or
        breaks a joint limit).
    branches : tuple of str
        Branch labels, length ``m``.
    reachable : ndarray of bool, shape (A, B, m)
    """

    robot: Robot
    x: Array
    y: Array
    z: Optional[float]
    q: Array
    branches: tuple
    reachable: NDArray[np.bool_]


def fk_maps(robot: Robot, q1_grid: ArrayLike, q2_grid: ArrayLike, q_rest: ArrayLike | None = None,
            joints: Sequence[int] = (0, 1)) -> FKMaps:
    """End point over a grid of two joints.

    Parameters
    ----------
    robot : Robot
    q1_grid, q2_grid : array_like, shapes (A,) and (B,)
        Values of ``joints[0]`` and ``joints[1]`` (rad / length units).
    q_rest : array_like, shape (n,), optional
        The other joints' values (zeros by default).
    joints : pair of int
        Which joints vary (0-based; default the first two).

    Returns
    -------
    FKMaps
    """
    g1, g2 = _grid(q1_grid, "q1_grid"), _grid(q2_grid, "q2_grid")
    j = tuple(int(i) for i in joints)
    if len(j) != 2 or j[0] == j[1] or not all(0 <= i < robot.n for i in j):
        raise ArgumentError.of("joints must be two different joint indices in 0..{last}, got {got}", last=robot.n - 1,
                               got=tuple(joints))
    rest = np.zeros(robot.n) if q_rest is None else robot.check_q(q_rest, "q_rest")
    if rest.shape != (robot.n,):
        raise ShapeError.of("q_rest must have shape ({n},), got {shape}", n=robot.n, shape=rest.shape)
    A, B = len(g1), len(g2)
    check_memory(A * B * 8.0 * 6, Fielded.of("FK maps over {a} x {b} joint values", a=A, b=B),
                 Fielded.of("use a coarser grid"))
    xyz = np.empty((3, A, B))
    rows = max(1, CHUNK // B)            # a few rows of the grid at a time: the chunk's FK, not the grid's, is held
    for i in range(0, A, rows):
        Q = np.broadcast_to(rest, (len(g1[i:i + rows]), B, robot.n)).copy()
        Q[..., j[0]] = g1[i:i + rows, None]
        Q[..., j[1]] = g2[None, :]
        p = fk(robot, Q)[..., :3, 3]
        xyz[:, i:i + rows] = np.moveaxis(p, -1, 0)
    return FKMaps(robot, j, g1, g2, xyz[0], xyz[1], xyz[2], rest)


ELBOW_JOINT = {"planar-2r": 1, "planar-3r": 1}
"""Closed-form families whose branches :func:`ik_maps` names by the sign of one joint (0-based index)."""


IK_CHUNK = 20_000
"""Targets per ``ik_all`` call of :func:`ik_maps` (a few rows of the grid at a time)."""


def _default_height(robot: Robot) -> float:
    """The IK maps' target height of a spatial arm: the middle of a flat, horizontal workspace (a SCARA's quill at
    mid-stroke, :func:`~.workspace.flat_frame`), else the shoulder's height."""
    from .workspace import flat_frame, shoulder_point, workspace

    flat = flat_frame(workspace(robot, samples=20_000, seed=0, scene=False))
    if flat is not None and abs(flat[3][2]) == 1.0:
        return float(flat[0][2])
    return float(shoulder_point(robot)[2])


def ik_maps(robot: Robot, x_grid: ArrayLike, y_grid: ArrayLike, z: float | None = None,
            phi: float | None = None, continuous: bool = True) -> IKMaps:
    r"""Every closed-form IK branch over a grid of targets (the symbolic 2-link tutorial's IK maps).

    Parameters
    ----------
    robot : Robot
        A robot with a closed-form solution for the target kind (``planar2``: positions
        ``(x, y)``; ``fighter``: positions ``(x, y, z)`` at height ``z``).
    x_grid, y_grid : array_like, shapes (A,) and (B,)
        Target coordinates (length units).
    z : float, optional
        Target height for a spatial arm (default: the height of the shoulder; the middle of the slab a SCARA
        reaches, its quill at mid-stroke).
    phi : float, optional
        End angle (rad) for planar arms that need one (``planar3``).
    continuous : bool
        Name the branches of a planar arm by the sign of its elbow angle, ``"q2+"``
        (:math:`q_2 \ge 0`) and ``"q2-"``, as the tutorial's two closed forms
        :math:`q_2 = \pm\arccos c_2` do: each map is then continuous over the reachable
        annulus (the solver's own names, elbow up/down seen from above, swap where the
        target crosses the line through the shoulder, which draws a seam). Where both
        solutions coincide (the elbow stretched or folded) the larger elbow angle is ``+``.
        Other arms keep the solver's names (front/back, elbow up/down), continuous away
        from their singularities.

    Returns
    -------
    IKMaps
        ``q[i, j, b]`` solves the target ``(x[i], y[j])`` on branch ``b``; NaN where it fails.
    """
    from .workspace import is_planar, shoulder_point

    gx, gy = _grid(x_grid, "x_grid"), _grid(y_grid, "y_grid")
    A, B = len(gx), len(gy)
    planar = is_planar(robot)
    zval = None if planar else (_default_height(robot) if z is None else float(z))
    elbow = ELBOW_JOINT.get(closed_form_family(robot) or "") if continuous else None
    # a few rows of the target grid at a time (IK_CHUNK targets): ik_all's result for the whole grid (labels, errors,
    # reasons of every branch: ~1.6-3.4 kB a target) is never held, only each branch's joint values
    rows = max(1, IK_CHUNK // B)
    maps: dict[str, tuple[Array, NDArray[np.bool_]]] = {}     # label -> (its q (A, B, n), reached (A, B))
    first: list[str] = []
    for i in range(0, A, rows):
        X, Y = np.meshgrid(gx[i:i + rows], gy, indexing="ij")
        target = np.stack([X, Y] if planar else [X, Y, np.full_like(X, zval)], axis=-1)
        res = ik_all(robot, target, phi=phi) if phi is not None else ik_all(robot, target)
        labels = np.asarray(res.branch).astype(str)
        qa = np.asarray(res.q, dtype=float)
        sa = np.asarray(res.success, dtype=bool)
        if elbow is not None and labels.shape[-1] == 2:
            labels = _sign_labels(qa[..., elbow], robot.joint_names[elbow] if robot.joint_names[elbow].startswith("q")
                                  else f"q{elbow + 1}")
        if i == 0:
            first = [str(lab) for lab in labels.reshape(-1, labels.shape[-1])[0]]
            check_memory(A * B * 8.0 * (robot.n + 1) * 2 * max(labels.shape[-1], 1),
                         Fielded.of("IK maps over {a} x {b} targets", a=A, b=B), Fielded.of("use a coarser grid"))
        for lab in np.unique(labels):
            if lab not in maps:
                maps[str(lab)] = (np.full((A, B, robot.n), np.nan), np.zeros((A, B), dtype=bool))
            qm, okm = maps[str(lab)]
            hit = labels == lab                               # (rows, B, m): at most one True per target
            has = hit.any(axis=-1)
            idx = np.argmax(hit, axis=-1)
            qb = np.take_along_axis(qa, idx[..., None, None], axis=-2)[..., 0, :]
            sb = np.take_along_axis(sa, idx[..., None], axis=-1)[..., 0] & has
            okm[i:i + rows] = sb
            qm[i:i + rows] = np.where(sb[..., None], qb, np.nan)
    # ik_all sorts the branches of each target by distance to q0; put them in one fixed order by label: the first
    # target's, then the others by name
    order: list[str] = []
    for lab in first + sorted(maps):
        if lab not in order:
            order.append(lab)
    q = np.stack([maps[lab][0] for lab in order], axis=2)
    ok = np.stack([maps[lab][1] for lab in order], axis=2)
    return IKMaps(robot, gx, gy, zval, q, tuple(order), ok)


def _sign_labels(elbow: Array, name: str) -> NDArray[np.str_]:
    """Two solutions per target named ``name+`` (the larger elbow angle) and ``name-``.

    ``elbow`` has shape ``(..., 2)``; a NaN (failed) solution is named after the other one.
    """
    e = np.where(np.isnan(elbow), np.where(np.isnan(elbow[..., ::-1]), 0.0, -elbow[..., ::-1]), elbow)
    first_plus = e[..., 0] >= e[..., 1]
    plus, minus = f"{name}+", f"{name}-"
    out = np.empty(elbow.shape, dtype=object)
    out[..., 0] = np.where(first_plus, plus, minus)
    out[..., 1] = np.where(first_plus, minus, plus)
    return out.astype(str)
