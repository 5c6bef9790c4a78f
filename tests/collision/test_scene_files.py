"""Scene files and the collision keys of robot files: what they build, and errors as file:line: field."""

from __future__ import annotations

import math

import numpy as np
import pytest

import armkit
from armkit.collision import Scene, SceneError, clearance
from armkit.errors import RobotFileError

GOOD = '''unit = "mm"
angle_unit = "deg"

[[shapes]]
type = "plane"
name = "floor"
normal = [0, 0, 2]
offset = -50

[[shapes]]
type = "box"
name = "crate"
center = [100, 0, 20]
size = [40, 60, 80]
rpy = [0, 0, 90]

[[shapes]]
type = "sphere"
center = [0, 100, 50]
radius = 10

[[shapes]]
type = "cylinder"
center = [0, -100, 50]
radius = 10
length = 100

[[shapes]]
type = "capsule"
a = [-100, 0, 0]
b = [-100, 0, 100]
radius = 5
allow = ["turret"]
'''


def test_scene_file_builds_every_shape(tmp_path):
    path = tmp_path / "scene.toml"
    path.write_text(GOOD)
    scene = armkit.Scene.load(str(path))
    assert scene.unit == "mm" and [s.kind for s in scene] == ["plane", "box", "sphere", "cylinder", "capsule"]
    floor, crate = scene.shapes[0], scene.shapes[1]
    np.testing.assert_allclose(floor.normal, [0, 0, 1])
    assert floor.offset == pytest.approx(-25.0)           # normal [0, 0, 2], offset -50: z <= -25
    np.testing.assert_allclose(crate.pose[:3, :3], [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-15)
    assert scene.shapes[4].allow == ("turret",) and scene.shapes[4].size == (5.0, 100.0)
    in_m = scene.in_unit("m")
    assert in_m.shapes[1].size == pytest.approx((0.04, 0.06, 0.08)) and in_m.shapes[0].offset == pytest.approx(-0.025)


@pytest.mark.parametrize("text, where", [
    ('[[shapes]]\ntype = "cone"\n', "scene.toml:2: shapes[1].type"),
    ('[[shapes]]\ntype = "box"\ncenter = [0, 0, 0]\nsize = [1, 2]\n', "scene.toml:4: shapes[1].size"),
    ('[[shapes]]\ntype = "sphere"\ncenter = [0, 0, 0]\n', "scene.toml:1: shapes[1].radius"),
    ('[[shapes]]\ntype = "sphere"\ncenter = [0, 0, 0]\nradius = -1\n', "scene.toml:4: shapes[1].radius"),
    ('[[shapes]]\ntype = "plane"\nnormal = [0, 0, 0]\n', "scene.toml:3: shapes[1].normal"),
    ('[[shapes]]\ntype = "box"\ncenter = [0, 0, 0]\nsize = [1, 1, 1]\ncolour = "red"\n', "scene.toml:5: shapes[1].colour"),
    ('unit = "inch"\n', "scene.toml:1: unit"),
    ('[[shapes]]\ntype = "sphere"\ncenter = [0, 0, "x"]\nradius = 1\n', "scene.toml:3: shapes[1].center"),
    # TOML integers have any size: one beyond the float range raised OverflowError (a fuzz run's traceback)
    ('[[shapes]]\ntype = "sphere"\ncenter = [0, 0, 1' + "0" * 400 + ']\nradius = 1\n', "scene.toml:3: shapes[1].center"),
    ('[[shapes]]\ntype = "sphere"\ncenter = [0, 0, 0]\nradius = 1' + "0" * 400 + '\n', "scene.toml:4: shapes[1].radius"),
    ('shapes = 3\n', "scene.toml:1: shapes"),
    ('[[shapes]\n', "scene.toml:1: not valid TOML"),
])
def test_scene_file_errors_name_file_line_field(tmp_path, text, where):
    path = tmp_path / "scene.toml"
    path.write_text(text)
    with pytest.raises(RobotFileError, match=None) as info:
        Scene.load(str(path))
    assert where in str(info.value).replace(str(tmp_path) + "/", "")


def test_missing_scene_file():
    with pytest.raises(RobotFileError, match="no such scene file"):
        Scene.load("/nonexistent/scene.toml")


def test_python_constructors_check_their_input():
    with pytest.raises(SceneError, match="box size"):
        Scene.box([0, 0, 0], [1, 0, 1])
    with pytest.raises(SceneError, match="normal must not be zero"):
        Scene.plane([0, 0, 0], 1)
    with pytest.raises(SceneError, match="sphere radius"):
        Scene.sphere([0, 0, 0], math.nan)
    with pytest.raises(SceneError, match="a Scene holds armkit Shapes"):
        Scene([("box", 1)])  # type: ignore[list-item]
    s = Scene([Scene.sphere([0, 0, 0], 1, name="a")]).with_shape(Scene.box([1, 1, 1], [1, 1, 1], name="b"))
    assert [x.name for x in s] == ["a", "b"] and [x.name for x in s.without("a")] == ["b"]


ROBOT = '''name = "two"
unit = "m"
link_radius = 0.05
allow_collision = [["link1", "link2"]]

[[joints]]
a = 1.0

[[joints]]
a = 0.5
link_radius = 0.02

[[body]]
type = "box"
name = "pedestal"
center = [0, 0, -0.25]
size = [0.4, 0.4, 0.5]

[[scene]]
type = "plane"
name = "ground"
normal = [0, 0, 1]
offset = -0.5
'''


def test_robot_file_collision_keys(tmp_path):
    path = tmp_path / "two.toml"
    path.write_text(ROBOT)
    arm = armkit.load(str(path))
    spec = arm.collision
    assert spec.link_radius == (0.05, 0.02)
    assert [s.name for s in spec.body] == ["pedestal"] and [s.name for s in spec.scene] == ["ground"]
    assert spec.allow_collision == (("link1", "link2"),)
    # arm flat along x at z = 0, ground at z = -0.5: 0.45 below link1, 0.48 below link2; pedestal on the base
    assert clearance(arm, [0.0, 0.0]) == pytest.approx(0.45, abs=1e-12)


@pytest.mark.parametrize("change, where", [
    (("link_radius = 0.05", "link_radius = -1"), "two.toml:3: link_radius"),
    (("link_radius = 0.02", 'link_radius = "thin"'), "two.toml:11: joints[2].link_radius"),
    (('allow_collision = [["link1", "link2"]]', 'allow_collision = [["link1", "elbow"]]'), "two.toml:4: allow_collision"),
    (('type = "box"', 'type = "plane"'), "two.toml:16: body[1].center: unknown key for a plane"),
    (('size = [0.4, 0.4, 0.5]', 'size = [0.4, 0.4]'), "two.toml:17: body[1].size"),
    (('offset = -0.5', 'offset = "low"'), "two.toml:23: scene[1].offset"),
    (("link_radius = 0.05", "link_radius = 1" + "0" * 400), "two.toml:3: link_radius"),     # beyond the float range
])
def test_robot_file_collision_errors(tmp_path, change, where):
    path = tmp_path / "two.toml"
    path.write_text(ROBOT.replace(*change))
    with pytest.raises(RobotFileError) as info:
        armkit.load(str(path))
    assert where in str(info.value).replace(str(tmp_path) + "/", "")
