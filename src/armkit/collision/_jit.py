"""Numba kernels of the collision check: every pair of one configuration in registers, configurations in parallel.

The same formulas as :mod:`armkit.collision.kernels` (the NumPy reference), one configuration
at a time: the arm's solids are placed from the chain frames, then each pair's signed distance
is computed. :func:`min_distance` keeps only the smallest per configuration and skips a pair
when a bounding-sphere lower bound already exceeds the smallest found so far; :func:`all_distances`
computes every pair. Imported only when the Numba back end is in use.

Item kinds (the ``kernel`` codes of :data:`armkit.collision.kinds.KINDS`): 0 a segment between two
frame origins, 1 a segment given by two points in a frame (or the world, frame -1; a capsule, or a
ball as a zero-length one), 2 a box, 3 a half-space (``normal · x <= offset``), 4 a cylinder
(``half`` holds its radius, 0 and its half length). :func:`_pair` is the pair table.

Packed arguments (so no kernel takes more than 8): ``items`` is the tuple
``(kind, fr, ia, ib, L, rad, half, bound)`` built by :func:`armkit.collision.query._jit_pack`
(per item: its kind, frame, the two frame indices of a chain segment, local data (4, 4), capsule
radius, box half extents (3,) or cylinder (radius, 0, half length), the solid's bounding radius), and ``placed`` is the per-configuration
scratch ``(P0, P1, W, C, R)``: segment ends (I, 3), item poses (I, 3, 4), bounding-sphere
centres (I, 3) and radii (I,). Numba passes a tuple of arrays as a struct: no copy, no cost
(benchmarks/bench_collision.py speed, before and after packing: the same within noise).

Each driver is a one-thread kernel with a multi-threaded twin made from it
(:func:`armkit._jit_twins.parallel_twin`: ``_all_serial``/``_all_parallel``,
``_min_serial``/``_min_parallel``): a ``parallel=True`` function pays a thread-pool launch on
every call and must not run inside another parallel region (IK restarts and the reachability
workers call these per sample), so small batches and nested callers use the one-thread kernel
(:func:`armkit._jit_loader.parallel_ok`).
"""

from __future__ import annotations

import math

import numpy as np

from .. import _jit_loader

_jit_loader.install_cache_fallback()  # before the first cache=True: read-only installs cache elsewhere

from numba import njit, prange  # noqa: E402

from .._jit_twins import parallel_twin  # noqa: E402

from ._jit_pairs import (BOX, CYL, PLANE, SEGF, SEGL, _convex, _cyl_plane, _point_box_sq,  # noqa: E402
                         _seg_box, _seg_cyl, _seg_seg)

PARALLEL_MIN = 128
"""Batches from this many configurations on are checked on all threads. Measured on the project's 2-core machine
(the fighter's self-collision check, 2026-12-06): 64 configurations 0.49 µs each either way, 128 0.38 on one thread
and 0.29 on two, 1,024 0.29 and 0.17."""
EXACT = np.True_
"""``exact`` of :func:`_chunk_all`: a NumPy True, which Numba types as ``bool`` (a literal ``True`` would compile
:func:`._jit_pairs._convex` and :func:`._jit_pairs._seg_cyl` once more, for that literal, beside the ``bool`` of
:func:`_chunk_min`)."""


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
        elif k == BOX or k == CYL:
            for j in range(3):
                C[i, j] = W[i, j, 3]
            R[i] = -1.0    # set by the caller from the item's bounding radius


@njit(cache=True, inline="always")
def _pair(i, j, items, placed, ts, S, exact):
    """Signed distance of items i and j (placed for this configuration); ``ts`` scratch (8,), ``S`` (4, 3).
    ``exact=False``: a yes/no check, where an overlap needs only a negative number, not its depth.

    The compiled pair table: segment (a capsule or a ball: SEGF, SEGL) against a segment, a box, a
    cylinder or a half-space by its exact formula; a half-space against a box or a cylinder by the
    lowest point; the other solid pairs (box, cylinder) by :func:`_convex`.
    """
    kind, rad, half = items[0], items[5], items[6]
    P0, P1, W = placed[0], placed[1], placed[2]
    ki = kind[i]
    kj = kind[j]
    if ki != SEGF and ki != SEGL:     # a segment first, a half-space last
        i, j = j, i
        ki, kj = kj, ki
    if ki == PLANE:
        i, j = j, i
        ki, kj = kj, ki
    if ki == SEGF or ki == SEGL:
        if kj == SEGF or kj == SEGL:
            return _seg_seg(P0, P1, i, j) - rad[i] - rad[j]
        if kj == BOX:
            return _seg_box(P0[i], P1[i], W[j], half[j], ts) - rad[i]
        if kj == CYL:
            return _seg_cyl(P0[i], P1[i], W[j], half[j, 0], half[j, 2], exact) - rad[i]
        n0, n1, n2 = W[j, 0, 2], W[j, 1, 2], W[j, 2, 2]
        off = n0 * W[j, 0, 3] + n1 * W[j, 1, 3] + n2 * W[j, 2, 3]
        d0 = n0 * P0[i, 0] + n1 * P0[i, 1] + n2 * P0[i, 2]
        d1 = n0 * P1[i, 0] + n1 * P1[i, 1] + n2 * P1[i, 2]
        return min(d0, d1) - off - rad[i]
    if kj == PLANE:
        if ki == CYL:
            return _cyl_plane(W, i, j, half)
        if ki == PLANE:
            return np.inf
        # box against a plane (an arm box on the ground): the lowest corner
        n0, n1, n2 = W[j, 0, 2], W[j, 1, 2], W[j, 2, 2]
        off = n0 * W[j, 0, 3] + n1 * W[j, 1, 3] + n2 * W[j, 2, 3]
        best = np.inf
        for sx in (-1.0, 1.0):
            for sy in (-1.0, 1.0):
                for sz in (-1.0, 1.0):
                    v = 0.0
                    for r in range(3):
                        x = W[i, r, 3] + sx * half[i, 0] * W[i, r, 0] + sy * half[i, 1] * W[i, r, 1] + \
                            sz * half[i, 2] * W[i, r, 2]
                        v += (n0, n1, n2)[r] * x
                    best = min(best, v - off)
        return best
    return _convex(ki, i, kj, j, P0, P1, W, half, S, exact)


CHUNK = 64


@njit(cache=True)
def _scratch(I):
    """The per-configuration ``placed`` tuple for I items: P0, P1 (I, 3), W (I, 3, 4), C (I, 3), R (I,)."""
    return np.empty((I, 3)), np.empty((I, 3)), np.empty((I, 3, 4)), np.empty((I, 3)), np.empty(I)


@njit(cache=True)
def _chunk_all(frames, items, pairs, out, c):
    placed = _scratch(items[0].shape[0])
    ts = np.empty(8)
    S = np.empty((4, 3))
    first = True
    for b in range(c * CHUNK, min((c + 1) * CHUNK, frames.shape[0])):
        _place(frames[b], items, placed, not first)
        first = False
        for p in range(pairs.shape[0]):
            out[b, p] = _pair(pairs[p, 0], pairs[p, 1], items, placed, ts, S, EXACT)


@njit(cache=True)
def _all_serial(frames, items, pairs, out):
    for c in prange((frames.shape[0] + CHUNK - 1) // CHUNK):   # int64: the multi-threaded twin's prange counts in
        _chunk_all(frames, items, pairs, out, np.int64(c))       # uint64, which compiled the chunk a second time


_all_parallel = parallel_twin(_all_serial)


@njit(cache=True)
def _chunk_min(frames, items, pairs, dist, arg, stop, c):
    kind, fr, rad, half, bound = items[0], items[1], items[5], items[6], items[7]
    I = kind.shape[0]
    placed = _scratch(I)
    C, R, W = placed[3], placed[4], placed[2]
    ts = np.empty(8)
    S = np.empty((4, 3))
    yes_no = stop == 0.0
    first = True
    for b in range(c * CHUNK, min((c + 1) * CHUNK, frames.shape[0])):
        _place(frames[b], items, placed, not first)
        for i in range(I):
            if not first and fr[i] < 0 and kind[i] != SEGF:
                continue
            if kind[i] == BOX or kind[i] == CYL:
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
            if ki != PLANE and kj != PLANE:
                # lower bounds from squared distances (no square root unless needed)
                iseg = ki == SEGF or ki == SEGL
                jseg = kj == SEGF or kj == SEGL
                if (kj == BOX and iseg) or (ki == BOX and jseg):   # the segment's bounding ball against the box
                    s_ = i if kj == BOX else j
                    b_ = j if kj == BOX else i
                    f = _point_box_sq(C[s_, 0], C[s_, 1], C[s_, 2], W[b_], half[b_])
                    rs = R[s_]
                    if f > rs * rs:            # apart: the distance is at least sqrt(f) - rs > 0
                        if yes_no or math.sqrt(f) - rs >= best:
                            continue
                else:                          # bounding balls (valid overlapping too)
                    dx = C[i, 0] - C[j, 0]
                    dy = C[i, 1] - C[j, 1]
                    dz = C[i, 2] - C[j, 2]
                    dsq = dx * dx + dy * dy + dz * dz
                    rr = R[i] + R[j]
                    if dsq > rr * rr and yes_no:
                        continue
                    if math.sqrt(dsq) - rr >= best:
                        continue
            d = _pair(i, j, items, placed, ts, S, not yes_no)
            if d < best:
                best = d
                barg = p
                if best < stop:   # a yes/no check: one overlapping pair is enough
                    break
        dist[b] = best
        arg[b] = barg


@njit(cache=True)
def _min_serial(frames, items, pairs, dist, arg, stop):
    for c in prange((frames.shape[0] + CHUNK - 1) // CHUNK):
        _chunk_min(frames, items, pairs, dist, arg, stop, np.int64(c))   # one signature for both twins


_min_parallel = parallel_twin(_min_serial)


def parallel_twins():
    """``(one-thread kernel, multi-threaded kernel)`` pairs taking the same arguments (for the warm-up)."""
    return [(_all_serial, _all_parallel), (_min_serial, _min_parallel)]


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


# this module's cached kernels inline the pair kernels of collision/_jit_pairs.py: compiled anew when it changes
_jit_loader.forget_stale_cache(globals(), ("collision/_jit_pairs.py",))
