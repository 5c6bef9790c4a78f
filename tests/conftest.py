"""Shared test set-up: headless plotting, a CI hypothesis profile, fixtures found relative to this file."""

from __future__ import annotations

import os
from pathlib import Path

os.environ.setdefault("MPLBACKEND", "Agg")
# compile Numba kernels in the test process on first use (no background warm-up process), so that the tests
# that compare the NumPy and Numba back ends always run both (docs/performance.md, "First use")
os.environ.setdefault("ARMKIT_JIT", "wait")

import numpy as np
import pytest
from hypothesis import HealthCheck, settings

# CI (CI=true) replays the same examples every run, so a landing never depends on luck; locally
# hypothesis keeps exploring new examples.
settings.register_profile("armkit", max_examples=60, deadline=None, derandomize=bool(os.environ.get("CI")),
                          suppress_health_check=[HealthCheck.too_slow])
settings.load_profile("armkit")

DATA = Path(__file__).parent / "data"


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20261121)


@pytest.fixture(scope="session", autouse=True)
def _symbolic_cache(tmp_path_factory):
    """One on-disk cache of symbolic derivations for the whole test session (each robot is derived once)."""
    mp = pytest.MonkeyPatch()
    mp.setenv("ARMKIT_CACHE_DIR", str(tmp_path_factory.mktemp("armkit-cache")))
    yield
    mp.undo()
