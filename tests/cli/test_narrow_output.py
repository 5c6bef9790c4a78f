"""Issue 11: tables fit an 80-column (and 60-column) terminal and never break a number across lines."""

from __future__ import annotations

import io
import re

import numpy as np
import pytest
from rich.console import Console
from typer.testing import CliRunner

import armkit
from armkit.cli import app

runner = CliRunner()
FLOAT = re.compile(r"^[-+]?\d+(\.\d+)?(e[-+]\d\d)?$")


def run(cols: int, *args: str) -> str:
    res = runner.invoke(app, list(args), env={"COLUMNS": str(cols)})
    assert res.exit_code in (0, 1), res.output
    return res.stdout


def check_lines(text: str, cols: int) -> None:
    """No line longer than ``cols``; every table cell holding a number holds a whole one; no row continues a
    number on the next line (the first cell of a continuation row is empty)."""
    for line in text.splitlines():
        assert len(line) <= cols, f"{len(line)} > {cols}: {line!r}"
        if not line.startswith("│"):
            continue
        cells = [c.strip() for c in line.strip("│").split("│")]
        if cells[0] == "":      # a wrapped row: it must not carry pieces of numbers
            assert not any(re.fullmatch(r"[-+\d.e]+", c) for c in cells[1:]), line
        for c in cells:
            if re.fullmatch(r"[-+\d.e]+", c):
                assert FLOAT.match(c), f"broken number {c!r} in {line!r}"


IK_CASES = [("fighter", "24.861", "14.353", "187.181"),
            ("puma560", "0.4", "0.1", "0.5", "--rpy", "180", "0", "0", "--deg"),
            ("ur5", "0.4", "0.1", "0.5", "--rpy", "180", "0", "0", "--deg"),
            ("planar2", "1.2", "0.3"),
            ("panda", "0.4", "0.1", "0.5", "--method", "lm", "--seed", "1")]


@pytest.mark.parametrize("cols", [60, 80, 120])
@pytest.mark.parametrize("case", IK_CASES, ids=lambda c: c[0])
def test_ik_fits_and_every_error_is_a_whole_float(cols: int, case: tuple[str, ...]) -> None:
    out = run(cols, "ik", *case)
    check_lines(out, cols)
    robot = armkit.load(case[0])
    res = armkit.ik_all(robot, [float(v) for v in case[1:4]]) if case[0] in ("fighter", "planar2") else None
    errors = re.findall(r"\d\.\de[-+]\d\d", out)
    n_rows = 1 if res is None else len(np.atleast_1d(res.success))
    assert len(errors) >= n_rows            # one whole position error per branch, at least
    for b in ([] if res is None else np.asarray(res.branch)):
        assert str(b) in out                # branch names whole


def test_fighter_at_80_columns_is_still_a_table() -> None:
    out = run(80, "ik", "fighter", "24.861", "14.353", "187.181")
    assert "branch" in out and "pos. error" in out          # headers whole, not "should"/"er"
    assert re.search(r"front/elbow-down\s+29\.9991\s+44\.9998\s+60\.0003\s+\d\.\de-1\d\s+solved", out), out


@pytest.mark.parametrize("cols", [60, 80, 120])
@pytest.mark.parametrize("args", [("robots",), ("info", "fighter"), ("info", "ur5"), ("info", "so101"),
                                  ("info", "stanford"), ("info", "puma560", "--dh", "--convention", "modified")],
                         ids=" ".join)
def test_robots_and_info_fit(cols: int, args: tuple[str, ...]) -> None:
    out = run(cols, *args)
    check_lines(out, cols)
    if args[0] == "info" and args[1] == "ur5":
        assert "shoulder_lift" in out and "-0.39225" in out      # names and numbers whole
    if args[0] == "info" and args[1] == "so101":
        assert "-8.9766e-09" in out


def test_ik_table_renders_in_an_80_column_console() -> None:
    """The table builder itself at a Rich console width of 80: the compact layout fits, nothing cut."""
    from armkit.cli.common import natural_width
    from armkit.cli.ik import _rows, _table

    r = armkit.load("fighter")
    rows = _rows(r, armkit.ik_all(r, [24.861, 14.353, 187.181]))
    t = _table(r, rows, "t", True, compact=True)
    assert natural_width(t) <= 80
    buf = io.StringIO()
    Console(file=buf, width=80, no_color=True).print(t)
    check_lines(buf.getvalue(), 80)
    assert "…" not in buf.getvalue()
