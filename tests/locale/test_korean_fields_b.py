"""Issue 21 item 2 ("messages from fields"), part B: the errors of the reachability maps, the browser view's server,
the collision shapes, the IK solvers (held joints, LM/Newton, FABRIK, CCD), the shell, the language table, the DH
twin, the joint axes, the chain classifier and the back-end choice keep their template and fields. A Korean user
reads each one rendered from the catalogue (no English sentence left), and the English text is the one it was.

One error per converted module, raised through the public API (or the command line), checked with the helpers of
test_korean_everywhere.py (``english_runs`` outside the field values, ``english_words`` for a command's output).
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from test_korean_everywhere import (ENV, _catalogue, _says_korean, app, english_runs, english_words, raise_site_templates,
                                    runner)

import armkit
from armkit.errors import (ArgumentError, IKInputError, MapFileError, ReachabilityError,
                           RobotDefinitionError, SceneError, ShapeError, ViewError)
from armkit.locale.library import localize


def _bent_chain() -> armkit.Robot:
    """A chain whose second axis leans 1e-6 rad from the first: no DH table reproduces it (the twin's check)."""
    from armkit.model import Joint, Robot
    from armkit.spatial import transl

    joints = [Joint(kind="revolute", origin=transl(0.3, 0.1 * i, 0.2), axis=[0.0, np.sin(1e-6) if i == 1 else 0.0, 1.0],
                    name=f"j{i}") for i in range(3)]
    return Robot(joints, "urdf", name="bent")


def _pose(name: str) -> np.ndarray:
    r = armkit.load(name)
    return armkit.fk(r, np.full(r.n, 0.3))


def _store_refuses_a_file(tmp_path):
    f = tmp_path / "notes.txt"
    f.write_text("mine\n", encoding="utf-8")
    armkit.reachability("planar2", resolution=0.5, path=str(f), overwrite=True)


def _view_lang():
    pytest.importorskip("viser")
    from armkit.viz.view.server import View

    View("planar2", lang="xx")


def _shell_mode():
    from armkit.cli.shell import Shell

    Shell(armkit.load("planar2"), mode="x")


def _remove_source_language():
    from armkit.locale import languages

    languages.remove("en")


def _bad_language_code():
    from dataclasses import replace

    from armkit.locale.languages import TABLE, add

    add(replace(TABLE["en"], code="Xx"))


def _lm_q0():
    from armkit.ik.numeric import solve_lm

    solve_lm(armkit.load("puma560"), _pose("puma560")[None], np.zeros((2, 6)))


def _axes_of_two():
    from armkit.model.axes import joint_axes

    joint_axes(armkit.load("planar2"), np.zeros((2, 2)))


def _classify_tol():
    from armkit.ik.geometric.classify import classify

    classify(armkit.load("puma560"), tol=-1.0)


def _dh_twin():
    from armkit.model.dh_extract import chain_to_dh

    chain_to_dh(_bent_chain(), "standard")


# (module, call, error class, the English it said before the conversion; PATH is tmp_path)
CASES = [
    ("reach/_store", lambda p: armkit.ReachabilityMap.open(str(p / "none.zarr")), MapFileError,
     "no reachability map at 'PATH/none.zarr'"),
    ("reach/_store-overwrite", _store_refuses_a_file, ReachabilityError,
     "will not overwrite 'PATH/notes.txt': it is a file, not a reachability map"),
    ("reach/_build", lambda p: armkit.reachability("planar2", method="x"), ReachabilityError,
     "method must be 'fk' or 'ik', got 'x'"),
    ("reach/_build-resolution", lambda p: armkit.reachability("planar2", resolution=-1.0), ReachabilityError,
     "resolution must be a positive length in m, got -1.0"),
    ("reach/_scene", lambda p: armkit.reachability("planar2", scene=123), SceneError,
     "scene must be an armkit.Scene, a sequence of shapes, a scene file or 'robot'; got int ("),
    ("reach/_base", lambda p: armkit.base_placement(None, np.eye(4)), ArgumentError,
     "map must be an armkit.ReachabilityMap, got NoneType"),
    ("viz/view/server", lambda p: _view_lang(), ViewError, "lang must be one of en"),
    ("collision/shapes", lambda p: armkit.Scene.box((0, 0, 0), (1, -1, 1)), SceneError,
     "box size must be a finite number > 0, got -1.0"),
    ("collision/shapes-normal", lambda p: armkit.Scene.plane((0, 0, 0), 0.0), SceneError,
     "plane normal must not be zero"),
    ("ik/geometric/locked", lambda p: armkit.ik_all(armkit.load("iiwa14"), _pose("iiwa14"), fixed={"nope": 1.0}),
     IKInputError, "fixed: no joint named 'nope' in robot 'iiwa14'; the joints are A1, A2, A3, A4, A5, A6, A7"),
    ("ik/numeric", lambda p: _lm_q0(), ShapeError, "solve_lm: q0 must have shape (1, 6) for 1 targets, got (2, 6)"),
    ("ik/fabrik", lambda p: armkit.ik(armkit.load("puma560"), _pose("puma560"), method="fabrik"), IKInputError,
     "FABRIK in armkit supports planar arms (all joint axes parallel) and a yaw joint followed by a planar arm; "
     "robot 'puma560' is neither; use method 'ccd' or 'lm'"),
    ("ik/ccd", lambda p: armkit.ik(armkit.load("planar2"), [0.1, 0.1], method="ccd", mask=(0, 0, 0, 1, 1, 1)),
     IKInputError, "CCD solves position targets only: mask must be None or weight x, y and z with zero rotation "
     "weights, got (0, 0, 0, 1, 1, 1); use method 'lm' for orientation masks"),
    ("cli/shell", lambda p: _shell_mode(), ArgumentError, "mode must be 'ik' or 'fk', got 'x'"),
    ("locale/languages", lambda p: _remove_source_language(), ArgumentError,
     "'en' is the language of the code itself and cannot be removed"),
    ("locale/languages-code", lambda p: _bad_language_code(), ArgumentError,
     "a language code is lower-case letters and digits (e.g. 'ja', 'pt_br'), got 'Xx'"),
    ("model/dh_extract", lambda p: _dh_twin(), RobotDefinitionError,
     "robot 'bent': no DH table reproduces this chain to 1e-09 of its reach (FK can differ by "),
    ("model/axes", lambda p: _axes_of_two(), ShapeError, "q must be one configuration of shape (2,), got (2, 2)"),
    ("ik/geometric/classify", lambda p: _classify_tol(), ArgumentError, "tol must be a positive number, got -1.0"),
    ("_jit_loader", lambda p: armkit.set_backend("x"), ArgumentError,
     "backend must be 'auto', 'numba' or 'numpy', got 'x'"),
]


@pytest.mark.parametrize("call, cls, english", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_each_converted_module_speaks_korean(call, cls, english, tmp_path):
    with pytest.raises(cls) as info:
        call(tmp_path)
    exc = info.value
    assert str(exc).replace(str(tmp_path), "PATH").startswith(english), str(exc)    # the English is unchanged
    _says_korean(exc, tmp_path)           # template + fields in the catalogue; Korean, no English run


def test_a_shape_error_names_its_field_in_korean():
    """A shape's field ("box size") is a part with its own template, so the whole sentence is Korean."""
    with pytest.raises(SceneError) as info:
        armkit.Scene.cylinder((0, 0, 0), 0.1, float("nan"))
    ko = localize(info.value, "ko")
    assert ko.startswith("원기둥 길이"), ko
    assert str(info.value) == "cylinder length must be a finite number > 0, got nan"


def test_a_chain_described_in_an_error_is_korean_phrase_by_phrase():
    """The chain's line (``describe``) inside an error is a sentence of parts, each rendered from the catalogue."""
    from armkit.ik.geometric.classify import classify, describe, described

    for name in ("ur5", "puma560", "iiwa14", "stanford"):
        cls = classify(armkit.load(name))
        line = described(cls)
        assert line == describe(cls)                                  # the English is describe's
        ko = localize(line, "ko")
        assert re.search(r"[가-힣]", ko) and english_runs(ko, (str(cls.locked_class),)) == [], ko


def test_holding_joints_that_leave_no_closed_form_is_said_in_korean(tmp_path):
    """The refusal names the chain left by its line; the line's phrases come from the catalogue, its glue (``6R: ``,
    ``, ``) is punctuation (a template of its own, not in the catalogue)."""
    from armkit.locale.library import fielded

    with pytest.raises(IKInputError) as info:
        armkit.ik_all(armkit.load("iiwa14"), _pose("iiwa14"), fixed={"A4": 0.3})
    exc = info.value
    assert str(exc).startswith("holding A4 leaves a 6-joint chain without a closed form in armkit: 6R: axes 1-2-3 "
                               "meet in a point (spherical shoulder)"), str(exc)
    ko_entries = _catalogue()
    template, fields = fielded(exc)
    assert ko_entries.get(template), template
    for part in fielded(fields["chain"])[1].values():
        assert ko_entries.get(fielded(part)[0]), fielded(part)[0]
    ko = localize(exc, "ko")
    assert "해석적 해가 없습니다" in ko and "구면 어깨" in ko, ko
    assert english_runs(ko) == [], ko


def test_the_points_of_a_map_query_are_checked_in_korean(tmp_path):
    m = armkit.reachability("planar2", resolution=0.5, samples=4096)
    with pytest.raises(ShapeError) as info:
        m.index([[1.0, 2.0]])
    assert str(info.value) == "points must have shape (..., 3), got (1, 2)"
    _says_korean(info.value, tmp_path)


def test_a_missing_map_is_reported_in_korean_by_the_command_line(tmp_path):
    res = runner.invoke(app, ["reach", "show", str(tmp_path / "none.zarr"), "--lang", "ko"], env=ENV)
    assert res.exit_code == 2, res.output
    out = ((res.stdout or "") + (res.stderr or "")).replace(str(tmp_path), "PATH")
    assert "도달 가능성 지도가 없습니다" in out, out
    assert english_words(out) == [], out


FILES = ("reach/_store.py", "reach/_build.py", "reach/_base.py", "reach/_map.py", "reach/_scene.py",
         "viz/view/server.py", "collision/shapes.py", "ik/geometric/locked.py", "ik/numeric.py", "ik/fabrik.py",
         "ik/ccd.py", "cli/shell.py", "model/dh_extract.py", "model/axes.py", "ik/geometric/classify.py",
         "_jit_loader.py", "ik/_numeric_inputs.py", "ik/_numeric_report.py", "viz/view/players.py",
         "viz/view/screenshots.py")


def test_every_template_of_these_modules_is_in_the_catalogue():
    """The scan of test_korean_everywhere finds these modules' templates, and each has a Korean entry with the same
    fields (the language table's two, in locale/ which the scan skips, are named here)."""
    ko = _catalogue()
    sites = {t: w for t, w in raise_site_templates().items() if w.rsplit(":", 1)[0] in FILES}
    assert len(sites) > 100, len(sites)
    sites["a language code is lower-case letters and digits (e.g. 'ja', 'pt_br'), got {code!r}"] = "languages"
    sites["{code!r} is the language of the code itself and cannot be removed"] = "languages"
    missing = {t: w for t, w in sites.items() if not ko.get(t)}
    assert missing == {}, missing
    for t in sites:
        assert re.search(r"[가-힣]", ko[t]) or re.fullmatch(r"[{}\w!:, =.]*", ko[t]), (t, ko[t])   # "{message} {note}"
        assert set(re.findall(r"(?<!\{)\{(\w+)", ko[t])) == set(re.findall(r"(?<!\{)\{(\w+)", t)), (t, ko[t])


def test_no_fstring_raise_is_left_in_these_modules():
    """Every raise of these modules keeps its template: no ``raise XError(f"...")`` (nor a sentence glued with +)."""
    import ast
    import pathlib

    root = pathlib.Path(armkit.__file__).parent
    left = []
    for rel in (*FILES, "locale/languages.py"):
        for node in ast.walk(ast.parse((root / rel).read_text(encoding="utf-8"))):
            if isinstance(node, ast.Raise) and isinstance(node.exc, ast.Call) and node.exc.args:
                name = getattr(node.exc.func, "id", "")
                if name.endswith("Error") and name not in ("IndexError", "LookupError", "KeyError", "OSError") \
                        and isinstance(node.exc.args[0], (ast.JoinedStr, ast.BinOp)):
                    left.append(f"{rel}:{node.lineno}")
    assert left == [], left


def test_the_back_ends_notes_are_worded_in_the_users_language(monkeypatch, capsys):
    """The notes on stderr about compiling the kernels (`armkit._jit_loader`: on first use, in the background, after
    a failed warm-up) are templates with fields: a command line in Korean words them from the catalogue (they were
    English in a Korean session, found when a command compiled a kernel), and the library alone prints the English
    it printed."""
    from armkit import _jit_loader as jl
    from armkit.cli import _word_the_notes
    from armkit.locale import LANG

    notes = ((jl.NOTE_COMPILING, {"seconds": 45}), (jl.NOTE_COMPILING_NO_HINT, {"seconds": 45}),
             (jl.NOTE_BACKGROUND, {"seconds": 45}), (jl.NOTE_FAILED, {"seconds": 45, "log": "/tmp/x.log"}))
    monkeypatch.setattr(jl, "_RENDER", [])
    monkeypatch.setattr(jl, "_told", set())
    jl.say_compiling()
    english = capsys.readouterr().err
    assert english == ("armkit: compiling armkit's kernels once, about 45 s in all (cached on disk for the next "
                       "runs; `armkit warmup` does it ahead of time)\n")
    monkeypatch.setitem(LANG, "lang", "ko")
    _word_the_notes()
    for k, (template, fields) in enumerate(notes):
        jl._say(template, f"note {k}", **fields)
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == len(notes)
    for line in lines:
        assert line.startswith("armkit: ") and re.search(r"[가-힣]", line), line
        assert english_words(line) == [], line
    assert "45 s" in lines[0] and "/tmp/x.log" in lines[3]
    monkeypatch.setattr(jl, "_told", set())
    jl._RENDER[:] = [lambda template, fields: 1 / 0]     # a renderer that fails: the English, never an error
    jl.say_compiling(hint=False)
    assert capsys.readouterr().err.startswith("armkit: compiling armkit's kernels once, about 45 s in all (cached")
