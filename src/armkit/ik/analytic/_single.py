"""One compiled call for one IK target: every closed-form branch solved, wrapped, verified and sorted.

:func:`armkit.ik.analytic.solve_all` does these steps for a batch, each as its own NumPy or Numba
call; for one target those calls and their small arrays cost far more than the maths. The
kernels here run the same steps for one target in one call, with the same compiled pieces, so
the answers are the same to the last bit:

1. the family's kernel (:mod:`._jit`, ``lo, hi = 0, 1``) on the target and ``q0 + theta``;
2. every branch wrapped by 2 pi into the limits nearest ``q0`` (:func:`._jit._wrap_one`) with its
   distance to ``q0``;
3. forward kinematics of every branch (the steps of :func:`armkit.kinematics._jit._fk_serial`, the batch
   kernel ``verify`` uses, the branches side by side as its batches are: :func:`armkit.kinematics._jit._fk_lanes`;
   for :func:`armkit.ik`, branch by branch nearest first, :func:`_fk_row`: its steps for one row; the same bits)
   and its check (the steps of :func:`armkit.ik._jit_verify._check`);
4. the reason code of each branch and the sort: successful branches first, each group by distance
   (the stable insertion sort of :func:`._jit.sort_branches`).

A pose target is checked for rigidity in the same pass (the measures of
:func:`armkit.spatial.check_transform`). What one call cannot do the same way ends it early with
a status, and the caller answers by the batched path: a target that is not finite or not rigid
(:data:`BAD_TARGET`: the batched path raises the error), a file's ideal-arm branch that the
Gauss-Newton touch-up (:func:`_touch_up`, run in the call) leaves failing within the window of
``_retarget``, or a note to give (a singular wrist, a target on the first axis, a stretched or folded
elbow) (:data:`FALLBACK`). Imported lazily, only when the Numba back end is in use
(:mod:`armkit._jit_loader`).

The calling convention keeps Numba's own cost per call low (each argument is unboxed, each
returned array boxed; the buffers are made by the caller): every kernel takes ``(t, q0, ctx, fb, ib, bb, wk)``:

* ``t``: the target, flat (16 values of a pose, or 3 of a point), and ``q0`` ``(n,)``;
* ``ctx``: everything of the robot and the call options in one read-only float64 vector
  (:func:`context`: the header :data:`CTX`, then the family's geometry, the joint table, the packed
  chain ``F`` of :func:`armkit.kinematics.packed` and the options :data:`OPTS`), built once per robot
  and options;
* three output buffers the kernel fills, laid out by :func:`layout` for ``m`` branches of ``n``
  joints (after those, ``ib`` and ``bb`` hold the kernel's int and flag work space): ``fb`` float64
  (``q`` ``(m, n)`` sorted, position and rotation errors, then for the
  messages a private copy of both errors and the ``reach`` rows ``(m, 4)`` in sorted order: clipped
  (out of reach, 1.0/0.0), then the numbers of the family's out-of-reach sentence, its ``reach_why``:
  the target beside the first axis (1.0/0.0), its distance from that axis, its distance from the
  shoulder; zeros for :func:`post`), then the pose target as the kernel read it (16 values: the messages
  of failed branches read it there, so that the caller need not copy its array), ``ib`` int64 (reason
  code: 0 converged, 1 unreachable, 2 joint limits; label index; zeros, the ``iterations`` field; the
  branch's index before sorting; the bits of the joints outside their limits, bit ``j``: joint ``j``, the
  test of ``_failure_messages``) and ``bb`` bool (success, within limits);
* ``wk``: the float work vector (:func:`work` gives its size and the work ends of ``ib`` and ``bb``),
  which the record keeps and every call uses: a kernel reads nothing there it did not write in the
  same call, and holds the GIL from start to end (none is compiled with ``nogil``), so two threads never
  use it at once. A kernel makes no array of its own: it is compiled without Numba's reference counts
  (``_nrt=False``; each array made and freed cost ~40 ns, and each view and call counted its arrays up and
  down with an atomic instruction: together ~0.6 µs of a UR5's 3.6 µs call, 2026-12-06);

and returns one int: the status (:data:`DONE`, :data:`FALLBACK`, :data:`BAD_TARGET`) plus
:data:`LIMIT_FAILURES` when a branch failed by the limits only and :data:`OTHER_FAILURES` when
one failed otherwise (for :func:`armkit.ik`, whose nearest successful branch is all it keeps:
:data:`NEAREST` and that branch's label index instead, so that the caller reads nothing else of ``ib``).

A batch of targets runs the same kernels through one compiled driver (:func:`_rows`, threaded in its twin),
which takes a kernel as the address of its compiled code (:func:`kernel_address`) and gives each target a row of
three ``(B, size)`` buffers, copying each row's ``q`` and ``success`` into the result's arrays as it goes: one
driver for every family, compiled once (:func:`armkit.ik.analytic._batch_from_rows` makes the other fields).
"""

from __future__ import annotations

import math

import numpy as np

from ... import _jit_loader

_jit_loader.install_cache_fallback()  # before the first cache=True: read-only installs cache elsewhere

from numba import njit, prange  # noqa: E402
from numba.core import cgutils  # noqa: E402
from numba.core import types as nbtypes  # noqa: E402
from numba.extending import intrinsic  # noqa: E402

from ..._jit_twins import parallel_twin  # noqa: E402

from ..._jit_shaped import shaped  # noqa: E402

from ...kinematics._jit import (LANES, PRISMATIC, ROW, _fk_lanes, _jacobian_cols, _load, _move, _mul,  # noqa: E402
                               _sincos, _store, _store2, sincos_block)
from .._jit_verify import _angle_of, _check, _within  # noqa: E402
from ._jit import (TWO_PI, _planar2_run, _planar3_run, _puma_run, _ur_run, _wrap_one, _ypp_run,  # noqa: E402
                   stable_order)
from ._layout import (JOINT_LOWER, JOINT_PRISMATIC, JOINT_ROWS, JOINT_THETA, JOINT_UPPER,  # noqa: E402
                      LABEL_SHIFT, NEAREST)

DONE, FALLBACK, BAD_TARGET = 0, 1, 2
"""Kernel status: answered; answer by the batched path (same result); target not finite or not rigid."""
RECHECK = 3
"""The status of a gated :func:`_finish` (a branch above the gate), inside a kernel only: never returned."""
_NO_GATE = math.inf
"""The gate of :func:`_finish` that lets every branch through (the family kernels')."""
LIMIT_FAILURES, OTHER_FAILURES = 4, 8
"""Bits of a kernel's return value besides the status: some branch failed by the limits alone; some
branch failed otherwise (unreachable)."""
OPTS = ("tol_p", "tol_r", "enforce", "window_p", "window_r", "above_p", "above_r", "sign", "check", "nearest",
        "scale", "steps", "done", "retarget")
"""The options at the end of ``ctx``: FK tolerances, enforce limits (1.0/0.0), the polish window and
threshold of ``solve_all`` (position entries already times the reach), the planar-2r joint-2 sign,
check rigidity (1.0/0.0), whether only the nearest branch is wanted (1.0/0.0: :func:`armkit.ik`; see
:func:`_nearest_first`), the touch-up's reach, most steps and converged step (:func:`_touch_up`), and where the
family solves the ideal arm of a file, the window of ``_retarget`` (0.0 else: a branch the touch-up leaves failing
within it is the batched path's)."""
CTX = ("n", "geometry", "joints", "F", "opts")
"""The header of ``ctx``: the number of joints, then where the geometry, the joint table, the packed
chain and the options start."""
RIGID_TOL = 1e-6   # check_transform's default
_YES, _NO = np.True_, np.False_
_FIRST, _ONE = np.int64(0), np.int64(1)   # the family kernels' row range (0, 1), typed int64 as in their batched use
"""True and False that Numba types as ``bool``, not as the literals ``True``/``False``: the kernels pass them
(and counts as ``np.int64``) to :func:`_finish`, so that one compiled signature of it serves every family
(a literal argument compiles a copy of :func:`_finish` per value)."""


def options(tol, enforce, window, above, scale, sign, check, nearest=False, steps=2, done=0.0, retarget=0.0):
    """The options (:data:`OPTS`), products formed as ``solve_all`` forms them."""
    return np.array([tol[0], tol[1], 1.0 if enforce else 0.0, window * scale, window, above * scale, above,
                     float(sign), 1.0 if check else 0.0, 1.0 if nearest else 0.0, scale, float(steps), done,
                     retarget])


def context(geometry, joints, F, opts):
    """The read-only ``ctx`` vector of the kernels (header :data:`CTX`; ``geometry`` None: none)."""
    g = np.zeros(0) if geometry is None else np.asarray(geometry, dtype=float).ravel()
    parts = [g, np.asarray(joints, dtype=float).ravel(), np.asarray(F, dtype=float).ravel(), np.asarray(opts, float)]
    head = len(CTX)
    starts, at = [], head
    for p in parts:
        starts.append(at)
        at += p.size
    ctx = np.concatenate([np.array([float(np.shape(joints)[1])] + [float(s) for s in starts])] + parts)
    ctx.setflags(write=False)
    return ctx


def layout(m, n):
    """Offsets in the output buffers for ``m`` branches of ``n`` joints: ``(fb size, ib size, bb size)`` and,
    in ``fb``, where the errors, the private errors, the reach rows and the target start (see the module
    docstring)."""
    mn = m * n
    return {"fb": mn + 8 * m + 16, "ib": 5 * m, "bb": 2 * m, "dp": mn, "dr": mn + m, "hdp": mn + 2 * m,
            "hdr": mn + 3 * m, "reach": mn + 4 * m, "target": mn + 8 * m}


@njit(cache=True, inline="always")
def _parts(ctx):
    """``(n, geometry, joints (JOINT_ROWS, n), F (n + 1, ROW), opts)``: views of ``ctx``."""
    n = int(ctx[0])
    a, b, c, d = int(ctx[1]), int(ctx[2]), int(ctx[3]), int(ctx[4])
    return n, ctx[a:b], shaped(ctx[b:c], (JOINT_ROWS, n)), shaped(ctx[c:d], (n + 1, ROW)), ctx[d:]


@njit(cache=True)
def _target(t, check, T):
    """Write the target into ``T`` (4, 4) (a point goes into column 3 of the identity) and return whether it is
    usable: finite, and a rigid transform when ``check`` (the test of :func:`armkit.spatial.check_transform`).
    With an unusable target or start (not finite, beyond 1e6) the kernels return :data:`BAD_TARGET`: the batched
    path raises the error or wraps the start."""
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
        for k in range(16):
            T[k // 4, k % 4] = 0.0
        for k in range(3):
            v = t[k]
            if not math.isfinite(v):
                good = False
            T[k, 3] = v
        T[3, 3] = 1.0
    return good


@njit(cache=True, inline="always")
def _usable_start(q0):
    """``q0`` as the batched path uses it unchanged: finite and within 1e6 (``api._normalise_q0`` wraps larger)."""
    for j in range(q0.shape[0]):
        if not abs(q0[j]) <= 1e6:
            return False
    return True


@njit(cache=True, inline="always")
def _fk_row(F, q, s, out):
    """FK of row ``s`` of ``q`` (m, n) into ``out`` (4, 4): the operations of
    :func:`armkit.kinematics._jit._fk_serial` for one configuration, in the same order (the same bits), without
    its block of sines and cosines. The caller has checked that the row is finite."""
    _store2(_end_pose(F, q, s), out)


@njit(cache=True, inline="always")
def _end_pose(F, q, s):
    """The pose (12 scalars) of :func:`_fk_row`."""
    X = _load(F, 0)
    for k in range(q.shape[1]):
        t = q[s, k]
        sk, ck = _sincos(t)
        X = _mul(_move(X, t, sk, ck, F[k + 1, PRISMATIC] != 0.0), F, k + 1)
    return X


@njit(cache=True, inline="always")
def _fk_rows_shared(F, q, s, c, out, P):
    """:func:`armkit.kinematics._jit._fk_rows` of every row of ``q`` (m, n) into ``out`` (m, 4, 4), each row taken
    up after the joints it shares with the row before (a closed form's branches come in pairs that differ only in
    the wrist: the Puma's 8 branches share 12 of their 48 joint steps): the same operations on the same values, the
    same bits. ``s``, ``c``: the sines and cosines of ``q``'s values (flat); ``P`` ((n + 1) * 12): the pose after
    each joint of the row before."""
    m, n = q.shape
    for i in range(m):
        k0 = 0
        if i > 0:
            while k0 < n and q[i, k0] == q[i - 1, k0]:
                k0 += 1
        if k0 == 0:
            X = _load(F, 0)
        else:
            a = 12 * k0
            X = (P[a], P[a + 1], P[a + 2], P[a + 3], P[a + 4], P[a + 5], P[a + 6], P[a + 7], P[a + 8], P[a + 9],
                 P[a + 10], P[a + 11])
        o = i * n
        for k in range(k0, n):
            X = _mul(_move(X, q[i, k], s[o + k], c[o + k], F[k + 1, PRISMATIC] != 0.0), F, k + 1)
            a = 12 * (k + 1)
            for j in range(12):
                P[a + j] = X[j]
        _store(X, out, i)


@njit(cache=True, inline="always")
def _errors_lanes(X, T, pose, m, dp, sr, cr):
    """The position errors ``dp`` of the ``m`` poses ``X`` of :func:`armkit.kinematics._jit._fk_lanes` against
    ``T`` (4, 4), and where ``pose`` the sine ``sr`` and cosine ``cr`` of each rotation error's angle: the
    operations of :func:`armkit.ik._jit_verify._check`, side by side as in ``_fk_lanes``
    (:func:`armkit.ik._jit_verify._angle_of` takes the angle from them)."""
    L = LANES
    t03, t13, t23 = T[0, 3], T[1, 3], T[2, 3]
    for i in range(m):
        ex = X[3 * L + i] - t03
        ey = X[7 * L + i] - t13
        ez = X[11 * L + i] - t23
        dp[i] = math.sqrt(ex * ex + ey * ey + ez * ez)
    if not pose:
        return
    t00, t01, t02 = T[0, 0], T[0, 1], T[0, 2]
    t10, t11, t12 = T[1, 0], T[1, 1], T[1, 2]
    t20, t21, t22 = T[2, 0], T[2, 1], T[2, 2]
    for i in range(m):
        r00, r01, r02 = X[i], X[L + i], X[2 * L + i]
        r10, r11, r12 = X[4 * L + i], X[5 * L + i], X[6 * L + i]
        r20, r21, r22 = X[8 * L + i], X[9 * L + i], X[10 * L + i]
        e00 = r00 * t00 + r10 * t10 + r20 * t20
        e01 = r00 * t01 + r10 * t11 + r20 * t21
        e02 = r00 * t02 + r10 * t12 + r20 * t22
        e10 = r01 * t00 + r11 * t10 + r21 * t20
        e11 = r01 * t01 + r11 * t11 + r21 * t21
        e12 = r01 * t02 + r11 * t12 + r21 * t22
        e20 = r02 * t00 + r12 * t10 + r22 * t20
        e21 = r02 * t01 + r12 * t11 + r22 * t21
        e22 = r02 * t02 + r12 * t12 + r22 * t22
        sr[i] = 0.5 * math.sqrt((e21 - e12) ** 2 + (e02 - e20) ** 2 + (e10 - e01) ** 2)
        cr[i] = 0.5 * (e00 + e11 + e22 - 1.0)


@njit(cache=True, inline="always")
def _begin(t, q0, opts, wk):
    """What every kernel does first: the target written into the first piece of its work vector, as (4, 4) ``T``
    (flat: ``T4``), by :func:`_target`. Returns ``(T4, T, the offset after it, usable)``: usable when the target
    and the start ``q0`` are (else the kernel returns :data:`BAD_TARGET`)."""
    T4 = wk[:16]
    T = shaped(T4, (4, 4))
    return T4, T, 16, _target(t, opts[8] != 0.0, T) and _usable_start(q0)


@njit(cache=True, inline="always")
def _cut(w, at, size):
    """``w[at:at + size]`` and the offset after it: the next piece of a work vector."""
    return w[at:at + size], at + size


@njit(cache=True, inline="always")
def _repeats_from(rawq):
    """The number of rows of ``rawq`` (m, n) before the last ones that repeat row 0 to the bit (the sign of a zero
    too; a NaN repeats nothing): ``m`` where the last row differs from row 0, at least 1."""
    m, n = rawq.shape
    real = m
    while real > 1:
        for j in range(n):
            a, b = rawq[real - 1, j], rawq[0, j]
            if not (a == b and math.copysign(1.0, a) == math.copysign(1.0, b)):
                return real
        real -= 1
    return real


@njit(cache=True, inline="always")
def _copy_branch(q, dist, a, b):
    """Row ``a`` of ``q`` and its distance ``dist[a]`` into row ``b``."""
    for j in range(q.shape[1]):
        q[b, j] = q[a, j]
    dist[b] = dist[a]


@njit(cache=True, _nrt=False)
def _finish(rawq, unreach, missing, lab, ctx, q0, T, pose, lat, rho, r, per, gate_p, gate_r, fb, ib, bb, wf, wi, wb):
    """Steps 2-4 of the module docstring for raw DH angles ``rawq`` (m, n) of one target ``T`` (4, 4), into
    the buffers; ``lat, rho, r[b // per]``: the numbers of branch ``b``'s out-of-reach sentence. ``wf``, ``wi``,
    ``wb``: its work space (float, int, bool; at least :func:`finish_work` long), the caller's.

    ``gate_p``, ``gate_r``: a branch whose FK error is above them (position, rotation angle) ends the call with
    :data:`RECHECK` before any branch is written (:data:`_NO_GATE`: none). A gated call checks every branch, also
    for :func:`armkit.ik` (the all-branch check, not :func:`_nearest_first`: the same answer, see
    :func:`_may_succeed`). The geometric kernel's shortcut (:mod:`armkit.ik.geometric.one_call`) gates its
    unchecked candidates so."""
    m, n = rawq.shape
    _, _, joints, F, opts = _parts(ctx)
    fb = shaped(fb, (fb.size,))   # made as rows (the caller's q is its first m rows); written by the flat layout
    tgt = m * n + 8 * m           # the target, for the messages (layout's "target")
    for k in range(16):
        fb[tgt + k] = T[k // 4, k % 4]
    # lo, hi (n), dist, dp, dr, key (m), the wrapped branches q (m, n) and their sines and cosines, one pose Tq and
    # every branch's Tm (m, 4, 4): pieces of the caller's work vector (each array made and freed costs ~40 ns, and
    # a function that makes none is compiled without reference counts; see the module docstring)
    lo, at = _cut(wf, 0, n)
    hi, at = _cut(wf, at, n)
    dist, at = _cut(wf, at, m)
    dp, at = _cut(wf, at, m)
    dr, at = _cut(wf, at, m)
    k_of, at = _cut(wf, at, m)
    qflat, at = _cut(wf, at, m * n)
    sn, at = _cut(wf, at, m * n)
    cs, at = _cut(wf, at, m * n)
    T4, at = _cut(wf, at, 16 * (m + 1))
    P, at = _cut(wf, at, 12 * (n + 1))
    wt, at = _cut(wf, at, 10 * n + 72)
    qt, at = _cut(wf, at, m * n)          # the branches side by side (_fk_lanes)
    X, at = _cut(wf, at, 12 * LANES)
    sr, at = _cut(wf, at, m)
    cr, at = _cut(wf, at, m)
    q = shaped(qflat, (m, n))
    T4 = shaped(T4, (m + 1, 4, 4))
    Tq, Tm = T4[0], T4[1:]
    for j in range(n):
        lo[j] = joints[JOINT_LOWER, j] - 1e-12
        hi[j] = joints[JOINT_UPPER, j] + 1e-12
    # the rows after ``real`` repeat row 0 to the bit (the padding of a target with fewer branches than m): their
    # wrap, FK, check and touch-up are row 0's, copied, not computed again (the same bits)
    real = _repeats_from(rawq)
    finite = True
    for b in range(real):    # solve_all: jit.wrap_dist
        s = 0.0
        for j in range(n):
            revolute = joints[JOINT_PRISMATIC, j] == 0.0
            v = _wrap_one(rawq[b, j] - joints[JOINT_THETA, j], q0[j], lo[j], hi[j], revolute)
            q[b, j] = v
            if not math.isfinite(v):
                finite = False
            if revolute:
                s += (v - q0[j]) ** 2
        dist[b] = math.sqrt(s)
    for b in range(real, m):
        _copy_branch(q, dist, 0, b)
    if not finite:   # a value that is not finite: the batched path says what
        return FALLBACK
    code, idx = wi[:m], wi[m:2 * m]   # the reason codes, the order
    ok, within = wb[:m], wb[m:2 * m]
    every = True
    if opts[9] != 0.0 and gate_p == _NO_GATE and _may_succeed(q, joints, opts):   # armkit.ik: the nearest branch
        # that succeeds, if any (a gated call checks every branch)
        s = _nearest_first(q, dist, unreach, missing, lab, F, joints, opts, T, pose, lat, rho, r, per, lo, hi,
                           Tq, idx, dp, dr, within, fb, ib, bb)
        if s >= 0:
            return s
        # -1: none succeeds, every branch was checked on the way, its errors are in dp, dr, within; -2: a branch to
        # touch up first (solve_all's answer): every branch, below
        every = s == -2
    if every:   # every branch (also for armkit.ik where none is within the limits: none can succeed, all are checked)
        # every branch's FK (the sines and cosines of all of them in one vector loop, as _fk_serial takes them):
        # the branches side by side, their errors too (_fk_lanes), or beyond LANES each taken up after the joints
        # it shares with the branch before (_fk_rows_shared); the same bits
        lanes = real <= LANES
        if lanes:
            for k in range(n):
                for b in range(real):
                    qt[k * real + b] = q[b, k]
            sincos_block(qt[:real * n], sn, cs)
            _fk_lanes(F, qt, sn, cs, real, n, X)
            _errors_lanes(X, T, pose, real, dp, sr, cr)
        else:
            sincos_block(qflat[:real * n], sn, cs)
            _fk_rows_shared(F, q[:real], sn, cs, Tm, P)
        for b in range(m):    # solve_all: verify and the polish test
            if b >= real:   # row 0 again: its answer (after its touch-up)
                _copy_branch(q, dist, 0, b)
                dp[b], dr[b], within[b] = dp[0], dr[0], within[0]
                continue
            if lanes:
                e_p, e_r = dp[b], (_angle_of(sr[b], cr[b]) if pose else 0.0)
                w_b = _within(q[b], joints[JOINT_LOWER], joints[JOINT_UPPER], 1e-12)
            else:
                e_p, e_r, w_b = _check(Tm[b], T, pose, q[b], joints[JOINT_LOWER], joints[JOINT_UPPER], 1e-12)
            if not (e_p <= gate_p and e_r <= gate_r):
                return RECHECK
            if _polishable(e_p, e_r, opts):   # solve_all's touch-up (a gated call: the caller's own path)
                if gate_p != _NO_GATE:
                    return FALLBACK
                taken, e_p, e_r, w_b = _touch_branch(F, q, b, T, pose, joints, opts, q0, dist, Tq, e_p, e_r, w_b, wt)
                if not taken:
                    return FALLBACK
            dp[b], dr[b], within[b] = e_p, e_r, w_b
    flags = DONE
    for b in range(m):    # solve_all: the reason codes
        e_p, e_r, w_b = dp[b], dr[b], within[b]
        fk_ok = e_p <= opts[0] and e_r <= opts[1] and not missing[b]
        good = fk_ok and (w_b or opts[2] == 0.0)
        ok[b] = good
        if good:
            code[b] = 0
        elif fk_ok and not w_b:
            code[b] = 2
            flags |= LIMIT_FAILURES
        else:
            code[b] = 1
            flags |= OTHER_FAILURES
    for b in range(m):    # solve_all: jit.sort_branches (a stable sort)
        k_of[b] = (0.0 if ok[b] else 1e9) + dist[b]
    stable_order(k_of, idx)
    for b in range(m):
        s = idx[b]
        _put(b, s, q, dp[s], dr[s], ok[s], within[s], code[s], unreach, lab, lat, rho, r, per, lo, hi, fb, ib, bb)
    return flags


def finish_work(m, n):
    """The work space :func:`_finish` takes for ``m`` branches of ``n`` joints: ``(floats, ints, flags)``."""
    return 2 * n + 6 * m + 4 * m * n + 16 * (m + 1) + 12 * (n + 1) + 10 * n + 72 + 12 * LANES, 2 * m, 2 * m


@njit(cache=True, inline="always")
def _may_succeed(q, joints, opts):
    """Whether some branch of ``q`` (m, n) may succeed: limits not enforced, or one within them (the test of
    ``_check``). Where none is, :func:`_nearest_first` would check every branch one by one; the all-branch check
    (one vector loop of sines and cosines, shared joints) does the same work faster, with the same bits (the Puma's
    ``ik`` of a target with no branch in its limits: 3.8 -> 3.3 µs)."""
    if opts[2] == 0.0:
        return True
    for b in range(q.shape[0]):
        if _within(q[b], joints[JOINT_LOWER], joints[JOINT_UPPER], 1e-12):
            return True
    return False


@njit(cache=True, inline="always")
def _polishable(e_p, e_r, opts):
    """Whether ``solve_all``'s Gauss-Newton touch-up would polish a branch with these FK errors (in its window,
    above its threshold): then the batched path answers."""
    return e_p <= opts[3] and e_r <= opts[4] and (e_p > opts[5] or e_r > opts[6])


PIVOT = 1e-7
"""A pivot of :func:`_touch_up`'s elimination below this share of the largest Jacobian entry: the Jacobian is too near
singular for it, and the step is ``pinv``'s (rcond 1e-10) by a Jacobi SVD instead (:func:`_pinv_step`)."""


@njit(cache=True, inline="always")
def _pinv_step(J, A, V, e, g, d):
    """``e`` := ``np.linalg.pinv(J[0, :d, :d], rcond=1e-10) @ e``, by a one-sided Jacobi SVD (Hestenes: plane
    rotations of the columns of ``A = J V`` until they are orthogonal; ``J = U S V^T`` with ``A = U S``), for a
    Jacobian too near singular for :func:`_touch_up`'s elimination. ``A``, ``V`` (d, d) and ``g`` (d,) are work
    space."""
    for r in range(d):
        for c in range(d):
            A[r, c] = J[0, r, c]
            V[r, c] = 1.0 if r == c else 0.0
    for _ in range(60):
        turned = False
        for i in range(d - 1):
            for j in range(i + 1, d):
                a = b = c = 0.0
                for k in range(d):
                    a += A[k, i] * A[k, i]
                    b += A[k, j] * A[k, j]
                    c += A[k, i] * A[k, j]
                if not abs(c) > 1e-16 * math.sqrt(a * b):
                    continue
                turned = True
                zeta = (b - a) / (2.0 * c)
                t = math.copysign(1.0, zeta) / (abs(zeta) + math.sqrt(1.0 + zeta * zeta))
                cs = 1.0 / math.sqrt(1.0 + t * t)
                sn = cs * t
                for k in range(d):
                    x, y = A[k, i], A[k, j]
                    A[k, i], A[k, j] = cs * x - sn * y, sn * x + cs * y
                    x, y = V[k, i], V[k, j]
                    V[k, i], V[k, j] = cs * x - sn * y, sn * x + cs * y
        if not turned:
            break
    top = 0.0
    for i in range(d):   # the singular values: the columns' norms
        x = 0.0
        for k in range(d):
            x += A[k, i] * A[k, i]
        g[i] = math.sqrt(x)
        top = max(top, g[i])
    for i in range(d):   # (U^T e)_i / s_i, over s_i^2 since A's column i is U_i s_i; 0 below rcond
        x = 0.0
        if g[i] > 1e-10 * top:
            for k in range(d):
                x += A[k, i] * e[k]
            x /= g[i] * g[i]
        g[i] = x
    for r in range(d):   # V (U^T e / s)
        x = 0.0
        for i in range(d):
            x += V[r, i] * g[i]
        e[r] = x


@njit(cache=True, inline="always")
def _touch_up(F, q, T, pose, steps, done, w):
    """The Gauss-Newton touch-up of ``solve_all`` (:func:`armkit.ik.analytic._polish`) of one branch ``q`` (n,), in
    place, compiled: at most ``steps`` steps on the true chain ``F`` towards ``T`` (4, 4; only column 3 read unless
    ``pose``), each solving ``J dq = e`` (the world-frame Jacobian, the position error and, for a pose, the rotation
    vector of ``R_target R^T``) by elimination with partial pivoting (where a pivot is below :data:`PIVOT`, the
    least-squares step of ``pinv``, :func:`_pinv_step`), ending after a step no larger than ``done``.
    A step that shrank by 1e3 or more from the one before (the first: to 1e-4 or less) keeps the Jacobian's factors
    for the next (a chord step: the FK alone, ~0.2 against ~0.4 µs a branch; the steps still shrink ~1e-5, 1e-10,
    1e-15 on the ideal arm of a file with rounded twists); else the next step takes a new Jacobian.
    Square systems only (six joints for a pose, three for a point): returns False where it does not take the branch
    (another shape, a value not finite), ``q`` then partly moved (the caller keeps a
    copy). ``w``: work space of at least ``9 n + 72`` floats."""
    n = q.shape[0]
    d = 6 if pose else 3
    if n != d:
        return False
    J = shaped(w[:6 * n], (1, 6, n))
    A = shaped(w[6 * n:6 * n + d * d], (d, d))
    e = w[6 * n + d * d:6 * n + d * d + d]
    pivots = w[6 * n + d * d + d:6 * n + d * d + 2 * d]   # the row each column's elimination took (as floats)
    V = shaped(w[6 * n + d * d + 2 * d:6 * n + 2 * d * d + 2 * d], (d, d))   # (the SVD's right factor, its norms)
    g = w[6 * n + 2 * d * d + 2 * d:6 * n + 2 * d * d + 3 * d]
    fresh = True
    last = 0.1   # (a first step of 1e-4 or less keeps its factors: from a start far off, the next takes new ones)
    for _ in range(steps):
        if fresh:
            X = _jacobian_cols(F, q, 0, A, -1, False, J, 0)   # (A: an unread sine table, o = -1)
        else:   # a chord step: the FK alone
            X = _end_pose(F, shaped(q, (1, n)), 0)
        e[0], e[1], e[2] = T[0, 3] - X[3], T[1, 3] - X[7], T[2, 3] - X[11]
        if pose:   # the rotation vector of M = R_target R^T (_small_log): (M - M^T) / 2 = sin(t) [u]x
            m21 = T[2, 0] * X[4] + T[2, 1] * X[5] + T[2, 2] * X[6]
            m12 = T[1, 0] * X[8] + T[1, 1] * X[9] + T[1, 2] * X[10]
            m02 = T[0, 0] * X[8] + T[0, 1] * X[9] + T[0, 2] * X[10]
            m20 = T[2, 0] * X[0] + T[2, 1] * X[1] + T[2, 2] * X[2]
            m10 = T[1, 0] * X[0] + T[1, 1] * X[1] + T[1, 2] * X[2]
            m01 = T[0, 0] * X[4] + T[0, 1] * X[5] + T[0, 2] * X[6]
            vx, vy, vz = 0.5 * (m21 - m12), 0.5 * (m02 - m20), 0.5 * (m10 - m01)
            sn = math.sqrt(vx * vx + vy * vy + vz * vz)
            ratio = math.asin(min(sn, 1.0)) / sn if sn > 0.0 else 1.0
            e[3], e[4], e[5] = vx * ratio, vy * ratio, vz * ratio
        singular = False
        if fresh:   # A := its LU factors (the multipliers below the diagonal), rows swapped as pivots says
            big = 0.0
            for r in range(d):
                for c in range(d):
                    A[r, c] = J[0, r, c]
                    big = max(big, abs(A[r, c]))
            for c in range(d):
                p = c
                for r in range(c + 1, d):
                    if abs(A[r, c]) > abs(A[p, c]):
                        p = r
                if not abs(A[p, c]) > PIVOT * big:
                    singular = True
                    break
                pivots[c] = p
                if p != c:
                    for k in range(d):
                        A[c, k], A[p, k] = A[p, k], A[c, k]
                for r in range(c + 1, d):
                    f = A[r, c] / A[c, c]
                    A[r, c] = f
                    for k in range(c + 1, d):
                        A[r, k] -= f * A[c, k]
        if singular:   # the least-squares step of pinv (rcond 1e-10), by a Jacobi SVD; its factors are not kept
            _pinv_step(J, A, V, e, g, d)
        else:   # the step, in e: the swaps, then L, then U
            for c in range(d):
                p = int(pivots[c])
                if p != c:
                    e[c], e[p] = e[p], e[c]
            for r in range(1, d):
                x = e[r]
                for k in range(r):
                    x -= A[r, k] * e[k]
                e[r] = x
            for c in range(d - 1, -1, -1):
                x = e[c]
                for k in range(c + 1, d):
                    x -= A[c, k] * e[k]
                e[c] = x / A[c, c]
        largest = 0.0
        for j in range(n):
            q[j] += e[j]
            if not math.isfinite(q[j]):
                return False
            largest = max(largest, abs(e[j]))
        if largest <= done:   # converged: a further step would move q by rounding only
            break
        fresh = singular or not largest <= 1e-3 * last
        last = largest
    return True


@njit(cache=True, inline="always")
def _distance(v, q0, joints):
    """The distance of ``v`` (n,) from ``q0`` over the revolute joints, summed as :func:`_finish` sums it."""
    s = 0.0
    for j in range(v.shape[0]):
        if joints[JOINT_PRISMATIC, j] == 0.0:
            s += (v[j] - q0[j]) ** 2
    return math.sqrt(s)


@njit(cache=True, inline="always")
def _touch_branch(F, q, b, T, pose, joints, opts, q0, dist, Tq, e_p, e_r, w_b, wt):
    """:func:`_touch_up` of branch ``b`` of ``q`` (m, n), then what ``solve_all`` does with it: its FK check, and
    the touched-up values kept (with their distance from ``q0`` in ``dist[b]``) only where they lower the error
    (position / reach + rotation: :func:`armkit.ik.analytic._common.keep_better`). Returns ``(taken, errors and
    within-limits flag of the branch kept)``; not taken (:func:`_touch_up` refused it, or on the ideal arm of a file
    the branch still fails within the window of ``_retarget``: the batched path takes it, by NumPy's steps and
    ``_retarget``): ``q`` unchanged. ``Tq`` (4, 4) and ``wt`` (:func:`finish_work`'s share) are work space."""
    n = q.shape[1]
    qb = wt[:n]
    for j in range(n):
        qb[j] = q[b, j]
    if not _touch_up(F, qb, T, pose, int(opts[11]), opts[12], wt[n:]):
        return False, e_p, e_r, w_b
    _fk_row(F, shaped(qb, (1, n)), 0, Tq)
    p2, r2, w2 = _check(Tq, T, pose, qb, joints[JOINT_LOWER], joints[JOINT_UPPER], 1e-12)
    scale = opts[10]
    better = p2 / scale + r2 < e_p / scale + e_r
    f_p, f_r = (p2, r2) if better else (e_p, e_r)
    if not (f_p <= opts[0] and f_r <= opts[1]) and f_p <= opts[13] * scale and f_r <= opts[13]:
        return False, e_p, e_r, w_b
    if not better:
        return True, e_p, e_r, w_b
    for j in range(n):
        q[b, j] = qb[j]
    dist[b] = _distance(qb, q0, joints)
    return True, p2, r2, w2


@njit(cache=True)
def touch_up_rows(F, q, T, pose, steps, done):
    """:func:`_touch_up` of every row of ``q`` (k, n) towards ``T`` (k, 4, 4), in place (the batched path's
    touch-up with the Numba back end, so that it and the one-call path give the same bits). Returns the rows it
    did not take (k,) bool, left unchanged."""
    k, n = q.shape
    refused = np.zeros(k, np.bool_)
    w = np.empty(9 * n + 72)
    keep = np.empty(n)
    for i in range(k):
        for j in range(n):
            keep[j] = q[i, j]
        if not _touch_up(F, q[i], T[i], pose, steps, done, w):
            refused[i] = True
            for j in range(n):
                q[i, j] = keep[j]
    return refused


@njit(cache=True)
def row_distances(q, q0, joints, out):
    """``out[i]``: the distance of row ``q[i]`` from ``q0[i]`` over the revolute joints, summed as
    :func:`_finish` sums it (the batched path's distances of touched-up branches, the same bits)."""
    for i in range(q.shape[0]):
        out[i] = _distance(q[i], q0[i], joints)


@njit(cache=True, inline="always")
def _put(b, s, q, e_p, e_r, good, w, code, unreach, lab, lat, rho, r, per, lo, hi, fb, ib, bb):
    """Branch ``s`` of ``q (m, n)`` (its FK errors, success, within limits, reason code) written as sorted branch
    ``b`` of the buffers (the layout of the module docstring), with the numbers of its out-of-reach sentence."""
    m, n = q.shape
    mn = m * n
    bits = 0
    for j in range(n):
        v = q[s, j]
        fb[b * n + j] = v
        if v < lo[j] or v > hi[j]:
            bits |= 1 << j
    fb[mn + b] = fb[mn + 2 * m + b] = e_p
    fb[mn + m + b] = fb[mn + 3 * m + b] = e_r
    at = mn + 4 * m + 4 * b
    fb[at] = 1.0 if unreach[s] else 0.0
    fb[at + 1] = 1.0 if lat else 0.0
    fb[at + 2] = rho
    fb[at + 3] = r[s // per]
    ib[b], ib[m + b], ib[2 * m + b], ib[3 * m + b], ib[4 * m + b] = code, lab[s], 0, s, bits
    bb[b], bb[m + b] = good, w


@njit(cache=True, _nrt=False)
def _nearest_first(q, dist, unreach, missing, lab, F, joints, opts, T, pose, lat, rho, r, per, lo, hi, Tq, order,
                   dp, dr, within, fb, ib, bb):
    """:func:`_finish` for :func:`armkit.ik`, which keeps only the first branch of the sorted ones: the branches
    are verified in order of distance from ``q0`` (stable, as the sort), and the first that succeeds is that
    first branch, written as :func:`_finish` writes it; the branches beyond it are never checked. Returns the
    status (:data:`DONE` with :data:`NEAREST` and the label index), -1 when no branch succeeds: then every branch
    has been checked, its errors left in ``dp``, ``dr`` and ``within`` (m,) for :func:`_finish` (the failures'
    sentences need each), or -2 where the touch-up of ``solve_all`` would move a nearer branch that may succeed
    (or, none succeeding, any branch): :func:`_finish` then checks and touches up every branch, as ``solve_all``.
    A nearer branch to touch up that the limits rule out anyway is passed over: ``solve_nearest`` never looks at
    it either. ``Tq`` (4, 4) and ``order`` (m,) are work space."""
    m = q.shape[0]
    stable_order(dist, order)   # by distance, as the sort (a successful branch's key is its distance)
    touch = False
    for i in range(m):
        s = order[i]
        _fk_row(F, q, s, Tq)
        e_p, e_r, w = _check(Tq, T, pose, q[s], joints[JOINT_LOWER], joints[JOINT_UPPER], 1e-12)
        if _polishable(e_p, e_r, opts):   # solve_all's touch-up would move this branch
            if w or opts[2] == 0.0:
                return -2
            touch = True
        elif e_p <= opts[0] and e_r <= opts[1] and not missing[s] and (w or opts[2] == 0.0):
            _put(0, s, q, e_p, e_r, True, w, 0, unreach, lab, lat, rho, r, per, lo, hi, fb, ib, bb)
            return DONE | NEAREST | (lab[s] << LABEL_SHIFT)
        dp[s], dr[s], within[s] = e_p, e_r, w
    return -2 if touch else -1


@njit(cache=True)
def usable(t, q0, check):
    """Whether target ``t`` (flat: 16 or 3 values) and start ``q0`` are usable (see :func:`_target`)."""
    return _target(t, check, np.empty((4, 4))) and _usable_start(q0)


@njit(cache=True, _nrt=False)
def post(rawq, unreach, missing, t, q0, ctx, fb, ib, bb, wk):
    """Steps 2-4 for raw DH angles ``rawq`` (m, n) of one target ``t`` (flat: 16 or 3 values) that a family's
    Python ``solve`` gave (the geometric family); label indices are the raw branch indices. Work space: ``wk``
    and the tails of ``ib`` and ``bb`` (:data:`WORK` ``["post"]``)."""
    m, n = rawq.shape
    opts = _parts(ctx)[4]
    T4, T, at, usable = _begin(t, q0, opts, wk)
    if not usable:
        return BAD_TARGET
    r, at = _cut(wk, at, 1)
    r[0] = 0.0
    lab, i_at = _cut(ib, 5 * m, m)
    for b in range(m):
        lab[b] = b
    return _finish(rawq, unreach, missing, lab, ctx, q0, T, t.shape[0] == 16, _NO, 0.0, r, m + 1,
                   _NO_GATE, _NO_GATE, fb, ib, bb, wk[at:], ib[i_at:], bb[2 * m:])


@njit(cache=True, inline="always")
def _q0phi(q0, joints, out):
    """``out`` (1, n) := ``q0 + theta``, the family kernels' reference joints."""
    for j in range(q0.shape[0]):
        out[0, j] = q0[j] + joints[JOINT_THETA, j]


@njit(cache=True, _nrt=False)
def planar2(t, q0, ctx, fb, ib, bb, wk):
    """Planar-2r (``_layout.P2_*``): ``t`` flat pose (16) or point (3)."""
    _, g, _, _, opts = _parts(ctx)
    T4, T, at, usable = _begin(t, q0, opts, wk)
    if not usable:
        return BAD_TARGET
    p, at = _cut(wk, at, 3)
    q, at = _cut(wk, at, 4)
    c, at = _cut(wk, at, 1)
    r, at = _cut(wk, at, 1)
    up, i_at = _cut(ib, 5 * 2, 2)
    unreach, b_at = _cut(bb, 2 * 2, 2)
    edge, b_at = _cut(bb, b_at, 1)
    missing, b_at = _cut(bb, b_at, 2)
    p2 = shaped(p, (1, 3))
    for k in range(3):
        p2[0, k] = T[k, 3]
    q3 = shaped(q, (1, 2, 2))
    _planar2_run(p2, g, q3, shaped(up, (1, 2)), c, r, shaped(unreach, (1, 2)), edge, _FIRST, _ONE)
    if edge[0]:
        return FALLBACK
    if opts[7] < 0:
        for b in range(2):
            q3[0, b, 1] *= -1.0
    missing[0] = missing[1] = False
    return _finish(q3[0], unreach, missing, up, ctx, q0, T, t.shape[0] == 16, _NO, 0.0, r, np.int64(2),
                   _NO_GATE, _NO_GATE, fb, ib, bb, wk[at:], ib[i_at:], bb[b_at:])


@njit(cache=True, _nrt=False)
def planar3(t, q0, ctx, fb, ib, bb, wk):
    """Planar-3r (``_layout.P3_*``): ``t`` flat pose (16)."""
    _, g, _, _, opts = _parts(ctx)
    T4, T, at, usable = _begin(t, q0, opts, wk)
    if not usable:
        return BAD_TARGET
    q, at = _cut(wk, at, 6)
    c, at = _cut(wk, at, 1)
    r, at = _cut(wk, at, 1)
    up, i_at = _cut(ib, 5 * 2, 2)
    unreach, b_at = _cut(bb, 2 * 2, 2)
    edge, b_at = _cut(bb, b_at, 1)
    missing, b_at = _cut(bb, b_at, 2)
    q3 = shaped(q, (1, 2, 3))
    _planar3_run(shaped(T4, (1, 4, 4)), g, q3, shaped(up, (1, 2)), c, r, shaped(unreach, (1, 2)), edge, _FIRST,
                 _ONE)
    if edge[0]:
        return FALLBACK
    missing[0] = missing[1] = False
    return _finish(q3[0], unreach, missing, up, ctx, q0, T, _YES, _NO, 0.0, r, np.int64(2), _NO_GATE, _NO_GATE,
                   fb, ib, bb, wk[at:], ib[i_at:], bb[b_at:])


@njit(cache=True, _nrt=False)
def yaw_pitch_pitch(t, q0, ctx, fb, ib, bb, wk):
    """Yaw-pitch-pitch (``_layout.POS_*``, ``YPP_F3``): ``t`` flat pose (16) or point (3)."""
    _, g, joints, _, opts = _parts(ctx)
    T4, T, at, usable = _begin(t, q0, opts, wk)
    if not usable:
        return BAD_TARGET
    p, at = _cut(wk, at, 3)
    yaw0, at = _cut(wk, at, 1)
    phi, at = _cut(wk, at, 12)
    c, at = _cut(wk, at, 2)
    r, at = _cut(wk, at, 2)
    rho, at = _cut(wk, at, 1)
    lab, i_at = _cut(ib, 5 * 4, 4)
    up, b_at = _cut(bb, 2 * 4, 4)
    unreach, b_at = _cut(bb, b_at, 4)
    lat, b_at = _cut(bb, b_at, 1)
    on_axis, b_at = _cut(bb, b_at, 1)
    edge, b_at = _cut(bb, b_at, 2)
    missing, b_at = _cut(bb, b_at, 4)
    p2 = shaped(p, (1, 3))
    for k in range(3):
        p2[0, k] = T[k, 3]
    yaw0[0] = q0[0] + joints[JOINT_THETA, 0]
    _ypp_run(p2, g, yaw0, shaped(phi, (1, 4, 3)), shaped(up, (1, 4)), shaped(unreach, (1, 4)), shaped(c, (1, 2)),
             shaped(r, (1, 2)), rho, lat, on_axis, shaped(edge, (1, 2)), shaped(lab, (1, 4)), _FIRST, _ONE)
    if on_axis[0] or edge[0] or edge[1]:
        return FALLBACK
    for b in range(4):
        missing[b] = False
    return _finish(shaped(phi, (4, 3)), unreach, missing, lab, ctx, q0, T, t.shape[0] == 16, lat[0], rho[0], r,
                   np.int64(2), _NO_GATE, _NO_GATE, fb, ib, bb, wk[at:], ib[i_at:], bb[b_at:])


@njit(cache=True, _nrt=False)
def spherical_wrist(t, q0, ctx, fb, ib, bb, wk):
    """Spherical-wrist (``_layout.SW_*``): ``t`` flat pose (16)."""
    _, g, joints, _, opts = _parts(ctx)
    T4, T, at, usable = _begin(t, q0, opts, wk)
    if not usable:
        return BAD_TARGET
    q0phi, at = _cut(wk, at, 6)
    out, at = _cut(wk, at, 48)
    phi, at = _cut(wk, at, 12)
    c, at = _cut(wk, at, 2)
    r, at = _cut(wk, at, 2)
    rho, at = _cut(wk, at, 1)
    lab, i_at = _cut(ib, 5 * 8, 8)
    lab4, i_at = _cut(ib, i_at, 4)
    singular, b_at = _cut(bb, 2 * 8, 4)
    up, b_at = _cut(bb, b_at, 4)
    unreach4, b_at = _cut(bb, b_at, 4)
    lat, b_at = _cut(bb, b_at, 1)
    on_axis, b_at = _cut(bb, b_at, 1)
    edge, b_at = _cut(bb, b_at, 2)
    unreach, b_at = _cut(bb, b_at, 8)
    missing, b_at = _cut(bb, b_at, 8)
    q0p = shaped(q0phi, (1, 6))
    _q0phi(q0, joints, q0p)
    _puma_run(shaped(T4, (1, 4, 4)), g, q0p, shaped(out, (1, 4, 2, 6)), shaped(lab, (1, 4, 2)),
              shaped(singular, (1, 4)), shaped(phi, (1, 4, 3)), shaped(up, (1, 4)), shaped(unreach4, (1, 4)),
              shaped(c, (1, 2)), shaped(r, (1, 2)), rho, lat, on_axis, shaped(edge, (1, 2)), shaped(lab4, (1, 4)),
              _FIRST, _ONE)
    if on_axis[0] or edge[0] or edge[1]:
        return FALLBACK
    for b in range(4):
        if singular[b]:
            return FALLBACK
        unreach[2 * b] = unreach[2 * b + 1] = unreach4[b]
    for b in range(8):
        missing[b] = False
    return _finish(shaped(out, (8, 6)), unreach, missing, lab, ctx, q0, T, _YES, lat[0], rho[0], r, np.int64(4),
                   _NO_GATE, _NO_GATE, fb, ib, bb, wk[at:], ib[i_at:], bb[b_at:])


@njit(cache=True, _nrt=False)
def ur(t, q0, ctx, fb, ib, bb, wk):
    """UR (``_layout.UR_*``): ``t`` flat pose (16)."""
    _, g, joints, _, opts = _parts(ctx)
    T4, T, at, usable = _begin(t, q0, opts, wk)
    if not usable:
        return BAD_TARGET
    q0phi, at = _cut(wk, at, 6)
    out, at = _cut(wk, at, 48)
    rho, at = _cut(wk, at, 1)
    r, at = _cut(wk, at, 4)
    lab, i_at = _cut(ib, 5 * 8, 8)
    up, b_at = _cut(bb, 2 * 8, 8)
    unreach, b_at = _cut(bb, b_at, 8)
    lat, b_at = _cut(bb, b_at, 1)
    on_axis, b_at = _cut(bb, b_at, 1)
    singular, b_at = _cut(bb, b_at, 4)
    missing, b_at = _cut(bb, b_at, 8)
    q0p = shaped(q0phi, (1, 6))
    _q0phi(q0, joints, q0p)
    _ur_run(shaped(T4, (1, 4, 4)), g, q0p, shaped(out, (1, 2, 2, 2, 6)), shaped(up, (1, 2, 2, 2)),
            shaped(lab, (1, 2, 2, 2)), shaped(unreach, (1, 2, 2, 2)), lat, rho, shaped(r, (1, 2, 2)), on_axis,
            shaped(singular, (1, 2, 2)), _FIRST, _ONE)
    if on_axis[0] or singular[0] or singular[1] or singular[2] or singular[3]:
        return FALLBACK
    for b in range(8):
        missing[b] = False
    return _finish(shaped(out, (8, 6)), unreach, missing, lab, ctx, q0, T, _YES, lat[0], rho[0], r, np.int64(2),
                   _NO_GATE, _NO_GATE, fb, ib, bb, wk[at:], ib[i_at:], bb[b_at:])


@intrinsic
def _call_at(typingctx, address, t, q0, ctx, fb, ib, bb, wk):
    """The compiled kernel at ``address`` (:func:`kernel_address`) called on ``(t, q0, ctx, fb, ib, bb, wk)`` as
    Numba calls one compiled function from another (its own calling convention; the kernels raise nothing, a
    status would be passed on): its int64 status."""
    sig = nbtypes.int64(address, t, q0, ctx, fb, ib, bb, wk)

    def codegen(context, builder, signature, args):
        kinds = signature.args[1:]
        fnty = context.call_conv.get_function_type(nbtypes.int64, kinds)
        fn = builder.inttoptr(args[0], fnty.as_pointer())
        status, res = context.call_conv.call_function(builder, fn, nbtypes.int64, kinds, args[1:])
        with cgutils.if_unlikely(builder, status.is_error):
            context.call_conv.return_status_propagate(builder, status)
        return res

    return sig, codegen


@njit(cache=True, _nrt=False)
def _rows(address, T, Q0, each, ctx, FB, IB, BB, WK, R, Q, OK):
    """Target ``i`` of ``T (B, 16 or 3)`` by the one-call kernel at ``address`` (:func:`kernel_address`) into row
    ``i`` of the buffers ``FB (B, rows, n)``, ``IB (B, isize)``, ``BB (B, bsize)``; start ``Q0[i]`` (``each``) or
    ``Q0[0]``. The rows are cut into chunks (``WK (chunks, wsize)``: the work vector of each; a kernel reads nothing
    there it did not write in the same call), a ``prange`` over them (its twin runs them on every thread). After
    each call the row's first ``k`` branches (``k``: ``OK``'s columns, 1 or ``m``) are copied into ``Q[i]`` (their
    joint values, ``(B, k n)``) and ``OK[i]`` (their success, ``(B, k)``): the result's ``q`` and ``success``.

    Returns -1 where a row's target is to be rejected (:data:`BAD_TARGET`: the caller answers every row by the
    batched path, which raises the error naming it), else the number of rows marked 1 in ``R (B,)`` (0 the others),
    plus ``2**32`` times the number marked 2: 1 where failed branches need sentences (for :func:`armkit.ik_all` a
    row with a failed branch, for :func:`armkit.ik` (``ctx``'s option ``nearest``) a row whose first branch
    failed: :func:`armkit.ik.analytic._sentences`, row by row), 2 where the status asks for the batched path
    (:data:`FALLBACK`: a singular wrist's note, a branch to polish further), which answers those rows alone.

    The kernel comes in as the address of its compiled code (as compiled for the one-call path), so that one
    driver serves every family and nothing of a kernel is compiled again: a driver that took the kernel itself
    would compile and optimise a copy of it per family, and a Numba first-class function costs ~0.1 ms a call to
    unbox (it asks the dispatcher for its addresses in Python).

    Compiled without reference counts (it makes views of the rows, no array; the caller holds every array for the
    call): each row's six views were counted up and down with an atomic instruction, ~0.08 µs a row of the Kinova's
    2.2 µs on one thread (its twin: 1.11-1.14 -> 1.05-1.09 µs a row on two; 2026-12-07)."""
    B = T.shape[0]
    chunks = min(B, WK.shape[0])
    kept, n = OK.shape[1], FB.shape[2]
    for k in prange(chunks):
        for i in range(k * B // chunks, (k + 1) * B // chunks):
            R[i] = _call_at(address, T[i], Q0[i if each else 0], ctx, FB[i], IB[i], BB[i], WK[k])
            for b in range(kept):
                OK[i, b] = BB[i, b]
                for j in range(n):
                    Q[i, b * n + j] = FB[i, b, j]
    nearest = _parts(ctx)[4][9] != 0.0
    pending = 0
    redo = 0
    for i in range(B):
        r = R[i]
        if r & 3 == FALLBACK:
            R[i] = 2
            redo += 1
            continue
        if r & 3:
            return -1
        p = (r & NEAREST) == 0 and IB[i, 0] != 0 if nearest else r != 0
        R[i] = 1 if p else 0
        pending += R[i]
    return pending + (redo << 32)


_ROWS_PAR = parallel_twin(_rows)
_ROWS_ENTRY: dict = {}


def rows_entry(parallel):
    """The compiled function of :func:`_rows` (``parallel``: of its twin) for the one set of argument types it
    takes (read-only targets and starts, as the kernel only reads them, are the same to the compiled code),
    called without the dispatcher's typing; compiled on first use (cached on disk)."""
    entry = _ROWS_ENTRY.get(parallel)
    if entry is None:
        f64, i64, b1, A = nbtypes.float64, nbtypes.int64, nbtypes.boolean, nbtypes.Array
        args = (i64, A(f64, 2, "C"), A(f64, 2, "C"), b1, A(f64, 1, "C", readonly=True), A(f64, 3, "C"),
                A(i64, 2, "C"), A(b1, 2, "C"), A(f64, 2, "C"), A(i64, 1, "C"), A(f64, 2, "C"), A(b1, 2, "C"))
        entry = _ROWS_ENTRY[parallel] = (_ROWS_PAR if parallel else _rows).compile(args)
    return entry


def kernel_address(kernel, sample):
    """The address of the compiled code of the Numba ``kernel`` for the types of the arguments ``sample`` (compiled
    now if it is not yet; Numba's own entry, not its C wrapper), for :func:`_rows`, which calls it as returning an
    int64; it stays valid while the kernel lives (a module's: the process). 0 where this Numba does not say it or
    the kernel returns another type (the caller then takes the batched path)."""
    import numba

    types = tuple(numba.typeof(a) for a in sample)
    try:
        kernel.compile(types)
        cres = kernel.overloads[types]
        if cres.signature.return_type != nbtypes.int64:
            return 0
        return int(cres.library.get_pointer_to_function(cres.fndesc.llvm_func_name))
    except (AttributeError, KeyError, TypeError):   # an internal of Numba renamed: no driver, the same answers
        return 0


NAME_WRIST, NAME_UR = 0, 1
"""The naming families :func:`name_rows` runs: the spherical wrist's kernel, the UR's."""
TIE = 1e-14
"""Distances (rad², squared) within this of the nearest are as near (:func:`name_rows`)."""


@njit(cache=True, inline="always")
def _less_turns(x):
    """``x`` less its nearest whole turns, as ``geometric._turns`` takes a joint's difference (a float remainder
    took ~25 ns)."""
    return x - TWO_PI * np.rint(x / TWO_PI)


@njit(cache=True)
def name_rows(q, theta, F, g, kind, k, first, dup):
    """The compiled core of ``Geometric.name_branches`` for branches ``q`` (R, 6) (``k`` a target, R = B k) of
    an arm named by a family of its ideal DH twin: row ``i``'s pose on the ideal arm (``F``: its packed chain;
    :func:`_fk_row`, the bits of ``armkit.fk``), that family's branches of the pose (its kernel, ``kind``:
    :data:`NAME_WRIST` or :data:`NAME_UR`, geometry ``g``, started at ``q[i] + theta``, as its ``branches``
    method runs it), and the index into its ``branch_labels`` of the branch nearest ``q[i]`` (joint differences
    less the nearest whole turns, squared and summed; within :data:`TIE` of the nearest, the first in the
    family's table) into ``first[i]``; ``dup[b]``: whether two of target ``b``'s ``k`` branches got one index.
    Returns False where the family's kernel does not answer alone (a UR wrist singular: its ``solve`` fixes it),
    leaving the outputs unset."""
    R, n = q.shape
    T = np.empty((R, 4, 4))
    q0p = np.empty((R, n))
    angles = np.empty((R, 8, 6))
    table = np.empty((R, 8), np.int64)
    A4, L4 = angles.reshape(R, 4, 2, 6), table.reshape(R, 4, 2)               # the spherical wrist's layout
    A5, L5 = angles.reshape(R, 2, 2, 2, 6), table.reshape(R, 2, 2, 2)         # the UR's
    # the kernels' other outputs, not read (each chunk writes its own rows)
    sing4, phi, up, unreach = np.empty((R, 4), np.bool_), np.empty((R, 4, 3)), np.empty((R, 4), np.bool_), \
        np.empty((R, 4), np.bool_)
    cw, rw, rho, lat, axis, edge, lab4 = np.empty((R, 2)), np.empty((R, 2)), np.empty(R), np.empty(R, np.bool_), \
        np.empty(R, np.bool_), np.empty((R, 2), np.bool_), np.empty((R, 4), np.int64)
    up5, unreach5, r5, singular = np.empty((R, 2, 2, 2), np.bool_), np.empty((R, 2, 2, 2), np.bool_), \
        np.empty((R, 2, 2)), np.zeros((R, 2, 2), np.bool_)
    chunks = min(R, NAME_CHUNKS)
    for c in prange(chunks):   # rows cut into chunks (its twin runs them on every thread)
        lo, hi = c * R // chunks, (c + 1) * R // chunks
        for i in range(lo, hi):
            _fk_row(F, q, i, T[i])
            for j in range(n):
                q0p[i, j] = q[i, j] + theta[j]
        if kind == NAME_WRIST:
            _puma_run(T, g, q0p, A4, L4, sing4, phi, up, unreach, cw, rw, rho, lat, axis, edge, lab4, lo, hi)
        else:
            _ur_run(T, g, q0p, A5, up5, L5, unreach5, lat, rho, r5, axis, singular, lo, hi)
        d = np.empty(8)
        for i in range(lo, hi):
            near = math.inf
            for b in range(8):
                s = 0.0
                for j in range(n):
                    x = _less_turns(q[i, j] - (angles[i, b, j] - theta[j]))
                    s += x * x
                d[b] = s
                near = min(near, s)
            best = 1 << 30
            for b in range(8):
                if d[b] <= near + TIE:
                    best = min(best, table[i, b])
            first[i] = best
    if kind != NAME_WRIST:
        for i in range(R):
            for a in range(2):
                for b in range(2):
                    if singular[i, a, b]:
                        return False
    for t in range(R // k):
        dup[t] = False
        for a in range(k):
            for b in range(a):
                if first[t * k + a] == first[t * k + b]:
                    dup[t] = True
    return True


_NAME_PAR = parallel_twin(name_rows)
NAME_CHUNKS = 64
"""The chunks of rows of :func:`name_rows` (each with its own scratch), on every thread in its twin."""
NAME_PARALLEL = 64
"""Rows from which ``Geometric.name_branches`` calls the twin of :func:`name_rows` (8 a target of ``ik_all``)."""


def name_entry(rows):
    """:func:`name_rows`, or its multi-threaded twin for :data:`NAME_PARALLEL` rows or more (where threads serve)."""
    return _NAME_PAR if rows >= NAME_PARALLEL and _jit_loader.parallel_ok() else name_rows


@njit(cache=True)
def settle_rows(first, q, twice, ideal, table, names, tie):
    """``geometric._settle`` of the targets ``twice`` (their rows of ``first`` (B, k), indices into the naming
    family's ``branch_labels``, one index given twice) in one call, in place: ``q`` (B, k, n) their branches,
    ``ideal`` (len(twice), m, n) the family's branches of each such target (its DH angles less theta) and ``table``
    (len(twice), m) their indices; ``names`` the number of names. The same rules and steps: the branches whose
    index is given more than once, ordered by their joint values (``rint`` of the angle plus pi modulo 2 pi, times
    1e9; by the first joint, then the next, the order they came in where all tie: a stable sort), and the family's
    branches whose index is not given exactly once, paired nearest first (joint differences less the nearest whole
    turns, squared and summed; the first pair in row order within ``tie`` times one plus the nearest of it: the
    sums' last bits differ from ``np.einsum``'s; once every distance is used up, the first pair)."""
    B, k, n = q.shape
    m = ideal.shape[1]
    count = np.empty(names, np.int64)
    shared = np.empty(k, np.int64)
    free = np.empty(m, np.int64)
    key = np.empty((k, n))
    d = np.empty((k, m))
    for r in range(twice.shape[0]):
        b = twice[r]
        for j in range(names):
            count[j] = 0
        for i in range(k):
            count[first[b, i]] += 1
        ns = 0
        for i in range(k):
            if count[first[b, i]] > 1:
                shared[ns] = i
                ns += 1
        for s in range(ns):
            for j in range(n):
                key[s, j] = np.rint(np.remainder(q[b, shared[s], j] + np.pi, 2.0 * np.pi) * 1e9)
        for s in range(1, ns):   # insertion sort: stable, by the first differing key
            i, ks = shared[s], key[s].copy()
            t = s - 1
            while t >= 0 and _key_after(key[t], ks):
                shared[t + 1] = shared[t]
                key[t + 1] = key[t]
                t -= 1
            shared[t + 1] = i
            key[t + 1] = ks
        nf = 0
        for j in range(m):
            if count[table[r, j]] != 1:
                free[nf] = j
                nf += 1
        for s in range(ns):
            for f in range(nf):
                acc = 0.0
                for j in range(n):
                    x = _less_turns(q[b, shared[s], j] - ideal[r, free[f], j])
                    acc += x * x
                d[s, f] = acc
        for _ in range(ns):
            near = math.inf
            for s in range(ns):
                for f in range(nf):
                    near = min(near, d[s, f])
            lim = near + tie * (1.0 + near)
            bi, bj = 0, 0
            for s in range(ns * nf):
                if d[s // nf, s % nf] <= lim:
                    bi, bj = s // nf, s % nf
                    break
            first[b, shared[bi]] = table[r, free[bj]]
            for f in range(nf):
                d[bi, f] = math.inf
            for s in range(ns):
                d[s, bj] = math.inf


@njit(cache=True, inline="always")
def _key_after(a, b):
    """Whether key row ``a`` sorts after ``b`` (the first differing entry larger)."""
    for j in range(a.shape[0]):
        if a[j] != b[j]:
            return a[j] > b[j]
    return False


def parallel_twins():
    """``(one-thread kernel, multi-threaded kernel)`` pairs taking the same arguments (for the warm-up)."""
    return [(_rows, _ROWS_PAR), (name_rows, _NAME_PAR)]


WORK: dict = {"planar-2r": (25, 2, 5), "planar-3r": (24, 2, 5), "yaw-pitch-pitch": (37, 4, 16),
        "spherical-wrist": (87, 12, 32), "ur": (75, 8, 30)}
"""Family -> the work space its kernel cuts for itself before :func:`_finish`'s: ``(floats of wk, ints at the
end of ib, flags at the end of bb)``, or a function of ``(m, n)`` that gives them (the geometric family registers
one); :func:`work` adds ``_finish``'s."""


def work(family, m, n):
    """``(wk size, extra ib, extra bb)`` of the kernel of ``family`` (None: :func:`post`) for ``m`` branches of
    ``n`` joints: its own work space (:data:`WORK`) and :func:`_finish`'s."""
    f, i, b = finish_work(m, n)
    if family is None:
        return 17 + f, m + i, b
    own = WORK[family]
    if callable(own):
        own = own(m, n)
    return own[0] + f, own[1] + i, own[2] + b


KERNELS = {"planar-2r": planar2, "planar-3r": planar3, "yaw-pitch-pitch": yaw_pitch_pitch,
           "spherical-wrist": spherical_wrist, "ur": ur}
"""Family name -> its one-call kernel ``(t, q0, ctx, fb, ib, bb, wk)``; other families: :func:`post` after their
``solve``. A family here also has ``reach_why(lateral_out, rho, r, target)``: its out-of-reach sentence (the
one its ``Raw.why`` gives) from the kernel's ``reach`` numbers, so that a target with a clipped branch is not
solved a second time."""

# the kernels inline helpers of these files: compiled anew when they change
_jit_loader.forget_stale_cache(globals(), ("ik/analytic/_jit.py", "ik/analytic/_layout.py", "kinematics/_jit.py",
                                           "ik/_jit_verify.py", "_jit_shaped.py"))
