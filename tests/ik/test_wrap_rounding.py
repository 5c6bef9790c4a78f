"""The compiled wrap of a branch's angles (``_wrap_one``, every closed-form kernel) against the NumPy one
(``wrap_to_limits``, the NumPy back end and the batched path): the same values to the bit, zeros' signs too, on every
path of the wrap (the turn nearest ``q0``, the turn just inside a limit, the turn nearest the middle of limits no
turn reaches). Its rounding (``_rint``, half to even) is ``np.round``'s, also at exact halves, past 2**52 and 2**63
(where the ``math.floor`` it replaced on 2026-12-07 returned an integer that overflowed), and for inf and nan."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("numba")

import armkit  # noqa: E402
from armkit.ik.analytic import wrap_to_limits  # noqa: E402
from armkit.ik.analytic._jit import _rint, _wrap_one  # noqa: E402


def _same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    return bool(np.array_equal(a, b, equal_nan=True) and np.array_equal(np.signbit(a), np.signbit(b)))


def test_round_half_to_even_is_numpys_everywhere():
    halves = np.arange(-12, 12) + 0.5
    edges = [np.nextafter(0.5, 0.0), np.nextafter(0.5, 1.0), -np.nextafter(0.5, 0.0), 0.0, -0.0, -0.3, 0.3,
             2.0 ** 52 + 1.0, 2.0 ** 52 - 0.5, 4503599627370495.5, 2.0 ** 63, -(2.0 ** 63) * 3.0, 1e300, -1e300,
             np.inf, -np.inf, np.nan, 5e-324]
    rng = np.random.default_rng(7)
    x = np.concatenate([halves, edges, rng.uniform(-1e3, 1e3, 2000), rng.normal(size=2000)])
    got = np.array([_rint(v) for v in x])
    assert _same_bits(got, np.round(x))


@pytest.mark.parametrize("limits", ["puma560", "none", "narrow", "mixed"])
def test_the_compiled_wrap_is_the_numpy_wrap(limits):
    n = 6
    if limits == "puma560":
        puma = armkit.load("puma560")
        lower, upper = puma.lower, puma.upper
    elif limits == "none":
        lower, upper = np.full(n, -np.inf), np.full(n, np.inf)
    elif limits == "narrow":       # intervals no turn of most values reaches: the middle's nearest turn
        lower = np.array([0.1, -0.2, 1.0, 2.0, -3.0, 0.0])
        upper = lower + np.array([0.2, 0.05, 0.3, 0.01, 0.5, 1e-9])
    else:                          # one side open, a prismatic joint
        lower = np.array([-np.inf, -1.0, 0.0, -4.0, -np.inf, -0.5])
        upper = np.array([1.0, np.inf, 7.0, 4.0, np.inf, 0.5])
    revolute = np.array([True, True, True, True, True, limits != "mixed"])
    rng = np.random.default_rng(11)
    q = np.concatenate([rng.uniform(-20.0, 20.0, (400, n)), rng.uniform(-np.pi, np.pi, (400, n)),
                        np.zeros((1, n)), -np.zeros((1, n)), np.tile(lower, (1, 1)), np.tile(upper, (1, 1))])
    q = np.where(np.isfinite(q), q, 0.0)
    q0 = rng.uniform(-10.0, 10.0, (len(q), n))
    q0[:2] = 0.0
    want = wrap_to_limits(q, q0, lower, upper, revolute)
    got = np.array([[_wrap_one(q[i, j], q0[i, j], lower[j] - 1e-12, upper[j] + 1e-12, bool(revolute[j]))
                     for j in range(n)] for i in range(len(q))])
    assert _same_bits(got, want)
    # every path was taken: inside at once, moved inside, and left outside (the middle's turn)
    lo, hi = lower - 1e-12, upper + 1e-12
    inside = (want >= lo) & (want <= hi)
    near = q + 2 * np.pi * np.round((q0 - q) / (2 * np.pi))
    if limits in ("puma560", "narrow"):
        assert inside.any() and (~inside).any() and (inside & ~((near >= lo) & (near <= hi))).any()


def test_values_near_the_start_take_no_turn_to_the_bit():
    """Values near the start, where the nearest turn is none and the sum ``v + 2 pi * rint(...)`` adds a zero: the
    same bits as the NumPy wrap, zeros' signs too (``-0.0`` against ``+0.0`` and ``-0.0`` starts, ``v`` equal to
    ``q0``), on both sides of a 3 rad step, and for values a tiny step from the start. (A shortcut for values within
    3 rad of ``q0``, adding a zero of the sign of ``q0 - v`` instead of dividing and rounding, was tried on
    2026-12-07 against this test and dropped: no faster in a batch.)"""
    rng = np.random.default_rng(23)
    q0 = np.concatenate([rng.uniform(-4.0, 4.0, 3000), [0.0, -0.0, 0.0, -0.0, 1.0, -1.0, 2.5, 0.0, 0.0, 0.0]])
    step = np.concatenate([rng.uniform(-3.2, 3.2, 3000), [-0.0, 0.0, 0.0, -0.0, 0.0, -0.0, 0.0, 3.0, -3.0, 5e-324]])
    v = q0 - step   # q0 - v: the step, up to rounding
    v[-10:] = [-0.0, 0.0, 0.0, -0.0, 1.0, -1.0, 2.5, -3.0, 3.0, -5e-324]
    edge = np.array([np.nextafter(3.0, 0.0), 3.0, np.nextafter(3.0, 4.0)])
    v = np.concatenate([v, -edge, edge])
    q0 = np.concatenate([q0, np.zeros(6)])
    for lo, hi in ((-np.inf, np.inf), (-np.pi, np.pi), (-1.0, 1.0)):
        want = wrap_to_limits(v[:, None], q0[:, None], np.full(1, lo), np.full(1, hi), np.array([True]))[:, 0]
        got = np.array([_wrap_one(v[i], q0[i], lo - 1e-12, hi + 1e-12, True) for i in range(len(v))])
        assert _same_bits(got, want)
    near = np.abs(q0 - v) < 3.0
    assert near.sum() > 2000 and (~near).sum() > 100   # values within 3 rad of the start and beyond
