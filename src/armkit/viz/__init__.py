"""Plots and animations (matplotlib, imported only when a function runs).

- :func:`plot_arm` — the arm at one or several configurations (2D for planar arms, 3D otherwise)
- :func:`plot_workspace` — reach cloud, sections and boundaries of :func:`armkit.analysis.workspace`
- :func:`plot_maps` — FK/IK contour maps of :mod:`armkit.analysis.maps`
- :func:`track` and :func:`render_animation` — an arm following a moving target, as GIF or MP4
- :func:`plot_trajectory` and :func:`animate_trajectory` — a :class:`armkit.motion.Trajectory` as q(t), qd(t)
  and the tool path, or as GIF/MP4
- :func:`write_demo_pictures` — the pictures ``make demo`` writes
"""

from __future__ import annotations

from typing import Any

from .._text import Fielded

__all__ = ["plot_arm", "plot_workspace", "plot_maps", "track", "TrackResult", "render_animation",
           "write_demo_pictures", "save_figure", "plot_trajectory", "animate_trajectory"]

_WHERE = {"plot_arm": "arm", "plot_workspace": "plots", "plot_maps": "plots", "save_figure": "plots",
          "track": "tracking", "TrackResult": "tracking", "render_animation": "animation",
          "write_demo_pictures": "demo", "plot_trajectory": "trajectory", "animate_trajectory": "trajectory"}


def __getattr__(name: str) -> Any:
    """Lazy attributes: ``armkit.viz.plot_arm`` imports :mod:`armkit.viz.arm` on first use."""
    if name in _WHERE:
        import importlib

        value = getattr(importlib.import_module(f"armkit.viz.{_WHERE[name]}"), name)
        globals()[name] = value
        return value
    raise AttributeError(Fielded.of("module {module!r} has no attribute {name!r}", module=__name__, name=name))
