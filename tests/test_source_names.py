"""Sources are named by what they are, not by our internal document numbers.

Users do not know the numbered documents the project started from; a comment, docstring, robot
file, doc page or CLI help that cites one must name the source instead ("the club's
fighting-robot report", "the symbolic 2-link tutorial", "the homogeneous-transform seminar",
"the CCD graphics assignment", "the modified-DH lecture") or describe the thing itself.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
# "seed" + optional "s" + optional space + a three-digit number; built from parts so that this
# file does not match itself.
# (?<![a-z]) rather than \b: in a test name the underscore before the word leaves no word boundary
NUMBERED = re.compile(r"(?<![a-z])" + "se" + r"eds?[ _-]?\d{3}(?!\d)", re.IGNORECASE)
TEXT = {".py", ".md", ".toml", ".txt", ".rst", ".cfg", ".json", ".csv", ".html", ".js"}


def _files() -> list[Path]:
    out = [ROOT / "README.md"]
    for top in ("src", "docs", "examples", "tests"):
        for p in sorted((ROOT / top).rglob("*")):
            if p.is_file() and p.suffix in TEXT and ".egg-info" not in str(p) and "__pycache__" not in p.parts:
                out.append(p)
    return out


def numbered_mentions(paths: list[Path]) -> list[str]:
    hits = []
    for p in paths:
        for i, line in enumerate(p.read_text(encoding="utf-8", errors="replace").splitlines(), 1):
            if NUMBERED.search(line):
                hits.append(f"{p.relative_to(ROOT)}:{i}: {line.strip()}")
    return hits


def test_no_numbered_source_documents_in_code_docs_or_robot_files():
    hits = numbered_mentions(_files())
    assert not hits, "name the source instead of its number:\n" + "\n".join(hits)


@pytest.mark.parametrize("line", ["(" + "se" + "ed 000)", "Se" + "eds 003, 004", "se" + "ed 001's maps", "se" + "ed004"])
def test_the_check_catches_each_form(tmp_path, line):
    p = tmp_path / "x.md"
    p.write_text("A line.\n" + line + "\n")
    hits = [h for h in (NUMBERED.search(t) for t in p.read_text().splitlines()) if h]
    assert len(hits) == 1


def test_the_check_leaves_random_seeds_alone():
    for line in ["seed : int", "rng = default_rng(seed=3)", "--seed 3", "seeds[i]", "seed 3 gives"]:
        assert not NUMBERED.search(line), line
