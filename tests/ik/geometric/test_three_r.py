"""Position IK of any 3R (and spatial 2R) arm by subproblems (the ``geometric-3r`` and ``geometric-2r`` families),
against independent references.

The laws: every successful branch puts the tool point on the target (FK of the robot, not of the solver's
chain) and the configuration the target was made from is one of them; no solution found by Levenberg-Marquardt
from many random starts (another algorithm) is missing; on the fighter, whose own family was derived by hand
(yaw, then the two pitch joints in their plane), the subproblems give the same configurations; the NumPy
back end gives the compiled one's answers; a target beyond the reach is reported as unreachable.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import armkit
from armkit import Joint, Robot, _jit_loader
from armkit.ik.analytic import closed_form, solve_all
from armkit.ik.analytic.geometric import Geometric1R, Geometric2R, Geometric3R
from armkit.ik.geometric.classify import classify
from armkit.ik.geometric.poe import poe


def _arm(rows, convention="standard", tool_xyz=(0.0, 0.0, 0.0)) -> Robot:
    tool = np.eye(4)
    tool[:3, 3] = tool_xyz
    return Robot([Joint("revolute", *row, -np.pi, np.pi) for row in rows], convention, tool=tool, name="arm3")


def _wrapped(a: np.ndarray) -> np.ndarray:
    return np.abs(np.angle(np.exp(1j * a)))


def _has(qs: np.ndarray, q: np.ndarray, tol: float) -> bool:
    return bool(len(qs)) and bool((_wrapped(qs - q).max(axis=-1) <= tol).any())


@st.composite
def three_r(draw):
    """3R arms of random DH rows (either convention, a tool offset), some with axes 1 ∥ 2 or 2 ∥ 3, some with
    axes 1, 2 or 2, 3 meeting."""
    rows = [[draw(st.floats(-1.0, 1.0)) for _ in range(4)] for _ in range(3)]
    special = draw(st.sampled_from([None, 0, 1]))
    convention = draw(st.sampled_from(["standard", "modified"]))
    if special is not None:
        row = rows[special + (1 if convention == "modified" else 0)]
        if draw(st.booleans()):
            row[3] = 0.0                   # a twist of 0: two consecutive axes parallel
        else:
            row[2] = 0.0                   # no common normal's length (a = 0): the two axes meet
    tool = [draw(st.floats(-0.5, 0.5)) for _ in range(3)]
    return _arm(rows, convention, tool)


@settings(max_examples=60, deadline=None)
@given(arm=three_r(), seed=st.integers(0, 2**31 - 1))
def test_every_branch_reaches_the_target_and_the_start_is_among_them(arm, seed):
    assume(getattr(closed_form(arm), "family", None) == "geometric-3r")    # (three axes through one point: the gimbal)
    q = arm.random_q(rng=seed)
    p = armkit.fk(arm, q)[:3, 3]
    res = armkit.ik_all(arm, p, enforce_limits=False)
    ok = np.asarray(res.success)
    assert res.q.shape == (4, 3) and 1 <= ok.sum() <= 4
    ends = armkit.fk(arm, res.q[ok])[:, :3, 3]
    assert np.abs(ends - p).max() <= 1e-9
    assert _has(res.q[ok], q, 1e-6), (res.q[ok], q)
    assert set(np.asarray(res.reason)[~ok]) <= {"unreachable"}


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize("kind", ["general", "2 || 3", "1 || 2", "1, 2 meet", "2, 3 meet"])
def test_no_solution_missed_against_many_lm_starts(kind, seed):
    g = np.random.default_rng(seed)
    rows = g.uniform(-1.0, 1.0, (3, 4))
    if kind == "2 || 3":
        rows[1, 3] = 0.0
    elif kind == "1 || 2":
        rows[0, 3] = 0.0
    elif kind == "1, 2 meet":
        rows[0, 2] = 0.0
    elif kind == "2, 3 meet":
        rows[1, 1:3] = 0.0
    arm = _arm(rows.tolist(), tool_xyz=g.uniform(-0.5, 0.5, 3))
    family = closed_form(arm)
    assert isinstance(family, Geometric3R) and family.case == kind
    assert classify(arm).name == ("3R-two-parallel" if "||" in kind else "3R-general")
    for t in range(4):
        p = armkit.fk(arm, arm.random_q(rng=100 * seed + t))[:3, 3]
        every = armkit.ik_all(arm, p, enforce_limits=False)
        found = every.q[np.asarray(every.success)]
        lm = armkit.ik(arm, np.tile(p, (48, 1)), arm.random_q(48, rng=t), method="lm", restarts=0,
                       enforce_limits=False, seed=t)
        solved = lm.q[np.asarray(lm.success)]
        assert len(solved) >= 10
        for x in solved:
            assert _has(found, x, 1e-5), (x, found)


def test_the_fighter_by_subproblems_has_the_configurations_of_its_own_family():
    arm = armkit.load("fighter")
    assert closed_form(arm).family == "yaw-pitch-pitch"
    geometric = Geometric3R(arm, poe(arm), classify(arm))
    targets = armkit.fk(arm, arm.random_q(40, rng=8))[:, :3, 3]
    q0 = np.zeros((40, 3))
    ours = solve_all(arm, geometric, targets, q0, True, None, False)
    theirs = solve_all(arm, closed_form(arm), targets, q0, True, None, False)
    for b in range(40):
        a = ours.q[b][np.asarray(ours.success[b])]
        h = theirs.q[b][np.asarray(theirs.success[b])]
        assert len(a) == len(h) == 4
        assert all(_has(a, x, 1e-9) for x in h) and all(_has(h, x, 1e-9) for x in a)


def test_numpy_back_end_gives_the_compiled_answers():
    pytest.importorskip("numba")
    arm = _arm([[0.2, 0.1, 0.3, 0.7], [-0.3, 0.2, 0.5, -1.1], [0.1, -0.2, 0.4, 0.4]], tool_xyz=(0.1, 0.2, 0.0))
    targets = armkit.fk(arm, arm.random_q(12, rng=2))[:, :3, 3]
    before = _jit_loader.backend_choice()
    try:
        armkit.set_backend("numba")
        compiled = armkit.ik_all(arm, targets, enforce_limits=False)
        armkit.set_backend("numpy")
        plain = armkit.ik_all(arm, targets, enforce_limits=False)
    finally:
        armkit.set_backend(before)
    np.testing.assert_array_equal(compiled.success, plain.success)
    ok = np.asarray(compiled.success)
    assert np.allclose(compiled.q[ok], plain.q[ok], atol=1e-9)


def test_beyond_the_reach_every_branch_says_unreachable():
    arm = _arm([[0.2, 0.1, 0.3, 0.7], [-0.3, 0.2, 0.5, -1.1], [0.1, -0.2, 0.4, 0.4]], tool_xyz=(0.1, 0.2, 0.0))
    far = np.array([5.0, 0.0, 0.0])
    res = armkit.ik_all(arm, far)
    assert not np.asarray(res.success).any() and set(res.reason) == {"unreachable"}
    assert all("no configuration of this arm reaches the target" in m for m in res.message)
    one = armkit.ik(arm, far)
    assert not bool(one.success) and str(one.reason) == "unreachable"


def test_classes_without_a_finite_answer_are_left_to_the_numeric_solvers():
    planar = _arm([[0.0, 0.0, 0.5, 0.0], [0.0, 0.0, 0.4, 0.0], [0.0, 0.0, 0.3, 0.0]])   # a curve of solutions
    assert classify(planar).name == "3R-planar" and not isinstance(closed_form(planar), Geometric3R)
    on_axis = _arm([[0.1, 0.2, 0.3, 0.7], [0.2, 0.1, 0.4, -0.9], [0.3, 0.0, 0.0, 0.0]], "modified")
    assert Geometric3R.detect(None, on_axis) is None     # the tool point on axis 3: joint 3 does not move it


# ---------------------------------------------------------------- spatial 2R arms (the geometric-2r family)
@pytest.mark.parametrize("meet", [False, True], ids=["offset shoulder", "pan-tilt"])
def test_two_joints_every_branch_reaches_the_target_and_the_start_is_among_them(meet):
    g = np.random.default_rng(7 if meet else 8)
    counts = []
    for t in range(60):
        rows = g.uniform(-1.0, 1.0, (2, 4))
        if meet:
            rows[0, 2] = 0.0                         # a1 = 0: the two axes meet (a pan-tilt head)
        arm = _arm(rows.tolist(), tool_xyz=g.uniform(-0.5, 0.5, 3))
        family = closed_form(arm)
        assert isinstance(family, Geometric2R) and family.case == ("1, 2 meet" if meet else "general")
        q = arm.random_q(rng=t)
        p = armkit.fk(arm, q)[:3, 3]
        res = armkit.ik_all(arm, p, enforce_limits=False)
        ok = np.asarray(res.success)
        counts.append(int(ok.sum()))
        assert np.abs(armkit.fk(arm, res.q[ok])[:, :3, 3] - p).max() <= 1e-9
        assert _has(res.q[ok], q, 1e-6)
    # a pan-tilt reaches each point of its sphere twice (pan by pi, tilt mirrored); an offset shoulder once
    assert set(counts) == ({2} if meet else {1})


def test_two_joints_off_their_surface_say_unreachable():
    arm = _arm([[0.1, 0.2, 0.3, 0.7], [0.0, 0.1, 0.4, 0.0]], tool_xyz=(0.2, 0.1, 0.0))
    p = armkit.fk(arm, np.array([0.4, -0.3]))[:3, 3] + np.array([0.0, 0.0, 0.2])
    res = armkit.ik_all(arm, p)
    assert not np.asarray(res.success).any() and set(res.reason) == {"unreachable"}
    assert np.all(np.asarray(res.position_error) > 1e-3)


def test_one_joint_turns_the_tool_point_onto_the_target_or_says_how_far_it_is():
    tool = np.eye(4)
    tool[:3, 3] = (0.2, 0.1, 0.3)
    arm = Robot([Joint("revolute", 0.1, 0.2, 0.3, 0.7, -np.pi, np.pi)], tool=tool)
    assert isinstance(closed_form(arm), Geometric1R)
    for t in range(20):
        q = arm.random_q(rng=t)
        res = armkit.ik_all(arm, armkit.fk(arm, q)[:3, 3])
        assert bool(res.success[0]) and abs(np.angle(np.exp(1j * (res.q[0, 0] - q[0])))) <= 1e-12
    # off the circle: the nearest angle (a dense scan of the turn agrees), reported unreachable
    p = np.array([0.3, -0.2, 0.1])
    res = armkit.ik(arm, p)
    assert not bool(res.success) and str(res.reason) == "unreachable"
    scan = np.linspace(-np.pi, np.pi, 20001)[:, None]
    miss = np.linalg.norm(armkit.fk(arm, scan)[:, :3, 3] - p, axis=1)
    assert float(res.position_error) <= miss.min() + 1e-9
