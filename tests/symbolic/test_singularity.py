"""Singularity analysis: the factored determinant against hand derivations, the named sets, numeric checks."""

from __future__ import annotations

import math

import numpy as np
import pytest

import armkit

sp = pytest.importorskip("sympy")
from armkit.analysis.singularity import analyze_singularities, factor_trig, plot_manipulability  # noqa: E402


class _Analyzed(dict):
    """Analyzes a robot the first time a test asks for it: a worker of ``pytest -n`` that runs only the planar2
    tests never pays for puma560's analysis (~9 s of CPU with its derivation, ~2.5 s without)."""

    def __missing__(self, name: str):
        self[name] = analyze_singularities(armkit.load(name))
        return self[name]


@pytest.fixture(scope="module")
def results():
    """One analysis per robot (planar2, fighter, puma560) for the whole module, made on first use."""
    return _Analyzed()


def _by_kind(res, kind):
    return [f for f in res.singular_factors if f.kind == kind]


def test_planar2_det_and_sets(results):
    res = results["planar2"]
    q2, a1, a2 = sp.symbols("q2 a1 a2", real=True)
    # hand: J_planar = [[-a1 s1 - a2 s12, -a2 s12], [a1 c1 + a2 c12, a2 c12]] -> det = a1 a2 s2
    assert sp.simplify(res.determinant - a1 * a2 * sp.sin(q2)) == 0
    (elbow,) = _by_kind(res, "elbow")
    assert [round(math.degrees(v), 9) for v, _ in elbow.solutions] == [0.0, 180.0]
    assert [lab for _, lab in elbow.solutions] == ["stretched", "folded"]


def test_scara_det_of_its_four_moving_rows():
    """The eCobra 600 moves its tool along vx, vy, vz and turns it about z: four rows for four joints, so det J of
    those rows (det(J Jᵀ) was a square of it that sympy could not tidy). By hand, rows (vx, vy, vz, wz), columns
    (q1, q2, d3, q4): [[-a1 s1 - a2 s12, -a2 s12, 0, 0], [a1 c1 + a2 c12, a2 c12, 0, 0], [0, 0, -1, 0],
    [1, 1, 0, -1]] -> det = (a1 a2 s2)(-1)(-1) = a1 a2 s2: singular with the elbow stretched or folded only."""
    res = analyze_singularities(armkit.load("cobra600"))
    q2, a1, a2 = sp.symbols("q2 a1 a2", real=True)
    assert res.method == "det(J)" and res.rows == ("vx", "vy", "vz", "wz")
    assert sp.simplify(res.determinant - a1 * a2 * sp.sin(q2)) == 0
    (elbow,) = _by_kind(res, "elbow")
    assert [lab for _, lab in elbow.solutions] == ["stretched", "folded"] and elbow.joints == (2,)


def test_fighter_stretched_folded_and_yaw_axis(results):
    res = results["fighter"]
    assert res.method == "det(J_v)"
    q2, q3, a2, a3 = sp.symbols("q2 q3 a2 a3", real=True)
    # hand: det J_v = -a2 a3 s3 (a2 c2 + a3 c23) (r = a2 c2 + a3 c23 is the distance from the yaw axis)
    assert sp.simplify(res.determinant + a2 * a3 * sp.sin(q3) * (a2 * sp.cos(q2) + a3 * sp.cos(q2 + q3))) == 0
    (elbow,) = _by_kind(res, "elbow")
    assert elbow.joints == (3,) and {lab for _, lab in elbow.solutions} == {"stretched", "folded"}
    (axis,) = _by_kind(res, "on-axis")
    assert "yaw axis" in axis.description and axis.joints == (2, 3)
    # independent check: on the samples the tool point is on the z axis (x = y = 0)
    p = armkit.fk(armkit.load("fighter"), axis.samples)[:, :3, 3]
    np.testing.assert_allclose(p[:, :2], 0.0, atol=1e-9)


def test_puma_wrist_singularity_found(results):
    res = results["puma560"]
    wrist = [f for f in res.singular_factors if f.expr == sp.sin(sp.Symbol("q5", real=True))]
    assert len(wrist) == 1 and wrist[0].kind == "wrist"
    assert [round(math.degrees(v), 9) for v, _ in wrist[0].solutions] == [0.0, 180.0]
    assert "4" in wrist[0].description and "6" in wrist[0].description
    assert {f.kind for f in res.singular_factors} == {"elbow", "on-axis", "wrist"}


@pytest.mark.parametrize("name", ["planar2", "fighter", "puma560"])
def test_factors_vanish_where_manipulability_vanishes(results, name):
    res = results[name]
    r = armkit.load(name)
    for f in res.singular_factors:
        assert len(f.samples) >= 1
        w = armkit.manipulability(r, f.samples)
        assert np.all(w < 1e-9 * max(res.typical_manipulability, 1e-12) + 1e-12), (f.text, w)
    # and away from every factor the arm is not singular
    d = __import__("armkit.symbolic", fromlist=["derive"]).derive(r)
    q = r.random_q(20, rng=5)
    prod = np.ones(len(q))
    for f in res.singular_factors:
        fn = sp.lambdify([list(d.q)], f.expr.subs(d.values), "numpy")
        prod *= np.array([abs(float(fn(x))) for x in q])
    keep = prod > 1e-3 * np.max(prod)
    assert np.all(armkit.manipulability(r, q[keep]) > 0)


def test_factor_trig_finds_hidden_products():
    q2, q3, a2, a3 = sp.symbols("q2 q3 a2 a3", real=True)
    e = sp.expand(sp.expand_trig(a2 * a3 * sp.sin(q3) * (a2 * sp.cos(q2) + a3 * sp.cos(q2 + q3))))
    c, fs = factor_trig(e, (a2, a3))
    got = {str(b) for b, _ in fs}
    assert "sin(q3)" in got and "a2*cos(q2) + a3*cos(q2 + q3)" in got


def test_seven_joints_refused_with_reason():
    with pytest.raises(armkit.ArmkitError, match="too large"):
        analyze_singularities(armkit.load("panda"))


def test_manipulability_plot(tmp_path, results):
    out = tmp_path / "m.png"
    fig = plot_manipulability(armkit.load("planar2"), out, joints=(1, 2), resolution=31, analysis=results["planar2"])
    assert out.stat().st_size > 1000 and fig.axes
    with pytest.raises(armkit.ArmkitError, match="revolute joints"):
        plot_manipulability(armkit.load("planar2"), None, joints=(1, 5))


def test_a_determinant_past_its_budget_is_said_not_waited_for():
    """The SO-101's URDF (a CAD export: offsets such as 1.3e-11 rad off pi/2 and 0.0276 rad) kept sympy busy for
    more than 15 minutes (measured) before the budget covered the determinant and its factoring. With 1 s each for
    the derivation and the determinant, the analysis stops with a LimitError that names the budget and the way on;
    a budget that is not a positive number of seconds is refused."""
    from armkit.errors import ArgumentError, LimitError
    from armkit.symbolic import derive

    so101 = armkit.load("so101")
    d = derive(so101, cache=False, simplify_budget=1.0)
    with pytest.raises(LimitError, match=r"'so101' was not factored within 1 s of CPU time.*armkit.manipulability"):
        analyze_singularities(so101, d, budget=1.0)
    for bad in (0, -1.0, float("nan")):
        with pytest.raises(ArgumentError, match="budget must be a number of CPU seconds"):
            analyze_singularities(so101, d, budget=bad)


def test_the_budget_leaves_the_round_arms_alone():
    """A budget does not change an answer that fits in it: planar2's determinant with the default budget and with
    none is the hand derivation a1*a2*sin(q2)."""
    r = armkit.load("planar2")
    a1, a2, q2 = sp.symbols("a1 a2 q2", real=True)
    for budget in (60.0, None):
        det = analyze_singularities(r, budget=budget).determinant
        assert sp.simplify(det - a1 * a2 * sp.sin(q2)) == 0
