"""Robot construction, validation, robot files and bundled robots."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import armkit
from armkit import Joint, Robot
from armkit.errors import RobotDefinitionError, RobotFileError, ShapeError, UnknownRobotError

BUNDLED = armkit.bundled_robots()


def test_bundled_robot_list():
    for name in ("fighter", "planar2", "planar3", "puma560", "stanford", "ur5", "panda", "iiwa14"):
        assert name in BUNDLED


@pytest.mark.parametrize("name", BUNDLED)
def test_every_bundled_robot_cites_its_source(name):
    r = armkit.load(name)
    assert len(r.source) > 40 and r.description


def test_fighter_is_the_club_report_arm():
    r = armkit.load("fighter")
    assert r.unit == "mm" and r.convention == "standard" and r.joint_types == "RRR"
    assert np.allclose(r.dh_table(), [[0, 36, 0, np.pi / 2], [0, 0, 77.2, 0], [0, 0, 100, 0]])
    assert "77.3" in r.source  # the report's other figure is mentioned


def test_model_is_immutable():
    r = armkit.load("planar2")
    with pytest.raises(AttributeError):
        r.name = "x"  # type: ignore[misc]
    with pytest.raises(ValueError):
        r.base[0, 0] = 2.0
    with pytest.raises(ValueError):
        r.chain.fixed[0, 0, 0] = 2.0


@pytest.mark.parametrize("kwargs, message", [
    ({"a": float("nan")}, "a must be a finite number"),
    ({"d": float("inf")}, "d must be a finite number"),
    ({"lower": 1.0, "upper": -1.0}, "lower limit 1 is greater than upper limit -1"),
    ({"kind": "spherical"}, "type must be 'revolute' or 'prismatic'"),
])
def test_joint_rejects_nonsense(kwargs, message):
    with pytest.raises(RobotDefinitionError, match=message):
        Joint(**kwargs)


def test_robot_rejects_nonsense():
    with pytest.raises(RobotDefinitionError, match="has no joints"):
        Robot([])
    with pytest.raises(RobotDefinitionError, match="convention must be"):
        Robot([Joint()], convention="craig")
    with pytest.raises(RobotDefinitionError, match="unit must be"):
        Robot([Joint()], unit="inch")
    with pytest.raises(RobotDefinitionError, match="names must be unique"):
        Robot([Joint(name="a"), Joint(name="a")])
    with pytest.raises(RobotDefinitionError, match="tool must be a 4x4"):
        Robot([Joint()], tool=np.eye(3))
    with pytest.raises(RobotDefinitionError, match="not a rigid transform"):
        Robot([Joint()], base=2 * np.eye(4))


def test_check_q_messages():
    r = armkit.load("fighter")
    with pytest.raises(ShapeError, match=r"q must have shape \(\.\.\., 3\) for robot 'fighter', got \(4,\)"):
        armkit.fk(r, [0, 0, 0, 0])
    with pytest.raises(ShapeError, match="NaN"):
        armkit.fk(r, [0, float("nan"), 0])
    with pytest.raises(ShapeError, match="numeric"):
        armkit.fk(r, ["a", "b", "c"])


def test_limits_helpers():
    r = armkit.load("puma560")
    q = np.zeros(6)
    assert r.within_limits(q)
    q[4] = math.radians(120)
    assert not r.within_limits(q)
    assert "wrist_bend = 120.000 deg outside [-100.000, 100.000] deg" in r.limit_violations(q)[0]
    qs = r.random_q(1000, rng=3)
    assert r.within_limits(qs).all()


def test_unknown_robot_lists_valid_names():
    with pytest.raises(UnknownRobotError, match="fighter, iiwa14, panda"):
        armkit.load("fightr")


@pytest.mark.parametrize("name", BUNDLED)
def test_save_load_round_trip(name, tmp_path):
    r = armkit.load(name)
    path = armkit.save(r, tmp_path / f"{name}.toml")
    r2 = armkit.load(path)
    r = r if r.is_dh else r.to_dh()   # a URDF chain goes to TOML as its DH twin
    assert r2.name == r.name and r2.unit == r.unit and r2.convention == r.convention
    assert r2.joint_names == r.joint_names and r2.link_names == r.link_names
    assert np.allclose(r2.dh_table(), r.dh_table(), atol=1e-12)
    assert np.allclose(r2.lower, r.lower, atol=1e-12) and np.allclose(r2.upper, r.upper, atol=1e-12)
    assert np.allclose(r2.tool, r.tool, atol=1e-12) and np.allclose(r2.base, r.base, atol=1e-12)
    q = r.random_q(5, rng=0)
    assert np.allclose(armkit.fk(r2, q), armkit.fk(r, q), atol=1e-12)


GOOD = """name = "mine"
unit = "mm"

[[joints]]
name = "j1"
d = 10
alpha = 90

[[joints]]
name = "j2"
a = 50
limits = [-90, 90]
"""


def _write(tmp_path: Path, text: str) -> Path:
    p = tmp_path / "arm.toml"
    p.write_text(text)
    return p


def test_user_file_loads_with_degrees(tmp_path):
    r = armkit.load(_write(tmp_path, GOOD))
    assert r.joints[0].alpha == pytest.approx(np.pi / 2)
    assert r.joints[1].upper == pytest.approx(np.pi / 2)
    r_rad = armkit.load(_write(tmp_path, GOOD.replace('unit = "mm"', 'unit = "mm"\nangle_unit = "rad"')))
    assert r_rad.joints[0].alpha == 90.0


@pytest.mark.parametrize("edit, where", [
    (lambda s: s.replace("a = 50", "a = nan"), r"arm\.toml:11: joints\[2\]\.a: must be a finite number"),
    (lambda s: s.replace("a = 50", 'a = "fifty"'), r"arm\.toml:11: joints\[2\]\.a: must be a finite number"),
    (lambda s: s.replace("limits = [-90, 90]", "limits = [90, -90]"),
     r"arm\.toml:12: joints\[2\]\.limits: lower limit 90 is greater than upper limit -90"),
    (lambda s: s.replace("d = 10", "dd = 10"), r"arm\.toml:6: joints\[1\]\.dd: unknown key"),
    (lambda s: s.replace('unit = "mm"', 'unit = "furlong"'), r"arm\.toml:2: unit: unit must be one of"),
    (lambda s: s.replace("alpha = 90", "alpha = [90"), r"arm\.toml:\d+: not valid TOML"),
    (lambda s: s.split("[[joints]]")[0], r"arm\.toml: joints: the file needs at least one \[\[joints\]\]"),
    (lambda s: s + '\n[[joints]]\ntype = "prismatic"\n', r"arm\.toml:\d+: joints\[3\]\.limits: a prismatic joint needs"),
    (lambda s: s + "\n[tool]\nxyz = [1, 2]\n", r"arm\.toml:\d+: tool\.xyz: must be a list of 3 numbers"),
])
def test_malformed_files_name_file_line_field(tmp_path, edit, where):
    with pytest.raises(RobotFileError, match=where):
        armkit.load(_write(tmp_path, edit(GOOD)))
