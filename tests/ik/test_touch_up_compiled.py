"""The compiled Gauss-Newton touch-up of the closed forms (issue 19: a file with rounded numbers).

A file whose numbers are a little off its ideal arm in a way that leaves no closed form on its own axes (a
calibrated file: :func:`test_single_call.calibrated`) is solved on its ideal arm and every branch is then
touched up by Gauss-Newton steps on the true arm. The arms here round their twists (``rpy="1.5708"``) and are
set to take that path (:func:`test_single_call.rounded`): every target keeps all its branches. With the Numba back end these steps are compiled
(:func:`armkit.ik.analytic._single._touch_up`) and run inside the one compiled call of a single target,
instead of sending it to the batched path's NumPy steps (0.56 ms -> ~16 µs a Puma call, bench_analytic).

Checked here against definitions, not stored numbers: a touched-up branch reaches the target on the
true arm to rounding (FK of the true model); the compiled steps and NumPy's least-squares steps (``pinv``)
land on the same root; a system that is not square, or a Jacobian with a singular direction, is left to
NumPy; a batch gives each target the bits a single call gives it; the NumPy back end gives the same
branches. (The one-call path against the batched path, bit for bit, on rounded arms: test_single_call.)
"""

from __future__ import annotations

import functools
import importlib.util

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit.ik.analytic import POLISH_DONE, _gauss_newton, closed_form
from armkit.kinematics import packed
from test_single_call import calibrated, rounded

pytestmark = pytest.mark.skipif(importlib.util.find_spec("numba") is None, reason="Numba is not available")


@pytest.fixture(scope="module", autouse=True)
def compiled():
    armkit.set_backend("numba")
    yield
    armkit.set_backend("auto")


def _kernels():
    from armkit.ik.analytic import _single

    return _single


@settings(max_examples=25, deadline=None)
@given(name=st.sampled_from(["puma560", "ur5"]), seed=st.integers(0, 2**16), size=st.sampled_from([1e-9, 1e-6, 1e-4]))
def test_touch_up_reaches_the_target_and_agrees_with_numpy(name, seed, size):
    """Rows moved off a true solution by ``size`` rad come back to the target, to rounding, as NumPy's pinv steps
    bring them (the same root: within 1e-12 rad)."""
    arm = rounded(armkit.load(name))
    rng = np.random.default_rng(seed)
    q = rng.uniform(-2.5, 2.5, (6, arm.n))
    T = armkit.fk(arm, q)
    start = q + rng.uniform(-size, size, q.shape)
    mine = start.copy()
    refused = _kernels().touch_up_rows(packed(arm)[0], mine, T, True, 6, POLISH_DONE)
    theirs = _gauss_newton(arm, start.copy(), T, True, 6)
    J = armkit.jacobian(arm, q)
    well = np.linalg.svd(J, compute_uv=False).min(axis=-1) > 1e-3   # away from the arm's singular configurations
    assert not refused[well].any()
    ok = well & ~refused
    back = armkit.fk(arm, mine[ok])
    assert np.abs(back[:, :3, 3] - T[ok, :3, 3]).max(initial=0.0) <= 4e-16 * arm.reach
    assert np.abs(back[:, :3, :3] - T[ok, :3, :3]).max(initial=0.0) <= 4e-15
    assert np.abs(mine[ok] - theirs[ok]).max(initial=0.0) <= 1e-12
    assert np.array_equal(mine[refused], start[refused])   # a refused row is left as it came


def test_point_targets_of_a_three_joint_arm():
    """The fighter arm (yaw-pitch-pitch, position targets): a 3 x 3 system."""
    arm = rounded(armkit.load("fighter"))
    rng = np.random.default_rng(3)
    q = arm.random_q(8, rng=rng)
    p = armkit.fk(arm, q)[:, :3, 3]
    T = np.zeros((8, 4, 4))
    T[:, :3, 3] = p
    start = q + rng.uniform(-1e-5, 1e-5, q.shape)
    mine = start.copy()
    refused = _kernels().touch_up_rows(packed(arm)[0], mine, T, False, 6, POLISH_DONE)
    assert not refused.any()
    assert np.abs(armkit.fk(arm, mine)[:, :3, 3] - p).max() <= 4e-16 * arm.reach
    assert np.abs(mine - _gauss_newton(arm, start.copy(), p, False, 6)).max() <= 1e-12


def test_what_is_not_square_is_left_to_numpy_and_a_singular_jacobian_takes_pinvs_step():
    """A planar 2R with point targets (3 x 2): refused, the rows unchanged. A UR5 with its wrist straight (q5 = 0:
    joints 4 and 6 in line, the Jacobian of rank 5) is too near singular for the elimination: its steps are pinv's
    (rcond 1e-10), compiled, as NumPy's touch-up takes them: the target to rounding, the same rows within 1e-9 rad
    (joints 4 and 6 nearly in line share their turn as rounding splits it: 2e-11 to 4e-11 apart)."""
    one = _kernels()
    planar = armkit.load("planar2")
    q = np.array([[0.3, 0.7], [1.0, -0.4]])
    T = armkit.fk(planar, q + 0.01)
    start = q.copy()
    assert one.touch_up_rows(packed(planar)[0], q, T, False, 6, POLISH_DONE).all()
    assert np.array_equal(q, start)
    ur5 = armkit.load("ur5")
    q = np.array([[0.3, -1.0, 1.2, 0.4, 0.0, 0.5], [0.3, -1.0, 1.2, 0.4, 0.7, 0.5]])
    assert np.linalg.matrix_rank(armkit.jacobian(ur5, q[0]), tol=1e-10) == 5
    T = armkit.fk(ur5, q + 1e-6)
    for steps in (1, 2, 6):
        mine = q.copy()
        assert not one.touch_up_rows(packed(ur5)[0], mine, T, True, steps, POLISH_DONE).any()
        assert np.abs(mine - _gauss_newton(ur5, q.copy(), T, True, steps)).max() <= 1e-9
    assert np.abs(armkit.fk(ur5, mine) - T).max() <= 1e-15 * ur5.reach


@functools.cache
def _pinv_runner():
    """``_pinv_step`` with its work arrays, compiled once (a kernel made in the test compiled again for every example:
    35 s of the suite)."""
    from numba import njit

    step = _kernels()._pinv_step

    @njit
    def run(J, e, d):
        A, V, g = np.empty((d, d)), np.empty((d, d)), np.empty(d)
        step(J, A, V, e, g, d)

    return run


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**16), rank=st.integers(0, 6), d=st.sampled_from([3, 6]))
def test_the_compiled_pinv_step_is_numpys_pinv(seed, rank, d):
    """``_pinv_step`` (a one-sided Jacobi SVD) against ``np.linalg.pinv(J, rcond=1e-10) @ e`` on random matrices of
    every rank, scaled rows as a Jacobian's (lengths and angles), and exactly singular ones."""
    run = _pinv_runner()
    rng = np.random.default_rng(seed)
    rank = min(rank, d)
    J = rng.normal(size=(d, rank)) @ rng.normal(size=(rank, d)) if rank else np.zeros((d, d))
    J *= rng.uniform(0.1, 2.0, size=(d, 1))
    e = rng.normal(size=d)
    want = np.linalg.pinv(J, rcond=1e-10) @ e
    got = e.copy()
    run(J[None].copy(), got, d)
    assert np.abs(got - want).max() <= 1e-9 * max(1.0, np.abs(want).max())


@pytest.mark.parametrize("name", ["puma560", "ur5", "fighter"])
def test_batch_equals_single_calls_and_numpy(name):
    """A batch of targets gives each the bits of its single (one-call) answer; the NumPy back end gives the same
    branches, within 1e-12 rad; every successful branch reaches its target on the true arm."""
    arm = rounded(armkit.load(name))
    q = arm.random_q(12, rng=5)
    T = armkit.fk(arm, q)
    target = T if name != "fighter" else T[:, :3, 3]
    batch = armkit.ik_all(arm, target)
    for i in range(len(target)):
        one = armkit.ik_all(arm, target[i])
        for f in ("q", "success", "position_error", "rotation_error", "branch", "reason"):
            assert np.array_equal(getattr(batch, f)[i], getattr(one, f)), (f, i)
    assert closed_form(arm) is not None and not closed_form(arm).sf.exact
    armkit.set_backend("numpy")
    try:
        slow = armkit.ik_all(arm, target)
    finally:
        armkit.set_backend("numba")
    assert np.array_equal(slow.success, batch.success) and np.array_equal(slow.branch, batch.branch)
    assert np.abs(slow.q - batch.q).max() <= 1e-12
    good = batch.success
    assert good.sum(axis=1).min() >= 1   # FK of random joint values: at least that branch
    back = armkit.fk(arm, batch.q[good])
    want = np.repeat(T[:, None], batch.q.shape[1], axis=1)[good]
    assert np.abs(back[:, :3, 3] - want[:, :3, 3]).max() <= 1e-15 * arm.reach


@pytest.mark.parametrize("backend", ["numba", "numpy"])
def test_a_target_beside_a_fold_of_the_ideal_arm_keeps_every_branch(backend, monkeypatch):
    """Where the ideal arm of a rounded file misses a target by a hair (its wrist centre inside the true arm's
    sideways offset, outside the ideal arm's), its branches are clipped onto a fold (the Jacobian of rank 4 or 5) and
    Newton's steps from there cannot choose a side: ``_retarget`` solves the ideal arm again for the target moved by
    the two arms' difference. On the Puma every random target has 8 branches (FK of the true arm at rounding), and
    without ``_retarget`` some do not (so the test reaches it); each such branch has the name the exact Puma gives
    the same joint values."""
    import importlib

    analytic = importlib.import_module("armkit.ik.analytic")
    arm = rounded(armkit.load("puma560"))
    q = np.random.default_rng(7).uniform(-np.pi, np.pi, (1000, arm.n))
    T = armkit.fk(arm, q)
    armkit.set_backend(backend)
    try:
        res = armkit.ik_all(arm, T, enforce_limits=False)
        monkeypatch.setattr(analytic, "_retarget", lambda robot, branches, *a: branches)
        without = armkit.ik_all(arm, T, enforce_limits=False)
    finally:
        armkit.set_backend("numba")
    assert res.success.all()
    back = armkit.fk(arm, res.q)
    assert np.abs(back[..., :3, 3] - T[:, None, :3, 3]).max() <= 1e-15 * arm.reach
    assert np.abs(back[..., :3, :3] - T[:, None, :3, :3]).max() <= 2e-15
    for i in range(len(T)):   # eight different configurations, each named once
        assert len(set(res.branch[i])) == 8
        gap = np.abs(np.remainder(res.q[i, :, None] - res.q[i, None] + np.pi, 2 * np.pi) - np.pi).max(axis=-1)
        assert (gap + np.eye(8) * 9 > 1e-6).all()
    unfolded = ~without.success
    assert 0 < unfolded.sum() <= 40
    exact = armkit.load("puma560")   # the arm the rounded file rounds: its own branch names for the same joints
    for i, k in zip(*np.nonzero(unfolded)):
        named = armkit.ik_all(exact, armkit.fk(exact, res.q[i, k]), res.q[i, k], enforce_limits=False)
        gap = np.abs(np.remainder(named.q - res.q[i, k] + np.pi, 2 * np.pi) - np.pi).max(axis=-1)
        near = np.sort(gap)   # (beside a fold the exact arm's own answer is ill-conditioned too: ~1e-9)
        assert near[0] <= 1e-6 < 1e-3 < near[1] and named.branch[np.argmin(gap)] == res.branch[i, k]


def test_armkit_info_says_a_calibrated_file_is_solved_on_its_ideal_arm(tmp_path):
    """``armkit info`` tells a user that the file's numbers are a little off the arm its closed form solves (text,
    Korean, ``--json``), and says nothing of the kind for an exact arm. (A file that only rounds its twists is
    solved on its own axes: tests/ik/test_rounded_file.py.)"""
    import json

    from typer.testing import CliRunner

    from armkit.cli import app

    runner = CliRunner()
    path = str(tmp_path / "puma_calibrated.urdf")
    armkit.save(calibrated(armkit.load("puma560")), path)
    text = runner.invoke(app, ["info", path], env={"COLUMNS": "300", "ARMKIT_LANG": "en"})
    assert text.exit_code == 0
    assert "8 branches; solved on the file's ideal arm" in text.output
    assert "touched up on the true arm" in text.output
    ko = runner.invoke(app, ["--lang", "ko", "info", path], env={"COLUMNS": "300"})
    assert "파일의 이상적인 팔로 풂" in ko.output and "ideal arm" not in ko.output
    assert json.loads(runner.invoke(app, ["info", path, "--json"]).stdout)["closed_form"]["ideal_arm"] is True
    exact = runner.invoke(app, ["info", "puma560"], env={"COLUMNS": "300", "ARMKIT_LANG": "en"})
    assert "ideal arm" not in exact.output
    assert json.loads(runner.invoke(app, ["info", "puma560", "--json"]).stdout)["closed_form"]["ideal_arm"] is False
