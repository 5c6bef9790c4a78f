"""The closed-form cores' lanes: a spherical core's wrists side by side
(:func:`armkit.ik.geometric.solvers_wrist._wrist_lanes`), and the three-parallel core's pairs.

The lanes take up to four positions at once by the common case of :func:`._wrist_from` (a non-singular wrist
with two exact answers), and flag the others for the one-by-one path. Checked here:

- lane by lane against the one-by-one path itself (the six turns of ``_core_spherical``, then ``_wrist_from``):
  a flagged lane is exactly the lane that path solves by its common case, and its answers are that path's, bit
  for bit (plain Python and compiled);
- through the compiled spherical and three-parallel cores, where the lanes (also the three-parallel core's (q1, q5)
  pairs side by side, :func:`.solvers_parallel._pairs_lanes`) are compiled to vector instructions: the candidates
  are those of the same cores run as plain Python with the lanes switched off, bit for bit, also for singular
  wrists, targets out of reach and a prismatic joint 3 (whose positions take the one-by-one path).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from armkit.ik.geometric import solvers as G
from armkit.ik.geometric import solvers_check as SC
from armkit.ik.geometric import solvers_wrist as SW

from test_solvers import random_arm, random_q   # same folder, on pytest's path


def _unit(g):
    v = g.normal(size=3)
    return v / np.linalg.norm(v)


def _kernels(compiled):
    if not compiled:
        return SW
    K = G.kernels()
    if K is None:
        pytest.skip("numba")
    return K


def _one_by_one(f, H, a, b, x, c, s, qref3=0.0):
    """``_core_spherical``'s path for one position: ``a``, ``b`` turned by -q1, -q2, -q3, then ``_wrist_from``."""
    S = np.zeros((5, 3))
    S[1] = x
    ta, tb = np.zeros(3), np.zeros(3)
    f._turn_to(H[0], -s[0], c[0], a, ta)
    f._turn_to(H[0], -s[0], c[0], b, tb)
    f._turn_to(H[1], -s[1], c[1], ta, S[3])
    f._turn_to(H[1], -s[1], c[1], tb, S[4])
    f._turn_to(H[2], -s[2], c[2], S[3], S[0])
    f._turn_to(H[2], -s[2], c[2], S[4], S[2])
    W = np.zeros((2, 3))
    m, ls, sing = f._wrist_from(H[3], H[4], H[5], qref3, W, S, np.zeros((3, 3, 3)))
    common = m == 2 and not sing and f._sp2cs(S[0, 0], S[0, 1], S[0, 2], H[5, 0], H[5, 1], H[5, 2], H[3], H[4])[0]
    return W[:m].copy(), bool(ls), bool(common)


def _case(g, kind):
    """Axes, ``a = R h6``, ``b = R x`` and four positions' cosines and sines; ``kind`` makes some lanes leave the
    common case (a singular wrist: lane 1's v along h4; axes 5 and 6 in line: every lane)."""
    H = np.stack([_unit(g) for _ in range(6)])
    q = g.uniform(-np.pi, np.pi, (4, 3))
    c, s = np.cos(q), np.sin(q)
    x = np.zeros(3)
    SW._perp_to(H[5], x)
    R = np.linalg.qr(g.normal(size=(3, 3)))[0]
    if kind == "singular":   # lane 1: R03ᵀ R h6 = h4, so v = h4 (a turn of R about h6 keeps that)
        R03 = _rot(H[0], q[1, 0]) @ _rot(H[1], q[1, 1]) @ _rot(H[2], q[1, 2])
        R = R03 @ _align(H[5], H[3])
    elif kind == "axes in line":   # h5 ∥ h6: no equation for q5 (the SP2 form answers), in every lane
        H[4] = -H[5]
    return H, R @ H[5], R @ x, x, c, s


def _rot(k, t):
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(t) * K + (1 - math.cos(t)) * K @ K


def _align(u, v):
    """A rotation taking the unit ``u`` to the unit ``v``."""
    w = np.cross(u, v)
    n = np.linalg.norm(w)
    if n < 1e-15:
        return np.eye(3)
    return _rot(w / n, math.atan2(n, float(u @ v)))


def _lanes(f, H, a, b, x, c, s):
    L = np.full((SC.CORE_T, SW.WRIST_LANES), np.nan)
    for i in range(SW.WRIST_LANES):
        for k in range(3):
            L[8 + 2 * k, i] = c[i, k]
            L[9 + 2 * k, i] = s[i, k]
    f._wrist_lanes(H, a, b, x, L)
    return L


@pytest.mark.parametrize("compiled", [False, True], ids=["python", "numba"])
@pytest.mark.parametrize("kind", ["random", "singular", "axes in line"])
def test_each_lane_is_the_one_by_one_path(compiled, kind):
    f = _kernels(compiled)
    g = np.random.default_rng(20261207)
    flags = []
    for _ in range(60 if compiled else 20):
        H, a, b, x, c, s = _case(g, kind)
        L = _lanes(f, H, a, b, x, c, s)
        flags.append(L[0].copy())
        for i in range(SW.WRIST_LANES):
            W, ls, common = _one_by_one(f, H, a, b, x, c[i], s[i])
            assert L[0, i] in (0.0, 1.0)
            assert (L[0, i] == 1.0) == common, (kind, i)
            if common:
                got = np.array([L[2:5, i], L[5:8, i]])
                assert np.array_equal(got, W), (got, W)    # the same bits
                assert (L[1, i] == 1.0) == ls
    taken = np.array(flags) == 1.0
    assert (taken.any() or kind == "axes in line") and not taken.all()   # (random axes, a random R: a wrist
    # reaches v about half the time)
    if kind == "singular":        # the cases built to leave the common case do
        assert not taken[:, 1].any()
    if kind == "axes in line":
        assert not taken.any()


CORES = {"sw12": ("spherical_two_intersecting", 0), "sw23": ("spherical_two_parallel", 0),
         "3p": ("three_parallel", 1), "3p56": ("three_parallel_two_intersecting", 1)}


def _no_lanes(*args):
    """A stand-in for the lanes that takes none: every position or pair goes the one-by-one path."""
    L = args[-1]
    L[0, :] = 0.0


@settings(max_examples=80, deadline=None)
@given(st.sampled_from(["sw12", "sw23", "sw12 prismatic", "3p", "3p56"]), st.integers(0, 2 ** 31 - 1),
       st.sampled_from(["random", "wrist straight", "far"]))
def test_the_compiled_cores_are_the_one_by_one_path(arm, seed, target):
    """``_core_in`` compiled (the lanes in vector instructions) against the same core as plain Python with the lanes
    switched off (every position's wrist, every (q1, q5) pair one by one): the same candidates, flags and order, bit
    for bit. A straight wrist (q5 = 0) is singular; a far target is out of reach (least-squares positions: the
    wrists then often leave the common case). The general three-parallel class finds its (q1, q5) pairs by SP6,
    whose quartic may take the companion matrix's eigenvalues (LAPACK: NumPy's build in plain Python, SciPy's in
    compiled code, which can differ in the last bit); the plain-Python run takes the compiled SP6 so that both
    cores start their pairs from the same numbers (seed 1910654 of "3p": 1 ulp apart, before the lanes)."""
    from armkit.ik.geometric import solvers_parallel as SPar

    K = _kernels(True)
    g = np.random.default_rng(seed)
    name, which = CORES[arm.split()[0]]
    form = random_arm(g, arm.split()[0], prismatic3=arm.endswith("prismatic"))
    q = random_q(g, form)
    if target == "wrist straight":
        q[4] = 0.0
    R, p = form.fk(q)
    if target == "far":
        p = 3.0 * p
    prep = G._prepare(form, name)

    def run(core):
        Q, LS, SG = np.zeros((G.MAXSOL, 6)), np.zeros(G.MAXSOL, bool), np.zeros(G.MAXSOL, bool)
        V3, M3 = np.full((SC.CORE_V, 3), np.nan), np.full((SC.CORE_M, 3, 3), np.nan)
        T14, CL = np.full((SC.CORE_T, 4), np.nan), np.zeros(8, bool)
        m = core(which, prep.kind, prep.Hi, prep.Pi, prep.RnT, prep.prism, R, p, np.zeros(6), G.SEARCH_N, Q, LS,
                 SG, V3, M3, T14, CL)
        return m, Q[:m].copy(), LS[:m].copy(), SG[:m].copy()

    m1, Q1, LS1, SG1 = run(K._core_in)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(SW, "_wrist_lanes", _no_lanes)
        mp.setattr(SPar, "_pairs_lanes", _no_lanes)
        mp.setattr(SPar, "_pairs_sp6", K._pairs_sp6)
        m2, Q2, LS2, SG2 = run(SC._core_in)
    assert m1 == m2 and m1 > 0
    assert np.array_equal(Q1, Q2), np.abs(Q1 - Q2).max()
    assert np.array_equal(LS1, LS2) and np.array_equal(SG1, SG2)
