"""A file that rounds its numbers is solved on its own axes, its branches named as its DH table names them (issue 19).

A URDF that writes 90 deg as ``rpy="1.5708"`` (3.7e-6 off) describes an arm a hair off its ideal DH twin. Where
the rounding keeps every axis meeting and lying parallel where the ideal arm's do (twists of joints with no offset
between them: the Puma's wrist stays spherical, the UR5's axes 2, 3, 4 parallel), the geometric family solves the
file's own axes in closed form: exact, with no Gauss-Newton touch-up (13-15 µs -> ~4 µs a call,
benchmarks/bench_analytic.py). Its branches are named by the hand-written family of the ideal arm: a branch ``q``
takes the name that family gives ``q`` itself (``Geometric.name_branches``).

Checked against definitions: FK of the true arm reproduces the target at every successful branch; the branch at
the joints a target was made from has the name the exact arm gives those joints (hypothesis); the names of a
target's branches are the family's, each once; ``armkit.ik`` names its branch as ``ik_all`` does; one target, a
few and many (the one-call, the rows and the batched paths) give the same branches and names; a calibrated file
whose axes no longer meet keeps the touch-up; ``armkit info`` says which.
"""

from __future__ import annotations

import importlib.util
import json

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import armkit
from armkit.ik.analytic import POOL_ROWS, closed_form
from test_single_call import calibrated, twists_rounded

pytestmark = pytest.mark.skipif(importlib.util.find_spec("numba") is None, reason="Numba is not available")

ARMS = ("puma560", "ur5")
_ARMS: dict = {}


def _arms(name: str) -> tuple[armkit.Robot, armkit.Robot]:
    """(the exact arm, the file that rounds its twists), loaded once."""
    if name not in _ARMS:
        exact = armkit.load(name)
        _ARMS[name] = exact, twists_rounded(exact)
    return _ARMS[name]


def _wrapped(a: np.ndarray) -> np.ndarray:
    return np.remainder(a + np.pi, 2 * np.pi) - np.pi


def _name_at(arm: armkit.Robot, q: np.ndarray) -> tuple[str, float]:
    """The name of the branch of ``ik_all(arm, fk(arm, q))`` nearest ``q`` (angles modulo 2 pi) and its distance."""
    res = armkit.ik_all(arm, armkit.fk(arm, q), enforce_limits=False)
    gap = np.abs(_wrapped(res.q - q)).max(axis=1)
    i = int(np.argmin(np.where(res.success, gap, np.inf)))
    return str(res.branch[i]), float(gap[i])


@pytest.mark.parametrize("name", ARMS)
def test_a_rounded_file_is_solved_on_its_own_axes_and_a_calibrated_one_on_its_ideal_arm(name):
    exact, rounded = _arms(name)
    cf = closed_form(rounded)
    assert cf.family == "geometric" and cf.sf.exact
    assert cf.names_from.family == closed_form(exact).family and not cf.names_from.sf.exact
    assert cf.solves_exactly()
    off = closed_form(calibrated(exact))
    assert off.family == closed_form(exact).family and not off.sf.exact   # no closed form on its own axes


@settings(max_examples=40, deadline=None)
@given(name=st.sampled_from(ARMS), u=st.lists(st.floats(-np.pi, np.pi), min_size=6, max_size=6))
def test_the_branch_at_the_joints_has_the_name_the_exact_arm_gives_them(name, u):
    """The target made from ``q`` on each arm: the branch at ``q`` is found on the rounded file (to 1e-9 rad), and
    its name is the one the exact arm's closed form gives ``q``; ``armkit.ik`` names its branch as ``ik_all`` names
    the same joints."""
    exact, rounded = _arms(name)
    q = np.array(u)
    J = armkit.jacobian(exact, q)
    assume(np.linalg.svd(J, compute_uv=False).min() > 1e-3)   # off the singular sets, where names switch
    mine, gap = _name_at(rounded, q)
    theirs, gap_exact = _name_at(exact, q)
    assert gap < 1e-9 and gap_exact < 1e-9
    assert mine == theirs
    one = armkit.ik(rounded, armkit.fk(rounded, q), q0=q, enforce_limits=False)   # (q0 is clipped into the limits)
    assert one.success
    assert _name_at(rounded, one.q) == (str(one.branch), pytest.approx(0.0, abs=1e-9))


@pytest.mark.parametrize("name", ARMS)
def test_every_branch_reaches_the_target_and_every_name_is_given_once(name):
    exact, rounded = _arms(name)
    q = rounded.random_q(300, rng=np.random.default_rng(3))
    T = armkit.fk(rounded, q)
    res = armkit.ik_all(rounded, T, enforce_limits=False)
    back = armkit.fk(rounded, res.q[res.success])
    want = np.broadcast_to(T[:, None], res.q.shape[:2] + (4, 4))[res.success]
    assert np.abs(back[:, :3, 3] - want[:, :3, 3]).max() <= 1e-12 * rounded.reach
    assert np.abs(back[:, :3, :3] - want[:, :3, :3]).max() <= 1e-12
    table = set(closed_form(exact).branch_labels)
    for row in res.branch:
        assert set(row) == table   # each of the family's names once
    # as many branches as the exact arm finds for the targets of the same joints (the UR5: fewer near its folds)
    count = armkit.ik_all(exact, armkit.fk(exact, q), enforce_limits=False).success.sum(axis=1)
    assert np.abs(res.success.sum(axis=1) - count).sum() <= 2


@pytest.mark.parametrize("name", ARMS)
def test_one_target_a_few_and_many_give_the_same_branches_and_names(name):
    """One call per target (the one compiled call), a batch of a few (its rows), a batch beyond :data:`POOL_ROWS` (in
    pieces of that many rows) and the batched path: the same joint values, successes and names."""
    _, rounded = _arms(name)
    q = rounded.random_q(POOL_ROWS + 30, rng=np.random.default_rng(5))
    T = armkit.fk(rounded, q)
    many = armkit.ik_all(rounded, T)
    assert "branch" not in vars(many)   # the names are made when read (tens of µs a target)
    few = armkit.ik_all(rounded, T[:30])
    api = importlib.import_module("armkit.ik.api")
    api.ONE_CALL = False
    try:
        batched = armkit.ik_all(rounded, T[:100])
    finally:
        api.ONE_CALL = True
    assert "branch" not in vars(batched)
    for i in range(0, 30, 3):
        one = armkit.ik_all(rounded, T[i])
        for other in (few, many, batched):
            assert np.array_equal(other.success[i], one.success)
            assert np.abs(other.q[i] - one.q).max() <= 1e-12
            assert list(other.branch[i]) == list(one.branch)
        near = armkit.ik(rounded, T[i])
        if near.success:
            assert str(near.branch) == str(one.branch[0]) and np.abs(near.q - one.q[0]).max() <= 1e-12


def test_armkit_info_says_a_rounded_file_is_solved_on_its_own_axes(tmp_path):
    from typer.testing import CliRunner

    from armkit.cli import app

    runner = CliRunner()
    path = str(tmp_path / "puma_rounded.urdf")
    armkit.save(_arms("puma560")[1], path)
    text = runner.invoke(app, ["info", path], env={"COLUMNS": "300", "ARMKIT_LANG": "en"})
    assert text.exit_code == 0
    assert "family geometric, 8 branches; solved on the file's own axes, its branches named as family " \
           "spherical-wrist" in text.output
    assert "ideal arm" not in text.output
    ko = runner.invoke(app, ["--lang", "ko", "info", path], env={"COLUMNS": "300"})
    assert "파일 자체의 축으로 풂" in ko.output and "own axes" not in ko.output
    data = json.loads(runner.invoke(app, ["info", path, "--json"]).stdout)["closed_form"]
    assert data["family"] == "geometric" and data["names_from"] == "spherical-wrist" and data["ideal_arm"] is False
    plain = json.loads(runner.invoke(app, ["info", "puma560", "--json"]).stdout)["closed_form"]
    assert plain["names_from"] is None


@pytest.mark.parametrize("name", ARMS)
def test_the_lean_branches_are_the_solve_s(name):
    """The families' ``branches`` (the angles and label indices that name another family's branches, without
    sentences) give what their ``solve`` gives: the same angles to the bit and the same names."""
    exact, _ = _arms(name)
    cf = closed_form(exact)
    q = exact.random_q(200, rng=np.random.default_rng(9))
    T = armkit.fk(exact, q)
    T[::5, :3, 3] *= 2.0   # some out of reach
    q0phi = q + cf.sf.theta
    got = cf.branches(T, q0phi)
    raw = cf.solve(T, q0phi)
    assert got is not None
    assert np.array_equal(got[0], raw.q)
    assert np.array_equal(np.asarray(cf.branch_labels, dtype=object)[got[1]], raw.label)


def test_near_the_singular_wrist_few_targets_leave_the_one_call_kernel():
    """Targets with ``|q5| < 1e-3`` on the rounded Puma: the one-call kernel answers nearly all itself. A branch whose
    FK error asks for the touch-up sends its target the batched way (and a batch holding one such target, whole).
    Near the singular wrist the second wrist angle is ill-conditioned: ``_sp2cs`` leaves the wrist to SP2 there
    (``subproblems.NEAR_TANGENT``); without that bound 20 % of these targets left the kernel (2026-12-07), with it
    6 %, as with SP2 alone."""
    from armkit.ik.analytic import _one_buffers, one_call_record

    _, rounded = _arms("puma560")
    rng = np.random.default_rng(5)
    q = rng.uniform(-np.pi, np.pi, (2000, 6))
    q[:, 4] = rng.uniform(-1e-3, 1e-3, 2000)
    T = armkit.fk(rounded, q)
    armkit.ik_all(rounded, T[0])
    c = one_call_record(rounded, closed_form(rounded))
    assert c is not None and c.kernel is not None
    fb, ib, bb = _one_buffers(c)
    left = sum(bool(c.entry(np.ascontiguousarray(t).ravel(), c.q0, c.ctx, fb, ib, bb, c.wk) & 3) for t in T)
    assert left <= 0.10 * len(T), left
    # and every branch the batched way gives for them is verified
    res = armkit.ik_all(rounded, T[:200], enforce_limits=False)
    assert (res.success.any(axis=1)).all()


@pytest.mark.parametrize("name", ARMS)
def test_the_compiled_names_are_the_numpy_steps(name, monkeypatch):
    """The names of a rounded file's branches by one compiled call (``_single.name_rows``: the ideal arm's FK, its
    family's kernel, the nearest branch) and by the NumPy steps it replaced, on the same branches: equal, for
    random targets, targets on the wrist's and the elbow's folds and out of reach (branches padded: names given
    twice, settled by ``_single.settle_rows`` against ``geometric._settle``), and the compiled call did answer (the
    UR's wrist straight: its kernel leaves the batch to the NumPy steps, which its family's solve answers)."""
    _, rounded = _arms(name)
    solver = closed_form(rounded)
    rng = np.random.default_rng(8)
    q = rounded.random_q(400, rng=rng)
    if name != "ur5":
        q[::5, 4] = rng.choice([0.0, 1e-9, -1e-7, np.pi], len(q[::5]))   # the wrist straight, or nearly
    q[1::5, 2] = rng.choice([0.0, np.pi, 1e-8], len(q[1::5]))            # the elbow on (or by) a fold
    T = armkit.fk(rounded, q)
    T[2::11, :3, 3] *= 2.5                                               # out of reach
    Q = armkit.ik_all(rounded, T, enforce_limits=False).q
    geometric = importlib.import_module("armkit.ik.analytic.geometric")
    answered = []
    real = geometric._named_compiled
    monkeypatch.setattr(geometric, "_named_compiled", lambda *a: answered.append(1) or real(*a))
    compiled = solver.name_branches(Q, T)
    got = real(rounded, solver.names_from, rounded.cache["ideal_arm"], np.ascontiguousarray(Q.reshape(-1, 6)), 8)
    monkeypatch.setattr(geometric, "_named_compiled", lambda *a: None)
    steps = solver.name_branches(Q, T)
    assert answered and got is not None
    assert got[1].sum() >= 10   # targets with a name given twice: settled by the compiled call (settle_rows)
    assert np.array_equal(compiled, steps)
    assert len({tuple(row) for row in compiled}) > 1
    if name == "ur5":   # a branch with the wrist exactly straight: the UR's kernel leaves the batch to the steps
        Q0 = Q[:20].copy()
        Q0[3, 2, 4] = 0.0
        assert real(rounded, solver.names_from, rounded.cache["ideal_arm"],
                    np.ascontiguousarray(Q0.reshape(-1, 6)), 8) is None
        assert solver.name_branches(Q0, T[:20]).shape == (20, 8)


def test_names_given_twice_are_settled_as_the_numpy_steps_settle_them(monkeypatch):
    """The rounded UR5 pads many targets' branches (out of reach, an elbow on its fold): names given twice, settled by
    the compiled call (``_single.settle_rows``: the same order of the branches by their joint values, the same
    pairing nearest first, ties within ``SETTLE_TIE``) as by ``geometric._settle``, on 2,000 targets."""
    _, rounded = _arms("ur5")
    solver = closed_form(rounded)
    rng = np.random.default_rng(101)
    q = rounded.random_q(2000, rng=rng)
    q[1::5, 2] = rng.choice([0.0, np.pi, 1e-8], len(q[1::5]))
    T = armkit.fk(rounded, q)
    T[2::7, :3, 3] *= rng.uniform(1.05, 3.0, len(T[2::7]))[:, None]
    Q = armkit.ik_all(rounded, T, enforce_limits=False).q
    geometric = importlib.import_module("armkit.ik.analytic.geometric")
    compiled = solver.name_branches(Q, T)
    got = geometric._named_compiled(rounded, solver.names_from, rounded.cache["ideal_arm"],
                                    np.ascontiguousarray(Q.reshape(-1, 6)), 8)
    assert got is not None and got[1].sum() > 500   # the compiled call answered, many names given twice
    monkeypatch.setattr(geometric, "_named_compiled", lambda *a: None)
    assert np.array_equal(compiled, solver.name_branches(Q, T))


@pytest.mark.parametrize("name", ARMS)
def test_the_nearest_branch_is_named_among_the_kernel_s_branches_as_among_solve_s(name, monkeypatch):
    """:func:`armkit.ik`'s one branch a target is named among every branch of the target: those of the one-call
    kernel (``geometric._kernel_branches``, named as ``ik_all`` names them) and those of ``Geometric.solve`` (the
    way before, and where the kernel does not serve) give the same names, with starts far off, limits on and off,
    targets out of reach; and the name is the one ``ik_all`` gives the same joint values."""
    _, rounded = _arms(name)
    solver = closed_form(rounded)
    rng = np.random.default_rng(9)
    T = armkit.fk(rounded, rounded.random_q(120, rng=rng))
    T[::7, :3, 3] *= 2.5
    geometric = importlib.import_module("armkit.ik.analytic.geometric")
    for q0, enforce in ((None, True), (rng.uniform(-4.0, 4.0, 6), False)):
        near = armkit.ik(rounded, T, q0, enforce_limits=enforce)
        Q = near.q[:, None, :]
        kernel = solver.name_branches(Q, T)
        assert geometric._kernel_branches(rounded, T) is not None
        with monkeypatch.context() as m:
            m.setattr(geometric, "_kernel_branches", lambda *a: None)
            solved = solver.name_branches(Q, T)
        assert np.array_equal(kernel, solved)
        every = armkit.ik_all(rounded, T, q0, enforce_limits=enforce)
        for i in np.flatnonzero(near.success):
            j = int(np.argmin(np.abs(every.q[i] - near.q[i]).max(axis=1)))
            assert np.abs(every.q[i, j] - near.q[i]).max() <= 1e-12 and every.branch[i, j] == near.branch[i]
