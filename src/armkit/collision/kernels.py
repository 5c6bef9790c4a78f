r"""Batched signed distances between a capsule and the scene's primitives, in NumPy.

Every function takes arrays broadcast over any leading shape ``(...)`` and returns the signed
distance ``(...)``: the gap between the two solids when they are apart, minus the penetration
depth (the length of the shortest translation that separates them) when they overlap. A capsule
is a segment ``p0 -> p1`` swept by a ball of radius ``r``, so its signed distance to a convex
solid ``C`` is the segment's signed distance to ``C`` minus ``r``.

These are the exact formulas; ``tests/collision`` checks them against coal (Pinocchio's
collision library) and against hand-computed cases.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

__all__ = ["segment_plane", "segment_sphere", "segment_segment", "segment_box", "segment_cylinder",
           "segment_cylinder_signed", "capsule_cylinder_depth", "closest_on_segment"]

Array = NDArray[np.float64]


def _dot(a: Array, b: Array) -> Array:
    return np.einsum("...i,...i->...", a, b)


def closest_on_segment(p0: Array, p1: Array, x: Array) -> Array:
    """The point of segment ``p0 -> p1`` nearest to ``x`` (all ``(..., 3)``)."""
    d = p1 - p0
    dd = _dot(d, d)
    t = np.clip(_dot(x - p0, d) / np.where(dd > 0, dd, 1.0), 0.0, 1.0)
    return p0 + t[..., None] * d


def segment_plane(p0: Array, p1: Array, normal: Array, offset: Array | float) -> Array:
    """Signed distance of a segment to the half-space ``normal · x <= offset`` (``normal`` unit)."""
    return np.minimum(_dot(p0, normal), _dot(p1, normal)) - offset


def segment_sphere(p0: Array, p1: Array, center: Array, radius: Array | float) -> Array:
    """Signed distance of a segment to a ball: ``|c - closest point| - R``."""
    return np.linalg.norm(center - closest_on_segment(p0, p1, center), axis=-1) - radius


def segment_segment(p0: Array, p1: Array, q0: Array, q1: Array) -> Array:
    """Distance between two segments (Ericson, *Real-Time Collision Detection*, 5.1.9).

    Segments cannot overlap with positive volume, so this is also their signed distance; two
    capsules are apart by ``segment_segment(...) - r1 - r2``.
    """
    d1, d2 = p1 - p0, q1 - q0
    rr = p0 - q0
    a, e, f = _dot(d1, d1), _dot(d2, d2), _dot(d2, rr)
    c, b = _dot(d1, rr), _dot(d1, d2)
    tiny = 1e-300
    a_ok, e_ok = a > tiny, e > tiny
    a_s, e_s = np.where(a_ok, a, 1.0), np.where(e_ok, e, 1.0)
    denom = a * e - b * b
    # general case: s from the infinite lines, clamped; parallel lines (denom ~ 0): s = 0
    par = denom <= 1e-14 * a * e
    s = np.where(par, 0.0, np.clip((b * f - c * e) / np.where(par, 1.0, denom), 0.0, 1.0))
    t = (b * s + f) / e_s
    # t outside [0, 1]: clamp it and recompute s
    t_lo, t_hi = t < 0.0, t > 1.0
    s = np.where(t_lo, np.clip(-c / a_s, 0.0, 1.0), np.where(t_hi, np.clip((b - c) / a_s, 0.0, 1.0), s))
    t = np.clip(t, 0.0, 1.0)
    # degenerate segments (points)
    s = np.where(a_ok, s, 0.0)
    t = np.where(a_ok, t, np.clip(f / e_s, 0.0, 1.0))
    s = np.where(e_ok, s, np.where(a_ok, np.clip(-c / a_s, 0.0, 1.0), 0.0))
    t = np.where(e_ok, t, 0.0)
    diff = (p0 + s[..., None] * d1) - (q0 + t[..., None] * d2)
    return np.sqrt(_dot(diff, diff))


def segment_box(p0: Array, p1: Array, T_world_box: Array, half: Array) -> Array:
    """Signed distance of a segment to a box with pose ``T_world_box`` (..., 4, 4) and half extents ``half`` (..., 3).

    Apart: the exact distance, from the squared distance ``f(t) = Σ max(|x_i(t)| - h_i, 0)²``
    along the segment, a convex piecewise quadratic minimised piece by piece. Overlapping: minus
    the penetration depth, the smallest overlap over the separating axes of a segment and a box
    (the 3 face normals and the 3 cross products of the segment with the box edges).
    """
    R = T_world_box[..., :3, :3]
    o = T_world_box[..., :3, 3]
    a = np.einsum("...ji,...j->...i", R, p0 - o)        # segment in the box frame: a + t b
    b = np.einsum("...ji,...j->...i", R, p1 - p0)
    h = np.broadcast_to(half, a.shape)
    # breakpoints where some |a_i + t b_i| = h_i, with 0 and 1
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        bs = np.where(np.abs(b) > 0, b, np.inf)
        cand = np.concatenate([(h - a) / bs, (-h - a) / bs], axis=-1)
    cand = np.where(np.isfinite(cand), np.clip(cand, 0.0, 1.0), 0.0)
    lead = a.shape[:-1]
    ts = np.sort(np.concatenate([np.zeros(lead + (1,)), np.ones(lead + (1,)), cand], axis=-1), axis=-1)  # (..., 8)
    lo, hi = ts[..., :-1], ts[..., 1:]
    mid = 0.5 * (lo + hi)
    A, B, H = a[..., None, :], b[..., None, :], h[..., None, :]
    xm = A + mid[..., None] * B
    # on each piece, coordinate i contributes (x_i - sign_i h_i)^2 if |x_i| > h_i at the midpoint
    act = np.abs(xm) > H
    sgn = np.sign(xm)
    u = np.where(act, A - sgn * H, 0.0)                  # (x_i - s h_i) = u_i + t b_i
    v = np.where(act, B, 0.0)
    qa = np.sum(v * v, axis=-1)
    qb = np.sum(u * v, axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        tstar = np.where(qa > 0, -qb / qa, mid)   # no coordinate outside at the midpoint: f(mid) = 0 exactly
    tstar = np.clip(tstar, lo, hi)
    x = A + tstar[..., None] * B
    excess = np.maximum(np.abs(x) - H, 0.0)
    f = np.min(np.sum(excess * excess, axis=-1), axis=-1)
    dist = np.sqrt(f)
    inside = f <= 0.0
    if not np.any(inside):
        return dist
    # penetration depth along the separating axes
    pe = np.stack([a, a + b], axis=-2)                   # (..., 2, 3) endpoints in the box frame
    axes = [np.broadcast_to(np.eye(3)[i], a.shape) for i in range(3)]
    for i in range(3):
        c = np.cross(b, np.eye(3)[i])
        nrm = np.linalg.norm(c, axis=-1, keepdims=True)
        axes.append(np.where(nrm > 1e-12 * (1.0 + np.linalg.norm(b, axis=-1, keepdims=True)),
                             c / np.where(nrm > 0, nrm, 1.0), np.nan))
    depth = np.full(lead, np.inf)
    for n in axes:
        proj = np.einsum("...ki,...i->...k", pe, n)
        rb = np.sum(np.abs(n) * h, axis=-1)
        ov = np.minimum(proj.max(axis=-1) + rb, rb - proj.min(axis=-1))
        depth = np.where(np.isnan(ov), depth, np.minimum(depth, ov))
    return np.where(inside, -depth, dist)


def _point_cylinder(x: Array, radius: Array | float, half: Array | float) -> Array:
    """Distance from points ``x`` (..., 3) in the cylinder's frame to a solid cylinder along z (0 inside)."""
    dr = np.maximum(np.hypot(x[..., 0], x[..., 1]) - radius, 0.0)
    dz = np.maximum(np.abs(x[..., 2]) - half, 0.0)
    return np.hypot(dr, dz)


def segment_cylinder(p0: Array, p1: Array, T_world_cyl: Array, radius: Array | float, half: Array | float,
                     iterations: int = 90) -> Array:
    """Distance of a segment to a solid cylinder (axis z of ``T_world_cyl``, half length ``half``); 0 where they meet.

    The distance from a point moving along the segment to a convex solid is a convex function
    of the segment parameter, so a golden-section search finds its minimum (``iterations``
    shrink the bracket by 0.618 each: 90 give 1e-19 of the segment). Where the result is 0 the
    two overlap and the caller needs the penetration depth from elsewhere (coal's EPA).
    """
    R = T_world_cyl[..., :3, :3]
    o = T_world_cyl[..., :3, 3]
    a = np.einsum("...ji,...j->...i", R, p0 - o)
    b = np.einsum("...ji,...j->...i", R, p1 - p0)

    def f(t: Array) -> Array:
        return _point_cylinder(a + t[..., None] * b, radius, half)

    lead = a.shape[:-1]
    g = 0.5 * (np.sqrt(5.0) - 1.0)
    lo, hi = np.zeros(lead), np.ones(lead)
    x1, x2 = hi - g * (hi - lo), lo + g * (hi - lo)
    f1, f2 = f(x1), f(x2)
    for _ in range(iterations):
        left = f1 <= f2          # the minimum lies in [lo, x2]: x1 becomes the new x2
        hi = np.where(left, x2, hi)
        lo = np.where(left, lo, x1)
        nx1 = np.where(left, hi - g * (hi - lo), x2)
        nx2 = np.where(left, x1, lo + g * (hi - lo))
        fn = f(np.where(left, nx1, nx2))
        f1, f2 = np.where(left, fn, f2), np.where(left, f1, fn)
        x1, x2 = nx1, nx2
    return np.minimum(np.minimum(f1, f2), np.minimum(f(np.zeros(lead)), f(np.ones(lead))))


def segment_cylinder_signed(p0: Array, p1: Array, T_world_cyl: Array, radius: float, half: float) -> Array:
    """Signed distance of segments ``(..., 3)`` to a solid cylinder: :func:`segment_cylinder` where they are apart,
    minus :func:`capsule_cylinder_depth` (one configuration at a time) where they overlap."""
    shape = np.broadcast_shapes(np.shape(p0)[:-1], np.shape(p1)[:-1], np.shape(T_world_cyl)[:-2])
    P0 = np.broadcast_to(p0, shape + (3,)).reshape(-1, 3)
    P1 = np.broadcast_to(p1, shape + (3,)).reshape(-1, 3)
    TT = np.broadcast_to(T_world_cyl, shape + (4, 4)).reshape(-1, 4, 4)
    flat = np.array(segment_cylinder(P0, P1, TT, radius, half), dtype=float).reshape(-1)
    for k in np.flatnonzero(flat <= 0.0):   # overlapping: the depth by support functions
        R, o = TT[k, :3, :3], TT[k, :3, 3]
        flat[k] = -capsule_cylinder_depth(R.T @ (P0[k] - o), R.T @ (P1[k] - o), 0.0, radius, half)
    return flat.reshape(shape)


def _circle_min(g, u: Array, v: Array, samples: int = 2048, iterations: int = 100) -> float:
    """Minimum of ``g(n)`` over the unit circle ``n = u cos t + v sin t``: dense samples, then golden section."""
    t = np.linspace(0.0, 2.0 * math.pi, samples, endpoint=False)
    vals = g(np.cos(t)[:, None] * u + np.sin(t)[:, None] * v)
    k = int(np.argmin(vals))
    step = 2.0 * math.pi / samples
    lo, hi = t[k] - step, t[k] + step
    gr = 0.5 * (math.sqrt(5.0) - 1.0)

    def at(x: float) -> float:
        return float(g((math.cos(x) * u + math.sin(x) * v)[None])[0])

    x1, x2 = hi - gr * (hi - lo), lo + gr * (hi - lo)
    f1, f2 = at(x1), at(x2)
    for _ in range(iterations):
        if f1 <= f2:
            hi, x2, f2 = x2, x1, f1
            x1 = hi - gr * (hi - lo)
            f1 = at(x1)
        else:
            lo, x1, f1 = x1, x2, f2
            x2 = lo + gr * (hi - lo)
            f2 = at(x2)
    return min(float(vals[k]), f1, f2)


def capsule_cylinder_depth(a: Array, b: Array, r: float, radius: float, half: float) -> float:
    r"""Penetration depth of the capsule ``a -> b`` (radius ``r``, in the cylinder's frame) into a solid cylinder.

    The shortest separating translation of two convex solids is along the direction ``n``
    minimising :math:`g(n) = h_C(n) + \max(n \cdot a, n \cdot b) + r` over the unit sphere, with
    :math:`h_C(n) = R |n_{xy}| + h |n_z|` the cylinder's support function. Inside a region where
    ``g`` is smooth it is the support function of the cylinder seen from one end point, whose
    only minima are the side and cap normals; so the minimum lies on one of the sets where ``g``
    is not smooth: the poles ``n = ±z``, the equator ``n_z = 0``, or the great circle
    ``n ⟂ b - a`` where the two end points tie. Each circle is searched densely, then by golden
    section (about 1e-15 of the answer).
    """
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)

    def g(n: Array) -> Array:
        hc = radius * np.hypot(n[..., 0], n[..., 1]) + half * np.abs(n[..., 2])
        return hc + np.maximum(n @ a, n @ b) + r

    ez = np.array([0.0, 0.0, 1.0])
    best = float(min(g(ez[None])[0], g(-ez[None])[0]))
    best = min(best, _circle_min(g, np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])))
    d = b - a
    dn = float(np.linalg.norm(d))
    if dn > 0:
        w = d / dn
        u = np.cross(w, np.eye(3)[int(np.argmin(np.abs(w)))])
        u /= np.linalg.norm(u)
        best = min(best, _circle_min(g, u, np.cross(w, u)))
    return best
