"""Analysis on top of the kinematics: sampled workspaces, FK/IK contour maps.

Singularity analysis lives in :mod:`armkit.analysis.singularity` (imported on its own).
"""

from .maps import FKMaps, IKMaps, fk_maps, ik_maps
from .workspace import Exclusion, WorkspaceResult, is_planar, joint_axes, shoulder_point, workspace

__all__ = ["workspace", "WorkspaceResult", "Exclusion", "is_planar", "joint_axes", "shoulder_point",
           "fk_maps", "ik_maps", "FKMaps", "IKMaps"]
