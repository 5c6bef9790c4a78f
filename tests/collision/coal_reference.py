"""Independent reference: signed distances computed with coal directly (not through armkit.collision)."""

from __future__ import annotations

import numpy as np
import pytest

coal = pytest.importorskip("coal")


def capsule_pose(p0, p1):
    d = np.asarray(p1, float) - np.asarray(p0, float)
    length = float(np.linalg.norm(d))
    R = np.eye(3)
    # below 1e-9 the axis is left alone: a subnormal length (1e-160, found by hypothesis) loses digits, so
    # d / length is no unit vector and coal gets a rotation that is not one (0.5 came back as 0.49999995)
    if length > 1e-9:
        z = d / length
        x = np.cross([0.0, 0.0, 1.0] if abs(z[2]) < 0.9 else [1.0, 0.0, 0.0], z)
        x /= np.linalg.norm(x)
        R = np.column_stack([x, np.cross(z, x), z])
    return coal.Transform3s(R, 0.5 * (np.asarray(p0, float) + np.asarray(p1, float))), length


def coal_shape(shape):
    """coal geometry and transform of an armkit Shape in the world."""
    T = shape.pose
    tf = coal.Transform3s(np.ascontiguousarray(T[:3, :3]), np.ascontiguousarray(T[:3, 3]))
    if shape.kind == "plane":
        return coal.Halfspace(np.asarray(shape.normal, float), shape.offset), coal.Transform3s()
    if shape.kind == "box":
        return coal.Box(*shape.size), tf
    if shape.kind == "sphere":
        return coal.Sphere(shape.size[0]), tf
    if shape.kind == "cylinder":
        return coal.Cylinder(*shape.size), tf
    if shape.kind == "capsule":
        return coal.Capsule(*shape.size), tf
    raise ValueError(shape.kind)


def coal_distance(g1, t1, g2, t2):
    req = coal.DistanceRequest()
    req.enable_signed_distance = True
    req.gjk_tolerance = req.epa_tolerance = 1e-9   # tighter than the default 1e-6; 1e-12 makes EPA fail on some boxes
    req.gjk_max_iterations = req.epa_max_iterations = 1000
    d = coal.distance(g1, t1, g2, t2, req, coal.DistanceResult())
    if d > 0:   # apart: GJK alone, run again to 1e-12 (on a cylinder's curved side it still stops ~1e-7 short;
        req.gjk_tolerance = 1e-12   # the Nesterov-accelerated variant is closer on most cases but wrong by
        d = coal.distance(g1, t1, g2, t2, req, coal.DistanceResult())   # 3-5 % of the reach on some)
    return d


def capsule_to(p0, p1, r, shape):
    tf, length = capsule_pose(p0, p1)
    g, t = coal_shape(shape)
    return coal_distance(coal.Capsule(r, length), tf, g, t)


def capsule_capsule(p0, p1, r1, q0, q1, r2):
    ta, la = capsule_pose(p0, p1)
    tb, lb = capsule_pose(q0, q1)
    return coal_distance(coal.Capsule(r1, la), ta, coal.Capsule(r2, lb), tb)
