"""The command table of ``armkit``: every listed command module is loaded, and a missing one is an error (issue 21)."""

from __future__ import annotations

import sys

import pytest
import typer

import armkit.cli as cli


def test_a_missing_command_module_is_an_error_that_names_it():
    group = typer.Typer()
    with pytest.raises(ImportError, match=r"armkit\.cli\.no_such_commands is missing") as info:
        cli._register_commands(group, ("core", "no_such_commands"))
    assert info.value.name == "armkit.cli.no_such_commands"
    assert group.registered_commands, "the modules before the missing one registered"


def test_a_missing_dependency_of_a_command_module_is_not_renamed(tmp_path, monkeypatch):
    (tmp_path / "needs_missing.py").write_text("import armkit_no_such_dependency  # noqa: F401\n", encoding="utf-8")
    monkeypatch.setattr(cli, "__path__", [*cli.__path__, str(tmp_path)])
    monkeypatch.delitem(sys.modules, "armkit.cli.needs_missing", raising=False)
    with pytest.raises(ModuleNotFoundError) as info:
        cli._register_commands(typer.Typer(), ("needs_missing",))
    assert info.value.name == "armkit_no_such_dependency"
    assert "is missing: it is listed" not in str(info.value)


@pytest.mark.parametrize("name", cli._COMMAND_MODULES)
def test_every_listed_module_registers_commands(name):
    group = typer.Typer()
    cli._register_commands(group, (name,))
    assert group.registered_commands or group.registered_groups
