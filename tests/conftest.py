"""Shared test set-up: headless plotting, a CI hypothesis profile, fixtures found relative to this file."""

from __future__ import annotations

import os
import shutil
import tempfile
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
_SHARED_CACHE = "armkit_symbolic_cache"


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20261121)


def pytest_configure(config: pytest.Config) -> None:
    """The controller of a ``pytest -n N`` run makes one symbolic cache for all its workers (see below)."""
    if not hasattr(config, "workerinput"):
        config.stash[_cache_key] = tempfile.mkdtemp(prefix="armkit-test-cache-")


def pytest_unconfigure(config: pytest.Config) -> None:
    folder = config.stash.get(_cache_key, None)
    if folder is not None:
        shutil.rmtree(folder, ignore_errors=True)


@pytest.hookimpl(optionalhook=True)
def pytest_configure_node(node) -> None:  # pytest-xdist's hook, called in the controller for each worker
    node.workerinput[_SHARED_CACHE] = node.config.stash[_cache_key]


_cache_key = pytest.StashKey[str]()


@pytest.fixture(scope="session", autouse=True)
def _symbolic_cache(request: pytest.FixtureRequest):
    """One on-disk cache of symbolic derivations for the whole test run (each robot is derived once per run).

    It starts empty (every derivation runs in the run) and is shared by the xdist workers, so that a robot
    derived by one worker (puma560 takes sympy ~10 s) is read by the other (the cache writes atomically);
    subprocesses (README commands, examples) inherit it through ``ARMKIT_CACHE_DIR``.
    """
    config = request.config
    folder = getattr(config, "workerinput", {}).get(_SHARED_CACHE) or config.stash[_cache_key]
    mp = pytest.MonkeyPatch()
    mp.setenv("ARMKIT_CACHE_DIR", folder)
    yield
    mp.undo()
