"""A write killed outright (SIGKILL) leaves a hidden temporary file; the next write of that path removes it."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from armkit._io import atomic_write, clean_stale

KILLED = """
import sys, time
from armkit._io import atomic_path
with atomic_path(sys.argv[1]) as tmp:
    tmp.write_text("half")
    print(tmp, flush=True)
    time.sleep(60)
"""


def test_a_killed_write_is_cleaned_by_the_next_write(tmp_path: Path) -> None:
    out = tmp_path / "picture.png"
    proc = subprocess.Popen([sys.executable, "-c", KILLED, str(out)], stdout=subprocess.PIPE, text=True)
    assert proc.stdout is not None
    tmp = Path(proc.stdout.readline().strip())
    assert tmp.exists() and tmp.name.startswith(f".picture.{proc.pid}.")
    assert clean_stale(out) == 0                          # its writer is alive: kept
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert tmp.exists() and not out.exists()              # what SIGKILL leaves
    other = tmp_path / ".notes.123.abcdefgh.tmp.png"      # another output's file, and a file of the user
    other.write_text("keep")
    (tmp_path / "mine.png").write_text("keep")
    with pytest.warns(UserWarning, match="interrupted write"):
        atomic_write(out, b"whole")
    assert not tmp.exists() and out.read_bytes() == b"whole"
    assert other.read_text() == "keep" and (tmp_path / "mine.png").read_text() == "keep"


def test_a_running_write_in_another_process_keeps_its_file(tmp_path: Path) -> None:
    out = tmp_path / "a.txt"
    live = tmp_path / f".a.{os.getppid()}.abcdefgh.tmp.txt"     # our parent is alive
    live.write_text("in progress")
    atomic_write(out, "x")
    assert live.exists()
    time.sleep(0)
