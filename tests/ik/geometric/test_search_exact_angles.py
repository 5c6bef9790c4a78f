"""The 1-D searches find configurations whose searched joint sits exactly on a sample (issue 19).

The searches sample their joint at ``−π + k 2π / N``: 0, ±π/2 and ±π are samples (±π twice, at both ends of
the turn), and so are the other joints' values at branch ends often enough. A target built as FK of a
configuration with such entries puts a root of the residual exactly on a sample, where the residual is 0 up to
rounding with either sign. Two ways to miss it were found: ±π evaluated at −π and at −π + N step (≈ π) with
residuals of opposite rounding signs (the root fell between the two copies of one sample), and a root on a
sample with a second root within the same step (no sign change between the step's ends). The reference is
the generating configuration itself: it solves the target by construction.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from armkit.ik.geometric import solvers as G

from test_dense_check import two_parallel_arm   # same folder, on pytest's path
from test_solvers import random_arm

ANGLES = [0.0, math.pi, -math.pi, 0.5 * math.pi, -0.5 * math.pi, 0.25 * math.pi]
"""Joint values that land on samples of the search (N = 240 samples a turn) or on branch ends."""


def _arm(kind: str, index: int):
    g = np.random.default_rng(index)
    return random_arm(g, "ti") if kind == "ti" else two_parallel_arm(g)


def _wrapped(a: np.ndarray) -> np.ndarray:
    return (a + np.pi) % (2 * np.pi) - np.pi


@settings(max_examples=120, deadline=None, derandomize=True)
@given(kind=st.sampled_from(["ti", "tp"]), index=st.integers(0, 60),
       q=st.lists(st.sampled_from(ANGLES), min_size=6, max_size=6))
def test_generating_configuration_on_samples_is_found(kind, index, q):
    pytest.importorskip("numba")
    form = _arm(kind, index)
    q = np.array(q)
    R, p = form.fk(q)
    solve = G.two_intersecting if kind == "ti" else G.two_parallel
    sol = solve(form, R, p, jit=True)
    assert len(sol.q) and not sol.ls.any()
    assert np.abs(_wrapped(sol.q - q)).max(axis=1).min() < 1e-7


@pytest.mark.parametrize("kind, index, q", [
    ("ti", 3, (1.0, 1.0, 0.0, 0.5, -0.5, 0.0)),     # q1 = π: the two ends of the turn
    ("tp", 8, (0.0, 0.0, 0.0, 0.0, 0.0, 1.0)),      # q6 = π
    ("ti", 4, (0.0, 0.0, 0.0, 1.0, 0.0, 0.0)),      # q1 = 0 on a sample, a second root 6e-4 rad from it
])
def test_cases_missed_before(kind, index, q):
    """Targets (in units of π) the search missed before the fix."""
    pytest.importorskip("numba")
    form = _arm(kind, index)
    q = np.array(q) * math.pi
    R, p = form.fk(q)
    solve = G.two_intersecting if kind == "ti" else G.two_parallel
    sol = solve(form, R, p, jit=True)
    assert np.abs(_wrapped(sol.q - q)).max(axis=1).min() < 1e-7
