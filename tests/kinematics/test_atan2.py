"""armkit's compiled ``atan2`` (``kinematics._jit._atan2``, used by the closed-form kernels and the geometric
solvers): its coefficients are the Chebyshev fit its comment names (fitted again here with mpmath), and its values
are within 1.5 ulp of the exact angle (mpmath at 40 digits), within 2 ulp of libm's, with libm's signs and
special values (zeros, axes, huge and tiny ratios) and odd in ``y`` to the bit."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

numba = pytest.importorskip("numba")
mp = pytest.importorskip("mpmath")

from armkit.kinematics import _jit as K  # noqa: E402


@numba.njit(cache=False)
def _many(Y, X, out):
    for i in range(Y.shape[0]):
        out[i] = K._atan2(Y[i], X[i])


def _ulps(got, exact):
    return abs(mp.mpf(got) - exact) / mp.mpf(np.spacing(abs(float(exact))) if exact != 0 else 5e-324)


def test_coefficients_are_the_chebyshev_fit():
    mp.mp.dps = 50
    b = mp.tan(mp.pi / 8) ** 2

    def f(z):   # (atan(√z) - √z) / z^(3/2), its limit -1/3 at 0
        if z == 0:
            return mp.mpf(-1) / 3
        s = mp.sqrt(z)
        return (mp.atan(s) - s) / (z * s)

    poly, err = mp.chebyfit(f, [0, b], 11, error=True)
    ours = [K._A0, K._A1, K._A2, K._A3, K._A4, K._A5, K._A6, K._A7, K._A8, K._A9, K._A10]
    assert ours == [float(c) for c in poly[::-1]]
    assert float(err * b) < 1e-17          # relative to atan(u): below a tenth of an ulp
    assert K._TAN_PI8 == float(mp.tan(mp.pi / 8))
    for hi, lo, c in ((K._PI4_HI, K._PI4_LO, mp.pi / 4), (K._PI2_HI, K._PI2_LO, mp.pi / 2),
                      (K._PI_HI, K._PI_LO, mp.pi)):
        assert hi == float(c) and abs(mp.mpf(hi) + mp.mpf(lo) - c) < mp.mpf(1e-32)


def test_random_pairs_against_mpmath_and_libm():
    rng = np.random.default_rng(2026)
    n = 200_000
    Y = rng.normal(size=n) * np.exp(rng.uniform(-8, 8, n))
    X = rng.normal(size=n) * np.exp(rng.uniform(-8, 8, n))
    out = np.empty(n)
    _many(Y, X, out)
    libm = np.arctan2(Y, X)
    assert (np.abs(out - libm) <= 2 * np.spacing(np.abs(libm))).all()
    mp.mp.dps = 40
    worst = max(_ulps(out[i], mp.atan2(mp.mpf(Y[i]), mp.mpf(X[i]))) for i in range(0, n, 97))
    assert worst <= 1.5


@settings(max_examples=300, deadline=None)
@given(st.floats(-1e30, 1e30), st.floats(-1e30, 1e30))
def test_odd_in_y_and_close_to_libm(y, x):
    a = K._atan2.py_func(y, x)
    assert K._atan2.py_func(-y, x) == -a and math.copysign(1.0, K._atan2.py_func(-y, x)) == -math.copysign(1.0, a)
    ref = math.atan2(y, x)
    assert abs(a - ref) <= 2 * np.spacing(abs(ref)) or (a == ref)
    assert -math.pi <= a <= math.pi


def test_special_values_as_libm():
    vals = [0.0, -0.0, 1.0, -1.0, 1e-300, -1e-300, 5e-324, -5e-324, 1e300, -1e300, 3.0, -2.5]
    for y in vals:
        for x in vals:
            got, ref = K._atan2.py_func(y, x), math.atan2(y, x)
            assert abs(got - ref) <= 2 * np.spacing(abs(ref)), (y, x, got, ref)
            assert math.copysign(1.0, got) == math.copysign(1.0, ref), (y, x)
    out = np.empty(1)
    _many(np.array([0.0]), np.array([-0.0]), out)   # compiled: the same as the Python function
    assert out[0] == math.pi
