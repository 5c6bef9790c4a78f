"""Motion: velocity kinematics (twists, pseudo-inverse and damped least squares, resolved rate) and trajectories.

NumPy only at import; Matplotlib and the animation renderer are loaded inside the plotting functions.
"""

from __future__ import annotations

from .trajectory import (PROFILES, Trajectory, animate_trajectory, blended_polyline, cartesian_arc, cartesian_line,
                         cartesian_path, cartesian_waypoints, joint_trajectory, plot_trajectory, profile,
                         segment_duration)
from .velocity import JointRates, damping_schedule, joint_rates, resolved_rate, task_rows, twist

__all__ = ["Trajectory", "PROFILES", "profile", "segment_duration", "joint_trajectory", "cartesian_path",
           "cartesian_line", "cartesian_arc", "cartesian_waypoints", "blended_polyline", "plot_trajectory",
           "animate_trajectory", "JointRates", "twist", "joint_rates", "damping_schedule", "resolved_rate", "task_rows"]
