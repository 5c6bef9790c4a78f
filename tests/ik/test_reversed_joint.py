"""A DH table that reverses joint 3 of a Puma-like arm (issue 19): the spherical-wrist family still answers.

Axes 2 and 3 parallel but opposite give the DH twist ``alpha_2 = 180`` deg (the Kinova Jaco2's DH
table, and the DH twin of its URDF), which the family's pattern (``alpha_2 = 0``) refused: the geometric family
answered instead. ``StandardForm.reversed_joint`` turns joint 3 back; the identity it rests on,

    R_x(alpha_{i-1}) R_z(phi) T_z(d) T_x(a) R_x(alpha_i)
        = R_x(alpha_{i-1} - pi) R_z(-phi) T_z(-d) T_x(a) R_x(alpha_i + pi),

is checked here with a product of matrices written out in the test, and the arms with joint 3 reversed are
built from that identity and checked against armkit's FK of the arm they came from (``q_3 -> -q_3``). The same
for the yaw-pitch-pitch family (the club's arm) and the UR family (any of its parallel axes 2, 3, 4 reversed).

Not on the nearby *ideal* arm of a file with rounded numbers (the Kinova's URDF, twists 4.9e-12 off): there the
family's branches would all take the Python touch-up (0.6-0.7 ms a call), and the geometric family, which solves on the
file's own axes and polishes compiled, keeps answering it (6 µs).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit import Robot
from armkit.ik.analytic import closed_form
from armkit.ik.analytic._common import standard_form
from armkit.model.erd import robots_folder
from armkit.spatial import rotx, rotz, transl

from test_ik_analytic import _random_arm, angle_gap


def _row(phi: float, d: float, a: float, alpha: float) -> np.ndarray:
    """One standard-DH link, written out: R_z(phi) T_z(d) T_x(a) R_x(alpha)."""
    c, s, ca, sa = math.cos(phi), math.sin(phi), math.cos(alpha), math.sin(alpha)
    return np.array([[c, -s * ca, s * sa, a * c], [s, c * ca, -c * sa, a * s], [0.0, sa, ca, d], [0, 0, 0, 1.0]])


def _chain(sf, q) -> np.ndarray:
    T = sf.base.copy()
    for j in range(sf.n):
        T = T @ _row(q[j] + sf.theta[j], sf.d[j], sf.a[j], sf.alpha[j])
    return T @ sf.tool


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), which=st.integers(1, 5))
def test_reversed_joint_is_the_same_arm_with_that_joint_negated(seed, which):
    rng = np.random.default_rng(seed)
    arm = _random_arm("spherical-wrist", rng)
    sf = standard_form(arm)
    twin = sf.reversed_joint(which)
    assert twin.reversed_joint(which).alpha == pytest.approx(sf.alpha, abs=1e-15)   # its own inverse
    q = rng.uniform(-math.pi, math.pi, 6)
    flipped = q.copy()
    flipped[which] = -q[which]
    assert np.allclose(_chain(twin, flipped), _chain(sf, q), rtol=0, atol=1e-13)
    assert np.allclose(_chain(sf, q), armkit.fk(arm, q), rtol=0, atol=1e-13)


def test_twists_that_are_multiples_of_90_deg_stay_exact():
    sf = standard_form(armkit.load("puma560"))          # twists 90, 0, -90, 90, -90 deg
    twin = sf.reversed_joint(2)
    assert list(twin.alpha / (math.pi / 2)) == [1.0, 2.0, 1.0, 1.0, -1.0, 0.0]
    assert twin.half_turn(1) and not sf.half_turn(1)
    assert list(twin.reversed_joint(2).alpha) == list(sf.alpha)


def _reversed(arm: Robot, *joints: int) -> Robot:
    """``arm`` with ``joints`` (0-based indices, from 1 on) reversed, as a DH table gives it: the identity above,
    applied by hand (the twist before each and its own row; its limits negated)."""
    j = list(arm.joints)
    for k in joints:
        j[k - 1] = dataclasses.replace(j[k - 1], alpha=j[k - 1].alpha + math.pi)
        j[k] = dataclasses.replace(j[k], theta=-j[k].theta, d=-j[k].d, alpha=j[k].alpha + math.pi,
                                   lower=-j[k].upper, upper=-j[k].lower)
    return Robot(j, name=f"{arm.name}, joints {joints} reversed", base=arm.base, tool=arm.tool)


def _same_branches(got, ref, n, joints=(2,)):
    """Each target's successful branches of ``got`` (``joints`` reversed) are those of ``ref`` with those joints
    negated, each under the same name (shoulder, elbow and wrist are the arm's, whichever way a table points an
    axis)."""
    flip = np.ones(n)
    flip[list(joints)] = -1
    for i in range(len(got.q)):
        mine, names = got.q[i][got.success[i]] * flip, got.branch[i][got.success[i]]
        theirs, their_names = ref.q[i][ref.success[i]], ref.branch[i][ref.success[i]]
        assert len(mine) == len(theirs)
        for x, name in zip(mine, names):
            k = int(np.argmin(angle_gap(theirs, x)))
            assert angle_gap(theirs[k], x) < 1e-9 and their_names[k] == name


@pytest.mark.parametrize("kind, joints", [
    ("spherical-wrist", (2,)), ("yaw-pitch-pitch", (2,)),
    # axes 2, 3, 4 of the UR family are parallel: a table may point any of them the other way (joint 2 reversed
    # flips the twist before it, +-90 deg, and puts 180 deg between axes 2 and 3)
    ("ur", (2,)), ("ur", (3,)), ("ur", (2, 3)), ("ur", (1,)), ("ur", (1, 2)), ("ur", (1, 3))])
@settings(max_examples=8, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_an_arm_with_a_joint_reversed_keeps_its_family_and_branches(kind, joints, seed):
    """A random arm of a family with ``joints`` (0-based) pointed the other way in its DH table: the same family,
    every branch of the arm it came from with those joints negated, under the same names, each checked by FK."""
    rng = np.random.default_rng(seed)
    arm = _random_arm(kind, rng)
    rev = _reversed(arm, *joints)
    q = arm.random_q(6, rng=rng)
    qr = q.copy()
    qr[:, list(joints)] *= -1
    assert np.allclose(armkit.fk(rev, qr), armkit.fk(arm, q), rtol=0, atol=1e-12)
    assert closed_form(rev).family == kind
    T = armkit.fk(arm, q)
    target = T if kind != "yaw-pitch-pitch" else T[:, :3, 3]
    got = armkit.ik_all(rev, target, enforce_limits=False)
    ref = armkit.ik_all(arm, target, enforce_limits=False)
    assert got.success.any(axis=1).all()
    back = armkit.fk(rev, got.q[got.success])
    want = np.repeat(T[:, None], got.q.shape[1], axis=1)[got.success]
    part = (slice(None), slice(0, 3), slice(None)) if kind != "yaw-pitch-pitch" else (slice(None), slice(0, 3), 3)
    assert np.abs(back[part] - want[part]).max() <= 1e-12 * max(rev.reach, 1.0)   # FK of the reversed arm
    assert np.all(angle_gap(got.q, qr[:, None]).min(axis=1) < 1e-6)   # the configuration the target came from
    _same_branches(got, ref, arm.n, joints)


@pytest.mark.parametrize("name", ["puma560", "fighter", "ur5"])
def test_numba_and_numpy_give_the_same_branches_on_a_reversed_joint(name):
    from armkit.kinematics import get_backend

    if get_backend() != "numba":
        pytest.skip("numba not available")
    rev = _reversed(armkit.load(name), *((2, 3) if name == "ur5" else (2,)))
    T = armkit.fk(rev, rev.random_q(40, rng=3))
    T = T if name != "fighter" else T[:, :3, 3]
    fast = armkit.ik_all(rev, T, enforce_limits=False)
    armkit.set_backend("numpy")
    try:
        ref = armkit.ik_all(rev, T, enforce_limits=False)
    finally:
        armkit.set_backend("auto")
    assert np.array_equal(fast.success, ref.success) and np.array_equal(fast.branch, ref.branch)
    assert np.allclose(fast.q, ref.q, rtol=0, atol=1e-9)


def _kinova_dh_twin() -> Robot:
    """The Kinova Jaco2 j2s6s200 as a standard-DH table: the DH twin of its URDF (example-robot-data) with the
    file's rounded twists (4.9e-12 off 90 deg) set to multiples of 90 deg. Its twist alpha_2 is 180 deg."""
    kinova = armkit.load("example-robot-data:kinova")
    return standard_form(kinova).as_robot(kinova, "kinova DH twin")   # the ideal arm: snapped values, base and tool


def test_the_kinova_dh_table_is_a_puma_like_arm_and_its_urdf_stays_geometric():
    if robots_folder() is None:
        pytest.skip("example-robot-data is not installed (test extra)")
    kinova = armkit.load("example-robot-data:kinova")
    dh = _kinova_dh_twin()
    assert closed_form(dh).family == "spherical-wrist" and closed_form(dh).sf.exact
    assert closed_form(kinova).family == "geometric"   # the ideal arm of a file: the geometric family, as before
    q = kinova.random_q(30, rng=11)
    assert np.allclose(armkit.fk(dh, q), armkit.fk(kinova, q), rtol=0, atol=1e-9)   # the same arm, to 1e-11
    T = armkit.fk(dh, q)
    a = armkit.ik_all(dh, T, enforce_limits=False)
    b = armkit.ik_all(kinova, T, enforce_limits=False)
    assert (a.success.sum(axis=1) == 8).all() and (b.success.sum(axis=1) == 8).all()
    for i in range(len(T)):
        assert all(angle_gap(b.q[i][b.success[i]], x).min() < 1e-8 for x in a.q[i][a.success[i]])


@pytest.mark.parametrize("off", [5e-12, 3.7e-6])
def test_a_reversed_joint_3_with_rounded_twists_stays_geometric_and_keeps_every_branch(off):
    """The Puma with joint 3 reversed, its twists rounded as a file rounds them (``rpy="1.5708"``: 3.7e-6 off;
    11 digits: 5e-12): the ideal arm of a file, answered by the geometric family, every branch to the FK of the
    true arm."""
    rev = _reversed(armkit.load("puma560"), 2)
    rounded = Robot([dataclasses.replace(j, alpha=j.alpha + off if j.alpha else 0.0) for j in rev.joints],
                    name="puma, joint 3 reversed, rounded", base=rev.base, tool=rev.tool)
    sf = standard_form(rounded)
    assert sf.exact is False and sf.half_turn(1)
    assert closed_form(rounded).family == "geometric"
    q = rounded.random_q(20, rng=4)
    T = armkit.fk(rounded, q)
    res = armkit.ik_all(rounded, T, enforce_limits=False)
    assert (res.success.sum(axis=1) == 8).all()
    back = armkit.fk(rounded, res.q[res.success])
    assert np.abs(back - np.repeat(T[:, None], 8, axis=1)[res.success]).max() <= 1e-12
    assert np.all(angle_gap(res.q, q[:, None]).min(axis=1) < 1e-6)


def test_joint_3_reversed_in_a_random_base_and_tool():
    """The reversed arm's own tool and base are kept (a sanity check of the construction with a turned tool)."""
    arm = Robot(list(armkit.load("puma560").joints), name="puma", base=transl(0.1, -0.2, 0.3) @ rotz(0.4),
                tool=transl(0.0, 0.05, 0.1) @ rotx(0.3))
    rev = _reversed(arm, 2)
    assert closed_form(rev).family == "spherical-wrist"
    q = arm.random_q(10, rng=8)
    T = armkit.fk(arm, q)
    res = armkit.ik_all(rev, T)
    assert res.success.any(axis=1).all()


def test_armkit_info_names_the_family_and_the_joint_turned_back(tmp_path):
    """``armkit info`` says which family answers ``armkit ik`` and which joint it solves turned back (text, Korean
    and JSON); an arm without a closed form says nothing of the kind."""
    import json

    from typer.testing import CliRunner

    from armkit.cli import app

    runner = CliRunner()
    rev = _reversed(armkit.load("puma560"), 2)
    armkit.save(rev, tmp_path / "puma_rev.toml")
    path = str(tmp_path / "puma_rev.toml")
    text = runner.invoke(app, ["info", path], env={"COLUMNS": "300", "ARMKIT_LANG": "en"})
    assert text.exit_code == 0
    assert "closed form, family spherical-wrist, 8 branches; solved with elbow turned back" in text.output
    ko = runner.invoke(app, ["--lang", "ko", "info", path], env={"COLUMNS": "300"})
    assert "spherical-wrist 계열, 해 8개; elbow 관절을 반대 방향으로 돌려서 풂" in ko.output
    data = json.loads(runner.invoke(app, ["info", path, "--json"]).stdout)
    assert data["closed_form"] == {"family": "spherical-wrist", "branches": 8, "turned_back": ["elbow"],
                                   "ideal_arm": False, "names_from": None}
    plain = json.loads(runner.invoke(app, ["info", "puma560", "--json"]).stdout)
    assert plain["closed_form"]["turned_back"] == []
    assert json.loads(runner.invoke(app, ["info", "panda", "--json"]).stdout)["closed_form"] is None
    armkit.save(_reversed(armkit.load("planar2"), 1), tmp_path / "planar_rev.toml")   # planar-2r's own sign
    data = json.loads(runner.invoke(app, ["info", str(tmp_path / "planar_rev.toml"), "--json"]).stdout)
    assert data["closed_form"]["family"] == "planar-2r"
    assert data["closed_form"]["turned_back"] == [armkit.load("planar2").joint_names[1]]
    assert "family" not in runner.invoke(app, ["info", "panda"], env={"COLUMNS": "300"}).output


@pytest.mark.parametrize("name, joints", [("puma560", (2,)), ("fighter", (2,)), ("ur5", (2, 3))])
def test_the_same_reversed_arm_in_modified_dh_gives_the_same_branches(name, joints):
    """Standard DH == modified DH of the same arm: the reversed arm written in modified DH (its 180 deg twist now
    on the row of the joint after it) keeps the family and gives the same branches."""
    rev = _reversed(armkit.load(name), *joints)
    mod = rev.to_dh("modified")
    assert mod.convention == "modified"
    assert any(abs(abs(j.alpha) - math.pi) < 1e-12 for j in mod.joints)
    assert closed_form(mod).family == closed_form(rev).family
    q = rev.random_q(10, rng=6)
    T = armkit.fk(rev, q)
    assert np.allclose(armkit.fk(mod, q), T, rtol=0, atol=1e-12)
    target = T if name != "fighter" else T[:, :3, 3]
    a = armkit.ik_all(rev, target, enforce_limits=False)
    b = armkit.ik_all(mod, target, enforce_limits=False)
    assert np.array_equal(a.success, b.success) and np.array_equal(a.branch, b.branch)
    assert np.allclose(a.q, b.q, rtol=0, atol=1e-9)
