"""Shared pieces of the command-line front end: console, argument parsing, errors, output.

Every command module (``core``, ``ik``, ``viz``, ``symbolic``) uses these so that all
commands parse joint values, report mistakes and print JSON the same way. Nothing here
imports more than NumPy, Typer and Rich, so ``armkit --help`` stays fast.
"""

from __future__ import annotations

import json
import math
import sys
from typing import Any, NoReturn, Sequence

import numpy as np
from rich.console import Console
from rich.table import Table

from ..errors import JointLimitError
from ..model import Robot, load

console = Console(highlight=False)
err_console = Console(stderr=True, highlight=False)

EXIT_OK, EXIT_FAILED, EXIT_BAD_INPUT = 0, 1, 2

# Commands that take numbers as positional arguments let "-1" through as a value, not an option.
NUMERIC_ARGS = {"ignore_unknown_options": True, "allow_extra_args": False}


def fail(message: str, code: int = EXIT_BAD_INPUT) -> NoReturn:
    """Print ``message`` to stderr and exit with ``code`` (never a traceback)."""
    err_console.print(f"[bold red]error:[/] {message}", soft_wrap=True)
    raise SystemExit(code)


def warn(message: str) -> None:
    err_console.print(f"[yellow]warning:[/] {message}", soft_wrap=True)


def get_robot(name: str) -> Robot:
    """Load a bundled robot or a robot file; bad names and files raise ArmkitError (exit 2)."""
    return load(name)


def parse_numbers(values: Sequence[str], what: str) -> np.ndarray:
    """Turn command-line words into finite floats, or fail with a one-line message."""
    out = []
    for v in values:
        try:
            x = float(v)
        except ValueError:
            fail(f"{what}: {v!r} is not a number")
        if not math.isfinite(x):
            fail(f"{what}: {v!r} is not a finite number")
        out.append(x)
    return np.array(out, dtype=float)


def parse_q(robot: Robot, values: Sequence[str], deg: bool, strict: bool = False) -> np.ndarray:
    """Joint values from the command line, in radians/length units, checked against the limits.

    ``deg`` converts revolute joints only (prismatic joints are always lengths).
    Outside a limit: a warning, or exit 2 with ``strict``.
    """
    q = parse_numbers(values, "joint values")
    if q.shape != (robot.n,):
        fail(f"robot {robot.name!r} has {robot.n} joints ({', '.join(robot.joint_names)}); "
             f"got {len(q)} value(s)")
    if deg:
        q = np.where(robot.prismatic, q, np.radians(q))
    bad = robot.limit_violations(q)
    if bad:
        msg = "joint limit: " + "; ".join(bad)
        if strict:
            raise JointLimitError(msg)
        warn(msg + " (computing anyway; --strict makes this an error)")
    return q


def q_display(robot: Robot, q: np.ndarray, deg: bool = True) -> list[str]:
    """Joint values as text with units: degrees for revolute joints, length units for prismatic."""
    return [f"{v:.6g} {robot.unit}" if p else (f"{math.degrees(v):.4f}°" if deg else f"{v:.6f} rad")
            for v, p in zip(q, robot.prismatic)]


def pose_table(T: np.ndarray, unit: str, title: str = "pose") -> Table:
    """A 4x4 pose as a Rich table with the translation column labelled with its unit."""
    t = Table(title=title, show_header=True, header_style="bold")
    for h in ("", "x", "y", "z", f"p ({unit})"):
        t.add_column(h, justify="right")
    for i, row in enumerate(T[:3]):
        t.add_row("xyz"[i], *(f"{v: .6f}" for v in row[:3]), f"{row[3]: .6f}")
    return t


def print_json(data: Any) -> None:
    """Print data as JSON (NumPy arrays become lists) on stdout."""
    def default(o: Any) -> Any:
        if isinstance(o, np.ndarray):
            return o.tolist()
        if isinstance(o, (np.floating, np.integer, np.bool_)):
            return o.item()
        raise TypeError(type(o))

    sys.stdout.write(json.dumps(data, default=default, indent=2, ensure_ascii=False) + "\n")
