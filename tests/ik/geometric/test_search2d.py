"""The 2-D search for the general 6R (armkit.ik.geometric.search2d): the true q is found, every branch passes FK,
and nothing is missed against a dense least-squares search (scipy's least_squares from 500 random starts)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit.ik.geometric import search2d as S
from armkit.ik.geometric.poe import POE
from test_dense_check import robot_of   # the chain read back as a Robot (its own test module's reading)

TOL = 1e-9


def wrapped(a):
    return (np.asarray(a) + np.pi) % (2 * np.pi) - np.pi


def general_arm(g) -> POE:
    """A random 6R chain: random axis directions and points (no two axes meet or are parallel, almost surely)."""
    H = g.normal(size=(6, 3))
    H /= np.linalg.norm(H, axis=1, keepdims=True)
    P = g.normal(size=(7, 3)) * 0.4
    A = np.linalg.qr(g.normal(size=(3, 3)))[0]
    if np.linalg.det(A) < 0:
        A[:, 0] *= -1
    return POE(H, P, A, np.zeros(6, dtype=bool))


def fk_ok(form: POE, q, R, p) -> bool:
    Rq, pq = form.fk(np.asarray(q, dtype=float))
    scale = float(np.linalg.norm(form.P, axis=1).sum())
    return bool(np.linalg.norm(pq - p) <= TOL * scale and np.linalg.norm(Rq - R) / math.sqrt(2) <= TOL)


def contains(Q, q, tol=1e-6) -> bool:
    return any(np.abs(wrapped(s - q)).max() < tol for s in Q)


def twin_within_resolution(Q, q, samples=S.N) -> bool:
    """The resolution the search states: a solution may be missed only when another found one lies within one
    grid step of it in (q1, q2) on the same branch (two zeros of e in one cell)."""
    h = 2 * np.pi / samples
    return any(np.abs(wrapped(s[:2] - q[:2])).max() < 1.5 * h and np.abs(wrapped(s[2:5] - q[2:5])).max() < S.MATCH
               for s in Q)


# -------------------------------------------------------------------------- the pieces
@settings(max_examples=200, deadline=None, derandomize=True)
@given(st.integers(0, 2**32 - 1))
def test_shared_trig2_meets_its_equations(seed):
    """The closed form both searches use for ``A (cos θ1, sin θ1) + B (cos θ2, sin θ2) = e``
    (:func:`armkit.ik.geometric._kernels._trig2_rows`), on a system built from a known pair (the definition):
    that pair is among the answers, and every answer meets both equations."""
    from armkit.ik.geometric import _kernels as K

    g = np.random.default_rng(seed)
    A, B = g.normal(size=(2, 2)), g.normal(size=(2, 2))
    t1, t2 = g.uniform(-np.pi, np.pi, 2)
    e = A @ [math.cos(t1), math.sin(t1)] + B @ [math.cos(t2), math.sin(t2)]
    T1, T2 = np.zeros(4), np.zeros(4)
    n, _ = K._trig2_rows(A[0, 0], A[0, 1], B[0, 0], B[0, 1], e[0], A[1, 0], A[1, 1], B[1, 0], B[1, 1], e[1], T1, T2,
                         None)
    assert 1 <= n <= 4
    for k in range(n):
        r = A @ [math.cos(T1[k]), math.sin(T1[k])] + B @ [math.cos(T2[k]), math.sin(T2[k])] - e
        assert np.abs(r).max() < 1e-8 * (np.abs(A).sum() + np.abs(B).sum())
    assert (np.maximum(np.abs(wrapped(T1[:n] - t1)), np.abs(wrapped(T2[:n] - t2))) < 1e-6).any()


def test_q345_meets_its_equation():
    """``rot(h3, q3) (p34 + rot(h4, q4) (p45 + rot(h5, q5) p56)) = u``: the true triple among the answers, and every
    answer meets the equation."""
    from armkit.ik.geometric.subproblems import rotm

    g = np.random.default_rng(11)
    for _ in range(200):
        form = general_arm(g)
        H, P = np.asarray(form.H), np.asarray(form.P)
        t = g.uniform(-np.pi, np.pi, 3)

        def lhs(a, b, c):
            return rotm(H[2], a) @ (P[3] + rotm(H[3], b) @ (P[4] + rotm(H[4], c) @ P[5]))
        u = lhs(*t)
        out = np.zeros((4, 3))
        n = S._q345(H, P, u, out, np.zeros((5, 5)))
        assert 1 <= n <= 4
        for k in range(n):
            assert np.linalg.norm(lhs(*out[k]) - u) < 1e-8
        assert contains(out[:n], t, 1e-6)


# -------------------------------------------------------------------------- the search
@pytest.mark.parametrize("seed", range(5))
def test_true_q_found_and_every_branch_verified(seed):
    """24 targets from random q on each of 5 random arms (120 targets): the true q is a branch (1e-6 after
    wrapping), every branch passes FK at 1e-9, no duplicates, at most 16."""
    g = np.random.default_rng(100 + seed)
    form = general_arm(g)
    twins = 0
    for _ in range(24):
        q = g.uniform(-np.pi, np.pi, 6)
        R, p = form.fk(q)
        sol = S.gen_six_dof(form, R, p, jit=True)
        assert not sol.ls.any()
        assert 1 <= len(sol.q) <= 16
        if not contains(sol.q, q):        # only two zeros within one cell may merge (the stated resolution)
            twins += 1
            assert twin_within_resolution(sol.q, q), (seed, q)
            assert contains(S.gen_six_dof(form, R, p, samples=4 * S.N, jit=True).q, q)
        for s in sol.q:
            assert fk_ok(form, s, R, p)
        for i in range(len(sol.q)):
            for j in range(i):
                assert np.abs(wrapped(sol.q[i] - sol.q[j])).max() > 1e-7
    assert twins <= 2


def _cross(a, b):
    """Row-wise cross product of (..., 3) arrays (broadcasting; cheaper than ``np.cross`` on tiny arrays)."""
    return a[..., [1, 2, 0]] * b[..., [2, 0, 1]] - a[..., [2, 0, 1]] * b[..., [1, 2, 0]]


class PoseResidual:
    """The pose residual ``[(p(q) - p) / scale, vec(R(q) - R)]`` (12,) of a revolute POE chain and its analytic
    Jacobian (12, n), derived here from the chain (independent of armkit's kernels).

    In the space frame joint k turns about the axis ``w_k = R_{k-1} h_k`` through the point ``o_k`` (the running
    position before joint k), so ``d p / d q_k = w_k x (p - o_k)`` and ``d R / d q_k = [w_k]x R``. Each rotation is
    Rodrigues' formula ``I + sin(q) K + (1 - cos(q)) K^2`` with ``K = [h_k]x``. The last q's chain is kept, because
    the solver asks for the residual and the Jacobian at the same point.
    """

    def __init__(self, form: POE, R, p):
        self.H, self.P, self.R_nT = np.asarray(form.H), np.asarray(form.P), np.asarray(form.R_nT)
        self.R, self.p = np.asarray(R), np.asarray(p)
        self.scale = float(np.linalg.norm(self.P, axis=1).sum())
        n = self.H.shape[0]
        K = np.zeros((n, 3, 3))
        K[:, 0, 1], K[:, 0, 2], K[:, 1, 2] = -self.H[:, 2], self.H[:, 1], -self.H[:, 0]
        self.K = K - K.transpose(0, 2, 1)
        self.K2 = self.K @ self.K
        self._key: bytes | None = None
        self._chain: tuple = ()

    def chain(self, q):
        """Tool rotation (3, 3), tool position (3,), space axes ``w`` (n, 3) and axis points ``o`` (n, 3) at q."""
        q = np.asarray(q, dtype=float)
        key = q.tobytes()
        if key != self._key:
            n = self.H.shape[0]
            rots = np.eye(3) + np.sin(q)[:, None, None] * self.K + (1.0 - np.cos(q))[:, None, None] * self.K2
            Rk, pk = np.eye(3), self.P[0].copy()
            W, O = np.empty((n, 3)), np.empty((n, 3))
            for k in range(n):
                W[k], O[k] = Rk @ self.H[k], pk
                Rk = Rk @ rots[k]
                pk = pk + Rk @ self.P[k + 1]
            self._key, self._chain = key, (Rk @ self.R_nT, pk, W, O)
        return self._chain

    def __call__(self, q):
        Rq, pq, _, _ = self.chain(q)
        return np.concatenate([(pq - self.p) / self.scale, (Rq - self.R).ravel()])

    def jac(self, q):
        Rq, pq, W, O = self.chain(q)
        n = W.shape[0]
        J = np.empty((12, n))
        J[:3] = _cross(W, pq - O).T / self.scale
        dR = _cross(W[:, None, :], Rq.T[None, :, :])       # [k, j] = w_k x (column j of R)
        J[3:] = dR.transpose(0, 2, 1).reshape(n, 9).T
        return J


def dense_least_squares(form: POE, R, p, starts: int, seed: int) -> list[np.ndarray]:
    """Distinct solutions (1e-6 rad) that scipy's least_squares (Levenberg-Marquardt, analytic Jacobian) reaches
    from ``starts`` random starts."""
    from scipy.optimize import least_squares

    resid = PoseResidual(form, R, p)
    g = np.random.default_rng(seed)
    out: list[np.ndarray] = []
    for x0 in g.uniform(-np.pi, np.pi, (starts, 6)):
        r = least_squares(resid, x0, jac=resid.jac, method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=400)
        q = wrapped(r.x)
        if fk_ok(form, q, R, p) and not contains(out, q):
            out.append(q)
    return out


@settings(max_examples=50, deadline=None, derandomize=True)
@given(st.integers(0, 2**32 - 1))
def test_pose_residual_and_its_jacobian(seed):
    """The dense check's residual is the pose error by :meth:`POE.fk` (the definition), and its analytic Jacobian
    matches central finite differences (step 1e-6, error O(h^2))."""
    g = np.random.default_rng(seed)
    form = general_arm(g)
    R, p = form.fk(g.uniform(-np.pi, np.pi, 6))
    resid = PoseResidual(form, R, p)
    q = g.uniform(-np.pi, np.pi, 6)
    Rq, pq = form.fk(q)
    np.testing.assert_allclose(resid(q), np.concatenate([(pq - p) / resid.scale, (Rq - R).ravel()]), atol=1e-13)
    h = 1e-6
    fd = np.stack([(resid(q + h * e) - resid(q - h * e)) / (2 * h) for e in np.eye(6)], axis=1)
    np.testing.assert_allclose(resid.jac(q), fd, atol=1e-8)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_nothing_missed_against_dense_least_squares(seed):
    """At the stated resolution (:data:`search2d.N`): every solution that 500 least-squares runs find is a branch."""
    g = np.random.default_rng(200 + seed)
    form = general_arm(g)
    q = g.uniform(-np.pi, np.pi, 6)
    R, p = form.fk(q)
    sol = S.gen_six_dof(form, R, p, jit=True)
    reference = dense_least_squares(form, R, p, 500, seed)
    assert len(reference) >= 2
    missing = [u for u in reference if not contains(sol.q, u) and not twin_within_resolution(sol.q, u)]
    assert missing == []


# A random arm of benchmarks/bench_coverage.py's dense check (2026-12-05), read back from its URDF file: the solution
# beside the true q lay 0.44 rad away along the Jacobian's most singular direction, beyond the Newton steps from the
# solution found (0.2 rad at most), and the search returned 1 solution
BENCH_H = [[0.367386888091681, 0.7130329642372489, -0.597169043378299],
           [0.9490204584161827, 0.14946888687396137, 0.2775233708432456],
           [0.6103803585721679, 0.7726964047771049, 0.1742873601666182],
           [-0.7226948755779949, 0.6578665822988587, 0.2119520622870317],
           [-0.6731061839817909, -0.5797710707797691, -0.459122609519888],
           [0.7073819481176942, 0.5711838770487093, 0.4163649337742324]]
BENCH_P = [[-0.3314834705310523, -0.21925795403788356, -1.1353162372006582],
           [0.9941074481091663, -0.0009873208545669032, 1.623572106228184],
           [-1.1927846705670824, -0.18011838918525344, -0.7694765140185263],
           [0.5967242280531888, 0.003216165729114484, 0.34241099843342404],
           [-0.24722655851807981, 0.0750566619925781, 0.0213374886574981],
           [0.03865116978386601, 0.04964743018070128, 0.025930436138302204],
           [-0.10097204912280577, 0.005226849283752777, -0.49915055678388676]]
BENCH_RNT = [[-0.5135196443220377, -0.6939382963266616, 0.5047248911898615],
             [0.13655516047463567, 0.5146184272868914, 0.8464753761595871],
             [-0.8471424101313281, 0.5036045226048089, -0.1695058163275484]]
BENCH_Q = [1.3927332713543805, 2.9669096179692733, -0.8951315715975254, 0.49633609273226, 0.6498060621124933,
           0.7122384017135897]


def _draw(g, count):
    """The ``count``-th arm and target of the random draws in :func:`test_real_solution_counts_are_even` (the
    arm as in the doctest of :func:`search2d.gen_six_dof`: axes and points only, the tool frame the identity)."""
    for _ in range(count + 1):
        H = g.normal(size=(6, 3))
        H /= np.linalg.norm(H, axis=1, keepdims=True)
        P = g.normal(size=(7, 3)) * 0.4
        q = g.uniform(-np.pi, np.pi, 6)
    return POE(H, P, np.eye(3), np.zeros(6, dtype=bool)), q


@pytest.mark.parametrize("case", ["bench arm", "draw 2499"])
def test_missed_pairs_are_found(case):
    """Two targets where the search missed solutions that least-squares runs from random starts find: the bench arm
    above (1 solution of 2: its twin lay beyond the Newton steps from it) and the 2,500th draw of seed 1 (3 of 6: a
    pair and a twin, all within a grid cell of others; a grid twice as fine finds them). With an odd count the
    search now steps up to 1 rad from each solution and then searches a finer grid: nothing is missed, with no
    allowance for the stated resolution."""
    if case == "bench arm":
        form = POE(np.array(BENCH_H), np.array(BENCH_P), np.array(BENCH_RNT), np.zeros(6, dtype=bool))
        q = np.array(BENCH_Q)
    else:
        form, q = _draw(np.random.default_rng(1), 2499)
    R, p = form.fk(q)
    sol = S.gen_six_dof(form, R, p, jit=True)
    reference = dense_least_squares(form, R, p, 200, 7)
    assert len(reference) >= 2
    assert [u for u in reference if not contains(sol.q, u)] == []
    assert len(sol.q) % 2 == 0
    for s in sol.q:
        assert fk_ok(form, s, R, p)


def test_real_solution_counts_are_even():
    """A 6R's real solutions come in pairs (the others are complex conjugates), so on random targets (no
    singularity, almost surely) every count is even: an odd count is a missed solution. 400 targets, each on its
    own random arm (before the finer grid and the longer Newton steps, 3 of these 400 had an odd count, and 10 of
    3,000 targets of another seed)."""
    g = np.random.default_rng(2)
    odd = []
    for i in range(400):
        form, q = _draw(g, 0)
        R, p = form.fk(q)
        sol = S.gen_six_dof(form, R, p, jit=True)
        if len(sol.q) % 2:
            odd.append(i)
    assert odd == []


def test_plain_python_agrees_with_the_compiled_search():
    """The plain functions (no Numba) and the compiled ones give the same branches (a small grid, to be quick)."""
    g = np.random.default_rng(5)
    form = general_arm(g)
    q = g.uniform(-np.pi, np.pi, 6)
    R, p = form.fk(q)
    a = S.gen_six_dof(form, R, p, samples=20, jit=True)
    b = S.gen_six_dof(form, R, p, samples=20, jit=False)
    assert len(a.q) == len(b.q)
    for s in a.q:
        assert contains(b.q, s, 1e-9)


def test_unreachable_target_gives_no_branch():
    g = np.random.default_rng(9)
    form = general_arm(g)
    R = np.eye(3)
    p = np.array([100.0, 0.0, 0.0])
    sol = S.gen_six_dof(form, R, p, jit=True)
    assert len(sol.q) == 0 or sol.ls.all()


def test_rejects_what_it_cannot_solve():
    g = np.random.default_rng(9)
    form = general_arm(g)
    bad = POE(form.H, form.P, form.R_nT, np.array([False, False, True, False, False, False]))
    with pytest.raises(ValueError):
        S.gen_six_dof(bad, np.eye(3), np.zeros(3))
    assert "grid" in S.resolution()


# ------------------------------------------------------------------------ through armkit.ik_all


def test_ik_all_answers_a_general_6r():
    """``armkit.ik_all`` on a general 6R: the class says "2-D search", every successful branch passes FK of the robot,
    and they are the search's branches."""
    from armkit.ik.geometric.classify import classify

    g = np.random.default_rng(21)
    form = general_arm(g)
    robot = robot_of(form)
    assert classify(robot).solver == "2-D search"
    q = g.uniform(-np.pi, np.pi, 6)
    T = armkit.fk(robot, q)
    res = armkit.ik_all(robot, T, enforce_limits=False)
    ok = np.asarray(res.success)
    assert ok.sum() >= 2
    good = np.asarray(res.q)[ok]
    assert np.abs(armkit.fk(robot, good) - T).max() < 1e-9
    assert contains(good, q)
    sol = S.gen_six_dof(form, T[:3, :3], T[:3, 3], jit=True)
    assert len(sol.q) == ok.sum()


# ------------------------------------------------------------------ the grid point's shortcuts
@settings(max_examples=300, deadline=None, derandomize=True)
@given(st.integers(0, 2**32 - 1), st.integers(-6, 6), st.integers(-6, 6))
def test_early_rejection_never_skips_a_solvable_system(seed, k0, k1):
    """:func:`search2d._reject` on a system built from a known pair (θ1, θ2) (so it has a solution by construction),
    rows scaled by 10^k0 and 10^k1: never rejected. And on a system whose right side is out of reach along the first
    row (``|e0| > ‖a0‖ + ‖b0‖``, no solution by the triangle inequality) it is rejected."""
    g = np.random.default_rng(seed)
    A, B = g.normal(size=(2, 2)), g.normal(size=(2, 2))
    t1, t2 = g.uniform(-np.pi, np.pi, 2)
    e = A @ [math.cos(t1), math.sin(t1)] + B @ [math.cos(t2), math.sin(t2)]
    sc = np.array([10.0 ** k0, 10.0 ** k1])
    A, B, e = A * sc[:, None], B * sc[:, None], e * sc
    assert not S._reject(A[0, 0], A[0, 1], B[0, 0], B[0, 1], e[0], A[1, 0], A[1, 1], B[1, 0], B[1, 1], e[1])
    far = 1.01 * (np.linalg.norm(A[0]) + np.linalg.norm(B[0])) * (1 if g.random() < 0.5 else -1)
    assert S._reject(A[0, 0], A[0, 1], B[0, 0], B[0, 1], far, A[1, 0], A[1, 1], B[1, 0], B[1, 1], e[1])


@settings(max_examples=200, deadline=None, derandomize=True)
@given(st.integers(0, 2**32 - 1))
def test_early_rejection_only_where_there_is_no_solution(seed):
    """Wherever :func:`search2d._reject` skips a system, the residual ``A c(θ1) + B c(θ2) − e`` stays away from 0 on
    a dense grid of (θ1, θ2) (400 x 400), and the closed form finds nothing either."""
    from armkit.ik.geometric import _kernels as K

    g = np.random.default_rng(seed)
    A, B = g.normal(size=(2, 2)), g.normal(size=(2, 2))
    e = g.normal(size=2) * g.uniform(0.5, 3.0)
    if not S._reject(A[0, 0], A[0, 1], B[0, 0], B[0, 1], e[0], A[1, 0], A[1, 1], B[1, 0], B[1, 1], e[1]):
        return
    th = np.linspace(-np.pi, np.pi, 400, endpoint=False)
    c = np.stack([np.cos(th), np.sin(th)])
    r = (A @ c)[:, :, None] + (B @ c)[:, None, :] - e[:, None, None]
    assert np.hypot(r[0], r[1]).min() > 1e-3
    T1, T2 = np.zeros(4), np.zeros(4)
    n, _ = K._trig2_rows(A[0, 0], A[0, 1], B[0, 0], B[0, 1], e[0], A[1, 0], A[1, 1], B[1, 0], B[1, 1], e[1], T1, T2,
                         None)
    assert n == 0


def test_branches_give_the_wrist_direction():
    """:func:`search2d._branches` beside each (q3, q4, q5) gives ``rot(h3, q3) rot(h4, q4) rot(h5, q5) h6`` (checked
    with the rotation matrices), and the same triples as :func:`search2d._q345`."""
    from armkit.ik.geometric.subproblems import rotm

    g = np.random.default_rng(12)
    for _ in range(100):
        form = general_arm(g)
        H, P = np.asarray(form.H), np.asarray(form.P)
        t = g.uniform(-np.pi, np.pi, 3)
        u = rotm(H[2], t[0]) @ (P[3] + rotm(H[3], t[1]) @ (P[4] + rotm(H[4], t[2]) @ P[5]))
        full = np.zeros((4, 6))
        n = S._branches(H, P, S._arm(H, P), u, np.zeros(4), np.zeros(4), full)
        out = np.zeros((4, 3))
        assert S._q345(H, P, u, out, np.zeros((5, 5))) == n
        np.testing.assert_allclose(full[:n, :3], out[:n], atol=1e-12)
        for k in range(n):
            d = rotm(H[2], full[k, 0]) @ rotm(H[3], full[k, 1]) @ rotm(H[4], full[k, 2]) @ H[5]
            assert np.abs(full[k, 3:] - d).max() < 1e-12
        assert contains(full[:n, :3], t, 1e-6)


@pytest.mark.parametrize("samples", [3, S.MAX_GRID + 1])
def test_a_grid_too_coarse_or_too_fine_is_refused_before_allocating(samples):
    """``samples`` outside 4..MAX_GRID is refused with the bound and the memory it stands for (an unbounded grid
    would allocate 264 bytes a point, and its finer passes 4x and 16x that)."""
    form = POE(np.eye(3)[[0, 1, 2, 0, 1, 2]], np.ones((7, 3)), np.eye(3), np.zeros(6, dtype=bool))
    with pytest.raises(ValueError, match=f"from 4 to {S.MAX_GRID}"):
        S.gen_six_dof(form, np.eye(3), np.zeros(3), samples=samples)
