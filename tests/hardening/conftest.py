"""Fixtures of the hardening tests (issue 10)."""

from __future__ import annotations

from pathlib import Path

import pytest

from hardening_helpers import HOSTILE_TOML


@pytest.fixture
def hostile_robot(tmp_path: Path) -> Path:
    p = tmp_path / "hostile.toml"
    p.write_text(HOSTILE_TOML, encoding="utf-8")
    return p
