"""A DH twist one ulp off 90 deg is round-off, not a rounded robot file (issue 19).

A UR5 whose joint 1 axis is reversed in its URDF has the DH twist -pi/2 one ulp off
(-1.5707963267948968). It used to count as the "ideal arm of a real file" (``sf.exact`` False): every
out-of-reach branch within 6e-3 of the reach went to the Gauss-Newton touch-up, and the one-call path
handed those targets to the batched path (7 of 300 random targets, ~40 µs a call on average instead of
~13). A twist moved by round-off only now leaves the arm exact; a twist from a file's ``rpy="1.5708"``
(3.7e-6 off) still makes it ideal.
"""

from __future__ import annotations

import importlib.util
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit.ik.analytic import closed_form, single_call
from armkit.ik.analytic._common import HALF_PI, IDEAL_ANGLE_TOL, _snap
from test_single_call import _flipped, rounded   # the reversed-axis and rounded arms, built one way for these files


@settings(max_examples=200, deadline=None)
@given(k=st.integers(-4, 4), ulps=st.integers(-4, 4))
def test_a_twist_moved_by_round_off_is_not_moved(k, ulps):
    exact = k * HALF_PI
    v = exact
    for _ in range(abs(ulps)):
        v = math.nextafter(v, math.inf if ulps > 0 else -math.inf)
    snapped, moved = _snap(np.array([0.3, v]), HALF_PI, IDEAL_ANGLE_TOL)
    assert snapped[1] == exact and snapped[0] == 0.3
    assert moved is False


@settings(max_examples=200, deadline=None)
@given(k=st.integers(-4, 4), off=st.floats(1e-12, 0.9e-4), sign=st.sampled_from([-1.0, 1.0]))
def test_a_twist_from_a_rounded_file_is_moved(k, off, sign):
    v = k * HALF_PI + sign * off          # e.g. rpy 1.5708: 3.7e-6 from 90 deg
    snapped, moved = _snap(np.array([v]), HALF_PI, IDEAL_ANGLE_TOL)
    assert snapped[0] == k * HALF_PI
    assert moved is True


def test_so101_file_stays_ideal_and_the_flipped_ur5_is_exact():
    assert closed_form(armkit.load("so101")).sf.exact is False     # its file's 1.5708: the ideal arm
    flipped = _flipped(armkit.load("ur5"))
    cf = closed_form(flipped)
    assert cf is not None and cf.family == "ur" and cf.sf.exact is True


def test_the_flipped_ur5_is_answered_by_one_call():
    """The 7 targets of 300 that went back to the batched path (clipped branches 0.2-6.6 mm from the
    target, inside the ideal arm's 6e-3 polish window) are answered by the one compiled call, with the
    batched path's answer."""
    if importlib.util.find_spec("numba") is None:
        pytest.skip("Numba is not available")
    armkit.set_backend("numba")
    api = importlib.import_module("armkit.ik.api")
    try:
        robot = _flipped(armkit.load("ur5"))
        rng = np.random.default_rng(7)
        T = armkit.fk(robot, rng.uniform(-np.pi, np.pi, (300, robot.n)))
        cf = closed_form(robot)
        assert all(single_call(robot, cf, t, None, None) is not None for t in T)
        for i in (40, 56, 80, 155, 195, 261, 280):     # the targets that used to fall back
            fast = armkit.ik_all(robot, T[i])
            api.ONE_CALL = False
            try:
                slow = armkit.ik_all(robot, T[i])
            finally:
                api.ONE_CALL = True
            for f in ("q", "success", "position_error", "rotation_error", "branch", "reason", "message"):
                assert np.array_equal(np.asarray(getattr(fast, f)), np.asarray(getattr(slow, f))), f
            assert fast.success.any()
            good = fast.q[fast.success]
            assert np.abs(armkit.fk(robot, good) - T[i]).max() <= 1e-9
    finally:
        armkit.set_backend("auto")


@settings(max_examples=60, deadline=None)
@given(axis=st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=3), angle=st.floats(0.0, 1.5))
def test_the_touch_ups_rotation_log_is_scipys_below_90_deg(axis, angle):
    """The Gauss-Newton touch-up's rotation error (``_small_log``) against :func:`armkit.spatial.so3_log` (scipy's
    quaternion route), for rotations from 0 to 86 deg, and the identity."""
    from armkit.ik.analytic import _small_log
    from armkit.spatial import so3_exp, so3_log

    u = np.asarray(axis)
    if np.linalg.norm(u) < 1e-3:
        u = np.array([0.0, 0.0, 1.0])
    w = u / np.linalg.norm(u) * angle
    R = so3_exp(w)[None]
    assert np.allclose(_small_log(R), so3_log(R), rtol=0, atol=4e-16 + 2e-15 * angle)
    assert np.array_equal(_small_log(np.eye(3)[None]), np.zeros((1, 3)))


def _rounded_puma() -> armkit.Robot:
    """The Puma 560 of a file that rounds its twists (``rpy="1.5708"``: 3.7e-6 off 90 deg)."""
    return rounded(armkit.load("puma560"))


def test_the_touch_up_of_a_rounded_file_stops_when_converged(monkeypatch):
    """A Puma whose file rounds its twists is solved on its ideal arm and every branch touched up by Gauss-Newton
    steps on the true arm: they converge in about three steps (~1e-5, 1e-10, 1e-15 rad; a batch ends when all
    have), and the touch-up stops there instead of taking all six (1.3 -> 0.66 ms a call), at full precision.
    The NumPy touch-up (the NumPy back end's, and the Numba back end's for a Jacobian too near singular), on rows
    1e-5 rad off well-conditioned solutions; the compiled one: test_touch_up_compiled.py."""
    from armkit.ik import analytic
    from armkit.ik.analytic import _gauss_newton

    rounded = _rounded_puma()
    assert closed_form(rounded).family == "spherical-wrist" and not closed_form(rounded).sf.exact
    rng = np.random.default_rng(4)
    q = rounded.random_q(200, rng=rng)
    q = q[np.linalg.svd(armkit.jacobian(rounded, q), compute_uv=False).min(axis=-1) > 0.05][:20]
    T = armkit.fk(rounded, q)
    steps = []
    real = analytic.jacobian
    monkeypatch.setattr(analytic, "jacobian", lambda *a, **k: steps.append(1) or real(*a, **k))
    armkit.set_backend("numpy")
    try:
        got = _gauss_newton(rounded, q + rng.uniform(-1e-5, 1e-5, q.shape), T, True, 6)
        back = armkit.fk(rounded, got)
    finally:
        armkit.set_backend("auto")
    assert len(q) == 20 and 2 <= len(steps) < 6     # one Jacobian a step, all rows at once (six before)
    assert np.abs(back[:, :3, 3] - T[:, :3, 3]).max() <= 1e-15 * rounded.reach
    assert np.abs(back[:, :3, :3] - T[:, :3, :3]).max() <= 2e-15


def test_every_branch_of_a_rounded_file_is_exact_on_the_true_arm():
    """The whole call (the compiled touch-up with the Numba back end): all 8 branches of every target, each to
    rounding on the true arm."""
    rounded = _rounded_puma()
    T = armkit.fk(rounded, rounded.random_q(20, rng=4))
    res = armkit.ik_all(rounded, T, enforce_limits=False)
    assert (res.success.sum(axis=1) == 8).all()
    back = armkit.fk(rounded, res.q[res.success])
    want = np.repeat(T[:, None], 8, axis=1)[res.success]
    assert np.abs(back[:, :3, 3] - want[:, :3, 3]).max() <= 1e-15 * rounded.reach
    assert np.abs(back[:, :3, :3] - want[:, :3, :3]).max() <= 2e-15
