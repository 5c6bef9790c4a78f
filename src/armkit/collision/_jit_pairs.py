"""Numba kernels of the signed distance of one pair of solids, for :mod:`armkit.collision._jit`.

Segments against segments, boxes and half-spaces in closed form; cylinders (exact against a
segment and a half-space) and every other pair of convex solids by the support-function search
(:func:`_convex`: GJK-style simplex steps, then a climb of the separating direction). The item kinds
and the packed arguments are described in :mod:`armkit.collision._jit`, which places the solids of
a configuration and picks a kernel per pair (:func:`armkit.collision._jit._pair`).
"""

from __future__ import annotations

import math

import numpy as np

from .. import _jit_loader

_jit_loader.install_cache_fallback()  # before the first cache=True: read-only installs cache elsewhere

from numba import njit  # noqa: E402

SEGF, SEGL, BOX, PLANE, CYL = 0, 1, 2, 3, 4
"""The item kinds (the ``kernel`` codes of :data:`armkit.collision.kinds.KINDS`)."""



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


# ------------------------------------------------------------------ cylinders and solid-solid pairs
GOLDEN = 0.5 * (math.sqrt(5.0) - 1.0)
CIRCLE_SAMPLES = 256
SPHERE_SAMPLES = 256
STARTS = 4


@njit(cache=True, inline="always")
def _local(T, x, y, z):
    """The point (x, y, z) in the frame of pose T (3x4 used)."""
    dx = x - T[0, 3]
    dy = y - T[1, 3]
    dz = z - T[2, 3]
    return (T[0, 0] * dx + T[1, 0] * dy + T[2, 0] * dz, T[0, 1] * dx + T[1, 1] * dy + T[2, 1] * dz,
            T[0, 2] * dx + T[1, 2] * dy + T[2, 2] * dz)


@njit(cache=True, inline="always")
def _point_cyl(x, y, z, rc, h):
    """Distance from a point (cylinder frame) to the solid cylinder of radius rc, half length h along z; 0 inside."""
    dr = math.sqrt(x * x + y * y) - rc
    dz = abs(z) - h
    if dr < 0.0:
        dr = 0.0
    if dz < 0.0:
        dz = 0.0
    return math.sqrt(dr * dr + dz * dz)


@njit(cache=True)
def _seg_cyl(p, q, T, rc, h, exact=True):
    """Signed distance of segment p->q to the solid cylinder (pose T, radius rc, half length h along its z).

    Apart: the distance from a point moving along the segment to a convex solid is a convex function
    of the segment parameter, minimised by golden section to 1e-13 of the segment. Overlapping: minus
    the exact penetration depth (:func:`_seg_cyl_depth`); with ``exact=False`` (a yes/no check) -0.0 instead
    (the caller's capsule radius makes it negative).
    """
    a0, a1, a2 = _local(T, p[0], p[1], p[2])
    e0, e1, e2 = _local(T, q[0], q[1], q[2])
    b0, b1, b2 = e0 - a0, e1 - a1, e2 - a2
    blen = math.sqrt(b0 * b0 + b1 * b1 + b2 * b2)
    best = min(_point_cyl(a0, a1, a2, rc, h), _point_cyl(e0, e1, e2, rc, h))
    if best > 0.0 and blen > 0.0:
        lo = 0.0
        hi = 1.0
        x1 = hi - GOLDEN * (hi - lo)
        x2 = lo + GOLDEN * (hi - lo)
        f1 = _point_cyl(a0 + x1 * b0, a1 + x1 * b1, a2 + x1 * b2, rc, h)
        f2 = _point_cyl(a0 + x2 * b0, a1 + x2 * b1, a2 + x2 * b2, rc, h)
        tol = 1e-13 * (1.0 + (blen + rc + h) / blen)
        for _ in range(80):
            if f1 == 0.0 or f2 == 0.0 or hi - lo < tol:
                break
            if f1 <= f2:
                hi = x2
                x2 = x1
                f2 = f1
                x1 = hi - GOLDEN * (hi - lo)
                f1 = _point_cyl(a0 + x1 * b0, a1 + x1 * b1, a2 + x1 * b2, rc, h)
            else:
                lo = x1
                x1 = x2
                f1 = f2
                x2 = lo + GOLDEN * (hi - lo)
                f2 = _point_cyl(a0 + x2 * b0, a1 + x2 * b1, a2 + x2 * b2, rc, h)
        best = min(best, f1, f2)
    if best > 0.0:
        return best
    if not exact:
        return -0.0
    return -_seg_cyl_depth(a0, a1, a2, e0, e1, e2, rc, h)


@njit(cache=True, inline="always")
def _cyl_g(n0, n1, n2, a0, a1, a2, rc, h):
    return rc * math.sqrt(n0 * n0 + n1 * n1) + h * abs(n2) + n0 * a0 + n1 * a1 + n2 * a2


@njit(cache=True)
def _seg_cyl_depth(a0, a1, a2, b0, b1, b2, rc, h):
    r"""Penetration depth of the segment a -> b (cylinder frame) into the cylinder (radius rc, half length h).

    The depth is the minimum over unit ``n`` of :math:`g(n) = R |n_{xy}| + h |n_z| + \max(n \cdot a, n \cdot b)`
    (the cylinder's support function plus the segment's). Where ``g`` is smooth it is the support
    function of the cylinder moved to one end point, which has no local minimum on the sphere away from
    the face normals; so the minimum lies on the poles ``±z`` (caps), the equator (side: there
    ``g = R - `` the distance from the axis to the segment's projection, in closed form) or the great
    circle ``n ⟂ b - a`` where the end points tie (sampled every 1.4 degrees, then golden section).
    """
    best = min(h + max(a2, b2), h + max(-a2, -b2))
    dx = b0 - a0
    dy = b1 - a1
    dd = dx * dx + dy * dy
    t = 0.0
    if dd > 0.0:
        t = min(max(-(a0 * dx + a1 * dy) / dd, 0.0), 1.0)
    cx = a0 + t * dx
    cy = a1 + t * dy
    best = min(best, rc - math.sqrt(cx * cx + cy * cy))
    w0, w1, w2 = b0 - a0, b1 - a1, b2 - a2
    wn = math.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
    if wn > 0.0:
        w0 /= wn
        w1 /= wn
        w2 /= wn
        # u: w crossed with the axis least aligned with w; v = w x u
        if abs(w0) <= abs(w1) and abs(w0) <= abs(w2):
            u0, u1, u2 = 0.0, w2, -w1
        elif abs(w1) <= abs(w2):
            u0, u1, u2 = -w2, 0.0, w0
        else:
            u0, u1, u2 = w1, -w0, 0.0
        un = math.sqrt(u0 * u0 + u1 * u1 + u2 * u2)
        u0 /= un
        u1 /= un
        u2 /= un
        v0 = w1 * u2 - w2 * u1
        v1 = w2 * u0 - w0 * u2
        v2 = w0 * u1 - w1 * u0
        step = 2.0 * math.pi / CIRCLE_SAMPLES
        kbest = 0
        gbest = np.inf
        cs = math.cos(step)
        sn = math.sin(step)
        c = 1.0
        s = 0.0
        for k in range(CIRCLE_SAMPLES):   # (c, s) turned by one step each time: no trigonometry in the loop
            g = _cyl_g(c * u0 + s * v0, c * u1 + s * v1, c * u2 + s * v2, a0, a1, a2, rc, h)
            if g < gbest:
                gbest = g
                kbest = k
            c, s = c * cs - s * sn, s * cs + c * sn
        lo = (kbest - 1) * step
        hi = (kbest + 1) * step
        x1 = hi - GOLDEN * (hi - lo)
        x2 = lo + GOLDEN * (hi - lo)
        c, s = math.cos(x1), math.sin(x1)
        f1 = _cyl_g(c * u0 + s * v0, c * u1 + s * v1, c * u2 + s * v2, a0, a1, a2, rc, h)
        c, s = math.cos(x2), math.sin(x2)
        f2 = _cyl_g(c * u0 + s * v0, c * u1 + s * v1, c * u2 + s * v2, a0, a1, a2, rc, h)
        for _ in range(60):
            if f1 <= f2:
                hi = x2
                x2 = x1
                f2 = f1
                x1 = hi - GOLDEN * (hi - lo)
                c, s = math.cos(x1), math.sin(x1)
                f1 = _cyl_g(c * u0 + s * v0, c * u1 + s * v1, c * u2 + s * v2, a0, a1, a2, rc, h)
            else:
                lo = x1
                x1 = x2
                f1 = f2
                x2 = lo + GOLDEN * (hi - lo)
                c, s = math.cos(x2), math.sin(x2)
                f2 = _cyl_g(c * u0 + s * v0, c * u1 + s * v1, c * u2 + s * v2, a0, a1, a2, rc, h)
        best = min(best, gbest, f1, f2)
    return best


@njit(cache=True)
def _cyl_plane(W, i, j, half):
    """Signed distance of cylinder item i to the half-space item j: its lowest point along the normal, exact."""
    n0, n1, n2 = W[j, 0, 2], W[j, 1, 2], W[j, 2, 2]
    off = n0 * W[j, 0, 3] + n1 * W[j, 1, 3] + n2 * W[j, 2, 3]
    c = n0 * W[i, 0, 3] + n1 * W[i, 1, 3] + n2 * W[i, 2, 3]
    nz = n0 * W[i, 0, 2] + n1 * W[i, 1, 2] + n2 * W[i, 2, 2]
    return c - half[i, 2] * abs(nz) - half[i, 0] * math.sqrt(max(1.0 - nz * nz, 0.0)) - off


@njit(cache=True)
def _support(k, i, n0, n1, n2, P0, P1, W, half):
    """The point of item i (its core: a segment without its radius, a box, a cylinder) farthest along n."""
    if k == SEGF or k == SEGL:
        if n0 * P0[i, 0] + n1 * P0[i, 1] + n2 * P0[i, 2] >= n0 * P1[i, 0] + n1 * P1[i, 1] + n2 * P1[i, 2]:
            return P0[i, 0], P0[i, 1], P0[i, 2]
        return P1[i, 0], P1[i, 1], P1[i, 2]
    x0, x1, x2 = W[i, 0, 3], W[i, 1, 3], W[i, 2, 3]
    if k == BOX:
        for c in range(3):
            s = half[i, c] if n0 * W[i, 0, c] + n1 * W[i, 1, c] + n2 * W[i, 2, c] >= 0.0 else -half[i, c]
            x0 += s * W[i, 0, c]
            x1 += s * W[i, 1, c]
            x2 += s * W[i, 2, c]
        return x0, x1, x2
    # cylinder: the cap on n's side, then the rim point towards n's part across the axis
    z0, z1, z2 = W[i, 0, 2], W[i, 1, 2], W[i, 2, 2]
    nz = n0 * z0 + n1 * z1 + n2 * z2
    s = half[i, 2] if nz >= 0.0 else -half[i, 2]
    p0, p1, p2 = n0 - nz * z0, n1 - nz * z1, n2 - nz * z2
    pz = p0 * z0 + p1 * z1 + p2 * z2     # again: n along the axis leaves rounding noise that must stay across it
    p0, p1, p2 = p0 - pz * z0, p1 - pz * z1, p2 - pz * z2
    pn = math.sqrt(p0 * p0 + p1 * p1 + p2 * p2)
    x0 += s * z0
    x1 += s * z1
    x2 += s * z2
    if pn > 1e-300:
        f = half[i, 0] / pn
        x0 += f * p0
        x1 += f * p1
        x2 += f * p2
    return x0, x1, x2


@njit(cache=True)
def _center(k, i, P0, P1, W):
    if k == SEGF or k == SEGL:
        return 0.5 * (P0[i, 0] + P1[i, 0]), 0.5 * (P0[i, 1] + P1[i, 1]), 0.5 * (P0[i, 2] + P1[i, 2])
    return W[i, 0, 3], W[i, 1, 3], W[i, 2, 3]


@njit(cache=True)
def _sep(ki, i, kj, j, u0, u1, u2, P0, P1, W, half):
    """``min over a in i, b in j of (a - b) · u`` for unit u: a lower bound of the signed distance of i and j (cores)."""
    a0, a1, a2 = _support(ki, i, -u0, -u1, -u2, P0, P1, W, half)
    b0, b1, b2 = _support(kj, j, u0, u1, u2, P0, P1, W, half)
    return (a0 - b0) * u0 + (a1 - b1) * u1 + (a2 - b2) * u2


@njit(cache=True)
def _closest_simplex(S, m):
    """Point of the convex hull of S[:m] (m <= 4 points) nearest the origin: (v0, v1, v2, mask of the face used).

    Every face (subset) whose affine nearest point has positive barycentric weights is a candidate;
    the hull's nearest point is the candidate nearest the origin (Johnson's rule, by enumeration).
    """
    best = np.inf
    bv0 = bv1 = bv2 = 0.0
    bmask = 1
    for mask in range(1, 1 << m):
        idx0 = idx1 = idx2 = idx3 = -1
        c = 0
        for k in range(m):
            if mask & (1 << k):
                if c == 0:
                    idx0 = k
                elif c == 1:
                    idx1 = k
                elif c == 2:
                    idx2 = k
                else:
                    idx3 = k
                c += 1
        x0, x1, x2 = S[idx0, 0], S[idx0, 1], S[idx0, 2]
        if c == 1:
            v0, v1, v2 = x0, x1, x2
        elif c == 2:
            d0, d1, d2 = S[idx1, 0] - x0, S[idx1, 1] - x1, S[idx1, 2] - x2
            dd = d0 * d0 + d1 * d1 + d2 * d2
            if dd <= 0.0:
                continue
            t = -(x0 * d0 + x1 * d1 + x2 * d2) / dd
            if not (t > 0.0 and t < 1.0):
                continue
            v0, v1, v2 = x0 + t * d0, x1 + t * d1, x2 + t * d2
        elif c == 3:
            d0, d1, d2 = S[idx1, 0] - x0, S[idx1, 1] - x1, S[idx1, 2] - x2
            e0, e1, e2 = S[idx2, 0] - x0, S[idx2, 1] - x1, S[idx2, 2] - x2
            a11 = d0 * d0 + d1 * d1 + d2 * d2
            a12 = d0 * e0 + d1 * e1 + d2 * e2
            a22 = e0 * e0 + e1 * e1 + e2 * e2
            r1 = -(x0 * d0 + x1 * d1 + x2 * d2)
            r2 = -(x0 * e0 + x1 * e1 + x2 * e2)
            det = a11 * a22 - a12 * a12
            if not det > 1e-14 * a11 * a22:
                continue
            s = (r1 * a22 - r2 * a12) / det
            t = (a11 * r2 - a12 * r1) / det
            if not (s > 0.0 and t > 0.0 and s + t < 1.0):
                continue
            v0, v1, v2 = x0 + s * d0 + t * e0, x1 + s * d1 + t * e1, x2 + s * d2 + t * e2
        else:
            d0, d1, d2 = S[idx1, 0] - x0, S[idx1, 1] - x1, S[idx1, 2] - x2
            e0, e1, e2 = S[idx2, 0] - x0, S[idx2, 1] - x1, S[idx2, 2] - x2
            f0, f1, f2 = S[idx3, 0] - x0, S[idx3, 1] - x1, S[idx3, 2] - x2
            # origin = x + s d + t e + r f: solve by Cramer's rule
            det = d0 * (e1 * f2 - e2 * f1) - d1 * (e0 * f2 - e2 * f0) + d2 * (e0 * f1 - e1 * f0)
            vol = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2) * math.sqrt(e0 * e0 + e1 * e1 + e2 * e2) * \
                math.sqrt(f0 * f0 + f1 * f1 + f2 * f2)
            if not abs(det) > 1e-12 * vol:
                continue
            g0, g1, g2 = -x0, -x1, -x2
            s = (g0 * (e1 * f2 - e2 * f1) - g1 * (e0 * f2 - e2 * f0) + g2 * (e0 * f1 - e1 * f0)) / det
            t = (d0 * (g1 * f2 - g2 * f1) - d1 * (g0 * f2 - g2 * f0) + d2 * (g0 * f1 - g1 * f0)) / det
            r = (d0 * (e1 * g2 - e2 * g1) - d1 * (e0 * g2 - e2 * g0) + d2 * (e0 * g1 - e1 * g0)) / det
            if not (s > 0.0 and t > 0.0 and r > 0.0 and s + t + r < 1.0):
                continue
            v0 = v1 = v2 = 0.0
        nv = v0 * v0 + v1 * v1 + v2 * v2
        if nv < best:
            best = nv
            bv0, bv1, bv2 = v0, v1, v2
            bmask = mask
    return bv0, bv1, bv2, bmask


@njit(cache=True)
def _convex(ki, i, kj, j, P0, P1, W, half, S, exact=True):
    """Signed distance of two convex items' cores (segments, boxes, cylinders), a lower bound that is exact when apart.

    Every value returned is ``min over a in i, b in j of (a - b) · u`` for some unit ``u``, which is
    never larger than the signed distance: a colliding pair is never reported clear.

    * Apart: GJK (Gilbert, Johnson, Keerthi 1988) on the Minkowski difference, stopped when its
      lower bound is within 1e-12 (relative) of the upper: the distance, to that tolerance.
    * Overlapping: minus a penetration depth from the best of the separating axes of the two
      (face normals, axes, their cross products, the centres' offset and its parts across each
      axis), refined by a pattern search over directions. For two boxes these axes give the exact
      depth (the separating axis theorem); with a cylinder the value is a bound: never shallower
      than the true depth, usually equal.

    ``S`` is scratch (4, 3). With ``exact=False`` (a yes/no check) an overlap returns a negative number
    without the search for the depth.
    """
    # a starting direction: the centres' offset
    ca0, ca1, ca2 = _center(ki, i, P0, P1, W)
    cb0, cb1, cb2 = _center(kj, j, P0, P1, W)
    v0, v1, v2 = ca0 - cb0, ca1 - cb1, ca2 - cb2
    if v0 * v0 + v1 * v1 + v2 * v2 == 0.0:
        v0 = 1.0
    lb = -np.inf
    m = 0
    overlap = False
    for _ in range(96):
        vv = v0 * v0 + v1 * v1 + v2 * v2
        vn = math.sqrt(vv)
        if vn <= 1e-15 * (1.0 + abs(ca0) + abs(ca1) + abs(ca2)):
            overlap = True
            break
        a0, a1, a2 = _support(ki, i, -v0, -v1, -v2, P0, P1, W, half)
        b0, b1, b2 = _support(kj, j, v0, v1, v2, P0, P1, W, half)
        w0, w1, w2 = a0 - b0, a1 - b1, a2 - b2
        lb = max(lb, (v0 * w0 + v1 * w1 + v2 * w2) / vn)
        if vn - lb <= 1e-12 * vn:
            break
        dup = False
        for k in range(m):
            if S[k, 0] == w0 and S[k, 1] == w1 and S[k, 2] == w2:
                dup = True
        if dup:
            break
        S[m, 0], S[m, 1], S[m, 2] = w0, w1, w2
        m += 1
        v0, v1, v2, mask = _closest_simplex(S, m)
        if mask == (1 << m) - 1 and m == 4:
            overlap = True
            break
        k2 = 0
        for k in range(m):
            if mask & (1 << k):
                S[k2, 0], S[k2, 1], S[k2, 2] = S[k, 0], S[k, 1], S[k, 2]
                k2 += 1
        m = k2
    if not overlap:
        return lb
    if not exact:
        return min(lb, -1e-300)
    # overlapping: separating axes, a sphere of directions, then a pattern search from the best
    fb, nb0, nb1, nb2 = lb, 1.0, 0.0, 0.0
    fb, nb0, nb1, nb2 = _cand(fb, nb0, nb1, nb2, ki, i, kj, j, ca0 - cb0, ca1 - cb1, ca2 - cb2, P0, P1, W, half)
    for side in range(2):
        k = ki if side == 0 else kj
        it = i if side == 0 else j
        if k == SEGF or k == SEGL:
            continue
        for c in range(3):
            if k == CYL and c != 2:
                continue
            fb, nb0, nb1, nb2 = _cand(fb, nb0, nb1, nb2, ki, i, kj, j, W[it, 0, c], W[it, 1, c], W[it, 2, c],
                                      P0, P1, W, half)
        if k == CYL:   # the centres' offset across the axis
            z0, z1, z2 = W[it, 0, 2], W[it, 1, 2], W[it, 2, 2]
            o0, o1, o2 = ca0 - cb0, ca1 - cb1, ca2 - cb2
            oz = o0 * z0 + o1 * z1 + o2 * z2
            fb, nb0, nb1, nb2 = _cand(fb, nb0, nb1, nb2, ki, i, kj, j, o0 - oz * z0, o1 - oz * z1, o2 - oz * z2,
                                      P0, P1, W, half)
    for ca in range(3):
        if ki == SEGF or ki == SEGL:
            if ca > 0:
                break
            x0, x1, x2 = P1[i, 0] - P0[i, 0], P1[i, 1] - P0[i, 1], P1[i, 2] - P0[i, 2]
        else:
            if ki == CYL and ca != 2:
                continue
            x0, x1, x2 = W[i, 0, ca], W[i, 1, ca], W[i, 2, ca]
        for cb in range(3):
            if kj == SEGF or kj == SEGL:
                if cb > 0:
                    break
                y0, y1, y2 = P1[j, 0] - P0[j, 0], P1[j, 1] - P0[j, 1], P1[j, 2] - P0[j, 2]
            else:
                if kj == CYL and cb != 2:
                    continue
                y0, y1, y2 = W[j, 0, cb], W[j, 1, cb], W[j, 2, cb]
            fb, nb0, nb1, nb2 = _cand(fb, nb0, nb1, nb2, ki, i, kj, j, x1 * y2 - x2 * y1, x2 * y0 - x0 * y2,
                                      x0 * y1 - x1 * y0, P0, P1, W, half)
    if ki == BOX and kj == BOX:
        return fb     # the separating axis theorem: these axes give the exact depth of two boxes
    # a Fibonacci sphere of directions; the pattern search then climbs from the axes' best and the
    # sphere's best STARTS directions (the separation has ridges: one start can stop on a lower one)
    golden_angle = math.pi * (3.0 - math.sqrt(5.0))
    top = np.full(STARTS, -np.inf)
    dirs = np.zeros((STARTS + 1, 3))
    dirs[STARTS, 0], dirs[STARTS, 1], dirs[STARTS, 2] = nb0, nb1, nb2
    for k in range(SPHERE_SAMPLES):
        z = 1.0 - (2.0 * k + 1.0) / SPHERE_SAMPLES
        r = math.sqrt(max(1.0 - z * z, 0.0))
        x, y = r * math.cos(golden_angle * k), r * math.sin(golden_angle * k)
        f = _sep(ki, i, kj, j, x, y, z, P0, P1, W, half)
        m = 0
        for t in range(1, STARTS):
            if top[t] < top[m]:
                m = t
        if f > top[m]:
            top[m] = f
            dirs[m, 0], dirs[m, 1], dirs[m, 2] = x, y, z
    for st in range(STARTS + 1):
        if st < STARTS and top[st] == -np.inf:
            continue
        f = _climb(ki, i, kj, j, dirs[st, 0], dirs[st, 1], dirs[st, 2], P0, P1, W, half)
        if f > fb:
            fb = f
    return fb


@njit(cache=True)
def _climb(ki, i, kj, j, n0, n1, n2, P0, P1, W, half):
    """The separation of items i and j climbed from unit direction n by a pattern search on the sphere
    (8 moves: along two tangents and their diagonals; the step halves when none improves)."""
    fb = _sep(ki, i, kj, j, n0, n1, n2, P0, P1, W, half)
    step = 0.1
    for _ in range(400):
        if abs(n0) < 0.9:
            t0, t1, t2 = 0.0, n2, -n1
        else:
            t0, t1, t2 = -n2, 0.0, n0
        tn = math.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
        t0 /= tn
        t1 /= tn
        t2 /= tn
        s0 = n1 * t2 - n2 * t1
        s1 = n2 * t0 - n0 * t2
        s2 = n0 * t1 - n1 * t0
        c = math.cos(step)
        sn = math.sin(step)
        moved = False
        for d in range(8):
            a = d * (math.pi / 4.0)
            ca = math.cos(a) * sn
            sa = math.sin(a) * sn
            x = c * n0 + ca * t0 + sa * s0
            y = c * n1 + ca * t1 + sa * s1
            z = c * n2 + ca * t2 + sa * s2
            f = _sep(ki, i, kj, j, x, y, z, P0, P1, W, half)
            if f > fb:
                fb = f
                n0, n1, n2 = x, y, z
                moved = True
                break
        if not moved:
            step *= 0.5
            if step < 1e-9:
                break
    return fb


@njit(cache=True)
def _cand(fb, nb0, nb1, nb2, ki, i, kj, j, u0, u1, u2, P0, P1, W, half):
    """The best (separation, direction) so far, updated with ±u (u need not be unit; ~0 is skipped)."""
    un = math.sqrt(u0 * u0 + u1 * u1 + u2 * u2)
    if un < 1e-12:
        return fb, nb0, nb1, nb2
    u0 /= un
    u1 /= un
    u2 /= un
    f = _sep(ki, i, kj, j, u0, u1, u2, P0, P1, W, half)
    if f > fb:
        fb, nb0, nb1, nb2 = f, u0, u1, u2
    f = _sep(ki, i, kj, j, -u0, -u1, -u2, P0, P1, W, half)
    if f > fb:
        fb, nb0, nb1, nb2 = f, -u0, -u1, -u2
    return fb, nb0, nb1, nb2
