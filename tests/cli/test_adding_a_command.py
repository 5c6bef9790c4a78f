"""docs/adding-a-command.md (issue 21): its example command runs as the page says, loaded the way armkit loads its own
command modules (``armkit.cli.<name>`` through ``_register_commands``)."""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

import pytest
import typer
from typer.testing import CliRunner

import armkit.cli as cli
from armkit.locale import LANG

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "adding-a-command.md"
EXAMPLE = ROOT / "examples" / "17_a_command.py"


def _doc_block() -> str:
    return re.search(r"```python\n(.*?)```", DOC.read_text(encoding="utf-8"), re.S).group(1)


@pytest.fixture
def home_app(tmp_path, monkeypatch):
    """A command group like armkit's with only the doc's module, saved as ``armkit/cli/home.py`` (in a folder
    added to the package's path) and registered by ``_register_commands``."""
    (tmp_path / "home.py").write_text(_doc_block(), encoding="utf-8")
    monkeypatch.setattr(cli, "__path__", [*cli.__path__, str(tmp_path)])
    monkeypatch.delitem(sys.modules, "armkit.cli.home", raising=False)
    group = typer.Typer(cls=cli._ArmkitGroup, add_completion=False, pretty_exceptions_enable=False)
    group.callback()(lambda: None)       # a group, as armkit's (one command alone would run without its name)
    cli._register_commands(group, ("home",))
    yield group
    sys.modules.pop("armkit.cli.home", None)
    LANG["lang"] = None


def _run(app: typer.Typer, *args: str):
    return CliRunner().invoke(app, list(args), env={"COLUMNS": "200"})


def test_the_doc_shows_the_example_file():
    """The page's code is the example script's module part, word for word (one text to keep up)."""
    assert _doc_block() in EXAMPLE.read_text(encoding="utf-8")


def test_home_prints_the_tool_position_at_zero(home_app):
    """planar2: links of 1 m and 0.5 m along x at q = 0, so the tool is at (1.5, 0, 0) m (hand derivation)."""
    res = _run(home_app, "home", "planar2")
    assert res.exit_code == 0, res.output
    assert res.stdout.strip() == "planar2: the tool is at (1.500, 0.000, 0.000) m with every joint at zero"


def test_home_json_and_korean(home_app):
    """fighter (robots/fighter.toml): d1 = 36 mm up, then links of 77.2 and 100 mm along x at q = 0: (177.2, 0, 36)."""
    data = json.loads(_run(home_app, "home", "fighter", "--json").stdout)
    assert data["unit"] == "mm" and data["position"] == pytest.approx([177.2, 0.0, 36.0], abs=1e-9)
    res = _run(home_app, "home", "fighter", "--lang", "ko")
    assert res.exit_code == 0
    assert res.stdout.strip() == "fighter: 모든 관절이 0일 때 툴은 (177.200, 0.000, 36.000) mm에 있습니다"


def test_home_shares_the_group_s_errors_and_options(home_app):
    res = _run(home_app, "home", "no_such_robot")
    assert res.exit_code == 2 and "no_such_robot" in res.stderr and "Traceback" not in res.output
    res = _run(home_app, "home", "planar2", "--lang", "fr")
    assert res.exit_code == 2 and "--lang must be one of en, ko" in res.stderr
    helptext = _run(home_app, "home", "--help").stdout
    assert "Print the answer as JSON" in helptext and "--tip" in helptext   # JsonOut, and the chain options


def test_a_listed_command_module_that_is_missing_is_named():
    with pytest.raises(ImportError, match=r"armkit\.cli\.home_is_not_here is missing"):
        cli._register_commands(typer.Typer(), ("home_is_not_here",))


def test_the_example_runs_as_a_script(tmp_path):
    import os
    import subprocess

    proc = subprocess.run([sys.executable, str(EXAMPLE)], capture_output=True, text=True, cwd=tmp_path, timeout=300,
                          env=dict(os.environ, ARMKIT_LANG="en", COLUMNS="200"))
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert "planar2: the tool is at (1.500, 0.000, 0.000) m" in proc.stdout and "177.2" in proc.stdout
