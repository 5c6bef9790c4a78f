"""Reachability maps: where an arm reaches, in which orientations, and where its base should go.

>>> import armkit, numpy as np
>>> m = armkit.reachability("planar2", resolution=0.05, samples=200_000)
>>> m.grid.symmetric, m.grid.position_only             # first joint turns freely; 2 joints: positions
(True, True)
>>> float(m.index([[1.0, 0.0, 0.0], [0.2, 0.0, 0.0]])[0]), float(m.index([0.2, 0.0, 0.0]))
(1.0, 0.0)

Dask and Zarr are imported only when a map is built, stored or opened.
See docs/reachability.md.
"""

from __future__ import annotations

from ._base import BasePlacement, base_placement
from ._build import ReachabilityError, reachability
from ._grid import Grid
from ._map import MapFileError, ReachabilityMap
from ._scene import SceneNotSupportedError

__all__ = ["reachability", "ReachabilityMap", "base_placement", "BasePlacement", "Grid",
           "ReachabilityError", "MapFileError", "SceneNotSupportedError"]
