"""A Robot is a value: equal and hash-equal when its fields are; derived data lives in one declared cache."""

from __future__ import annotations

import dataclasses
import importlib
import pickle

import numpy as np
import pytest

import armkit
from armkit import Joint, Robot

closed_form = importlib.import_module("armkit.ik.analytic").closed_form


def two_link(**kw) -> Robot:
    args = dict(joints=[Joint(a=1.0, name="shoulder"), Joint(a=0.5, name="elbow")], name="two-link")
    args.update(kw)
    return Robot(**args)


@pytest.mark.parametrize("name", armkit.bundled_robots())
def test_a_robot_loaded_twice_is_equal_and_hashes_equal(name):
    a, b = armkit.load(name), armkit.load(name)
    assert a is not b
    assert a == b and not (a != b)
    assert hash(a) == hash(b)
    assert len({a, b}) == 1


def test_bundled_robots_differ_from_each_other():
    robots = [armkit.load(n) for n in armkit.bundled_robots()]
    assert len(set(robots)) == len(robots)
    assert all((a == b) == (i == j) for i, a in enumerate(robots) for j, b in enumerate(robots))


@pytest.mark.parametrize("change", [
    dict(joints=[Joint(a=1.0, name="shoulder"), Joint(a=0.5 + 1e-12, name="elbow")]),
    dict(joints=[Joint(a=1.0, name="shoulder"), Joint(a=0.5, name="elbow", upper=1.0)]),
    dict(joints=[Joint(a=1.0, name="shoulder"), Joint(a=0.5, name="wrist")]),
    dict(joints=[Joint(a=1.0, name="shoulder"), Joint("prismatic", a=0.5, name="elbow")]),
    dict(convention="modified"),
    dict(name="other"),
    dict(unit="mm"),
    dict(base=armkit.spatial.transl(0, 0, 1e-15)),
    dict(tool=armkit.spatial.rotz(1e-9)),
    dict(description="a description"),
    dict(source="a source"),
    dict(link_names=["a", "b", "c"]),
    dict(ignored_joints=["gripper"]),
])
def test_any_changed_field_makes_robots_unequal(change):
    a, b = two_link(), two_link(**change)
    assert a != b
    assert hash(a) != hash(b)   # not required by the hash contract, but these keys must not collide


def test_links_compare_by_value():
    a = two_link()
    moved = tuple(dataclasses.replace(lk, offset=armkit.spatial.transl(0.1, 0, 0)) if lk.frame == 1 else lk
                  for lk in a.links)
    copied = tuple(dataclasses.replace(lk, offset=np.array(lk.offset)) for lk in a.links)
    assert two_link(links=copied) == a
    assert two_link(links=moved) != a


def test_arrays_compare_exactly_and_signed_zero_is_zero():
    tool = np.eye(4)
    tool[0, 1] = -0.0
    assert two_link(tool=tool) == two_link()
    assert hash(two_link(tool=tool)) == hash(two_link())


def test_equality_with_other_types():
    assert two_link() != "two-link"
    assert two_link() != None  # noqa: E711


def test_the_cache_is_declared_and_outside_equality_and_repr():
    a, b = armkit.load("ur5"), armkit.load("ur5")
    assert isinstance(a.cache, dict)
    armkit.ik(a, armkit.fk(a, np.full(6, 0.3)))    # fills a's cache, not b's
    assert "closed_form" in a.cache and "closed_form" not in b.cache
    assert a == b and hash(a) == hash(b)
    assert "cache" not in repr(a)
    assert "cache" not in {f.name for f in dataclasses.fields(Robot) if f.compare}


def test_derived_data_is_computed_once():
    r = armkit.load("puma560")
    assert closed_form(r) is closed_form(r) is r.cache["closed_form"]
    assert r.to_dh("modified") is r.to_dh("modified")
    so = armkit.load("so101")
    assert so.to_dh() is so.to_dh()
    r.cache.clear()                                   # only costs recomputation
    assert closed_form(r) is not None and r.link_index(r.links[-1].name) == len(r.links) - 1


def test_no_ad_hoc_attributes_after_use():
    """Every computation keeps its derived data in ``robot.cache``, none as a new attribute."""
    declared = {f.name for f in dataclasses.fields(Robot)}   # collision, loaded_from, _lower, _upper among them
    for name in ("fighter", "ur5", "panda", "so101"):
        r = armkit.load(name)
        q = r.random_q(rng=1)
        T = armkit.fk(r, q)
        armkit.jacobian(r, q)
        armkit.ik(r, T)
        armkit.ik(r, T, method="lm", q0=q)
        if name == "so101":                            # a yaw-pitch3 arm: position and tool pitch
            armkit.ik_all(r, T[:3, 3], pitch=0.2)
        elif closed_form(r) is not None:
            armkit.ik_all(r, T)
        r.to_dh("modified")
        armkit.collisions(r, q)
        assert set(vars(r)) <= declared, set(vars(r)) - declared
        assert r.cache                                 # the computations above did use it


def test_pickled_robot_is_equal_and_rehashes():
    a = armkit.load("fighter")
    hash(a)
    closed_form(a)
    b = pickle.loads(pickle.dumps(a))
    assert "hash" not in b.cache                        # recomputed in the receiving process
    assert b == a and hash(b) == hash(a)
    assert "closed_form" in b.cache
