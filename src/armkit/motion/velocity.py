r"""Velocity kinematics: twists from joint rates, joint rates from twists, resolved-rate control.

Twists are ordered ``(v, omega)`` like the rows of :func:`armkit.jacobian`: ``v`` is the
velocity of the tool origin (robot length unit per second), ``omega`` the angular
velocity (rad/s), both in the base frame.

**Velocity rows.** A requested end-effector velocity may name only some rows of the twist
(:func:`velocity_rows`): 6 values are ``(vx, vy, vz, wx, wy, wz)``, 3 values ``(vx, vy, vz)``
(position only), 2 values ``(vx, vy)`` (planar arms). Pass ``rows=`` to choose others. (The rows
an *arm* can move, which the manipulability measures use, are :func:`armkit.kinematics.task_rows`.)

**Damped least squares.** :math:`\dot q = J^T (J J^T + \lambda^2 I)^{-1} \dot x`.
``damping="auto"`` (default for :func:`joint_rates` with ``method="dls"``) uses the
schedule of Nakamura and Hanafusa / Maciejewski: :math:`\lambda^2 = 0` while the
smallest singular value :math:`\sigma_{min}` of the (metre-scaled) task Jacobian is above
:math:`\epsilon = 0.04` m, and
:math:`\lambda^2 = \lambda_{max}^2 (1 - (\sigma_{min}/\epsilon)^2)` below it, with
:math:`\lambda_{max} = 0.04` m (so :math:`\lambda^2 \le 1.6 \times 10^{-3}\,\mathrm{m}^2`).
A number gives a constant :math:`\lambda` in metres (e.g. ``0.01``: :math:`\lambda^2 = 10^{-4}\,\mathrm{m}^2`).
Near a singularity DLS trades exactness for bounded rates: :math:`\|\dot q\| \le \|\dot x\| / (2\lambda)`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, Literal, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._text import Fielded
from ..errors import ArgumentError, LimitError, ShapeError
from ..kinematics import fk, jacobian, movable_rows
from ..model.robot import Robot

__all__ = ["ROW_NAMES", "SINGULAR_SIGMA", "DLS_EPSILON", "DLS_LAMBDA_MAX", "JointRates", "twist",
           "joint_rates", "velocity_rows", "damping_schedule", "resolved_rate"]

Array = NDArray[np.float64]
ROW_NAMES = ("vx", "vy", "vz", "wx", "wy", "wz")
SINGULAR_SIGMA = 1e-3
"""Smallest singular value (task Jacobian, lengths in metres) below which a warning is raised."""
DLS_EPSILON = 0.04
"""Damping starts when the smallest singular value (metres) drops below this."""
DLS_LAMBDA_MAX = 0.04
"""Largest damping factor lambda (metres) of the automatic schedule."""


def velocity_rows(count: int, rows: Sequence[int | str] | None = None) -> tuple[int, ...]:
    """The twist rows that an end-effector velocity of ``count`` values gives (see the module docstring):
    ``rows`` (names of :data:`ROW_NAMES` or indices) when given, else by the count.

    Not :func:`armkit.kinematics.task_rows`, which is about the arm (the rows it can move).

    >>> velocity_rows(2), velocity_rows(3), velocity_rows(2, ["vx", "wz"])
    ((0, 1), (0, 1, 2), (0, 5))
    """
    if rows is not None:
        idx = tuple(ROW_NAMES.index(r) if isinstance(r, str) else int(r) for r in rows)
        if len(idx) != count:
            raise ShapeError.of("rows names {k} task rows but the velocity has {count} values", k=len(idx), count=count)
        return idx
    defaults = {6: (0, 1, 2, 3, 4, 5), 3: (0, 1, 2), 2: (0, 1)}
    if count not in defaults:
        raise ShapeError.of("an end-effector velocity needs 6 (v, omega), 3 (v) or 2 (vx, vy) values, got {count}",
                            count=count)
    return defaults[count]


def twist(robot: Robot, q: ArrayLike, qd: ArrayLike, frame: Literal["base", "tool"] = "base") -> Array:
    r"""End-effector twist :math:`(v, \omega) = J(q)\,\dot q`, shape ``(..., 6)``.

    Parameters
    ----------
    q, qd : array_like, shape (..., n)
        Joint values and rates (rad/s, or length units per second for prismatic joints).
    frame : {"base", "tool"}

    Examples
    --------
    >>> import armkit, numpy as np
    >>> arm = armkit.load("planar2")  # stretched along x, both joints at 1 rad/s: vy = (a1 + a2) + a2
    >>> twist(arm, [0, 0], [1, 1]).round(12) + 0.0
    array([0., 2., 0., 0., 0., 2.])
    """
    J = jacobian(robot, q, frame=frame)
    qd = robot.check_q(qd, "qd")
    return np.einsum("...ij,...j->...i", J, qd)


def damping_schedule(sigma_min: ArrayLike, epsilon: float = DLS_EPSILON, lambda_max: float = DLS_LAMBDA_MAX) -> Array:
    r"""Automatic damping :math:`\lambda^2` (m^2) from the smallest singular value (m).

    >>> damping_schedule([0.1, 0.02, 0.0]).round(6)
    array([0.    , 0.0012, 0.0016])
    """
    s = np.asarray(sigma_min, dtype=float)
    return np.where(s < epsilon, lambda_max ** 2 * (1 - (s / epsilon) ** 2), 0.0)


@dataclass(frozen=True)
class JointRates:
    """Joint rates for a requested end-effector velocity.

    Attributes
    ----------
    qd : ndarray, shape (n,)
        Joint rates (rad/s or length units per second).
    achieved : ndarray, shape (k,)
        ``J qd`` in the requested task rows: what the arm really does.
    residual : float
        ``|achieved - requested|`` (length units per second and rad/s mixed as given).
    sigma_min : float
        Smallest singular value of the task Jacobian (lengths in metres).
    singular : bool
        ``sigma_min`` below :data:`SINGULAR_SIGMA`: the warning flag.
    direction : ndarray, shape (k,)
        Unit task direction (left singular vector of ``sigma_min``) that the arm can
        hardly move along: the "singular direction".
    damping : float
        :math:`\\lambda^2` used (m^2; 0 for the pseudo-inverse).
    method : str
    rows : tuple of str
    message : str
        A sentence: what is limited, and along which direction.
    """

    qd: Array
    achieved: Array
    residual: float
    sigma_min: float
    singular: bool
    direction: Array
    damping: float
    method: str
    rows: tuple[str, ...]
    message: str


def _scaled_task_jacobian(robot: Robot, q: Array, rows: tuple[int, ...]) -> tuple[Array, Array]:
    """Task rows of J with lengths in metres, and the row scale used (to undo it)."""
    J = jacobian(robot, q)[list(rows), :]
    s = robot.unit_scale
    row_scale = np.array([s if r < 3 else 1.0 for r in rows])
    col_scale = np.where(robot.prismatic, 1.0 / s, 1.0)
    return J * row_scale[:, None] * col_scale[None, :], row_scale


def joint_rates(robot: Robot, q: ArrayLike, xd: ArrayLike, method: Literal["pinv", "dls"] = "pinv",
                damping: float | Literal["auto"] = "auto", rows: Sequence[int | str] | None = None) -> JointRates:
    """Joint rates that produce the end-effector velocity ``xd`` (one configuration).

    Parameters
    ----------
    robot : Robot
    q : array_like, shape (n,)
    xd : array_like, shape (k,)
        Requested velocity in the task rows (length units per second, rad/s).
    method : {"pinv", "dls"}
        Moore-Penrose pseudo-inverse (least squares, minimum norm) or damped least squares.
        The pseudo-inverse drops singular values below ``1e-12 * max(1, sigma_max)`` of the
        Jacobian with lengths in metres: below that they are rounding noise of the SVD
        (about ``eps * sigma_max``), and inverting them would give rates of order 1e12.
    damping : float or "auto"
        For ``"dls"``: constant lambda in metres, or the automatic schedule
        (:func:`damping_schedule`).
    rows : sequence of str or int, optional
        Twist rows of ``xd`` (default from its length, see :func:`velocity_rows`).

    Returns
    -------
    JointRates

    Examples
    --------
    >>> import armkit, numpy as np
    >>> r = joint_rates(armkit.load("planar2"), [0.0, np.pi / 2], [0.0, 0.5])   # J = [[-0.5, -0.5], [1, 0]]
    >>> r.qd.round(6) + 0.0, r.singular
    (array([ 0.5, -0.5]), False)
    """
    qv = robot.check_q(q)
    if qv.shape != (robot.n,):
        raise ShapeError.of("q must be one configuration of shape ({n},), got {shape}", n=robot.n, shape=qv.shape)
    x = np.asarray(xd, dtype=float)
    if x.ndim != 1 or not np.all(np.isfinite(x)):
        raise ShapeError.of("xd must be a finite vector of 2, 3 or 6 values, got shape {shape}", shape=x.shape)
    idx = velocity_rows(len(x), rows)
    if method not in ("pinv", "dls"):
        raise ArgumentError.of("method must be 'pinv' or 'dls', got {method!r}", method=method)
    Js, row_scale = _scaled_task_jacobian(robot, qv, idx)
    xs = x * row_scale
    U, S, Vt = np.linalg.svd(Js)
    k = min(Js.shape)
    sigma_min = float(S[k - 1]) if len(idx) <= robot.n else 0.0
    movable = movable_rows(robot)
    never = tuple(i for i in idx if i not in movable)      # rows the arm never changes (a SCARA's wx, wy)
    kept = [j for j, i in enumerate(idx) if i in movable]
    weakest = None     # the direction it cannot move in, among the rows it can move (when some never move)
    if never and kept:   # conditioned by the rows it can move; the others' components are dropped
        Uk, Sk, _ = np.linalg.svd(Js[kept])
        sigma_min = float(Sk[len(kept) - 1]) if len(kept) <= robot.n else 0.0
        weakest = np.zeros(len(idx))
        weakest[kept] = Uk[:, len(kept) - 1]
    if method == "pinv":
        lam2 = 0.0
        # Singular values below 1e-12 x max(1, sigma_max) (lengths in metres) are dropped: that is
        # ~4,500 machine epsilons of the largest one, where an SVD's singular values are rounding
        # noise (their absolute error is about eps * sigma_max), and 1/sigma would turn that noise
        # into joint rates of 1e12. The damped method (dls) needs no cut-off: damping bounds 1/sigma.
        cutoff = 1e-12 * max(1.0, float(S[0]))
        inv = np.where(S > cutoff, 1.0 / np.where(S > cutoff, S, 1.0), 0.0)
    else:
        lam2 = float(damping_schedule(sigma_min)) if damping == "auto" else float(damping) ** 2
        if lam2 < 0 or not math.isfinite(lam2):
            raise ArgumentError.of("damping must be a non-negative number of metres or 'auto', got {damping!r}",
                                   damping=damping)
        inv = S / (S ** 2 + lam2) if lam2 > 0 else np.where(S > 1e-12, 1.0 / np.where(S > 1e-12, S, 1.0), 0.0)
    with np.errstate(over="ignore", invalid="ignore"):   # checked below: overflow is an error, not a warning
        qd_s = Vt[:k].T @ (inv[:k] * (U[:, :k].T @ xs))
    col_scale = np.where(robot.prismatic, 1.0 / robot.unit_scale, 1.0)
    qd = qd_s * col_scale
    with np.errstate(over="ignore", invalid="ignore"):
        achieved = (jacobian(robot, qv)[list(idx), :] @ qd)
        residual = float(np.linalg.norm(achieved - x))
    if not (np.all(np.isfinite(qd)) and np.all(np.isfinite(achieved)) and math.isfinite(residual)):
        raise LimitError.of("the requested velocity (largest component {largest:.3g}) is too large: the joint rates "
                            "overflow float64; ask for a smaller velocity", largest=float(np.max(np.abs(x))))
    direction = weakest if weakest is not None else U[:, len(idx) - 1] if len(idx) > robot.n else U[:, k - 1]
    direction = direction * (1 if direction[np.argmax(np.abs(direction))] > 0 else -1)
    names = tuple(ROW_NAMES[i] for i in idx)
    singular = sigma_min < SINGULAR_SIGMA
    dir_txt = ", ".join(f"{n} {v:+.3f}" for n, v in zip(names, direction) if abs(v) > 5e-4)
    if singular:     # a template and its fields: the sentence in the user's language
        msg = Fielded.of("near a singularity (smallest singular value {sigma} m): the arm cannot move along "
                         "({direction}); rates are damped, the velocity is only approximated" if lam2 > 0 else
                         "near a singularity (smallest singular value {sigma} m): the arm cannot move along "
                         "({direction}); the pseudo-inverse drops that direction",
                         sigma=f"{sigma_min:.2e}", direction=dir_txt)
    else:
        msg = Fielded.of("well-conditioned (smallest singular value {sigma} m)", sigma=f"{sigma_min:.3g}")
    asked = [ROW_NAMES[i] for j, i in enumerate(idx) if i in never and x[j] != 0.0]
    if asked:          # a component the arm can never produce: said, not hidden in the residual
        msg = Fielded.of("{note}; the arm never moves along {rows} (its {n} joints cannot), so those components are "
                         "dropped", note=msg, rows=", ".join(asked), n=robot.n)
    return JointRates(qd, achieved, residual, sigma_min, singular, direction, lam2, method, names, msg)


@dataclass(frozen=True)
class _RateResult:
    q: Array
    qd: Array
    error: Array
    clamped: NDArray[np.bool_]


def resolved_rate(robot: Robot, q0: ArrayLike, path: Callable[[float], tuple[Array, Array]], duration: float,
                  dt: float = 0.01, rows: Sequence[int | str] | None = None, gain: float = 10.0,
                  qd_max: ArrayLike | None = None, damping: float | Literal["auto"] = "auto",
                  enforce_limits: bool = True) -> Any:
    r"""Resolved-rate motion control along a Cartesian path (Whitney 1969), with DLS.

    At each step :math:`\dot q = J^{\#}(\dot x_d + K (x_d - x))`, then the rates are scaled
    down together so that no joint exceeds ``qd_max``, integrated over ``dt`` (explicit
    Euler) and clamped to the joint limits.

    Parameters
    ----------
    robot : Robot
    q0 : array_like, shape (n,)
        Start configuration (should put the tool at ``path(0)``).
    path : callable
        ``path(t) -> (x_d, xd_d)``: desired task position (shape ``(k,)`` in the task rows,
        positions only: ``k`` = 2 or 3) and its velocity.
    duration, dt : float
        Seconds.
    rows : sequence, optional
        Task rows (default by ``k``: 2 -> vx, vy; 3 -> vx, vy, vz).
    gain : float
        Position feedback gain K (1/s).
    qd_max : array_like, shape (n,) or float, optional
        Joint speed limits (rad/s); none by default.
    damping : float or "auto"
        DLS damping (see :func:`joint_rates`).
    enforce_limits : bool
        Clamp to the joint limits (joints on a limit stop; the error then grows and shows).

    Returns
    -------
    armkit.motion.trajectory.Trajectory
        Sampled ``t, q, qd, qdd`` plus ``positions`` (tool point) and ``deviation``
        (``|x - x_d|`` per step, length units).
    """
    from .trajectory import Trajectory

    qv = robot.check_q(q0, "q0").astype(float).copy()
    if duration <= 0 or dt <= 0:
        raise ArgumentError.of("duration and dt must be positive, got {duration}, {dt}", duration=duration, dt=dt)
    steps = int(round(duration / dt))
    x0, _ = path(0.0)
    k = len(np.atleast_1d(x0))
    if k not in (2, 3):
        raise ShapeError.of("resolved_rate follows positions: path(t) must give 2 or 3 values, got {k}", k=k)
    idx = velocity_rows(k, rows)
    vmax = None if qd_max is None else np.broadcast_to(np.asarray(qd_max, dtype=float), (robot.n,))
    lo, hi = robot.lower, robot.upper
    t = np.arange(steps + 1) * dt
    Q = np.empty((steps + 1, robot.n))
    QD = np.zeros((steps + 1, robot.n))
    dev = np.empty(steps + 1)
    for i, ti in enumerate(t):
        xd, vd = (np.asarray(v, dtype=float) for v in path(float(ti)))
        x = fk(robot, qv)[list(idx), 3]
        dev[i] = float(np.linalg.norm(x - xd))
        Q[i] = qv
        if i == steps:
            break
        cmd = vd + gain * (xd - x)
        qd = joint_rates(robot, qv, cmd, method="dls", damping=damping, rows=[ROW_NAMES[r] for r in idx]).qd
        if vmax is not None:
            ratio = np.max(np.abs(qd) / vmax)
            if ratio > 1:
                qd = qd / ratio
        q_next = qv + qd * dt
        if enforce_limits:
            q_next = np.clip(q_next, lo, hi)
            qd = (q_next - qv) / dt
        QD[i] = qd
        qv = q_next
    QD[-1] = 0.0
    QDD = np.asarray(np.gradient(QD, dt, axis=0))
    pos = fk(robot, Q)[..., :3, 3]
    return Trajectory(t, Q, QD, QDD, positions=pos, deviation=dev, label="resolved rate")
