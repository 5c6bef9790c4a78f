"""Issue 24, item 6 and the "files and content" findings: what is loaded is what is saved (the fighter's torso,
ground and link radius survive ``save``/``convert``; nothing writes onto its own input), URDFs and scenes have
the robot files' size limits, scene mesh paths stay in the scene's folder, a bad ``--host`` and an unreadable
mesh are one-line errors, and ``traj`` refuses 1 step, a path past the memory budget and lengths whose FK
overflows.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np
import pytest

import armkit
from armkit._limits import check_mesh_file
from armkit.collision import in_collision
from armkit.errors import LimitError, RobotFileError, SceneError, SceneFileError, WriteError
from armkit.model.files import MAX_FILE_BYTES, MAX_JOINTS, dumps
from hardening_helpers import invoke

BELOW_FLOOR_MM = ("100", "0", "-30")          # the forearm would hit the ground by 13 mm
BELOW_FLOOR_M = ("0.1", "0", "-0.03")


def no_traceback(code: int, out: str, exc: BaseException | None) -> None:
    assert exc is None, exc
    assert "Traceback" not in out and code in (0, 1, 2), (code, out[-2000:])


# ---------------------------------------------------------------------------- 1. load(save(r)) collides as r
def test_the_fighter_refuses_a_target_below_its_floor():
    code, out, exc = invoke("ik", "fighter", *BELOW_FLOOR_MM)
    no_traceback(code, out, exc)
    assert code == 1 and "ground" in out


@pytest.mark.parametrize("suffix, target", [(".toml", BELOW_FLOOR_MM), (".urdf", BELOW_FLOOR_M)])
def test_converted_fighter_keeps_its_surroundings(tmp_path, suffix, target):
    dst = tmp_path / f"fighter{suffix}"
    code, out, exc = invoke("convert", "fighter", str(dst))
    no_traceback(code, out, exc)
    assert code == 0
    code, out, exc = invoke("ik", str(dst), *target)
    no_traceback(code, out, exc)
    assert code == 1 and "ground" in out           # before: "4 of 4 branches solve the target", exit 0


@pytest.mark.parametrize("suffix", [".toml", ".urdf"])
def test_load_of_save_has_the_same_collision_behaviour(tmp_path, suffix):
    r = armkit.load("fighter")
    back = armkit.load(armkit.save(r, tmp_path / f"f{suffix}"))
    spec, spec2 = r.collision, back.collision
    assert [s.name for s in spec2.body] == ["torso"] and [s.name for s in spec2.scene] == ["ground"]
    scale = r.unit_scale / back.unit_scale
    assert np.allclose(np.array(spec2.link_radius) / scale, spec.link_radius)
    q = r.random_q(2000, rng=7)
    hits = in_collision(r, q)
    assert 0 < hits.mean() < 1
    assert np.array_equal(in_collision(back, q), hits)


def test_a_second_save_changes_nothing(tmp_path):
    r = armkit.load("fighter")
    armkit.save(r, tmp_path / "a.toml")
    back = armkit.load(tmp_path / "a.toml")
    assert dumps(back) == dumps(r)
    armkit.save(back, tmp_path / "b.urdf")
    again = armkit.load(tmp_path / "b.urdf")
    assert len(again.collision.body) == 1 and np.array_equal(again.to_dh().collision.link_radius, (0.008,) * 3)


def test_a_urdf_chain_twin_carries_the_surroundings(tmp_path):
    armkit.save(armkit.load("fighter"), tmp_path / "f.urdf")
    code, out, exc = invoke("convert", str(tmp_path / "f.urdf"), str(tmp_path / "f.toml"))
    assert code == 0, out
    assert "[[scene]]" in (tmp_path / "f.toml").read_text()
    code, out, exc = invoke("ik", str(tmp_path / "f.toml"), *BELOW_FLOOR_M)
    assert code == 1 and "ground" in out


URDF_WITH_EXTRAS = """<?xml version="1.0"?>
<!-- my arm: keep this comment -->
<robot name="arm">
  <link name="base"/>
  <link name="l1"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <transmission name="t1"><type>transmission_interface/SimpleTransmission</type></transmission>
  <gazebo reference="l1"><material>Gazebo/Red</material></gazebo>
</robot>
"""


@pytest.mark.parametrize("name, text", [("arm.urdf", URDF_WITH_EXTRAS), ("arm.toml", None)])
def test_convert_onto_its_own_input_is_refused(tmp_path, name, text):
    p = tmp_path / name
    if text is None:
        armkit.save(armkit.load("fighter"), p)
        p.write_text("# my notes\n" + p.read_text())
    else:
        p.write_text(text)
    before = p.read_bytes()
    for dst in (str(p), str(tmp_path / "." / name), f"{tmp_path}/../{tmp_path.name}/{name}"):
        code, out, exc = invoke("convert", str(p), dst)
        no_traceback(code, out, exc)
        assert code == 2 and "read from" in out and "another file" in out
        assert p.read_bytes() == before
    with pytest.raises(WriteError, match="read from"):
        armkit.save(armkit.load(p), p)
    assert p.read_bytes() == before
    code, out, exc = invoke("convert", str(p), str(tmp_path / ("copy" + p.suffix)))   # elsewhere: fine
    assert code == 0, out


def test_save_onto_a_bundled_robot_is_refused():
    r = armkit.load("fighter")
    with pytest.raises(WriteError, match="read from"):
        armkit.save(r, armkit.model.files.BUNDLED_DIR / "fighter.toml")


# ---------------------------------------------------------------------------- 2. sizes
def star_urdf(path: Path, children: int) -> Path:
    out = ['<robot name="star">', '<link name="root"/>']
    for i in range(children):
        out.append(f'<link name="l{i}"/><joint name="j{i}" type="revolute"><parent link="root"/><child link="l{i}"/>'
                   '<axis xyz="0 0 1"/><limit lower="-1" upper="1"/></joint>')
    path.write_text("\n".join(out + ["</robot>"]))
    return path


def test_a_urdf_over_16_mb_is_refused_unread(tmp_path):
    p = tmp_path / "huge.urdf"
    with open(p, "wb") as f:
        f.truncate(MAX_FILE_BYTES + 1)          # sparse: nothing is written
    start = time.perf_counter()
    with pytest.raises(RobotFileError, match="at most 16,777,216"):
        armkit.load(p)
    assert time.perf_counter() - start < 1.0


def test_a_urdf_with_more_than_1000_joints_is_refused(tmp_path):
    with pytest.raises(RobotFileError, match=f"1,001 <joint> elements.*at most {MAX_JOINTS:,} joints"):
        armkit.load(star_urdf(tmp_path / "star.urdf", MAX_JOINTS + 1), tip="l7")
    assert armkit.load(star_urdf(tmp_path / "ok.urdf", MAX_JOINTS), tip="l7").n == 1


def test_a_star_of_10000_children_answers_at_once(tmp_path):
    p = star_urdf(tmp_path / "star.urdf", 10_000)
    start = time.perf_counter()
    code, out, exc = invoke("fk", str(p), "0.1", "--tip", "l7")
    took = time.perf_counter() - start
    no_traceback(code, out, exc)
    assert code == 2 and "at most 1,000 joints" in out
    assert took < 3.0, took                     # before: 9 s (fk), 29 s (info), "101 minutes" in the issue


def test_a_scene_file_over_16_mb_is_refused_unread(tmp_path):
    p = tmp_path / "huge.toml"
    with open(p, "wb") as f:
        f.truncate(16 * 1024 ** 2 + 1)
    with pytest.raises(SceneFileError, match="at most 16,777,216"):
        armkit.Scene.load(str(p))


def test_a_scene_of_more_than_10000_shapes_is_refused(tmp_path):
    p = tmp_path / "many.toml"
    p.write_text("[[shapes]]\ntype = 'sphere'\ncenter = [0, 0, 0]\nradius = 1\n" * 10_001)
    start = time.perf_counter()
    with pytest.raises(SceneFileError, match="10,001 shapes.*at most 10,000"):
        armkit.Scene.load(str(p))
    assert time.perf_counter() - start < 5.0
    code, out, exc = invoke("ik", "fighter", "100", "0", "60", "--scene", str(p))
    no_traceback(code, out, exc)
    assert code == 2 and "10,001 shapes" in out


def test_a_3_gb_stl_is_refused_by_the_mesh_limit(tmp_path):
    stl = tmp_path / "big.stl"
    with open(stl, "wb") as f:
        f.truncate(3 * 2 ** 30)                 # sparse: 3 GB that take no disk
    with pytest.raises(LimitError, match="more than the limit"):
        check_mesh_file(stl)
    scene = tmp_path / "scene.toml"
    scene.write_text('[[shapes]]\ntype = "mesh"\npath = "big.stl"\n')
    start = time.perf_counter()
    with pytest.raises(SceneFileError, match="3 GiB.*not read"):
        armkit.Scene.load(str(scene))
    assert time.perf_counter() - start < 1.0
    code, out, exc = invoke("ik", "fighter", "100", "0", "60", "--scene", str(scene))
    no_traceback(code, out, exc)
    assert code == 2 and "ARMKIT_MESH_LIMIT_MB" in out


# ---------------------------------------------------------------------------- 3. scene mesh paths
@pytest.fixture
def outside_scene(tmp_path):
    (tmp_path / "secret.stl").write_bytes(b"solid x\nendsolid x\n")
    inner = tmp_path / "cell"
    inner.mkdir()
    (inner / "meshes").mkdir()
    (inner / "meshes" / "fixture.stl").write_bytes(b"solid x\nendsolid x\n")
    return inner, tmp_path / "secret.stl"


@pytest.mark.parametrize("path", ["../secret.stl", "ABS", "file://ABS", "package://../secret.stl",
                                  "meshes/../../secret.stl"])
def test_scene_mesh_paths_outside_the_folder_are_refused(outside_scene, path, monkeypatch):
    monkeypatch.delenv("ARMKIT_ALLOW_OUTSIDE", raising=False)
    inner, secret = outside_scene
    path = path.replace("ABS", str(secret))
    scene = inner / "scene.toml"
    scene.write_text(f'[[shapes]]\ntype = "mesh"\npath = "{path}"\n')
    with pytest.raises(SceneFileError, match="leads outside the file's folder") as info:
        armkit.Scene.load(str(scene))
    assert "scene.toml:3: shapes[1].path" in str(info.value)
    if not path.startswith("package://"):
        from armkit.collision.files import load_scene

        assert load_scene(scene, allow_outside=True).shapes[0].mesh_path == str(secret.resolve())
        monkeypatch.setenv("ARMKIT_ALLOW_OUTSIDE", "1")
        assert armkit.Scene.load(str(scene)).shapes[0].mesh_path == str(secret.resolve())


def test_scene_mesh_paths_inside_the_folder_and_package_path_load(outside_scene, monkeypatch, tmp_path):
    monkeypatch.delenv("ARMKIT_ALLOW_OUTSIDE", raising=False)
    inner, _ = outside_scene
    scene = inner / "scene.toml"
    scene.write_text(f'[[shapes]]\ntype = "mesh"\npath = "meshes/fixture.stl"\n'
                     f'[[shapes]]\ntype = "mesh"\npath = "{inner / "meshes" / "fixture.stl"}"\n'
                     f'[[shapes]]\ntype = "mesh"\npath = "package://cell/meshes/fixture.stl"\n')
    monkeypatch.setenv("ARMKIT_PACKAGE_PATH", str(tmp_path))
    sc = armkit.Scene.load(str(scene))
    assert {s.mesh_path for s in sc} == {str((inner / "meshes" / "fixture.stl").resolve())}
    scene.write_text('[[shapes]]\ntype = "mesh"\npath = "meshes/missing.stl"\n')
    with pytest.raises(SceneFileError, match="mesh file not found"):
        armkit.Scene.load(str(scene))


def test_robot_file_body_meshes_follow_the_same_rules(outside_scene, monkeypatch):
    monkeypatch.delenv("ARMKIT_ALLOW_OUTSIDE", raising=False)
    inner, secret = outside_scene
    p = inner / "arm.toml"
    p.write_text(f'[[joints]]\na = 1\n[[body]]\ntype = "mesh"\npath = "{secret}"\n')
    with pytest.raises(RobotFileError, match="leads outside"):
        armkit.load(p)
    assert armkit.load(p, allow_outside=True).collision.body[0].mesh_path == str(secret.resolve())


# ---------------------------------------------------------------------------- 4. small
@pytest.mark.parametrize("host", ["example.invalid", "192.0.2.1"])
def test_a_host_that_cannot_be_bound_is_one_line(host):
    code, out, exc = invoke("view", "panda", "--host", host)
    no_traceback(code, out, exc)
    assert code == 2 and "cannot listen on --host" in out and "gaierror" not in out
    assert len(out.strip().splitlines()) <= 2


def test_an_unreadable_mesh_names_the_file_not_the_library(tmp_path):
    pytest.importorskip("coal")
    bad = tmp_path / "bad.stl"
    bad.write_bytes(b"\x00\x01 this is not a mesh" * 10)
    scene = armkit.Scene([armkit.Scene.mesh(str(bad), name="fixture")])
    with pytest.raises(SceneError) as info:
        armkit.collisions(armkit.load("fighter"), np.zeros(3), scene)
    text = str(info.value)
    assert "bad.stl" in text and "not a valid STL, OBJ or DAE file" in text
    assert not any(w in text.lower() for w in ("assimp", "coal", "c++", "exception", "hpp"))


# ---------------------------------------------------------------------------- 5. traj
def test_traj_one_step_is_refused_and_two_report_a_speed():
    code, out, exc = invoke("traj", "planar2", "--line", "1.2,0.2", "0.6,0.9", "--steps", "1")
    no_traceback(code, out, exc)
    assert code == 2 and "steps must be at least 2" in out      # before: exit 0, "peak joint speed: q1 0, q2 0"
    code, out, exc = invoke("traj", "planar2", "--line", "1.2,0.2", "0.6,0.9", "--steps", "2", "--json")
    assert code == 0, out
    import json

    assert min(json.loads(out)["max_abs_qd"]) > 0


def test_traj_steps_past_the_memory_budget_are_refused_before_allocating():
    start = time.perf_counter()
    code, out, exc = invoke("traj", "planar2", "--line", "1.2,0.2", "0.6,0.9", "--steps", "100000000")
    no_traceback(code, out, exc)
    assert code == 2 and "100,000,001 samples" in out and "ARMKIT_MEMORY_LIMIT" in out   # before: 3.9 GB
    assert time.perf_counter() - start < 2.0
    code, out, exc = invoke("traj", "planar2", "--arc", "90", "0.8,0", "1.1,0", "--steps", "100000000")
    assert code == 2 and "memory" in out


@pytest.mark.parametrize("rows, joint, field", [
    ("[[joints]]\nname = 'j1'\na = 1e308\n[[joints]]\nname = 'j2'\na = 1e308\n", "j2", "joints[2].a"),
    ("[[joints]]\nname = 'j1'\na = 1e308\nd = 1e308\n", "j1", "joints[1].a"),
    ("[[joints]]\nname = 'j1'\nd = -1.5e308\n[[joints]]\nname = 'j2'\ntype = 'prismatic'\n"
     "limits = [0, 1e308]\n", "j2", "joints[2].limits"),
])
def test_dh_lengths_whose_fk_overflows_are_refused_naming_the_joint(tmp_path, rows, joint, field):
    p = tmp_path / "big.toml"
    p.write_text(rows)
    with pytest.raises(RobotFileError, match=f"joint '{joint}'.*overflow") as info:
        armkit.load(p)
    assert field in str(info.value) and "big.toml:" in str(info.value)
    code, out, exc = invoke("fk", str(p), *(["0"] * rows.count("[[joints]]")))
    no_traceback(code, out, exc)
    assert code == 2 and joint in out


def test_large_but_finite_dh_lengths_still_load_with_finite_fk(tmp_path):
    p = tmp_path / "big.toml"
    p.write_text("[[joints]]\na = 8e307\n[[joints]]\na = 8e307\n")
    r = armkit.load(p)
    assert np.all(np.isfinite(armkit.fk(r, [0.0, 0.0]))) and math.isfinite(r.reach)
    p.write_text("[[joints]]\na = 1e308\n[[joints]]\na = 1\n[tool]\nxyz = [1e308, 0, 0]\n")
    with pytest.raises(RobotFileError, match="tool.xyz"):
        armkit.load(p)
