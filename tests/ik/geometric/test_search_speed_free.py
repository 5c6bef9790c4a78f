"""The 1-D searches (armkit.ik.geometric.search) on random arms of every 1-D class: nothing missed.

For each class, 200 targets (40 random arms x 5 random configurations): every solution the solver
returns passes FK at 1e-9 (the test's own check, POE.fk), the generating configuration is among them,
and every root of a dense scan written here is among them: 20,000 samples of the searched joint, the
branches followed from sample to sample by nearest neighbour (no refinement, no branch-end logic), a
root wherever a followed branch changes sign (its position by linear interpolation). The dense scan
evaluates the branches with the engine's own ``_scan``; that evaluation is checked separately
against the reference subproblems (eigenvalue quartic, :mod:`armkit.ik.geometric.subproblems`).
No timing here (benchmarks/bench_geometric.py --searches).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from armkit.ik.geometric import _kernels as K
from armkit.ik.geometric import search as S
from armkit.ik.geometric import solvers as G
from armkit.ik.geometric import subproblems as sp
from armkit.ik.geometric.poe import POE

from test_dense_check import two_parallel_arm   # same folder, on pytest's path
from test_solvers import random_arm, random_q

DENSE = 20000
TWO_PI = 2 * math.pi


def _wrap(a):
    return (np.asarray(a) + np.pi) % TWO_PI - np.pi


def spherical_middle_arm(g: np.random.Generator) -> POE:
    """A random 6R chain whose axes 2, 3, 4 meet in one point (points slid randomly along their axes)."""
    H = g.normal(size=(6, 3))
    H /= np.linalg.norm(H, axis=1, keepdims=True)
    pts = g.normal(size=(6, 3)) * 0.5
    c = g.normal(size=3) * 0.5
    for k in (1, 2, 3):
        pts[k] = c + g.uniform(-0.5, 0.5) * H[k]
    tool = pts[5] + g.normal(size=3) * 0.3
    Q, Rr = np.linalg.qr(g.normal(size=(3, 3)))
    Q = Q * np.sign(np.diag(Rr))
    Q = Q if np.linalg.det(Q) > 0 else -Q
    return POE(H, np.vstack([pts[0], np.diff(pts, axis=0), tool - pts[5]]), Q, np.zeros(6, dtype=bool))


# kind: (solver name, random arm)
KINDS = {
    "TI": ("two_intersecting", lambda g: random_arm(g, "ti")),
    "TP": ("two_parallel", two_parallel_arm),
    "SW": ("spherical", lambda g: random_arm(g, "sw")),
    "SM": ("spherical_middle", spherical_middle_arm),
}


KNOWN: dict[str, tuple[int, int]] = {}
"""(targets whose generating q is lost, dense roots missing) of the 200, where not (0, 0): see the test. Empty since
the search looks at the seams of its finer steps (``search._seam``); before, TI lost one target (below)."""


def _target_c(kind: str, H, P, R06, p) -> np.ndarray:
    """The search's ``C (4, 3)`` for the ideal chain ``(H, P)`` and the target (as the solver cores set it)."""
    C = np.zeros((4, 3))
    if kind == "TI":
        C[0] = R06 @ H[5]
        C[1] = p - P[0] - R06 @ P[6]
    elif kind == "SW":
        C[0] = p - P[0] - R06 @ P[6]
    else:
        C[:3] = R06
        C[3] = p
    return C


def search_case(kind: str, seed: int):
    """A random arm of the class ``kind`` and a random target of it, as one search sees them: ``(H, P, C, g)``,
    the ideal chain, the search's ``C`` (:func:`_target_c`) and the generator, to draw joint values from."""
    name, make = KINDS[kind]
    g = np.random.default_rng(seed)
    form = make(g)
    prep = G._prepare(form, name)
    R, p = form.fk(random_q(g, form))
    return prep.Hi, prep.Pi, _target_c(kind, prep.Hi, prep.Pi, R @ form.R_nT.T, p), g


def _coords(kind: str, Q: np.ndarray, H) -> np.ndarray:
    """Each solution as ``(x, branch)``: the searched joint and the branch values of the class."""
    Q = np.atleast_2d(Q)
    out = np.zeros((len(Q), 4))
    if kind == "TI":
        out[:, 0], out[:, 1:] = Q[:, 0], Q[:, 1:4]
    elif kind == "TP":
        sgn = 1.0 if H[1] @ H[2] > 0 else -1.0
        out[:, 0], out[:, 1], out[:, 2], out[:, 3] = Q[:, 5], Q[:, 0], Q[:, 3], _wrap(Q[:, 1] + sgn * Q[:, 2])
    elif kind == "SW":
        out[:, 0], out[:, 1] = Q[:, 0], Q[:, 2]
    else:
        out[:, 0], out[:, 1] = Q[:, 5], Q[:, 0]
    return out


def _circle_distance(a, b):
    """``|_wrap(a - b)|`` for angles in [-pi, pi] (the scan's atan2 values), without the slow float modulo."""
    d = np.abs(a - b)
    return np.where(d > np.pi, TWO_PI - d, d)


def dense_roots(kind: str, H, P, C) -> np.ndarray:
    """Roots ``(x, branch)`` of the class's residual from DENSE samples of the searched joint: branches of
    neighbouring samples paired by nearest neighbour (mutual, within 0.05 rad), a root where a pair's
    residuals differ in sign, at the linear interpolation."""
    K = S.kernels()
    xs = np.linspace(-np.pi, np.pi, DENSE + 1)
    Sx = np.zeros((DENSE + 1, 4, S.WIDTH))
    E = np.zeros((DENSE + 1, 4))
    cnt = np.zeros(DENSE + 1, dtype=np.int64)
    K._scan(getattr(S, kind), H, P, C, xs, Sx, E, cnt)
    Sx = Sx[..., :3]                                        # the branches (then cosines and sines, S.WIDTH)
    assert np.abs(Sx).max() <= np.pi                        # what _circle_distance takes
    valid = np.arange(4)[None, :] < cnt[:, None]
    D = _circle_distance(Sx[:-1, :, None, 0], Sx[1:, None, :, 0])              # (n, 4, 4): the largest of the
    for c in (1, 2):                                                            # three coordinates' distances
        np.maximum(D, _circle_distance(Sx[:-1, :, None, c], Sx[1:, None, :, c]), out=D)
    D = np.where(valid[:-1, :, None] & valid[1:, None, :], D, np.inf)
    fwd = D.argmin(axis=2)                                  # (n, 4): each branch's nearest at the next sample
    back = D.argmin(axis=1)                                 # (n, 4): each next branch's nearest at this sample
    i, j = np.nonzero(valid[:-1])                           # every (sample, branch), at once
    k = fwd[i, j]
    paired = (D[i, j, k] < 0.05) & (back[i, k] == j)        # mutual nearest neighbours within 0.05 rad
    i, j, k = i[paired], j[paired], k[paired]
    fa, fb = E[i, j], E[i + 1, k]
    root = (fa == 0.0) | (fa * fb < 0.0)                    # the residual changes sign between the pair
    i, j, k, fa, fb = i[root], j[root], k[root], fa[root], fb[root]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(fa == 0.0, 0.0, fa / (fa - fb))        # linear interpolation
    x = xs[i] + t * (xs[i + 1] - xs[i])
    s = Sx[i, j] + t[:, None] * _wrap(Sx[i + 1, k] - Sx[i, j])
    return np.column_stack([x, s]).reshape(-1, 4)


def feasible(kind: str, H, P, R06, p, root) -> bool:
    """Whether a root of the residual is an IK solution: for the classes with three meeting axes (SW: the wrist
    4-5-6, SM: the middle 2-3-4), the rotation left for them must be one they reach (their SP2 exact);
    the other classes' remaining joints (SP1) always exist at a root."""
    x, s0 = root[0], root[1]
    if kind == "SW":
        p0W = p - P[0] - R06 @ P[6]
        v = sp.rot(H[0], -x, p0W) - P[1]
        w = P[2] + sp.rot(H[2], s0, P[3])
        q1 = sp.sp1(w, v, H[1])[0]
        Rr = (sp.rotm(H[0], x) @ sp.rotm(H[1], q1) @ sp.rotm(H[2], s0)).T @ R06       # R_36
        a, b, c = 3, 4, 5
    elif kind == "SM":
        R05 = R06 @ sp.rotm(H[5], -x)
        d = p - P[0] - R05 @ P[5] - R06 @ P[6] - sp.rot(H[0], s0, P[1])
        phi = sp.sp1(P[4], R05.T @ d, H[4])[0]
        Rr = sp.rotm(H[0], s0).T @ R05 @ sp.rotm(H[4], phi)                             # R_14
        a, b, c = 1, 2, 3
    else:
        return True
    return not sp.sp2(Rr @ H[c], H[c], -H[a], H[b])[3]


def _missing(found: np.ndarray, reference: np.ndarray) -> int:
    """Reference roots with no solution within 2e-3 rad of the searched joint and 0.05 rad of the branch."""
    miss = 0
    for r in reference:
        d = np.abs(_wrap(found - r)) if len(found) else np.full((1, 4), np.inf)
        if not ((d[:, 0] < 2e-3) & (d[:, 1:].max(axis=1) < 0.05)).any():
            miss += 1
    return miss


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_every_branch_verified_and_none_missed_against_a_dense_scan(kind):
    pytest.importorskip("numba")
    name, make = KINDS[kind]
    g = np.random.default_rng({"TI": 11, "TP": 12, "SW": 13, "SM": 14}[kind])
    missing = lost = 0
    counts = []
    for _ in range(40):
        form = make(g)
        prep = G._prepare(form, name)
        size = float(np.linalg.norm(form.P, axis=1).sum())
        for _ in range(5):
            q = random_q(g, form)
            R, p = form.fk(q)
            sol = G.SOLVERS[name](form, R, p)
            assert not sol.ls.any()
            for x in sol.q:                                   # nothing claimed without FK at 1e-9
                Rx, px = form.fk(x)
                assert np.linalg.norm(px - p) <= 1e-9 * size
                assert np.linalg.norm(Rx - R) <= 1e-9 * math.sqrt(2)
            lost += not (np.abs(_wrap(sol.q - q)).max(axis=1) < 1e-7).any()
            R06 = R @ form.R_nT.T
            ref = dense_roots(kind, prep.Hi, prep.Pi, _target_c(kind, prep.Hi, prep.Pi, R06, p))
            ref = np.array([r for r in ref if feasible(kind, prep.Hi, prep.Pi, R06, p, r)]).reshape(-1, 4)
            missing += _missing(_coords(kind, sol.q, prep.Hi), ref)
            counts.append(len(sol.q))
    # the miss known until search._seam (TI, seed 11, arm 31, target 3): a near-double root (residual peak 2e-6,
    # its two roots 5e-4 rad apart) 4e-3 rad from a branch end, beside a step sampled finer: 1 target lost, 2 roots
    assert (lost, missing) == KNOWN.get(kind, (0, 0)), (lost, missing)
    assert max(counts) <= 16 and np.mean(counts) > 2


@settings(max_examples=300, deadline=None, derandomize=True)
@given(c=st.lists(st.floats(-10, 10), min_size=5, max_size=5))
def test_quartic_roots_against_numpy(c):
    """The closed-form quartic: the same 4 roots as numpy's companion-matrix eigenvalues (leading coefficient
    the largest, as the search makes it)."""
    c = np.array(c)
    big = np.abs(c).max()
    if big < 1e-3:
        return
    c[0] = big * (1.0 if c[0] >= 0 else -1.0)
    re, im = np.empty(4), np.empty(4)
    K._quartic(*c, re, im)
    mine = re + 1j * im
    for r in np.roots(c):
        assert np.abs(mine - r).min() <= 1e-6 * (1 + abs(r)) or np.abs(np.polyval(c, mine)).min() <= 1e-9 * big


def test_branches_match_the_reference_subproblems():
    """The engine's branches (scalar SP5 / SP6 / SP3, closed-form quartic) against the reference subproblems
    (arrays, eigenvalue quartic) at random values of the searched joint."""
    g = np.random.default_rng(5)
    for kind in ("TI", "TP", "SW"):
        name, make = KINDS[kind]
        for _ in range(4):
            form = make(g)
            prep = G._prepare(form, name)
            H, P = prep.Hi, prep.Pi
            R, p = form.fk(random_q(g, form))
            R06 = R @ form.R_nT.T
            C = _target_c(kind, H, P, R06, p)
            for x in g.uniform(-np.pi, np.pi, 20):
                Sx, E = np.zeros((4, S.WIDTH)), np.zeros(4)
                n = S._eval(getattr(S, kind), H, P, C, x, Sx, E)
                if kind in ("TI", "TP"):    # the cosines and sines kept with SP6's two joints are theirs
                    a, b = (0, 2) if kind == "TI" else (0, 1)
                    for i in range(n):
                        want = [math.cos(Sx[i, a]), math.sin(Sx[i, a]), math.cos(Sx[i, b]), math.sin(Sx[i, b])]
                        assert np.abs(Sx[i, 3:7] - want).max() < 1e-14, (kind, x, Sx[i], want)
                if kind == "TI":
                    v = sp.rot(H[0], -x, C[1]) - P[1]
                    t1, t2, t3, m, ls = sp.sp5(-P[2], v, P[3], P[4], -H[1], H[2], H[3])
                    ref = [] if ls else [np.array([t1[i], t2[i], t3[i]]) for i in range(m)]
                elif kind == "TP":
                    R05 = R06 @ sp.rotm(H[5], -x)
                    w = p - P[0] - R05 @ P[5] - R06 @ P[6]
                    v = R05 @ H[4]
                    t0, t3, m, ls = sp.sp6(np.array([H[1], -H[1], H[1], -H[1]]), np.array([-H[0], H[3], -H[0], H[3]]),
                                           np.array([w, P[4], v, H[4]]), H[1] @ (P[1] + P[2] + P[3]), 0.0)
                    ref = [] if ls else [np.array([t0[i], t3[i]]) for i in range(m)]
                else:
                    v = sp.rot(H[0], -x, C[0]) - P[1]
                    t, m, ls = sp.sp3(P[3], -P[2], H[2], np.linalg.norm(v))
                    ref = [] if ls else [np.array([t[i]]) for i in range(m)]
                mine = [Sx[i, :len(r)] for i in range(n) for r in ref[:1]]
                assert len({tuple(np.round(r, 6)) for r in ref}) == len({tuple(np.round(s, 6)) for s in mine}), (kind, x)
                for r in ref:
                    assert min(np.abs(_wrap(s - r)).max() for s in mine) < 1e-7


def test_spherical_middle_in_ik_all():
    """An arm with axes 2, 3, 4 meeting gets every branch from ``ik_all`` (the geometric family), and read from
    tool to base (axes 3, 4, 5 meet: the reversed chain)."""
    import armkit
    from armkit.ik.analytic import closed_form
    from armkit.ik.geometric.classify import classify
    from test_dense_check import robot_of

    for reverse in (False, True):
        form = spherical_middle_arm(np.random.default_rng(3))
        if reverse:
            form = G.reverse(form)
        robot = robot_of(form)
        cls = classify(robot)
        assert cls.name == "6R-spherical-middle" and cls.inverted == reverse
        assert closed_form(robot).family == "geometric"
        q = np.random.default_rng(4).uniform(-math.pi, math.pi, 6)
        T = armkit.fk(robot, q)
        res = armkit.ik_all(robot, T)
        ok = np.asarray(res.success)
        assert res.q.shape == (16, 6) and ok.sum() % 2 == 0
        assert np.abs(armkit.fk(robot, res.q[ok]) - T).max() < 1e-9
        assert np.abs(_wrap(res.q[ok] - q)).max(axis=1).min() < 1e-7
