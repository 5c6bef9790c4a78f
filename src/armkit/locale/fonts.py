"""Letters in pictures: the font each language needs for matplotlib, or English labels with one warning.

A label drawn with a font that lacks its letters shows empty boxes ("tofu"): Hangul in DejaVu Sans.
So the plots translate their labels with :func:`plot_text` (imported as ``_`` in the drawing
modules, so that ``pybabel extract`` finds them), which uses :func:`plot_language`:

- the user's language when its letters need no font of their own (English: the row of
  :data:`armkit.locale.languages.TABLE` has ``fonts=None``);
- the user's language when a font its row names is installed (for Korean NanumGothic first, then the
  other families of the row, then any font whose name has one of the row's ``family_words``);
  matplotlib is told to use it;
- English, with one warning that says how to install the font (the row's Debian package), when none
  is found.

``make fonts`` (run by ``make test`` and ``make demo``) installs the Debian packages of
:func:`missing_packages` (``python -m armkit.locale.fonts`` prints them).

>>> plot_text("time (s)") in ("time (s)", "시간 (s)")
True
"""

from __future__ import annotations

import sys
from functools import lru_cache
from typing import Callable

from . import N_, current_language, translate
from .languages import HANGUL, SOURCE, TABLE, Fonts

__all__ = ["KOREAN_FONTS", "FALLBACK", "font_for", "korean_font", "plot_language", "plot_text", "install_hint",
           "missing_packages", "INSTALL_HINT"]

KOREAN_FONTS = HANGUL.families
"""Fonts with Hangul, in order of preference (the first installed one is used): the Korean row's."""

INSTALL_HINT = f"sudo apt-get install {HANGUL.debian}"
"""The Korean row's hint (:func:`install_hint`)."""

FALLBACK = ("DejaVu Sans",)
"""Fonts after a language's own in matplotlib's list: signs its font lacks (``⁷``, ``✓``, ``ᵀ``) come from them
(matplotlib falls back glyph by glyph through ``font.family`` when it names families, not through ``sans-serif``).
DejaVu Sans comes with matplotlib."""

_WARNED: list[bool] = []


def _say(text: str) -> None:
    """Print a warning line to stderr (the command line's ``warning:`` label, in the user's language)."""
    sys.stderr.write(translate(N_("warning:"), current_language()) + " " + text + "\n")


WARN: list[Callable[[str], None]] = [_say]
"""Where the missing-font warning goes (the first callable; tests replace it)."""


def install_hint(lang: str) -> str:
    """The command that installs the font of ``lang`` on Debian or Ubuntu (``""`` when it needs none)."""
    fonts = TABLE[lang].fonts if lang in TABLE else None
    return f"sudo apt-get install {fonts.debian}" if fonts is not None else ""


def _installed(fonts: Fonts) -> str | None:
    """The first family of ``fonts`` that matplotlib can use, else one whose name has a ``family_words`` word.

    Looks in matplotlib's font list, then among the system's font files (a font installed after
    matplotlib built its cache is added to it).
    """
    from matplotlib import font_manager as fm

    def known() -> set[str]:
        return {f.name for f in fm.fontManager.ttflist}

    names = known()
    for family in fonts.families:
        if family in names:
            return family
    for path in fm.findSystemFonts():
        low = path.lower().replace("-", "").replace("_", "")
        if any(w in low for w in fonts.file_words) and low.endswith((".ttf", ".otf", ".ttc")):
            try:
                fm.fontManager.addfont(path)
            except (OSError, RuntimeError, ValueError):
                continue
    names = known()
    for family in fonts.families:
        if family in names:
            return family
    return next((n for n in sorted(names) if any(w in n for w in fonts.family_words)), None)


@lru_cache(maxsize=None)
def font_for(lang: str) -> str | None:
    """The family name of an installed font that draws ``lang``'s letters, or ``None``; ``""`` when the language
    needs no font of its own (matplotlib's default draws it)."""
    fonts = TABLE[lang].fonts if lang in TABLE else None
    return "" if fonts is None else _installed(fonts)


def korean_font() -> str | None:
    """:func:`font_for` Korean: the family name of an installed font with Hangul, or ``None``."""
    return font_for("ko")


def missing_packages() -> list[str]:
    """The Debian packages of the languages whose font is not installed (what ``make fonts`` installs)."""
    return sorted({row.fonts.debian for code, row in TABLE.items() if row.fonts is not None and not font_for(code)})


def plot_language() -> str:
    """The language of the pictures: the user's (:func:`armkit.locale.current_language`), except a language whose
    font is missing, which falls back to English with one warning (never boxes instead of letters). With a font of
    its own, matplotlib's font list is that font, then :data:`FALLBACK` (minus signs drawn as hyphens, which every
    font has)."""
    lang = current_language()
    if lang == SOURCE or lang not in TABLE or TABLE[lang].fonts is None:
        return lang
    font = font_for(lang)
    if font is None:
        if not _WARNED:
            _WARNED.append(True)
            WARN[0](translate(N_("no {script} font found, so the pictures are labelled in English; on Debian or "
                                 "Ubuntu install one with {command} (or {make} in armkit's folder)"), lang,
                              script=TABLE[lang].fonts.script, command=install_hint(lang),  # type: ignore[union-attr]
                              make="make fonts"))
        return SOURCE
    import matplotlib

    rc = matplotlib.rcParams
    families = list(rc["font.sans-serif"])
    if families[:1] != [font]:
        rc["font.sans-serif"] = [font] + [f for f in families if f != font]
    chain = [font] + [f for f in FALLBACK if f != font]
    if list(rc["font.family"]) != chain:     # named families: matplotlib takes a glyph the font lacks from the next
        rc["font.family"] = chain
        rc["axes.unicode_minus"] = False
    return lang


def plot_text(text: str, /, **fields: object) -> str:
    """A picture's label in :func:`plot_language`, formatted with ``fields`` (see :func:`armkit.locale.translate`).

    Drawing modules import it as ``_`` so that ``pybabel extract`` finds their labels.
    """
    return translate(text, plot_language(), **fields)


if __name__ == "__main__":      # ``make fonts``: the Debian packages to install, one a line
    for package in missing_packages():
        print(package)
