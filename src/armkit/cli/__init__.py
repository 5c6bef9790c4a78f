"""The ``armkit`` command: a thin Typer + Rich front end over the public functions.

Each module registers its commands (``core``: robots, info, fk, jacobian; ``ik``; ``viz``;
``symbolic``). Heavy imports live inside the command bodies so that ``armkit --help``
starts fast, and the CLI uses the NumPy kernels (no JIT start-up cost).

Exit codes: 0 success, 1 a computation that failed (e.g. unreachable target), 2 bad input.
"""

from __future__ import annotations

import importlib
import os

import typer

__all__ = ["app", "main"]

_COMMAND_MODULES = ("core", "ik", "viz", "symbolic")

app = typer.Typer(
    name="armkit",
    help="Serial robot-arm kinematics: DH models, FK, Jacobians, IK, plots.\n\n"
         "Example: armkit fk fighter 30 45 60 --deg",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode="rich",
)

for _name in _COMMAND_MODULES:
    try:
        _module = importlib.import_module(f"armkit.cli.{_name}")
    except ModuleNotFoundError as _exc:  # a command module not written yet
        if _exc.name != f"armkit.cli.{_name}":
            raise
        continue
    _module.register(app)


def main() -> None:
    """Entry point: run the app; armkit errors become one-line messages with exit code 2."""
    from ..errors import ArmkitError
    from .common import EXIT_BAD_INPUT, err_console

    os.environ.setdefault("ARMKIT_BACKEND", "numpy")
    from .. import kinematics

    kinematics.set_backend(os.environ["ARMKIT_BACKEND"])  # type: ignore[arg-type]
    try:
        app(standalone_mode=True)
    except ArmkitError as exc:
        err_console.print(f"[bold red]error:[/] {exc}", soft_wrap=True)
        raise SystemExit(EXIT_BAD_INPUT) from None
    except KeyboardInterrupt:
        raise SystemExit(130) from None
