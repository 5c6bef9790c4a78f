"""Issue 11: Korean labels in pictures only with a Korean font; without one, English labels and one warning that
says how to install the font (never boxes instead of letters)."""

from __future__ import annotations

import pytest

pytest.importorskip("matplotlib")

import matplotlib  # noqa: E402

matplotlib.use("Agg")

import armkit  # noqa: E402
from armkit.locale import LANG, fonts  # noqa: E402


@pytest.fixture
def korean(monkeypatch):
    """Korean as the user's language, the font lookup replaced by the test, the one-time warning re-armed."""
    monkeypatch.setitem(LANG, "lang", "ko")
    monkeypatch.setattr(fonts, "_WARNED", [])
    said: list[str] = []
    monkeypatch.setattr(fonts, "WARN", [said.append])
    monkeypatch.setattr(matplotlib, "rcParams", matplotlib.rcParams.copy())
    return said


def _labels(fig) -> list[str]:
    from matplotlib.text import Text

    return [t.get_text() for t in fig.findobj(Text) if t.get_text()]


def test_without_a_korean_font_pictures_are_english_with_one_warning(korean, monkeypatch):
    monkeypatch.setattr(fonts, "korean_font", lambda: None)
    from armkit.viz.arm import plot_arm

    fig = plot_arm(armkit.load("planar2"), [0.3, 0.4])
    fig2 = plot_arm(armkit.load("planar2"), [[0.3, 0.4], [0.5, -0.4]])
    text = "\n".join(_labels(fig) + _labels(fig2))
    assert "end point (" in text and "2 configurations" in text and "frame x" in text
    assert not any("가" <= c <= "힣" for c in text)          # no Hangul drawn with a font that lacks it
    assert len(korean) == 1                                   # one warning for the whole run, in Korean
    assert "sudo apt-get install fonts-nanum" in korean[0] and "make fonts" in korean[0]
    assert "한글 글꼴이 없어서" in korean[0]
    assert fonts.plot_language() == "en"


def test_with_a_korean_font_pictures_are_korean_in_that_font(korean, monkeypatch):
    monkeypatch.setattr(fonts, "korean_font", lambda: "NanumGothic")
    from armkit.viz.arm import plot_arm

    fig = plot_arm(armkit.load("planar2"), [0.3, 0.4])
    text = "\n".join(_labels(fig))
    assert "끝점 (" in text and "좌표축 x" in text
    assert matplotlib.rcParams["font.sans-serif"][0] == "NanumGothic"
    assert matplotlib.rcParams["axes.unicode_minus"] is False   # a hyphen for the minus sign: every font has it
    assert korean == []


def test_english_users_never_need_the_font(monkeypatch):
    monkeypatch.setitem(LANG, "lang", "en")

    def boom():
        raise AssertionError("the font lookup must not run in English")

    monkeypatch.setattr(fonts, "korean_font", boom)
    assert fonts.plot_text("target") == "target"


def test_the_lookup_finds_an_installed_hangul_font_or_says_none():
    """Against the real font list: a name matplotlib knows, or None (then make fonts installs fonts-nanum)."""
    from matplotlib import font_manager

    fonts.korean_font.cache_clear()
    found = fonts.korean_font()
    assert found is None or found in {f.name for f in font_manager.fontManager.ttflist}
