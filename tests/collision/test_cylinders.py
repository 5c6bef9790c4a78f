"""Cylinders in the compiled kernels: hand-computed cases, coal on random poses, and the kind table.

The compiled path (``armkit.collision._jit``) is exact for a cylinder against a half-space, a
ball, a capsule (apart and overlapping) and, apart, against a box or a cylinder; overlapping
boxes and cylinders get a depth that is a bound (every value returned is the separation along
some direction, never more than the true signed distance). These tests hold it to that.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import armkit
from armkit.collision import KIND_TABLE, Scene
from armkit.collision.query import _jit_pack, _pairs, shape_distance
from armkit.collision.geometry import arm_geometry

from coal_reference import coal_distance, coal_shape


@pytest.fixture(autouse=True, scope="module")
def numba_backend():
    before = armkit.get_backend()
    armkit.set_backend("numba")
    yield
    armkit.set_backend(before)


# --------------------------------------------------------------------------- by hand
def test_cylinder_and_ball_by_hand():
    cyl = Scene.cylinder([0, 0, 0], 0.5, 2.0)             # radius 0.5, z in [-1, 1]
    # beside the side: centre 2 from the axis, radius 0.5 -> gap 2 - 0.5 - 0.5
    assert shape_distance(cyl, Scene.sphere([2, 0, 0.3], 0.5)) == pytest.approx(1.0, abs=1e-12)
    # above the cap: centre 3 above the axis' middle -> 3 - 1 - 0.5
    assert shape_distance(cyl, Scene.sphere([0.2, 0.1, 3], 0.5)) == pytest.approx(1.5, abs=1e-12)
    # past the rim: the nearest point is the rim point (0.5, 0, 1); centre (1.5, 0, 2) -> sqrt(2) - 0.25
    assert shape_distance(cyl, Scene.sphere([1.5, 0, 2], 0.25)) == pytest.approx(math.sqrt(2) - 0.25, abs=1e-12)
    # centre inside, 0.1 from the side and 0.6 from the caps: pushed out sideways by 0.1 + 0.2
    assert shape_distance(cyl, Scene.sphere([0.4, 0, 0.4], 0.2)) == pytest.approx(-0.3, abs=1e-12)
    # centre inside, 0.05 under the top cap, 0.5 from the side: out through the cap by 0.05 + 0.2
    assert shape_distance(cyl, Scene.sphere([0, 0, 0.95], 0.2)) == pytest.approx(-0.25, abs=1e-12)


def test_cylinder_and_capsule_by_hand():
    cyl = Scene.cylinder([0, 0, 0], 0.5, 2.0, [math.pi / 2, 0, 0])   # turned onto the y axis, y in [-1, 1]
    # a capsule along x at z = 2 crossing above it: 2 - 0.5 - 0.1
    cap = Scene.capsule([-3, 0, 2], [3, 0, 2], 0.1)
    assert shape_distance(cyl, cap) == pytest.approx(1.4, abs=1e-12)
    # a capsule through the middle along x (radius 0.1): out along z (or x) by 0.5 + 0.1 at the least
    cap = Scene.capsule([-3, 0, 0], [3, 0, 0], 0.1)
    assert shape_distance(cyl, cap) == pytest.approx(-0.6, abs=1e-12)


def test_cylinder_and_half_space_by_hand():
    # a cylinder lying along x at height 1 (radius 0.3) over the ground z <= 0: lowest point 0.7
    cyl = Scene.cylinder([0, 0, 1], 0.3, 4.0, [0, math.pi / 2, 0])
    assert shape_distance(cyl, Scene.plane([0, 0, 1], 0.0)) == pytest.approx(0.7, abs=1e-12)
    # tilted by 30 deg about y: lowest point 1 - 2 sin 30 - 0.3 cos 30
    cyl = Scene.cylinder([0, 0, 1], 0.3, 4.0, [0, math.pi / 2 - math.radians(30), 0])
    expect = 1 - 2 * math.sin(math.radians(30)) - 0.3 * math.cos(math.radians(30))
    assert shape_distance(cyl, Scene.plane([0, 0, 1], 0.0)) == pytest.approx(expect, abs=1e-12)


def test_cylinder_and_solids_by_hand():
    a = Scene.cylinder([0, 0, 0], 0.5, 2.0)
    # parallel cylinders 1.5 apart: 1.5 - 0.5 - 0.25
    assert shape_distance(a, Scene.cylinder([1.5, 0, 0.5], 0.25, 2.0)) == pytest.approx(0.75, abs=1e-9)
    # the same overlapping: 0.6 apart -> the side overlap 0.5 + 0.25 - 0.6 is the smallest way out
    assert shape_distance(a, Scene.cylinder([0.6, 0, 0.5], 0.25, 2.0)) == pytest.approx(-0.15, abs=1e-9)
    # a cylinder stood on top, across: the gap between the caps' planes
    assert shape_distance(a, Scene.cylinder([0, 0, 1.7], 0.3, 1.0, [0, math.pi / 2, 0])) == \
        pytest.approx(0.4, abs=1e-9)
    # a box beside the side, face parallel to the axis: 2 - 0.5 - 0.5
    assert shape_distance(a, Scene.box([2, 0, 0], [1, 1, 1])) == pytest.approx(1.0, abs=1e-9)
    # a box sitting 0.1 into the top cap (box z in [0.9, 1.9], wider than the cylinder): out by 0.1
    assert shape_distance(a, Scene.box([0, 0, 1.4], [3, 3, 1])) == pytest.approx(-0.1, abs=1e-9)


# --------------------------------------------------------------------------- coal on random poses
def _random(kind, rng):
    c, rpy = rng.uniform(-0.6, 0.6, 3), rng.uniform(-3, 3, 3)
    if kind == "cylinder":
        return Scene.cylinder(c, rng.uniform(0.05, 0.5), rng.uniform(0.05, 1.5), rpy)
    if kind == "box":
        return Scene.box(c, rng.uniform(0.05, 1.0, 3), rpy)
    if kind == "sphere":
        return Scene.sphere(c, rng.uniform(0.05, 0.5))
    if kind == "capsule":
        return Scene.capsule(c, c + rng.uniform(-0.8, 0.8, 3), rng.uniform(0.02, 0.4))
    return Scene.plane(rng.normal(size=3), rng.uniform(-0.5, 0.5))


def _support(s, n):
    """An independent support function (NumPy, written here): the point of shape s farthest along unit n.

    ``n`` is one direction (3,) or many (k, 3): one support point per direction."""
    T = s.pose
    n = np.asarray(n, dtype=float)
    many = n.reshape(-1, 3)
    side = lambda v: np.where(many @ v >= 0, 1.0, -1.0)[:, None]  # noqa: E731
    x = T[:3, 3]
    if s.kind == "box":
        out = x + sum(side(T[:3, c]) * 0.5 * s.size[c] * T[:3, c] for c in range(3))
    elif s.kind == "cylinder":
        z = T[:3, 2]
        p = many - (many @ z)[:, None] * z
        pn = np.linalg.norm(p, axis=1, keepdims=True)
        rim = np.where(pn > 1e-9, s.size[0] * p / np.where(pn > 1e-9, pn, 1.0), 0.0)
        out = x + side(z) * 0.5 * s.size[1] * z + rim
    elif s.kind == "sphere":
        out = x + s.size[0] * many
    else:
        a, b = s.segment()
        out = np.where((many @ a >= many @ b)[:, None], a, b) + s.size[0] * many
    return out.reshape(n.shape)


def _best_separation(a, b, rng, samples=3000):
    """max over sampled unit u of min over A - B of (x · u): a lower bound of the signed distance, approaching it."""
    u = rng.normal(size=(samples, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    return float(np.max(np.sum((_support(a, -u) - _support(b, u)) * u, axis=1)))


EXACT = ["sphere", "capsule", "plane"]


@pytest.mark.parametrize("other", ["sphere", "capsule", "box", "cylinder", "plane"])
def test_cylinder_pairs_against_coal(other):
    rng = np.random.default_rng({"sphere": 1, "capsule": 2, "box": 3, "cylinder": 4, "plane": 5}[other])
    ours, ref, pairs = [], [], []
    for _ in range(200):
        a, b = _random("cylinder", rng), _random(other, rng)
        ours.append(shape_distance(a, b))
        ref.append(coal_distance(*coal_shape(a), *coal_shape(b)))
        pairs.append((a, b))
    ours, ref = np.array(ours), np.array(ref)
    apart = ref > 0
    assert 20 < apart.sum() < 180          # both cases are exercised
    # the sign always agrees: a colliding pair is never reported clear, a clear one never colliding
    np.testing.assert_array_equal(ours < 0, ref < 0)
    # apart: coal's GJK, to 1e-6 (coal stops up to ~1e-7 short on curved sides)
    np.testing.assert_allclose(ours[apart], ref[apart], rtol=0, atol=1e-6)
    over = np.flatnonzero(~apart)
    if other in EXACT:
        # overlapping, exact: no sampled direction separates better, and coal's EPA agrees where it converged
        # (it sometimes stops on a face that is not the nearest and reports a deeper overlap, never a shallower)
        if other != "plane":   # (a half-space has no support point: its depth is the closed form, checked above)
            for k in over[:40]:
                assert _best_separation(*pairs[k], rng) <= ours[k] + 1e-9
        assert np.all(ours[over] >= ref[over] - 1e-8)
        assert np.mean(np.abs(ours[over] - ref[over]) < 1e-6) > 0.8   # EPA misses ~12 % of sphere-cylinder overlaps
    else:
        # overlapping, a bound: within 1e-3 of coal on most pairs (coal's EPA is itself sometimes too deep), and
        # never more than 1e-3 below the best separation found by sampling 3,000 directions
        assert np.mean(np.abs(ours[over] - ref[over]) < 1e-3) > 0.7
        for k in over[:40]:
            best = _best_separation(*pairs[k], rng)
            assert best - 1e-3 <= ours[k] < 0


def test_solid_pairs_never_claim_clear_when_touching_deeply():
    # boxes and cylinders pushed into each other along random directions: every answer is negative
    rng = np.random.default_rng(8)
    for _ in range(200):
        a = _random("cylinder", rng)
        b = _random(rng.choice(["box", "cylinder"]), rng)
        b = Scene(b.moved(_shift(a.center - b.center)) for _ in [0]).shapes[0]   # same centre: overlapping
        assert shape_distance(a, b) < 0


def _shift(v):
    T = np.eye(4)
    T[:3, 3] = v
    return T


# --------------------------------------------------------------------------- the compiled path and the table
def test_a_scene_with_a_cylinder_is_checked_by_the_compiled_kernels_only():
    arm = armkit.load("ur5")
    R = arm.reach
    scene = Scene([Scene.plane([0, 0, 1], -0.05 * R, name="ground"),
                   Scene.cylinder([-0.5 * R, 0.5 * R, 0.5 * R], 0.05 * R, R, name="pole"),
                   Scene.box([0.6 * R, 0, 0.2 * R], [0.4 * R, 0.8 * R, 0.4 * R], name="table")])
    geo = arm_geometry(arm)
    scene_pairs, self_pairs = _pairs(geo, scene, True)
    _, pairs, cols = _jit_pack(geo, scene_pairs, self_pairs)
    assert len(cols) == len(scene_pairs) + len(self_pairs)     # no pair left to NumPy or coal


@pytest.mark.parametrize("kind", list(KIND_TABLE))
def test_every_kind_has_a_full_row(kind, tmp_path):
    row = KIND_TABLE[kind]
    assert row.name == kind and row.keys
    shapes = {"plane": Scene.plane([0, 0.6, 0.8], 0.3, name="p"),
              "box": Scene.box([1, 2, 3], [0.5, 0.6, 0.7], [0.1, 0.2, 0.3], name="b"),
              "sphere": Scene.sphere([1, 2, 3], 0.4, name="s"),
              "cylinder": Scene.cylinder([1, 2, 3], 0.4, 1.2, [0.3, -0.2, 0.1], name="c"),
              "capsule": Scene.capsule([1, 2, 3], [2, 2, 4], 0.3, name="k")}
    if kind == "mesh":
        pytest.skip("a mesh row needs a file: tests/collision/test_scene_files.py reads one")
    s = shapes[kind]
    # the file keys round-trip: write the row, read it back through a scene file
    from armkit.collision.files import parse_scene

    fields = row.write(s, 1.0)
    assert set(fields) <= row.keys
    lines = ['angle_unit = "rad"', "[[shapes]]", f'type = "{kind}"', f'name = "{s.name}"']
    lines += [f"{k} = {v!r}" if not isinstance(v, str) else f'{k} = "{v}"' for k, v in fields.items()]
    back = parse_scene("\n".join(lines), str(tmp_path / "scene.toml")).shapes[0]
    assert back.kind == kind and back.name == s.name
    np.testing.assert_allclose(back.pose[:, 2:], s.pose[:, 2:], atol=1e-12)    # the axis and the centre
    np.testing.assert_allclose(back.size, s.size, atol=1e-12)
    assert row.describe(s) and row.drawing(s)
    assert all(p.primitive in ("plane", "box", "sphere", "cylinder", "mesh") for p in row.drawing(s))
    import coal

    assert row.coal(coal, s) is not None


def test_the_adding_a_primitive_example_runs(capsys):
    import re
    from pathlib import Path

    text = (Path(__file__).resolve().parents[2] / "docs" / "adding-a-primitive.md").read_text()
    code = re.search(r"```python\n(.*?)```", text, re.S).group(1)
    exec(compile(code, "docs/adding-a-primitive.md", "exec"), {})
    assert capsys.readouterr().out.split("\n")[:2] == ["pillar of radius 0.05 and height 1 False", "True"]
    assert "pillar" not in KIND_TABLE
