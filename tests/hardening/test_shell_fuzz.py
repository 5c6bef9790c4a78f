"""Issue 10: a fixed-seed fuzz of the shell: thousands of hostile lines, no traceback, nothing executed.

Lines mix the shell's grammar with Rich markup, control and escape characters, format
strings, code and shell injection attempts, huge numbers and 1 MB lines. Every line must
give a status (ok, info, error, empty, exit), no exception, no escape sequence on the
terminal, and no side effect (a sentinel file that an executed line would create).
"""

from __future__ import annotations

import io
import random
import time
from pathlib import Path

from rich.console import Console

import armkit
from armkit.cli.shell import Shell

WORDS = ["theta1", "theta2", "theta3", "q", "q1", "j2", "yaw", "shoulder", "elbow", "goto", "go", "ik", "branch",
         "auto", "units", "deg", "rad", "lang", "ko", "en", "limits", "home", "show", "help", "?", "exit", "quit",
         "=", ";", ",", "[", "]", "(", ")", "#", "30", "-45.5", "1e3", "1e308", "-1e308", "nan", "inf", "0x10",
         "1_000", "°", "30deg", "0.5rad", "mm", "front/elbow-up", "elbow-down", "1" * 400]
HOSTILE = ["[/]", "[red]", "[bold]x[/bold]", "[link=file:///etc/passwd]x[/link]", "\\[", "\x1b[2J", "\x1b]0;pwn\x07",
           "\x00", "\r", "\x7f", "\u202e", "\x9b31m", "{0.__class__}", "{robot}", "%s%s%n", "$(touch {s})",
           "`touch {s}`", "__import__('os').system('touch {s}')", "exec('open(\"{s}\",\"w\")')",
           "eval('1+1')", "; rm -rf /", "| touch {s}", "{s}", "\n", "\t", "😀", "한국어", "\udcff"]


def _line(rnd: random.Random, sentinel: str) -> str:
    kind = rnd.random()
    if kind < 0.12:            # valid statements with random numbers
        a, b, c = (round(rnd.uniform(-60, 60), 2) for _ in range(3))
        return rnd.choice([f"theta1 = {a}", f"theta2 = {b}; theta1 = {c}", f"q {a} {b} {c}", f"q {a} {b}",
                           f"theta2 = {a}deg", "home", "show", f"goto {a} {b} {c}", f"[{a / 60} {b / 60}]"])
    if kind < 0.45:            # grammar-shaped
        return " ".join(rnd.choice(WORDS) for _ in range(rnd.randint(1, 7)))
    if kind < 0.8:             # grammar with hostile pieces in it
        parts = [rnd.choice(WORDS + HOSTILE) for _ in range(rnd.randint(1, 8))]
        return rnd.choice([" ", "", ";", "="]).join(parts).replace("{s}", sentinel)
    if kind < 0.95:            # random characters
        return "".join(chr(rnd.choice([rnd.randint(0, 0x7f), rnd.randint(0x80, 0x2fff)]))
                       for _ in range(rnd.randint(0, 40)))
    return rnd.choice(HOSTILE).replace("{s}", sentinel) * rnd.randint(1, 20)


def test_shell_fuzz(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    sentinel = str(tmp_path / "PWNED")
    rnd = random.Random(20261201)
    lines = [_line(rnd, sentinel) for _ in range(2500)]
    big = ["x" * 1_000_000, "q " + "1 " * 500_000, "[" * 1_000_000, "theta1 = " + "9" * 1_000_000]
    statuses: dict[str, int] = {}
    start = time.perf_counter()
    for robot, part in (("fighter", lines[:1250] + big), ("planar3", lines[1250:] + big)):
        term = io.StringIO()
        sh = Shell(armkit.load(robot), lang="en", plot="none", console=Console(file=term, force_terminal=True))
        for line in part:
            out = sh.execute(line)
            assert out.status in ("ok", "info", "error", "empty", "exit"), (line, out.status)
            statuses[out.status] = statuses.get(out.status, 0) + 1
            assert "Traceback" not in out.text
        shown = term.getvalue()
        # Rich's own styling uses CSI ... m; nothing else (clear screen, title, ...) may reach the terminal
        assert "\x1b[2J" not in shown and "\x1b]0;" not in shown and "\x07" not in shown
    assert not Path(sentinel).exists()
    assert statuses.get("ok", 0) > 150 and statuses.get("error", 0) > 1000     # the fuzz reached both sides
    assert time.perf_counter() - start < 120     # a few seconds on an idle machine


def test_shell_run_loop_with_hostile_stdin(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    term = io.StringIO()
    sh = Shell(armkit.load("planar2"), lang="ko", plot="none", console=Console(file=term))
    stdin = io.StringIO("foo [/]\n\x1b[31m\ntheta1 = 30\nq 10 20\n" + "y" * 300_000 + "\nexit; q 1 2\nquit\n")
    assert sh.run(stdin=stdin) == 0
    assert "\x1b[31m" not in term.getvalue()
