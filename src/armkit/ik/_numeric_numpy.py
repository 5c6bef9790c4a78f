"""The NumPy engine of the numerical solvers: task error, Jacobian, LM/Newton steps, the batched loop.

The algorithm is described in :mod:`armkit.ik.numeric`; the compiled kernels
(:mod:`armkit.ik._jit_lm`) run the same iteration. :func:`_evaluate` and :func:`_errors` also
serve the FK check of masked targets (:mod:`armkit.ik._numeric_report`) and the diagnosis of
failures (:func:`_smallest_sigma`). Everything here is re-exported by :mod:`armkit.ik.numeric`.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ..kinematics import fk, jacobian
from ._numeric_inputs import Problem

Array = NDArray[np.float64]

_STALL_STEPS = 8       # an attempt ends when its cost has not fallen by 1 % in this many steps


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



def _smallest_sigma(prob: Problem, q: Array, idx: NDArray[np.intp]) -> Array:
    _, _, J = _evaluate(prob, q, idx)
    J = J * np.sqrt(prob.w)[None, :, None]
    sv: Array = np.asarray(np.linalg.svd(J, compute_uv=False), dtype=float)
    return sv[:, min(5, J.shape[-1] - 1)]        # the rank-deciding value (the 6th for redundant arms)
