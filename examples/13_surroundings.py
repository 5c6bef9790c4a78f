"""The arm's surroundings (issue 13): the fighter arm with its torso and the ground, in 60 lines.

Run: python examples/13_surroundings.py [OUT_DIR]   (pictures go to OUT_DIR, default docs/img)
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import armkit


def draw(ax, robot, q, scene, title):
    """The arm's capsules (red where they collide), the torso box and the ground."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    res = armkit.collisions(robot, q, scene)
    hit = {a for a, b, _ in res.colliding_pairs()} | {b for a, b, _ in res.colliding_pairs()}
    F = armkit.fk_frames(robot, q)[:, :3, 3]
    for k, name in enumerate(robot.link_names[1:]):
        ax.plot(*F[k:k + 2].T, lw=9, solid_capstyle="round", color="tab:red" if name in hit else "tab:blue")
    for s in list(robot.collision.body) + [s for s in scene if s.kind == "box"]:
        c, h = s.center, 0.5 * np.array(s.size)
        x = [[c[0] - h[0], c[0] + h[0]][i] for i in (0, 1, 1, 0)]
        y = [[c[1] - h[1], c[1] + h[1]][i] for i in (0, 0, 1, 1)]
        faces = [[(x[i], y[i], c[2] + z * h[2]) for i in range(4)] for z in (-1, 1)]
        ax.add_collection3d(Poly3DCollection(faces, alpha=0.35, color="tab:red" if s.name in hit else "grey"))
    g = [s for s in scene if s.kind == "plane"]
    if g:
        X, Y = np.meshgrid([-200, 200], [-200, 200])
        ax.plot_surface(X, Y, np.full_like(X, g[0].offset, dtype=float), alpha=0.15,
                        color="tab:red" if "ground" in hit else "tab:green")
    ax.set(xlim=(-200, 200), ylim=(-200, 200), zlim=(-60, 220), xlabel="x (mm)", ylabel="y (mm)", zlabel="z (mm)")
    ax.set_title(title + ("\n" + res.message().replace(" (", "\n(") if res.colliding else "\ncollision-free"), fontsize=8)


def main(out_dir: str = "docs/img") -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    arm = armkit.load("fighter")                          # the robot file ships link_radius, [[body]], [[scene]]
    scene = armkit.collision.robot_scene(arm)             # its ground (the torso is part of the arm's body)
    every = armkit.ik_all(arm, [100, 0, 60], scene=scene)
    print(every.branch, every.success, every.reason, every.message, sep="\n")
    print(armkit.ik(arm, [100, 0, -30], scene=scene).message)      # under the floor: reason "collision"
    fig = plt.figure(figsize=(15, 4.8))
    for k in range(4):
        ax = fig.add_subplot(1, 4, k + 1, projection="3d")
        draw(ax, arm, every.q[k], scene, f"{every.branch[k]}: {'solved' if every.success[k] else every.reason[k]}")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(out / "scene_fighter_branches.png", dpi=90)
    table = armkit.Scene([armkit.Scene.box([120, 0, 40], [60, 200, 20], name="table")]) + scene
    fig = plt.figure(figsize=(9, 4.5))
    for k, q in enumerate([np.radians([0, 70, -40]), np.radians([0, 60, -100])]):
        ax = fig.add_subplot(1, 2, k + 1, projection="3d")
        draw(ax, arm, q, table, f"q = {np.round(np.degrees(q)).astype(int).tolist()} deg")
    fig.tight_layout()
    fig.savefig(out / "scene_fighter_table.png", dpi=90)
    print("wrote", out / "scene_fighter_branches.png", out / "scene_fighter_table.png")


if __name__ == "__main__":
    main(*sys.argv[1:2])
