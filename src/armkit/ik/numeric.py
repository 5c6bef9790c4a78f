r"""Numerical IK on any serial chain: Levenberg-Marquardt (damped least squares) and Newton.

Both solvers iterate every target of a batch together (batched FK, Jacobians and linear
solves; with Numba, one compiled loop per target run in parallel threads) and report
honestly: ``success`` comes only from the FK check :func:`armkit.ik.verify` (or its
masked form, see ``mask``), and a failure says why (``reason``) and by how much
(``message``). A single target with the default mask and tolerance takes a short route
to the same kernel, seeds and check (single-call latency is mostly Python around the
kernel); its result is the same, field by field.

The task error
--------------
For the current tool pose :math:`(R, p)` and the target :math:`(R_t, p_t)`

.. math::

    e = \begin{pmatrix} s\,(p_t - p) \\ \log(R^T R_t)^\vee \end{pmatrix} \in \mathbb{R}^6 ,

the position part in metres (``s`` = metres per length unit, so a mm arm behaves like a
m arm) in the world frame, the rotation part as a rotation vector in the *target* frame
(the rotation still to be done). The solvers model the error as
:math:`e(q + \Delta q) \approx e(q) - J\,\Delta q` with the task Jacobian

.. math::

    J = \begin{pmatrix} s\,J_v \\ R_t^T J_\omega \end{pmatrix}

(:math:`J_v, J_\omega` the rows of the geometric Jacobian in the world frame; prismatic
joints move in metres). The linear rows are exact. The angular rows are the derivative of
the rotation error only at zero error: the exact rows are
:math:`J_r^{-1}(e_r)\,R_t^T J_\omega`, with the inverse right Jacobian of SO(3)

.. math::

    J_r^{-1}(\phi) = I + \tfrac12 [\phi]_\times
        + \Bigl(\frac{1}{\theta^2} - \frac{1 + \cos\theta}{2\theta\sin\theta}\Bigr)[\phi]_\times^2,
    \qquad \theta = \lVert\phi\rVert ,

so the exact rows differ from the rows used by at most
:math:`\lVert J_r^{-1}(e_r) - I\rVert_2 = \sqrt{\theta^2/4 + c^2\theta^4}` relative to them
(:math:`c` the bracket above): 0.51 at 1 rad of rotation error, 0.050 at 0.1 rad, 0.0050 at
0.01 rad (``tests/ik/test_lm_task_jacobian.py`` checks this by finite differences of the
solvers' own error, for both engines). Near a solution this costs nothing: a Jacobian error
of order :math:`\theta` times a step of order :math:`\theta` is of second order, so the
convergence stays quadratic; far from the target the step differs from the Gauss-Newton
step by up to that factor, which the damping and the accept/reject rule below absorb.
The exact rows were tried (NumPy engine, 1,000 random reachable poses per arm, default
restarts) and do not pay: mean iterations 19.3 -> 20.4 (UR5), 28.7 -> 29.0 (Panda),
26.4 -> 27.6 (Puma 560, and one failure more), so the solvers keep the simpler rows.
A weight vector ``w`` (the ``mask``) over ``(x, y, z, rx, ry, rz)`` selects what
matters: position-only is ``(1, 1, 1, 0, 0, 0)``; a 5-DOF arm that cannot choose the
rotation about its tool axis uses ``(1, 1, 1, 1, 1, 0)``. Masked position axes are world
axes; masked rotation axes are axes of the target frame.

Levenberg-Marquardt
-------------------
With :math:`W = \mathrm{diag}(w)` and the cost :math:`E = \tfrac12 e^T W e` one step solves

.. math:: (J^T W J + \lambda I)\,\Delta q = J^T W e, \qquad \lambda = \mu E + 10^{-12},

an error-dependent damping in the spirit of Chan and Lawrence (1988) and Sugihara (2011):
far from the target the step is short and safe, near it :math:`\lambda \to 0` and the
iteration becomes Gauss-Newton with quadratic convergence. Steps that lower the cost are
accepted (and :math:`\mu` shrinks), others are rejected (and :math:`\mu` grows), as in
Marquardt's method. After each step the joints are projected into their limits (revolute
joints by whole turns when that brings them inside, then clamping). An attempt stops when
it converges, after ``max_iterations`` steps, or when its cost has not fallen by 1 % for
8 steps; the next attempt starts from a random configuration inside the limits, up to
``restarts`` times.

Newton
------
:func:`solve_newton` is the textbook iteration :math:`\Delta q = (W^{1/2} J)^+ W^{1/2} e`
with the Moore-Penrose pseudo-inverse, full steps and no damping: fast near a solution,
erratic near singularities. It exists for teaching and comparison; use LM for work.

References
----------
S. K. Chan and P. D. Lawrence, "General inverse kinematics with the error damped
pseudoinverse", ICRA 1988. T. Sugihara, "Solvability-unconcerned
inverse kinematics by the Levenberg-Marquardt method", IEEE T-RO 27(5), 2011.
"""

from __future__ import annotations

import math
import time
from typing import Any, Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _jit_loader
from .. import kinematics as _kinematics
from .._text import Fielded
from ..errors import ArmkitError, ShapeError
from ..model.robot import Robot
from .result import (DEFAULT_MAX_ITERATIONS, DEFAULT_NEWTON_RESTARTS, DEFAULT_RESTARTS, IKResult, default_tolerance,
                     verify)

__all__ = ["solve_lm", "solve_newton"]

Array = NDArray[np.float64]

_TOL_FACTOR = 0.25     # iterate to a quarter of the tolerance, so that the FK check has margin
_STALL_STEPS = 8       # an attempt ends when its cost has not fallen by 1 % in this many steps
_SINGULAR_SIGMA = 1e-5  # smallest singular value (metres, rad) below which a stalled solve is "singular"


# ----------------------------------------------------------------------------------------- inputs
_W_POSE = np.ones(6)
_W_POSITION = np.array([1, 1, 1, 0, 0, 0.0])
_W_POSE.setflags(write=False)
_W_POSITION.setflags(write=False)


def _constants(robot: Robot) -> dict:
    """Per-robot arrays the solvers need on every call (computed once, kept in the robot's cache)."""
    c = robot.cache.get("lm_constants")
    if c is None:
        rev = ~robot.prismatic
        reach = robot.reach
        span = 2.0 * reach if np.isfinite(reach) and reach > 0 else 1.0
        free_lo = np.where(rev, -math.pi, -np.inf)
        free_hi = np.where(rev, math.pi, np.inf)
        lo, hi = robot.lower.astype(float), robot.upper.astype(float)
        c = dict(rev=rev, reach=reach, origin=robot.base[:3, 3].copy(),
                 limits=(lo, hi, np.where(np.isfinite(lo), lo, np.where(rev, -math.pi, -span)),
                         np.where(np.isfinite(hi), hi, np.where(rev, math.pi, span))),
                 free=(free_lo, free_hi, np.where(rev, -math.pi, -span), np.where(rev, math.pi, span)))
        c["origin xyz"] = tuple(c["origin"].tolist())
        # arms with a yaw joint and three parallel pitch joints (the SO-101): the reach is measured from the
        # shoulder (its nearest position over the yaw angle), which is tighter than from the base origin
        try:
            from .analytic.yaw_pitch3 import shoulder_reach

            c["shoulder"] = shoulder_reach(robot)
        except Exception:   # noqa: BLE001 - a robot without a standard form: the base-origin bound only
            c["shoulder"] = None
        c["reach from"] = "the base origin" if c["shoulder"] is None else "the shoulder"
        c["reach at most"] = reach if c["shoulder"] is None else c["shoulder"][-1]
        for key in ("limits", "free"):  # lower, upper, random-start low and high as one (4, n) array
            c["packed " + key] = np.ascontiguousarray(np.stack(c[key]))
        robot.cache["lm_constants"] = c
    return c


class Problem:
    """Normalised inputs shared by the numerical solvers (internal)."""

    def __init__(self, robot: Robot, target: ArrayLike, q0: ArrayLike, mask: Optional[ArrayLike],
                 tol: Optional[tuple[float, float]], enforce_limits: bool, what: str = "solve_lm") -> None:
        if not isinstance(robot, Robot):
            raise ArmkitError.of("{what}: robot must be an armkit.Robot, got {type}", what=what,
                                 type=type(robot).__name__)
        t = np.asarray(target, dtype=float)
        if t.ndim == 3 and t.shape[1:] == (4, 4):
            self.position_target = False
            poses = t
        elif t.ndim == 2 and t.shape[1] == 3:
            self.position_target = True
            poses = np.broadcast_to(np.eye(4), (t.shape[0], 4, 4)).copy()
            poses[:, :3, 3] = t
        else:
            raise ShapeError.of("{what}: target must have shape (B, 4, 4) or (B, 3), got {shape}", what=what,
                                shape=t.shape)
        if not np.all(np.isfinite(t)):
            raise ShapeError.of("{what}: target contains NaN or infinite values", what=what)
        B = t.shape[0]
        q = robot.check_q(q0, "q0")
        if q.shape != (B, robot.n):
            raise ShapeError.of("{what}: q0 must have shape ({B}, {n}) for {B} targets, got {shape}", what=what, B=B,
                                n=robot.n, shape=q.shape)
        if mask is None:
            w = _W_POSITION if self.position_target else _W_POSE
        else:
            w = np.asarray(mask, dtype=float)
            if w.shape != (6,) or not np.all(np.isfinite(w)) or np.any(w < 0) or not np.any(w > 0):
                raise ShapeError.of("{what}: mask must be 6 non-negative weights over (x, y, z, rx, ry, rz) with at "
                                    "least one positive, got {mask!r}", what=what, mask=mask)
            if self.position_target:
                w = w.copy()
                w[3:] = 0.0
                if not np.any(w > 0):
                    raise ShapeError.of("{what}: a position target needs a positive weight on x, y or z, got {mask!r}",
                                        what=what, mask=mask)
        self.robot = robot
        self.target = t
        self.poses = np.ascontiguousarray(poses)
        self.q0 = np.array(q, dtype=float)
        self.w = w
        self.B = B
        self.tol: tuple[float, float] = (float(tol[0]), float(tol[1])) if tol is not None and len(tol) == 2 \
            else default_tolerance(robot) if tol is None else (-1.0, -1.0)
        if min(self.tol) <= 0 or min(self.tol) <= 0:
            raise ShapeError.of("{what}: tol must be (position, rotation) > 0, got {tol!r}", what=what, tol=tol)
        self.enforce_limits = bool(enforce_limits)
        self.s = robot.unit_scale
        self.const = _constants(robot)
        # without limits revolute joints are wrapped into [-pi, pi] and prismatic joints are free
        self.lower, self.upper, self.rand_lo, self.rand_hi = self.const["limits" if enforce_limits else "free"]

        if w is _W_POSE or w is _W_POSITION:
            self.full_pose, self.position_only = w is _W_POSE, w is _W_POSITION
        else:
            self.full_pose = bool(np.all(w > 0))
            self.position_only = bool(np.all(w[:3] > 0) and not np.any(w[3:] > 0))

    @property
    def packed_limits(self) -> Array:
        """lower, upper, random-start low and high as one (4, n) array for the kernel (cached per robot)."""
        if self.lower is self.const["limits"][0]:
            return self.const["packed limits"]  # type: ignore[no-any-return]
        if self.lower is self.const["free"][0]:
            return self.const["packed free"]  # type: ignore[no-any-return]
        return np.ascontiguousarray(np.stack([self.lower, self.upper, self.rand_lo, self.rand_hi]))

    @property
    def internal_tol(self) -> tuple[float, float]:
        return self.tol[0] * self.s * _TOL_FACTOR, self.tol[1] * _TOL_FACTOR

    def unreachable(self) -> tuple[NDArray[np.bool_], Array]:
        """Targets whose position is provably beyond the reach, and their distances from where the reach is
        measured: ``const["reach from"]`` (the base origin, or the shoulder of a yaw-pitch3 arm such as the
        SO-101), the reach being ``const["reach at most"]``."""
        sh = self.const["shoulder"]
        if sh is not None:
            dist = shoulder_distance(sh, self.poses[:, :3, 3])
            if not (self.w[0] > 0 and self.w[1] > 0 and self.w[2] > 0):
                return np.zeros(self.B, bool), dist
            return dist > sh[-1] * (1.0 + 1e-9) + self.tol[0], dist
        if self.B == 1:
            o = self.const["origin"]
            P = self.poses[0]
            dist = np.array([math.sqrt((P[0, 3] - o[0]) ** 2 + (P[1, 3] - o[1]) ** 2 + (P[2, 3] - o[2]) ** 2)])
        else:
            d = self.poses[:, :3, 3] - self.const["origin"]
            dist = np.sqrt(np.einsum("bi,bi->b", d, d))
        if not (self.w[0] > 0 and self.w[1] > 0 and self.w[2] > 0):
            return np.zeros(self.B, bool), dist
        return dist > self.const["reach"] * (1.0 + 1e-9) + self.tol[0], dist


def shoulder_distance(sh: tuple, p: Array) -> Array:
    """Distance of points ``p`` ``(B, 3)`` from the circle ``sh = (centre (3,), axis (3,), radius, reach)`` that
    the shoulder runs on as the yaw joint turns (:func:`armkit.ik.analytic.yaw_pitch3.shoulder_reach`)."""
    c, u, rs = sh[0], sh[1], sh[2]
    w = p - c
    z = w @ u
    rh = np.sqrt(np.maximum(np.einsum("bi,bi->b", w, w) - z * z, 0.0))
    return np.hypot(rh - rs, z)


def _seed_base(seed: Any) -> int:
    """The first target's restart seed (0 <= base < 2**62), reproducible from ``seed``."""
    if seed is None:   # the default is seeded too: the same call gives the same answer every run
        seed = 0
    if type(seed) is int or isinstance(seed, (int, np.integer)) and not isinstance(seed, bool):
        return (int(seed) * 0x9E3779B97F4A7C15 + 0x632BE59BD9B4E019) % 2**62
    return int(np.random.default_rng(seed).integers(0, 2**62))


def _seeds(seed: Any, B: int) -> NDArray[np.uint64]:
    """One restart seed per target, reproducible from ``seed``: base, base + 1, ..."""
    return (np.uint64(_seed_base(seed)) + np.arange(B, dtype=np.uint64)).astype(np.uint64)


# ------------------------------------------------------------------------------ NumPy primitives
def _rotation_vector(M: Array) -> Array:
    """Batched log of rotation matrices ``(..., 3, 3) -> (..., 3)``, accurate near 0 and pi."""
    v = np.stack([M[..., 2, 1] - M[..., 1, 2], M[..., 0, 2] - M[..., 2, 0], M[..., 1, 0] - M[..., 0, 1]], -1)
    sn = 0.5 * np.linalg.norm(v, axis=-1)
    c = 0.5 * (np.trace(M, axis1=-2, axis2=-1) - 1.0)
    th = np.arctan2(sn, c)
    f = np.where(th < 1e-6, 0.5 + th**2 / 12.0, th / (2.0 * np.where(sn > 0, sn, 1.0)))
    out = f[..., None] * v
    near_pi = (sn <= 1e-6) & (c <= 0.0)
    if np.any(near_pi):
        Mp, cp, vp, tp = M[near_pi], c[near_pi], v[near_pi], th[near_pi]
        S = 0.5 * (Mp + np.swapaxes(Mp, -1, -2)) - cp[:, None, None] * np.eye(3)
        S /= (1.0 - cp)[:, None, None]          # = a a^T
        i = np.argmax(np.diagonal(S, axis1=-2, axis2=-1), axis=-1)
        col = S[np.arange(len(i)), :, i]
        a = col / np.sqrt(np.maximum(col[np.arange(len(i)), i], 1e-300))[:, None]
        a *= np.where(np.einsum("bi,bi->b", a, vp) < 0, -1.0, 1.0)[:, None]
        out[near_pi] = tp[:, None] * a
    return out


def _evaluate(prob: Problem, q: Array, idx: NDArray[np.intp]) -> tuple[Array, Array, Array]:
    """Residual e (k, 6), weighted cost E (k,) and task Jacobian J (k, 6, n) at q (k, n) for targets idx."""
    from ..kinematics import fk, jacobian

    T = fk(prob.robot, q)
    J = jacobian(prob.robot, q).copy()
    Tt = prob.poses[idx]
    rev = ~prob.robot.prismatic
    J[:, :3, rev] *= prob.s
    e = np.empty((len(idx), 6))
    e[:, :3] = (Tt[:, :3, 3] - T[:, :3, 3]) * prob.s
    if np.any(prob.w[3:] > 0):
        Rt = Tt[:, :3, :3]
        e[:, 3:] = _rotation_vector(np.swapaxes(T[:, :3, :3], -1, -2) @ Rt)
        J[:, 3:] = np.swapaxes(Rt, -1, -2) @ J[:, 3:]
    else:
        e[:, 3:] = 0.0
    E = 0.5 * np.einsum("bi,i,bi->b", e, prob.w, e)
    return e, E, J


def _errors(prob: Problem, e: Array) -> tuple[Array, Array]:
    sel = prob.w > 0
    return (np.sqrt(np.sum(np.where(sel[:3], e[:, :3] ** 2, 0.0), axis=-1)),
            np.sqrt(np.sum(np.where(sel[3:], e[:, 3:] ** 2, 0.0), axis=-1)))


def _project(prob: Problem, q: Array) -> Array:
    """Joint values into the limits: revolute joints by whole turns where that suffices, then clamping."""
    lo, up = prob.lower, prob.upper
    rev = ~prob.robot.prismatic
    two_pi = 2.0 * math.pi
    with np.errstate(invalid="ignore"):
        down = q - two_pi * np.ceil((q - up) / two_pi)
        upw = q + two_pi * np.ceil((lo - q) / two_pi)
    q = np.where(rev & (q > up) & (down >= lo), down, q)
    q = np.where(rev & (q < lo) & (upw <= up), upw, q)
    return np.clip(q, lo, up)


def _leaves_range(prob: Problem, v: Array) -> NDArray[np.bool_]:
    """Where joint values v (k, n) lie outside the limits even after whole turns (revolute joints)."""
    lo, up = prob.lower, prob.upper
    two_pi = 2.0 * math.pi
    with np.errstate(invalid="ignore"):
        down = v - two_pi * np.ceil((v - up) / two_pi)
        upw = v + two_pi * np.ceil((lo - v) / two_pi)
    rev = ~prob.robot.prismatic
    over = (v > up) & ~(rev & (down >= lo))
    under = (v < lo) & ~(rev & (upw <= up))
    return over | under


def _step(prob: Problem, q: Array, e: Array, E: Array, J: Array, mu: Array, newton: bool) -> Array:
    """Joint step (k, n) in joint units: pseudo-inverse (Newton) or damped least squares with an active set.

    The LM step treats the limits as an active set: joints that the step would push out of
    range move exactly to their limit and the other joints are solved again for the rest
    of the error (repeated until no free joint leaves its range).
    """
    w = prob.w
    prism = prob.robot.prismatic
    to_units = np.where(prism, 1.0 / prob.s, 1.0)
    if newton:
        sw = np.sqrt(w)
        dq = np.einsum("bij,bj->bi", np.linalg.pinv(J * sw[None, :, None], rcond=1e-12), e * sw)
        return dq * to_units
    k, n = q.shape
    fixed = np.zeros((k, n), bool)
    dfix = np.zeros((k, n))
    lam = mu * E + 1e-12
    diag = np.arange(n)
    for _ in range(n + 1):
        r = (e - np.einsum("bij,bj->bi", J, dfix)) * w
        Jf = J * (~fixed)[:, None, :]
        A = np.swapaxes(Jf, -1, -2) @ (Jf * w[None, :, None])
        A[:, diag, diag] = np.where(fixed, 1.0, A[:, diag, diag] + lam[:, None])
        dq = np.linalg.solve(A, np.einsum("bji,bj->bi", Jf, r)[..., None])[..., 0]
        v = q + dq * to_units
        leave = ~fixed & _leaves_range(prob, v)
        if not leave.any():
            break
        bound = np.where(v > prob.upper, prob.upper, prob.lower)
        dfix = np.where(leave, (bound - q) / to_units, dfix)
        fixed |= leave
    return np.where(fixed, dfix, dq) * to_units


# ------------------------------------------------------------------------------ NumPy engine
def _run_numpy(prob: Problem, q: Array, max_iterations: int, attempts: int, first_attempt: int,
               rng: np.random.Generator, newton: bool, want_trace: bool
               ) -> tuple[Array, NDArray[np.int64], NDArray[np.int64], NDArray[np.bool_], Array, list]:
    """All targets together; returns q, iterations, attempts used, converged, best cost, trace rows."""
    B, n = q.shape
    tol_p, tol_r = prob.internal_tol
    all_idx = np.arange(B)
    q = _project(prob, q.copy())
    if first_attempt > 0:
        q = rng.uniform(prob.rand_lo, prob.rand_hi, size=(B, n))
    e, E, J = _evaluate(prob, q, all_idx)
    best_q, best_E = q.copy(), E.copy()
    mu = np.ones(B)
    iters = np.zeros(B, np.int64)
    it_attempt = np.zeros(B, np.int64)
    used = np.ones(B, np.int64)
    stale = np.zeros(B, np.int64)
    attempt_best = E.copy()
    converged = np.zeros(B, bool)
    active = np.ones(B, bool)
    trace_rows: list = [[] for _ in range(B)] if want_trace else []
    while True:
        better = E < best_E
        best_E = np.where(better, E, best_E)
        best_q[better] = q[better]
        ep, er = _errors(prob, e)
        conv = active & (ep <= tol_p) & (er <= tol_r)
        converged |= conv
        active &= ~conv
        # attempts that ran out: restart from random configurations, or stop
        over = active & ((it_attempt >= max_iterations) | (stale >= _STALL_STEPS) | (mu > 1e10))
        if np.any(over):
            more = over & (used < attempts)
            active &= ~(over & ~more)
            if np.any(more):
                k = np.flatnonzero(more)
                q[k] = _project(prob, rng.uniform(prob.rand_lo, prob.rand_hi, size=(len(k), n)))
                e[k], E[k], J[k] = _evaluate(prob, q[k], k)
                used[k] += 1
                it_attempt[k] = 0
                stale[k] = 0
                mu[k] = 1.0
                attempt_best[k] = E[k]
                continue  # check the new starts for convergence first
        k = np.flatnonzero(active)
        if len(k) == 0:
            break
        qn = _project(prob, q[k] + _step(prob, q[k], e[k], E[k], J[k], mu[k], newton))
        en, En, Jn = _evaluate(prob, qn, k)
        iters[k] += 1
        it_attempt[k] += 1
        acc = np.ones(len(k), bool) if newton else En < E[k]
        a = k[acc]
        q[a], e[a], E[a], J[a] = qn[acc], en[acc], En[acc], Jn[acc]
        mu[a] = np.maximum(mu[a] * 0.5, 1e-6)
        mu[k[~acc]] *= 4.0
        impr = E[k] < 0.99 * attempt_best[k]
        attempt_best[k] = np.where(impr, E[k], attempt_best[k])
        stale[k] = np.where(impr, 0, stale[k] + 1)
        if want_trace:
            p_, r_ = _errors(prob, e[k])
            for j, v in zip(k, np.hypot(p_, r_)):
                trace_rows[j].append(v)
    q = np.where(converged[:, None], q, best_q)
    return q, iters, used, converged, np.where(converged, E, best_E), trace_rows


# ------------------------------------------------------------------------------- Numba engine
def _jit():
    """The compiled kernels, or None when Numba is unavailable or the NumPy backend is chosen."""
    return _jit_loader.kernels("ik._jit_lm")


def _kernel_args(const: dict, s: float, tol: tuple[float, float], w: Array, max_iterations: int, attempts: int,
                 first_attempt: int) -> Array:
    """The kernel's packed options ``params`` (layout: :mod:`armkit.ik._jit_lm`), cached per robot (they
    repeat from call to call)."""
    key = ("params", tol, True if w is _W_POSE else False if w is _W_POSITION else w.tobytes(), max_iterations,
           attempts, first_attempt)
    params = const.get(key)
    if params is None:
        k = _jit_loader.module("ik._jit_lm")
        params = np.empty(k.N_PARAMS)
        params[k.SCALE], params[k.TOL_P], params[k.TOL_R] = s, tol[0] * s * _TOL_FACTOR, tol[1] * _TOL_FACTOR
        params[k.W:k.W + 6] = w
        params[k.MAX_ITERATIONS], params[k.FIRST_ATTEMPT], params[k.ATTEMPTS] = max_iterations, first_attempt, attempts
        params.setflags(write=False)
        if len(const) < 64:
            const[key] = params
    return params


def _run_jit(kernels, prob: Problem, q: Array, max_iterations: int, attempts: int, first_attempt: int,
             seeds: NDArray[np.uint64], want_trace: bool):
    B, n = q.shape
    q = np.array(q, dtype=float, order="C")
    info = np.zeros((B, 4))
    cap = max_iterations * attempts if want_trace else 0
    trace = np.full((B, cap), np.nan) if cap else np.empty((B, 0))
    params = _kernel_args(prob.const, prob.s, prob.tol, prob.w, max_iterations, attempts, first_attempt)
    run = kernels.lm_batch if B >= 8 else kernels.lm_serial
    run(_kinematics.packed(prob.robot)[1], prob.packed_limits, params, prob.poses, seeds, q, trace, info)
    iters = info[:, 0].astype(np.int64)
    rows = [trace[i, :iters[i]].tolist() for i in range(B)] if want_trace else []
    return q, iters, info[:, 2].astype(np.int64), info[:, 1] == 0, info[:, 3], rows


# ------------------------------------------------------------------------------------ checking
def check(prob: Problem, q: Array) -> tuple[Array, Array, NDArray[np.bool_], NDArray[np.bool_]]:
    """The FK check: :func:`armkit.ik.verify`, or its masked form when only some axes count.

    With a partial mask the reported errors are the norms of the masked residual (position
    in length units over the weighted world axes, rotation in rad over the weighted target axes).
    """
    robot = prob.robot
    if prob.full_pose or prob.position_only:
        return verify(robot, q, prob.target, prob.position_only or prob.position_target, prob.tol,
                      prob.enforce_limits)
    e, _, _ = _evaluate(prob, q, np.arange(len(q)))
    dp, dr = _errors(prob, e)
    dp = dp / prob.s
    within = robot.within_limits(q)
    ok = (dp <= prob.tol[0]) & (dr <= prob.tol[1])
    if prob.enforce_limits:
        ok &= within
    return dp, dr, ok, within


def _fmt(x: float) -> str:
    return f"{x:.2e}" if (x != 0 and (abs(x) < 1e-3 or abs(x) >= 1e4)) else f"{x:.4g}"


def unreachable_note(distance: str, reach: str, origin: str) -> Fielded:
    """Why a target is out of reach (``distance`` and ``reach`` with their unit), measured from ``origin``
    (``const["reach from"]``: the base origin, or the shoulder); its template and fields go with it."""
    if origin == "the shoulder":
        return Fielded.of("target is {distance} from the shoulder; the arm reaches at most {reach}; q is the closest "
                          "configuration found", distance=distance, reach=reach)
    return Fielded.of("target is {distance} from the base origin; the arm reaches at most {reach}; q is the closest "
                      "configuration found", distance=distance, reach=reach)


def residual_note(dp: float, dr: float | None, unit: str) -> Fielded:
    """``position error ... [, rotation error ... rad]``, in words that keep their fields."""
    if dr is None:
        return Fielded.of("position error {error}", error=f"{_fmt(dp)} {unit}")
    return Fielded.of("position error {error}, rotation error {rotation}", error=f"{_fmt(dp)} {unit}",
                      rotation=f"{_fmt(dr)} rad")


def assemble(prob: Problem, q: Array, iterations: ArrayLike, branch: str, failure_reasons: dict[int, tuple[str, str]],
             trace: Optional[Array] = None, note: str = "") -> IKResult:
    """Build the :class:`IKResult`: success from :func:`check`, reasons and messages.

    ``failure_reasons`` maps a target index to ``(reason, sentence)`` for failures whose
    cause the solver knows; other failures get "max iterations" (or "joint limits" when
    the pose is met but the limits are not).
    """
    dp, dr, ok, within = check(prob, q)
    B = prob.B
    unit = prob.robot.unit
    its: NDArray[np.int64] = np.broadcast_to(np.asarray(iterations, np.int64), (B,)).copy()
    reason = np.empty(B, dtype=object)
    message = np.empty(B, dtype=object)
    rot = not (prob.position_only or prob.position_target)
    dpl, drl, okl, itl, wl = dp.tolist(), dr.tolist(), ok.tolist(), its.tolist(), within.tolist()
    for i in range(B):
        resid = residual_note(dpl[i], drl[i] if rot else None, unit)
        if okl[i]:
            reason[i] = "converged"
            message[i] = Fielded.of("converged in {n} iterations: {residual}.", n=itl[i], residual=resid)
        elif i in failure_reasons:
            reason[i], text = failure_reasons[i]
            message[i] = Fielded.of("{text}; {residual}.", text=text, residual=resid)
        elif prob.enforce_limits and not wl[i]:
            reason[i] = "joint limits"
            message[i] = Fielded.of("the configuration breaks the joint limits; {residual}.", residual=resid)
        else:
            reason[i] = "max iterations"
            message[i] = Fielded.of("no solution within {n} iterations; best {residual}.", n=itl[i], residual=resid)
        if note:
            message[i] = Fielded.of("{message} {note}", message=message[i], note=note)
    return IKResult(q=q, success=ok, position_error=dp, rotation_error=dr, iterations=its,
                    branch=np.full(B, branch, dtype=object), within_limits=within,
                    reason=reason.astype(str), message=message, trace=trace)


def _trace_array(rows: list) -> Optional[Array]:
    if not rows:
        return None
    width = max(1, max(len(r) for r in rows))
    out = np.full((len(rows), width), np.nan)
    for i, r in enumerate(rows):
        out[i, :len(r)] = r
        if len(r) and len(r) < width:   # a finished target keeps its last error
            out[i, len(r):] = r[-1]
    return out


def _smallest_sigma(prob: Problem, q: Array, idx: NDArray[np.intp]) -> Array:
    _, _, J = _evaluate(prob, q, idx)
    J = J * np.sqrt(prob.w)[None, :, None]
    sv: Array = np.asarray(np.linalg.svd(J, compute_uv=False), dtype=float)
    return sv[:, min(5, J.shape[-1] - 1)]        # the rank-deciding value (the 6th for redundant arms)


# --------------------------------------------------------------------------------- the solvers
def _solve(prob: Problem, method: str, max_iterations: Optional[int], restarts: Optional[int], seed: Any,
           trace: bool, time_limit: Optional[float], diagnose: bool = True) -> IKResult:
    max_iterations = DEFAULT_MAX_ITERATIONS if max_iterations is None else int(max_iterations)
    restarts = DEFAULT_RESTARTS if restarts is None else int(restarts)
    if max_iterations < 0 or restarts < 0:
        raise ShapeError.of("max_iterations and restarts must be >= 0, got {max_iterations} and {restarts}",
                            max_iterations=max_iterations, restarts=restarts)
    newton = method == "newton"
    B = prob.B
    unreachable, dist = prob.unreachable()
    any_unreachable = bool(unreachable.any())
    kernels = None if newton else _jit()
    seeds = _seeds(seed, B)
    total_attempts = restarts + 1
    if kernels is not None and time_limit is None and not any_unreachable:  # the common case, no bookkeeping
        q, iters, used, _, _, rows = _run_jit(kernels, prob, prob.q0, max_iterations, total_attempts, 0, seeds,
                                              trace)
        return _finish(prob, q, iters, used, method, max_iterations, restarts, seed, _trace_array(rows), diagnose)
    rng = np.random.default_rng(0 if seed is None else seed) if kernels is None else None
    q = prob.q0.copy()
    iters = np.zeros(B, np.int64)
    used = np.zeros(B, np.int64)
    done = np.zeros(B, bool)
    rows = [[] for _ in range(B)] if trace else []
    t0 = time.perf_counter()
    if time_limit is None:
        # provably unreachable targets get one attempt (the closest configuration from q0), no restarts
        rounds = [(np.flatnonzero(unreachable), 0, 1), (np.flatnonzero(~unreachable), 0, total_attempts)]
    else:  # attempt by attempt, checking the clock between rounds
        rounds = [(np.flatnonzero(unreachable), 0, 1)] + \
                 [(np.flatnonzero(~unreachable), a, 1) for a in range(total_attempts)]
    for idx, first, count in rounds:
        idx = idx[~done[idx]]
        if len(idx) == 0:
            continue
        if time_limit is not None and first > 0 and time.perf_counter() - t0 > time_limit:
            break
        sub = _subproblem(prob, idx)
        if kernels is not None:
            out = _run_jit(kernels, sub, q[idx], max_iterations, count, first, seeds[idx], trace)
        else:
            out = _run_numpy(sub, q[idx], max_iterations, count, first, rng or np.random.default_rng(0 if seed is None else seed),
                             newton, trace)
        q_i, it_i, used_i, conv_i, _, rows_i = out
        q[idx] = q_i
        iters[idx] += it_i
        used[idx] += used_i
        done[idx] = conv_i | (count == 1 and first == 0 and unreachable[idx[0]])
        if trace:
            for j, r in zip(idx, rows_i):
                rows[j].extend(r)
    reasons: dict[int, tuple[str, str]] = {}
    unit = prob.robot.unit
    for i in (np.flatnonzero(unreachable) if any_unreachable else ()):
        reasons[int(i)] = ("unreachable", unreachable_note(f"{_fmt(dist[i])} {unit}",
                                                           f"{_fmt(prob.const['reach at most'])} {unit}",
                                                           prob.const["reach from"]))
    res = assemble(prob, q, iters, method, reasons, _trace_array(rows))
    if diagnose and not res.success.all() and len(failed := np.flatnonzero(~res.success & ~unreachable)):
        _diagnose(prob, res, failed, reasons, used, method, max_iterations, restarts, seed)
        res = assemble(prob, q, iters, method, reasons, res.trace)
    return res


def _finish(prob: Problem, q: Array, iters: NDArray[np.int64], used: NDArray[np.int64], method: str,
            max_iterations: int, restarts: int, seed: Any, trace: Optional[Array], diagnose: bool) -> IKResult:
    """The result of a solve without provably unreachable targets: checked, and failures diagnosed."""
    res = assemble(prob, q, iters, method, {}, trace)
    if diagnose and not res.success.all():
        failed = np.flatnonzero(~res.success)
        reasons: dict[int, tuple[str, str]] = {}
        _diagnose(prob, res, failed, reasons, used, method, max_iterations, restarts, seed)
        res = assemble(prob, q, iters, method, reasons, res.trace)
    return res


_EYE_1 = np.eye(4)[None]
_LM_BRANCH = np.full(1, "lm", dtype=object)
_CONVERGED = np.array(["converged"])      # the dtype of assemble's reason field: "<U9"
for _a in (_EYE_1, _LM_BRANCH, _CONVERGED):
    _a.setflags(write=False)


def _solve_one(robot: Robot, target: Any, q0: Any, max_iterations: Optional[int], restarts: Optional[int],
               seed: Any, enforce_limits: bool) -> Optional[IKResult]:
    """:func:`solve_lm` of one target with the default mask and tolerance, without the batch machinery.

    Same kernel, same seeds, the same FK check (:func:`~armkit.ik.verify`) and the same
    result as the general path, ~25 µs less Python around the kernel. ``None`` for
    anything else (the general path then handles it and raises the errors): a target
    other than a float64 (1, 4, 4) pose or (1, 3) position, ``q0`` other than float64
    (1, n), non-finite values, a provably unreachable target, no Numba.
    """
    if type(target) is not np.ndarray or type(q0) is not np.ndarray or not isinstance(robot, Robot):
        return None
    point = target.shape == (1, 3)
    if not (point or target.shape == (1, 4, 4)) or q0.shape != (1, robot.n) \
            or target.dtype != np.float64 or q0.dtype != np.float64:
        return None
    max_iterations = DEFAULT_MAX_ITERATIONS if max_iterations is None else max_iterations
    restarts = DEFAULT_RESTARTS if restarts is None else restarts
    if type(max_iterations) is not int or type(restarts) is not int or max_iterations < 0 or restarts < 0:
        return None
    kernels = _jit()
    if kernels is None:
        return None
    tol = default_tolerance(robot)
    c = _constants(robot)
    x, y, z = (target[0] if point else target[0, :3, 3]).tolist()
    sh = c["shoulder"]
    if sh is None:
        ox, oy, oz = c["origin xyz"]
        beyond = math.sqrt((x - ox) ** 2 + (y - oy) ** 2 + (z - oz) ** 2) > c["reach"] * (1.0 + 1e-9) + tol[0]
    else:   # the distance from the shoulder's circle (cx, cy, cz, ux, uy, uz, radius, reach)
        cx, cy, cz, ux, uy, uz, rs, reach = sh[3]
        wx, wy, wz = x - cx, y - cy, z - cz
        h = wx * ux + wy * uy + wz * uz
        rh = math.sqrt(max(wx * wx + wy * wy + wz * wz - h * h, 0.0))
        beyond = math.hypot(rh - rs, h) > reach * (1.0 + 1e-9) + tol[0]
    if beyond:
        return None  # provably unreachable: the general path explains it
    if point:
        poses = _EYE_1.copy()
        poses[0, :3, 3] = target[0]
    else:
        poses = np.ascontiguousarray(target)
    q = np.array(q0, order="C")
    params = _kernel_args(c, robot.unit_scale, tol, _W_POSITION if point else _W_POSE, max_iterations,
                          restarts + 1, 0)
    info = np.zeros((1, 4))
    limits = c["packed limits" if enforce_limits else "packed free"]
    FP = robot.cache.get("packed_chain") or _kinematics.packed(robot)
    if not kernels.lm_single(FP[1], limits, params, poses, _seed_base(seed), q, info):
        return None  # NaN or infinity in the target or q0: the general path says which
    dp, dr, ok, within = verify(robot, q, target, point, tol, enforce_limits)
    iters = int(info[0, 0])
    if not ok[0]:  # a failure: say why, as the general path does
        prob = Problem(robot, target, q0, None, None, enforce_limits)
        return _finish(prob, q, np.array([iters], dtype=np.int64), info[:, 2].astype(np.int64), "lm",
                       max_iterations, restarts, seed, None, True)
    message = Fielded.of("converged in {n} iterations: {residual}.", n=iters,
                         residual=residual_note(float(dp[0]), None if point else float(dr[0]), robot.unit))
    return IKResult._of(q=q, success=ok, position_error=dp, rotation_error=dr, iterations=np.array([iters], np.int64),
                        branch=_LM_BRANCH.copy(), within_limits=within, reason=_CONVERGED.copy(),
                        message=np.array([message], dtype=object))


def _subproblem(prob: Problem, idx: NDArray[np.intp]) -> Problem:
    sub = object.__new__(Problem)
    sub.__dict__.update(prob.__dict__)
    sub.target, sub.poses, sub.q0, sub.B = prob.target[idx], prob.poses[idx], prob.q0[idx], len(idx)
    return sub


def _diagnose(prob: Problem, res: IKResult, failed: NDArray[np.intp], reasons: dict, used: NDArray[np.int64],
              method: str, max_iterations: int, restarts: int, seed: Any) -> None:
    """Why did these targets fail? Joint limits (a solution exists without them), singular, or budget."""
    sub = _subproblem(prob, failed)
    if prob.enforce_limits:
        free = object.__new__(Problem)
        free.__dict__.update(sub.__dict__)
        free.enforce_limits = False
        free.lower, free.upper, free.rand_lo, free.rand_hi = prob.const["free"]
        alt = _solve(free, method, max_iterations, min(restarts, 5), seed, False, None, diagnose=False)
    sigma = _smallest_sigma(prob, res.q[failed], failed)
    too_many = int(np.count_nonzero(prob.w > 0)) > prob.robot.n and bool(np.any(prob.w[3:] > 0))
    if too_many:   # more to meet than joints (a pose for a 5-DOF arm): say so, with the nearest pose's miss
        from .partial import too_few_joints

        short = too_few_joints(prob, res, failed, seed)
    for j, i in enumerate(failed):
        i = int(i)
        if prob.enforce_limits and alt.success[j]:
            broken = ", ".join(prob.robot.limit_violations(alt.q[j])) or "limits"
            reasons[i] = ("joint limits", Fielded.of("found solutions only outside the joint limits ({broken}); q is "
                                                     "the best configuration found inside them", broken=broken))
        elif too_many:
            reasons[i] = ("unreachable", short[j])
        elif sigma[j] < _SINGULAR_SIGMA:
            reasons[i] = ("singular", Fielded.of("stalled at a singular configuration (smallest singular value "
                                                 "{sigma}) after {n} iterations and {starts} starts",
                                                 sigma=f"{sigma[j]:.1e}", n=int(res.iterations[i]), starts=int(used[i])))
        else:
            reasons[i] = ("max iterations", Fielded.of("no solution within {n} iterations ({starts} starts of at most "
                                                       "{steps} steps)", n=int(res.iterations[i]), starts=int(used[i]),
                                                       steps=max_iterations))


def solve_lm(robot: Robot, target: ArrayLike, q0: ArrayLike, *, mask: Optional[ArrayLike] = None,
             tol: Optional[tuple[float, float]] = None, max_iterations: Optional[int] = DEFAULT_MAX_ITERATIONS,
             restarts: Optional[int] = DEFAULT_RESTARTS, seed: Any = None, enforce_limits: bool = True, trace: bool = False,
             time_limit: Optional[float] = None) -> IKResult:
    r"""Levenberg-Marquardt (damped least squares) IK for a batch of targets.

    Parameters
    ----------
    robot : Robot
    target : array_like, shape (B, 4, 4) or (B, 3)
        Target poses ``T_world_tool`` or positions (position-only IK), length units of the robot.
    q0 : array_like, shape (B, n)
        Initial guesses (warm start); the first attempt starts here.
    mask : array_like, shape (6,), optional
        Weights over ``(x, y, z, rx, ry, rz)``; position axes are world axes, rotation axes
        are axes of the target frame. Default: all ones for a pose, ``(1, 1, 1, 0, 0, 0)``
        for a position. ``(1, 1, 1, 1, 1, 0)`` leaves the rotation about the tool's z axis free.
    tol : (float, float), optional
        Position (length units) and rotation (rad) tolerance; default
        :func:`~armkit.ik.default_tolerance` (1e-9 m or 1e-6 mm, 1e-9 rad).
    max_iterations : int, default :data:`~armkit.ik.DEFAULT_MAX_ITERATIONS` (100)
        Steps per attempt.
    restarts : int, default :data:`~armkit.ik.DEFAULT_RESTARTS` (50)
        Further attempts from random configurations inside the limits.
    seed : int or numpy Generator, optional
        Seeds the restarts: the same seed gives the same answers. The default (None) is
        seed 0, so a call without a seed is reproducible too.
    enforce_limits : bool, default True
        Keep joints inside their limits (projection after each step) and require it for success.
    trace : bool, default False
        Record the error norm (metres and rad combined) after every step: ``trace`` (B, iterations).
    time_limit : float, optional
        Seconds after which no further restart begins (checked between attempts).

    Returns
    -------
    IKResult
        Batched over B. ``reason`` is "converged", "unreachable" (the position lies beyond
        ``robot.reach`` from the base: q is the closest configuration found), "joint limits"
        (a solution exists only outside the limits), "singular" (stalled where the Jacobian
        lost rank) or "max iterations" (budget spent; the residual is in ``message``).

    Examples
    --------
    >>> import armkit, numpy as np
    >>> from armkit.ik.numeric import solve_lm
    >>> arm = armkit.load("puma560")
    >>> T = armkit.fk(arm, [[0.3, 0.5, -1.0, 0.2, 0.6, -0.4]])
    >>> res = solve_lm(arm, T, np.zeros((1, 6)), seed=1)
    >>> bool(res.success[0]), str(res.reason[0])
    (True, 'converged')
    >>> bool(np.allclose(armkit.fk(arm, res.q), T, atol=1e-9))
    True
    """
    if mask is None and tol is None and not trace and time_limit is None:
        one = _solve_one(robot, target, q0, max_iterations, restarts, seed, enforce_limits)
        if one is not None:
            return one
    prob = Problem(robot, target, q0, mask, tol, enforce_limits, "solve_lm")
    return _solve(prob, "lm", max_iterations, restarts, seed, trace, time_limit)


def solve_newton(robot: Robot, target: ArrayLike, q0: ArrayLike, *, mask: Optional[ArrayLike] = None,
                 tol: Optional[tuple[float, float]] = None, max_iterations: Optional[int] = DEFAULT_MAX_ITERATIONS,
                 restarts: Optional[int] = DEFAULT_NEWTON_RESTARTS, seed: Any = None, enforce_limits: bool = True,
                 trace: bool = False, time_limit: Optional[float] = None) -> IKResult:
    r"""Newton-Raphson IK with the pseudo-inverse: :math:`\Delta q = J^+ e`, full steps, no damping.

    The textbook method, for teaching and for comparison with :func:`solve_lm` (same
    parameters and result). Converges quadratically near a regular solution; near a
    singularity the pseudo-inverse produces huge steps, which the joint-limit projection
    and random restarts have to absorb. Runs on NumPy (batched), never on the JIT kernel.

    Examples
    --------
    >>> import armkit, numpy as np
    >>> from armkit.ik.numeric import solve_newton
    >>> arm = armkit.load("planar2")
    >>> res = solve_newton(arm, [[1.2, 0.3, 0.0]], [[0.1, 0.5]], seed=0)
    >>> bool(res.success[0])
    True
    """
    prob = Problem(robot, target, q0, mask, tol, enforce_limits, "solve_newton")
    return _solve(prob, "newton", max_iterations, restarts, seed, trace, time_limit)
