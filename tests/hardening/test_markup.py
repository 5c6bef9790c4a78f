"""Issue 10, item 1: text the user controls is never read as Rich markup nor sent raw to the terminal."""

from __future__ import annotations

import io

import pytest
from rich.console import Console

import armkit
from armkit._text import esc, name_list, plain, shorten
from armkit.cli.shell import Shell

from hardening_helpers import invoke


def test_plain_shows_control_characters_and_keeps_newlines():
    assert plain("a\x1b[31mb\x07\r\n\tc\u202e") == "a\\x1b[31mb\\x07\\x0d\n\tc\\u202e"
    assert esc("[/]x") == "\\[/]x"
    assert name_list(range(3)) == "0, 1, 2"
    assert "(1,000 in all)" in name_list(range(1000))
    assert shorten("x" * 5000).endswith("(3,000 more characters)")


@pytest.mark.parametrize("args", [
    ("info", "{p}"), ("info", "{p}", "--json"), ("fk", "{p}", "10", "20", "--deg"), ("jacobian", "{p}", "0.1", "0.2"),
    ("ik", "{p}", "0.6", "0.3"), ("ik", "{p}", "0.6", "0.3", "--method", "lm"), ("ik", "{p}", "5", "5"),
    ("velocity", "{p}", "0.1", "0.2", "--ee-vel", "0.1,0"), ("traj", "{p}", "--joint", "0,0", "10,10", "--deg"),
    ("workspace", "{p}", "-n", "2000"), ("fk", "{p}", "1", "2", "3"), ("fk", "{p}", "400", "0", "--deg"),
])
def test_hostile_names_print_literally_in_every_command(hostile_robot, args):
    code, out, exc = invoke(*(a.format(p=hostile_robot) for a in args))
    assert exc is None, f"traceback: {exc!r}"
    assert code in (0, 1, 2)
    assert "\x1b" not in out and "\x07" not in out          # no escape sequence reaches the terminal
    if code == 0 and "--json" not in args:
        assert "[/]" in out or "\\x1b" in out              # the name is shown as typed


def test_info_shows_the_whole_name_and_description(hostile_robot):
    code, out, _ = invoke("info", hostile_robot)
    assert code == 0
    assert "[/]arm\\x1b[31m[bold]" in out
    assert "[red]not red[/red] and [/]" in out
    assert "[/]yaw" in out and "[bold]elbow" in out


def test_error_messages_keep_brackets(tmp_path):
    p = tmp_path / "nojoints.toml"
    p.write_text('name = "x"\n', encoding="utf-8")
    code, out, _ = invoke("info", p)
    assert code == 2 and "[[joints]]" in out
    code, out, _ = invoke("fk", "fighter", "1", "2")
    assert code == 2 and "got 2 value(s)" in out
    code, out, _ = invoke("fk", "[/]nonexistent.toml", "1")
    assert code == 2 and "[/]nonexistent.toml" in out


def test_shell_survives_markup_and_escapes():
    buf = io.StringIO()
    sh = Shell(armkit.load("fighter"), lang="en", plot="none", console=Console(file=buf, force_terminal=True))
    out = sh.execute("foo [/]")
    assert out.status == "error" and "foo [/]" in out.text
    out = sh.execute("theta1 = [red]30")
    assert out.status == "error" and "[red]30" in out.text
    out = sh.execute("yaw = 30\x1b[2J")
    assert out.status == "error" and "\x1b" not in out.text
    assert "\x1b[2J" not in buf.getvalue()
    assert "[x y z]" in sh.execute("help").text


def test_shell_with_a_hostile_robot(hostile_robot):
    r = armkit.load(hostile_robot)
    buf = io.StringIO()
    sh = Shell(r, lang="en", plot="none", console=Console(file=buf, width=120))
    for line in ("show", "limits", "branch", "q 10 20", "[0.5 0.3]", "theta1 = 5", "unknown [/] line"):
        assert sh.execute(line).status in ("ok", "info", "error")
    text = buf.getvalue()
    assert "[/]yaw" in text and "\x1b" not in text


def test_help_keeps_bracketed_text():
    code, out, _ = invoke("shell", "--help")
    assert code == 0 and "[100 50 80]" in out
