"""derive()'s fast path (products in the angle sums, no trigsimp) against the numeric kernels and the general path.

References: armkit.fk / armkit.jacobian (independent numeric code) on random joint values, for every bundled DH arm
and for random arms whose twists and offsets are exact multiples of pi/2 (both conventions, prismatic joints,
twists of pi that flip the sign of the next angle); the general trigsimp path for a small arm (symbolic equality).
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit

sp = pytest.importorskip("sympy")
from armkit.symbolic import derive  # noqa: E402

_derive_module = sys.modules["armkit.symbolic.derive"]


def _no_general_path(*args, **kwargs):
    raise AssertionError("derive() left the fast path for an arm whose twists and offsets are exact")


def _check_numeric(r: armkit.Robot, d, q: np.ndarray) -> None:
    scale = max(1.0, r.reach)
    f_T, f_J = d.lambdify("T"), d.lambdify("J")
    for x in q:
        np.testing.assert_allclose(np.array(f_T(x), dtype=float), armkit.fk(r, x), atol=1e-12 * scale)
        np.testing.assert_allclose(np.array(f_J(x), dtype=float), armkit.jacobian(r, x), atol=1e-12 * scale)


@pytest.mark.parametrize("name", sorted(armkit.bundled_robots()))
def test_every_bundled_arm_fast_path_matches_fk_and_jacobian(name, monkeypatch):
    r = armkit.load(name)
    if not r.is_dh:
        # a URDF arm's DH twin has offsets like -76.03 deg: the fast path declines it (the general path takes it)
        from armkit.symbolic._angle_sums import angle_basis

        dh = r.to_dh()
        q, _, rows = _derive_module._symbols_for(dh)
        assert angle_basis(dh.convention, q, rows, [j.is_prismatic for j in dh.joints]) is None
        return
    monkeypatch.setattr(_derive_module, "_general_chain", _no_general_path)
    d = derive(r, cache=False, simplify_budget=None)
    assert "note" not in d.meta
    _check_numeric(r, d, r.random_q(4, rng=17))


_EXACT = [0.0, math.pi / 2, -math.pi / 2, math.pi]


@st.composite
def exact_arms(draw) -> armkit.Robot:
    """Arms of 1-4 joints with twists and offsets among 0, +-pi/2, pi and lengths that are often zero."""
    n = draw(st.integers(1, 4))
    lengths = st.sampled_from([0.0, 0.0, 0.25, -0.4, 0.7])
    joints = []
    for _ in range(n):
        kind = draw(st.sampled_from(["revolute", "revolute", "prismatic"]))
        joints.append(armkit.Joint(kind, theta=draw(st.sampled_from(_EXACT)), d=draw(lengths), a=draw(lengths),
                                   alpha=draw(st.sampled_from(_EXACT)), lower=-math.pi, upper=math.pi))
    tool = np.eye(4)
    tool[:3, 3] = [draw(lengths), 0.0, draw(lengths)]
    base = np.eye(4)
    turn = draw(st.sampled_from([0.0, 0.0, math.pi / 6, -math.pi / 4, 2 * math.pi / 3]))   # about z: sqrt(3)/2, ...
    base[:2, :2] = [[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]]
    return armkit.Robot(joints, convention=draw(st.sampled_from(["standard", "modified"])), name="exact", tool=tool,
                        base=base)


@settings(max_examples=15)
@given(r=exact_arms())
def test_random_exact_arms_fast_path_matches_fk_and_jacobian(r):
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(_derive_module, "_general_chain", _no_general_path)
        d = derive(r, cache=False, simplify_budget=None)
    _check_numeric(r, d, r.random_q(3, rng=5))
    # at most one power of each sine and cosine per term: the reduced (multilinear) form, no sin(q)**2 left over
    for e in list(d.T) + list(d.J):
        assert not any(p.base.func in (sp.sin, sp.cos) and p.exp >= 2 for p in e.atoms(sp.Pow)), e


def test_a_turned_base_gives_cosines_of_shifted_angles():
    """A base turned by 30 deg about z: cos(q1 + pi/6), as written by hand, not sqrt(3)/2 cos(q1) - sin(q1)/2."""
    J = armkit.Joint
    c, s = math.cos(math.pi / 6), math.sin(math.pi / 6)
    base = [[c, -s, 0, 0.1], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]
    r = armkit.Robot([J(d=0.3, alpha=math.pi / 2), J(a=0.4, theta=math.pi / 6), J(a=0.3, alpha=math.pi), J(d=0.1)],
                     name="turned", base=base)
    d = derive(r, cache=False, simplify_budget=None)
    q1, q2, q3, _ = d.q
    a2, a3, d4, bx = sp.symbols("a2 a3 d4 b_x", real=True)
    # by hand: the base turn adds to q1 (parallel z axes), the offset to q2; alpha3 = pi flips z3 = -z2 =
    # (-sin(q1 + pi/6), cos(q1 + pi/6), 0), along which d4 points
    p1 = q1 + sp.pi / 6
    x = bx + sp.cos(p1) * (a2 * sp.cos(q2 + sp.pi / 6) + a3 * sp.cos(q2 + q3 + sp.pi / 6)) - d4 * sp.sin(p1)
    assert sp.simplify(d.T[0, 3] - x) == 0
    assert "sqrt" not in str(d.T) + str(d.J)
    _check_numeric(r, d, r.random_q(3, rng=2))


def test_fast_path_equals_the_general_path_and_is_no_longer(monkeypatch):
    r = armkit.load("fighter")
    fast = derive(r, cache=False, simplify_budget=None)
    monkeypatch.setattr(_derive_module, "_fast_chain", lambda *a: None)
    general = derive(r, cache=False, simplify_budget=None)
    for a, b in zip([*fast.T, *fast.J], [*general.T, *general.J]):
        assert sp.simplify(a - b) == 0
        assert sp.count_ops(a) <= sp.count_ops(b), (a, b)


def test_the_budget_bounds_the_fast_path_too(monkeypatch):
    """A fast path that runs past the budget is interrupted: the entries stay raw (exact) and the note says so."""
    def slow(*args):
        end = time.process_time() + 30.0
        while time.process_time() < end:
            pass
        raise AssertionError("not interrupted")

    monkeypatch.setattr(_derive_module, "_fast_chain", slow)
    r = armkit.load("fighter")
    t0 = time.process_time()
    d = derive(r, cache=False, simplify_budget=0.5)
    assert time.process_time() - t0 < 5
    assert "budget" in d.meta.get("note", "")
    _check_numeric(r, d, r.random_q(2, rng=1))
