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
    monkeypatch.setattr(fonts, "font_for", lambda lang: None)
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
    monkeypatch.setattr(fonts, "font_for", lambda lang: "NanumGothic" if lang == "ko" else None)
    from armkit.viz.arm import plot_arm

    fig = plot_arm(armkit.load("planar2"), [0.3, 0.4])
    text = "\n".join(_labels(fig))
    assert "끝점 (" in text and "좌표축 x" in text
    assert matplotlib.rcParams["font.sans-serif"][0] == "NanumGothic"
    assert list(matplotlib.rcParams["font.family"]) == ["NanumGothic", "DejaVu Sans"]   # signs Nanum lacks: DejaVu
    assert matplotlib.rcParams["axes.unicode_minus"] is False   # a hyphen for the minus sign: every font has it
    assert korean == []


def test_english_users_never_need_the_font(monkeypatch):
    monkeypatch.setitem(LANG, "lang", "en")

    def boom(lang):
        raise AssertionError("the font lookup must not run in English")

    monkeypatch.setattr(fonts, "font_for", boom)
    assert fonts.plot_text("target") == "target"


def test_the_lookup_finds_an_installed_hangul_font_or_says_none():
    """Against the real font list: a name matplotlib knows, or None (then make fonts installs fonts-nanum)."""
    from matplotlib import font_manager

    fonts.font_for.cache_clear()
    found = fonts.korean_font()
    assert found is None or found in {f.name for f in font_manager.fontManager.ttflist}


# ------------------------------------------------------------ the language table's font needs (issue 21)

def _po_texts(code: str) -> list[str]:
    from babel.messages.pofile import read_po

    from armkit.locale.languages import catalogue_dir

    with (catalogue_dir(code) / code / "LC_MESSAGES" / "armkit.po").open("rb") as f:
        return [m.string if isinstance(m.string, str) else "".join(m.string) for m in read_po(f) if m.id]


@pytest.mark.parametrize("code", [c for c, row in __import__("armkit.locale.languages", fromlist=["TABLE"]).TABLE.items()
                                  if row.fonts is not None])
def test_the_font_a_language_names_draws_every_letter_of_its_catalogue(code):
    """Each letter of the catalogue in the row's glyph ranges is in the font found for it; every other sign is in
    that font or in DejaVu Sans, matplotlib's default that stays behind it (no box anywhere)."""
    from matplotlib import font_manager
    from matplotlib.ft2font import FT2Font

    from armkit.locale.languages import TABLE

    row = TABLE[code]
    fonts.font_for.cache_clear()
    family = fonts.font_for(code)
    if family is None:
        pytest.skip(f"no font for {code} installed here ({fonts.install_hint(code)}; make fonts does it)")
    own = FT2Font(font_manager.findfont(family, fallback_to_default=False))
    default = FT2Font(font_manager.findfont("DejaVu Sans"))
    texts = _po_texts(code) + [row.fonts.sample, row.native, row.word, row.fonts.script]
    letters = {c for t in texts for c in t if c.isprintable() and not c.isspace()}
    assert any(row.fonts.needs(c) for c in letters)       # the ranges name letters the catalogue uses
    missing = sorted(c for c in letters if own.get_char_index(ord(c)) == 0
                     and (row.fonts.needs(c) or default.get_char_index(ord(c)) == 0))
    assert missing == []


def test_needs_reads_the_glyph_ranges():
    from armkit.locale.languages import HANGUL

    assert HANGUL.needs("관절") and HANGUL.needs("ㄹ") and HANGUL.needs("x 가")
    assert not HANGUL.needs("joint ±ω ✓ 10⁷")


def test_missing_packages_names_the_debian_package_of_a_missing_font(monkeypatch):
    """``make fonts`` installs what this prints: the Korean row's package when no Hangul font is found, else
    nothing."""
    monkeypatch.setattr(fonts, "font_for", lambda lang: None)
    assert fonts.missing_packages() == ["fonts-nanum"]
    monkeypatch.setattr(fonts, "font_for", lambda lang: "NanumGothic")
    assert fonts.missing_packages() == []


def test_a_korean_picture_has_no_missing_glyph(korean):
    """With the Korean font found here, Hangul and the signs it lacks (the workspace title's 10⁷, ✓, ᵀ) are all
    drawn: matplotlib warns "Glyph ... missing" for any it would draw as a box."""
    import io
    import warnings

    from matplotlib.figure import Figure

    fonts.font_for.cache_clear()
    if fonts.font_for("ko") is None:
        pytest.skip("no Korean font installed here (make fonts installs one)")
    assert fonts.plot_language() == "ko"
    fig = Figure()
    fig.text(0.1, 0.5, "관절 자세 10⁷ ✓ Jᵀ ⚠ ±π —")
    with warnings.catch_warnings():
        warnings.simplefilter("error")          # a missing glyph fails the test
        fig.savefig(io.BytesIO(), format="png")
