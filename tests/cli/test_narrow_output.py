"""Issue 11: tables fit an 80-column (and 60-column) terminal and never break a number across lines."""

from __future__ import annotations

import io
import re

import numpy as np
import pytest
from rich.console import Console
from typer.testing import CliRunner

import armkit
from armkit.cli import app

runner = CliRunner()
FLOAT = re.compile(r"^([-+]?\d+(\.\d+)?(e[-+]\d\d)?|\d+\.\d+\.\d+)$")     # a number, or a version


def run(cols: int, *args: str) -> str:
    res = runner.invoke(app, list(args), env={"COLUMNS": str(cols)})
    assert res.exit_code in (0, 1), res.output
    return res.stdout


def check_lines(text: str, cols: int) -> None:
    """No line longer than ``cols``; every table cell holding a number holds a whole one; no row continues a
    number on the next line (the first cell of a continuation row is empty)."""
    for line in text.splitlines():
        assert len(line) <= cols, f"{len(line)} > {cols}: {line!r}"
        if not line.startswith("│"):
            continue
        cells = [c.strip() for c in line.strip("│").split("│")]
        if cells[0] == "":      # a wrapped row: it must not carry pieces of numbers
            assert not any(re.fullmatch(r"[-+\d.e]+", c) for c in cells[1:]), line
        for c in cells:
            if re.fullmatch(r"[-+\d.e]+", c):
                assert FLOAT.match(c), f"broken number {c!r} in {line!r}"


IK_CASES = [("fighter", "24.861", "14.353", "187.181"),
            ("puma560", "0.4", "0.1", "0.5", "--rpy", "180", "0", "0", "--deg"),
            ("ur5", "0.4", "0.1", "0.5", "--rpy", "180", "0", "0", "--deg"),
            ("planar2", "1.2", "0.3"),
            ("panda", "0.4", "0.1", "0.5", "--method", "lm", "--seed", "1")]


@pytest.mark.parametrize("cols", [60, 80, 120])
@pytest.mark.parametrize("case", IK_CASES, ids=lambda c: c[0])
def test_ik_fits_and_every_error_is_a_whole_float(cols: int, case: tuple[str, ...]) -> None:
    out = run(cols, "ik", *case)
    check_lines(out, cols)
    robot = armkit.load(case[0])
    res = armkit.ik_all(robot, [float(v) for v in case[1:4]]) if case[0] in ("fighter", "planar2") else None
    errors = re.findall(r"\d\.\de[-+]\d\d", out)
    n_rows = 1 if res is None else len(np.atleast_1d(res.success))
    assert len(errors) >= n_rows            # one whole position error per branch, at least
    for b in ([] if res is None else np.asarray(res.branch)):
        assert str(b) in out                # branch names whole


def test_fighter_at_80_columns_is_still_a_table() -> None:
    out = run(80, "ik", "fighter", "24.861", "14.353", "187.181")
    assert "branch" in out and "pos. error" in out          # headers whole, not "should"/"er"
    assert re.search(r"front/elbow-down\s+29\.9991\s+44\.9998\s+60\.0003\s+\d\.\de-1\d\s+solved", out), out


@pytest.mark.parametrize("cols", [60, 80, 120])
@pytest.mark.parametrize("args", [("robots",), ("info", "fighter"), ("info", "ur5"), ("info", "so101"),
                                  ("info", "stanford"), ("info", "puma560", "--dh", "--convention", "modified")],
                         ids=" ".join)
def test_robots_and_info_fit(cols: int, args: tuple[str, ...]) -> None:
    out = run(cols, *args)
    check_lines(out, cols)
    if args[0] == "info" and args[1] == "ur5":
        assert "shoulder_lift" in out and "-0.39225" in out      # names and numbers whole
    if args[0] == "info" and args[1] == "so101":
        assert "-8.9766e-09" in out


def test_ik_table_renders_in_an_80_column_console() -> None:
    """The table builder itself at a Rich console width of 80: the compact layout fits, nothing cut."""
    from armkit.cli.common import natural_width
    from armkit.cli.ik import _rows, _table

    r = armkit.load("fighter")
    rows = _rows(r, armkit.ik_all(r, [24.861, 14.353, 187.181]))
    t = _table(r, rows, "t", True, compact=True)
    assert natural_width(t) <= 80
    buf = io.StringIO()
    Console(file=buf, width=80, no_color=True).print(t)
    check_lines(buf.getvalue(), 80)
    assert "…" not in buf.getvalue()


# ---- every other table the CLI prints, at 60, 80 and 120 columns -------------------------------------------

NUMBER = re.compile(r"(?<![\w.])[-+]?\d+(?:\.\d+)?(?:e[-+]\d+)?(?![\w.])")


def numbers_in(text: str) -> list[float]:
    """Every whole number token of the output."""
    return [float(m) for m in NUMBER.findall(text)]


def check_no_cut(text: str, cols: int) -> None:
    """Nothing is cut (no ellipsis), no line is wider than ``cols``, no table cell holds a piece of a number and no
    line ends inside a number that the next line continues (a digit, '.' or 'e' followed by a line starting with
    a digit)."""
    check_lines(text, cols)
    assert "…" not in text, text
    lines = text.splitlines()
    for a, b in zip(lines, lines[1:]):
        if a.startswith("│") or b.startswith("│"):
            continue
        assert not (re.search(r"[\d.e]$", a) and re.match(r"\d", b)), f"number broken across lines: {a!r} / {b!r}"


def has_value(text: str, value: float, rel: float = 5e-4, abs_: float = 5e-4) -> bool:
    return any(abs(v - value) <= max(abs_, rel * abs(value)) for v in numbers_in(text))


WIDTHS = [60, 80, 120]
Q_PUMA = ("10", "20", "30", "40", "50", "60")


@pytest.mark.parametrize("cols", WIDTHS)
@pytest.mark.parametrize("robot,q", [("fighter", ("30", "45", "60")), ("puma560", Q_PUMA), ("so101", ("10",) * 5)],
                         ids=lambda v: v if isinstance(v, str) else "q")
def test_fk_fits_and_shows_every_coordinate(cols: int, robot: str, q: tuple[str, ...]) -> None:
    out = run(cols, "fk", robot, *q, "--deg")
    check_no_cut(out, cols)
    r = armkit.load(robot)
    qv = np.radians([float(v) for v in q])
    T = armkit.fk(r, qv)
    for v in T[:3, :].ravel():                                  # the pose, whole, 6 decimals
        assert has_value(out, v, abs_=2e-6), (v, out)
    for f in armkit.kinematics.fk_frames(r, qv):                # every joint origin, 3 decimals
        for v in f[:3, 3]:
            assert has_value(out, v, abs_=2e-3), (v, out)


@pytest.mark.parametrize("cols", WIDTHS)
@pytest.mark.parametrize("robot,q", [("fighter", ("30", "45", "60")), ("puma560", Q_PUMA), ("ur5", Q_PUMA),
                                     ("panda", ("10", "-20", "30", "-90", "50", "60", "70"))],
                         ids=lambda v: v if isinstance(v, str) else "q")
def test_jacobian_fits_and_every_entry_is_whole(cols: int, robot: str, q: tuple[str, ...]) -> None:
    out = run(cols, "jacobian", robot, *q, "--deg")
    check_no_cut(out, cols)
    r = armkit.load(robot)
    J = armkit.jacobian(r, np.radians([float(v) for v in q]))
    for v in J.ravel():                                          # 4 significant digits at least
        assert has_value(out, v, rel=6e-4, abs_=1e-6), (v, out)


_ANALYSED: dict[tuple, object] = {}


def _analysed_once(analyze):
    """``analyze`` (:func:`analyze_singularities`) remembered per robot and arguments: ``armkit singular ROBOT`` at
    each width prints the same analysis (its default rng is fixed), and puma560's costs sympy seconds each time."""
    def once(robot: armkit.Robot, *args, **kwargs):
        # the command hands over its derivation (a new, equal object each time): the robot stands for it
        key = (robot.name, robot.convention, np.asarray(robot.dh_table()).tobytes(),
               tuple(a for a in args if not hasattr(a, "links")), tuple(sorted(kwargs.items())))
        if key not in _ANALYSED:
            _ANALYSED[key] = analyze(robot, *args, **kwargs)
        return _ANALYSED[key]
    return once


@pytest.mark.parametrize("cols", WIDTHS)
@pytest.mark.parametrize("args", [("singular", "fighter"), ("singular", "puma560"), ("singular", "planar2"),
                                  ("velocity", "fighter", "30", "45", "60", "--deg", "--ee-vel", "10,0,0"),
                                  ("velocity", "panda", "0", "-20", "0", "-90", "0", "70", "0", "--deg",
                                   "--ee-vel", "0.1,0,0,0,0,0.2"),
                                  ("traj", "fighter", "--joint", "0,0,0", "30,45,60", "--deg"),
                                  ("traj", "planar2", "--line", "1.2,0.2", "0.6,0.9", "--steps", "20"),
                                  ("workspace", "planar2", "--samples", "2000"),
                                  ("derive", "planar2"), ("derive", "fighter"),
                                  ("ik", "ur5", "0.4", "0.1", "0.5", "--method", "lm", "--trace")],
                         ids=lambda a: "-".join(a[:2]))
def test_other_tables_fit(cols: int, args: tuple[str, ...], monkeypatch: pytest.MonkeyPatch) -> None:
    if args[0] == "singular":       # the analysis does not depend on the width: analysed once per robot, printed 3x
        from armkit.analysis import singularity

        monkeypatch.setattr(singularity, "analyze_singularities", _analysed_once(singularity.analyze_singularities))
    out = run(cols, *args)
    check_no_cut(out, cols)
    if args[0] == "velocity" and args[1] == "fighter":
        r = armkit.load("fighter")
        qd = np.linalg.pinv(armkit.jacobian(r, np.radians([30, 45, 60]))[:3]) @ [10, 0, 0]
        for v in qd:
            assert has_value(out, v, rel=1e-5), (v, out)
            assert has_value(out, np.degrees(v), rel=1e-5), (v, out)
    if args[0] == "singular" and args[1] == "fighter":
        assert "180.0000°" in out and "0.0000°" in out


@pytest.fixture(scope="module")
def ur5_map(tmp_path_factory):
    d = tmp_path_factory.mktemp("reach")
    store = d / "ur5.zarr"
    res = runner.invoke(app, ["reach", "build", "ur5", "-o", str(store), "--resolution", "0.2", "--orientations",
                              "6", "--samples", "20000"])
    assert res.exit_code == 0, res.output
    tasks = d / "tasks.csv"
    tasks.write_text("0.4,0.1,0.3\n0.3,-0.2,0.4\n0.5,0,0.2\n")
    return store, tasks


@pytest.mark.parametrize("cols", WIDTHS)
def test_reach_tables_fit(cols: int, ur5_map) -> None:
    import json

    store, tasks = ur5_map
    out = run(cols, "reach", "show", str(store))
    check_no_cut(out, cols)
    assert "546" in out and "208" in out                          # cells, reachable cells, whole
    out = run(cols, "reach", "base", str(store), str(tasks), "--top", "3")
    check_no_cut(out, cols)
    ranking = json.loads(runner.invoke(app, ["reach", "base", str(store), str(tasks), "--top", "3",
                                             "--json"]).stdout)
    rows = ranking["ranking"] if isinstance(ranking, dict) and "ranking" in ranking else ranking
    for row in rows:
        assert has_value(out, row["x"], rel=1e-3) and has_value(out, row["y"], rel=1e-3), (row, out)
    check_no_cut(run(cols, "reach", "query", str(store), "0.4", "0.1", "0.3"), cols)
