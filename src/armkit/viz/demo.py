"""The pictures ``make demo`` writes for the fighter arm (and planar2's contour maps)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from ..ik import ik_all
from ..model import load

__all__ = ["write_demo_pictures"]


def write_demo_pictures(out_dir: str | Path = "out", progress: bool = False,
                        report: list[str] | None = None) -> list[Path]:
    """Write the demo pictures into ``out_dir`` and return their paths.

    - ``fighter_arm.png``: the arm at (30°, 45°, 60°) with its frames
    - ``fighter_ik_branches.png``: every collision-free closed-form IK branch for the target (100, 50, 80) mm
    - ``fighter_workspace.png``: reach cloud, sections, boundaries, volume with its error
    - ``fighter_track.gif``: the arm following a circle with the closed form (60 frames)
    - ``planar2_maps.png``: the symbolic 2-link tutorial's FK and IK contour maps

    The fighter's pictures honour its own surroundings (its torso and the ground; the one
    collision rule of :func:`armkit.collision.resolve_scene`), as ``armkit ik``, ``armkit
    workspace`` and ``armkit track`` do: the workspace is the same sampling as ``armkit
    workspace fighter`` (200,000 samples, seed 0), so its volume is the same number. Lines
    saying so (volume, collisions, what was checked) are appended to ``report`` when given.

    Takes a few seconds (well under 20 s on a laptop).
    """
    from ..analysis.maps import fk_maps, ik_maps
    from ..analysis.workspace import workspace
    from .animation import render_animation
    from .arm import plot_arm
    from .plots import plot_maps, plot_workspace, save_figure
    from .tracking import track

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    arm = load("fighter")
    paths = [save_figure(plot_arm(arm, np.radians([30.0, 45.0, 60.0])), out / "fighter_arm.png")]

    target = np.array([100.0, 50.0, 80.0])
    res = ik_all(arm, target)                  # scene=None: the robot's own surroundings (torso, ground)
    ok = np.asarray(res.success)
    checked = ", ".join(res.checked_against)
    from ._mpl import angle_text

    labels = [f"{b}: {angle_text(arm, q, names=False)}" for b, q in zip(np.asarray(res.branch)[ok], np.asarray(res.q)[ok])]
    fig = plot_arm(arm, np.asarray(res.q)[ok], labels=labels, targets=target,
                   title=f"fighter: {int(ok.sum())} collision-free IK branches for the target (100, 50, 80) mm "
                         f"(checked against: {checked})")
    paths.append(save_figure(fig, out / "fighter_ik_branches.png"))

    ws = workspace(arm, samples=200_000, seed=0, manipulability=True)   # = `armkit workspace fighter`
    paths.append(save_figure(plot_workspace(ws), out / "fighter_workspace.png"))

    tr = track(arm, path="circle", method="analytic", frames=60)    # branches that do not collide
    if report is not None:
        from ..analysis.workspace import format_measure

        report.append(f"IK branches for (100, 50, 80) mm: {int(ok.sum())} of {ok.size} collision-free "
                      f"(checked against: {checked})")
        report.append(f"workspace: {ws.measure_name} {format_measure(ws.volume, ws.volume_error)} "
                      f"{ws.measure_unit} from {ws.samples:,} samples, as `armkit workspace fighter` "
                      f"(checked against: {', '.join(ws.checked_against)})")
        hits = 0 if tr.colliding is None else int(tr.colliding.sum())
        report.append(f"tracking GIF: {hits} of {len(tr.q)} frames in collision "
                      f"(checked against: {', '.join(tr.checked_against)})")
    paths.append(render_animation(arm, tr.q, out / "fighter_track.gif", targets=tr.targets, fps=15,
                                  title="fighter follows a circle (closed-form IK, nearest branch)",
                                  progress=progress))

    p2 = load("planar2")
    fm = fk_maps(p2, np.radians(np.linspace(0, 90, 91)), np.radians(np.linspace(-180, 180, 181)))
    im = ik_maps(p2, np.arange(0.0, 1.5001, 0.01), np.arange(0.0, 1.5001, 0.01))
    paths.append(save_figure(plot_maps(fm, im), out / "planar2_maps.png"))
    return paths
