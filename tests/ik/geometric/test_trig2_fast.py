"""The scalar 2 x 2 trigonometric system of :mod:`armkit.ik.geometric._kernels` and its parts (issue 19).

``A (cos θ1, sin θ1) + B (cos θ2, sin θ2) = e`` is checked against the equations themselves and against the
intersection of two circles, whose solutions are known in closed form: with
``A = M`` and ``B = r M rot(β)`` the system is ``u1 + r u2' = M⁻¹ e`` for unit
``u1 = (cos θ1, sin θ1)`` and ``u2' = (cos (θ2 + β), sin (θ2 + β))``, so that with
``d = ‖M⁻¹ e‖`` and ``φ`` its direction (law of cosines)

* two solutions when ``|1 − r| < d < 1 + r``, none outside;
* ``θ1 = φ ± acos((1 + d² − r²) / (2 d))`` and ``u2' = (M⁻¹ e − u1) / r``.

Near ``d = 1 + r`` the two solutions merge (a near-double root of the quartic): the count must stay 2 just
inside and drop to 0 just outside. The quartic, the cubic and the angle helper are checked against
``numpy.roots`` and ``math.atan2``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from armkit.ik.geometric import _kernels as K

_PLAIN = K._trig2_rows


def _compiled():
    k = K.kernels()
    return None if k is None else k._trig2_rows


_SOLVERS = [pytest.param(_PLAIN, id="python"), pytest.param("compiled", id="compiled")]


def _solver(which):
    if which == "compiled":
        f = _compiled()
        if f is None:
            pytest.skip("numba not available")
        return f
    return which


def _solve(f, A, B, e):
    T1 = np.zeros(4)
    T2 = np.zeros(4)
    CS = np.full((4, 4), np.nan)
    n, _ = f(A[0, 0], A[0, 1], B[0, 0], B[0, 1], e[0], A[1, 0], A[1, 1], B[1, 0], B[1, 1], e[1], T1, T2, CS)
    # the cosines and sines handed back with each answer are those of its angles (to rounding)
    for i in range(n):
        want = [math.cos(T1[i]), math.sin(T1[i]), math.cos(T2[i]), math.sin(T2[i])]
        assert np.abs(CS[i] - want).max() < 1e-14, (CS[i], want)
    return [(T1[i], T2[i]) for i in range(n)]


def _residual(A, B, e, t1, t2):
    return np.linalg.norm(A @ [math.cos(t1), math.sin(t1)] + B @ [math.cos(t2), math.sin(t2)] - e)


def _adist(a, b):
    return abs(math.remainder(a - b, 2.0 * math.pi))


def _circles(M, r, beta, e):
    """The exact solutions (law of cosines), or [] when the circles do not meet."""
    g = np.linalg.solve(M, e)
    d = float(np.hypot(g[0], g[1]))
    x = (1.0 + d * d - r * r) / (2.0 * d)
    if abs(x) > 1.0:
        return []
    phi = math.atan2(g[1], g[0])
    out = []
    for sgn in (1.0, -1.0):
        t1 = phi + sgn * math.acos(x)
        u2 = (g - np.array([math.cos(t1), math.sin(t1)])) / r
        out.append((t1, math.atan2(u2[1], u2[0]) - beta))
    return out


def _rot(b):
    return np.array([[math.cos(b), -math.sin(b)], [math.sin(b), math.cos(b)]])


def _det2(M):
    """The determinant of a 2 x 2 matrix by its formula (NumPy's LU warns of a division by zero on an exactly
    singular one, which Hypothesis draws)."""
    return float(M[0, 0] * M[1, 1] - M[0, 1] * M[1, 0])


def _case(rng_vals):
    m00, m01, m10, m11, r, beta = rng_vals
    M = np.array([[m00, m01], [m10, m11]])
    return M, r, beta, r * M @ _rot(beta)


_mat = st.floats(-2.0, 2.0)
_CASE = st.tuples(_mat, _mat, _mat, _mat, st.floats(0.2, 3.0), st.floats(-math.pi, math.pi))


@pytest.mark.parametrize("which", _SOLVERS)
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(vals=_CASE, frac=st.floats(0.02, 0.98), phi=st.floats(-math.pi, math.pi))
def test_two_circles_both_solutions(which, vals, frac, phi):
    """Inside the annulus ``|1 − r| < d < 1 + r``: exactly the two law-of-cosines solutions."""
    f = _solver(which)
    M, r, beta, B = _case(vals)
    if abs(_det2(M)) < 0.05 * max(1.0, float(np.sum(M * M))):
        return
    d = abs(1.0 - r) + frac * (1.0 + r - abs(1.0 - r))
    e = M @ (d * np.array([math.cos(phi), math.sin(phi)]))
    ref = _circles(M, r, beta, e)
    got = _solve(f, M, B, e)
    assert len(got) == len(ref) == 2
    for t1, t2 in ref:
        assert min(_adist(t1, a) + _adist(t2, b) for a, b in got) < 1e-8
    for a, b in got:
        assert -math.pi < a <= math.pi and -math.pi < b <= math.pi
        assert _residual(M, B, e, a, b) < 1e-10 * (1.0 + np.linalg.norm(e))


@pytest.mark.parametrize("which", _SOLVERS)
@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(vals=_CASE, out=st.floats(1e-4, 2.0), phi=st.floats(-math.pi, math.pi))
def test_two_circles_apart_none(which, vals, out, phi):
    """Outside the annulus (beyond ``1 + r``): no solution."""
    f = _solver(which)
    M, r, beta, B = _case(vals)
    if abs(_det2(M)) < 0.05 * max(1.0, float(np.sum(M * M))):
        return
    d = (1.0 + r) * (1.0 + out)
    e = M @ (d * np.array([math.cos(phi), math.sin(phi)]))
    assert _solve(f, M, B, e) == []


@pytest.mark.parametrize("which", _SOLVERS)
@pytest.mark.parametrize("delta", [1e-3, 1e-5, 1e-7])
def test_near_double_root(which, delta):
    """Circles almost tangent (``d = (1 + r)(1 ∓ δ)``): two close solutions inside, none outside."""
    f = _solver(which)
    rng = np.random.default_rng(19)
    for _ in range(20):
        M = rng.normal(size=(2, 2))
        if abs(_det2(M)) < 0.3:
            continue
        r = float(rng.uniform(0.3, 2.0))
        beta = float(rng.uniform(-math.pi, math.pi))
        B = r * M @ _rot(beta)
        phi = float(rng.uniform(-math.pi, math.pi))
        u = np.array([math.cos(phi), math.sin(phi)])
        e_in = M @ ((1.0 + r) * (1.0 - delta) * u)
        ref = _circles(M, r, beta, e_in)
        got = _solve(f, M, B, e_in)
        # the two solutions are about sqrt(delta) apart: both found when that exceeds the duplicate tolerance
        assert len(got) == 2
        for t1, t2 in ref:
            assert min(_adist(t1, a) + _adist(t2, b) for a, b in got) < 1e-6
        e_out = M @ ((1.0 + r) * (1.0 + delta) * u)
        assert _solve(f, M, B, e_out) == []


@pytest.mark.parametrize("which", _SOLVERS)
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(a=st.lists(st.floats(-3.0, 3.0), min_size=8, max_size=8), t1=st.floats(-math.pi, math.pi),
       t2=st.floats(-math.pi, math.pi))
def test_general_system(which, a, t1, t2):
    """Random A, B and ``e`` from known angles: every returned pair meets the equations, no two repeat, and
    the generating pair is among them when the system is well conditioned there."""
    f = _solver(which)
    A = np.array(a[:4]).reshape(2, 2)
    B = np.array(a[4:]).reshape(2, 2)
    e = A @ [math.cos(t1), math.sin(t1)] + B @ [math.cos(t2), math.sin(t2)]
    scale = max(np.linalg.norm(A[0]) + np.linalg.norm(B[0]), np.linalg.norm(A[1]) + np.linalg.norm(B[1]))
    got = _solve(f, A, B, e)
    for x, y in got:
        assert _residual(A, B, e, x, y) < 1e-8 * (1.0 + scale)
    for i in range(len(got)):
        for j in range(i):
            assert _adist(got[i][0], got[j][0]) + _adist(got[i][1], got[j][1]) > 1e-8
    J = np.column_stack([A @ [-math.sin(t1), math.cos(t1)], B @ [-math.sin(t2), math.cos(t2)]])
    na = np.linalg.norm(A)
    nb = np.linalg.norm(B)
    wellcond = (min(na, nb) > 0.1 and abs(_det2(J)) > 0.05 * (na * nb)
                and max(abs(_det2(A)) / na ** 2, abs(_det2(B)) / nb ** 2) > 0.05
                and min(np.linalg.norm(A[0]) + np.linalg.norm(B[0]),
                        np.linalg.norm(A[1]) + np.linalg.norm(B[1])) > 0.1)
    if wellcond:
        assert min((_adist(t1, x) + _adist(t2, y) for x, y in got), default=1.0) < 1e-7


@settings(max_examples=300, deadline=None)
@given(t=st.floats(-math.pi, math.pi))
def test_angle_is_atan2(t):
    """The half-angle form equals ``atan2`` on the unit circle, in [−π, π] (as ``atan2``)."""
    c = math.cos(t)
    s = math.sin(t)
    a = K._angle(c, s)
    assert -math.pi <= a <= math.pi
    assert _adist(a, math.atan2(s, c)) < 1e-15 * 8


def test_angle_edges():
    assert K._angle(-1.0, 0.0) == math.pi
    assert K._angle(1.0, 0.0) == 0.0
    assert abs(K._angle(0.0, 1.0) - 0.5 * math.pi) < 1e-15
    assert abs(K._angle(0.0, -1.0) + 0.5 * math.pi) < 1e-15


@settings(max_examples=200, deadline=None)
@given(roots=st.lists(st.floats(-5.0, 5.0), min_size=3, max_size=3))
def test_cubic_max_real_roots(roots):
    """The largest root of ``(z − r1)(z − r2)(z − r3)``, built from its roots (a simple one; double ones below)."""
    top = sorted(roots)
    if top[2] - top[1] < 1e-2:
        return
    a2, a1, a0 = np.poly(roots)[1:]
    z = K._cubic_max(a2, a1, a0)
    assert abs(z - max(roots)) < 1e-6 * (1.0 + max(abs(x) for x in roots)) or \
        abs(((z + a2) * z + a1) * z + a0) < 1e-12 * (1.0 + abs(a0) + abs(a1) + abs(a2))


def _cubic_of(r1, r2, r3):
    """``(a2, a1, a0)`` of ``(z − r1)(z − r2)(z − r3)`` by Vieta's formulas."""
    return -(r1 + r2 + r3), r1 * r2 + r1 * r3 + r2 * r3, -(r1 * r2 * r3)


def test_cubic_max_exact_double_largest_root():
    """0.9, 0.9, −2 (issue 19): the closed form lands on the double root, where the cubic and its derivative
    are both rounding; a plain Newton step from there threw it to 0.9434."""
    z = K._cubic_max(*_cubic_of(0.9, 0.9, -2.0))
    assert abs(z - 0.9) < 1e-7
    z = _compiled_cubic()(*_cubic_of(0.9, 0.9, -2.0)) if _compiled_cubic() is not None else z
    assert abs(z - 0.9) < 1e-7


def _compiled_cubic():
    k = K.kernels()
    return None if k is None else k._cubic_max


@settings(max_examples=300, deadline=None)
@given(r=st.floats(-5.0, 5.0), gap=st.floats(1e-2, 8.0), near=st.sampled_from([0.0, 1e-12, 1e-9, 1e-6]))
def test_cubic_max_double_largest_root(r, gap, near):
    """A double (or nearly double, ``near`` apart) largest root ``r`` above a simple one ``r − gap``: found to
    the conditioning of a double root: rounding the coefficients (size S³, S = 1 + |r| + gap) by ε S³ moves it
    by about √(ε S³ / gap), the cubic's half second derivative there being the gap. Returning the simple root
    instead is off by the gap, far more."""
    a2, a1, a0 = _cubic_of(r, r - near, r - gap)
    z = K._cubic_max(a2, a1, a0)
    size = 1.0 + abs(r) + gap
    assert abs(z - r) < near + 1e-9 * size + 3.0 * math.sqrt(1e-15 * size ** 3 / gap)


@settings(max_examples=200, deadline=None)
@given(x=st.floats(-5.0, 5.0), y=st.floats(-5.0, 5.0), zr=st.floats(-3.0, 3.0), zi=st.floats(0.5, 3.0))
def test_cubic_max_one_real_root(x, y, zr, zi):
    """One real root and a complex pair: the real root (Cardano branch)."""
    del y
    a2, a1, a0 = np.real(np.poly([x, complex(zr, zi), complex(zr, -zi)]))[1:]
    z = K._cubic_max(a2, a1, a0)
    assert abs(z - x) < 1e-9 * (1.0 + abs(x) + abs(zr) + zi)


@settings(max_examples=200, deadline=None)
@given(rs=st.lists(st.floats(-4.0, 4.0), min_size=2, max_size=2), zr=st.floats(-3.0, 3.0),
       zi=st.floats(0.1, 3.0), lead=st.floats(0.5, 4.0))
def test_quartic_two_real(rs, zr, zi, lead):
    """Two real roots and a complex pair, built from the roots: the real ones are found to 1e-9 and the
    complex pair keeps its imaginary parts."""
    coef = lead * np.real(np.poly([rs[0], rs[1], complex(zr, zi), complex(zr, -zi)]))
    out = K._quartic4(*coef)
    re = [out[2 * i] for i in range(4)]
    im = [out[2 * i + 1] for i in range(4)]
    real = sorted(r for r, i in zip(re, im) if abs(i) < 1e-9)
    sep = abs(rs[0] - rs[1])
    if sep > 1e-3:
        assert len(real) == 2
        for want, have in zip(sorted(rs), real):
            assert abs(want - have) < 1e-8 * (1.0 + abs(want)) / min(1.0, sep)
    assert sorted(abs(i) for i in im)[-1] == pytest.approx(zi, rel=1e-6, abs=1e-6)


def test_newton_step_off_to_overflow_is_refused_without_a_warning():
    """A Newton step of the quartic polish where the slope is nearly 0 would jump to 1e300, where the quartic
    overflows (the plain functions, run with NumPy scalars, warned of it): the step is refused and ``t`` kept,
    compiled and plain alike, with no warning."""
    import warnings

    from armkit.ik.geometric import _kernels as kk

    K = kk.kernels()
    b, c, d, e = (np.float64(v) for v in (0.0, 0.0, 1e-300, 1.0))   # t⁴ + 1e-300 t + 1 from t = 0: f = 1, f' ~ 0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert kk._newton4(np.float64(0.0), b, c, d, e) == 0.0
    if K is not None:
        assert K._newton4(0.0, 0.0, 0.0, 1e-300, 1.0) == 0.0


def _count_margin(f, A, B, e):
    T1 = np.zeros(4)
    T2 = np.zeros(4)
    return f(A[0, 0], A[0, 1], B[0, 0], B[0, 1], e[0], A[1, 0], A[1, 1], B[1, 0], B[1, 1], e[1], T1, T2, None)


@pytest.mark.parametrize("which", _SOLVERS)
@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(seed=st.integers(0, 2**31 - 1))
def test_the_margin_closes_where_two_solutions_appear(which, seed):
    """The margin (how near a complex pair of the quartic is to turning real, what the 1-D search watches for
    branches born and dying between two samples) goes to 0 where two more solutions appear. Along
    ``e(s) = s e1`` the count is found to change by 2 at ``s*`` (by bisection on the count alone); on the side
    with fewer solutions the margin is small next to ``s*`` and shrinks towards it (like the square root of the
    distance), and it is ``inf`` wherever there are 4 solutions (no complex root left)."""
    f = _solver(which)
    rng = np.random.default_rng(seed)
    A, B = rng.normal(size=(2, 2)), rng.normal(size=(2, 2))
    e1 = rng.normal(size=2)
    e1 /= np.linalg.norm(e1)
    s = np.linspace(0.0, 3.0 * (np.abs(A).sum() + np.abs(B).sum()), 600)
    counts = [_count_margin(f, A, B, si * e1) for si in s]
    for c, mg in counts:
        if c == 4:
            assert mg == math.inf
    steps = [i for i in range(len(s) - 1) if abs(counts[i + 1][0] - counts[i][0]) == 2]
    if not steps:
        return
    i = steps[0]
    few = min(counts[i][0], counts[i + 1][0])
    side = -1.0 if counts[i][0] == few else 1.0      # the fewer solutions before s* (-1) or after it (+1)
    lo, hi = s[i], s[i + 1]                            # counts[lo side] != counts[hi side]
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if _count_margin(f, A, B, mid * e1)[0] == counts[i][0]:
            lo = mid
        else:
            hi = mid
    edge = lo if side < 0 else hi
    h = s[1] - s[0]
    far = _count_margin(f, A, B, (edge + side * 1e-3 * h) * e1)
    near = _count_margin(f, A, B, (edge + side * 1e-9 * h) * e1)
    if far[0] != few or near[0] != few:
        return          # another change of count that close: not this test's case
    assert near[1] < far[1]
    assert near[1] < 1e-3
