"""The README runs by copy-paste, top to bottom: every command and every Python block in it.

Convention (what a README writer must keep):

* Shell commands live in fenced blocks marked ```console, ```bash or ```sh. Each non-blank line of such a block
  is one command, typed as shown (a leading ``$ `` is dropped); a ``# ...`` comment after it is fine (bash
  ignores it). Blocks without one of these markers (or ```text) are not run.
* A command's exit code must be 0, unless its comment says ``exit N`` (``armkit ik fighter 500 0 0  #
  unreachable: exit 1``): then it must be N. No command may print a Python traceback or a ``warning:`` line,
  and the commands of :data:`PRINTS` must print what the README's comment says they print.
* Lines that are not ``armkit`` commands (``make``, ``pip``, ``git clone``) are skipped: :data:`SKIPPED_PROGRAMS`
  says why for each; any other program fails this test, so that a new kind of line is a decision. ``armkit``
  commands that wait for the user (:data:`SKIPPED_COMMANDS`) are skipped too, each with its reason.
* ```python blocks run too, each in a fresh interpreter, after the shell commands.

How the commands run: in a temporary folder (the current folder of every command, so that the pictures
and files they write, ``-o arm.png``, ``> puma_fk.py``, land there), in which ``examples`` is a link to the
repository's ``examples/`` folder, so that ``examples/my_arm.toml`` reads as it does from the repository's
root in a fresh clone. ``armkit`` is the command installed next to this interpreter (``.venv/bin/armkit``),
first on ``PATH``; each line is one test case (``pytest -n`` spreads them over its workers), run through bash
(redirections work as typed); no line reads a file that another writes, so the cases need no order.

``example-robot-data:...`` lines need the example-robot-data package (a test extra); they are skipped when it
is missing.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
SHELL_BLOCKS = ("console", "bash", "sh", "shell")

PRINTS = {
    # what the README's comment says a command prints (command line as in the README -> text in its output)
    "armkit --version": "armkit ",
    "armkit fk fighter 30 45 60 --deg": "end point: (24.861, 14.353, 187.181) mm",
    "armkit fk examples/my_arm.toml 10 20 30 --deg": "end point: (38.961, 6.870, 39.702) cm",
    "armkit ik example-robot-data:ur5 0.4 0.1 0.3 --rpy 180 0 0 --deg": "8 of 8 branches",
    "armkit ik fighter 500 0 0": "the arm reaches 177.2 mm (outer) and 22.8 mm (inner)",
}

SKIPPED_PROGRAMS = {
    "make": "builds the virtual environment and runs the whole suite or the demo (make test runs this test)",
    "pip": "installs packages: needs the network, and this test runs inside an installed environment already",
    "git": "git clone needs the network; the test runs in the clone",
    ".": "activating the virtual environment: the test puts its armkit first on PATH instead",
    "source": "activating the virtual environment: the test puts its armkit first on PATH instead",
}
SKIPPED_COMMANDS = {
    "armkit view": "serves the browser view until Ctrl-C (tests/viz/view drives it in headless chromium)",
    "armkit shell": "an interactive shell that waits for the user (tests/cli/test_shell_script.py scripts it)",
}


def blocks(text: str) -> list[tuple[str, str]]:
    """``(language, body)`` of every fenced block of ``text``, in order."""
    return [(m.group(1).strip().lower(), m.group(2))
            for m in re.finditer(r"^```([^\n`]*)\n(.*?)^```\s*$", text, re.M | re.S)]


def commands(text: str) -> list[tuple[str, int]]:
    """Every shell line of the README's console/bash/sh blocks with the exit code its comment documents."""
    out = []
    for lang, body in blocks(text):
        if lang not in SHELL_BLOCKS:
            continue
        for line in body.splitlines():
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            line = line[2:] if line.startswith("$ ") else line
            m = re.search(r"#.*\bexit (\d+)\b", line)
            out.append((line, int(m.group(1)) if m else 0))
    return out


def skip_reason(line: str) -> str | None:
    """Why ``line`` is not run, or None; a program that is neither armkit nor listed fails the test."""
    words = line.split()
    for start, reason in SKIPPED_COMMANDS.items():
        if line == start or line.startswith(start + " "):
            return reason
    if words[0] == "armkit":
        return None
    assert words[0] in SKIPPED_PROGRAMS, f"README runs {words[0]!r}: add it to SKIPPED_PROGRAMS with a reason, " \
                                         "or write the line as an armkit command"
    return SKIPPED_PROGRAMS[words[0]]


def written(line: str) -> list[str]:
    """The files a command line writes (``-o FILE``, ``--output FILE``, ``> FILE``), its comment left out."""
    return re.findall(r"(?:^|\s)(?:-o|--output|>)\s+(\S+)", line.split(" #")[0])


def _armkit_bin() -> Path:
    here = Path(sys.executable).parent / ("armkit.exe" if os.name == "nt" else "armkit")
    if here.is_file():
        return here.parent
    found = shutil.which("armkit")
    if found is None:
        pytest.skip("the armkit command is not installed (pip install -e .)")
    return Path(found).parent


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    """The folder every README command runs in: ``examples`` links to the repository's examples."""
    folder = tmp_path_factory.mktemp("readme")
    (folder / "examples").symlink_to(ROOT / "examples", target_is_directory=True)
    return folder


def _env(workdir: Path) -> dict[str, str]:
    env = dict(os.environ, MPLBACKEND="Agg", COLUMNS="120")
    env["PATH"] = f"{_armkit_bin()}{os.pathsep}{env.get('PATH', '')}"
    env.pop("ARMKIT_LANG", None)
    return env


def test_the_convention_finds_the_readme_commands():
    found = [line for line, _ in commands(README.read_text(encoding="utf-8"))]
    assert any(line.startswith("armkit fk examples/my_arm.toml") for line in found)
    assert sum(line.startswith("armkit ") for line in found) >= 25
    assert [code for line, code in commands(README.read_text(encoding="utf-8"))
            if line.startswith("armkit ik fighter 500 0 0")] == [1]
    assert (ROOT / "examples" / "my_arm.toml").is_file()
    assert set(PRINTS) <= {line.split(" #")[0].strip() for line in found}, "PRINTS names a line the README lost"


RUN = [(line, code) for line, code in commands(README.read_text(encoding="utf-8")) if skip_reason(line) is None]


def test_every_runnable_readme_command_is_a_case_and_writes_its_own_file():
    """The cases below are the README's runnable lines, in order, and no line overwrites another's picture."""
    assert len(RUN) >= 25
    outputs = [name for line, _ in RUN for name in written(line)]
    assert len(outputs) == len(set(outputs)), outputs
    assert len(outputs) >= 8


@pytest.mark.parametrize("line,expected", RUN, ids=[f"{i:02d}" for i in range(len(RUN))])
def test_every_readme_command_runs(workdir, line, expected):
    """One README line per case (so that pytest -n spreads them): it runs as typed, through bash, in the folder
    shared by the module's cases; no line reads what another writes, so they need not run in order."""
    from armkit.model.erd import robots_folder

    if "example-robot-data:" in line and robots_folder() is None:
        pytest.skip("example-robot-data is a test extra (test_erd_* in tests/cli/test_first_hour.py)")
    proc = subprocess.run(["bash", "-c", line], cwd=workdir, env=_env(workdir), capture_output=True, text=True,
                          timeout=600)
    both = proc.stdout + proc.stderr
    problems = []
    if proc.returncode != expected:
        problems.append(f"exit {proc.returncode}, README says {expected}")
    if "Traceback" in both:
        problems.append("a traceback")
    if re.search(r"^\s*warning:", proc.stderr, re.M):
        problems.append("a warning")
    said = PRINTS.get(line.split(" #")[0].strip())
    if said is not None and said not in both:
        problems.append(f"does not print {said!r}")
    assert not problems, f"$ {line}\n  {', '.join(problems)}\n  {proc.stderr.strip()[-1500:]}"
    for name in written(line):                       # every picture and file the line writes is there
        assert (workdir / name).is_file() and (workdir / name).stat().st_size > 0, name


def test_readme_python_blocks_run(workdir):
    code = [body for lang, body in blocks(README.read_text(encoding="utf-8")) if lang in ("python", "py")]
    assert code
    for body in code:
        proc = subprocess.run([sys.executable, "-c", body], cwd=workdir, env=_env(workdir), capture_output=True,
                              text=True, timeout=600)
        assert proc.returncode == 0, proc.stderr[-3000:]
        assert "Traceback" not in proc.stderr


def test_the_readme_keeps_its_first_hour():
    """The quick start, its two commands and a picture stay; the benchmark tables live in docs/performance.md."""
    text = README.read_text(encoding="utf-8")
    assert "## Quick start" in text and "make demo" in text and "make test" in text
    assert re.search(r"!\[[^\]]*\]\(docs/img/[^)]+\.(png|gif)\)", text)
    tables = [line for line in text.splitlines() if line.startswith("| ---")]
    assert len(tables) <= 3, "benchmark tables go to docs/performance.md (one summary line each in the README)"
    assert "## Tables moved from the README" in (ROOT / "docs" / "performance.md").read_text(encoding="utf-8")
