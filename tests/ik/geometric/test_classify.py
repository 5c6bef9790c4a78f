"""The geometric class of a chain: which axes meet or are parallel, and which closed form follows (IK-Geo's families)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from typer.testing import CliRunner

import armkit
from armkit import Joint, Robot
from armkit.cli import app
from armkit.ik.geometric.classify import TEXTS, ChainClass, axis_points, classify, describe, intersect, parallel
from armkit.ik.geometric.poe import POE, poe
from armkit.spatial import axis_angle_to_rotation


# ------------------------------------------------------------------ the bundled robots, from their published geometry
# (name, intersecting, parallel, solver, max_solutions), each with the reasoning
BUNDLED = {
    # fighter (3R): the base yaw axis (z) meets the shoulder axis (y, 36 mm up); shoulder ∥ elbow. An elbow arm:
    # position IK in closed form, shoulder front/back × elbow up/down.
    "fighter": ("3R-elbow", ((1, 2),), ((2, 3),), "closed form", 4),
    # planar2 / planar3: every axis is z; in the plane (x, y) or (x, y, heading): elbow up/down.
    "planar2": ("2R-planar", (), ((1, 2),), "closed form", 2),
    "planar3": ("3R-planar", (), ((1, 2, 3),), "closed form", 2),
    # Puma 560: axes 1, 2 meet at the shoulder; 2 ∥ 3 (a2 = 0.4318); the wrist axes 4, 5, 6 meet in one point
    # (d4 = 0.4318 along axis 4, a4 = a5 = 0). IK-Geo's "spherical joint and two intersecting axes".
    "puma560": ("6R-spherical-wrist-two-intersecting", ((1, 2), (4, 5, 6)), ((2, 3),), "closed form", 8),
    # UR5: 2 ∥ 3 ∥ 4 (the shoulder, elbow, wrist-1 pitch axes); 1 meets 2 and 5 meets 6 (d5 and d6 lie along the
    # axes), 4 meets 5 (a4 = 0) but 4, 5, 6 do not share a point (d5 ≠ 0). IK-Geo's UR5 family.
    "ur5": ("6R-three-parallel-two-intersecting", ((1, 2), (4, 5), (5, 6)), ((2, 3, 4),), "closed form", 8),
    # Stanford arm (RRPRRR): 1 meets 2, joint 3 slides (a direction, no line: never "meets"), spherical wrist
    # 4-5-6; the slide is ∥ axis 4. A 3-joint positioning problem plus a wrist: closed form.
    "stanford": ("RRPRRR-spherical-wrist", ((1, 2), (4, 5, 6)), ((3, 4),), "closed form", 8),
    # Panda (7R): axes 1, 2, 3 meet at the shoulder (d1 = 0.333 along 1, a = 0 to axis 3); 5 meets 6; axes 3 and 5
    # (and 5 and 7) are both perpendicular to the axis between them and lie in one plane with it for every value
    # of that joint, so they meet (parallel at q = 0). Locking joint 6 (or 7) leaves a 6R arm with a spherical
    # joint at the base and two intersecting axes at the tool end: the inverted "spherical + two intersecting".
    "panda": ("7R-lock-6-spherical-wrist-base-two-intersecting", ((1, 2, 3), (3, 5), (5, 6), (5, 7)), (),
              "sweep joint 6", 8),
    # iiwa 14: every axis crosses the z axis at q = 0; shoulder 1-2-3, elbow 3-4-5 and wrist 5-6-7 each meet in a
    # point. Locking joint 3 (IK-Geo's "KUKA LBR iiwa, fixed q3") leaves 1 ∩ 2 and the spherical wrist.
    "iiwa14": ("7R-lock-3-spherical-wrist-two-intersecting", ((1, 2, 3), (3, 4, 5), (5, 6, 7)), (),
               "sweep joint 3", 8),
    # SO-101 (5R): base yaw, then three parallel pitch axes (shoulder, elbow, wrist flex), then the wrist roll,
    # which meets the wrist flex axis. The yaw axis is 30 mm off the shoulder axis: no 1 ∩ 2.
    "so101": ("5R-yaw-three-parallel-roll", ((4, 5),), ((2, 3, 4),), "closed form", 4),
}


@pytest.mark.parametrize("name", sorted(BUNDLED))
def test_bundled_robot_classes(name):
    want, inter, par, solver, m = BUNDLED[name]
    c = classify(armkit.load(name))
    assert (c.name, c.intersecting, c.parallel, c.solver, c.max_solutions) == (want, inter, par, solver, m)
    assert c.n == armkit.load(name).n and c.joint_types == armkit.load(name).joint_types
    assert not c.degenerate


def test_exact_robots_report_no_snapping_and_so101_reports_its_rounded_urdf():
    for name in ("fighter", "planar2", "planar3", "puma560", "ur5", "stanford", "panda", "iiwa14"):
        assert classify(armkit.load(name)).near < 1e-12, name
    # the SO-101 URDF writes its angles rounded (3.14159, 1.5708): the wrist roll axis misses the wrist flex
    # axis by ~2e-7 m; accepted within the tolerance but reported
    near = classify(armkit.load("so101")).near
    assert 1e-9 < near < 1e-6


def test_alternatives_and_inversion():
    puma = classify(armkit.load("puma560"))
    assert "6R-spherical-wrist-two-parallel" in puma.alternatives and "6R-spherical-wrist" in puma.alternatives
    assert not puma.inverted
    panda = classify(armkit.load("panda"))
    assert panda.inverted and panda.locked == 6 and panda.locked_class == "6R-spherical-wrist-base-two-intersecting"
    assert "7R-lock-7-spherical-wrist-base-two-intersecting" in panda.alternatives
    iiwa = classify(armkit.load("iiwa14"))
    # locking the elbow (joint 4) between two spherical joints leaves a 6R arm that cannot move freely: never offered
    assert not any(a.startswith("7R-lock-4") for a in iiwa.alternatives)
    assert "7R-lock-1-spherical-wrist-two-intersecting" in iiwa.alternatives


def test_describe_lines():
    assert describe(classify(armkit.load("puma560"))) == (
        "6R: axes 1-2 meet, axes 4-5-6 meet in a point (spherical wrist), axes 2 ∥ 3; closed form, "
        "up to 8 solutions")
    assert describe(classify(armkit.load("iiwa14"))).endswith(
        "locking joint 3 leaves a closed form ('6R-spherical-wrist-two-intersecting'): sweep joint 3, "
        "up to 8 solutions per value")
    assert "polish the solutions" in describe(classify(armkit.load("so101")))
    seen = []
    describe(classify(armkit.load("panda")), lambda text, **f: seen.append(text) or text.format(**f))
    assert seen and set(seen) <= set(TEXTS)


def test_helpers_on_ur5():
    f = poe(armkit.load("ur5"))
    assert parallel(f.H, 1, 2) and parallel(f.H, 1, 3) and not parallel(f.H, 0, 1)
    assert intersect(f.H, f.P, 0, 1) and intersect(f.H, f.P, 4, 5) and not intersect(f.H, f.P, 1, 2)
    assert np.allclose(axis_points(f.P)[1], f.P[0] + f.P[1])


# ------------------------------------------------------------------ a POE chain as a URDF robot (axes as written)
def _urdf_from_poe(form: POE, flip: tuple[int, ...] = ()) -> Robot:
    """A URDF-convention robot with the chain's geometry: joint frames aligned with the world at q = 0, each at its
    point on the axis, the axis written in that frame; the joints in ``flip`` written with the axis reversed."""
    pts = axis_points(form.P)
    joints, prev = [], np.zeros(3)
    for k in range(form.n):
        O = np.eye(4)
        O[:3, 3] = pts[k] - prev
        prev = pts[k]
        axis = -form.H[k] if k in flip else form.H[k]
        joints.append(Joint("prismatic" if form.prismatic[k] else "revolute", lower=-3.0, upper=3.0,
                            name=f"j{k + 1}", origin=tuple(map(tuple, O)), axis=tuple(float(v) for v in axis)))
    tool = np.eye(4)
    tool[:3, :3] = form.R_nT
    tool[:3, 3] = form.P[-1]
    return Robot(joints, "urdf", "from-poe", tool=tool)


@pytest.mark.parametrize("name", sorted(BUNDLED))
def test_the_class_is_the_same_when_written_as_urdf_with_reversed_axes(name):
    r = armkit.load(name)
    form = poe(r)
    want = classify(r)
    same = _urdf_from_poe(form)
    assert classify(same).name == want.name
    rng = np.random.default_rng(len(name))
    for flip in [(0,), (r.n - 1,), tuple(np.flatnonzero(rng.random(r.n) < 0.5))]:
        flipped = classify(_urdf_from_poe(form, flip))
        assert (flipped.name, flipped.intersecting, flipped.parallel, flipped.solver) == (
            want.name, want.intersecting, want.parallel, want.solver), flip


def test_so101_urdf_with_one_axis_written_reversed():
    r = armkit.load("so101")
    for k in range(r.n):
        joints = [Joint(j.kind, lower=j.lower, upper=j.upper, name=j.name, origin=j.origin,
                        axis=tuple(-a for a in j.axis) if i == k else j.axis) for i, j in enumerate(r.joints)]
        flipped = Robot(joints, "urdf", r.name, r.unit, r.base, r.tool, link_names=r.link_names)
        assert classify(flipped).name == "5R-yaw-three-parallel-roll"


# ------------------------------------------------------------------ random arms with a known structure
def _unit(rng) -> np.ndarray:
    v = rng.normal(size=3)
    return v / np.linalg.norm(v)


def _random_arm(structure: str, rng) -> POE:
    """A random 6R or 7R chain with only the relations ``structure`` asks for (generic otherwise)."""
    n = 7 if structure.startswith("7R") else 6
    H = np.array([_unit(rng) for _ in range(n)])
    P = rng.normal(scale=0.3, size=(n + 1, 3))

    def meet(i, j):         # axes i, j (0-based, consecutive) meet: the offset between them in span(h_i, h_j)
        P[j] = rng.normal(scale=0.3) * H[i] + rng.normal(scale=0.3) * H[j]

    def concurrent(i):      # axes i, i+1, i+2 through one point c
        a, b, d = rng.normal(scale=0.3, size=3)
        P[i + 1] = a * H[i] + b * H[i + 1]
        P[i + 2] = -b * H[i + 1] + d * H[i + 2]

    def par(*idx):          # parallel axes, each in a random sense
        for k in idx[1:]:
            H[k] = H[idx[0]] * rng.choice([-1.0, 1.0])

    if structure == "spherical-two-intersecting":
        concurrent(3), meet(0, 1)
    elif structure == "spherical-two-parallel":
        concurrent(3), par(1, 2)
    elif structure == "spherical":
        concurrent(3)
    elif structure == "spherical-base":
        concurrent(0)
    elif structure == "three-parallel-two-intersecting":
        par(1, 2, 3), meet(4, 5)
    elif structure == "three-parallel":
        par(1, 2, 3)
    elif structure == "two-parallel":
        par(1, 2)
    elif structure == "two-intersecting":
        meet(4, 5)
    elif structure == "spherical-middle":
        concurrent(1)
    elif structure == "spherical-middle-345":
        concurrent(2)
    elif structure == "7R-iiwa-like":
        concurrent(0), concurrent(4), meet(2, 3)
    # rotate and move the whole chain: the class must not notice
    Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    H, P = H @ Q.T, P @ Q.T
    P[0] += rng.normal(size=3)
    return POE(H, P, np.eye(3), np.zeros(n, dtype=bool))


RANDOM = {
    "spherical-two-intersecting": "6R-spherical-wrist-two-intersecting",
    "spherical-two-parallel": "6R-spherical-wrist-two-parallel",
    "spherical": "6R-spherical-wrist",
    "spherical-base": "6R-spherical-wrist-base",
    "three-parallel-two-intersecting": "6R-three-parallel-two-intersecting",
    "three-parallel": "6R-three-parallel",
    "two-parallel": "6R-two-parallel",
    "two-intersecting": "6R-two-intersecting",
    "spherical-middle": "6R-spherical-middle",
    "spherical-middle-345": "6R-spherical-middle",
    "general": "6R-general",
    # shoulder and wrist spherical, 3 ∩ 4: locking joint 4 keeps 1-2-3 and 5-6-7 (degenerate: never chosen),
    # locking 3 (or 2) leaves 1 ∩ 2 and the wrist; the rule prefers the joint nearest the middle, then the lower
    "7R-iiwa-like": "7R-lock-3-spherical-wrist-two-intersecting",
}


@pytest.mark.parametrize("structure", sorted(RANDOM))
def test_random_arms_with_known_structure(structure):
    for seed in range(5):
        c = classify(_random_arm(structure, np.random.default_rng(seed)))
        assert c.name == RANDOM[structure], (seed, c)
        if structure.startswith("spherical-middle"):      # solved with axes 2-3-4 meeting, 3-4-5 reversed
            assert c.inverted == structure.endswith("345") and c.solver == "1-D search"
        assert c.near < 1e-9
        if c.name == "6R-general":
            assert c.solver == "2-D search" and c.intersecting == () and c.parallel == ()


def test_near_parallel_axes_are_snapped_and_reported():
    f = poe(armkit.load("ur5"))
    H = np.array(f.H)
    H[2] = axis_angle_to_rotation([1.0, 0.0, 0.0], 1e-8) @ H[2]          # axis 3 tilted by 1e-8 rad off axes 2 and 4
    tilted = POE(H, f.P, f.R_nT, f.prismatic)
    c = classify(tilted)
    assert c.name == "6R-three-parallel-two-intersecting"
    assert 5e-9 < c.near < 2e-8
    assert "polish the solutions" in describe(c)
    # a tolerance tighter than the tilt no longer calls them parallel: UR5 without 2 ∥ 3 ∥ 4 still has 1 ∩ 2
    tight = classify(tilted, tol=1e-10)
    assert tight.name == "6R-two-intersecting" and (2, 3, 4) not in tight.parallel


def test_nearly_meeting_axes_within_tolerance():
    f = poe(armkit.load("puma560"))
    P = np.array(f.P)
    P[5] = P[5] + np.array([1e-9, 0.0, 0.0])                        # axis 6 (z) misses the wrist point by 1 nm
    c = classify(POE(f.H, P, f.R_nT, f.prismatic))
    assert c.name == "6R-spherical-wrist-two-intersecting" and c.near > 1e-12
    assert classify(POE(f.H, P, f.R_nT, f.prismatic), tol=1e-12).name != c.name


def test_bad_tolerance():
    with pytest.raises(ValueError):
        classify(armkit.load("ur5"), tol=0.0)


def test_chain_class_is_frozen_and_json_ready():
    c = classify(armkit.load("ur5"))
    assert isinstance(c, ChainClass)
    with pytest.raises(Exception):
        c.name = "x"  # type: ignore[misc]
    d = json.loads(json.dumps(c.as_dict()))
    assert d["intersecting"] == [[1, 2], [4, 5], [5, 6]] and d["parallel"] == [[2, 3, 4]]


# ------------------------------------------------------------------ Kinova j2s6s200 (example-robot-data)
# Its URDF (example-robot-data, robots/kinova_description/robots/kinova.urdf): axis 2 crosses axis 1 (the
# 0.0016 m offset lies along axis 2 itself), axis 3 ∥ axis 2, the 0.0114 m side offset runs along axis 3 so
# axis 4 crosses axis 3 (unlike the Puma, whose a3 = 0.0203 keeps them apart), and axes 4, 5, 6 meet in one
# point (the 0.10375 m offsets run along axis 4 and along axis 6). So the Jaco 2 6-DOF *spherical* wrist arm is
# the Puma's family, "spherical + two intersecting" (also "+ two parallel"), closed form with up to 8
# solutions; its URDF writes pi as 3.14159265359, so the relations hold to ~1e-12, snapped and reported.
KINOVA = [  # (origin xyz, origin rpy) of joints 1..6, axis z each: the numbers of the URDF
    ((0, 0, 0.15675), (0, 3.14159265359, 0)),
    ((0, 0.0016, -0.11875), (-1.57079632679, 0, 3.14159265359)),
    ((0, -0.410, 0), (0, 3.14159265359, 0)),
    ((0, 0.2073, -0.0114), (-1.57079632679, 0, 3.14159265359)),
    ((0, 0, -0.10375), (1.57079632679, 0, 3.14159265359)),
    ((0, 0.10375, 0), (-1.57079632679, 0, 3.14159265359)),
]


def _kinova_urdf(tmp_path):
    links = "".join(f'<link name="l{k}"/>' for k in range(7))
    joints = "".join(
        f'<joint name="joint_{k + 1}" type="revolute"><parent link="l{k}"/><child link="l{k + 1}"/>'
        f'<origin xyz="{" ".join(map(str, xyz))}" rpy="{" ".join(map(str, rpy))}"/><axis xyz="0 0 1"/>'
        f'<limit lower="-6.28" upper="6.28" effort="1" velocity="1"/></joint>'
        for k, (xyz, rpy) in enumerate(KINOVA))
    path = tmp_path / "j2s6s200.urdf"
    path.write_text(f'<robot name="j2s6s200">{links}{joints}</robot>')
    return armkit.load(path)


def test_kinova_j2s6s200_geometry_from_its_urdf(tmp_path):
    c = classify(_kinova_urdf(tmp_path))
    assert c.name == "6R-spherical-wrist-two-intersecting" and c.solver == "closed form" and c.max_solutions == 8
    assert c.intersecting == ((1, 2), (3, 4), (4, 5, 6)) and c.parallel == ((2, 3),)
    assert "6R-spherical-wrist-two-parallel" in c.alternatives
    assert c.near < 1e-9


def test_kinova_j2s6s200_from_example_robot_data():
    erd = pytest.importorskip("example_robot_data")
    pin = pytest.importorskip("pinocchio")  # noqa: F841  (example_robot_data loads through it)
    model = erd.load("kinova")
    path = model.urdf if hasattr(model, "urdf") else None
    if path is None:
        pytest.skip("example_robot_data gives no URDF path for kinova")
    r = armkit.load(path, tip="j2s6s200_link_6")
    assert classify(r).name == "6R-spherical-wrist-two-intersecting"


# ------------------------------------------------------------------ the command line
runner = CliRunner()


def test_info_prints_the_class_line():
    res = runner.invoke(app, ["info", "ur5"], env={"COLUMNS": "250"})
    assert res.exit_code == 0, res.output
    assert ("geometric class '6R-three-parallel-two-intersecting': 6R: axes 1-2 meet, axes 4-5 meet, "
            "axes 5-6 meet, axes 2 ∥ 3 ∥ 4; closed form, up to 8 solutions") in res.output


def test_info_json_has_the_class():
    res = runner.invoke(app, ["info", "puma560", "--json"])
    assert res.exit_code == 0, res.output
    cls = json.loads(res.stdout)["class"]
    assert cls["name"] == "6R-spherical-wrist-two-intersecting" and cls["solver"] == "closed form"
    assert cls["intersecting"] == [[1, 2], [4, 5, 6]] and cls["parallel"] == [[2, 3]] and cls["max_solutions"] == 8


def test_info_class_line_in_korean():
    res = runner.invoke(app, ["info", "so101", "--lang", "ko"], env={"COLUMNS": "250"})
    assert res.exit_code == 0, res.output
    assert "기하 분류 '5R-yaw-three-parallel-roll': 5R: 축 4-5 교차, 축 2 ∥ 3 ∥ 4; 해석적 해, 해 최대 4개" in res.output


def test_every_phrase_has_a_korean_translation():
    from armkit.locale import translate

    for text in TEXTS + ("geometric class {name!r}: {line}",):
        fields = {k: 1 for k in ("axes", "a", "b", "n", "k", "cls", "dev", "name", "line", "step")}
        assert translate(text, "ko", **fields) != translate(text, "en", **fields), text
