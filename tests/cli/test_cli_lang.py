"""Issue 11: the command line's common messages from a gettext catalogue (Babel), English and Korean, chosen by
--lang, then ARMKIT_LANG, then the locale (LC_ALL, LC_MESSAGES, LANG)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from typer.testing import CliRunner

import armkit
from armkit.cli import app

runner = CliRunner()
LOCALE = Path(armkit.__file__).parent / "locale"
NO_LOCALE = {"LC_ALL": None, "LC_MESSAGES": None, "LANG": None, "ARMKIT_LANG": None, "COLUMNS": "200"}


def run(*args: str, **env: str | None):
    return runner.invoke(app, list(args), env={**NO_LOCALE, **env})


@pytest.mark.parametrize("args, env", [
    (("--lang", "ko"), {}), (("--lang=ko",), {}), ((), {"ARMKIT_LANG": "ko"}), ((), {"LANG": "ko_KR.UTF-8"}),
    ((), {"LC_ALL": "ko_KR.UTF-8", "LANG": "en_US.UTF-8"}), (("--lang", "ko"), {"ARMKIT_LANG": "en"}),
    ((), {"ARMKIT_LANG": "ko", "LANG": "en_US.UTF-8"}),
])
def test_korean_chosen_by_flag_then_env_then_locale(args, env):
    res = run("fk", "fighter", "1", "x", "2", *args, **env)
    assert res.exit_code == 2
    assert res.stderr.strip() == "오류: 관절 값: 'x'는 숫자가 아닙니다"


@pytest.mark.parametrize("args, env", [((), {}), (("--lang", "en"), {"ARMKIT_LANG": "ko"}),
                                       ((), {"ARMKIT_LANG": "en", "LANG": "ko_KR.UTF-8"}),
                                       ((), {"LANG": "C.UTF-8"})])
def test_english_otherwise(args, env):
    res = run("fk", "fighter", "1", "x", "2", *args, **env)
    assert res.exit_code == 2 and res.stderr.strip() == "error: joint values: 'x' is not a number"


def test_korean_limit_warning_and_deg_hint():
    res = run("fk", "fighter", "30", "45", "60", "--lang", "ko")
    assert res.exit_code == 0
    err = res.stderr
    assert err.startswith("경고: 관절 한계를 벗어납니다: yaw = 1718.873 deg(한계 -180.000 ~ 180.000 deg)")
    assert "--deg를 빠뜨리지 않았나요? (30 45 60을 도 단위로 읽으면 한계 안입니다)" in err
    assert run("fk", "fighter", "1", "2", "--lang", "ko").stderr.strip() == \
        "오류: 로봇 'fighter'의 관절은 3개(yaw, shoulder, elbow)인데 값은 2개입니다"
    assert "목표 좌표: 'y'는 숫자가 아닙니다" in run("ik", "fighter", "1", "y", "2", "--lang", "ko").stderr


def test_bad_lang_is_exit_2():
    res = run("fk", "fighter", "0", "0", "0", "--lang", "fr")
    assert res.exit_code == 2 and "--lang must be one of en, ko, got 'fr'" in res.stderr


def test_commands_with_their_own_lang_still_get_it():
    res = runner.invoke(app, ["--lang", "ko", "shell", "fighter", "--no-plot"], input="theta4 = 3\nexit\n",
                        env=NO_LOCALE)
    assert res.exit_code == 0 and "'theta4'라는 관절이 없습니다" in res.output


def test_user_text_stays_plain_in_korean():
    res = run("fk", "fighter", "[red]x[/red]", "1", "2", "--lang", "ko")
    assert res.exit_code == 2 and "'[red]x[/red]'는 숫자가 아닙니다" in res.stderr


# Korean entries that rebuild the English sentence from other fields (the solver's English sentence is replaced
# by the reason and the residual)
REBUILT = {"{reason}: {message}"}
# English words a Korean entry may keep: options, units, the shell's commands and the symbols of its help text
# (identifiers a user types), file suffixes
KEPT = {"en", "ko", "deg", "rad", "mm", "tool", "lang", "strict", "armkit", "help", "exit", "quit", "goto",
        "branch", "auto", "home", "limits", "ground", "box", "clear", "scene", "units", "show", "q", "theta",
        "pi", "x", "y", "z", "w", "roll", "pitch", "yaw", "phi", "Ctrl", "D", "X", "Y", "Z", "png", "pdf", "svg",
        "gif", "mp4", "html", "csv", "json", "toml", "urdf", "output", "o", "elbow", "up", "down",   # + branch names
        "info", "DH", "Craig", "xyz", "rpy", "URDF", "TOML", "v", "sqrt", "det", "J", "T", "m", "lm", "CCD",
        "circular", "parabolic", "ik", "fk", "mode",
        "s", "r", "t", "A", "n", "vx", "vy", "vz", "wx", "wy", "wz", "lambda",   # + units and symbols of formulas
        "Zarr", "SO", "LeRobot", "Python", "NumPy", "Numba", "CSV", "PNG", "IP", "NaN", "JSON", "UTF", "MB",
        "FK", "N",
        # robot and scene files' element, attribute and key names, arguments and variables a user writes (issue 21)
        "robot", "joint", "joints", "link", "links", "limit", "lower", "upper", "origin", "axis", "mimic", "geometry",
        "mesh", "sphere", "cylinder", "filename", "type", "unit", "convention", "frame", "base", "tip", "mask",
        "direction", "method", "fixed", "allow", "outside", "out", "dtype", "float", "True", "ARMKIT", "PACKAGE", "PATH",
        "Joint", "Link", "XML", "CLI", "IK", "FABRIK", "UR", "Puma", "R", "C", "e", "all", "i", "names", "init", "py"}   # + software, formats, protocols, NaN      # + commands, formats, formulas and their symbols, methods, option values


def _marked_messages(root: Path) -> set[tuple[str | None, str]]:
    """(context, msgid) of what `pybabel extract -F babel.cfg` finds: every _(), N_() and NC_() in the folders
    babel.cfg names."""
    from babel.messages.extract import extract_from_dir

    patterns = re.findall(r"^\[python: (.+)\]", (root / "babel.cfg").read_text(), re.M)
    method_map = [(p, "python") for p in patterns]
    keywords = {"_": None, "N_": None, "NC_": ((1, "c"), 2)}
    return {(m[4], m[2]) for m in extract_from_dir(str(root), method_map=method_map, keywords=keywords)
            if isinstance(m[2], str)}


def test_catalogue_is_complete_and_korean():
    """Every message marked _() / N_() / NC_() (babel.cfg: command line, shell, plots, view) is in the Korean
    catalogue, translated, with no placeholder the English lacks, and no English word but options, units,
    commands and placeholders."""
    pytest.importorskip("babel.messages")
    from babel.messages.pofile import read_po

    root = Path(armkit.__file__).parents[2]
    if not (root / "babel.cfg").is_file():
        pytest.skip("not a source checkout")
    marked = _marked_messages(root)
    with (LOCALE / "ko/LC_MESSAGES/armkit.po").open("rb") as f:
        catalogue = {(m.context, m.id): m.string for m in read_po(f) if m.id and not m.fuzzy}
    assert marked <= set(catalogue), sorted(marked - set(catalogue), key=str)
    for key in marked:
        msgid, ko = key[1], catalogue[key]
        assert ko, f"untranslated: {msgid!r}"
        fields = lambda t: set(re.findall(r"\{(\w+)", t))  # noqa: E731
        if msgid not in REBUILT:
            assert fields(ko) <= fields(msgid), (msgid, ko)
        # placeholders, options, values typed, file names and paths
        text = re.sub(r"\{[^}]*\}|--?[A-Za-z][\w-]*|'[^']*'|[\w/]*\.[a-z0-9]+\b", "", ko)
        words = [re.sub(r"\d+$", "", w) for w in re.findall(r"[A-Za-z]+\d*", text)]
        assert set(words) <= KEPT, (msgid, ko, set(words) - KEPT)


def test_compiled_catalogue_is_current():
    """make locale (run by make test) compiles the .po; without it the .po is compiled in memory (never stale)."""
    from armkit.locale import _catalogue

    _catalogue.cache_clear()
    assert _catalogue("ko").gettext("error:") == "오류:"


def test_a_commands_language_and_printer_end_with_it():
    """A program (or a test) that calls the app in-process goes on after the command: --lang ko and the command
    line's warning printer were left set, so a picture the library made afterwards had Korean labels (a test of
    derive's picture failed after a Korean command had run in the same worker). After a command, its success and
    its error alike, the language is the one before it and warnings print as before."""
    import warnings

    from typer.testing import CliRunner

    from armkit.cli import app
    from armkit.locale import current_language

    before_lang, before_show = current_language(), warnings.showwarning
    for args, code in ((["info", "planar2", "--lang", "ko"], 0), (["ik", "planar2", "9", "9", "--lang", "ko"], 1),
                       (["fk", "planar2", "x", "--lang", "ko"], 2)):
        res = CliRunner().invoke(app, args)
        assert res.exit_code == code, res.output
        assert current_language() == before_lang
        assert warnings.showwarning is before_show
