"""Matplotlib set-up shared by the plots: lazy import, a headless fallback, the arm's geometry."""

from __future__ import annotations

import math
import os
import sys
from typing import Any

import numpy as np

from .._extras import require
from ..model.robot import Robot

__all__ = ["pyplot", "has_display", "angle_text", "COLORS", "AXIS_COLORS"]

COLORS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf")
AXIS_COLORS = ("#e41a1c", "#4daf4a", "#377eb8")  # x red, y green, z blue


def has_display() -> bool:
    """True when a window can be opened (Windows, macOS, or an X11/Wayland display)."""
    if sys.platform in ("win32", "darwin"):
        return True
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def pyplot() -> Any:
    """``matplotlib.pyplot``, imported on first use; Agg when there is no display and no MPLBACKEND."""
    matplotlib = require("matplotlib", "drawing pictures")

    if not has_display() and "MPLBACKEND" not in os.environ and "matplotlib.pyplot" not in sys.modules:
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def angle_text(robot: Robot, q: np.ndarray, deg: bool = True, names: bool = True, digits: int = 1) -> str:
    """``yaw = 30.0°, shoulder = 45.0°`` (revolute joints in degrees, prismatic in length units)."""
    parts = []
    for j, v in zip(robot.joints, q):
        if j.is_prismatic:
            s = f"{v:.{digits + 1}f} {robot.unit}"
        elif deg:
            s = f"{math.degrees(v):.{digits}f}°"
        else:
            s = f"{v:.3f} rad"
        parts.append(f"{j.name} = {s}" if names else s)
    return ", ".join(parts)
