"""Issue 10, item 5: save then load gives the same robot back, value for value (tomli_w writer)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import armkit
from armkit.errors import RobotFileError
from armkit.model import Joint, Robot
from armkit.model.files import dumps, load, save

NAMES = st.text(st.characters(blacklist_categories=("Cs",)), min_size=1, max_size=30)
TEXT = st.text(st.characters(blacklist_categories=("Cs",)), max_size=60)
ANGLE = st.floats(-2 * math.pi, 2 * math.pi, allow_nan=False, allow_infinity=False)
LENGTH = st.floats(-5.0, 5.0, allow_nan=False, allow_infinity=False)


@st.composite
def robots(draw):
    n = draw(st.integers(1, 4))
    joints = []
    for i in range(n):
        kind = draw(st.sampled_from(["revolute", "prismatic"]))
        lo = draw(st.one_of(st.just(-math.inf), st.floats(-10, 0, allow_nan=False)))
        hi = draw(st.one_of(st.just(math.inf), st.floats(0, 10, allow_nan=False)))
        joints.append(Joint(kind, draw(ANGLE), draw(LENGTH), draw(LENGTH), draw(ANGLE), lo, hi,
                            draw(NAMES) + f"#{i}"))
    return Robot(joints, draw(st.sampled_from(["standard", "modified"])), draw(NAMES),
                 draw(st.sampled_from(["m", "mm", "cm"])), description=draw(TEXT), source=draw(TEXT))


def assert_same(a: Robot, b: Robot) -> None:
    for f in ("name", "description", "source", "convention", "unit", "link_names"):
        assert getattr(a, f) == getattr(b, f), f
    assert len(a.joints) == len(b.joints)
    for ja, jb in zip(a.joints, b.joints):
        for f in ("kind", "theta", "d", "a", "alpha", "lower", "upper", "name"):
            assert getattr(ja, f) == getattr(jb, f), (f, getattr(ja, f), getattr(jb, f))
    np.testing.assert_allclose(a.base, b.base, atol=1e-12)
    np.testing.assert_allclose(a.tool, b.tool, atol=1e-12)


@given(robots())
def test_load_of_save_is_the_same_robot(tmp_path_factory, r):
    p = tmp_path_factory.mktemp("rt") / "arm.toml"
    save(r, p)
    back = load(p)
    assert_same(r, back)
    assert dumps(back) == dumps(r)              # a second save changes nothing


@pytest.mark.parametrize("name", ["Kim's arm", 'the "best" arm', 'three """ quotes', "back\\nslash",
                                  "tab\tand\x01control\x1b[31m", "[/]markup", "줄\n바꿈", "ends with \\"])
def test_awkward_names_and_descriptions(tmp_path, name):
    r = armkit.load("planar2")
    r2 = Robot(r.joints, r.convention, name, r.unit, description=name + "\n" + name, source='"""' + name)
    save(r2, tmp_path / "a.toml")
    assert_same(r2, load(tmp_path / "a.toml"))


def test_infinite_limits_round_trip(tmp_path):
    r = Robot([Joint("revolute", a=1.0, lower=-math.inf, upper=math.inf),
               Joint("prismatic", lower=0.0, upper=math.inf)], name="free")
    save(r, tmp_path / "f.toml")
    back = load(tmp_path / "f.toml")
    assert back.joints[0].lower == -math.inf and back.joints[1].upper == math.inf


def test_every_bundled_robot_round_trips_without_drift(tmp_path):
    for name in armkit.model.bundled_robots():
        r = load(name)
        if not r.is_dh:
            continue
        save(r, tmp_path / f"{name}.toml")
        back = load(tmp_path / f"{name}.toml")
        assert_same(r, back)
        save(back, tmp_path / "again.toml")
        assert (tmp_path / "again.toml").read_text() == (tmp_path / f"{name}.toml").read_text()


@pytest.mark.parametrize("text,match", [
    ('\ufeffname = "x"\n[[joints]]\na = 1\n', None),                                 # BOM: accepted
    ('joints = [1, 2]\n', "must be a table"),
    ('unit = ["m"]\n[[joints]]\na = 1\n', "unit: must be a string"),
    ('link_names = "abcd"\n[[joints]]\na = 1\n', "link_names: must be a list of strings"),
    ('name = 5\n[[joints]]\na = 1\n', "name: must be a string"),
    ("x = " + "[" * 5000 + "]" * 5000 + "\n", "nested too deeply|not valid TOML"),
    ('[[joints]]\na = 1' + "0" * 400 + '\n', "finite number"),
    ('[[joints]]\na = nan\n', "finite number"),
    ('[[joints]]\nlimits = [nan, 1]\n', "inf allowed"),
])
def test_malformed_files_give_file_errors(tmp_path, text, match):
    p = tmp_path / "bad.toml"
    p.write_text(text, encoding="utf-8")
    if match is None:
        assert load(p).n == 1
    else:
        with pytest.raises(RobotFileError, match=match):
            load(p)


def test_too_many_joints_is_refused_quickly(tmp_path):
    p = tmp_path / "long.toml"
    p.write_text("[[joints]]\na = 0.1\n" * 20_000, encoding="utf-8")
    with pytest.raises(RobotFileError, match="at most 1,000 joints"):
        load(p)
