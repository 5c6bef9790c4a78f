"""The compiled kernels get one set of argument types from all their callers (issue 21: the cold compile).

Numba compiles a function once per distinct tuple of argument types, and types a Python ``int`` or ``bool``
constant (written in the call, or a module global) as a *literal*: ``Literal[int](2)`` is another type than
``int64``, and a kernel called once with ``2`` and once with an ``int64`` variable is compiled twice for the
same work. The same holds for a loop-carried count that starts as the literal ``0`` (the calls in the loop are
typed once with the literal, then again with ``int64``). These tests check the callers that used to do that:
the constants they pass are NumPy scalars (which Numba does not type as literals, see
:func:`numba.core.types.maybe_literal`) and no such call passes a literal ``int``/``bool`` in its source.
"""

from __future__ import annotations

import ast
import inspect
from pathlib import Path

import numpy as np
import pytest

numba = pytest.importorskip("numba")
from numba.core import types  # noqa: E402

SRC = Path(__file__).resolve().parents[3] / "src" / "armkit"


def _literal(value) -> bool:
    """Whether Numba types ``value`` (a constant or a global of a compiled function) as a literal type."""
    return types.maybe_literal(value) is not None


def test_the_law_the_other_tests_rely_on():
    # a Python int or bool is a literal to Numba; the NumPy scalar of the same value is not
    assert _literal(0) and _literal(True)
    assert not _literal(np.int64(0)) and not _literal(np.True_)
    assert numba.typeof(np.int64(0)) == types.int64 and numba.typeof(np.False_) == types.boolean


def test_search_kinds_are_not_literals():
    from armkit.ik.geometric import search

    kinds = (search.TI, search.TP, search.SW, search.SM)
    assert [int(k) for k in kinds] == [0, 1, 2, 3]      # the values of the table in the module docstring
    for k in kinds:
        assert not _literal(k), k
        assert numba.typeof(k) == types.int64


def test_single_call_flags_are_not_literals():
    from armkit.ik.analytic import _single

    assert bool(_single._YES) is True and bool(_single._NO) is False
    for v in (_single._YES, _single._NO):
        assert not _literal(v) and numba.typeof(v) == types.boolean


def test_collision_exact_flag_is_not_a_literal():
    from armkit.collision import _jit

    assert bool(_jit.EXACT) is True
    assert not _literal(_jit.EXACT) and numba.typeof(_jit.EXACT) == types.boolean


def _calls(path: Path, callee: str) -> list[ast.Call]:
    tree = ast.parse(path.read_text())
    return [node for node in ast.walk(tree) if isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
            and node.func.id == callee]


def _constant_args(call: ast.Call) -> list[object]:
    """The ``int``/``bool`` constants written as arguments of ``call`` (floats are not literals to Numba)."""
    return [a.value for a in call.args if isinstance(a, ast.Constant) and isinstance(a.value, (bool, int))]


@pytest.mark.parametrize("path, callee, count", [
    (SRC / "ik" / "analytic" / "_single.py", "_finish", 6),
    (SRC / "ik" / "geometric" / "one_call.py", "_finish", 2),
    (SRC / "ik" / "geometric" / "solvers_check.py", "_closed_core", 2),
    (SRC / "ik" / "geometric" / "one_call.py", "_core_in", 1),
    (SRC / "ik" / "geometric" / "batched.py", "_core_in", 1),
    (SRC / "ik" / "analytic" / "_single.py", "_planar2_run", 1),
    (SRC / "ik" / "analytic" / "_single.py", "_planar3_run", 1),
    (SRC / "ik" / "analytic" / "_single.py", "_ypp_run", 1),
    (SRC / "ik" / "analytic" / "_single.py", "_puma_run", 2),
    (SRC / "ik" / "analytic" / "_single.py", "_ur_run", 2),
    (SRC / "collision" / "_jit.py", "_pair", 2),
    (SRC / "collision" / "_jit.py", "_convex", 1),
    (SRC / "collision" / "_jit.py", "_seg_cyl", 1),
])
def test_no_literal_int_or_bool_in_the_calls(path, callee, count):
    calls = _calls(path, callee)
    assert len(calls) == count     # the sites this test knows (a new one: look at its arguments too)
    for call in calls:
        assert _constant_args(call) == [], (path.name, call.lineno, ast.unparse(call))


def test_search_engine_calls_and_its_root_count():
    from armkit.ik.geometric import search

    path = SRC / "ik" / "geometric" / "search.py"
    for name in search.KERNELS:
        for call in _calls(path, name):
            assert _constant_args(call) == [], (call.lineno, ast.unparse(call))
    # the count of roots carried through the loop of _search starts as a NumPy int, not the literal 0
    fn = next(node for node in ast.parse(inspect.getsource(search)).body
              if isinstance(node, ast.FunctionDef) and node.name == "_search")
    first = min((node for node in ast.walk(fn) if isinstance(node, ast.Assign)
                 and any(isinstance(t, ast.Name) and t.id == "m" for t in node.targets)), key=lambda node: node.lineno)
    assert not isinstance(first.value, ast.Constant), ast.unparse(first)
