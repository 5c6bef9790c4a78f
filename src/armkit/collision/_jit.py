"""Numba kernels of the collision check: every pair of one configuration in registers, configurations in parallel.

The same formulas as :mod:`armkit.collision.kernels` (the NumPy reference), one configuration
at a time: the arm's solids are placed from the chain frames, then each pair's signed distance
is computed. :func:`min_distance` keeps only the smallest per configuration and skips a pair
when a bounding-sphere lower bound already exceeds the smallest found so far; :func:`all_distances`
computes every pair. Imported only when the Numba back end is in use.

Item kinds: 0 a segment between two frame origins, 1 a segment given by two points in a frame
(or the world, frame -1), 2 a box, 3 a half-space (``normal · x <= offset``).

Packed arguments (so no kernel takes more than 8): ``items`` is the tuple
``(kind, fr, ia, ib, L, rad, half, bound)`` built by :func:`armkit.collision.query._jit_pack`
(per item: its kind, frame, the two frame indices of a chain segment, local data (4, 4), capsule
radius, box half extents (3,), box bounding radius), and ``placed`` is the per-configuration
scratch ``(P0, P1, W, C, R)``: segment ends (I, 3), item poses (I, 3, 4), bounding-sphere
centres (I, 3) and radii (I,). Numba passes a tuple of arrays as a struct: no copy, no cost
(benchmarks/bench_collision.py speed, before and after packing: the same within noise).

Each driver has a parallel and a serial twin (``_all_parallel``/``_all_serial``,
``_min_parallel``/``_min_serial``) on purpose: a ``parallel=True`` function pays a thread-pool
launch on every call and must not run inside another parallel region (IK restarts and the
reachability workers call these per sample), so small batches and nested callers use the
serial twin (:func:`armkit._jit_loader.parallel_ok`). Both are three lines around the same
chunk body.
"""

from __future__ import annotations

import math

import numpy as np

from .. import _jit_loader

_jit_loader.install_cache_fallback()  # before the first cache=True: read-only installs cache elsewhere

from numba import njit, prange  # noqa: E402

SEGF, SEGL, BOX, PLANE = 0, 1, 2, 3
PARALLEL_MIN = 2048


@njit(cache=True, inline="always")
def _seg_seg(P0, P1, i, j):
    """Distance between segments a->b = P0[i]->P1[i] and c->d = P0[j]->P1[j] (Ericson 5.1.9)."""
    a0, a1, a2 = P0[i, 0], P0[i, 1], P0[i, 2]
    b0, b1, b2 = P1[i, 0], P1[i, 1], P1[i, 2]
    c0, c1, c2 = P0[j, 0], P0[j, 1], P0[j, 2]
    d0, d1, d2 = P1[j, 0], P1[j, 1], P1[j, 2]
    e10, e11, e12 = b0 - a0, b1 - a1, b2 - a2
    e20, e21, e22 = d0 - c0, d1 - c1, d2 - c2
    r0, r1, r2 = a0 - c0, a1 - c1, a2 - c2
    a = e10 * e10 + e11 * e11 + e12 * e12
    e = e20 * e20 + e21 * e21 + e22 * e22
    f = e20 * r0 + e21 * r1 + e22 * r2
    tiny = 1e-300
    if a <= tiny and e <= tiny:
        s = 0.0
        t = 0.0
    elif a <= tiny:
        s = 0.0
        t = min(max(f / e, 0.0), 1.0)
    else:
        c = e10 * r0 + e11 * r1 + e12 * r2
        if e <= tiny:
            t = 0.0
            s = min(max(-c / a, 0.0), 1.0)
        else:
            b = e10 * e20 + e11 * e21 + e12 * e22
            denom = a * e - b * b
            if denom <= 1e-14 * a * e:
                s = 0.0
            else:
                s = min(max((b * f - c * e) / denom, 0.0), 1.0)
            t = (b * s + f) / e
            if t < 0.0:
                t = 0.0
                s = min(max(-c / a, 0.0), 1.0)
            elif t > 1.0:
                t = 1.0
                s = min(max((b - c) / a, 0.0), 1.0)
    x = a0 + s * e10 - (c0 + t * e20)
    y = a1 + s * e11 - (c1 + t * e21)
    z = a2 + s * e12 - (c2 + t * e22)
    return math.sqrt(x * x + y * y + z * z)


@njit(cache=True)
def _seg_box(p, q, T, h, ts):
    """Signed distance of segment p->q to the box with pose T (3x4 used) and half extents h; ``ts`` scratch (8,)."""
    a0 = T[0, 0] * (p[0] - T[0, 3]) + T[1, 0] * (p[1] - T[1, 3]) + T[2, 0] * (p[2] - T[2, 3])
    a1 = T[0, 1] * (p[0] - T[0, 3]) + T[1, 1] * (p[1] - T[1, 3]) + T[2, 1] * (p[2] - T[2, 3])
    a2 = T[0, 2] * (p[0] - T[0, 3]) + T[1, 2] * (p[1] - T[1, 3]) + T[2, 2] * (p[2] - T[2, 3])
    b0 = T[0, 0] * (q[0] - p[0]) + T[1, 0] * (q[1] - p[1]) + T[2, 0] * (q[2] - p[2])
    b1 = T[0, 1] * (q[0] - p[0]) + T[1, 1] * (q[1] - p[1]) + T[2, 1] * (q[2] - p[2])
    b2 = T[0, 2] * (q[0] - p[0]) + T[1, 2] * (q[1] - p[1]) + T[2, 2] * (q[2] - p[2])
    a = (a0, a1, a2)
    b = (b0, b1, b2)
    hh = (h[0], h[1], h[2])
    # quick exact test first: the endpoint distances bound the answer only from above, so no shortcut;
    # breakpoints where some |a_i + t b_i| = h_i
    ts[0] = 0.0
    ts[1] = 1.0
    m = 2
    for i in range(3):
        if b[i] != 0.0:
            t = (hh[i] - a[i]) / b[i]
            if t > 0.0 and t < 1.0:
                ts[m] = t
                m += 1
            t = (-hh[i] - a[i]) / b[i]
            if t > 0.0 and t < 1.0:
                ts[m] = t
                m += 1
    for i in range(1, m):
        v = ts[i]
        j = i - 1
        while j >= 0 and ts[j] > v:
            ts[j + 1] = ts[j]
            j -= 1
        ts[j + 1] = v
    best = np.inf
    for k in range(m - 1):
        lo = ts[k]
        hi = ts[k + 1]
        mid = 0.5 * (lo + hi)
        qa = 0.0
        qb = 0.0
        for i in range(3):
            xm = a[i] + mid * b[i]
            if xm > hh[i]:
                qa += b[i] * b[i]
                qb += (a[i] - hh[i]) * b[i]
            elif xm < -hh[i]:
                qa += b[i] * b[i]
                qb += (a[i] + hh[i]) * b[i]
        t = -qb / qa if qa > 0.0 else mid   # nothing outside at the midpoint: f(mid) = 0 exactly
        t = min(max(t, lo), hi)
        f = 0.0
        for i in range(3):
            x = abs(a[i] + t * b[i]) - hh[i]
            if x > 0.0:
                f += x * x
        if f < best:
            best = f
    if best > 0.0:
        return math.sqrt(best)
    return -_overlap_depth(a, b, hh)


@njit(cache=True, inline="always")
def _overlap_depth(a, b, hh):
    """Penetration depth of segment a -> a + b (box frame) into the box of half extents hh: the smallest
    overlap over the separating axes (the box's three, and b crossed with each)."""
    a0, a1, a2 = a
    b0, b1, b2 = b
    depth = np.inf
    bn = math.sqrt(b0 * b0 + b1 * b1 + b2 * b2)
    for ax in range(6):
        if ax == 0:
            n0, n1, n2 = 1.0, 0.0, 0.0
        elif ax == 1:
            n0, n1, n2 = 0.0, 1.0, 0.0
        elif ax == 2:
            n0, n1, n2 = 0.0, 0.0, 1.0
        else:
            if ax == 3:     # b x e_x
                n0, n1, n2 = 0.0, b2, -b1
            elif ax == 4:   # b x e_y
                n0, n1, n2 = -b2, 0.0, b0
            else:           # b x e_z
                n0, n1, n2 = b1, -b0, 0.0
            nn = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
            if not nn > 1e-12 * (1.0 + bn):
                continue
            n0 /= nn
            n1 /= nn
            n2 /= nn
        pa = n0 * a0 + n1 * a1 + n2 * a2
        pb = pa + n0 * b0 + n1 * b1 + n2 * b2
        rb = abs(n0) * hh[0] + abs(n1) * hh[1] + abs(n2) * hh[2]
        ov = min(max(pa, pb) + rb, rb - min(pa, pb))
        if ov < depth:
            depth = ov
    return depth


@njit(cache=True, inline="always")
def _point_box_sq(x, y, z, T, h):
    """Squared distance from a point to a solid box (pose T, half extents h); 0 inside."""
    dx = x - T[0, 3]
    dy = y - T[1, 3]
    dz = z - T[2, 3]
    f = 0.0
    for i in range(3):
        u = abs(T[0, i] * dx + T[1, i] * dy + T[2, i] * dz) - h[i]
        if u > 0.0:
            f += u * u
    return f


@njit(cache=True)
def _place(frames, items, placed, moving_only=False):
    """World data of every item for one configuration: segment ends P0/P1, poses W, bounding spheres C/R.

    ``moving_only``: skip the static items (frame -1, not a chain segment), placed once per chunk.
    """
    kind, fr, ia, ib, L = items[0], items[1], items[2], items[3], items[4]
    P0, P1, W, C, R = placed
    for i in range(kind.shape[0]):
        k = kind[i]
        f = fr[i]
        if moving_only and f < 0 and k != SEGF:
            continue
        if k == SEGF:
            for j in range(3):
                P0[i, j] = frames[ia[i], j, 3]
                P1[i, j] = frames[ib[i], j, 3]
        elif k == SEGL:
            if f < 0:
                for j in range(3):
                    P0[i, j] = L[i, 0, j]
                    P1[i, j] = L[i, 1, j]
            else:
                for j in range(3):
                    P0[i, j] = (frames[f, j, 0] * L[i, 0, 0] + frames[f, j, 1] * L[i, 0, 1]
                                + frames[f, j, 2] * L[i, 0, 2] + frames[f, j, 3])
                    P1[i, j] = (frames[f, j, 0] * L[i, 1, 0] + frames[f, j, 1] * L[i, 1, 1]
                                + frames[f, j, 2] * L[i, 1, 2] + frames[f, j, 3])
        else:
            if f < 0:
                for r in range(3):
                    for c in range(4):
                        W[i, r, c] = L[i, r, c]
            else:
                for r in range(3):
                    for c in range(4):
                        v = frames[f, r, 0] * L[i, 0, c] + frames[f, r, 1] * L[i, 1, c] + frames[f, r, 2] * L[i, 2, c]
                        if c == 3:
                            v += frames[f, r, 3]
                        W[i, r, c] = v
        if k == SEGF or k == SEGL:
            hl = 0.0
            for j in range(3):
                C[i, j] = 0.5 * (P0[i, j] + P1[i, j])
                hl += (P1[i, j] - P0[i, j]) ** 2
            R[i] = 0.5 * math.sqrt(hl)
        elif k == BOX:
            for j in range(3):
                C[i, j] = W[i, j, 3]
            R[i] = -1.0    # set by the caller's half extents (bounding radius stored in rad)


@njit(cache=True, inline="always")
def _pair(i, j, items, placed, ts):
    """Signed distance of items i and j (placed for this configuration); ``ts`` scratch (8,)."""
    kind, rad, half = items[0], items[5], items[6]
    P0, P1, W = placed[0], placed[1], placed[2]
    ki = kind[i]
    kj = kind[j]
    if ki == BOX or ki == PLANE:
        i, j = j, i
        ki, kj = kj, ki
    if kj == SEGF or kj == SEGL:
        return _seg_seg(P0, P1, i, j) - rad[i] - rad[j]
    if kj == BOX:
        if ki == PLANE:   # box against a plane (an arm box on the ground): the lowest corner
            n0, n1, n2 = W[i, 0, 2], W[i, 1, 2], W[i, 2, 2]
            off = n0 * W[i, 0, 3] + n1 * W[i, 1, 3] + n2 * W[i, 2, 3]
            best = np.inf
            for sx in (-1.0, 1.0):
                for sy in (-1.0, 1.0):
                    for sz in (-1.0, 1.0):
                        v = 0.0
                        for r in range(3):
                            x = W[j, r, 3] + sx * half[j, 0] * W[j, r, 0] + sy * half[j, 1] * W[j, r, 1] + \
                                sz * half[j, 2] * W[j, r, 2]
                            v += (n0, n1, n2)[r] * x
                        best = min(best, v - off)
            return best
        return _seg_box(P0[i], P1[i], W[j], half[j], ts) - rad[i]
    # plane
    n0, n1, n2 = W[j, 0, 2], W[j, 1, 2], W[j, 2, 2]
    off = n0 * W[j, 0, 3] + n1 * W[j, 1, 3] + n2 * W[j, 2, 3]
    d0 = n0 * P0[i, 0] + n1 * P0[i, 1] + n2 * P0[i, 2]
    d1 = n0 * P1[i, 0] + n1 * P1[i, 1] + n2 * P1[i, 2]
    return min(d0, d1) - off - rad[i]


CHUNK = 64


@njit(cache=True)
def _scratch(I):
    """The per-configuration ``placed`` tuple for I items: P0, P1 (I, 3), W (I, 3, 4), C (I, 3), R (I,)."""
    return np.empty((I, 3)), np.empty((I, 3)), np.empty((I, 3, 4)), np.empty((I, 3)), np.empty(I)


@njit(cache=True)
def _chunk_all(frames, items, pairs, out, c):
    placed = _scratch(items[0].shape[0])
    ts = np.empty(8)
    first = True
    for b in range(c * CHUNK, min((c + 1) * CHUNK, frames.shape[0])):
        _place(frames[b], items, placed, not first)
        first = False
        for p in range(pairs.shape[0]):
            out[b, p] = _pair(pairs[p, 0], pairs[p, 1], items, placed, ts)


@njit(cache=True, parallel=True)
def _all_parallel(frames, items, pairs, out):
    for c in prange((frames.shape[0] + CHUNK - 1) // CHUNK):
        _chunk_all(frames, items, pairs, out, c)


@njit(cache=True)
def _all_serial(frames, items, pairs, out):
    for c in range((frames.shape[0] + CHUNK - 1) // CHUNK):
        _chunk_all(frames, items, pairs, out, c)


@njit(cache=True)
def _chunk_min(frames, items, pairs, dist, arg, stop, c):
    kind, fr, rad, half, bound = items[0], items[1], items[5], items[6], items[7]
    I = kind.shape[0]
    placed = _scratch(I)
    C, R, W = placed[3], placed[4], placed[2]
    ts = np.empty(8)
    yes_no = stop == 0.0
    first = True
    for b in range(c * CHUNK, min((c + 1) * CHUNK, frames.shape[0])):
        _place(frames[b], items, placed, not first)
        for i in range(I):
            if not first and fr[i] < 0 and kind[i] != SEGF:
                continue
            if kind[i] == BOX:
                R[i] = bound[i]
            elif kind[i] != PLANE:
                R[i] += rad[i]
        first = False
        best = np.inf
        barg = -1
        for p in range(pairs.shape[0]):
            i = pairs[p, 0]
            j = pairs[p, 1]
            ki = kind[i]
            kj = kind[j]
            if ki != PLANE and kj != PLANE and not (ki == BOX and kj == BOX):
                # lower bounds from squared distances (no square root unless needed)
                if kj == BOX or ki == BOX:   # the segment's bounding ball against the box itself
                    s_ = i if kj == BOX else j
                    b_ = j if kj == BOX else i
                    f = _point_box_sq(C[s_, 0], C[s_, 1], C[s_, 2], W[b_], half[b_])
                    rs = R[s_]
                    if f > rs * rs:            # apart: the distance is at least sqrt(f) - rs > 0
                        if yes_no or math.sqrt(f) - rs >= best:
                            continue
                else:                          # two capsules: their bounding balls (valid overlapping too)
                    dx = C[i, 0] - C[j, 0]
                    dy = C[i, 1] - C[j, 1]
                    dz = C[i, 2] - C[j, 2]
                    dsq = dx * dx + dy * dy + dz * dz
                    rr = R[i] + R[j]
                    if dsq > rr * rr:
                        if yes_no:
                            continue
                    if math.sqrt(dsq) - rr >= best:
                        continue
            d = _pair(i, j, items, placed, ts)
            if d < best:
                best = d
                barg = p
                if best < stop:   # a yes/no check: one overlapping pair is enough
                    break
        dist[b] = best
        arg[b] = barg


@njit(cache=True, parallel=True)
def _min_parallel(frames, items, pairs, dist, arg, stop):
    for c in prange((frames.shape[0] + CHUNK - 1) // CHUNK):
        _chunk_min(frames, items, pairs, dist, arg, stop, c)


@njit(cache=True)
def _min_serial(frames, items, pairs, dist, arg, stop):
    for c in range((frames.shape[0] + CHUNK - 1) // CHUNK):
        _chunk_min(frames, items, pairs, dist, arg, stop, c)


def all_distances(frames, items, pairs):
    """Every pair's signed distance ``(B, P)``; ``items`` from :func:`armkit.collision.query._jit_items`."""
    out = np.empty((frames.shape[0], pairs.shape[0]))
    kernel = _all_parallel if frames.shape[0] >= PARALLEL_MIN and _jit_loader.parallel_ok() else _all_serial
    kernel(frames, items, pairs, out)
    return out


def min_distance(frames, items, pairs, stop=-np.inf):
    """The smallest signed distance ``(B,)`` and its pair index ``(B,)``.

    With ``stop=0`` a configuration's search ends at its first overlapping pair (its distance
    is then negative but not necessarily the deepest): the fast yes/no check.
    """
    B = frames.shape[0]
    dist = np.empty(B)
    arg = np.empty(B, dtype=np.int64)
    kernel = _min_parallel if B >= PARALLEL_MIN and _jit_loader.parallel_ok() else _min_serial
    kernel(frames, items, pairs, dist, arg, float(stop))
    return dist, arg
