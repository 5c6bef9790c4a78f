"""Symbolic FK/Jacobian against the numeric kernels, the generated NumPy module, LaTeX, and the derived 2R IK.

References: the numeric kernels (independent code path), hand derivations written below
(planar 2R/3R textbook formulas, Craig's modified DH of the 3R arm), the law-of-cosines 2R IK.
"""

from __future__ import annotations

import importlib.util
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit

sp = pytest.importorskip("sympy")
from armkit.symbolic import derive, exact_angle  # noqa: E402
from armkit.symbolic.export import shorthand, to_latex, to_numpy_source, to_text  # noqa: E402
from armkit.symbolic.ik2r import derive_planar_2r_ik  # noqa: E402

ROBOTS = sorted(armkit.bundled_robots())


def _custom() -> armkit.Robot:
    """Modified DH with a prismatic joint and an angle that is not a simple multiple of pi."""
    J = armkit.Joint
    return armkit.Robot([J(theta=0.3, d=0.1, lower=-3, upper=3), J("prismatic", alpha=math.pi / 2, d=0.2, a=0.05,
                                                                     lower=0, upper=0.5),
                         J(alpha=-0.4, a=0.3, lower=-3, upper=3)], convention="modified", name="custom",
                        tool=[[1, 0, 0, 0.1], [0, 1, 0, 0], [0, 0, 1, 0.05], [0, 0, 0, 1]])


class _Derived(dict):
    """Derives a robot the first time a test asks for it (so that pytest -n spreads the robots over its workers)."""

    def __missing__(self, name: str) -> tuple:
        r = _custom() if name == "custom" else armkit.load(name)
        d = derive(r, simplify=r.n <= 6 and r.is_dh)   # URDF arms (so101: offsets like -76.03 deg) raw
        self[name] = (r, d)
        return self[name]


class _Lambdified(dict):
    """The lambdified T and J of a derived robot, made the first time a test asks for them: only the numeric
    comparison needs them, and for the raw so101 products they cost ~13 s of CPU (``Derivation.lambdify``)."""

    def __init__(self, derived: _Derived) -> None:
        super().__init__()
        self.derived = derived

    def __missing__(self, name: str) -> tuple:
        r, d = self.derived[name]
        self[name] = (r, d, d.lambdify("T"), d.lambdify("J"))
        return self[name]


@pytest.fixture(scope="module")
def derived():
    """One derivation per robot (simplified up to 6 joints, raw products for 7 and URDF arms): (robot, derivation)."""
    return _Derived()


@pytest.fixture(scope="module")
def lambdified(derived):
    """One lambdified T, J per robot on top of :func:`derived`: (robot, derivation, T(q), J(q))."""
    return _Lambdified(derived)


def _q_in_limits(r: armkit.Robot, u: list[float]) -> np.ndarray:
    lo = np.where(np.isfinite(r.lower), r.lower, -math.pi)
    hi = np.where(np.isfinite(r.upper), r.upper, math.pi)
    return lo + (hi - lo) * np.asarray(u[: r.n])


@pytest.mark.parametrize("name", ROBOTS + ["custom"])
@settings(max_examples=8)
@given(u=st.lists(st.floats(0, 1), min_size=7, max_size=7))
def test_symbolic_fk_and_jacobian_match_numeric(lambdified, name, u):
    r, d, f_T, f_J = lambdified[name]
    q = _q_in_limits(r, u)
    scale = max(1.0, r.reach)
    np.testing.assert_allclose(np.array(f_T(q), dtype=float), armkit.fk(r, q), atol=1e-12 * scale)
    np.testing.assert_allclose(np.array(f_J(q), dtype=float), armkit.jacobian(r, q), atol=1e-12 * scale)


@pytest.mark.parametrize("name", [n for n in ROBOTS if armkit.load(n).n <= 6] + ["custom"])
def test_generated_numpy_module_imports_and_matches(derived, name, tmp_path):
    r, d = derived[name]
    path = tmp_path / f"gen_{name}.py"
    path.write_text(to_numpy_source(d))
    spec = importlib.util.spec_from_file_location(f"gen_{name}", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    Q = r.random_q(6, rng=3).reshape(2, 3, r.n)            # batched over two leading axes
    scale = max(1.0, r.reach)
    np.testing.assert_allclose(mod.fk(Q), armkit.fk(r, Q), atol=1e-12 * scale)
    np.testing.assert_allclose(mod.jacobian(Q), armkit.jacobian(r, Q), atol=1e-12 * scale)
    np.testing.assert_allclose(mod.fk(Q[0, 0]), armkit.fk(r, Q[0, 0]), atol=1e-12 * scale)
    with pytest.raises(ValueError, match=f"shape"):
        mod.fk(np.zeros(r.n + 1))
    assert "import numpy as np" in path.read_text() and "sympy" not in path.read_text()


def test_planar2_hand_formulas(derived):
    _, d = derived["planar2"]
    q1, q2 = d.q
    a1, a2 = sp.symbols("a1 a2", real=True)
    assert sp.simplify(d.T[0, 3] - (a1 * sp.cos(q1) + a2 * sp.cos(q1 + q2))) == 0
    assert sp.simplify(d.T[1, 3] - (a1 * sp.sin(q1) + a2 * sp.sin(q1 + q2))) == 0
    assert sp.simplify(d.J[0, 1] + a2 * sp.sin(q1 + q2)) == 0
    assert list(d.J[5, :]) == [1, 1]
    text = to_text(d)
    assert str(text["T"][0, 3]) == "a1*c1 + a2*c12"


def test_planar3_modified_dh_hand_formula(derived):
    """Craig's 3R arm: x = l1 c1 + l2 c12 + l3 c123 with l3 the tool (a_{i-1} named a1, a2)."""
    _, d = derived["planar3"]
    q1, q2, q3 = d.q
    a1, a2, tx = sp.symbols("a1 a2 t_x", real=True)
    x = a1 * sp.cos(q1) + a2 * sp.cos(q1 + q2) + tx * sp.cos(q1 + q2 + q3)
    assert sp.simplify(d.T[0, 3] - x) == 0
    assert d.values == {a1: 1.0, a2: 0.8, tx: 0.3}
    assert "c123" in str(to_text(d)["T"][0, 0])


def test_exact_angles_make_exact_zeros(derived):
    _, d = derived["fighter"]
    A1 = d.links[0]
    assert A1[1, 1] == 0 and A1[2, 1] == 1 and A1[2, 2] == 0      # alpha = 90 deg exactly
    assert exact_angle(math.radians(90)) == sp.pi / 2 and exact_angle(0.4) is None
    _, dc = derived["custom"]
    assert "alpha2" in {s.name for s in dc.values}                # -0.4 rad stays a named parameter


def test_shorthand_only_plain_joint_sums():
    q1, q2 = sp.symbols("q1 q2", real=True)
    e, m = shorthand(sp.cos(q1 + q2) + sp.sin(2 * q1) + sp.cos(q1 - q2), (q1, q2))
    assert str(e).count("c12") == 1 and "sin(2*q1)" in str(e) and "cos(q1 - q2)" in str(e)


def test_latex_has_every_link_product_and_jacobian(derived):
    _, d = derived["fighter"]
    tex = to_latex(d)
    assert tex.startswith("\\documentclass") and tex.rstrip().endswith("\\end{document}")
    for i in (1, 2, 3):
        assert f"{{}}^{{{i - 1}}}A_{{{i}}} = " in tex
    assert "{}^{0}T_{3}" in tex and "J(q) = " in tex
    assert "c_{1} \\left(a_{2} c_{2} + a_{3} c_{23}\\right)" in tex
    assert "a_{2} = 77.2" in tex


def test_cache_round_trip(tmp_path, monkeypatch):
    monkeypatch.setenv("ARMKIT_CACHE_DIR", str(tmp_path))
    r = armkit.load("planar2")
    d1 = derive(r)
    files = list((tmp_path / "symbolic").glob("planar2-*.pkl"))
    assert len(files) == 1
    d2 = derive(r)
    assert sp.expand(d2.T - d1.T) == sp.zeros(4, 4) and sp.expand(d2.J - d1.J) == sp.zeros(6, 2)
    files[0].write_bytes(b"not a pickle")                       # a corrupt cache is derived again
    assert sp.expand(derive(r).T - d1.T) == sp.zeros(4, 4)


# ------------------------------------------------------------------------------------------- 2R IK
@pytest.fixture(scope="module")
def ik2r():
    return derive_planar_2r_ik()


def test_derived_c2_is_the_law_of_cosines(ik2r):
    x, y, a1, a2 = ik2r.x, ik2r.y, ik2r.a1, ik2r.a2
    assert sp.simplify(ik2r.c2 - (x ** 2 + y ** 2 - a1 ** 2 - a2 ** 2) / (2 * a1 * a2)) == 0


@settings(max_examples=25)
@given(r=st.floats(0.55, 1.45), phi=st.floats(-math.pi, math.pi))
def test_derived_branches_equal_hand_formula_and_solver(ik2r, r, phi):
    arm = armkit.load("planar2")
    L1, L2 = 1.0, 0.5
    x, y = r * math.cos(phi), r * math.sin(phi)
    # hand formula (the homogeneous-transform seminar's, with the atan2 arguments in the right order)
    c2 = (x * x + y * y - L1 ** 2 - L2 ** 2) / (2 * L1 * L2)
    hand = []
    for sgn in (1, -1):
        t2 = math.atan2(sgn * math.sqrt(max(0.0, 1 - c2 * c2)), c2)
        t1 = math.atan2(y, x) - math.atan2(L2 * math.sin(t2), L1 + L2 * math.cos(t2))
        hand.append((t1, t2))
    derived = [f(x, y) for _, f in ik2r.numeric(L1, L2)]
    wrap = lambda a: (a + math.pi) % (2 * math.pi) - math.pi  # noqa: E731
    for (h1, h2), (d1, d2) in zip(hand, derived):
        assert abs(wrap(h1 - float(d1))) < 1e-9 and abs(wrap(h2 - float(d2))) < 1e-9
    if hasattr(armkit, "ik_all"):
        res = armkit.ik_all(arm, np.array([x, y]))
        sols = np.asarray(res.q)[np.asarray(res.success)]
        for d1, d2 in derived:
            assert any(abs(wrap(s[0] - float(d1))) < 1e-7 and abs(wrap(s[1] - float(d2))) < 1e-7 for s in sols)
