"""Fixtures of the browser tests: one headless chromium for the whole view suite.

Chromium is Debian's (``/usr/bin/chromium``, installed by ``make test`` with apt), driven by
Playwright. Where it cannot start, the tests fail under CI (``CI`` set) with a message on how
to install it, and are skipped elsewhere with the same message.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import Any, Iterator

import pytest

sys.path.insert(0, str(Path(__file__).parent))

from _browser import INSTALL_HINT, browser_context  # noqa: E402

DOCS_IMG = Path(__file__).resolve().parents[3] / "docs" / "img"


def pytest_configure(config: Any) -> None:
    config.addinivalue_line("markers", "browser: drives headless chromium through Playwright (tests/viz/view)")


@pytest.fixture(scope="session")
def browser() -> Iterator[Any]:
    try:
        # antialiasing only for the docs' pictures (`make pictures`): the tests' own runs draw without it (cheaper)
        cm = browser_context(antialiasing=os.environ.get("ARMKIT_UPDATE_PICTURES") == "1")
        ctx = cm.__enter__()
    except Exception as exc:  # noqa: BLE001 - any failure to start the browser gets the install hint
        msg = INSTALL_HINT.format(why=f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}")
        if os.environ.get("CI"):
            pytest.fail(msg, pytrace=False)
        pytest.skip(msg)
    try:
        yield ctx
    finally:
        cm.__exit__(None, None, None)


@pytest.fixture
def docs_img(tmp_path_factory) -> Path:
    """Where the screenshots go: a temporary folder, so that tests never rewrite tracked files;
    ``make pictures`` (ARMKIT_UPDATE_PICTURES=1) sends them to docs/img to refresh the docs."""
    import os

    if os.environ.get("ARMKIT_UPDATE_PICTURES") == "1":
        DOCS_IMG.mkdir(parents=True, exist_ok=True)
        return DOCS_IMG
    return tmp_path_factory.mktemp("screenshots")
