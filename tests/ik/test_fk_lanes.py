"""The closed forms' check of every branch, side by side, and of the padding rows once (issue 19).

:func:`armkit.kinematics._jit._fk_lanes` computes the poses of up to eight configurations at once, one vector
instruction for four of them, and :func:`armkit.ik.analytic._single._errors_lanes` their errors against a target.
Checked here against their definitions, bit for bit: each pose is the pose that a single FK call (``armkit.fk``
of one configuration with the Numba back end, ``_fk_one``: its own code) gives that configuration, and each
error the one that the check of a single candidate (``_jit_verify.check_pose``) gives it, on arms with revolute
and prismatic joints, one to eight configurations, angles far beyond a turn. The rows of a target with fewer
branches than the kernel's rows repeat row 0, whose work ``_finish`` copies to them: the answers against the
batched path's. (The one-call path against the batched path on whole answers: test_single_call.)
"""

from __future__ import annotations

import functools
import importlib.util

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit.kinematics import packed

pytestmark = pytest.mark.skipif(importlib.util.find_spec("numba") is None, reason="Numba is not available")

ARMS = ("puma560", "ur5", "stanford", "fighter", "planar3", "so101")
"""Revolute arms of 3 to 6 joints, and the Stanford arm's prismatic joint 3."""


@pytest.fixture(scope="module", autouse=True)
def compiled():
    armkit.set_backend("numba")
    yield
    armkit.set_backend("auto")


@functools.lru_cache(maxsize=None)
def _lanes():
    """A compiled caller of the two kernels, as :func:`armkit.ik.analytic._single._finish` calls them."""
    from numba import njit

    from armkit.ik._jit_verify import _angle_of
    from armkit.ik.analytic._single import _errors_lanes
    from armkit.kinematics._jit import LANES, _fk_lanes, sincos_block

    @njit
    def run(F, q, T, pose):
        m, n = q.shape
        qt, s, c = np.empty(m * n), np.empty(m * n), np.empty(m * n)
        for k in range(n):
            for i in range(m):
                qt[k * m + i] = q[i, k]
        sincos_block(qt, s, c)
        X = np.full(12 * LANES, np.nan)
        _fk_lanes(F, qt, s, c, m, n, X)
        dp, sr, cr, dr = np.empty(m), np.empty(m), np.empty(m), np.zeros(m)
        _errors_lanes(X, T, pose, m, dp, sr, cr)
        out = np.zeros((m, 4, 4))
        for i in range(m):
            for j in range(12):
                out[i, j // 4, j % 4] = X[LANES * j + i]
            out[i, 3, 3] = 1.0
            if pose:
                dr[i] = _angle_of(sr[i], cr[i])
        return out, dp, dr

    return run


@settings(max_examples=60, deadline=None)
@given(name=st.sampled_from(ARMS), m=st.integers(1, 8), seed=st.integers(0, 2**32 - 1),
       span=st.sampled_from([1.0, np.pi, 40.0]), pose=st.booleans(), near=st.booleans())
def test_poses_and_errors_side_by_side_are_those_of_one_at_a_time(name, m, seed, span, pose, near):
    """Each configuration's pose is a single ``armkit.fk`` call's, each error ``check_pose``'s, to the bit;
    ``near``: the target is the pose of the first configuration (errors at rounding, the angle taken by division,
    not ``atan2``)."""
    from armkit.ik._jit_verify import check_pose

    arm = armkit.load(name)
    rng = np.random.default_rng(seed)
    q = rng.uniform(-span, span, (m, arm.n))
    if arm.prismatic.any():
        q[:, arm.prismatic] = rng.uniform(0.0, 0.5, (m, int(arm.prismatic.sum())))
    T = armkit.fk(arm, q[0] + (0.0 if near else rng.uniform(-0.3, 0.3, arm.n)))
    got, dp, dr = _lanes()(packed(arm)[0], q, T, pose)
    want = np.array([armkit.fk(arm, x) for x in q])
    assert np.array_equal(got, want)
    for i in range(m):
        e_p, e_r, _ = check_pose(want[i], T, pose, q[i], arm.lower, arm.upper, 1e-12)
        assert dp[i] == e_p and dr[i] == e_r
    if near:
        assert dp[0] < 1e-12 and (dr[0] < 1e-12 or not pose)


def test_a_rotation_error_of_a_half_turn_takes_atan2():
    """Far from the target, where the division would not be the angle, the angle is ``atan2``'s: a pose turned a
    half turn about z gives pi, one turned 0.3 rad gives 0.3."""
    arm = armkit.load("puma560")
    q = np.zeros((2, arm.n))
    q[0, 5], q[1, 5] = np.pi, 0.3     # joint 6 turns the tool about its own z axis
    _, dp, dr = _lanes()(packed(arm)[0], q, armkit.fk(arm, np.zeros(arm.n)), True)
    assert dp == pytest.approx([0.0, 0.0], abs=1e-12)
    assert dr == pytest.approx([np.pi, 0.3], abs=1e-12)


def test_the_rows_that_repeat_row_zero_are_counted_to_the_bit():
    """``_repeats_from``: the trailing rows equal to row 0 in every bit (a zero's sign too; a NaN equals nothing)
    are the padding whose work ``_finish`` copies from row 0."""
    from numba import njit

    from armkit.ik.analytic._single import _repeats_from

    count = njit(lambda a: _repeats_from(a))
    r0 = [0.5, -1.0, 0.0]
    assert count(np.array([r0, [1.0, 2.0, 3.0], r0, r0])) == 2
    assert count(np.array([r0, r0, r0])) == 1
    assert count(np.array([r0, r0, [0.5, -1.0, 1e-300]])) == 3
    assert count(np.array([r0, r0, [0.5, -1.0, -0.0]])) == 3          # -0.0 is not 0.0 here
    assert count(np.array([[np.nan, 0.0], [np.nan, 0.0]])) == 2       # nor NaN NaN
    assert count(np.array([r0])) == 1


@pytest.mark.parametrize("kind", ["spherical-wrist-parallel", "three-parallel-meet", "spherical-general"])
def test_targets_with_fewer_branches_than_rows_answer_as_the_batched_path(kind):
    """Arms of classes whose targets have 2 to 8 branches: the one-call kernel pads the missing rows with row 0 and
    copies its work; every field as the batched path gives it, bit for bit (``test_single_call``'s comparison)."""
    from geometric.test_family import _random_arm
    from test_single_call import _assert_same, _both

    rng = np.random.default_rng(11)
    arm = _random_arm(rng, kind)
    T = armkit.fk(arm, rng.uniform(-np.pi, np.pi, (40, arm.n)))
    counts = set()
    for t in T:
        fast, slow = _both(lambda: armkit.ik_all(arm, t))
        _assert_same(fast, slow)
        counts.add(int(fast.success.sum()))
        fast, slow = _both(lambda: armkit.ik(arm, t))
        _assert_same(fast, slow)
    assert len(counts) > 1 and max(counts) <= 8   # targets with different numbers of branches were met
