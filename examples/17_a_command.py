"""A new armkit command in one file: ``armkit home ROBOT`` (docs/adding-a-command.md).

Saved as ``src/armkit/cli/home.py`` and named in ``armkit.cli._COMMAND_MODULES``, this module is
part of ``armkit``. Run as a script, it adds its command to armkit's command group in this process
and runs it three times, so that a command can be tried before it is installed.

Run: python examples/17_a_command.py
"""

from __future__ import annotations

import numpy as np
import typer

from armkit.cli.common import JsonOut, RobotArg, _, esc, get_robot, message, print_json

__all__ = ["register", "home"]


def home(robot: RobotArg, json_out: JsonOut = False) -> None:
    """Where the tool is when every joint is at zero (the home pose's position).

    Example: armkit home fighter
    """
    from armkit.kinematics import fk

    r = get_robot(robot)                 # a bad name or file: one line, exit 2 (the command group does it)
    p = fk(r, np.zeros(r.n))[:3, 3]
    if json_out:
        print_json({"robot": r.name, "unit": r.unit, "position": p})
        return
    message(esc(_("{robot}: the tool is at ({x}, {y}, {z}) {unit} with every joint at zero", robot=r.name,
                  x=f"{p[0]:.3f}", y=f"{p[1]:.3f}", z=f"{p[2]:.3f}", unit=r.unit)))


def register(app: typer.Typer) -> None:
    """Add this module's commands to ``app`` (armkit.cli calls it for every module of ``_COMMAND_MODULES``)."""
    app.command("home")(home)


if __name__ == "__main__":
    from armkit.cli import app

    register(app)
    for args in (["home", "planar2"], ["home", "fighter", "--json"], ["home", "fighter", "--lang", "ko"]):
        print("$ armkit " + " ".join(args))
        app(args, standalone_mode=False)
