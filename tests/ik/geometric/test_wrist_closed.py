"""The spherical wrist in closed form (:func:`armkit.ik.geometric.solvers_wrist._wrist_from`) and the pair test of
the one-call shortcut (:func:`armkit.ik.geometric.solvers_check._close_wrapped`).

The wrist solves ``rot(h4, q4) rot(h5, q5) rot(h6, q6) = R36`` from ``v = R36 h6`` and ``y = R36 x``: q5 from
``h4ᵀ v = h4ᵀ rot(h5, q5) h6`` (a cosine and sine in closed form), then q4 and q6 by SP1. Each answer is checked
here against the equation itself (the product of the three rotations, by SciPy), and the set against the older
form, SP2 of ``h6`` onto ``v`` (:func:`._wrist_sp2`), which the degenerate axes still take.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from armkit.ik.geometric import solvers as G
from armkit.ik.geometric import solvers_check as SC
from armkit.ik.geometric import solvers_wrist as SW


def _rot(k, t):
    return Rotation.from_rotvec(np.asarray(k) * t).as_matrix()


def _unit(g):
    v = g.normal(size=3)
    return v / np.linalg.norm(v)


def _inputs(h6, R36):
    x = G._perp(h6)
    S = np.zeros((5, 3))
    S[0] = R36 @ h6
    S[1] = x
    S[2] = R36 @ x
    return S


def _solve(f, h, R36, sp2=False):
    W = np.zeros((2, 3))
    S = _inputs(h[2], R36)
    if sp2:
        m, ls = f(h[0], h[1], h[2], W, S)[:2]
    else:
        m, ls, sing = f(h[0], h[1], h[2], 0.0, W, S, np.zeros((3, 3, 3)))
        assert not sing
    return W[:m].copy(), bool(ls)


def _product(h, w):
    return _rot(h[0], w[0]) @ _rot(h[1], w[1]) @ _rot(h[2], w[2])


def _wrist_axes(g, orthogonal):
    if orthogonal:   # a wrist like the Puma's: h4 ⊥ h5 ⊥ h6, h6 = h4 at q = 0, turned at random
        Rb = Rotation.random(random_state=int(g.integers(2 ** 31))).as_matrix()
        return Rb[:, 2], Rb[:, 1], Rb[:, 2]
    return _unit(g), _unit(g), _unit(g)   # any three axes (the Kinova's 60° wrists, or worse)


def _both(compiled):
    if compiled:
        K = G.kernels()
        if K is None:
            pytest.skip("numba")
        return K._wrist_from, K._wrist_sp2
    return SW._wrist_from, SW._wrist_sp2


@pytest.mark.parametrize("compiled", [False, True], ids=["python", "numba"])
@pytest.mark.parametrize("orthogonal", [True, False], ids=["orthogonal", "any-axes"])
def test_every_answer_makes_R36_and_the_set_is_the_sp2_forms(compiled, orthogonal):
    new, old = _both(compiled)
    g = np.random.default_rng(20261207)
    exact = 0
    for _ in range(200):
        h = _wrist_axes(g, orthogonal)
        q = g.uniform(-np.pi, np.pi, 3)
        R36 = _product(h, q)
        W, ls = _solve(new, h, R36)
        W2, ls2 = _solve(old, h, R36, sp2=True)
        assert not ls and not ls2 and len(W) == len(W2) and len(W) >= 1
        for w in W:   # the equation itself
            assert np.abs(_product(h, w) - R36).max() < 1e-12
        # the same answers, in the same order, as the SP2 form's (to rounding)
        d = np.abs((W - W2 + np.pi) % (2 * np.pi) - np.pi).max()
        assert d < 1e-9, (W, W2)
        # q itself is among them
        assert np.abs((W - q + np.pi) % (2 * np.pi) - np.pi).max(axis=1).min() < 1e-9
        exact += len(W) == 2
    assert exact > 150   # two answers nearly always (one at the tangent only)


@pytest.mark.parametrize("compiled", [False, True], ids=["python", "numba"])
def test_least_squares_when_no_q5_exists(compiled):
    """Axes where ``h4ᵀ rot(h5, q5) h6`` cannot reach ``h4ᵀ v``: one answer, flagged, nearest in that component."""
    new, _ = _both(compiled)
    h4 = np.array([0.6, 0.0, 0.8])                    # h4 tilted off the plane h5 turns h6 in
    h5 = np.array([1.0, 0.0, 0.0])
    h6 = np.array([0.0, math.sin(1.2), math.cos(1.2)])
    h = (h4, h5, h6)
    hi = max(h4 @ _rot(h5, t) @ h6 for t in np.linspace(-np.pi, np.pi, 20001))
    assert hi < 1.0 - 1e-3
    v = 0.95 * h4 + math.sqrt(1 - 0.95 ** 2) * np.array([0.0, 1.0, 0.0])   # h4ᵀ v = 0.95 > hi (0.8): out of reach
    R36 = Rotation.align_vectors([v], [h6])[0].as_matrix()
    W, ls = _solve(new, h, R36)
    assert ls and len(W) == 1
    assert h4 @ _rot(h5, W[0, 1]) @ h6 == pytest.approx(hi, abs=1e-7)


@pytest.mark.parametrize("compiled", [False, True], ids=["python", "numba"])
def test_axes_in_line_take_the_sp2_form(compiled):
    """h5 ∥ h6 (no wrist of the class; the closed form has no equation for q5): the SP2 form answers."""
    new, _ = _both(compiled)
    g = np.random.default_rng(7)
    h4 = _unit(g)
    h5 = _unit(g)
    h = (h4, h5, h5)
    R36 = _product(h, (0.4, 0.9, -0.2))
    W, ls = _solve(new, h, R36)
    for w in W:
        assert np.abs(_product(h, w) - R36).max() < 1e-12


angles = st.floats(-math.pi, math.pi, allow_nan=False).map(lambda x: x if x > -math.pi else math.pi)
near = st.sampled_from([0.0, 1e-9, 5e-9, 1e-8, 2e-8, 1e-7, math.pi, 2 * math.pi - 1e-8, 2 * math.pi - 2e-8])


@settings(max_examples=400, deadline=None)
@given(st.lists(angles, min_size=6, max_size=6), st.lists(near, min_size=6, max_size=6),
       st.lists(st.booleans(), min_size=6, max_size=6), st.lists(st.booleans(), min_size=6, max_size=6))
def test_close_wrapped_is_close_on_wrapped_rows(a, shift, sign, prism):
    """:func:`_close_wrapped` gives :func:`_close`'s answer for rows wrapped into (-π, π] (``_distinct``'s), also a
    hair either side of its 1e-8 and across ±π."""
    a = np.array(a)
    b = a + np.where(sign, 1.0, -1.0) * np.array(shift)
    pr = np.array(prism)
    W = np.stack([np.where(pr, a, [SC._wrap(x) for x in a]), np.where(pr, b, [SC._wrap(x) for x in b])])
    assert SC._close_wrapped(W, 0, 1, pr) == SC._close(W[0], W[1], pr)


coef = st.floats(-3.0, 3.0, allow_nan=False)


@settings(max_examples=400, deadline=None)
@given(coef, coef, coef, st.sampled_from([None, "tangent+", "tangent-", "flat"]))
def test_trig1cs_is_trig1s_with_cosines(a, b, c, case):
    """:func:`_trig1cs` (the closed-form cores' ``a cos θ + b sin θ = c``) gives :func:`_trig1s`'s count, flag and
    angles (to rounding, in its order), each with its own cosine and sine; every exact answer meets the equation."""
    from armkit.ik.geometric import subproblems as SP

    if case == "tangent+":
        c = math.hypot(a, b)
    elif case == "tangent-":
        c = -math.hypot(a, b)
    elif case == "flat":
        a = b = 0.0
    scale = max(abs(a) + abs(b) + abs(c), 1.0)
    t0, t1, n, ls = SP._trig1s(a, b, c, scale)
    n2, ls2, r0, r1 = SP._trig1cs(a, b, c, scale)
    assert (n2, ls2) == (n, ls)
    for want, (th, ct, sn) in zip((t0, t1)[:n], (r0, r1)[:n]):
        assert abs((th - want + np.pi) % (2 * np.pi) - np.pi) < 1e-7 + 1e-9 / max(math.hypot(a, b), 1e-300)
        assert -math.pi < th <= math.pi
        assert ct == pytest.approx(math.cos(th), abs=1e-12) and sn == pytest.approx(math.sin(th), abs=1e-12)
        if not ls and math.hypot(a, b) > 1e-6:
            assert a * ct + b * sn == pytest.approx(c, abs=1e-12 * scale)
