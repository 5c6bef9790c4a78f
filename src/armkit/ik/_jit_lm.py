"""Numba kernel of the Levenberg-Marquardt IK loop: one target per call, scalar loops.

The whole solve (FK + Jacobian, residual, damped normal equations by Cholesky, joint
limit projection, accept/reject, random restarts) runs in compiled code, so a single
target costs a few microseconds per iteration instead of the ~50 us per iteration that
NumPy's per-call overhead imposes. :func:`lm_batch` runs many targets in parallel
threads. Imported lazily by :mod:`armkit.ik.numeric` (never at ``import armkit``).

The algorithm is the same as the NumPy engine in :mod:`armkit.ik.numeric`; read that
module for the mathematics.
"""

from __future__ import annotations

import math

import numpy as np

from .. import _jit_loader

_jit_loader.install_cache_fallback()  # before the first cache=True: read-only installs cache elsewhere

from numba import njit, prange  # noqa: E402
from .._jit_twins import parallel_twin  # noqa: E402

# The 12-scalar pose helpers of the kinematics kernels (a pose is the 3x4 affine part, row by row) and
# their packed chain layout: _load(P, k) = P[k], _mul(X, P, k) = X · P[k], _move(X, t, sin t, cos t,
# prismatic) = X · Rz(t) or X · Tz(t). The end of this module ties its on-disk cache to that file.
from ..kinematics._jit import PRISMATIC, _load, _move, _mul  # noqa: E402

# status codes written to info[:, 1]
CONVERGED, EXHAUSTED = 0, 1

# The packed arguments of the kernels (built by armkit.ik.numeric, once per robot and options):
#   P       (2n + 2, ROW)  the chain: base, pre[n], post[n], tool; P[1 + k, PRISMATIC] joint k's flag
#                          (armkit.kinematics.packed(robot)[1])
#   limits  (4, n)         lower, upper, random-start low, random-start high
#   params  (N_PARAMS,)    the solver options, at these indices:
SCALE = 0            # metres per robot length unit
TOL_P, TOL_R = 1, 2  # position (m) and rotation (rad) tolerance of the iteration
W = 3                # weights of (x, y, z, rx, ry, rz): params[W:W + 6]
MAX_ITERATIONS = 9   # steps per attempt
FIRST_ATTEMPT = 10   # index of the first attempt (0: from q; later ones: random restarts)
ATTEMPTS = 11        # attempts to make
N_PARAMS = 12


@njit(cache=True, inline="always")
def _copy(src, dst):
    """dst[:] = src for 1-D arrays of the same length, as a loop: a slice assignment would compile
    Numba's shape-mismatch error message (integer-to-string formatting), ~3 s on first use."""
    for j in range(dst.shape[0]):
        dst[j] = src[j]


@njit(cache=True, inline="always")
def _prismatic(P, k):
    return P[1 + k, PRISMATIC] != 0.0


@njit(cache=True)
def _pose_jacobian(P, q, s, J):
    """Tool pose (12-tuple) and the geometric Jacobian in J (6, n), linear rows in metres."""
    X = _load(P, 0)
    n = q.shape[0]
    for k in range(n):
        X = _mul(X, P, 1 + k)
        J[0, k], J[1, k], J[2, k] = X[3], X[7], X[11]
        J[3, k], J[4, k], J[5, k] = X[2], X[6], X[10]
        t = q[k]
        X = _mul(_move(X, t, math.sin(t), math.cos(t), _prismatic(P, k)), P, 1 + n + k)
    X = _mul(X, P, 2 * n + 1)
    ex, ey, ez = X[3], X[7], X[11]
    for k in range(n):
        zx, zy, zz = J[3, k], J[4, k], J[5, k]
        if _prismatic(P, k):  # d p_m / d q_m = z (q in metres too)
            J[0, k], J[1, k], J[2, k] = zx, zy, zz
            J[3, k], J[4, k], J[5, k] = 0.0, 0.0, 0.0
        else:
            rx, ry, rz = ex - J[0, k], ey - J[1, k], ez - J[2, k]
            J[0, k] = (zy * rz - zz * ry) * s
            J[1, k] = (zz * rx - zx * rz) * s
            J[2, k] = (zx * ry - zy * rx) * s
    return X


@njit(cache=True)
def _residual(X, Tt, s, w, e):
    """e = (position error in metres, world frame; rotation error vector in the target frame).

    Returns the weighted cost 0.5 * sum(w e^2).
    """
    e[0] = (Tt[0, 3] - X[3]) * s
    e[1] = (Tt[1, 3] - X[7]) * s
    e[2] = (Tt[2, 3] - X[11]) * s
    if w[3] == 0.0 and w[4] == 0.0 and w[5] == 0.0:
        e[3] = e[4] = e[5] = 0.0
    else:
        # M = R^T R_t; log(M) = R_t^T log(R_t R^T): the rotation still to do, in the target frame
        m00 = X[0] * Tt[0, 0] + X[4] * Tt[1, 0] + X[8] * Tt[2, 0]
        m01 = X[0] * Tt[0, 1] + X[4] * Tt[1, 1] + X[8] * Tt[2, 1]
        m02 = X[0] * Tt[0, 2] + X[4] * Tt[1, 2] + X[8] * Tt[2, 2]
        m10 = X[1] * Tt[0, 0] + X[5] * Tt[1, 0] + X[9] * Tt[2, 0]
        m11 = X[1] * Tt[0, 1] + X[5] * Tt[1, 1] + X[9] * Tt[2, 1]
        m12 = X[1] * Tt[0, 2] + X[5] * Tt[1, 2] + X[9] * Tt[2, 2]
        m20 = X[2] * Tt[0, 0] + X[6] * Tt[1, 0] + X[10] * Tt[2, 0]
        m21 = X[2] * Tt[0, 1] + X[6] * Tt[1, 1] + X[10] * Tt[2, 1]
        m22 = X[2] * Tt[0, 2] + X[6] * Tt[1, 2] + X[10] * Tt[2, 2]
        vx, vy, vz = m21 - m12, m02 - m20, m10 - m01
        sn = 0.5 * math.sqrt(vx * vx + vy * vy + vz * vz)
        c = 0.5 * (m00 + m11 + m22 - 1.0)
        th = math.atan2(sn, c)
        if sn > 1e-6 or c > 0.0:
            f = 0.5 + th * th / 12.0 if th < 1e-6 else th / (2.0 * sn)
            e[3], e[4], e[5] = f * vx, f * vy, f * vz
        else:  # angle near pi: the axis from the symmetric part, a a^T = (M + M^T) / 2 - c I) / (1 - c)
            k = 1.0 / (1.0 - c)
            d0, d1, d2 = (m00 - c) * k, (m11 - c) * k, (m22 - c) * k
            s01, s02, s12 = 0.5 * (m01 + m10) * k, 0.5 * (m02 + m20) * k, 0.5 * (m12 + m21) * k
            if d0 >= d1 and d0 >= d2:
                r = math.sqrt(max(d0, 1e-300))
                ax, ay, az = r, s01 / r, s02 / r
            elif d1 >= d2:
                r = math.sqrt(max(d1, 1e-300))
                ax, ay, az = s01 / r, r, s12 / r
            else:
                r = math.sqrt(max(d2, 1e-300))
                ax, ay, az = s02 / r, s12 / r, r
            if ax * vx + ay * vy + az * vz < 0.0:
                ax, ay, az = -ax, -ay, -az
            e[3], e[4], e[5] = th * ax, th * ay, th * az
    E = 0.0
    for i in range(6):
        E += w[i] * e[i] * e[i]
    return 0.5 * E


@njit(cache=True)
def _errors(e, w):
    p = 0.0
    r = 0.0
    for i in range(3):
        if w[i] > 0.0:
            p += e[i] * e[i]
        if w[3 + i] > 0.0:
            r += e[3 + i] * e[3 + i]
    return math.sqrt(p), math.sqrt(r)


@njit(cache=True)
def _rotate_rows(J, Tt, n):
    """Angular rows of J from the world frame to the target frame (R_t^T omega)."""
    for k in range(n):
        a, b, c = J[3, k], J[4, k], J[5, k]
        J[3, k] = Tt[0, 0] * a + Tt[1, 0] * b + Tt[2, 0] * c
        J[4, k] = Tt[0, 1] * a + Tt[1, 1] * b + Tt[2, 1] * c
        J[5, k] = Tt[0, 2] * a + Tt[1, 2] * b + Tt[2, 2] * c


@njit(cache=True, inline="always")
def _project1(v, limits, j, prismatic):
    """Joint ``j``'s value ``v`` inside its limits: a revolute joint by whole turns where that suffices, then
    clamping (the rule of the NumPy back end's ``_project``; CCD's kernel uses it too)."""
    lo, up = limits[0, j], limits[1, j]
    if not prismatic:
        two_pi = 2.0 * math.pi
        if v > up:
            v2 = v - two_pi * math.ceil((v - up) / two_pi)
            if v2 >= lo:
                v = v2
        elif v < lo:
            v2 = v + two_pi * math.ceil((lo - v) / two_pi)
            if v2 <= up:
                v = v2
    if v > up:
        v = up
    elif v < lo:
        v = lo
    return v


@njit(cache=True)
def _project(q, limits, P):
    """Bring revolute joints into their limits by whole turns where possible, then clamp."""
    for j in range(q.shape[0]):
        q[j] = _project1(q[j], limits, j, _prismatic(P, j))


@njit(cache=True)
def _next_random(state):
    """splitmix64: a uniform float in [0, 1); state is a one-element uint64 array."""
    state[0] += np.uint64(0x9E3779B97F4A7C15)
    z = state[0]
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    z = z ^ (z >> np.uint64(31))
    return float(z >> np.uint64(11)) * (1.0 / 9007199254740992.0)


@njit(cache=True)
def _solve_spd(A, g, n, dq):
    """Solve A dq = g in place by Cholesky (A symmetric positive definite, n x n). False if not SPD."""
    for j in range(n):
        d = A[j, j]
        for k in range(j):
            d -= A[j, k] * A[j, k]
        if d <= 0.0:
            return False
        d = math.sqrt(d)
        A[j, j] = d
        for i in range(j + 1, n):
            v = A[i, j]
            for k in range(j):
                v -= A[i, k] * A[j, k]
            A[i, j] = v / d
    for i in range(n):
        v = g[i]
        for k in range(i):
            v -= A[i, k] * dq[k]
        dq[i] = v / A[i, i]
    for i in range(n - 1, -1, -1):
        v = dq[i]
        for k in range(i + 1, n):
            v -= A[k, i] * dq[k]
        dq[i] = v / A[i, i]
    return True


@njit(cache=True)
def _leaves_range(v, lo, up, prismatic):
    """True where joint value v lies outside [lo, up] even after whole turns (revolute)."""
    if lo <= v <= up:
        return False
    if prismatic:
        return True
    two_pi = 2.0 * math.pi
    if v > up:
        return v - two_pi * math.ceil((v - up) / two_pi) < lo
    return v + two_pi * math.ceil((lo - v) / two_pi) > up


@njit(cache=True)
def _active_set_step(J, e, lam, q, P, limits, params, work):
    """One damped least-squares step with joint limits as an active set; ``qn = q + step``.

    ``work`` holds scratch arrays and the result: ``(A (n, n), g (n,), dq (n,), r6 (6,),
    fixed (n,) bool, dfix (n,), qn (n,))``.

    Solve :math:`(J_f^T W J_f + \\lambda I) \\Delta q_f = J_f^T W (e - J_c \\Delta q_c)` over the
    free joints f, where the joints c that the step would push out of their limits move
    exactly to the limit (``dfix``); repeat until no free joint leaves its range.
    Returns False if the normal matrix is not positive definite.
    """
    A, g, dq, r6, fixed, dfix, qn = work
    w = params[W:W + 6]
    s = params[SCALE]
    lower, upper = limits[0], limits[1]
    n = q.shape[0]
    for j in range(n):
        fixed[j] = False
        dfix[j] = 0.0
    for _ in range(n + 1):
        for r in range(6):
            v = e[r]
            for j in range(n):
                if fixed[j]:
                    v -= J[r, j] * dfix[j]
            r6[r] = w[r] * v
        for a in range(n):
            if fixed[a]:
                for b in range(n):
                    A[a, b] = 0.0
                    A[b, a] = 0.0
                A[a, a] = 1.0
                g[a] = 0.0
                continue
            v = 0.0
            for r in range(6):
                v += J[r, a] * r6[r]
            g[a] = v
            for b in range(a + 1):
                if fixed[b]:
                    continue
                v = 0.0
                for r in range(6):
                    v += J[r, a] * w[r] * J[r, b]
                A[a, b] = v
                A[b, a] = v
            A[a, a] += lam
        if not _solve_spd(A, g, n, dq):
            return False
        moved = False
        for j in range(n):
            if fixed[j]:
                continue
            pj = _prismatic(P, j)
            v = q[j] + (dq[j] / s if pj else dq[j])
            if _leaves_range(v, lower[j], upper[j], pj):
                fixed[j] = True
                bound = upper[j] if v > upper[j] else lower[j]
                dfix[j] = (bound - q[j]) * s if pj else bound - q[j]
                moved = True
        if not moved:
            break
    for j in range(n):
        d = dfix[j] if fixed[j] else dq[j]
        qn[j] = q[j] + (d / s if _prismatic(P, j) else d)
    return True


@njit(cache=True)
def _evaluate(P, params, Tt, q, J, e):
    """The task Jacobian of ``q`` into ``J`` (6, n) (rotation rows in the target frame when rotation counts)
    and the residual into ``e`` (6,); returns the weighted cost."""
    s, w = params[SCALE], params[W:W + 6]
    X = _pose_jacobian(P, q, s, J)
    if w[3] != 0.0 or w[4] != 0.0 or w[5] != 0.0:
        _rotate_rows(J, Tt, q.shape[0])
    return _residual(X, Tt, s, w, e)


@njit(cache=True)
def _random_start(q, limits, seed, attempt, state):
    """``q`` uniform in the random-start box of ``limits``, from the stream of (``seed``, ``attempt``)."""
    state[0] = np.uint64(seed) * np.uint64(1000003) + np.uint64(attempt)
    for j in range(q.shape[0]):
        q[j] = limits[2, j] + (limits[3, j] - limits[2, j]) * _next_random(state)


@njit(cache=True)
def _lm_one(P, limits, params, Tt, seed, q, trace, info):
    """Solve the target ``Tt`` (4, 4) from ``q`` (n,) (modified in place to the best configuration found).

    ``P``, ``limits``, ``params``: see the top of this module. ``info`` (4,): iterations, status,
    attempts used, best cost; ``trace[i]`` = error norm after iteration ``i`` (length 0: none).
    """
    n = q.shape[0]
    w = params[W:W + 6]
    tol_p, tol_r = params[TOL_P], params[TOL_R]
    max_iterations, first_attempt = int(params[MAX_ITERATIONS]), int(params[FIRST_ATTEMPT])
    attempts = int(params[ATTEMPTS])
    J = np.empty((6, n))
    Jn = np.empty((6, n))
    e = np.empty(6)
    en = np.empty(6)
    qn = np.empty(n)
    work = (np.empty((n, n)), np.empty(n), np.empty(n), np.empty(6), np.zeros(n, np.bool_), np.zeros(n), qn)
    best_q = q.copy()
    best_E = np.inf
    state = np.empty(1, np.uint64)
    total = 0
    used = 0
    status = EXHAUSTED
    for attempt in range(first_attempt, first_attempt + attempts):
        used += 1
        if attempt > 0:
            _random_start(q, limits, seed, attempt, state)
        _project(q, limits, P)
        E = _evaluate(P, params, Tt, q, J, e)
        mu = 1.0
        stale = 0
        attempt_best = E
        for it in range(max_iterations + 1):
            if E < best_E:
                best_E = E
                _copy(q, best_q)
            ep, er = _errors(e, w)
            if ep <= tol_p and er <= tol_r:
                status = CONVERGED
                break
            if it == max_iterations:
                break
            lam = mu * E + 1e-12
            if not _active_set_step(J, e, lam, q, P, limits, params, work):
                mu *= 10.0
                continue
            _project(qn, limits, P)
            En = _evaluate(P, params, Tt, qn, Jn, en)
            total += 1
            if trace.shape[0] > 0 and total <= trace.shape[0]:
                a1, a2 = _errors(en if En < E else e, w)
                trace[total - 1] = math.sqrt(a1 * a1 + a2 * a2)
            if En < E:
                _copy(qn, q)
                for r in range(6):
                    _copy(Jn[r], J[r])
                _copy(en, e)
                E = En
                mu = max(mu * 0.5, 1e-6)
            else:
                mu *= 4.0
                if mu > 1e10:
                    break
            # stall: no 1 % improvement of this attempt's best cost in 8 iterations
            if E < 0.99 * attempt_best:
                attempt_best = E
                stale = 0
            else:
                stale += 1
                if stale >= 8:
                    break
        if status == CONVERGED:
            break
    if status != CONVERGED:
        _copy(best_q, q)
    info[0] = total
    info[1] = status
    info[2] = used
    info[3] = min(best_E, E) if status == CONVERGED else best_E


def lm_batch(P, limits, params, targets, seeds, q, trace, info):
    """Solve every target ``targets[i]`` (B, 4, 4) from ``q[i]`` in parallel; q, trace, info written in place.

    ``P``, ``limits``, ``params``: the packed chain, limits and options (see the top of this
    module); ``seeds`` (B,) uint64; ``trace`` (B, k); ``info`` (B, 4). One thread (the same
    results) while the multi-threaded kernel is still being compiled by the warm-up process.
    """
    (_lm_parallel if _jit_loader.parallel_ok() else lm_serial)(P, limits, params, targets, seeds, q, trace, info)


@njit(cache=True)
def lm_serial(P, limits, params, targets, seeds, q, trace, info):
    """As :func:`lm_batch` without threads (small batches, single calls)."""
    for i in prange(targets.shape[0]):
        _lm_one(P, limits, params, targets[i], seeds[i], q[i], trace[i], info[i])


_lm_parallel = parallel_twin(lm_serial)


@njit(cache=True)
def lm_single(P, limits, params, targets, seed, q, info):
    """:func:`lm_serial` for one target (restart seed ``seed``, no trace) that first checks it:
    False (nothing solved) if the target ``targets[0]`` or the start ``q[0]`` holds a NaN or
    an infinity."""
    for i in range(4):
        for j in range(4):
            if not math.isfinite(targets[0, i, j]):
                return False
    for j in range(q.shape[1]):
        if not math.isfinite(q[0, j]):
            return False
    _lm_one(P, limits, params, targets[0], np.uint64(seed), q[0], np.empty(0), info[0])
    return True


def parallel_twins():
    """``(one-thread kernel, multi-threaded kernel)`` pairs taking the same arguments (for the warm-up)."""
    return [(lm_serial, _lm_parallel)]


# this module's cached kernels inline the pose helpers of kinematics/_jit.py: compiled anew when it changes
_jit_loader.forget_stale_cache(globals(), ("kinematics/_jit.py",))
