"""``armkit reach build|show|query|base``: outputs, exit codes (0 ok, 1 not reachable, 2 bad input), Korean."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from armkit.cli import app

runner = CliRunner()


@pytest.fixture(scope="module")
def fighter_map(tmp_path_factory) -> Path:
    p = tmp_path_factory.mktemp("reach") / "fighter.zarr"
    r = runner.invoke(app, ["reach", "build", "fighter", "-o", str(p), "--resolution", "10", "--samples",
                            "200000", "--workers", "1", "--json"])
    assert r.exit_code == 0, r.output
    info = json.loads(r.output)
    assert info["robot"] == "fighter" and info["orientations"] == 1 and info["yaw_symmetric"] is True
    return p


def test_build_progress_and_resume_message(tmp_path: Path) -> None:
    p = tmp_path / "p.zarr"
    r = runner.invoke(app, ["reach", "build", "planar2", "-o", str(p), "--samples", "100000", "--workers", "1"])
    assert r.exit_code == 0, r.output
    assert "map written to" in r.output and "ETA" in r.output
    r = runner.invoke(app, ["reach", "build", "planar2", "-o", str(p), "--samples", "100000", "--workers", "1",
                            "--lang", "ko"])
    assert r.exit_code == 0 and "맵 저장" in r.output


def test_show_writes_a_picture(fighter_map: Path, tmp_path: Path) -> None:
    out = tmp_path / "reach.png"
    r = runner.invoke(app, ["reach", "show", str(fighter_map), "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert out.stat().st_size > 10_000 and "picture:" in r.output
    r = runner.invoke(app, ["reach", "show", str(fighter_map), "--json"])
    assert json.loads(r.output)["robot"] == "fighter"


def test_query_exit_codes(fighter_map: Path) -> None:
    # fighter: yaw, 36 mm, pitch, 77.2 mm, pitch, 100 mm; (24.861, 14.353, 187.181) is FK of (30, 45, 60) deg
    r = runner.invoke(app, ["reach", "query", str(fighter_map), "24.861", "14.353", "187.181", "--json"])
    assert r.exit_code == 0, r.output
    assert json.loads(r.output)["reachable"] is True
    r = runner.invoke(app, ["reach", "query", str(fighter_map), "500", "0", "0"])
    assert r.exit_code == 1 and "not reachable" in r.output
    r = runner.invoke(app, ["reach", "query", str(fighter_map), "500", "0", "0", "--lang", "ko"])
    assert r.exit_code == 1 and "도달 불가" in r.output


@pytest.mark.parametrize("args, match", [
    (["query", "{map}", "1", "2"], "position needs 3 numbers"),
    (["query", "{map}", "1", "2", "x"], "'x' is not a number"),
    (["query", "{map}", "1", "2", "3", "--rpy", "1,2"], "--rpy needs 3 numbers"),
    (["query", "{map}", "1", "2", "3", "--lang", "fr"], "--lang must be one of en, ko"),
    (["query", "{tmp}/nothing.zarr", "1", "2", "3"], "no reachability map"),
    (["show", "{map}", "-o", "{tmp}/a.gif"], "--output must end in"),
    (["build", "fighter", "-o", "{tmp}/b.zarr", "--resolution", "-1"], "resolution must be a positive length"),
    (["build", "fighter", "-o", "{tmp}/b.zarr", "--method", "guess"], "--method must be fk or ik"),
    (["build", "no-such-arm", "-o", "{tmp}/b.zarr"], "unknown robot"),
    (["base", "{map}", "{tmp}/missing.csv"], "task file .* not found"),
    # a name longer than the system takes (ENAMETOOLONG; a 300-example fuzz run found the traceback)
    (["show", "{tmp}/" + "x" * 300], "no reachability map at"),
    (["query", "{tmp}/" + "x" * 300, "1", "2", "3"], "no reachability map at"),
    (["build", "fighter", "-o", "{tmp}/" + "y" * 300 + ".zarr"], r"cannot use '.*\.zarr': the name is too long"),
    (["build", "fighter", "-o", "{tmp}/" + "y" * 300 + ".zarr", "--lang", "ko"], "사용할 수 없습니다: 이름이 너무 깁니다"),
])
def test_bad_input_exits_2(fighter_map: Path, tmp_path: Path, args: list[str], match: str) -> None:
    import re

    words = [a.format(map=fighter_map, tmp=tmp_path) for a in args]
    r = runner.invoke(app, ["reach", *words])
    assert r.exit_code == 2, r.output
    assert re.search(match, r.output), r.output
    assert "Traceback" not in r.output


def test_base_placement_from_csv(fighter_map: Path, tmp_path: Path) -> None:
    tasks = tmp_path / "tasks.csv"
    # three points 150 mm around (400, 0): reachable from a base near (400, 0), not from the origin
    tasks.write_text("x,y,z\n# comment\n550,0,60\n400,150,60\n400,-150,60\n", encoding="utf-8")
    r = runner.invoke(app, ["reach", "base", str(fighter_map), str(tasks), "--top", "3", "--json"])
    assert r.exit_code == 0, r.output
    rows = json.loads(r.output)
    assert len(rows) == 3
    best = rows[0]
    assert best["ik_reached"] == 3 and best["map_reached"] == 3
    bad = tmp_path / "bad.csv"
    bad.write_text("1,2,3\n4,5,oops\n", encoding="utf-8")
    r = runner.invoke(app, ["reach", "base", str(fighter_map), str(bad)])
    assert r.exit_code == 2 and "bad.csv:2: field z" in r.output


def test_os_errors_are_named_in_the_language_or_in_the_systems_words() -> None:
    """The command line's last net for OS errors (armkit.cli.common.os_reason): the errors armkit names are said in
    the current language, any other in the system's own words."""
    import errno

    from armkit.cli.common import os_reason
    from armkit.locale import LANG

    long_name = OSError(errno.ENAMETOOLONG, "File name too long", "x" * 300)
    other = OSError(errno.EIO, "Input/output error", "disk")
    saved = LANG.get("lang")
    try:
        LANG["lang"] = "en"
        assert os_reason(long_name) == "the name is too long"
        assert os_reason(other) == "Input/output error"
        LANG["lang"] = "ko"
        assert os_reason(long_name) == "이름이 너무 깁니다"
        assert os_reason(other) == "Input/output error"
    finally:
        LANG["lang"] = saved
