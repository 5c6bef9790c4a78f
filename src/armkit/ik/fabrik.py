r"""FABRIK (Forward And Backward Reaching IK) for position targets, batched over targets.

FABRIK moves *points*, not angles: the joint points and the tool point form a chain of
fixed-length segments. A backward pass puts the tool point on the target and pulls each
point towards its successor, keeping the segment lengths; a forward pass pins the root
back in place and pushes the points outwards again (Aristidou and Lasenby, 2011). The
points are then turned back into joint angles.

Supported structures (detected from the model at ``q = 0``, not from the robot's name):

* **planar arms**: every joint revolute and every joint axis parallel (planar2, planar3,
  the CCD graphics assignment's arm). FABRIK runs in the plane perpendicular to the axes; a target off that
  plane is unreachable.
* **a yaw joint followed by a planar arm**: joint 1 revolute, joints 2..n revolute and
  parallel to each other and perpendicular to joint 1 (the fighter arm of the club's fighting-robot report). The
  yaw angle that brings the target into the arm's plane is computed first (both
  solutions are tried), then planar FABRIK solves the rest.

Other arms (spatial wrists, prismatic joints, coincident joint points) raise
:class:`~armkit.IKInputError` with a pointer to ``method="ccd"`` or ``"lm"``.

Convergence is linear, and slow near the workspace boundary: a two-segment chain reaching
for a point near full extension can stall above the 1e-9 m tolerance, and then the result
says "max iterations" with the residual (use ``method="lm"`` or the closed form there).

Joint limits: after every backward/forward pass the points are converted to angles,
projected into the limits and recomputed, so the iteration only ever holds feasible
configurations.

References
----------
A. Aristidou and J. Lasenby, "FABRIK: A fast, iterative solver for the Inverse Kinematics
problem", Graphical Models 73(5), 2011.
"""

from __future__ import annotations

from typing import Any, Optional

import numpy as np
from numpy.typing import ArrayLike

from .._text import Fielded
from ..errors import IKInputError
from ..kinematics import fk_frames
from ..model.robot import Robot
from .ccd import _position_problem
from .numeric import _TOL_FACTOR, Problem, _project, _trace_array, assemble, unreachable_note
from .result import DEFAULT_MAX_SWEEPS, DEFAULT_SWEEP_RESTARTS, IKResult
from .verdict import settle

__all__ = ["solve_fabrik", "fabrik_structure"]

_EPS = 1e-9
_STALL_PASSES = 200  # an attempt ends when its error has not fallen by 0.1 % in this many passes


def _joint_frames_at_zero(robot: Robot) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    c = robot.chain
    F = fk_frames(robot, np.zeros(robot.n))
    frames = np.stack([F[j] @ c.pre[j] for j in range(robot.n)])
    return frames[:, :3, 2], frames[:, :3, 3], F[robot.n, :3, 3]


def fabrik_structure(robot: Robot) -> str:
    """``"planar"``, ``"yaw+planar"``, or raise :class:`~armkit.IKInputError` saying why FABRIK does not apply."""
    return _structure(robot)["kind"]


def _structure(robot: Robot) -> dict:
    if robot.prismatic.any():
        raise IKInputError.of("FABRIK in armkit supports revolute planar arms and yaw + planar arms; robot {robot!r} "
                              "has prismatic joints ({joint_types}); use method 'ccd' or 'lm'", robot=robot.name,
                              joint_types=robot.joint_types)
    z, p, e = _joint_frames_at_zero(robot)
    scale = max(robot.reach, 1e-12)

    def parallel(a: np.ndarray, b: np.ndarray) -> bool:
        return bool(np.linalg.norm(np.cross(a, b)) < _EPS)

    if all(parallel(z[0], z[j]) for j in range(robot.n)):
        first = 0
        kind = "planar"
    elif robot.n >= 2 and all(parallel(z[1], z[j]) for j in range(1, robot.n)) and abs(z[0] @ z[1]) < _EPS \
            and abs(z[1] @ (p[0] - p[1])) < _EPS * scale:
        first = 1
        kind = "yaw+planar"
    else:
        raise IKInputError.of("FABRIK in armkit supports planar arms (all joint axes parallel) and a yaw joint "
                              "followed by a planar arm; robot {robot!r} is neither; use method 'ccd' or 'lm'",
                              robot=robot.name)
    nrm = z[first] / np.linalg.norm(z[first])
    pts = np.vstack([p[first:], e[None]])
    flat = pts - np.outer((pts - pts[0]) @ nrm, nrm)           # projected on the plane through the root
    seg = np.diff(flat, axis=0)
    lengths = np.linalg.norm(seg, axis=1)
    if np.any(lengths < _EPS * scale):
        raise IKInputError.of("FABRIK needs distinct joint points in the plane; robot {robot!r} has a zero-length "
                              "segment (coincident joint axes); use method 'ccd' or 'lm'", robot=robot.name)
    xh = seg[0] / lengths[0]
    yh = np.cross(nrm, xh)
    phi0 = np.arctan2(seg @ yh, seg @ xh)                       # segment directions at q = 0
    sign = np.array([1.0 if zj @ nrm > 0 else -1.0 for zj in z[first:]])
    return dict(kind=kind, first=first, root=pts[0], nrm=nrm, xh=xh, yh=yh, lengths=lengths, phi0=phi0,
                sign=sign, height=float((e - pts[0]) @ nrm), z0=z[0], p0=p[0])


def _planar_points(st: dict, q: np.ndarray) -> np.ndarray:
    """Joint and tool points in plane coordinates (k, m + 1, 2) for planar joint values q (k, m)."""
    phi = st["phi0"] + np.cumsum(st["sign"] * q, axis=-1)
    steps = st["lengths"] * np.stack([np.cos(phi), np.sin(phi)], axis=-1).swapaxes(-1, -2)
    out = np.zeros(q.shape[:-1] + (q.shape[-1] + 1, 2))
    out[..., 1:, :] = np.cumsum(steps.swapaxes(-1, -2), axis=-2)
    return out


def _planar_angles(st: dict, P: np.ndarray) -> np.ndarray:
    seg = np.diff(P, axis=-2)
    phi = np.arctan2(seg[..., 1], seg[..., 0]) - st["phi0"]
    rel = np.diff(np.concatenate([np.zeros(phi.shape[:-1] + (1,)), phi], axis=-1), axis=-1)
    return np.angle(np.exp(1j * rel)) * st["sign"]


def _fabrik_plane(st: dict, goal: np.ndarray, q: np.ndarray, project, iterations: int, tol: float,
                  rows: Optional[list]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Planar FABRIK from q (k, m) to 2-D goals (k, 2). Returns q, iterations used, final error."""
    L = st["lengths"]
    k, m = q.shape
    q = project(q)
    P = _planar_points(st, q)
    err = np.linalg.norm(P[:, -1] - goal, axis=-1)
    used = np.zeros(k, np.int64)
    active = err > tol
    best = err.copy()
    stale = np.zeros(k, np.int64)
    for _ in range(iterations):
        idx = np.flatnonzero(active)
        if len(idx) == 0:
            break
        Q = P[idx].copy()
        g = goal[idx]
        Q[:, m] = g                                   # backward: tool on the target
        for i in range(m - 1, -1, -1):
            d = Q[:, i] - Q[:, i + 1]
            nd = np.linalg.norm(d, axis=-1, keepdims=True)
            d = np.where(nd > 1e-15, d / np.maximum(nd, 1e-300), np.array([1.0, 0.0]))
            Q[:, i] = Q[:, i + 1] + L[i] * d
        Q[:, 0] = 0.0                                 # forward: root back in place
        for i in range(m):
            d = Q[:, i + 1] - Q[:, i]
            nd = np.linalg.norm(d, axis=-1, keepdims=True)
            d = np.where(nd > 1e-15, d / np.maximum(nd, 1e-300), np.array([1.0, 0.0]))
            Q[:, i + 1] = Q[:, i] + L[i] * d
        qi = project(_planar_angles(st, Q))           # limits: back to angles, project, recompute points
        q[idx] = qi
        P[idx] = _planar_points(st, qi)
        err[idx] = np.linalg.norm(P[idx, -1] - g, axis=-1)
        used[idx] += 1
        if rows is not None:
            for j, v in zip(idx, err[idx]):
                rows[j].append(v)
        impr = err[idx] < best[idx] * (1.0 - 1e-3)
        best[idx] = np.minimum(best[idx], err[idx])
        stale[idx] = np.where(impr, 0, stale[idx] + 1)
        active[idx] = (err[idx] > tol) & (stale[idx] < _STALL_PASSES)
    return q, used, err


def solve_fabrik(robot: Robot, target: ArrayLike, q0: ArrayLike, *, mask: Optional[ArrayLike] = None,
                 tol: Optional[tuple[float, float]] = None, max_iterations: Optional[int] = DEFAULT_MAX_SWEEPS,
                 restarts: Optional[int] = DEFAULT_SWEEP_RESTARTS, seed: Any = None, enforce_limits: bool = True,
                 trace: bool = False, time_limit: Optional[float] = None) -> IKResult:
    """FABRIK inverse kinematics for position targets on planar and yaw + planar arms.

    Parameters
    ----------
    robot : Robot
        A planar arm or a yaw joint followed by a planar arm (see the module docstring);
        anything else raises :class:`~armkit.IKInputError`.
    target : array_like, shape (B, 3) or (B, 4, 4)
        Target positions (length units); of a pose only the position is used.
    q0 : array_like, shape (B, n)
        Start configurations (the points FABRIK starts from).
    mask : None
        Position targets only.
    tol : (float, float), optional
        Position tolerance first (length units).
    max_iterations : int, default :data:`~armkit.ik.DEFAULT_MAX_SWEEPS` (2000)
        Backward/forward passes per attempt.
    restarts : int, default :data:`~armkit.ik.DEFAULT_SWEEP_RESTARTS` (20)
        Further attempts from random configurations for targets not yet solved.
    seed : int, optional
    enforce_limits : bool, default True
    trace : bool, default False
        Position error after every pass: ``trace`` (B, passes).
    time_limit : float, optional
        Accepted for a uniform interface; unused.

    Returns
    -------
    IKResult

    Examples
    --------
    >>> import armkit, numpy as np
    >>> from armkit.ik.fabrik import solve_fabrik
    >>> arm = armkit.load("fighter")
    >>> res = solve_fabrik(arm, [[24.861, 14.353, 187.181]], np.zeros((1, 3)), seed=0)
    >>> bool(res.success[0])
    True
    """
    st = _structure(robot)
    prob, note = _position_problem(robot, target, q0, mask, tol, enforce_limits, "FABRIK")
    iterations = DEFAULT_MAX_SWEEPS if max_iterations is None else int(max_iterations)
    restarts = DEFAULT_SWEEP_RESTARTS if restarts is None else int(restarts)
    rng = np.random.default_rng(0 if seed is None else seed)   # seeded by default: reproducible
    B, n, f = prob.B, robot.n, st["first"]
    tol_p = prob.tol[0] * _TOL_FACTOR
    goal = prob.target
    root, nrm, xh, yh = st["root"], st["nrm"], st["xh"], st["yh"]
    lo, hi = prob.lower[f:], prob.upper[f:]
    sub = object.__new__(Problem)
    sub.__dict__.update(prob.__dict__)
    sub.lower, sub.upper = lo, hi
    sub.robot = _PlanarView(robot.prismatic[f:])  # type: ignore[assignment]

    def project(qp: np.ndarray) -> np.ndarray:
        return _project(sub, qp)

    yaws = _yaw_candidates(st, goal)
    q_out = prob.q0.copy()
    err_out = np.full(B, np.inf)
    it_out = np.zeros(B, np.int64)
    rows_out: list = [[] for _ in range(B)] if trace else []
    for yaw in yaws:
        q = _project(prob, prob.q0.copy())
        if yaw is not None:
            q[:, 0] = yaw
            q = _project(prob, q)
            # bring the target into the q0 = 0 plane by undoing the yaw about axis 0
            g3 = _rotate_about(goal - st["p0"], st["z0"], -q[:, 0]) + st["p0"]
        else:
            g3 = goal
        rel = g3 - root
        goal2 = np.stack([rel @ xh, rel @ yh], axis=-1)
        off_plane = np.abs(rel @ nrm - st["height"])
        rows: Optional[list] = [[] for _ in range(B)] if trace else None
        qp, used, err = _fabrik_plane(st, goal2, q[:, f:].copy(), project, iterations, tol_p, rows)
        left = np.flatnonzero(err > tol_p)
        for _ in range(restarts):                      # random restarts for the unsolved
            if len(left) == 0:
                break
            start = rng.uniform(prob.rand_lo[f:], prob.rand_hi[f:], size=(len(left), n - f))
            qr, ur, er = _fabrik_plane(st, goal2[left], start, project, iterations, tol_p,
                                       [rows[i] for i in left] if rows is not None else None)
            better = er < err[left]
            qp[left[better]] = qr[better]
            err[left[better]] = er[better]
            used[left] += ur
            left = left[er > tol_p]
        q[:, f:] = qp
        err = np.hypot(err, off_plane)
        take = err < err_out
        q_out[take], err_out[take], it_out[take] = q[take], err[take], used[take]
        if rows is not None:
            for j in np.flatnonzero(take):
                rows_out[j] = rows[j]
    reasons = _reasons(prob, st, err_out > tol_p, it_out)
    return assemble(prob, q_out, it_out, "fabrik", reasons, _trace_array(rows_out) if trace else None, note)


def _yaw_candidates(st: dict, goal: np.ndarray) -> list:
    """The two yaw angles ``(B,)`` (front and back) that put each target in the arm's plane (yaw + planar
    arms), or ``[None]`` for a planar arm."""
    if st["kind"] != "yaw+planar":
        return [None]
    z0, p0, nrm = st["z0"], st["p0"], st["nrm"]
    d = goal - p0
    a = d @ nrm
    b = d @ np.cross(z0, nrm)
    r = np.hypot(a, b)
    off = np.arccos(np.clip(st["height"] / np.maximum(r, 1e-300), -1.0, 1.0))
    base = np.arctan2(b, a)
    # turning joint 1 by psi turns the arm's plane normal to n(psi) = cos psi nrm + sin psi (z0 x nrm);
    # the target lies in the plane when n(psi) . (target - p0) = h: two solutions (front and back)
    return [np.angle(np.exp(1j * (base + off))), np.angle(np.exp(1j * (base - off)))]


def _reasons(prob: Problem, st: dict, failed: np.ndarray, passes: np.ndarray) -> dict[int, tuple[str, str]]:
    """Reason and message of every failed target: out of the arm's reach, or no convergence."""
    unreachable, dist = prob.unreachable()
    unit = prob.robot.unit
    reasons: dict[int, tuple[str, str]] = {}
    for i in map(int, np.flatnonzero(failed)):
        if unreachable[i]:
            reasons[i] = ("unreachable", unreachable_note(f"{dist[i]:.4g} {unit}", f"{prob.const['reach at most']:.4g} {unit}",
                                                          prob.const["reach from"]))
        else:
            reasons[i] = ("max iterations", Fielded.of("FABRIK did not converge in {n} passes ({kind} structure)",
                                                       n=int(passes[i]), kind=st["kind"]))
    settle(prob, reasons)   # where a closed form settles it (armkit.ik.verdict)
    return reasons


class _PlanarView:
    """The attributes of a Robot that ``_project`` reads, for the planar joints only."""

    def __init__(self, prismatic: np.ndarray) -> None:
        self.prismatic = prismatic


def _rotate_about(v: np.ndarray, axis: np.ndarray, angle: np.ndarray) -> np.ndarray:
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    return v * c + np.cross(axis, v) * s + np.outer(v @ axis, axis) * (1.0 - c)

