"""Signed distances through coal (Pinocchio's collision library), one configuration at a time.

Used for the pairs the NumPy kernels do not cover (cylinders, meshes, boxes on the arm against
boxes) and as the reference in the tests. Imported only when such a pair is checked.
"""

from __future__ import annotations

import os
from types import SimpleNamespace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._extras import require
from .shapes import SceneError, kind_of

__all__ = ["distances", "geometry", "mesh_hull", "signed_distance", "mesh_error"]

Array = NDArray[np.float64]
_MESHES: dict[tuple[str, int, tuple[float, ...]], Any] = {}
"""Convex hulls of mesh files, shared by every scene and robot that uses the file: keyed by the file's path,
its modification time (an edited file is read again) and the scale. Module-level on purpose: a hull
belongs to a file, not to one Robot (so not in ``Robot.cache``)."""


def _coal() -> Any:
    return require("coal", "collision checking of this pair (a cylinder or a mesh)")


def geometry(kind: str, size: Any, shape: Any = None) -> Any:
    """A coal geometry for a shape kind in its own frame (a plane: the half-space z <= 0); the kind's ``coal``
    entry in :data:`armkit.collision.shapes.KIND_TABLE`."""
    row = kind_of(kind)
    if shape is None or shape.kind != kind:
        shape = SimpleNamespace(kind=kind, size=tuple(size), mesh_path=getattr(shape, "mesh_path", None),
                                scale=getattr(shape, "scale", (1.0, 1.0, 1.0)))
    return row.coal(_coal(), shape)


def mesh_hull(coal: Any, shape: Any) -> Any:
    """The convex hull of a mesh shape's file (``shape.mesh_path`` at ``shape.scale``), read once per file version."""
    try:
        stamp = os.stat(shape.mesh_path).st_mtime_ns
    except OSError:
        stamp = -1    # unreadable: the loader below says why
    key = (shape.mesh_path, stamp, tuple(shape.scale))
    if key not in _MESHES:
        from .._limits import check_mesh_file

        check_mesh_file(shape.mesh_path)     # LimitError naming the file, before coal reads it (issue 24)
        try:
            model = coal.MeshLoader().load(shape.mesh_path, np.array(shape.scale, dtype=float))
            model.buildConvexHull(True, "Qt")
            _MESHES[key] = model.convex
        except Exception:  # noqa: BLE001 - coal raises plain RuntimeErrors whose text is C++ internals
            raise SceneError(mesh_error(shape.mesh_path)) from None
    return _MESHES[key]


def mesh_error(path: Any) -> str:
    """The message for a mesh file that cannot be read: the file and what it should be, no library internals."""
    shown = str(path)
    shown = shown if len(shown) <= 300 else shown[:297] + "..."
    return (f"cannot read mesh {shown!r}: it is not a valid STL, OBJ or DAE file with at least one triangle "
            "(or it cannot be opened)")


def _transform(T: Array) -> Any:
    coal = _coal()
    return coal.Transform3s(np.ascontiguousarray(T[:3, :3]), np.ascontiguousarray(T[:3, 3]))


def _segment_pose(p0: Array, p1: Array) -> tuple[Array, float]:
    d = p1 - p0
    length = float(np.linalg.norm(d))
    T = np.eye(4)
    T[:3, 3] = 0.5 * (p0 + p1)
    if length > 0:
        z = d / length
        helper = np.eye(3)[int(np.argmin(np.abs(z)))]
        x = np.cross(helper, z)
        x /= np.linalg.norm(x)
        T[:3, :3] = np.column_stack([x, np.cross(z, x), z])
    return T, length


def signed_distance(geom_a: Any, T_a: Array, geom_b: Any, T_b: Array) -> float:
    """coal's signed distance (negative: penetration depth) between two placed geometries."""
    coal = _coal()
    req = coal.DistanceRequest()
    req.enable_signed_distance = True
    req.gjk_tolerance = req.epa_tolerance = 1e-9   # tighter than the default 1e-6 (1e-12 makes EPA fail on some boxes)
    req.gjk_max_iterations = req.epa_max_iterations = 1000
    ta, tb = _transform(T_a), _transform(T_b)
    d = float(coal.distance(geom_a, ta, geom_b, tb, req, coal.DistanceResult()))
    if d > 0:   # apart: GJK alone, run again to 1e-12
        req.gjk_tolerance = 1e-12
        d = float(coal.distance(geom_a, ta, geom_b, tb, req, coal.DistanceResult()))
    return d


def _placed(item: tuple[str, Any], row: int) -> tuple[Any, Array]:
    tag, data = item
    if tag == "seg":
        p0, p1, r = data
        p0 = p0 if p0.ndim == 1 else p0[row]
        p1 = p1 if p1.ndim == 1 else p1[row]
        T, length = _segment_pose(p0, p1)
        return _coal().Capsule(r, length), T
    kind, T, size, shape = data
    return geometry(kind, size, shape), (T if T.ndim == 2 else T[row])


def distances(a: tuple[str, Any], b: tuple[str, Any], batch: int) -> Array:
    """Signed distances of two world solids (see ``query._world``) for each of ``batch`` rows."""
    out = np.empty(batch)
    for k in range(batch):
        ga, Ta = _placed(a, k)
        gb, Tb = _placed(b, k)
        out[k] = signed_distance(ga, Ta, gb, Tb)
    return out
