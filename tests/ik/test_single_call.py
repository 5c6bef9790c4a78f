"""One compiled call for one IK target (issue 19, item 5): the same answers as the batched path.

``armkit.ik_all(robot, T)`` and ``armkit.ik(robot, T)`` for ONE pose or position take
:func:`armkit.ik.analytic.single_call` (solve, wrap, verify and sort in one Numba call,
:mod:`armkit.ik.analytic._single`). Every field must equal what the batched path
(:func:`armkit.ik.analytic.solve_all` / ``solve_nearest``, reached with ``api.ONE_CALL = False``)
gives for the same call: the same joint values to the last bit, success, errors, branch labels,
reasons, messages and order, and the same types. Targets: reachable ones (FK of random joint
values), unreachable ones (moved away), starts that put branches outside the limits, on every
fused family and on the geometric family (a UR5 with axis 1 reversed, the Stanford arm).
Timing lives in benchmarks/bench_analytic.py.
"""

from __future__ import annotations

import importlib
import importlib.util
import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit.errors import IKInputError, ShapeError
from armkit.ik.analytic import _hand_written, closed_form, single_call
from armkit.ik.analytic._common import standard_form
from armkit.model.axes import with_axes_reversed
from armkit.model.robot import Robot

api = importlib.import_module("armkit.ik.api")
FIELDS = ("q", "success", "position_error", "rotation_error", "iterations", "branch", "within_limits", "reason",
          "message")


def _flipped(robot: Robot) -> Robot:
    """The same arm as a URDF-convention robot with joint 1's axis reversed (q1 -> -q1), limits off: the DH-pattern
    families no longer match it, so the geometric family answers."""
    flipped = with_axes_reversed(robot)
    return Robot([replace(j, lower=-np.inf, upper=np.inf) for j in flipped.joints], convention="urdf",
                 name=flipped.name, unit=flipped.unit, tool=flipped.chain.tool)


def twists_rounded(robot: Robot, off: float = 3.7e-6) -> Robot:
    """``robot`` as a file that rounds its twists (``rpy="1.5708"``: 3.7e-6 off 90 deg) and nothing else: its axes
    still meet and lie parallel where the arm's do, so the geometric family solves it on its own axes, naming the
    branches as the hand-written family of its ideal arm (tests/ik/test_rounded_file.py)."""
    return Robot([replace(j, alpha=j.alpha + math.copysign(off, j.alpha) if j.alpha else 0.0) for j in robot.joints],
                 name=robot.name + ", rounded", base=robot.base, tool=robot.tool)


def rounded(robot: Robot, off: float = 3.7e-6) -> Robot:
    """:func:`twists_rounded`, solved as a calibrated file is (one whose axes no longer meet or lie parallel where
    the ideal arm's do, :func:`calibrated`): by the hand-written family of its ideal arm, every branch touched up on
    the true one (by the one compiled call, since 2026-12-06). Its closed form is set to that family, which
    ``closed_form`` would leave for the geometric family on this arm; the same steps, on an arm whose every
    target has all its branches."""
    arm = twists_rounded(robot, off)
    arm.cache["closed_form"] = _hand_written(standard_form(arm), arm)
    assert not arm.cache["closed_form"].sf.exact
    return arm


def calibrated(robot: Robot, off: float = 3.7e-6) -> Robot:
    """:func:`twists_rounded` with its zero twists 2e-6 rad off too (parallel axes no longer parallel) and joint 5's
    length 1e-6 off (a wrist whose axes no longer meet): no closed form holds on its own axes, so ``closed_form``
    gives the hand-written family of its ideal arm (as :func:`rounded` sets it)."""
    twisted = twists_rounded(robot, off)
    return Robot([replace(j, alpha=j.alpha or 2e-6, a=j.a + 1e-6 if k == 4 else j.a)
                  for k, j in enumerate(twisted.joints)], name=robot.name + ", calibrated", base=robot.base,
                 tool=robot.tool)


ARMS = {"planar2": "point", "planar3": "pose", "fighter": "point", "puma560": "pose", "ur5": "pose",
        "stanford": "pose", "ur5-flipped": "pose", "puma560-rounded": "pose", "ur5-rounded": "pose",
        "fighter-rounded": "point"}
_LOADED: dict = {}


def _arm(name: str) -> Robot:
    if name not in _LOADED:
        if name == "ur5-flipped":
            _LOADED[name] = _flipped(armkit.load("ur5"))
        elif name.endswith("-rounded"):
            _LOADED[name] = rounded(armkit.load(name.removesuffix("-rounded")))
        else:
            _LOADED[name] = armkit.load(name)
    return _LOADED[name]


@pytest.fixture(scope="module", autouse=True)
def compiled():
    armkit.set_backend("numba")    # the one-call path serves the Numba back end only
    if closed_form(armkit.load("ur5")) is None or importlib.util.find_spec("numba") is None:
        pytest.skip("Numba is not available")
    yield
    armkit.set_backend("auto")


def _both(fn):
    """``fn()`` by the one-call path and by the batched path."""
    try:
        api.ONE_CALL = True
        fast = fn()
        api.ONE_CALL = False
        slow = fn()
    finally:
        api.ONE_CALL = True
    return fast, slow


def _assert_same(fast, slow) -> None:
    for f in FIELDS:
        a, b = getattr(fast, f), getattr(slow, f)
        assert type(a) is type(b), f
        if isinstance(a, np.ndarray):   # text: the same kind (str), whatever the width (the longest text of the
            same = a.dtype.kind == b.dtype.kind == "U" or a.dtype == b.dtype   # array it was taken from)
            assert same and a.shape == b.shape, f
            assert np.array_equal(a, b), (f, a, b)   # bit for bit (NaN never occurs here)
        else:
            assert a == b, f
    assert fast.checked_against == slow.checked_against


def _target(robot: Robot, kind: str, q: np.ndarray, far: float) -> np.ndarray:
    T = armkit.fk(robot, q)
    T[:3, 3] *= far
    return T[:3, 3].copy() if kind == "point" else T


@settings(max_examples=40, deadline=None)
@given(name=st.sampled_from(sorted(ARMS)), u=st.lists(st.floats(-1.0, 1.0), min_size=7, max_size=7),
       v=st.lists(st.floats(-1.0, 1.0), min_size=7, max_size=7), far=st.sampled_from([1.0, 1.0, 1.0, 1.4, 3.0]),
       start=st.booleans(), enforce=st.booleans())
def test_one_call_equals_batched(name, u, v, far, start, enforce):
    robot = _arm(name)
    n = robot.n
    lo = np.where(np.isfinite(robot.lower), robot.lower, -np.pi)
    hi = np.where(np.isfinite(robot.upper), robot.upper, np.pi)
    q = lo + (hi - lo) * (np.asarray(u[:n]) + 1.0) / 2.0
    target = _target(robot, ARMS[name], q, far)
    q0 = 4.0 * np.asarray(v[:n]) if start else None    # a start far from the limits: branches outside them
    fast, slow = _both(lambda: armkit.ik_all(robot, target, q0, enforce_limits=enforce))
    _assert_same(fast, slow)
    fast, slow = _both(lambda: armkit.ik(robot, target, q0, enforce_limits=enforce))
    _assert_same(fast, slow)
    # and the answer itself: every successful branch reaches the target (FK of the true model)
    res = armkit.ik_all(robot, target, q0, enforce_limits=enforce)
    if res.success.any():
        got = armkit.fk(robot, res.q[res.success])
        want = target if target.shape == (4, 4) else None
        err = np.abs(got[:, :3, 3] - (target[:3, 3] if want is not None else target)).max()
        assert err <= 1e-9 * max(1.0, robot.reach)
        if want is not None:
            assert np.abs(got[:, :3, :3] - want[:3, :3]).max() <= 1e-8


@pytest.mark.parametrize("name", sorted(ARMS))
def test_one_call_is_taken(name, rng):
    """The path under test answers typical targets itself (else the test above compares a path with itself)."""
    robot = _arm(name)
    hits = 0
    for _ in range(20):
        target = _target(robot, ARMS[name], robot.random_q(rng=rng), 1.0)
        hits += single_call(robot, closed_form(robot), target, None, None) is not None
    assert hits >= 15


def test_unreachable_messages_and_limits():
    """An unreachable UR5 target and a Puma target with branches outside the limits: the sentences of
    the batched path (the family's reach sentence, the limit sentence), in the same order."""
    ur5 = _arm("ur5")
    T = armkit.fk(ur5, np.array([0.3, -1.0, 1.2, 0.4, 0.9, -0.2]))
    T[:3, 3] *= 3.0
    fast, slow = _both(lambda: armkit.ik_all(ur5, T))
    _assert_same(fast, slow)
    assert not fast.success.any() and all(m.startswith("unreachable") for m in fast.message)
    puma = _arm("puma560")
    T = armkit.fk(puma, np.array([0.2, 0.4, -0.3, 0.5, 0.6, 0.7]))
    fast, slow = _both(lambda: armkit.ik_all(puma, T))
    _assert_same(fast, slow)
    assert (fast.reason == "joint limits").any() and fast.success.any()
    assert list(fast.success) == sorted(fast.success, reverse=True)     # successful branches first


@pytest.mark.parametrize("name", ["ur5", "puma560", "fighter", "planar2", "planar3"])
def test_reach_sentences_from_the_kernel(name, rng):
    """Every out-of-reach sentence the one-call kernels give from their own numbers (``reach_why``, without
    solving again) is the family's sentence on the batched path, bit for bit: targets beside the first
    axis (closer than the sideways offset), beyond the reach, and (planar-2r) off the arm's plane."""
    robot = _arm(name)
    seen = set()
    for _ in range(3):
        T = armkit.fk(robot, robot.random_q(rng=rng))
        for xy, z, dz in ((0.0, 1.0, 0.0), (0.02, 1.0, 0.0), (3.0, 1.0, 0.0), (3.0, 3.0, 0.0), (3.0, 1.0, 0.1)):
            t = T.copy()
            t[:2, 3] *= xy
            t[2, 3] = t[2, 3] * z + dz
            target = t[:3, 3].copy() if ARMS[name] == "point" else t
            if single_call(robot, closed_form(robot), target, None, None) is None:
                continue    # the batched path answers this one anyway (a target on the first axis)
            fast, slow = _both(lambda: armkit.ik_all(robot, target))
            _assert_same(fast, slow)
            for m in fast.message[fast.reason == "unreachable"]:
                seen.add("beside" if "closer than" in m else "shoulder" if "from the shoulder" in m else "misses")
                seen.add("plane" if "off the arm's plane" in m else "")
    assert "shoulder" in seen
    if name in ("ur5", "puma560"):      # a sideways offset: targets near the first axis are out of reach
        assert "beside" in seen
    if name == "planar2":
        assert "plane" in seen


def test_bad_targets_raise_as_before():
    ur5 = _arm("ur5")
    bad = np.eye(4)
    bad[0, 0] = 2.0
    for target, error in ((bad, ShapeError), (np.full((4, 4), np.nan), ShapeError)):
        with pytest.raises(error):
            armkit.ik_all(ur5, target)
        with pytest.raises(error):
            armkit.ik(ur5, target)
    assert armkit.ik_all(ur5, bad, check=False).shape == (8,)       # unchecked: answered, not raised
    with pytest.raises(IKInputError):
        armkit.ik_all(ur5, np.array([0.3, 0.1, 0.2]))                # a position for a pose-only family


def test_start_beyond_1e6_is_wrapped_as_before():
    ur5 = _arm("ur5")
    T = armkit.fk(ur5, np.array([0.3, -1.0, 1.2, 0.4, 0.9, -0.2]))
    q0 = np.array([1e7, 0.0, 0.0, 0.0, 0.0, 0.0])
    fast, slow = _both(lambda: armkit.ik_all(ur5, T, q0))
    _assert_same(fast, slow)


def test_fighter_keeps_its_collision_check():
    fighter = _arm("fighter")
    p = armkit.fk(fighter, np.radians([30.0, 45.0, 60.0]))[:3, 3]
    fast, slow = _both(lambda: armkit.ik_all(fighter, p))
    _assert_same(fast, slow)
    assert fast.checked_against == ("ground", "torso")
    fast, slow = _both(lambda: armkit.ik(fighter, p))
    _assert_same(fast, slow)


def test_ik_takes_fixed():
    """``ik(..., fixed=)``: the nearest of ``ik_all(..., fixed=)``'s branches, the held joint kept exactly."""
    panda = armkit.load("panda")
    q = np.array([0.3, -0.5, 0.2, -2.0, 0.4, 1.6, 0.7])
    T = armkit.fk(panda, q)
    every = armkit.ik_all(panda, T, fixed={"panda_joint6": 1.6})
    one = armkit.ik(panda, T, fixed={"panda_joint6": 1.6})
    assert bool(one.success) and one.q[5] == 1.6
    assert np.array_equal(one.q, every.q[0]) and str(one.branch) == str(every.branch[0])
    assert np.allclose(armkit.fk(panda, one.q), T, atol=1e-9)
    with pytest.raises(IKInputError):
        armkit.ik(panda, T, fixed={"panda_joint6": 1.6}, method="lm")
