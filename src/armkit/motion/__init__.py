"""Motion: velocity kinematics (twists, pseudo-inverse and damped least squares, resolved rate) and trajectories.

NumPy only. The plots of a trajectory live with the other plots: :func:`armkit.viz.plot_trajectory`
and :func:`armkit.viz.animate_trajectory` (:mod:`armkit.viz.trajectory`).
"""

from __future__ import annotations

from .._text import Fielded
from .trajectory import (PROFILES, Trajectory, blended_polyline, cartesian_arc, cartesian_line, cartesian_path,
                         cartesian_waypoints, joint_trajectory, profile, segment_duration)
from .velocity import JointRates, damping_schedule, joint_rates, resolved_rate, twist, velocity_rows

__all__ = ["Trajectory", "PROFILES", "profile", "segment_duration", "joint_trajectory", "cartesian_path",
           "cartesian_line", "cartesian_arc", "cartesian_waypoints", "blended_polyline", "JointRates", "twist",
           "joint_rates", "damping_schedule", "resolved_rate", "velocity_rows"]


_MOVED = {"plot_trajectory": "armkit.viz.plot_trajectory", "animate_trajectory": "armkit.viz.animate_trajectory"}


def __getattr__(name: str) -> object:
    """The plots moved to :mod:`armkit.viz` (issue 21): say where, without importing the floor above."""
    if name in _MOVED:
        raise AttributeError(Fielded.of("armkit.motion.{name} moved to {place} (armkit.viz.trajectory)", name=name,
                                        place=_MOVED[name]))
    raise AttributeError(Fielded.of("module {module!r} has no attribute {name!r}", module=__name__, name=name))
