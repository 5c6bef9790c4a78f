"""The view's panels use the public API of :class:`armkit.viz.view.View` only (issue 21): read from the source,
so no browser is needed."""

from __future__ import annotations

import ast
from pathlib import Path

import armkit.viz.view.panels as panels
from armkit.viz.view.server import View


def _view_attributes() -> list[tuple[int, str]]:
    """Every ``view.X`` / ``self.view.X`` read in panels.py, with its line."""
    tree = ast.parse(Path(panels.__file__).read_text(encoding="utf-8"))
    found = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.Attribute):
            continue
        owner = node.value
        is_view = (isinstance(owner, ast.Name) and owner.id == "view") or \
            (isinstance(owner, ast.Attribute) and owner.attr == "view")
        if is_view:
            found.append((node.lineno, node.attr))
    return found


def test_panels_use_no_private_attribute_of_the_view():
    used = _view_attributes()
    assert len(used) > 20, "the scan finds the panels' uses of the view"
    private = [(line, name) for line, name in used if name.startswith("_")]
    assert private == []


def test_the_player_methods_the_panels_use_exist_on_the_view():
    names = {name for _, name in _view_attributes()}
    for name in ("show_configuration", "start_player", "stop_player", "player_alive", "player_wait", "update_target"):
        assert name in names and callable(getattr(View, name)), name
