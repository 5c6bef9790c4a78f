"""Reachability maps: hand-derived reference workspaces, symmetry, IK agreement, queries, errors."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

import armkit
from armkit.reach import Grid, MapFileError, ReachabilityError, ReachabilityMap, reachability
from armkit.reach._map import decide
from armkit.reach._symmetry import roll_symmetric, yaw_symmetric


def _poses_at(points: np.ndarray) -> np.ndarray:
    T = np.tile(np.eye(4), (len(points), 1, 1))
    T[:, :3, 3] = points
    return T


@pytest.fixture(scope="module")
def planar2_map() -> ReachabilityMap:
    return reachability("planar2", resolution=0.02, samples=400_000, workers=1)


@pytest.fixture(scope="module")
def ur5_map() -> ReachabilityMap:
    return reachability("ur5", resolution=0.1, orientations=32, samples=1_000_000, workers=1)


def test_planar_2r_annulus_by_hand(planar2_map: ReachabilityMap) -> None:
    # L1 = 1, L2 = 0.5: the tool reaches exactly the annulus |L1 - L2| <= r <= L1 + L2 in z = 0
    m = planar2_map
    assert m.grid.symmetric and m.grid.position_only
    rng = np.random.default_rng(1)
    r = rng.uniform(0.0, 2.0, 4000)
    th = rng.uniform(-math.pi, math.pi, 4000)
    pts = np.stack([r * np.cos(th), r * np.sin(th), np.zeros_like(r)], axis=1)
    said = m.reachable(_poses_at(pts))
    h = m.grid.resolution
    inside = (r > 0.5 + 1.5 * h) & (r < 1.5 - 1.5 * h)          # a voxel and a half away from either circle
    outside = (r < 0.5 - 1.5 * h) | (r > 1.5 + 1.5 * h)
    assert said[inside].all()
    assert not said[outside].any()
    # off the plane of motion: nothing
    assert not m.reachable(_poses_at(pts[inside] + [0.0, 0.0, 3 * h])).any()
    # the index of a position-only map is 1 where reachable
    assert np.array_equal(m.index(pts[inside]), np.ones(int(inside.sum()), dtype=np.float32))


def test_ik_per_cell_matches_the_annulus_at_cell_centres() -> None:
    m = reachability("planar2", resolution=0.05, method="ik", workers=1)
    C = m.voxel_centres()[:, 0, :, :]                       # (nx, nz, 3), y = 0
    r = np.hypot(C[..., 0], C[..., 1])
    expect = (np.abs(C[..., 2]) < 1e-12) & (r >= 0.5 - 1e-9) & (r <= 1.5 + 1e-9)
    assert np.array_equal(m.hits[:, 0, :, 0], expect)


def test_symmetries_are_detected_from_fk() -> None:
    assert yaw_symmetric(armkit.load("ur5")) and roll_symmetric(armkit.load("ur5"))
    # Panda's first and last joints stop at +-166 deg: neither symmetry is exact
    assert not yaw_symmetric(armkit.load("panda")) and not roll_symmetric(armkit.load("panda"))
    assert yaw_symmetric(armkit.load("fighter"))
    g = reachability("panda", resolution=0.4, orientations=8, samples=20_000, workers=1).grid
    assert not g.symmetric and g.rolls == 8 and g.dims[0] == g.dims[1] == g.dims[2]


def test_yaw_symmetric_map_does_not_care_about_the_turn(ur5_map: ReachabilityMap) -> None:
    robot = ur5_map.robot
    T = armkit.fk(robot, robot.random_q(2000, rng=3))
    th = np.random.default_rng(4).uniform(-math.pi, math.pi, 2000)
    Rz = np.tile(np.eye(4), (2000, 1, 1))
    Rz[:, 0, 0], Rz[:, 0, 1], Rz[:, 1, 0], Rz[:, 1, 1] = np.cos(th), -np.sin(th), np.sin(th), np.cos(th)
    a = ur5_map.cells(T)
    b = ur5_map.cells(Rz @ T)
    assert np.mean(a == b) > 0.995          # equal but for rounding exactly on a bin boundary


def test_map_agrees_with_closed_form_ik(ur5_map: ReachabilityMap) -> None:
    robot = ur5_map.robot
    rng = np.random.default_rng(5)
    T_fk = armkit.fk(robot, robot.random_q(2000, rng=rng))
    assert ur5_map.reachable(T_fk).mean() > 0.99                       # reachable by construction
    # random poses in the workspace box, judged by every closed-form branch
    T = np.tile(np.eye(4), (2000, 1, 1))
    T[:, :3, 3] = rng.uniform(-0.9, 0.9, (2000, 3))
    q, _ = np.linalg.qr(rng.normal(size=(2000, 3, 3)))
    q *= np.sign(np.linalg.det(q))[:, None, None]
    T[:, :3, :3] = q
    truth = np.asarray(armkit.ik_all(robot, T).success).any(axis=-1)
    said = ur5_map.reachable(T)
    assert np.mean(said == truth) > 0.9
    # where the map says yes, IK finds a solution for most poses (the misses are cells on the boundary)
    assert truth[said].mean() > 0.85
    # and every cell the map marks came from a real configuration: FK of the counted samples
    assert (ur5_map.counts[ur5_map.hits] > 0).all()


def test_coverage_rule_only_removes_cells() -> None:
    m = reachability("ur5", resolution=0.1, orientations=16, samples=300_000, workers=1)
    loose = decide(m.counts, m.grid, 0.0)
    assert np.array_equal(loose, m.counts > 0)
    assert not (m.hits & ~loose).any()


def test_queries_shapes_and_outside(ur5_map: ReachabilityMap) -> None:
    T = np.tile(np.eye(4), (2, 3, 1, 1))
    assert ur5_map.reachable(T).shape == (2, 3)
    assert ur5_map.reachable(np.eye(4)).shape == ()
    far = np.eye(4)
    far[:3, 3] = [50.0, 0.0, 0.0]
    assert not ur5_map.reachable(far)
    assert ur5_map.index([[50.0, 0, 0], [0.3, 0.0, 0.3]]).shape == (2,)
    assert float(ur5_map.index([50.0, 0, 0])) == 0.0


@pytest.mark.parametrize("bad, match", [
    (np.eye(3), r"shape \(\.\.\., 4, 4\)"), ([[np.nan] * 4] * 4, "NaN"), ("pose", "numeric"),
    (np.diag([1.0, 1.0, -1.0, 1.0]), "not a rigid transform: det R = -1")])
def test_query_errors(ur5_map: ReachabilityMap, bad: object, match: str) -> None:
    with pytest.raises(armkit.ShapeError, match=match):
        ur5_map.reachable(bad)


@pytest.mark.parametrize("kw, match", [
    ({"resolution": -1.0}, "resolution must be a positive length"),
    ({"resolution": 1e-6}, "finer than reach/1000"),
    ({"orientations": 0}, "orientations must be a positive integer"),
    ({"rolls": 2.5}, "rolls must be a positive integer"),
    ({"method": "magic"}, "method must be 'fk' or 'ik'"),
    ({"samples": 0}, "samples must be a positive integer"),
    ({"seed": -3}, "seed must be a non-negative integer"),
    ({"coverage": 2.0}, r"coverage must be a number in \[0, 1\]"),
])
def test_build_errors(kw: dict, match: str) -> None:
    with pytest.raises(ReachabilityError, match=match):
        reachability("planar2", **{"workers": 1, **kw})


def test_unknown_robot_and_bad_scene() -> None:
    with pytest.raises(armkit.UnknownRobotError):
        reachability("no-such-arm")
    with pytest.raises(armkit.ArmkitError):
        reachability("planar2", scene=object(), samples=1000, workers=1)


def test_scene_removes_colliding_samples() -> None:
    # the fighter arm ships its torso box and the ground: reaching into them no longer counts
    free = reachability("fighter", samples=60_000, workers=1, coverage=0.0)
    clear = reachability("fighter", samples=60_000, workers=1, coverage=0.0, scene="robot")
    assert clear.parameters["scene"] is not None
    assert not (clear.hits & ~free.hits).any()                 # only removes cells
    assert clear.hits.sum() < 0.9 * free.hits.sum()
    below = armkit.fk(free.robot, free.robot.random_q(5000, rng=2))
    below = below[below[:, 2, 3] < -40.0]                      # the ground plane is z = -25 mm
    assert len(below) > 50 and not clear.reachable(below).any() and free.reachable(below).mean() > 0.9


def test_same_seed_same_map_other_seed_other_samples() -> None:
    a = reachability("fighter", samples=200_000, block_size=50_000, workers=1)
    b = reachability("fighter", samples=200_000, block_size=50_000, workers=1)
    c = reachability("fighter", samples=200_000, block_size=50_000, workers=1, seed=9)
    assert np.array_equal(a.counts, b.counts) and np.array_equal(a.manipulability, b.manipulability)
    assert not np.array_equal(a.counts, c.counts)


def test_grid_bins_every_fk_sample_inside_the_box() -> None:
    for name in ("panda", "ur5", "fighter", "puma560"):
        robot = armkit.load(name)
        g = reachability(robot, resolution=robot.reach / 4, orientations=4, rolls=2, samples=1000, workers=1).grid
        T = armkit.fk(robot, robot.random_q(20_000, rng=0))
        c = g.cells(T)
        assert (c >= 0).all() and (c < g.n_cells).all()


def test_orientation_centres_bin_to_themselves() -> None:
    g = Grid.build(np.eye(4), False, 1.0, 0.5, 32, 4)
    R = g.orientation_centres()
    T = np.tile(np.eye(4), (len(R), 1, 1))
    T[:, :3, :3] = R
    assert np.array_equal(g.cells(T) % g.n_orient, np.arange(g.n_orient))


def test_import_armkit_does_not_import_dask_or_zarr() -> None:
    code = ("import sys, armkit; armkit.ReachabilityMap; "
            "print(any(m.split('.')[0] in ('dask', 'distributed', 'zarr') for m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_every_disagreement_with_ik_lies_in_a_boundary_cell(ur5_map: ReachabilityMap) -> None:
    robot = ur5_map.robot
    rng = np.random.default_rng(8)
    T = np.tile(np.eye(4), (3000, 1, 1))
    T[:, :3, 3] = rng.uniform(-0.9, 0.9, (3000, 3))
    q, _ = np.linalg.qr(rng.normal(size=(3000, 3, 3)))
    T[:, :3, :3] = q * np.sign(np.linalg.det(q))[:, None, None]
    truth = np.asarray(armkit.ik_all(robot, T).success).any(axis=-1)
    wrong = ur5_map.reachable(T) != truth
    c = ur5_map.cells(T)
    assert wrong.any()
    # nearly all: a cell can also be wrong inside a neighbourhood that is itself only partly reachable
    # (here the thin unreachable cylinder around UR5's first axis, narrower than a 10 cm voxel)
    assert ur5_map.boundary.reshape(-1)[c[wrong]].mean() > 0.97
    assert np.mean(ur5_map.reachable(T, refine=True) == truth) > 0.998


def test_base_placement_against_distances_by_hand() -> None:
    # fighter: the tool stays within reach (213.2 mm) of the first joint's origin, so a base
    # farther than that from a task cannot reach it; tasks 120 mm around (400, 0, 60)
    from armkit.reach import base_placement

    m = reachability("fighter", resolution=8.0, samples=400_000, workers=1)
    tasks = np.tile(np.eye(4), (3, 1, 1))
    tasks[:, :3, 3] = [[520.0, 0.0, 60.0], [400.0, 120.0, 60.0], [400.0, -120.0, 60.0]]
    best = base_placement(m, tasks, top=5)
    assert best[0].ik_count == 3 and best[0].map_count == 3
    assert [b.ik_count for b in best] == sorted((b.ik_count for b in best), reverse=True)
    for b in best:     # what IK confirms is within reach of the base, by hand
        d = np.linalg.norm(tasks[:, :3, 3] - b.pose[:3, 3], axis=1)
        assert np.all(d[b.ik_reached] <= m.robot.reach + 1e-9)
    far, near = np.eye(4), np.eye(4)
    near[:3, 3] = [420.0, 0.0, 0.0]
    ranked = base_placement(m, tasks, candidates=np.stack([far, near]), top=2)
    assert np.array_equal(ranked[0].pose, near) and ranked[0].ik_count == 3
    assert ranked[1].ik_count == 0 and ranked[1].map_count == 0
    with pytest.raises(armkit.ShapeError, match="task_poses"):
        base_placement(m, np.eye(3))
