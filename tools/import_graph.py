"""The import graph of armkit: its rooms (packages), floors, import circles and back arrows.

Reads the sources under ``src/armkit`` with :mod:`ast` (nothing of armkit is imported, except
with ``--loaded``), so it runs on any tree, broken or not::

    python tools/import_graph.py            # the summary and every back arrow and circle
    python tools/import_graph.py --json     # the same as data
    python tools/import_graph.py --loaded   # also: which function-level imports name a module
                                            # that ``import armkit`` has loaded already
    python tools/import_graph.py --src /tmp/old/src/armkit   # another tree (a checkout of an older commit)

Terms (docs/architecture.md):

room
    One top-level part of the package: a subpackage (``ik``, ``collision``) or a module
    (``spatial``, ``_jit_loader``).
floor
    Rooms are stacked on floors (:data:`FLOORS`, lowest first). A room may import rooms on
    its own floor or below.
back arrow
    An import from a module to a module on a higher floor (module pairs, counted once,
    whether the import is at module level or inside a function; ``from armkit import fk``
    is an arrow to ``armkit/__init__.py``, the top floor). Imports under
    ``if TYPE_CHECKING:`` are not counted (they never run), nor the implicit arrow to the
    subpackage (below).
circle
    A strongly connected set of modules of the graph of every import that runs (module level
    and inside functions). One inside a room is an internal matter of that room; the
    summary counts the circles through more than one room.

Importing ``armkit.a.b`` also runs ``armkit/a/__init__.py``; that implicit arrow to the
subpackage is counted (it is why a module cannot import ``armkit.kinematics._numpy`` without
loading ``armkit.kinematics``). The one to ``armkit/__init__.py`` is not (every module has it).
"""

from __future__ import annotations

import argparse
import ast
import json
import subprocess
import sys
from collections import defaultdict
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1] / "src" / "armkit"

FLOORS: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("ground", ("_jit_loader", "_kernel_store", "_jit_twins", "_jit_shaped", "_arith", "errors", "_checks", "_text",
                "_io", "_extras", "_limits", "_version", "locale")),
    ("spatial", ("spatial",)),
    ("model", ("model",)),
    ("kinematics", ("kinematics",)),
    ("collision", ("collision",)),
    ("ik", ("ik",)),
    ("analysis", ("analysis", "motion", "reach", "symbolic")),
    ("viz", ("viz",)),
    ("top", ("cli", "warmup", "lerobot", "_lerobot_kinematics", "__init__")),
)
"""The floors, lowest first, and the rooms on each. ``__init__`` is ``armkit/__init__.py``."""

ROBOT_FIELDS_FROM = "model/robot.py"


def floor_of(room: str) -> int:
    for k, (_, rooms) in enumerate(FLOORS):
        if room in rooms:
            return k
    raise KeyError(f"room {room!r} is on no floor: add it to FLOORS in {__file__}")


@dataclass
class Import:
    source: str          # importing module, "armkit.ik.api"
    target: str          # imported module, "armkit.collision.query"
    line: int
    in_function: bool
    type_checking: bool
    implicit: bool = False   # the subpackage __init__ that importing a module inside it runs
    by_name: bool = False    # a kernel module loaded by name (armkit._jit_loader.module / kernels)


@dataclass
class Graph:
    modules: list[str]
    imports: list[Import] = field(default_factory=list)
    function_imports_all: int = 0      # every import statement inside a function (armkit's or not)


def module_name(path: Path) -> str:
    rel = path.relative_to(ROOT.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def room_of(module: str) -> str:
    parts = module.split(".")
    return "__init__" if len(parts) == 1 else parts[1]


def _is_package(module: str, modules: set[str]) -> bool:
    return any(m.startswith(module + ".") for m in modules)


def _resolve(base: str, names: list[str], modules: set[str]) -> list[str]:
    """The armkit modules that ``from base import names`` loads: ``base`` and each name that is a submodule."""
    subs = [f"{base}.{n}" for n in names if f"{base}.{n}" in modules]
    attrs = len(subs) < len(names)   # some names are attributes of base itself: base is needed
    return ([base] if base in modules and (attrs or not subs) else []) + subs


def _parents(module: str) -> list[str]:
    """The subpackages whose ``__init__`` importing ``module`` runs (not ``armkit`` itself)."""
    parts = module.split(".")
    return [".".join(parts[:k]) for k in range(2, len(parts))]


def read_graph() -> Graph:
    files = sorted(p for p in ROOT.rglob("*.py") if "__pycache__" not in p.parts)
    modules = [module_name(p) for p in files]
    known = set(modules)
    graph = Graph(modules)
    for path, mod in zip(files, modules):
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        package = mod if path.name == "__init__.py" else mod.rpartition(".")[0]

        def visit(node: ast.AST, in_function: bool, type_checking: bool) -> None:
            for child in ast.iter_child_nodes(node):
                fn = in_function or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda))
                tc = type_checking or (isinstance(child, ast.If) and "TYPE_CHECKING" in ast.unparse(child.test))
                if isinstance(child, (ast.Import, ast.ImportFrom)):
                    if in_function:
                        graph.function_imports_all += 1
                    targets: list[str] = []
                    if isinstance(child, ast.Import):
                        targets = [a.name for a in child.names if a.name.split(".")[0] == "armkit"]
                        targets = [t for t in targets if t in known]
                    else:
                        if child.level:
                            base_parts = package.split(".")
                            if child.level > 1:
                                base_parts = base_parts[: len(base_parts) - child.level + 1]
                            base = ".".join(base_parts + ([child.module] if child.module else []))
                        else:
                            base = child.module or ""
                        if base.split(".")[0] == "armkit":
                            targets = _resolve(base, [a.name for a in child.names], known)
                    for t in targets:
                        for tt in _parents(t) + [t]:
                            if tt != mod and tt in known:
                                graph.imports.append(Import(mod, tt, child.lineno, in_function, type_checking,
                                                            implicit=tt != t and tt not in targets))
                # importlib.import_module("armkit.x") with a literal name
                if (isinstance(child, ast.Call) and ast.unparse(child.func).endswith("import_module")
                        and child.args and isinstance(child.args[0], ast.Constant)
                        and isinstance(child.args[0].value, str) and child.args[0].value in known):
                    t = child.args[0].value
                    for tt in _parents(t) + [t]:
                        if tt != mod:
                            graph.imports.append(Import(mod, tt, child.lineno, in_function, type_checking,
                                                        implicit=tt != t))
                # a kernel module loaded by name through the back end: _jit_loader.module("ik._jit_lm")
                if (isinstance(child, ast.Call) and ast.unparse(child.func).split(".")[-1] in ("module", "kernels")
                        and child.args and isinstance(child.args[0], ast.Constant)
                        and isinstance(child.args[0].value, str) and f"armkit.{child.args[0].value}" in known):
                    t = f"armkit.{child.args[0].value}"
                    if t != mod:
                        graph.imports.append(Import(mod, t, child.lineno, in_function, type_checking, by_name=True))
                visit(child, fn, tc)

        visit(tree, False, False)
    return graph


def strongly_connected(nodes: list[str], edges: dict[str, set[str]]) -> list[list[str]]:
    """Tarjan's algorithm, iterative; components of more than one module (or a self-loop)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    on_stack: set[str] = set()
    stack: list[str] = []
    out: list[list[str]] = []
    counter = 0
    for root in nodes:
        if root in index:
            continue
        work = [(root, iter(sorted(edges.get(root, ()))))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            v, it = work[-1]
            advanced = False
            for w in it:
                if w not in index:
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(sorted(edges.get(w, ())))))
                    advanced = True
                    break
                if w in on_stack:
                    low[v] = min(low[v], index[w])
            if advanced:
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    on_stack.discard(w)
                    comp.append(w)
                    if w == v:
                        break
                if len(comp) > 1:
                    out.append(sorted(comp))
    return out


def robot_undeclared() -> list[str]:
    """Attribute names that ``object.__setattr__(robot-ish, "name", ...)`` sets on a Robot but that
    are no field of the Robot dataclass (static: the class's annotations vs every such call in the tree)."""
    tree = ast.parse((ROOT / ROBOT_FIELDS_FROM).read_text(encoding="utf-8"))
    fields: set[str] = set()
    robot_cls = None
    for top in tree.body:
        if isinstance(top, ast.ClassDef) and top.name == "Robot":
            robot_cls = top
            fields = {s.target.id for s in top.body if isinstance(s, ast.AnnAssign) and isinstance(s.target, ast.Name)}
    found: set[str] = set()
    for path in ROOT.rglob("*.py"):
        if "__pycache__" in path.parts:
            continue
        t = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(t):
            if not (isinstance(node, ast.Call) and ast.unparse(node.func) in ("object.__setattr__", "set_", "setattr")
                    and len(node.args) >= 2):
                continue
            who = ast.unparse(node.args[0])
            name = node.args[1]
            in_robot = robot_cls is not None and path.name == "robot.py" and who == "self" and \
                robot_cls.lineno <= node.lineno <= (robot_cls.end_lineno or 10**9)
            if "robot" in who.lower() or who in ("target", "arm") or in_robot:
                if isinstance(name, ast.Constant) and isinstance(name.value, str):
                    if name.value not in fields:
                        found.add(name.value)
                elif in_robot:   # a loop over names, e.g. for attr in ("_lower", "_upper")
                    for sub in ast.walk(tree):
                        if isinstance(sub, ast.For) and sub.lineno <= node.lineno <= (sub.end_lineno or 0):
                            for c in ast.walk(sub.iter):
                                if isinstance(c, ast.Constant) and isinstance(c.value, str) and \
                                        c.value.isidentifier() and c.value not in fields:
                                    found.add(c.value)
    return sorted(found)


def _imported_names(module: str, line: int) -> list[str]:
    """The names the import statement at ``line`` of ``module`` binds (its ``import`` or ``from ... import``)."""
    path = ROOT.parent / (module.replace(".", "/") + ".py")
    if not path.exists():
        path = ROOT.parent / module.replace(".", "/") / "__init__.py"
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, (ast.Import, ast.ImportFrom)) and node.lineno == line:
            return [a.name for a in node.names]
    return []


def loaded_by_import() -> set[str]:
    """The armkit modules in ``sys.modules`` after ``import armkit`` (a fresh interpreter)."""
    code = "import sys, armkit; print('\\n'.join(m for m in sys.modules if m.split('.')[0] == 'armkit'))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         cwd=ROOT.parents[1], env={"PYTHONPATH": str(ROOT.parent), "PATH": ""})
    return set(out.stdout.split())


def analyse(with_loaded: bool = False) -> dict[str, Any]:
    g = read_graph()
    run_edges: dict[str, set[str]] = defaultdict(set)
    for imp in g.imports:
        if not imp.type_checking:
            run_edges[imp.source].add(imp.target)
    circles = strongly_connected(g.modules, run_edges)
    multi = [c for c in circles if len({room_of(m) for m in c}) > 1]
    back: dict[tuple[str, str], Import] = {}
    for imp in g.imports:
        if imp.type_checking or imp.implicit:
            continue
        if floor_of(room_of(imp.source)) < floor_of(room_of(imp.target)):
            back.setdefault((imp.source, imp.target), imp)
    fn_imports = [i for i in g.imports if i.in_function and not i.type_checking]
    fn_statements = {(i.source, i.line) for i in fn_imports}
    rooms: dict[str, list[str]] = defaultdict(list)
    for m in g.modules:
        rooms[room_of(m)].append(m)
    result: dict[str, Any] = {
        "floors": [{"floor": name, "rooms": [r for r in rs if r in rooms]} for name, rs in FLOORS],
        "rooms": len(rooms),
        "modules": len(g.modules),
        "circles_through_several_rooms": [{"size": len(c), "rooms": sorted({room_of(m) for m in c}), "modules": c}
                                          for c in multi],
        "circles_inside_one_room": len(circles) - len(multi),
        "circles_inside_rooms": [c for c in circles if c not in multi],
        "back_arrows": [{"from": s, "to": t, "line": i.line, "in_function": i.in_function, "by_name": i.by_name}
                        for (s, t), i in sorted(back.items())],
        "function_level_imports": {"statements": g.function_imports_all,
                                   "of_armkit_modules": len(fn_statements)},
        "robot_undeclared_attributes": robot_undeclared(),
    }
    if with_loaded:
        loaded = loaded_by_import()
        already = {(i.source, i.line) for i in fn_imports if i.target in loaded
                   and not any(j.source == i.source and j.line == i.line and j.target not in loaded for j in fn_imports)}
        result["function_level_imports"]["of_modules_loaded_by_import_armkit"] = len(already)
        result["function_level_imports"]["loaded_already"] = [
            {"module": m, "line": line, "names": _imported_names(m, line)} for m, line in sorted(already)]
    return result


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true", help="print the result as JSON")
    ap.add_argument("--loaded", action="store_true",
                    help="count the function-level imports of modules `import armkit` loaded already (imports armkit)")
    ap.add_argument("--src", type=Path, default=None, help="the armkit package folder to read (default: this tree's)")
    ap.add_argument("-v", "--verbose", action="store_true", help="also list the modules of each circle")
    args = ap.parse_args(argv)
    if args.src is not None:
        global ROOT
        ROOT = args.src.resolve()
    r = analyse(args.loaded)
    if args.json:
        print(json.dumps(r, indent=1))
        return 0
    print("floors (lowest first):")
    for f in r["floors"]:
        print(f"  {f['floor']:<11} {', '.join(f['rooms'])}")
    circles = r["circles_through_several_rooms"]
    arrows = r["back_arrows"]
    fl = r["function_level_imports"]
    print(f"rooms: {r['rooms']} ({r['modules']} modules)")
    print(f"circles through more than one room: {len(circles)}"
          + "".join(f"\n  {c['size']} modules, rooms {', '.join(c['rooms'])}" for c in circles))
    print(f"circles inside one room: {r['circles_inside_one_room']}")
    print(f"back arrows: {len(arrows)}")
    for a in arrows:
        where = ("in a function" if a["in_function"] else "module level") + (", by name" if a["by_name"] else "")
        print(f"  {a['from']} -> {a['to']}  (line {a['line']}, {where})")
    loaded = fl.get("of_modules_loaded_by_import_armkit")
    print(f"imports inside functions: {fl['statements']} statements, {fl['of_armkit_modules']} of armkit modules"
          + ("" if loaded is None else f", {loaded} of modules `import armkit` loaded already"))
    for imp in fl.get("loaded_already", []):
        print(f"  {imp['module']}:{imp['line']} imports {', '.join(imp['names'])}")
    und = r["robot_undeclared_attributes"]
    print(f"undeclared attributes on Robot: {len(und)}" + (f" ({', '.join(und)})" if und else ""))
    if args.verbose:
        for c in circles:
            print("  circle:", " ".join(c["modules"]))
        for c in r["circles_inside_rooms"]:
            print("  circle inside a room:", " ".join(c))
    return 0


if __name__ == "__main__":
    sys.exit(main())
