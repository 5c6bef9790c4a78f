"""One on-disk cache of symbolic derivations for the whole test session (each robot is derived once)."""

from __future__ import annotations

import pytest


@pytest.fixture(scope="session", autouse=True)
def _symbolic_cache(tmp_path_factory):
    mp = pytest.MonkeyPatch()
    mp.setenv("ARMKIT_CACHE_DIR", str(tmp_path_factory.mktemp("armkit-cache")))
    yield
    mp.undo()
