"""Why a numeric method failed, settled by the closed form where the arm has one (armkit.ik.verdict).

Reference values: the annulus of a 2-link arm by the law of cosines (written here), LM with the limits off as an
independent check of "only outside the limits", and the closed form's own branches for "missed".
"""

from __future__ import annotations

import numpy as np
import pytest

import armkit
from armkit.ik.numeric import solve_lm
from armkit.ik.verdict import LIMITS, SOLVABLE, UNREACHABLE, closed_form_verdict


@pytest.mark.parametrize("method", ["lm", "newton", "ccd", "fabrik"])
def test_a_point_in_the_inner_hole_is_out_of_reach_for_every_method(method):
    """planar2 (links 1 and 0.5) reaches 0.5 <= r <= 1.5: r = 0.2 is inside the hole. LM said 'max iterations: no
    solution within 1311 iterations', CCD and FABRIK 'did not converge'."""
    r = armkit.load("planar2")
    l1, l2 = (j.a for j in r.joints)
    p = np.array([0.2, 0.0, 0.0])
    assert np.hypot(*p[:2]) < abs(l1 - l2)                 # inside the hole, by the law of cosines
    res = armkit.ik(r, p, method=method)
    assert not res.success and str(res.reason) == "unreachable"
    assert "closed form (planar-2r) finds none" in str(res.message)


def test_the_verdict_follows_the_law_of_cosines():
    r = armkit.load("planar2")
    l1, l2 = (j.a for j in r.joints)
    g = np.random.default_rng(4)
    rad = g.uniform(0.0, 2.0, 300)
    ang = g.uniform(-np.pi, np.pi, 300)
    p = np.stack([rad * np.cos(ang), rad * np.sin(ang), np.zeros(300)], axis=1)
    v = closed_form_verdict(r, p, True)
    inside = (rad >= abs(l1 - l2) + 1e-9) & (rad <= l1 + l2 - 1e-9)
    np.testing.assert_array_equal(v.code == UNREACHABLE, ~inside)
    np.testing.assert_array_equal(v.code == SOLVABLE, inside)
    assert np.all(v.inside[inside] == 2)                   # elbow up and down (joints turn all the way round)


def test_only_outside_the_limits_names_the_closed_form_and_lm_without_limits_agrees():
    """A Puma 560 pose whose branches all break a limit (shoulder narrowed to [-0.2, 0.2] rad): LM says why, from
    the closed form, and LM with the limits off reaches the same pose."""
    base = armkit.load("puma560")
    joints = [armkit.Joint(j.kind, j.theta, j.d, j.a, j.alpha, *((-0.2, 0.2) if k == 1 else (j.lower, j.upper)),
                           j.name) for k, j in enumerate(base.joints)]
    arm = armkit.Robot(joints, base.convention, name="narrow shoulder")
    q = np.array([0.3, 1.2, -0.4, 0.2, 0.5, 0.1])         # shoulder 1.2 rad, outside [-0.2, 0.2]
    T = armkit.fk(arm, q)
    v = closed_form_verdict(arm, T[None], False)
    assert v.code.tolist() == [LIMITS]
    res = armkit.ik(arm, T, method="lm", restarts=5)
    assert not res.success and str(res.reason) == "joint limits"
    assert "reaches the target only outside the joint limits" in str(res.message) and "shoulder" in str(res.message)
    free = armkit.ik(arm, T, method="lm", enforce_limits=False)
    assert free.success


def test_a_solution_lm_missed_is_counted():
    """puma560, seed 4203 of the LM property test: the only in-limit solution has the waist 0.24 deg from its
    limit and LM's 51 starts miss it. The message says the closed form finds it; armkit.ik's default does."""
    arm = armkit.load("puma560")
    q = arm.random_q(3, 4203)
    T = armkit.fk(arm, q)[1]
    res = solve_lm(arm, T[None], np.zeros((1, arm.n)), seed=4203)
    if res.success[0]:
        pytest.skip("LM found it on this back end")
    assert res.reason[0] == "max iterations"
    assert "finds 1 inside the limits (method 'auto' gives them)" in res.message[0]
    assert armkit.ik(arm, T).success


def test_no_verdict_where_the_closed_form_searches_or_is_missing():
    assert closed_form_verdict(armkit.load("ur5"), np.zeros((1, 3)), True) is None       # a pose-only family
    assert closed_form_verdict(armkit.load("panda"), np.eye(4)[None], False) is None     # 7 joints: a sweep
    ur5 = armkit.load("ur5")
    assert closed_form_verdict(ur5, armkit.fk(ur5, ur5.random_q(2, 1)), False).code.tolist() == [SOLVABLE] * 2


def test_the_message_in_korean():
    from armkit.locale.library import localize

    res = armkit.ik(armkit.load("planar2"), np.array([0.2, 0.0, 0.0]), method="ccd")
    ko = localize(res.message, "ko")
    assert "해석적 해(planar-2r)" in ko and "closed form" not in ko
