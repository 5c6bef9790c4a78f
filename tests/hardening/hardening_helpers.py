"""Shared pieces of the hardening tests (issue 10): a CLI runner and a hostile robot file."""

from __future__ import annotations

from pathlib import Path

from typer.testing import CliRunner

from armkit.cli import app

runner = CliRunner()

HOSTILE_TOML = '''name = "[/]arm\\u001b[31m[bold]"
description = "[red]not red[/red] and [/] and \\u001b]0;title\\u0007"
source = "[link=http://x]click[/link]"
convention = "standard"
unit = "m"
link_names = ["[/]base", "[b]l1", "l2\\u001b[2J"]

[[joints]]
name = "[/]yaw"
type = "revolute"
a = 0.5
limits = [-180, 180]

[[joints]]
name = "[bold]elbow\\u001b[31m"
type = "revolute"
a = 0.4
limits = [-180, 180]
'''


def invoke(*args: str, env: dict | None = None):
    """Run the CLI in-process; return (exit code, stdout + stderr, the exception if it was not SystemExit)."""
    res = runner.invoke(app, [str(a) for a in args], env={"COLUMNS": "250", **(env or {})})
    exc = res.exception if not isinstance(res.exception, SystemExit) else None
    return res.exit_code, res.output, exc
