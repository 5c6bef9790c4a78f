"""One compiled call for one IK target: every closed-form branch solved, wrapped, verified and sorted.

:func:`armkit.ik.analytic.solve_all` does these steps for a batch, each as its own NumPy or Numba
call; for one target those calls and their small arrays cost far more than the maths. The
kernels here run the same steps for one target in one call, with the same compiled pieces, so
the answers are the same to the last bit:

1. the family's kernel (:mod:`._jit`, ``lo, hi = 0, 1``) on the target and ``q0 + theta``;
2. every branch wrapped by 2 pi into the limits nearest ``q0`` (:func:`._jit._wrap_one`) with its
   distance to ``q0``;
3. forward kinematics of every branch (:func:`armkit.kinematics._jit._fk_serial`, the batch
   kernel ``verify`` uses) and its check (:func:`armkit.ik._jit_verify._check`);
4. the reason code of each branch and the sort: successful branches first, each group by distance
   (the stable insertion sort of :func:`._jit.sort_branches`).

A pose target is checked for rigidity in the same pass (the measures of
:func:`armkit.spatial.check_transform`). What one call cannot do the same way ends it early with
a status, and the caller answers by the batched path: a target that is not finite or not rigid
(:data:`BAD_TARGET`: the batched path raises the error), a branch the Gauss-Newton touch-up of
``solve_all`` would polish, or a note to give (a singular wrist, a target on the first axis, a
stretched or folded elbow) (:data:`FALLBACK`). Imported lazily, only when the Numba back end is
in use (:mod:`armkit._jit_loader`).

Every kernel returns ``(status, limit failures, other failures, q, errors, flags, ints, reach)``: ``q``
``(m, n)`` sorted; ``errors`` ``(2, m)``: position and rotation error; ``flags`` ``(2, m)``: success
and within limits; ``ints`` ``(4, m)``: reason code (0 converged, 1 unreachable, 2 joint limits),
label index, the branch's index before sorting, and the bits of the joints outside their limits (bit ``j``:
joint ``j``, the test of ``_failure_messages``); ``reach`` ``(m, 4)``, per branch before sorting: clipped
(out of reach, 1.0/0.0), then the numbers of the family's out-of-reach sentence (its ``reach_why``): the
target beside the first axis (1.0/0.0), its distance from that axis, its distance from the shoulder (zeros
for :func:`post`). ``opts`` is the float64 vector of :data:`OPTS`.
"""

from __future__ import annotations

import math

import numpy as np

from ... import _jit_loader

_jit_loader.install_cache_fallback()  # before the first cache=True: read-only installs cache elsewhere

from numba import njit  # noqa: E402

from ...kinematics._jit import _fk_serial  # noqa: E402
from .._jit_verify import _check  # noqa: E402
from ._jit import _planar2_run, _planar3_run, _puma_run, _ur_run, _widened, _wrap_one, _ypp_run  # noqa: E402
from ._layout import JOINT_LOWER, JOINT_THETA, JOINT_UPPER  # noqa: E402

DONE, FALLBACK, BAD_TARGET = 0, 1, 2
"""Kernel status: answered; answer by the batched path (same result); target not finite or not rigid."""
OPTS = ("tol_p", "tol_r", "enforce", "window_p", "window_r", "above_p", "above_r", "sign", "check")
"""The entries of ``opts``: FK tolerances, enforce limits (1.0/0.0), the polish window and threshold of
``solve_all`` (position entries already times the reach), the planar-2r joint-2 sign, check rigidity (1.0/0.0)."""
RIGID_TOL = 1e-6   # check_transform's default


def options(tol, enforce, window, above, scale, sign, check):
    """The ``opts`` vector (:data:`OPTS`), products formed as ``solve_all`` forms them."""
    return np.array([tol[0], tol[1], 1.0 if enforce else 0.0, window * scale, window, above * scale, above,
                     float(sign), 1.0 if check else 0.0])


@njit(cache=True)
def _target(t, check):
    """The target as a (4, 4) array (a point goes into column 3) and whether it is usable: finite, and a
    rigid transform when ``check`` (the test of :func:`armkit.spatial.check_transform`). With an unusable
    target or start (not finite, beyond 1e6) the kernels return :data:`BAD_TARGET`: the batched path
    raises the error or wraps the start."""
    T = np.zeros((4, 4))
    good = True
    if t.shape[0] == 16:
        for k in range(16):
            v = t[k]
            if not math.isfinite(v):
                good = False
            T[k // 4, k % 4] = v
        if check and good:
            a, b, c = T[0, 0], T[0, 1], T[0, 2]
            d, e, f = T[1, 0], T[1, 1], T[1, 2]
            g, h, i = T[2, 0], T[2, 1], T[2, 2]
            o = max(abs(a * a + d * d + g * g - 1.0), abs(b * b + e * e + h * h - 1.0),
                    abs(c * c + f * f + i * i - 1.0), abs(a * b + d * e + g * h), abs(a * c + d * f + g * i),
                    abs(b * c + e * f + h * i))
            det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
            last = T[3, 0] == 0.0 and T[3, 1] == 0.0 and T[3, 2] == 0.0 and T[3, 3] == 1.0
            good = o <= RIGID_TOL and abs(det - 1.0) <= RIGID_TOL and last
    else:
        for k in range(3):
            v = t[k]
            if not math.isfinite(v):
                good = False
            T[k, 3] = v
        T[3, 3] = 1.0
    return T, good


@njit(cache=True, inline="always")
def _usable_start(q0):
    """``q0`` as the batched path uses it unchanged: finite and within 1e6 (``api._normalise_q0`` wraps larger)."""
    for j in range(q0.shape[0]):
        if not abs(q0[j]) <= 1e6:
            return False
    return True


@njit(cache=True)
def _early(status, m, n):
    """The result of a kernel that stops before verifying (the caller answers by the batched path)."""
    return (status, 0, 0, np.empty((m, n)), np.empty((2, m)), np.zeros((2, m), np.bool_),
            np.zeros((4, m), np.int64), np.zeros((m, 4)))


@njit(cache=True)
def _finish(rawq, unreach, missing, lab, joints, F, q0, T, pose, opts, reach):
    """Steps 2-4 of the module docstring for raw DH angles ``rawq`` (m, n) of one target ``T`` (4, 4)."""
    m, n = rawq.shape
    theta = joints[JOINT_THETA]
    lower, upper = joints[JOINT_LOWER], joints[JOINT_UPPER]
    lo, hi, revolute = _widened(joints)
    q = np.empty((m, n))
    dist = np.empty(m)
    for b in range(m):    # solve_all: jit.wrap_dist
        s = 0.0
        for j in range(n):
            v = _wrap_one(rawq[b, j] - theta[j], q0[j], lo[j], hi[j], revolute[j])
            q[b, j] = v
            if revolute[j]:
                s += (v - q0[j]) ** 2
        dist[b] = math.sqrt(s)
    Tq = np.empty((m, 4, 4))
    if _fk_serial(F, q, Tq):   # a value that is not finite: the batched path says what
        return _early(FALLBACK, m, n)
    tol_p, tol_r, enforce = opts[0], opts[1], opts[2] != 0.0
    win_p, win_r, above_p, above_r = opts[3], opts[4], opts[5], opts[6]
    dp, dr = np.empty(m), np.empty(m)
    ok, within = np.empty(m, np.bool_), np.empty(m, np.bool_)
    code = np.empty(m, np.int64)
    n_limits = n_other = 0
    for b in range(m):    # solve_all: verify, the polish test, the reason codes
        e_p, e_r, w = _check(Tq[b], T, pose, q[b], lower, upper, 1e-12)
        if e_p <= win_p and e_r <= win_r and (e_p > above_p or e_r > above_r):
            return _early(FALLBACK, m, n)   # _polish would touch this branch up
        fk_ok = e_p <= tol_p and e_r <= tol_r and not missing[b]
        good = fk_ok and (w or not enforce)
        dp[b], dr[b], ok[b], within[b] = e_p, e_r, good, w
        if good:
            code[b] = 0
        elif fk_ok and not w:
            code[b] = 2
            n_limits += 1
        else:
            code[b] = 1
            n_other += 1
    key = np.empty(m)
    idx = np.empty(m, np.int64)
    for b in range(m):    # solve_all: jit.sort_branches (a stable insertion sort)
        k = (0.0 if ok[b] else 1e9) + dist[b]
        j = b - 1
        while j >= 0 and key[j] > k:
            key[j + 1] = key[j]
            idx[j + 1] = idx[j]
            j -= 1
        key[j + 1] = k
        idx[j + 1] = b
    qs, ev, fl, iv = np.empty((m, n)), np.empty((2, m)), np.empty((2, m), np.bool_), np.empty((4, m), np.int64)
    for b in range(m):
        s = idx[b]
        bits = 0
        for j in range(n):
            qs[b, j] = q[s, j]
            if q[s, j] < lo[j] or q[s, j] > hi[j]:
                bits |= 1 << j
        ev[0, b], ev[1, b], fl[0, b], fl[1, b] = dp[s], dr[s], ok[s], within[s]
        iv[0, b], iv[1, b], iv[2, b], iv[3, b] = code[s], lab[s], s, bits
    return DONE, n_limits, n_other, qs, ev, fl, iv, reach


@njit(cache=True)
def usable(t, q0, check):
    """Whether target ``t`` (flat: 16 or 3 values) and start ``q0`` are usable (see :func:`_target`)."""
    return _target(t, check)[1] and _usable_start(q0)


@njit(cache=True)
def post(rawq, unreach, missing, joints, F, q0, t, opts):
    """Steps 2-4 for raw DH angles ``rawq`` (m, n) of one target ``t`` (flat: 16 or 3 values) that a family's
    Python ``solve`` gave (the geometric family); label indices are the raw branch indices."""
    m, n = rawq.shape
    T, good = _target(t, opts[8] != 0.0)
    if not good or not _usable_start(q0):
        return _early(BAD_TARGET, m, n)
    return _finish(rawq, unreach, missing, np.arange(m), joints, F, q0, T, t.shape[0] == 16, opts,
                   _reach(m, 1, unreach, False, 0.0, np.zeros(m)))


@njit(cache=True, inline="always")
def _reach(m, per, unreach, lat, rho, r):
    """The ``reach`` rows of ``m`` branches: ``unreach[b]``, ``lat`` and ``rho`` of the target, ``r[b // per]``."""
    out = np.empty((m, 4))
    for b in range(m):
        out[b, 0] = 1.0 if unreach[b] else 0.0
        out[b, 1] = 1.0 if lat else 0.0
        out[b, 2] = rho
        out[b, 3] = r[b // per]
    return out


@njit(cache=True, inline="always")
def _q0phi(q0, joints):
    n = q0.shape[0]
    out = np.empty((1, n))
    for j in range(n):
        out[0, j] = q0[j] + joints[JOINT_THETA, j]
    return out


@njit(cache=True)
def planar2(t, g, joints, F, q0, opts):
    """Planar-2r (``_layout.P2_*``): ``t`` flat pose (16) or point (3)."""
    n = q0.shape[0]
    T, good = _target(t, opts[8] != 0.0)
    if not good or not _usable_start(q0):
        return _early(BAD_TARGET, 2, n)
    p = np.empty((1, 3))
    for k in range(3):
        p[0, k] = T[k, 3]
    q, up, c, r = np.empty((1, 2, 2)), np.empty((1, 2), np.int64), np.empty(1), np.empty(1)
    unreach, edge = np.empty((1, 2), np.bool_), np.empty(1, np.bool_)
    _planar2_run(p, g, q, up, c, r, unreach, edge, 0, 1)
    if edge[0]:
        return _early(FALLBACK, 2, n)
    if opts[7] < 0:
        for b in range(2):
            q[0, b, 1] *= -1.0
    return _finish(q[0], unreach[0], np.zeros(2, np.bool_), up[0], joints, F, q0, T, t.shape[0] == 16, opts,
                   _reach(2, 2, unreach[0], False, 0.0, r))


@njit(cache=True)
def planar3(t, g, joints, F, q0, opts):
    """Planar-3r (``_layout.P3_*``): ``t`` flat pose (16)."""
    n = q0.shape[0]
    T, good = _target(t, opts[8] != 0.0)
    if not good or not _usable_start(q0):
        return _early(BAD_TARGET, 2, n)
    Tb = np.empty((1, 4, 4))
    Tb[0] = T
    q, up, c, r = np.empty((1, 2, 3)), np.empty((1, 2), np.int64), np.empty(1), np.empty(1)
    unreach, edge = np.empty((1, 2), np.bool_), np.empty(1, np.bool_)
    _planar3_run(Tb, g, q, up, c, r, unreach, edge, 0, 1)
    if edge[0]:
        return _early(FALLBACK, 2, n)
    return _finish(q[0], unreach[0], np.zeros(2, np.bool_), up[0], joints, F, q0, T, True, opts,
                   _reach(2, 2, unreach[0], False, 0.0, r))


@njit(cache=True)
def yaw_pitch_pitch(t, g, joints, F, q0, opts):
    """Yaw-pitch-pitch (``_layout.POS_*``): ``t`` flat pose (16) or point (3)."""
    n = q0.shape[0]
    T, good = _target(t, opts[8] != 0.0)
    if not good or not _usable_start(q0):
        return _early(BAD_TARGET, 4, n)
    p = np.empty((1, 3))
    for k in range(3):
        p[0, k] = T[k, 3]
    q0phi = _q0phi(q0, joints)
    phi, up, unreach = np.empty((1, 4, 3)), np.empty((1, 4), np.bool_), np.empty((1, 4), np.bool_)
    c, r, rho = np.empty((1, 2)), np.empty((1, 2)), np.empty(1)
    lat, on_axis, edge, lab = np.empty(1, np.bool_), np.empty(1, np.bool_), np.empty((1, 2), np.bool_), \
        np.empty((1, 4), np.int64)
    _ypp_run(p, g, q0phi[:, 0].copy(), phi, up, unreach, c, r, rho, lat, on_axis, edge, lab, 0, 1)
    if on_axis[0] or edge[0, 0] or edge[0, 1]:
        return _early(FALLBACK, 4, n)
    return _finish(phi[0], unreach[0], np.zeros(4, np.bool_), lab[0], joints, F, q0, T, t.shape[0] == 16, opts,
                   _reach(4, 2, unreach[0], lat[0], rho[0], r[0]))


@njit(cache=True)
def spherical_wrist(t, g, joints, F, q0, opts):
    """Spherical-wrist (``_layout.SW_*``): ``t`` flat pose (16)."""
    n = q0.shape[0]
    T, good = _target(t, opts[8] != 0.0)
    if not good or not _usable_start(q0):
        return _early(BAD_TARGET, 8, n)
    Tb = np.empty((1, 4, 4))
    Tb[0] = T
    q0phi = _q0phi(q0, joints)
    out, lab, singular = np.empty((1, 4, 2, 6)), np.empty((1, 4, 2), np.int64), np.empty((1, 4), np.bool_)
    phi, up, unreach4 = np.empty((1, 4, 3)), np.empty((1, 4), np.bool_), np.empty((1, 4), np.bool_)
    c, r, rho = np.empty((1, 2)), np.empty((1, 2)), np.empty(1)
    lat, on_axis, edge, lab4 = np.empty(1, np.bool_), np.empty(1, np.bool_), np.empty((1, 2), np.bool_), \
        np.empty((1, 4), np.int64)
    _puma_run(Tb, g, q0phi, out, lab, singular, phi, up, unreach4, c, r, rho, lat, on_axis, edge, lab4, 0, 1)
    if on_axis[0] or edge[0, 0] or edge[0, 1]:
        return _early(FALLBACK, 8, n)
    unreach = np.empty(8, np.bool_)
    for b in range(4):
        if singular[0, b]:
            return _early(FALLBACK, 8, n)
        unreach[2 * b] = unreach[2 * b + 1] = unreach4[0, b]
    return _finish(out.reshape(8, 6), unreach, np.zeros(8, np.bool_), lab.reshape(8), joints, F, q0, T, True, opts,
                   _reach(8, 4, unreach, lat[0], rho[0], r[0]))


@njit(cache=True)
def ur(t, g, joints, F, q0, opts):
    """UR (``_layout.UR_*``): ``t`` flat pose (16)."""
    n = q0.shape[0]
    T, good = _target(t, opts[8] != 0.0)
    if not good or not _usable_start(q0):
        return _early(BAD_TARGET, 8, n)
    Tb = np.empty((1, 4, 4))
    Tb[0] = T
    q0phi = _q0phi(q0, joints)
    out, up, unreach = np.empty((1, 2, 2, 2, 6)), np.empty((1, 2, 2, 2), np.bool_), np.empty((1, 2, 2, 2), np.bool_)
    lab = np.empty((1, 2, 2, 2), np.int64)
    lat, rho, r = np.empty(1, np.bool_), np.empty(1), np.empty((1, 2, 2))
    on_axis, singular = np.empty(1, np.bool_), np.empty((1, 2, 2), np.bool_)
    _ur_run(Tb, g, q0phi, out, up, lab, unreach, lat, rho, r, on_axis, singular, 0, 1)
    if on_axis[0] or singular[0, 0, 0] or singular[0, 0, 1] or singular[0, 1, 0] or singular[0, 1, 1]:
        return _early(FALLBACK, 8, n)
    return _finish(out.reshape(8, 6), unreach.reshape(8), np.zeros(8, np.bool_), lab.reshape(8), joints, F, q0, T,
                   True, opts, _reach(8, 2, unreach.reshape(8), lat[0], rho[0], r[0].reshape(4)))


KERNELS = {"planar-2r": planar2, "planar-3r": planar3, "yaw-pitch-pitch": yaw_pitch_pitch,
           "spherical-wrist": spherical_wrist, "ur": ur}
"""Family name -> its one-call kernel ``(t, g, joints, F, q0, opts)``; other families: :func:`post` after their
``solve``. A family here also has ``reach_why(lateral_out, rho, r, target)``: its out-of-reach sentence (the
one its ``Raw.why`` gives) from the kernel's ``reach`` numbers, so that a target with a clipped branch is not
solved a second time."""

# the kernels inline helpers of these files: compiled anew when they change
_jit_loader.forget_stale_cache(globals(), ("ik/analytic/_jit.py", "ik/analytic/_layout.py", "kinematics/_jit.py",
                                           "ik/_jit_verify.py"))
