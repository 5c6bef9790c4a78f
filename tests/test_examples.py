"""Every script in examples/ runs headless and exits 0 (they are documentation that must work): the numbered
guide examples and the ones an issue names (examples/so101_lerobot.py)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = sorted((Path(__file__).parent.parent / "examples").glob("*.py"))


@pytest.mark.parametrize("script", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_example_runs(script, tmp_path):
    env = dict(os.environ, MPLBACKEND="Agg")
    proc = subprocess.run([sys.executable, str(script), str(tmp_path / "out")], capture_output=True, text=True,
                          env=env, timeout=300, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert "Traceback" not in proc.stderr
    stray = [p.name for p in tmp_path.iterdir() if p.name != "out"]   # outputs go into the folder given
    assert not stray, stray


GUIDES = sorted((Path(__file__).parent.parent / "docs").glob("*.md"))


@pytest.mark.parametrize("guide", GUIDES, ids=[p.stem for p in GUIDES])
def test_every_guide_links_an_example_that_exists(guide):
    import re

    linked = re.findall(r"examples/((?:[0-9][0-9]_)?\w+\.py)", guide.read_text(encoding="utf-8"))
    assert linked, f"{guide.name} has no 'Example: examples/NN_name.py' (or examples/name.py) line"
    for name in linked:
        assert (guide.parent.parent / "examples" / name).is_file(), name
