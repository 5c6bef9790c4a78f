"""The back end's state has one owner on the ground floor, and the floors hold (issue 21, docs/architecture.md)."""

from __future__ import annotations

import ast
import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

import armkit
from armkit import _jit_loader, kinematics
from armkit.errors import ArgumentError

ROOT = Path(__file__).resolve().parents[2]
PKG = ROOT / "src" / "armkit"


def _graph():
    spec = importlib.util.spec_from_file_location("import_graph", ROOT / "tools" / "import_graph.py")
    mod = importlib.util.module_from_spec(spec)
    assert spec.loader is not None
    sys.modules["import_graph"] = mod    # its dataclasses look their module up there
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.parametrize(("name", "siblings"), [("_jit_loader", {"errors", "_kernel_store"}), ("_kernel_store", set())])
def test_the_loader_imports_only_the_standard_library_and_the_errors(name, siblings):
    """The loader: the standard library, the errors and the kernel store; the store: the standard library."""
    tree = ast.parse((PKG / f"{name}.py").read_text(encoding="utf-8"))
    stdlib = set(sys.stdlib_module_names)
    for node in tree.body:     # module level (Numba is imported inside functions, on first use)
        if isinstance(node, ast.Import):
            assert all(a.name.split(".")[0] in stdlib for a in node.names), ast.unparse(node)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                assert (node.module or "") in siblings or not node.module and {a.name for a in node.names} <= siblings, \
                    ast.unparse(node)
            else:
                assert (node.module or "").split(".")[0] in stdlib | {"__future__"}, ast.unparse(node)


def test_set_backend_has_one_owner():
    assert kinematics.set_backend is _jit_loader.set_backend is armkit.set_backend
    before = _jit_loader.backend_choice()
    try:
        armkit.set_backend("numpy")
        assert kinematics._backend == _jit_loader._backend == "numpy"     # the old name reads the owner
        assert armkit.get_backend() == "numpy" and kinematics._jit_module(True) is None
        with pytest.raises(ArgumentError, match="backend must be 'auto', 'numba' or 'numpy', got 'cuda'"):
            armkit.set_backend("cuda")  # type: ignore[arg-type]
        assert _jit_loader.backend_choice() == "numpy"
    finally:
        armkit.set_backend(before)  # type: ignore[arg-type]


def test_the_warmup_is_on_the_top_floor():
    assert armkit.warmup.__module__ == "armkit.warmup"
    assert not hasattr(_jit_loader, "warmup") and not hasattr(_jit_loader, "_worker_main")
    assert "from armkit.warmup import _worker_main" in _jit_loader._WORKER


def test_import_armkit_does_not_load_collision_motion_or_viz():
    code = ("import sys, armkit; print(sorted({m.split('.')[1] for m in sys.modules "
            "if m.startswith('armkit.')}))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    loaded = set(ast.literal_eval(out.strip().splitlines()[-1]))
    assert not loaded & {"collision", "motion", "viz", "analysis", "reach", "symbolic", "cli"}, loaded


@pytest.fixture(scope="module")
def analysis():
    """The tool's reading of this tree, with the modules ``import armkit`` loads (a fresh interpreter): ~1.7 s, once."""
    return _graph().analyse(with_loaded=True)


def test_the_floors_hold(analysis):
    """No circle through more than one room, at most 4 back arrows, no undeclared Robot attributes."""
    r = analysis
    assert r["circles_through_several_rooms"] == []
    assert len(r["back_arrows"]) <= 4, r["back_arrows"]
    assert r["robot_undeclared_attributes"] == []


def test_what_import_armkit_loads_is_imported_at_the_top(analysis):
    """An import inside a function is for what ``import armkit`` does not load (optional and heavy packages, the
    rooms it leaves out, the lazy pairs inside a room): one of a module it loads anyway saves nothing and hides the
    module's dependencies (161 of them before 2026-12-07, docs/architecture.md)."""
    r = analysis
    assert r["function_level_imports"]["loaded_already"] == []
    assert r["function_level_imports"]["of_modules_loaded_by_import_armkit"] == 0


def test_the_graph_tool_finds_a_planted_circle_and_back_arrow(tmp_path):
    """The tool can fail: a lower floor importing a higher one is an arrow and a circle."""
    pkg = tmp_path / "armkit"
    for rel in ("__init__.py", "errors.py", "model/__init__.py", "model/robot.py", "kinematics/__init__.py"):
        (pkg / rel).parent.mkdir(parents=True, exist_ok=True)
        (pkg / rel).write_text("")
    (pkg / "model" / "robot.py").write_text("class Robot:\n    x: int\n\n\ndef f(robot):\n"
                                            "    from ..kinematics import fk\n"
                                            "    object.__setattr__(robot, 'extra', 1)\n")
    (pkg / "kinematics" / "__init__.py").write_text("from ..model.robot import Robot\n\n\ndef fk():\n    pass\n")
    graph = _graph()
    graph.ROOT = pkg
    r = graph.analyse()
    assert [(a["from"], a["to"]) for a in r["back_arrows"]] == [("armkit.model.robot", "armkit.kinematics")]
    assert len(r["circles_through_several_rooms"]) == 1
    assert r["robot_undeclared_attributes"] == ["extra"]
