"""``armkit._jit_shaped.shaped``: the compiled kernels' reshape without Numba's run-time call gives the view
``reshape`` gives (same numbers, same memory, writes seen through it), for 1-D pieces of any stride and
C-contiguous arrays, in functions compiled with and without reference counts; a wrong size raises as ``reshape``."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

numba = pytest.importorskip("numba")

from armkit._jit_shaped import shaped  # noqa: E402


@numba.njit(cache=False)
def _piece2(w, a, step, d0, d1):
    return shaped(w[a::step][:d0 * d1], (d0, d1))


@numba.njit(cache=False)
def _piece3(w, a, d0, d1, d2):
    return shaped(w[a:a + d0 * d1 * d2], (d0, d1, d2))


@numba.njit(cache=False)
def _flat(W):
    return shaped(W, (W.size,))


@numba.njit(cache=False, _nrt=False)
def _copy_through(w, out):
    """No reference counts (the one-call kernels' flags): read and write through the view."""
    v = shaped(w[1:1 + out.size], out.shape)
    for i in range(out.shape[0]):
        for j in range(out.shape[1]):
            out[i, j] = v[i, j]
    v[0, 0] = -1.0
    return 0


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 5), st.integers(1, 5), st.integers(0, 7), st.integers(1, 3))
def test_pieces_of_a_vector_are_reshape(d0, d1, a, step):
    w = np.arange(200.0)
    got = _piece2(w, a, step, d0, d1)
    want = w[a::step][:d0 * d1].reshape(d0, d1)
    assert got.shape == want.shape
    assert all(g == s for g, s, d in zip(got.strides, want.strides, want.shape) if d > 1)   # (a length-1 axis:
    # any stride; NumPy's choice differs)
    np.testing.assert_array_equal(got, want)
    got[-1, -1] = -5.0   # a view of w, not a copy
    assert w[a + step * (d0 * d1 - 1)] == -5.0


@settings(max_examples=30, deadline=None)
@given(st.integers(1, 4), st.integers(1, 4), st.integers(1, 4), st.integers(0, 9))
def test_three_dimensions(d0, d1, d2, a):
    w = np.arange(100.0)
    np.testing.assert_array_equal(_piece3(w, a, d0, d1, d2), w[a:a + d0 * d1 * d2].reshape(d0, d1, d2))


def test_c_contiguous_array_flattened_and_bools_and_ints():
    W = np.arange(12.0).reshape(3, 4)
    f = _flat(W)
    np.testing.assert_array_equal(f, W.ravel())
    f[5] = 99.0
    assert W[1, 1] == 99.0
    B = np.array([[True, False], [False, True]])
    np.testing.assert_array_equal(_flat(B), B.ravel())
    np.testing.assert_array_equal(_flat(np.arange(6).reshape(2, 3)), np.arange(6))


def test_without_reference_counts():
    w = np.arange(30.0)
    out = np.zeros((3, 4))
    _copy_through(w, out)
    np.testing.assert_array_equal(out, np.arange(1.0, 13.0).reshape(3, 4))
    assert w[1] == -1.0


def test_wrong_size_raises_as_reshape():
    w = np.arange(10.0)
    with pytest.raises(ValueError, match="total size"):
        _piece3(w, 0, 2, 2, 2 + 1)   # 12 of a 10-long vector: the slice has 10
    with pytest.raises(ValueError):
        w[0:10].reshape(2, 2, 3)


def test_fortran_order_is_refused_at_compile_time():
    @numba.njit(cache=False)
    def f(W):
        return shaped(W, (W.size,))

    with pytest.raises(numba.core.errors.TypingError):
        f(np.asfortranarray(np.arange(6.0).reshape(2, 3)))
