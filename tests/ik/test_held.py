"""A position target with joints held (armkit.ik.analytic.held): the SCARA's wrist, a 6R arm's wrist, fixed=.

References: the SCARA by hand from its DH rows; the reduced arm against FK of the full arm; every branch against
Levenberg-Marquardt from many starts on the free joints (nothing missed); hypothesis over random targets.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit import IKInputError, Joint, Robot
from armkit.ik.analytic.held import idle_tail, position_solver, reduced

R, P = "revolute", "prismatic"


def _wrapped_close(a, b, prismatic, tol):
    d = np.abs(a - b)
    d = np.where(prismatic, d, np.abs((a - b + np.pi) % (2 * np.pi) - np.pi))
    return bool(np.all(d <= tol))


@pytest.mark.parametrize("name", ["cobra600", "textbook"])
def test_a_scara_position_by_hand(name):
    """Standard DH (q1, d1, a1, 0), (q2, 0, a2, 180 deg), (0, d3, 0, 0), (q4, d4, 0, 0): the tool point is at
    (a1 c1 + a2 c12, a1 s1 + a2 s12, d1 - d3 - d4) whatever q4 is. So d3 = d1 - d4 - z, q2 = ±acos((x² + y² - a1²
    - a2²) / (2 a1 a2)), q1 = atan2(y, x) - atan2(a2 sin q2, a1 + a2 cos q2); the wrist keeps q0."""
    if name == "cobra600":
        arm, (d1, a1, a2, d4) = armkit.load("cobra600"), (0.387, 0.325, 0.275, 0.0)
    else:
        d1, a1, a2, d4 = 0.4, 0.35, 0.3, 0.05
        arm = Robot([Joint(R, d=d1, a=a1), Joint(R, a=a2, alpha=math.pi), Joint(P, lower=-1, upper=1),
                     Joint(R, d=d4)], name="scara")
    assert idle_tail(arm) == [3] and position_solver(arm) is not None
    g = np.random.default_rng(11)
    for _ in range(10):
        r, th, z, wrist = g.uniform(0.1, 0.55), g.uniform(-3, 3), g.uniform(-0.2, 0.3), g.uniform(-3, 3)
        x, y = r * math.cos(th), r * math.sin(th)
        q0 = np.array([0.0, 0.0, 0.0, wrist])
        res = armkit.ik_all(arm, np.array([x, y, z]), q0=q0, enforce_limits=False)
        assert res.success.tolist() == [True, True]
        assert np.all(res.q[:, 3] == wrist)                       # held at its start, exactly
        for sign in (1, -1):
            q2 = sign * math.acos((x * x + y * y - a1 * a1 - a2 * a2) / (2 * a1 * a2))
            q1 = math.atan2(y, x) - math.atan2(a2 * math.sin(q2), a1 + a2 * math.cos(q2))
            want = np.array([q1, q2, d1 - d4 - z, wrist])
            assert any(_wrapped_close(q, want, arm.prismatic, 1e-10) for q in res.q), (want, res.q)
        one = armkit.ik(arm, np.array([x, y, z]), q0=q0, enforce_limits=False)
        assert one.success and one.branch == res.branch[0] and np.allclose(one.q, res.q[0], atol=1e-12)


def test_a_tool_off_the_wrist_axis_needs_the_wrist_held_by_the_user():
    arm = armkit.load("cobra600").with_tool(np.array([[1, 0, 0, 0.05], [0, 1, 0, 0], [0, 0, 1, 0.02], [0, 0, 0, 1.0]]))
    assert idle_tail(arm) == [] and position_solver(arm) is None
    q = np.array([0.4, 0.9, 0.1, -0.7])
    p = armkit.fk(arm, q)[:3, 3]
    with pytest.raises(IKInputError, match="needs a pose target"):
        armkit.ik_all(arm, p)
    assert armkit.ik(arm, p).branch == "lm"                      # four joints for three coordinates: LM answers
    res = armkit.ik_all(arm, p, fixed={"wrist": -0.7})
    good = res.q[res.success]
    assert len(good) == 2 and np.all(good[:, 3] == -0.7)
    assert np.allclose(armkit.fk(arm, good)[:, :3, 3], p, atol=1e-12)
    assert any(_wrapped_close(x, q, arm.prismatic, 1e-9) for x in good)


def test_a_six_r_arm_whose_tool_point_is_its_wrist_centre():
    """The Puma 560 of its DH table: the tool point is the wrist centre, so the three wrist joints never move it and
    the first three give every branch (4, the classic shoulder and elbow pairs) with the wrist at q0."""
    puma = armkit.load("puma560")
    assert idle_tail(puma) == [5, 4, 3]
    g = np.random.default_rng(2)
    for q in puma.random_q(20, rng=g):
        p = armkit.fk(puma, q)[:3, 3]
        res = armkit.ik_all(puma, p, q0=q, enforce_limits=False)
        assert res.success.all() and res.q.shape == (4, 6)
        assert np.all(res.q[:, 3:] == q[3:])
        assert _wrapped_close(res.q[0], q, puma.prismatic, 1e-9)    # q itself, nearest to itself
        assert np.allclose(armkit.fk(puma, res.q)[:, :3, 3], p, atol=1e-12)
        assert len({tuple(np.round(x[:3], 6)) for x in res.q}) == 4  # four different branches


@pytest.mark.parametrize("name, held", [("ur5", (3, 4, 5)), ("ur5", (0, 3, 5)), ("ur5", (1, 4, 5)), ("fighter", (0,)),
                                        ("stanford", (3, 4, 5)), ("cobra600", (3,))])
def test_fixed_joints_and_levenberg_marquardt_from_many_starts_agree(name, held):
    """Every solution LM finds on the free joints (40 random starts, the held ones kept) is one of the branches."""
    arm = armkit.load(name)
    g = np.random.default_rng(7)
    q = arm.random_q(rng=g)
    p = armkit.fk(arm, q)[:3, 3]
    fixed = {arm.joint_names[k]: float(q[k]) for k in held}
    res = armkit.ik_all(arm, p, fixed=fixed, enforce_limits=False, scene=False)   # LM below knows no torso
    good = res.q[res.success]
    assert len(good) >= 1 and np.all(good[:, list(held)] == q[list(held)])
    assert np.allclose(armkit.fk(arm, good)[:, :3, 3], p, atol=1e-9 * max(arm.reach, 1))
    assert any(_wrapped_close(x, q, arm.prismatic, 1e-8) for x in good)
    small = reduced(arm, {k: float(q[k]) for k in held})
    free = [k for k in range(arm.n) if k not in held]
    starts = small.random_q(40, rng=g)
    lm = armkit.ik(small, np.repeat(p[None], 40, axis=0), q0=starts, method="lm", enforce_limits=False)
    for x in lm.q[lm.success]:
        assert any(_wrapped_close(x, y[free], small.prismatic, 1e-6) for y in good), (x, good[:, free])


@settings(max_examples=60, deadline=None)
@given(name=st.sampled_from(["ur5", "puma560", "panda", "cobra600", "fighter", "stanford"]),
       seed=st.integers(0, 2**32 - 1), convention=st.sampled_from(["standard", "modified"]))
def test_the_reduced_arm_is_the_arm_with_its_joints_held(name, seed, convention):
    arm = armkit.load(name)
    if arm.is_dh:
        arm = arm.to_dh(convention)
    g = np.random.default_rng(seed)
    q = arm.random_q(rng=g)
    held = sorted(g.choice(arm.n, size=g.integers(1, arm.n), replace=False).tolist())
    small = reduced(arm, {k: float(q[k]) for k in held})
    free = [k for k in range(arm.n) if k not in held]
    assert small.n == len(free) and small.joint_names == tuple(arm.joint_names[k] for k in free)
    assert np.allclose(armkit.fk(small, q[free]), armkit.fk(arm, q), atol=1e-12 * max(arm.reach, 1))


@settings(max_examples=40, deadline=None)
@given(name=st.sampled_from(["cobra600", "puma560", "stanford"]), seed=st.integers(0, 2**32 - 1),
       convention=st.sampled_from(["standard", "modified"]))
def test_fk_of_every_branch_is_the_target_and_the_start_is_among_them(name, seed, convention):
    arm = armkit.load(name).to_dh(convention)
    g = np.random.default_rng(seed)
    q, other = arm.random_q(2, rng=g)
    p = armkit.fk(arm, q)[:3, 3]
    res = armkit.ik_all(arm, p, q0=q, enforce_limits=False)
    ok = np.asarray(res.success)
    assert ok.any() and _wrapped_close(res.q[0], q, arm.prismatic, 1e-8)
    assert np.allclose(armkit.fk(arm, res.q[ok])[:, :3, 3], p, atol=1e-9 * max(arm.reach, 1))
    # batched == looped, each target's wrist held at its own start
    p2 = armkit.fk(arm, other)[:3, 3]
    batched = armkit.ik_all(arm, np.stack([p, p2]), q0=np.stack([q, other]), enforce_limits=False)
    second = armkit.ik_all(arm, p2, q0=other, enforce_limits=False)
    assert np.array_equal(batched.q[0], res.q) and np.array_equal(batched.success[0], res.success)
    assert np.array_equal(batched.q[1], second.q) and np.array_equal(batched.branch[1], second.branch)
    idle = idle_tail(arm)
    assert np.all(batched.q[1][:, idle] == other[idle]) and np.all(batched.q[0][:, idle] == q[idle])


def test_bad_fixed_values_say_what_is_wrong():
    ur5 = armkit.load("ur5")
    p = np.array([0.3, 0.2, 0.4])
    with pytest.raises(IKInputError, match="leaves 5 joints .* without a closed form for a position"):
        armkit.ik_all(ur5, p, fixed={"wrist_3": 0.0})
    with pytest.raises(IKInputError, match="no joint named"):
        armkit.ik_all(ur5, p, fixed={"nope": 0.0})
    with pytest.raises(IKInputError, match="must be a dict"):
        armkit.ik_all(ur5, p, fixed=[0.1])
    with pytest.raises(IKInputError, match="needs a pose target"):   # no idle joints to hold: the pose closed form
        armkit.ik_all(ur5, p)


def test_the_note_keeps_its_template_so_it_reads_in_korean():
    from armkit.locale.library import fielded, localize

    res = armkit.ik_all(armkit.load("cobra600"), np.array([[0.3, 0.2, 0.25]]))
    note = res.message[0, 0]
    assert fielded(note) is not None and note == "wrist held at the start q0 (turning about the tool point, never moving it)"
    assert "고정" in localize(note, "ko") and "wrist" in localize(note, "ko")


def test_an_arm_whose_every_joint_is_idle_has_no_held_solver():
    """One joint whose axis passes through the tool point: it never moves the point, and nothing is left to solve
    (armkit info printed 'no joints' here, exit 2, while the class line was being extended)."""
    arm = Robot([Joint(R, d=0.3)], name="turntable")
    assert idle_tail(arm) == [0] and position_solver(arm) is None
    with pytest.raises(IKInputError):
        armkit.ik_all(arm, [0.0, 0.0, 0.3])


def test_an_empty_fixed_holds_nothing():
    """fixed={} is the call without it: the UR5's own closed form for a pose (it raised AttributeError), the
    SCARA's wrist held at its start for a position (it was set to 0)."""
    ur5 = armkit.load("ur5")
    T = armkit.fk(ur5, np.full(6, 0.3))
    assert np.array_equal(armkit.ik_all(ur5, T, fixed={}).q, armkit.ik_all(ur5, T).q)
    cobra = armkit.load("cobra600")
    q0 = np.array([0.0, 0.0, 0.0, 0.5])
    res = armkit.ik_all(cobra, np.array([0.3, 0.2, 0.25]), q0=q0, fixed={})
    assert np.all(res.q[:, 3] == 0.5)
