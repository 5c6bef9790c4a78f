"""Issue 11: Korean that reads as written by a Korean engineer (particles chosen by the word before them,
attached without a space; no English left in the Korean shell but names, units and commands)."""

from __future__ import annotations

import io
import re

import pytest
from rich.console import Console

import armkit
from armkit.locale import MESSAGES, final_consonant, josa, message
from armkit.cli.shell import Shell


@pytest.mark.parametrize("word, pair, expected", [
    ("관절", "을/를", "관절을"), ("해", "을/를", "해를"), ("해", "은/는", "해는"), ("끝점", "이/가", "끝점이"),
    ("관절", "으로/로", "관절로"),            # ㄹ takes 로
    ("목표", "으로/로", "목표로"), ("끝점", "으로/로", "끝점으로"),
    ("0", "으로/로", "0으로"), ("1", "으로/로", "1로"), ("3", "으로/로", "3으로"), ("2", "을/를", "2를"),
    ("6", "이/가", "6이"), ("10", "을/를", "10을"), ("100", "이/가", "100이"), ("1000", "은/는", "1000은"),
    ("0.5", "이/가", "0.5가"), ("45", "이/가", "45가"),
    ("'theta4'", "이라는/라는", "'theta4'라는"), ("'elbow-up'", "이라는/라는", "'elbow-up'이라는"),
    ("goto", "은/는", "goto는"), ("front/elbow-down", "을/를", "front/elbow-down을"), ("elbow", "이/가", "elbow가"),
    ("forearm", "이/가", "forearm이"), ("roll", "으로/로", "roll로"), ("back", "은/는", "back은"),
    ("'mm'", "은/는", "'mm'는"), ("rad", "이/가", "rad이"), ("x", "이라는/라는", "x라는"), ("l", "으로/로", "l로"),
    ("n", "이/가", "n이"), ("m", "으로/로", "m로"), ("fighter", "은/는", "fighter는"), ("puma560", "은/는", "puma560은"),
    ("ur5", "은/는", "ur5는"), ("30°", "이/가", "30°가"), ("'[/]'", "을/를", "'[/]'을(를)"),
])
def test_josa(word, pair, expected):
    assert josa(word, pair) == expected


def test_final_consonant_of_hangul_reads_the_last_syllable():
    assert final_consonant("각") is True and final_consonant("가") is False and final_consonant("말") == "ㄹ"
    assert final_consonant("공간)") is True       # brackets and punctuation after the word are skipped
    assert final_consonant("...") is None


def test_message_attaches_particles_to_placeholders():
    assert message("unknown_joint", "ko", name="theta4", names="a") == "'theta4'라는 관절이 없습니다. 관절: a"
    assert message("branch_unknown", "ko", name="elbow-up", names="a").startswith("'elbow-up'이라는 해가")
    assert message("not_number", "ko", word="abc") == "'abc'는 숫자가 아닙니다"
    assert message("not_number", "ko", word="1e") == "'1e'는 숫자가 아닙니다"
    assert message("unknown", "ko", text="hello") .startswith("'hello'를 이해할 수 없습니다")
    assert message("no_branches", "ko", robot="panda").startswith("panda는 ")
    assert message("no_branches", "ko", robot="iiwa14").startswith("iiwa14는 ")
    assert message("bad_unit", "ko", unit="mm", joint="yaw", kind="revolute") == "단위 'mm'는 yaw 관절(회전 관절)에 맞지 않습니다"
    assert message("bad_unit", "en", unit="mm", joint="yaw", kind="revolute") == "unit 'mm' does not fit joint yaw (revolute)"


# a space between a word and a particle, or the old "을(를)" style: neither belongs in written Korean
SPACED = re.compile(r"[\w'\")\]] (?:을|를|은|는|이|가|으로|로|이라는|라는|의|에|에는|도)(?=[\s.,;)]|$)")
OLD_STYLE = re.compile(r"을\(를\)|은\(는\)|이\(가\)")


def test_korean_catalogue_has_no_spaced_particles():
    for key, texts in MESSAGES.items():
        ko = texts.get("ko", "")
        assert not SPACED.search(ko), (key, ko)
        assert not OLD_STYLE.search(ko), (key, ko)
        assert "도 가능" not in ko, key


SESSION = ["help", "theta4 = 3", "yaw = 400", "q 1 2", "goto 1 2", "goto 300 0 0", "branch elbow-up", "branch",
           "branch front/elbow-up", "branch auto", "theta2 = -30", "units furlongs", "lang xx", "yaw = 3mm",
           "home", "theta1 = 30; theta2 = 45; theta3 = 60", "theta2 = 90/2", "100 50 80", "x = abc", "hello",
           "ground 1 2", "box 1", "limits", "units rad", "show", "exit; home"]
# names, units, commands and symbols that stay as they are in Korean text
ALLOWED = {"armkit", "fighter", "yaw", "shoulder", "elbow", "front", "back", "elbow-up", "elbow-down", "auto",
           "deg", "rad", "mm", "help", "exit", "quit", "goto", "branch", "home", "limits", "ground", "box", "clear",
           "scene", "units", "lang", "en", "ko", "show", "q", "theta", "x", "y", "z", "roll", "pitch", "phi", "pi",
           "Ctrl-D", "Ctrl", "D", "X0", "Y0", "Z0", "X1", "Y1", "Z1", "x0", "y0", "z0", "x1", "y1", "z1", "Z",
           "forearm", "furlongs", "xx", "abc", "hello", "branch", "deg|rad", "en|ko", "auto", "mm", "e", "mode", "ik",
           "fk", "ik|fk"}


def test_korean_shell_session_reads_as_korean():
    sh = Shell(armkit.load("fighter"), lang="ko", plot="none", console=Console(file=io.StringIO(), width=120))
    text = "\n".join(sh.execute(line).text for line in SESSION)
    for word in re.findall(r"[A-Za-z][A-Za-z0-9\-|]*", text):
        parts = [p for p in re.split(r"[-|]", word) if p] if word not in ALLOWED else [word]
        for p in parts:
            assert p in ALLOWED or re.fullmatch(r"(theta|q)\d*", p), (p, word)
    assert "end point" not in text and "joint limit" not in text and "target" not in text
    assert not SPACED.search(text) and not OLD_STYLE.search(text)
    # the examples, now right
    assert "'theta4'라는 관절이 없습니다" in text
    assert "'elbow-up'이라는 해가 없습니다" in text
    assert "모든 관절을 0으로" in text and "goto에 쓸 해" in text
    assert "목표 위치에 도달할 수 없습니다(작업 공간 밖" in text
    assert "관절 한계를 벗어납니다: yaw = 400 (한계 -180 ~ 180 deg)" in text
    assert "x y z 또는 x y z roll pitch yaw 형식" in text


# a particle written right after a placeholder: its form cannot be right for every value ({x:j:을/를} chooses it)
FIXED_PARTICLE = re.compile(r"\{\w+(?:![rsa])?(?::(?!j:)[^{}]*)?\}(?:을|를|은|는|이|가|과|와|으로|로|이라는|라는)(?![가-힣])")


# a particle spaced off the placeholder before it ("{path} 에서")
SPACED_AFTER_FIELD = re.compile(r"\} (?:을|를|은|는|이|가|과|와|으로|로|이라는|라는|의|에|에서|에는)(?=[\s.,;)]|$)")


def test_catalogue_never_hard_codes_a_particle_after_a_placeholder():
    """Every Korean entry of the catalogue (command line, shell, pictures, view): particles after a placeholder are
    chosen by josa, and no particle is spaced off the word before it."""
    from babel.messages.pofile import read_po

    with (armkit.locale.LOCALE_DIR / "ko/LC_MESSAGES/armkit.po").open("rb") as f:
        entries = [m for m in read_po(f) if m.id and m.string]
    assert len(entries) > 300
    for m in entries:
        assert not FIXED_PARTICLE.search(m.string), (m.id, m.string)
        assert not SPACED_AFTER_FIELD.search(m.string), (m.id, m.string)
        assert not OLD_STYLE.search(m.string), (m.id, m.string)
    assert FIXED_PARTICLE.search("{path!r}를 읽을 수 없습니다") and not FIXED_PARTICLE.search("{path!r:j:을/를} 읽")
    assert SPACED_AFTER_FIELD.search("{path} 에서 이어서 만듭니다")


# ------------------------------------------------------------ the one list of languages (issue 21)

def test_the_table_and_the_catalogue_folders_agree():
    """Every language but the source has a catalogue folder, and every catalogue folder is a row of the table."""
    from pathlib import Path

    from armkit.locale import languages

    here = Path(languages.__file__).parent
    folders = {p.parent.parent.name for p in here.glob("*/LC_MESSAGES/armkit.po")}
    assert folders == set(languages.TABLE) - {languages.SOURCE}
    assert list(languages.LANGUAGES)[0] == languages.SOURCE == "en"


@pytest.mark.parametrize("code", ["ko"])
def test_particles_field_says_whether_the_catalogue_attaches_particles(code):
    from armkit.locale import languages

    text = (languages.catalogue_dir(code) / code / "LC_MESSAGES" / "armkit.po").read_text(encoding="utf-8")
    assert languages.TABLE[code].particles == (":j:" in text)


@pytest.mark.parametrize("value, code", [("ko", "ko"), ("KO", "ko"), ("ko_KR.UTF-8", "ko"), ("ko-KR", "ko"),
                                         ("en_GB.UTF-8", "en"), ("C.UTF-8", None), ("fr_FR", None), ("", None),
                                         ("kor", None), (None, None)])
def test_language_of(value, code):
    from armkit.locale.languages import language_of

    assert language_of(value) == code


def test_the_locale_picks_a_language_of_the_table(monkeypatch):
    from armkit.locale import cli_language, default_language

    for var in ("LC_ALL", "LC_MESSAGES", "ARMKIT_LANG"):
        monkeypatch.delenv(var, raising=False)
    monkeypatch.setenv("LANG", "ko_KR.UTF-8")
    assert default_language() == "ko" and cli_language() == "ko"
    monkeypatch.setenv("LANG", "fr_FR.UTF-8")
    assert default_language() == "en"
    monkeypatch.setenv("ARMKIT_LANG", "ko")
    assert cli_language() == "ko" and cli_language("en") == "en"


def test_the_shell_lists_the_languages_of_the_table():
    sh = Shell(armkit.load("fighter"), lang="en", plot="none", console=Console(file=io.StringIO()))
    assert re.search(r"lang en\|ko +language of the messages", sh.execute("help").text)
    bad = sh.execute("lang fr").text
    assert "language must be one of en, ko, got 'fr'" in bad
    sh.lang = "ko"
    assert re.search(r"lang en\|ko +메시지 언어", sh.execute("help").text)


def test_adding_a_language_as_docs_languages_md_shows(capsys):
    """docs/languages.md, "Adding a language": its example runs as written and prints what the page says."""
    from pathlib import Path

    from armkit.locale import LANG, languages

    text = (Path(__file__).resolve().parents[2] / "docs" / "languages.md").read_text(encoding="utf-8")
    section = text[text.index("## Adding a language"):]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    try:
        exec(compile(code, "docs/languages.md", "exec"), {})
    finally:
        languages.TABLE.pop("xx", None)
        LANG["lang"] = None
    assert capsys.readouterr().out.splitlines() == [
        "yebay", "onay ointjay amednay 'wrist'; ethay ointsjay areay yaw, shoulder", "0", "False"]
    assert "xx" not in languages.LANGUAGES and message("bye", "en") == "bye"
