"""Position IK of chains of 1 to 3 joints with prismatic ones (the ``geometric-prismatic`` family): the textbook
arms (Cartesian, cylindrical, spherical, SCARA) and every other order of turns and slides.

References, independent of the solver: each textbook arm's IK derived by hand from its DH rows in the test; the
Stanford arm's first three joints against its own 6-joint closed form (another solver: the spherical wrist's
position part); Levenberg-Marquardt from many random starts (no solution it finds is missing); the rank of a
finite-difference Jacobian for the classes called degenerate; and for random chains FK of the robot (every
branch reaches the target, the configuration the target came from is among them).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import armkit
from armkit import Joint, Robot
from armkit.ik.analytic import closed_form
from armkit.ik.analytic.geometric_prismatic import GeometricPrismatic
from armkit.ik.geometric.classify import classify
from test_gimbal import _fd_ranks, numeric_jacobian  # noqa: E402  (central differences of FK, and their ranks)

R, P = "revolute", "prismatic"
HALF = math.pi / 2


def _joint(kind: str, theta=0.0, d=0.0, a=0.0, alpha=0.0) -> Joint:
    lo, hi = (-math.pi, math.pi) if kind == R else (-2.0, 2.0)
    return Joint(kind, theta, d, a, alpha, lo, hi)


def _same(a: np.ndarray, b: np.ndarray, slides: np.ndarray, tol: float) -> bool:
    d = np.asarray(a - b, dtype=float)
    d[..., ~slides] = np.angle(np.exp(1j * d[..., ~slides]))
    return bool(np.abs(d).max() <= tol)


def _has(qs: np.ndarray, q: np.ndarray, slides: np.ndarray, tol: float) -> bool:
    return any(_same(x, q, slides, tol) for x in qs)


def _solved(robot: Robot, p: np.ndarray) -> np.ndarray:
    res = armkit.ik_all(robot, p, enforce_limits=False)
    return res.q[np.asarray(res.success)]


def _fd_rank(robot: Robot, q: np.ndarray, tol: float = 1e-6) -> int:
    """The rank of the tool point's Jacobian by central differences of FK (not the code under test): directions
    the point moves in by more than ``tol`` per unit of slide, or of the arm's size per rad of turn."""
    J = numeric_jacobian(robot, q)[:3]
    J[:, ~np.asarray(robot.chain.prismatic)] /= max(float(robot.reach), 1e-9)
    s = np.linalg.svd(J, compute_uv=False)
    return int((s > tol * max(s[0], 1.0)).sum())


# ---------------------------------------------------------------- random chains
@st.composite
def chains(draw):
    """1 to 3 joints with at least one slide, random DH rows of either convention (some twists of 0 or 90 deg,
    some lengths of 0) and a tool offset."""
    n = draw(st.integers(1, 3))
    kinds = [draw(st.sampled_from([R, P])) for _ in range(n)]
    if P not in kinds:
        kinds[draw(st.integers(0, n - 1))] = P
    joints = []
    for kind in kinds:
        theta, d, a = (draw(st.floats(-1.0, 1.0)) for _ in range(3))
        alpha = draw(st.one_of(st.floats(-1.5, 1.5), st.sampled_from([0.0, HALF, -HALF])))
        if draw(st.booleans()):
            a = 0.0
        joints.append(_joint(kind, theta, d, a, alpha))
    tool = np.eye(4)
    tool[:3, 3] = [draw(st.floats(-0.5, 0.5)) for _ in range(3)]
    convention = draw(st.sampled_from(["standard", "modified"]))
    return Robot(joints, convention, tool=tool, name="chain")


@settings(max_examples=80, deadline=None)
@given(arm=chains(), seed=st.integers(0, 2**31 - 1))
def test_every_branch_reaches_the_target_and_the_start_is_among_them(arm, seed):
    cls = classify(arm)
    q = arm.random_q(rng=seed)
    slides = np.asarray(arm.chain.prismatic)
    if cls.degenerate:          # the joints cannot move the point in every direction (classify: by 1e-4 of the
        # arm's size; checked here at 1e-2): the numeric solvers answer
        assert _fd_rank(arm, q, 1e-2) < arm.n and closed_form(arm) is None
        return
    assert _fd_rank(arm, q) == arm.n or _fd_rank(arm, arm.random_q(rng=seed + 1)) == arm.n
    family = closed_form(arm)
    assert isinstance(family, GeometricPrismatic) and cls.solver == "closed form"
    p = armkit.fk(arm, q)[:3, 3]
    res = armkit.ik_all(arm, p, enforce_limits=False)
    ok = np.asarray(res.success)
    assert res.q.shape == (cls.max_solutions, arm.n) and ok.sum() >= 1
    ends = armkit.fk(arm, res.q[ok])[:, :3, 3]
    assert np.abs(ends - p).max() <= 1e-9
    assert _has(res.q[ok], q, slides, 1e-6), (res.q[ok], q)
    assert set(np.asarray(res.reason)[~ok]) <= {"unreachable"}


@pytest.mark.parametrize("seed", range(2))
@pytest.mark.parametrize("kinds", ["RPP", "PRP", "PPR", "RRP", "RPR", "PRR", "RP", "PR"])
def test_no_solution_missed_against_many_lm_starts(kinds, seed):
    g = np.random.default_rng(seed + 10 * len(kinds))
    rows = g.uniform(-1.0, 1.0, (len(kinds), 4))
    tool = np.eye(4)
    tool[:3, 3] = g.uniform(-0.5, 0.5, 3)
    arm = Robot([_joint(R if k == "R" else P, *row) for k, row in zip(kinds, rows)], tool=tool, name="chain")
    assert isinstance(closed_form(arm), GeometricPrismatic)
    for t in range(3):
        _nothing_missed(arm, armkit.fk(arm, arm.random_q(rng=100 * seed + t))[:3, 3], t)


def _nothing_missed(arm: Robot, target: np.ndarray, seed: int) -> None:
    """Levenberg-Marquardt from 40 random starts: every solution it finds is among the closed form's branches."""
    every = armkit.ik_all(arm, target, enforce_limits=False)
    found = every.q[np.asarray(every.success)]
    lm = armkit.ik(arm, np.tile(target, (40,) + (1,) * target.ndim), arm.random_q(40, rng=seed), method="lm",
                   restarts=0, enforce_limits=False, seed=seed)
    solved = lm.q[np.asarray(lm.success)]
    assert len(solved) >= 5
    for x in solved:
        assert _has(found, x, np.asarray(arm.chain.prismatic), 1e-5), (x, found)


# ---------------------------------------------------------------- the textbook arms, by hand
def test_cylindrical_arm_by_hand():
    """A turn about z at height d1, a vertical lift d2, a horizontal reach d3 (standard DH rows (q1, 0.3, 0, 0),
    (0, d2, 0, -90 deg), (0, d3, 0, 0)). From the rows: the tool is at (-d3 sin q1, d3 cos q1, 0.3 + d2), so
    d2 = z - 0.3, d3 = ±√(x² + y²), q1 = atan2(-x / d3, y / d3)."""
    arm = Robot([_joint(R, d=0.3), _joint(P, alpha=-HALF), _joint(P)], name="cylindrical")
    assert classify(arm).name == "RPP-cylindrical" and classify(arm).max_solutions == 2
    for x, y, z in [(0.2, 0.3, 0.5), (-0.4, 0.1, 0.1), (0.0, -0.7, 0.9)]:
        found = _solved(arm, np.array([x, y, z]))
        assert len(found) == 2
        for d3 in (math.hypot(x, y), -math.hypot(x, y)):
            hand = np.array([math.atan2(-x / d3, y / d3), z - 0.3, d3])
            assert _has(found, hand, np.array([False, True, True]), 1e-12)


def test_scara_rrp_by_hand():
    """Two parallel turns (links 0.4 and 0.3) and a slide along them: standard DH (q1, 0.2, 0.4, 0), (q2, 0, 0.3,
    180 deg), (0, d3, 0, 0). The slide points down (the twist of 180 deg), so z = 0.2 - d3; in the plane the law of
    cosines gives q2 = ±acos((x² + y² - 0.4² - 0.3²) / (2 · 0.4 · 0.3)) and q1 = atan2(y, x) - atan2(0.3 sin q2,
    0.4 + 0.3 cos q2)."""
    arm = Robot([_joint(R, d=0.2, a=0.4), _joint(R, a=0.3, alpha=math.pi), _joint(P)], name="scara")
    assert classify(arm).name == "RRP-scara" and classify(arm).max_solutions == 2
    for x, y, z in [(0.5, 0.2, 0.05), (-0.1, 0.6, -0.3)]:
        found = _solved(arm, np.array([x, y, z]))
        assert len(found) == 2
        for sign in (1, -1):
            q2 = sign * math.acos((x * x + y * y - 0.16 - 0.09) / 0.24)
            q1 = math.atan2(y, x) - math.atan2(0.3 * math.sin(q2), 0.4 + 0.3 * math.cos(q2))
            assert _has(found, np.array([q1, q2, 0.2 - z]), np.array([False, False, True]), 1e-12)


def test_cartesian_arm_by_hand():
    """Three perpendicular slides: modified DH (Craig) rows (alpha, a, theta, d) = (0, 0, 0, d1), (-90 deg, 0,
    -90 deg, d2), (-90 deg, 0, 0, d3) put the tool at (d3 ... ) read off by FK of unit moves: one solution,
    the differences of the target from the zero position along the three slide directions."""
    arm = Robot([_joint(P), _joint(P, theta=-HALF, alpha=-HALF), _joint(P, alpha=-HALF)], "modified", name="xyz")
    assert classify(arm).name == "PPP-cartesian" and classify(arm).max_solutions == 1
    origin = armkit.fk(arm, np.zeros(3))[:3, 3]
    dirs = np.array([armkit.fk(arm, np.eye(3)[k])[:3, 3] - origin for k in range(3)])
    assert np.allclose(np.abs(dirs @ dirs.T), np.eye(3), atol=1e-12)       # perpendicular unit slides
    target = np.array([0.3, -0.2, 0.7])
    found = _solved(arm, target)
    assert len(found) == 1
    np.testing.assert_allclose(found[0], dirs @ (target - origin), atol=1e-12)


def test_stanford_arm_position_part_agrees_with_its_six_joint_closed_form():
    stanford = armkit.load("stanford")
    three = Robot(stanford.joints[:3], stanford.convention, base=stanford.base, name="stanford3")
    assert classify(three).name == "RRP-spherical" and classify(three).max_solutions == 4
    slides = np.array([False, False, True])
    for seed in range(10):
        q = stanford.random_q(rng=seed)
        six = armkit.ik_all(stanford, armkit.fk(stanford, q), enforce_limits=False)
        theirs = six.q[np.asarray(six.success)][:, :3]
        wrist = armkit.fk(three, q[:3])[:3, 3]          # axes 4, 5, 6 meet at joint 4's origin (d4 = 0)
        ours = _solved(three, wrist)
        assert len(ours) == 4 and len(theirs) == 8
        assert all(_has(ours, x, slides, 1e-9) for x in theirs) and all(_has(theirs, x, slides, 1e-9) for x in ours)


# ---------------------------------------------------------------- honest answers
def test_off_the_surface_of_a_two_joint_arm_is_unreachable_with_its_distance():
    arm = Robot([_joint(R, alpha=HALF), _joint(P)], name="polar")      # turn about z, slide in the xy-plane
    assert classify(arm).name == "RP" and isinstance(closed_form(arm), GeometricPrismatic)
    found = _solved(arm, np.array([0.3, 0.4, 0.0]))
    assert len(found) == 2 and sorted(np.round(np.abs(found[:, 1]), 12)) == [0.5, 0.5]
    res = armkit.ik_all(arm, np.array([0.3, 0.4, 0.25]), enforce_limits=False)
    assert not np.asarray(res.success).any() and set(res.reason) == {"unreachable"}
    np.testing.assert_allclose(res.position_error, 0.25, atol=1e-12)


def test_a_slide_beyond_its_stroke_is_a_joint_limit():
    arm = Robot([Joint(R, d=0.3), Joint(P, alpha=-HALF, lower=0.0, upper=0.5), Joint(P, lower=0.1, upper=0.6)],
                name="cylindrical")
    res = armkit.ik_all(arm, np.array([0.2, 0.3, 0.5]))
    assert list(np.asarray(res.success)) == [True, False]
    assert res.reason[1] == "joint limits" and res.q[1, 2] < 0.0
    far = armkit.ik(arm, np.array([0.0, 0.0, 2.0]))      # the lift would need 1.7 m of its 0.5
    assert not bool(far.success) and str(far.reason) == "joint limits"


def test_a_turntable_under_two_level_slides_is_degenerate_and_left_to_the_numeric_solvers():
    """Slides in the plane perpendicular to the turn: the tool point cannot rise, so a position has a circle of
    solutions or none."""
    arm = Robot([_joint(R, alpha=HALF), _joint(P, theta=HALF, alpha=HALF), _joint(P)], name="table")
    assert _fd_rank(arm, arm.random_q(rng=1)) == 2
    assert classify(arm).degenerate and closed_form(arm) is None


# ---------------------------------------------------------------- six joints: a slide and a spherical wrist
def _wrist_arm(seed: int, at_base: bool) -> Robot:
    """Six standard-DH joints with one or two slides: three positioning joints of random rows and a spherical
    wrist (a = 0 on the wrist rows, d = 0 on the middle one, twists of ±90 deg), the wrist at the end or, read
    the other way, at the base."""
    g = np.random.default_rng(seed)
    rows = g.uniform(-0.5, 0.5, (6, 4))
    w = (0, 1) if at_base else (3, 4)
    rows[w[0], 2] = rows[w[1], 1] = rows[w[1], 2] = 0.0
    rows[w[0], 3], rows[w[1], 3] = g.choice([HALF, -HALF], 2)
    if not at_base:
        rows[5, 2] = 0.0
    kinds = [R] * 6
    for k in g.choice(3, size=g.integers(1, 3), replace=False):
        kinds[k + (3 if at_base else 0)] = P
    tool = np.eye(4)
    tool[:3, 3] = g.uniform(-0.2, 0.2, 3)
    return Robot([_joint(k, *row) for k, row in zip(kinds, rows)], tool=tool, name="wrist")


@pytest.mark.parametrize("at_base", [False, True], ids=["wrist at the end", "wrist at the base"])
def test_a_slide_and_a_spherical_wrist_every_branch_reaches_the_pose(at_base):
    from armkit.ik.analytic.geometric_prismatic import GeometricPrismaticWrist

    solved = 0
    for seed in range(40):
        arm = _wrist_arm(seed, at_base)
        cls = classify(arm)
        if cls.degenerate:        # the first three cannot move the wrist centre every way: no full-rank Jacobian
            assert _fd_ranks(arm, arm.random_q(rng=seed))[0] < 6 and closed_form(arm) is None
            continue
        assert cls.name.endswith("spherical-wrist-base" if at_base else "spherical-wrist")
        family = closed_form(arm)
        assert family is not None and (family.family == "geometric-prismatic-wrist" or "RRP" in arm.joint_types)
        q = arm.random_q(rng=seed)
        T = armkit.fk(arm, q)
        res = armkit.ik_all(arm, T, enforce_limits=False)
        ok = np.asarray(res.success)
        assert res.q.shape[0] == cls.max_solutions and ok.any()
        assert np.abs(armkit.fk(arm, res.q[ok]) - T).max() <= 1e-9
        assert _has(res.q[ok], q, np.asarray(arm.chain.prismatic), 1e-6)
        solved += isinstance(family, GeometricPrismaticWrist)
    assert solved >= 20


def test_a_stanford_arm_whose_first_axes_miss_each_other_still_gets_every_branch():
    """The Stanford arm with an offset between axes 1 and 2 (a1 = 0.05 m): its own compiled solver needs them to
    meet, so this family answers; LM from 40 random starts finds nothing it missed."""
    stanford = armkit.load("stanford")
    joints = list(stanford.joints)
    j = joints[0]
    joints[0] = Joint(j.kind, j.theta, j.d, 0.05, j.alpha, j.lower, j.upper, j.name)
    arm = Robot(joints, stanford.convention, name="stanford-offset")
    assert closed_form(stanford).family == "geometric"
    assert closed_form(arm).family == "geometric-prismatic-wrist"
    for t in range(3):
        _nothing_missed(arm, armkit.fk(arm, arm.random_q(rng=t)), t)


# ---------------------------------------------------------------- four joints: the SCARA
@pytest.mark.parametrize("name", ["textbook", "cobra600"])
def test_scara_rrpr_by_hand(name):
    """Standard DH (q1, d1, a1, 0), (q2, 0, a2, 180 deg), (0, d3, 0, 0), (q4, d4, 0, 0): a SCARA of the textbook
    (d1, a1, a2, d4 = 0.4, 0.35, 0.3, 0.05) and the bundled Omron eCobra 600 (0.387, 0.325, 0.275, 0, its file
    read here). From the rows: the tool is at (a1 c1 + a2 c12, a1 s1 + a2 s12, d1 - d3 - d4) and turned by
    Rz(q1 + q2 - q4) Rx(180 deg) (Rx(180 deg) Rz(q4) = Rz(-q4) Rx(180 deg)). So d3 = d1 - d4 - z,
    q2 = ±acos((x² + y² - a1² - a2²) / (2 a1 a2)), q1 = atan2(y, x) - atan2(a2 sin q2, a1 + a2 cos q2) and
    q4 = q1 + q2 - ψ."""
    if name == "cobra600":
        arm, (d1, a1, a2, d4) = armkit.load("cobra600"), (0.387, 0.325, 0.275, 0.0)
    else:
        d1, a1, a2, d4 = 0.4, 0.35, 0.3, 0.05
        arm = Robot([_joint(R, d=d1, a=a1), _joint(R, a=a2, alpha=math.pi), _joint(P), _joint(R, d=d4)],
                    name="scara")
    assert classify(arm).name == "RRPR-scara" and closed_form(arm).family == "geometric-scara"
    slides = np.array([False, False, True, False])
    g = np.random.default_rng(5)
    for _ in range(10):
        r, th, z, psi = g.uniform(0.1, 0.55), g.uniform(-3, 3), g.uniform(-0.2, 0.3), g.uniform(-3, 3)
        x, y = r * math.cos(th), r * math.sin(th)
        T = np.eye(4)
        T[:3, :3] = Rotation.from_euler("ZX", [psi, math.pi]).as_matrix()     # Rz(psi) Rx(180 deg)
        T[:3, 3] = (x, y, z)
        res = armkit.ik_all(arm, T, enforce_limits=False)
        found = res.q[np.asarray(res.success)]
        assert len(found) == 2
        for sign in (1, -1):
            q2 = sign * math.acos((x * x + y * y - a1 * a1 - a2 * a2) / (2 * a1 * a2))
            q1 = math.atan2(y, x) - math.atan2(a2 * math.sin(q2), a1 + a2 * math.cos(q2))
            assert _has(found, np.array([q1, q2, d1 - d4 - z, q1 + q2 - psi]), slides, 1e-9)


def test_a_scara_cannot_tilt_its_tool_and_says_so():
    arm = Robot([_joint(R, d=0.4, a=0.35), _joint(R, a=0.3, alpha=math.pi), _joint(P), _joint(R, d=0.05)],
                name="scara")
    T = armkit.fk(arm, np.array([0.3, 0.8, 0.1, -0.5]))
    T[:3, :3] = T[:3, :3] @ Rotation.from_rotvec([0.2, 0.0, 0.0]).as_matrix()     # tilted by 0.2 rad
    res = armkit.ik_all(arm, T, enforce_limits=False)
    assert not np.asarray(res.success).any() and set(res.reason) == {"unreachable"}
    assert np.all(np.asarray(res.rotation_error) >= 0.2 - 1e-9)


@pytest.mark.parametrize("order", ["PRRR", "RPRR", "RRRP"])
def test_scara_in_any_order_every_branch_reaches_the_pose(order):
    g = np.random.default_rng(len(order) + ord(order[1]))
    for t in range(10):
        rows = g.uniform(-0.5, 0.5, (4, 4))
        rows[:, 2] = g.choice([-1.0, 1.0], 4) * g.uniform(0.05, 0.5, 4)      # links, none of about 0 length
        rows[:, 3] = g.choice([0.0, math.pi], 4)
        tool = np.eye(4)
        tool[:3, 3] = g.uniform(-0.2, 0.2, 3)
        arm = Robot([_joint(R if k == "R" else P, *row) for k, row in zip(order, rows)], tool=tool, name="scara")
        assert classify(arm).name == f"{order}-scara" and closed_form(arm).family == "geometric-scara"
        q = arm.random_q(rng=t)
        T = armkit.fk(arm, q)
        res = armkit.ik_all(arm, T, enforce_limits=False)
        ok = np.asarray(res.success)
        assert ok.any() and np.abs(armkit.fk(arm, res.q[ok]) - T).max() <= 1e-9
        assert _has(res.q[ok], q, np.asarray(arm.chain.prismatic), 1e-6)


@pytest.mark.parametrize("order", ["RRPR", "PRRR", "RPRR", "RRRP"])
def test_scara_batch_is_the_same_as_target_by_target(order):
    """From geometric.MANY targets a SCARA's branches come from its whole-batch form (_candidates_many); they are
    each target's own (its one-target form, _one_by_one): the same unreachable marks and found counts, angles and
    slides to 1e-12, on poses it reaches, poses beyond its reach and poses tilted off its axes."""
    from armkit.ik.analytic.geometric import MANY, _assemble

    if order == "RRPR":
        arm = armkit.load("cobra600")
    else:                                   # a random SCARA of this order, as in the test above
        g = np.random.default_rng(ord(order[0]) + 7 * ord(order[2]))
        rows = g.uniform(-0.5, 0.5, (4, 4))
        rows[:, 2] = g.choice([-1.0, 1.0], 4) * g.uniform(0.05, 0.5, 4)
        rows[:, 3] = g.choice([0.0, math.pi], 4)
        arm = Robot([_joint(R if k == "R" else P, *row) for k, row in zip(order, rows)], name="scara")
    solver = closed_form(arm)
    assert solver.family == "geometric-scara"
    T = armkit.fk(arm, arm.random_q(300, rng=5))
    T[:60, :3, 3] *= 4.0                                                     # beyond the reach
    T[60:100, :3, :3] = T[60:100, :3, :3] @ Rotation.from_rotvec([0.2, 0.0, 0.0]).as_matrix()   # tilted
    q0 = np.zeros((len(T), arm.n))
    one = solver._one_by_one(T, q0, None)
    many = _assemble(*solver._candidates_many(T), solver.m, arm.n, q0)
    assert np.array_equal(one[1], many[1]) and np.array_equal(one[2], many[2])
    assert np.abs(one[0] - many[0]).max() <= 1e-12
    assert len(T) >= MANY and 0 < one[2].sum() < 2 * len(T)                   # both kinds of target are here
    # and through the public call: a batch equals its targets one at a time
    batch = armkit.ik_all(arm, T[95:95 + 2 * MANY])
    for i in range(2 * MANY):
        single = armkit.ik_all(arm, T[95 + i])
        assert list(batch.success[i]) == list(single.success) and list(batch.reason[i]) == list(single.reason)
        assert np.abs(batch.q[i] - single.q).max() <= 1e-9


def test_a_scara_batch_takes_the_batch_form(monkeypatch):
    """armkit.ik_all of MANY or more cobra600 poses answers from the whole-batch form: with the target-by-target
    form made to fail, the batch still solves (and a single pose, which takes that form, fails)."""
    from armkit.ik.analytic.geometric import MANY
    from armkit.ik.analytic.geometric_prismatic import GeometricScara

    arm = armkit.load("cobra600")
    T = armkit.fk(arm, arm.random_q(MANY, rng=3))

    def refuse(*args, **kwargs):
        raise RuntimeError("target by target")

    monkeypatch.setattr(GeometricScara, "_candidates_of", refuse)
    res = armkit.ik_all(arm, T)
    ok = np.asarray(res.success)                     # (MANY, 2): both branches of each pose
    assert ok.any(axis=-1).all()
    reached = armkit.fk(arm, res.q[ok])
    wanted = np.broadcast_to(T[:, None], ok.shape + (4, 4))[ok]
    assert np.abs(reached - wanted).max() <= 1e-9
    with pytest.raises(RuntimeError, match="target by target"):
        armkit.ik_all(arm, T[0])


def test_a_polar_arm_takes_planar_targets_by_hand():
    """A turn about z and a reach across it move the tool in the world xy plane, so (x, y) targets apply (as for a
    planar 2R arm): standard DH (q1, 0, 0, 90 deg), (0, d2, 0, 0) put the tool at (d2 sin q1, -d2 cos q1, 0), so
    d2 = ±√(x² + y²) and q1 = atan2(x / d2, -y / d2)."""
    arm = Robot([Joint(R, alpha=HALF, lower=-math.pi, upper=math.pi), Joint(P, lower=0.1, upper=1.0)], name="polar")
    for x, y in [(0.3, 0.4), (-0.5, 0.2), (0.0, -0.9)]:
        res = armkit.ik_all(arm, np.array([x, y]))
        d = math.hypot(x, y)
        assert list(np.asarray(res.success)).count(True) == 1            # the negative reach is outside its stroke
        q = res.q[np.asarray(res.success)][0]
        assert _same(q, np.array([math.atan2(x / d, -y / d), d]), np.array([False, True]), 1e-12)
    with pytest.raises(armkit.ArmkitError, match="2-D targets"):     # a slide along z (a lift): not planar
        armkit.ik_all(Robot([Joint(R, lower=-3, upper=3), Joint(P, alpha=0.3, lower=0, upper=1)], name="tilted"),
                      np.array([0.3, 0.4]))


# ---------------------------------------------------------------- seven joints: a 6R arm on a rail
def test_a_ur5_on_a_rail_is_swept_along_the_rail():
    """A slide along the world x axis under the UR5 (standard DH rail row (0, d, 0, -90 deg) then the UR5's rows):
    holding the rail leaves the UR5's class at every position, so ik_all without fixed= sweeps the rail over its
    stroke (32 evenly spaced values, np.linspace of the limits) and every branch reaches the pose; holding it at the
    value the pose came from gives that configuration among its branches."""
    ur = armkit.load("ur5")
    arm = Robot([Joint(P, alpha=-HALF, lower=-1.0, upper=1.0, name="rail"), *ur.joints], name="ur5_on_rail")
    cls = classify(arm)
    assert cls.name == "PRRRRRR-lock-1-three-parallel-two-intersecting" and cls.solver == "sweep joint 1"
    q = np.r_[0.3, ur.random_q(rng=1)]
    T = armkit.fk(arm, q)
    res = armkit.ik_all(arm, T)
    ok = np.asarray(res.success)
    assert ok.sum() >= 16 and np.abs(armkit.fk(arm, res.q[ok]) - T).max() <= 1e-9
    rails = np.unique(np.round(res.q[:, 0], 12))
    assert set(rails) <= set(np.round(np.linspace(-1.0, 1.0, 32), 12))
    held = armkit.ik_all(arm, T, fixed={"rail": 0.3})
    assert _has(held.q[np.asarray(held.success)], q, np.asarray(arm.chain.prismatic), 1e-9)


@pytest.mark.filterwarnings("error::RuntimeWarning")   # Newton's step was f / df before the 0.5 rad test: overflow
@settings(max_examples=200, deadline=None)
@given(st.lists(st.floats(-3, 3), min_size=4, max_size=4))
@example([0.0, 0.0, 8.253527970530516e-162, 8.253527970530516e-162])   # tiny: squares below the smallest normal
@example([0.0, 0.0, 1.0, 1.00000001])   # sin θ + 1.00000001: 1e-8 above 0 at best, no root (a 3,000-example run)
def test_an_isotropic_trig_quadratic_has_the_roots_of_its_quartic(c):
    """k0 + kc cos + ks sin + kq (cos² + sin²): the linear shortcut of _trig_roots (a SCARA's slide along its turns)
    finds the roots the quartic in tan(θ/2) finds, each a zero of the trigonometric polynomial."""
    from armkit.ik.analytic import geometric_prismatic as gp

    k = np.array([c[0], c[1], c[2], c[3], 0.0, c[3]])
    fast, _ = gp._trig_roots(k)
    saved = gp.ISOTROPIC
    gp.ISOTROPIC = -1.0
    try:
        slow, _ = gp._trig_roots(k)
    finally:
        gp.ISOTROPIC = saved
    size = np.abs(k).max()
    for t in fast:
        assert abs(gp._trig_value(k, t)[0]) <= 1e-9 * max(size, 1e-300)
    margin = math.hypot(c[1], c[2]) - abs(c[0] + c[3])     # two roots, one (tangent) or none
    if abs(margin) > 1e-6:
        assert len(fast) == len(slow) == (2 if margin > 0 else 0), (fast, slow)
        for t in slow:
            assert min(abs(math.remainder(t - u, 2 * math.pi)) for u in fast) < 1e-7
