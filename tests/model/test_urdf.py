"""URDF import/export, general joint axes and the DH twin of any chain.

References: yourdfpy's own forward kinematics (an independent implementation that reads
the same files), finite differences for Jacobians, and hand-built chains whose FK is
written out in the test. Pinocchio is compared in tests/peers (optional extra).
"""

from __future__ import annotations

import math
import os
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit import RobotFileError
from armkit.ik.analytic import closed_form
from armkit.ik.api import closed_form_family
from armkit.model.axes import joint_axes
from armkit.model.robot import Joint, Robot
from armkit.spatial import rpy_to_rotation

yourdfpy = pytest.importorskip("yourdfpy")
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "kinematics"))
from test_kinematics import _fd_jacobian as numeric_jacobian  # noqa: E402  (central differences of FK)

ERD = Path(sys.prefix) / "lib" / f"python{sys.version_info[0]}.{sys.version_info[1]}" / "site-packages" / \
    "cmeel.prefix" / "share" / "example-robot-data" / "robots"
REAL = {   # name: (file, base, tip) from the example-robot-data wheel (a test extra)
    "ur5": (ERD / "ur_description/urdf/ur5_robot.urdf", None, "tool0"),
    "panda": (ERD / "panda_description/urdf/panda.urdf", None, "panda_hand_tcp"),
    "z1": (ERD / "z1_description/urdf/z1.urdf", None, None),
    "so101": (Path(armkit.model.files.BUNDLED_DIR) / "so101.urdf", "base_link", "gripper_frame_link"),
}


# ------------------------------------------------------------------ helpers
def yourdfpy_fk(path, robot: Robot, q: np.ndarray, base: str, tip: str) -> np.ndarray:
    """FK of ``tip`` in ``base`` computed by yourdfpy, joints off the chain at 0."""
    y = yourdfpy.URDF.load(str(path), build_scene_graph=True, load_meshes=False)
    names = list(y.actuated_joint_names)
    out = np.empty((len(q), 4, 4))
    for k, qk in enumerate(q):
        cfg = dict.fromkeys(names, 0.0)
        cfg.update(zip(robot.joint_names, qk))
        y.update_cfg(np.array([cfg[n] for n in names]))
        out[k] = y.get_transform(tip, base)
    return out


def load_real(name: str) -> tuple[Path, Robot, str, str]:
    """A real URDF arm of :data:`REAL`: its file, the robot, and the base and tip links (skips when absent)."""
    path, base, tip = REAL[name]
    if not path.is_file():
        pytest.skip("example-robot-data is not installed (test extra)")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")     # meshes are not needed for kinematics
        r = armkit.load(path, base=base, tip=tip)
    return path, r, base or r.links[0].name, tip or [lk.name for lk in r.links if lk.joint not in r.ignored_joints][-1]


def urdf_text(joints: list[dict], name: str = "random_arm") -> str:
    """A chain URDF: link0 -> link1 -> ... with the given joints (type, xyz, rpy, axis, limits)."""
    out = [f'<?xml version="1.0"?>\n<robot name="{name}">']
    out += [f'  <link name="link{i}"/>' for i in range(len(joints) + 1)]
    for i, j in enumerate(joints):
        xyz = " ".join(repr(float(v)) for v in j["xyz"])
        rpy = " ".join(repr(float(v)) for v in j["rpy"])
        body = f'<parent link="link{i}"/><child link="link{i + 1}"/><origin xyz="{xyz}" rpy="{rpy}"/>'
        if j["type"] != "fixed":
            body += f'<axis xyz="{" ".join(repr(float(v)) for v in j["axis"])}"/>'
        if j["type"] in ("revolute", "prismatic"):
            body += f'<limit lower="{j["lower"]}" upper="{j["upper"]}" effort="1" velocity="1"/>'
        out.append(f'  <joint name="j{i}" type="{j["type"]}">{body}</joint>')
    return "\n".join(out + ["</robot>\n"])


def _vec(lo: float, hi: float):
    return st.lists(st.floats(lo, hi, allow_nan=False), min_size=3, max_size=3)


joint_strategy = st.fixed_dictionaries({
    "type": st.sampled_from(["revolute", "revolute", "continuous", "prismatic", "fixed"]),
    "xyz": _vec(-0.5, 0.5), "rpy": _vec(-3.2, 3.2),
    # unit axes: yourdfpy (the reference) slides a prismatic joint by |axis| q; armkit normalises (tested by hand)
    "axis": _vec(-1, 1).filter(lambda v: math.hypot(*v) > 0.1).map(lambda v: [x / math.hypot(*v) for x in v]),
    "lower": st.just(-2.5), "upper": st.just(2.5),
})
chain_strategy = st.lists(joint_strategy, min_size=1, max_size=8).filter(
    lambda js: any(j["type"] != "fixed" for j in js))


# ------------------------------------------------------------------ random chains (hypothesis)
@settings(max_examples=40, deadline=None)
@given(joints=chain_strategy, seed=st.integers(0, 2**31 - 1))
def test_random_chain_fk_matches_yourdfpy_and_dh_twin_and_round_trip(joints, seed, tmp_path_factory):
    d = tmp_path_factory.mktemp("urdf")
    path = d / "arm.urdf"
    path.write_text(urdf_text(joints))
    r = armkit.load(path)
    moving = [j for j in joints if j["type"] != "fixed"]
    assert r.n == len(moving)
    assert r.joint_types == "".join("P" if j["type"] == "prismatic" else "R" for j in moving)
    q = r.random_q(20, rng=seed)
    T = armkit.fk(r, q)
    tip = f"link{len(joints)}"
    scale = 1.0 + r.reach
    assert np.allclose(T, yourdfpy_fk(path, r, q, "link0", tip), atol=1e-12 * scale)
    _, u = joint_axes(r)
    sines = np.linalg.norm(np.cross(u[:-1], u[1:]), axis=-1)
    near_parallel = bool(((sines > 1e-12) & (sines < 1e-3)).any())
    for conv in ("standard", "modified"):
        if near_parallel:   # DH itself is ill-conditioned there (the common normal runs off to ~1/angle)
            try:
                twin = r.to_dh(conv)
            except armkit.RobotDefinitionError as exc:
                assert "almost, but not exactly, parallel" in str(exc)
                continue
            assert np.allclose(armkit.fk(twin, q), T, atol=1e-9 * scale), conv
            continue
        twin = r.to_dh(conv)
        assert twin.convention == conv and twin.joint_names == r.joint_names
        assert np.allclose(armkit.fk(twin, q), T, atol=1e-12 * scale), conv
    armkit.save(r, d / "again.urdf")
    back = armkit.load(d / "again.urdf")
    assert back.joint_names == r.joint_names and back.joint_types == r.joint_types
    assert np.array_equal(back.lower, r.lower) and np.array_equal(back.upper, r.upper)
    assert np.allclose(armkit.fk(back, q), T, atol=1e-12 * scale)
    assert np.allclose(armkit.jacobian(r, q[0]), numeric_jacobian(r, q[0]), atol=1e-6 * scale)


@settings(max_examples=25, deadline=None)
@given(joints=chain_strategy)
def test_every_named_link_is_reachable_and_fixed_joints_fold(joints, tmp_path_factory):
    path = tmp_path_factory.mktemp("urdf") / "arm.urdf"
    path.write_text(urdf_text(joints))
    r = armkit.load(path)
    q = r.random_q(3, rng=1)
    ref = {}
    for i in range(len(joints) + 1):
        ref[f"link{i}"] = yourdfpy_fk(path, r, q, "link0", f"link{i}")
    frames = armkit.link_frames(r, q)
    for k, lk in enumerate(r.links):
        assert np.allclose(armkit.fk(r, q, link=lk.name), ref[lk.name], atol=1e-12), lk.name
        assert np.allclose(frames[:, k], ref[lk.name], atol=1e-12)
    assert armkit.fk_frames(r, q).shape == (3, r.n + 1, 4, 4)


# ------------------------------------------------------------------ hand-built chain with non-z axes
def test_hand_derived_chain_with_x_axis_and_fixed_joint_in_the_middle(tmp_path):
    # base -(revolute about x, at z=1)-> a -(fixed, +0.5 y)-> b -(prismatic along y)-> tip
    # tip(q1, q2) = (0, (0.5 + q2) cos q1, 1 + (0.5 + q2) sin q1)   (rotation about x of the y offset)
    path = tmp_path / "hand.urdf"
    path.write_text(urdf_text([
        {"type": "revolute", "xyz": [0, 0, 1], "rpy": [0, 0, 0], "axis": [2, 0, 0], "lower": -3, "upper": 3},
        {"type": "fixed", "xyz": [0, 0.5, 0], "rpy": [0, 0, 0], "axis": [1, 0, 0], "lower": 0, "upper": 0},
        {"type": "prismatic", "xyz": [0, 0, 0], "rpy": [0, 0, 0], "axis": [0, 1, 0], "lower": 0, "upper": 1},
    ]))
    r = armkit.load(path)
    assert r.n == 2 and r.joint_types == "RP" and r.joints[0].axis == (1.0, 0.0, 0.0)
    for q1, q2 in [(0.3, 0.2), (-1.2, 0.9), (2.0, 0.0)]:
        p = armkit.fk(r, np.array([q1, q2]))[:3, 3]
        assert np.allclose(p, [0, (0.5 + q2) * math.cos(q1), 1 + (0.5 + q2) * math.sin(q1)], atol=1e-15)
    assert np.allclose(armkit.fk(r, [0.3, 0.2], link="link2")[:3, 3], [0, 0.5 * math.cos(0.3), 1 + 0.5 * math.sin(0.3)])


# ------------------------------------------------------------------ real files
@pytest.mark.parametrize("name", sorted(REAL))
def test_real_urdf_fk_and_jacobian_match_yourdfpy(name):
    path, r, base, tip = load_real(name)
    q = r.random_q(1000, rng=7)
    assert np.abs(armkit.fk(r, q) - yourdfpy_fk(path, r, q, base, tip)).max() <= 1e-12
    J = armkit.jacobian(r, q[:20])
    for k in range(20):
        assert np.allclose(J[k], numeric_jacobian(r, q[k]), atol=1e-7)
    twin = r.to_dh()
    assert np.abs(armkit.fk(twin, q) - armkit.fk(r, q)).max() <= 1e-12


def test_ur5_from_its_description_gives_all_eight_branches():
    _, r, _, _ = load_real("ur5")
    assert closed_form_family(r) == "ur"
    q = r.random_q(300, rng=3)
    T = armkit.fk(r, q)
    res = armkit.ik_all(r, T)
    ok = np.asarray(res.success)
    assert res.q.shape == (300, 8, 6) and ok.any(axis=1).all()
    # every branch that exists: the same count as the closed form on the exact DH twin, target by target
    # (random poses: some branches' wrist centre is out of the shoulder's reach, so not always 8)
    twin_ok = np.asarray(armkit.ik_all(r.to_dh(), T).success)
    assert np.array_equal(ok.sum(axis=1), twin_ok.sum(axis=1))
    assert (ok.sum(axis=1) == 8).mean() > 0.5
    Tq = armkit.fk(r, np.asarray(res.q)[ok])
    Tt = np.broadcast_to(T[:, None], (300, 8, 4, 4))[ok]
    assert np.abs(Tq - Tt).max() <= 1e-11


# ------------------------------------------------------------------ closed forms on perturbed URDF exports
def _perturbed(r: Robot, eps: float, seed: int) -> Robot:
    rng = np.random.default_rng(seed)
    joints = []
    for j in r.joints:
        O = j.origin_matrix().copy()
        O[:3, :3] = O[:3, :3] @ rpy_to_rotation(rng.uniform(-eps, eps, 3))
        joints.append(Joint(j.kind, lower=j.lower, upper=j.upper, name=j.name, origin=tuple(map(tuple, O)),
                            axis=j.axis))
    return Robot(joints, "urdf", r.name, r.unit, r.base, r.tool, link_names=r.link_names)


@pytest.mark.parametrize("name,family,position_only", [
    ("planar2", "planar-2r", True), ("planar3", "planar-3r", False), ("fighter", "yaw-pitch-pitch", True),
    ("puma560", "spherical-wrist", False), ("ur5", "ur", False)])
def test_closed_form_family_found_on_perturbed_urdf_export(name, family, position_only, tmp_path):
    armkit.save(armkit.load(name), tmp_path / f"{name}.urdf")
    exact = armkit.load(tmp_path / f"{name}.urdf")
    assert closed_form_family(exact) == family
    r = _perturbed(exact, 1e-5, seed=11)
    # the family's closed form on the export's ideal arm, or where the export keeps every axis meeting and parallel
    # where the ideal arm's are (frames turned about their origins leave the Puma's wrist spherical and its axes 1
    # and 2 meeting), the geometric family on the export's own axes, its branches named by the family
    cf = closed_form(r)
    assert (cf.names_from.family if getattr(cf, "names_from", None) is not None else cf.family) == family
    assert cf.family == ("geometric" if name == "puma560" else family)
    q = r.random_q(200, rng=5)
    T = armkit.fk(r, q)
    target = T[:, :3, 3] if position_only else T
    res = armkit.ik_all(r, target)
    ok = np.asarray(res.success)
    assert ok.any(axis=1).all()                  # the configuration we came from is always found
    qs = np.asarray(res.q)[ok]
    Tq = armkit.fk(r, qs)                        # judged on the true (perturbed) model
    Tt = np.broadcast_to(T[:, None], ok.shape + (4, 4))[ok]
    scale = r.reach
    assert np.abs(Tq[:, :3, 3] - Tt[:, :3, 3]).max() <= 1e-9 * scale
    if not position_only:
        assert np.abs(Tq[:, :3, :3] - Tt[:, :3, :3]).max() <= 1e-9
    if name in ("fighter", "puma560", "ur5"):    # 3-D arms keep every branch; a bent planar arm cannot
        assert ok.sum(axis=1).mean() >= 0.97 * np.asarray(armkit.ik_all(exact, target).success).sum(axis=1).mean()


# ------------------------------------------------------------------ choosing the chain
def _tree(tmp_path, extra: str = "") -> Path:
    text = f"""<?xml version="1.0"?>
<robot name="tree">
  <link name="base"/><link name="upper"/><link name="hand"/><link name="jaw_a"/><link name="jaw_b"/><link name="cam"/>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="wrist" type="continuous"><parent link="upper"/><child link="hand"/><origin xyz="0.5 0 0"/>
    <axis xyz="0 1 0"/></joint>
  <joint name="jaw_a_joint" type="prismatic"><parent link="hand"/><child link="jaw_a"/><origin xyz="0.1 0 0"/>
    <axis xyz="0 1 0"/><limit lower="0" upper="0.04" effort="1" velocity="1"/></joint>
  <joint name="jaw_b_joint" type="prismatic"><parent link="hand"/><child link="jaw_b"/><origin xyz="0.1 0 0"/>
    <axis xyz="0 -1 0"/><limit lower="0" upper="0.04" effort="1" velocity="1"/></joint>
  <joint name="cam_joint" type="fixed"><parent link="base"/><child link="cam"/><origin xyz="0 0 1"/></joint>
  {extra}
</robot>
"""
    p = tmp_path / "tree.urdf"
    p.write_text(text)
    return p


def test_several_tips_are_listed_and_tip_chooses(tmp_path):
    p = _tree(tmp_path)
    with pytest.raises(RobotFileError, match=r"2 possible tip links: jaw_a, jaw_b; choose one with tip="):
        armkit.load(p)
    r = armkit.load(p, tip="hand")
    assert r.joint_names == ("shoulder", "wrist") and r.joints[1].is_continuous
    assert set(r.ignored_joints) == {"jaw_a_joint", "jaw_b_joint", "cam_joint"}
    assert r.lower[1] == -math.inf and r.upper[1] == math.inf
    r2 = armkit.load(p, base="upper", tip="jaw_a")
    assert r2.joint_names == ("wrist", "jaw_a_joint") and r2.joint_types == "RP"
    # the links off the chain keep their place at q = 0 (for viewers)
    assert np.allclose(armkit.fk(r, [0.0, 0.0], link="cam")[:3, 3], [0, 0, 1])
    with pytest.raises(RobotFileError, match="not below base link"):
        armkit.load(p, base="hand", tip="upper")
    with pytest.raises(armkit.RobotDefinitionError, match="has no link 'nope'"):
        armkit.fk(r, [0.0, 0.0], link="nope")


def test_continuous_joint_ik_returns_the_turn_nearest_q0(tmp_path):
    r = armkit.load(_tree(tmp_path), tip="hand")
    q_true = np.array([0.4, 2.5])
    T = armkit.fk(r, q_true)
    res = armkit.ik(r, T, q0=np.array([0.3, 2.5 + 4 * math.pi + 0.1]), method="lm")
    assert res.success
    assert abs(float(res.q[1]) - (2.5 + 4 * math.pi)) < 1e-6



# ------------------------------------------------------------------ the comments before <robot>: description and source
_BANNER = """<!-- =================================================================================== -->
<!-- |    This document was autogenerated by xacro from arm.urdf.xacro                 | -->
<!-- |    EDITING THIS FILE BY HAND IS NOT RECOMMENDED                                 | -->
<!-- =================================================================================== -->
"""
_ARM = ('<robot name="arm"><link name="a"/><link name="b"/><joint name="j" type="revolute"><parent link="a"/>'
        '<child link="b"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>')


def _commented(tmp_path, comments: str) -> Robot:
    p = tmp_path / "arm.urdf"
    p.write_text('<?xml version="1.0"?>\n' + comments + _ARM)
    return armkit.load(p)


def test_xacro_banner_is_where_the_file_came_from_not_what_the_robot_is(tmp_path):
    """xacro writes a box of '=' rules and '|' borders at the top of the URDFs it makes (every ROS arm's, the
    example-robot-data files): it was shown as the robot's description ('ur5: =====...')."""
    r = _commented(tmp_path, _BANNER + "<!-- This file describes a one-joint test arm. -->\n")
    assert r.description == "This file describes a one-joint test arm."
    assert r.source.splitlines()[:2] == ["This document was autogenerated by xacro from arm.urdf.xacro",
                                        "EDITING THIS FILE BY HAND IS NOT RECOMMENDED"]
    assert "=" not in r.source and "|" not in r.source and r.source.endswith(f"(URDF file {tmp_path / 'arm.urdf'})")


def test_only_a_banner_describes_the_robot_by_its_name_in_the_users_language(tmp_path):
    from typer.testing import CliRunner

    from armkit.cli import app
    from armkit.locale.library import localize

    r = _commented(tmp_path, _BANNER)
    assert r.description == "URDF robot 'arm'" and localize(r.description, "ko") == "URDF 로봇 'arm'"
    assert localize(r.source, "ko").endswith(f"(URDF 파일 {tmp_path / 'arm.urdf'})")
    res = CliRunner().invoke(app, ["info", str(tmp_path / "arm.urdf"), "--lang", "ko"])
    assert res.exit_code == 0 and res.output.splitlines()[0] == "arm: URDF 로봇 'arm'", res.output
    words = " ".join(res.output.split())      # the path may wrap
    assert "URDF file" not in words and "URDF 파일" in words


def test_a_plain_comment_gives_its_first_line_as_the_description(tmp_path):
    r = _commented(tmp_path, "<!-- A test arm\n  made by hand -->\n<!-- | boxed note | -->\n")
    assert r.description == "A test arm"
    assert r.source.splitlines()[:2] == ["made by hand", "boxed note"]


# ------------------------------------------------------------------ malformed files: clear message + line
ROBOT_OK = '<link name="a"/><link name="b"/>'
JOINT = '<joint name="j" type="revolute"><parent link="a"/><child link="b"/>{inner}</joint>'
LIMIT = '<limit lower="-1" upper="1" effort="1" velocity="1"/>'
BAD = {
    "not xml": ("<robot name='x'><link name='a'></robot>", "not valid XML"),
    "empty file": ("", "not valid XML"),
    "wrong root": ("<model name='x'/>", "root element must be <robot>"),
    "no links": ("<robot name='x'/>", "has no <link>"),
    "link without name": ("<robot name='x'><link/></robot>", "<link> without a name"),
    "duplicate link": ("<robot name='x'><link name='a'/><link name='a'/></robot>", "defined twice"),
    "duplicate joint": (f"<robot name='x'>{ROBOT_OK}<link name='c'/>" + JOINT.format(inner=LIMIT)
                        + JOINT.format(inner=LIMIT).replace('"b"', '"c"') + "</robot>", "defined twice"),
    "unknown type": (f"<robot name='x'>{ROBOT_OK}" + JOINT.format(inner="").replace("revolute", "hinge")
                     + "</robot>", "unknown joint type 'hinge'"),
    "missing parent link": (f"<robot name='x'>{ROBOT_OK}" + JOINT.format(inner=LIMIT).replace(
        '<parent link="a"/>', '<parent link="zz"/>') + "</robot>", "parent link 'zz' does not exist"),
    "missing child element": (f"<robot name='x'>{ROBOT_OK}" + JOINT.format(inner=LIMIT).replace(
        '<child link="b"/>', '') + "</robot>", r'needs <child link="..."/>'),
    "self loop": (f"<robot name='x'>{ROBOT_OK}" + JOINT.format(inner=LIMIT).replace('"b"', '"a"')
                  + "</robot>", "parent and child are the same link"),
    "two parents": (f"<robot name='x'>{ROBOT_OK}<link name='c'/>" + JOINT.format(inner=LIMIT)
                    + JOINT.format(inner=LIMIT).replace('name="j"', 'name="k"').replace('"a"', '"c"')
                    + "</robot>", "has two parent joints"),
    "two roots": (f"<robot name='x'>{ROBOT_OK}<link name='c'/>" + JOINT.format(inner=LIMIT) + "</robot>",
                  "2 root links"),
    "cycle": ("<robot name='x'><link name='r'/><link name='a'/><link name='b'/>"
              + JOINT.format(inner=LIMIT) + JOINT.format(inner=LIMIT).replace('name="j"', 'name="k"').replace(
                  '<parent link="a"/><child link="b"/>', '<parent link="b"/><child link="a"/>')
              + "</robot>", "has two parent joints|cycle"),
    "nan origin": (f"<robot name='x'>{ROBOT_OK}" + JOINT.format(inner='<origin xyz="0 nan 0"/>' + LIMIT)
                   + "</robot>", "NaN or infinite"),
    "short rpy": (f"<robot name='x'>{ROBOT_OK}" + JOINT.format(inner='<origin rpy="0 1"/>' + LIMIT)
                  + "</robot>", "must be 3 numbers, got 2"),
    "text in xyz": (f"<robot name='x'>{ROBOT_OK}" + JOINT.format(inner='<origin xyz="0 a 0"/>' + LIMIT)
                    + "</robot>", "must be 3 numbers"),
    "zero axis": (f"<robot name='x'>{ROBOT_OK}" + JOINT.format(inner='<axis xyz="0 0 0"/>' + LIMIT)
                  + "</robot>", "zero length"),
    "lower above upper": (f"<robot name='x'>{ROBOT_OK}" + JOINT.format(
        inner='<limit lower="1" upper="-1" effort="1" velocity="1"/>') + "</robot>", "greater than upper"),
    "prismatic without limit": (f"<robot name='x'>{ROBOT_OK}" + JOINT.format(inner="").replace(
        "revolute", "prismatic") + "</robot>", "prismatic joint needs <limit"),
    "floating on chain": (f"<robot name='x'>{ROBOT_OK}<link name='c'/>" + JOINT.format(inner="").replace(
        "revolute", "floating") + JOINT.format(inner=LIMIT).replace('name="j"', 'name="k"').replace(
        '"a"', '"b"').replace('<child link="b"/>', '<child link="c"/>') + "</robot>", "floating joint"),
    "mimic on chain": (f"<robot name='x'>{ROBOT_OK}<link name='c'/>" + JOINT.format(inner=LIMIT)
                       + JOINT.format(inner=LIMIT + '<mimic joint="j"/>').replace('name="j"', 'name="k"').replace(
                           '"a"', '"b"', 1).replace('<child link="b"/>', '<child link="c"/>') + "</robot>",
                       "mimics joint 'j'"),
    "only fixed joints": (f"<robot name='x'>{ROBOT_OK}" + JOINT.format(inner="").replace("revolute", "fixed")
                          + "</robot>", "no moving joint"),
    "bad geometry": ("<robot name='x'><link name='a'><visual><geometry><cone/></geometry></visual></link>"
                     "<link name='b'/>" + JOINT.format(inner=LIMIT) + "</robot>", "unknown geometry <cone>"),
    "box with two sizes": ("<robot name='x'><link name='a'><visual><geometry><box size='1 2'/></geometry>"
                           "</visual></link><link name='b'/>" + JOINT.format(inner=LIMIT) + "</robot>",
                           "must be 3 numbers"),
    "entity expansion": ("<?xml version='1.0'?><!DOCTYPE r [<!ENTITY a 'aaaa'><!ENTITY b '&a;&a;&a;'>]>"
                         "<robot name='&b;'><link name='a'/></robot>", "no moving joint|not valid XML"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_malformed_urdf_gives_a_clear_message(case, tmp_path):
    text, pattern = BAD[case]
    p = tmp_path / "bad.urdf"
    p.write_text(text)
    with pytest.raises(RobotFileError, match=pattern) as info:
        armkit.load(p)
    assert str(p) in str(info.value)


def test_malformed_urdf_messages_carry_the_line(tmp_path):
    p = tmp_path / "bad.urdf"
    p.write_text('<?xml version="1.0"?>\n<robot name="x">\n  <link name="a"/>\n  <link name="b"/>\n'
                 '  <joint name="j" type="revolute">\n    <parent link="a"/><child link="zz"/>\n  </joint>\n</robot>\n')
    with pytest.raises(RobotFileError) as info:
        armkit.load(p)
    assert info.value.line == 6 and f"{p}:6" in str(info.value)


@pytest.mark.parametrize("case", ["not xml", "cycle", "zero axis", "mimic on chain"])
def test_malformed_urdf_cli_exit_code_2(case, tmp_path):
    from typer.testing import CliRunner

    from armkit.cli import app

    p = tmp_path / "bad.urdf"
    p.write_text(BAD[case][0])
    res = CliRunner().invoke(app, ["info", str(p)])
    assert res.exit_code == 2, res.output
    assert "Traceback" not in res.output and "error" in res.output


# ------------------------------------------------------------------ meshes
def _mesh_urdf(folder: Path, filename: str) -> Path:
    p = folder / "robot.urdf"
    p.write_text(f"""<robot name="m"><link name="a"><visual><geometry><mesh filename="{filename}" scale="2 2 2"/>
</geometry></visual></link><link name="b"/>""" + JOINT.format(inner=LIMIT) + "</robot>")
    return p


def test_mesh_paths_resolve_relative_and_through_package(tmp_path, monkeypatch):
    pkg = tmp_path / "share" / "my_arm_description"
    (pkg / "meshes").mkdir(parents=True)
    (pkg / "meshes" / "a.stl").write_text("solid a\nendsolid a\n")
    urdf_dir = pkg / "urdf"
    urdf_dir.mkdir()
    r = armkit.load(_mesh_urdf(urdf_dir, "../meshes/a.stl"))
    shape = r.links[0].visuals[0]
    assert shape.kind == "mesh" and shape.mesh_path == str((pkg / "meshes" / "a.stl").resolve())
    assert shape.scale == (2.0, 2.0, 2.0)
    # package:// found through the file's parent folders
    r = armkit.load(_mesh_urdf(urdf_dir, "package://my_arm_description/meshes/a.stl"))
    assert r.links[0].visuals[0].mesh_path == str((pkg / "meshes" / "a.stl").resolve())
    # ... and through ARMKIT_PACKAGE_PATH from anywhere
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.setenv("ARMKIT_PACKAGE_PATH", str(tmp_path / "share"))
    r = armkit.load(_mesh_urdf(elsewhere, "package://my_arm_description/meshes/a.stl"))
    assert r.links[0].visuals[0].mesh_path == str((pkg / "meshes" / "a.stl").resolve())


def test_missing_meshes_warn_once_and_kinematics_work(tmp_path, monkeypatch):
    monkeypatch.delenv("ARMKIT_PACKAGE_PATH", raising=False)
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    with pytest.warns(UserWarning, match="1 mesh file") as rec:
        r = armkit.load(_mesh_urdf(tmp_path, "package://nowhere/x.stl"))
    assert len(rec) == 1
    assert r.links[0].visuals[0].mesh_path is None
    assert np.allclose(armkit.fk(r, [0.0])[:3, 3], 0)


# ------------------------------------------------------------------ export of DH robots
@pytest.mark.parametrize("name", ["fighter", "stanford", "panda", "puma560"])
def test_dh_robot_saved_as_urdf_loads_with_yourdfpy_and_same_fk(name, tmp_path):
    r = armkit.load(name)
    p = armkit.save(r, tmp_path / f"{name}.urdf")
    back = armkit.load(p)
    assert back.joint_names == r.joint_names and back.joint_types == r.joint_types
    q = r.random_q(200, rng=2)
    s = r.unit_scale                         # URDF is in metres
    T, Tb = armkit.fk(r, q), armkit.fk(back, q * np.where(r.prismatic, s, 1.0))
    assert np.abs(Tb[:, :3, 3] - T[:, :3, 3] * s).max() <= 1e-12
    assert np.abs(Tb[:, :3, :3] - T[:, :3, :3]).max() <= 1e-12
    tip = [lk.name for lk in back.links][-1]
    assert np.abs(yourdfpy_fk(p, back, q[:50] * np.where(r.prismatic, s, 1.0), back.links[0].name, tip)
                  - Tb[:50]).max() <= 1e-12


def test_to_dh_reproduces_textbook_puma_table_from_modified_form():
    puma = armkit.load("puma560")                   # Corke's standard table
    twin = puma.to_dh("modified").to_dh("standard")  # through the general extractor twice
    assert np.allclose(twin.dh_table(), puma.dh_table(), atol=1e-12)


def test_cli_info_dh_and_convert(tmp_path):
    from typer.testing import CliRunner

    from armkit.cli import app

    run = CliRunner().invoke
    res = run(app, ["info", "so101", "--dh"])
    assert res.exit_code == 0 and "equivalent standard DH table" in res.output
    res = run(app, ["info", "so101"])
    assert "joints off the chain (ignored): gripper" in res.output
    res = run(app, ["convert", "so101", str(tmp_path / "so.toml")])
    assert res.exit_code == 0, res.output
    back = armkit.load(tmp_path / "so.toml")
    q = back.random_q(50, rng=0)
    assert np.allclose(armkit.fk(back, q), armkit.fk(armkit.load("so101"), q), atol=1e-12)
    p = _tree(tmp_path)
    res = run(app, ["fk", str(p), "--tip", "hand", "0", "0"])
    assert res.exit_code == 0, res.output
    res = run(app, ["fk", str(p), "0", "0"])
    assert res.exit_code == 2 and "possible tip links" in res.output


def test_cli_ik_pitch_and_direction_on_the_so101():
    from typer.testing import CliRunner

    from armkit.cli import app

    r = armkit.load("so101")
    q = np.radians([20, 10, 30, 40, 10])
    T = armkit.fk(r, q)
    run = CliRunner().invoke
    res = run(app, ["ik", "so101", *map(repr, T[:3, 3].tolist()), "--direction", *map(repr, T[:3, 2].tolist()),
                    "--json"])
    assert res.exit_code == 0, res.output
    import json

    sol = json.loads(res.output)["solutions"][0]
    qs = np.array(sol["q_rad"] if "q_rad" in sol else sol["q"])
    T2 = armkit.fk(r, qs)
    assert np.allclose(T2[:3, 3], T[:3, 3], atol=1e-9) and np.allclose(T2[:3, 2], T[:3, 2], atol=1e-8)
    res = run(app, ["ik", "so101", "0.25", "0.05", "0.1", "--pitch", "-60", "--deg"])
    assert res.exit_code == 0 and "branches solve the target" in res.output
    res = run(app, ["ik", "so101", "0.25", "0.05", "0.1", "--direction", "0", "0", "0"])
    assert res.exit_code == 2 and "non-zero" in res.output


def test_cli_fk_link(tmp_path):
    import json

    from typer.testing import CliRunner

    from armkit.cli import app

    r = armkit.load("so101")
    q = np.radians([10, 20, 30, 40, 50])
    res = CliRunner().invoke(app, ["fk", "so101", "10", "20", "30", "40", "50", "--deg", "--link", "wrist_link",
                                   "--json"])
    assert res.exit_code == 0, res.output
    assert np.allclose(json.loads(res.output)["pose"], armkit.fk(r, q, link="wrist_link"), atol=1e-12)
    res = CliRunner().invoke(app, ["fk", "so101", "0", "0", "0", "0", "0", "--link", "nope"])
    assert res.exit_code == 2 and "its links are: base_link" in res.output
