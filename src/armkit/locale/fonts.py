"""Korean text in pictures: a CJK font for matplotlib, or English labels with one warning.

A Korean label drawn with a font that lacks Hangul shows empty boxes ("tofu"). So the
plots translate their labels with :func:`plot_text` (imported as ``_`` in the drawing
modules, so that ``pybabel extract`` finds them), which uses :func:`plot_language`:

- English when the user's language is English;
- Korean when it is Korean and a Korean font is installed (NanumGothic first, then other
  known Korean fonts, then any font whose name says CJK/KR); matplotlib is told to use it;
- English, with one warning that says how to install the font, when none is found.

``make fonts`` (run by ``make test`` and ``make demo``) installs ``fonts-nanum`` on Debian
and Ubuntu when it is missing.

>>> plot_text("time (s)") in ("time (s)", "시간 (s)")
True
"""

from __future__ import annotations

import sys
from functools import lru_cache
from typing import Callable

from . import N_, current_language, translate

__all__ = ["KOREAN_FONTS", "korean_font", "plot_language", "plot_text", "INSTALL_HINT"]

KOREAN_FONTS = ("NanumGothic", "NanumBarunGothic", "Noto Sans CJK KR", "Noto Sans KR", "Source Han Sans KR",
                "Malgun Gothic", "AppleGothic", "Apple SD Gothic Neo", "UnDotum", "Baekmuk Gulim")
"""Fonts with Hangul, in order of preference (the first installed one is used)."""

INSTALL_HINT = "sudo apt-get install fonts-nanum"

_WARNED: list[bool] = []


def _say(text: str) -> None:
    """Print a warning line to stderr (the command line's ``warning:`` label, in the user's language)."""
    sys.stderr.write(translate(N_("warning:"), current_language()) + " " + text + "\n")


WARN: list[Callable[[str], None]] = [_say]
"""Where the missing-font warning goes (the first callable; tests replace it)."""


@lru_cache(maxsize=1)
def korean_font() -> str | None:
    """The family name of an installed font with Hangul that matplotlib can use, or ``None``.

    Looks in matplotlib's font list, then among the system's font files (a font installed after
    matplotlib built its cache is added to it).
    """
    from matplotlib import font_manager as fm

    def known() -> set[str]:
        return {f.name for f in fm.fontManager.ttflist}

    names = known()
    for family in KOREAN_FONTS:
        if family in names:
            return family
    hangul = ("nanum", "cjk", "notosanskr", "malgun", "applegothic", "undotum", "baekmuk", "sourcehansans")
    for path in fm.findSystemFonts():
        low = path.lower().replace("-", "").replace("_", "")
        if any(h in low for h in hangul) and low.endswith((".ttf", ".otf", ".ttc")):
            try:
                fm.fontManager.addfont(path)
            except (OSError, RuntimeError, ValueError):
                continue
    names = known()
    for family in KOREAN_FONTS:
        if family in names:
            return family
    return next((n for n in sorted(names) if "CJK" in n or n.endswith(" KR") or "Nanum" in n), None)


def plot_language() -> str:
    """The language of the pictures: the user's (:func:`armkit.locale.current_language`), except Korean without
    a Korean font, which falls back to English with one warning (never boxes instead of letters). When Korean,
    matplotlib's sans-serif family starts with the Korean font (minus signs drawn as hyphens, which every font
    has)."""
    lang = current_language()
    if lang == "en":
        return "en"
    font = korean_font()
    if font is None:
        if not _WARNED:
            _WARNED.append(True)
            WARN[0](translate(N_("no Korean font found, so the pictures are labelled in English; on Debian or "
                                 "Ubuntu install one with {command} (or {make} in armkit's folder)"), lang,
                              command=INSTALL_HINT, make="make fonts"))
        return "en"
    import matplotlib

    families = list(matplotlib.rcParams["font.sans-serif"])
    if families[:1] != [font]:
        matplotlib.rcParams["font.sans-serif"] = [font] + [f for f in families if f != font]
        matplotlib.rcParams["font.family"] = "sans-serif"
        matplotlib.rcParams["axes.unicode_minus"] = False
    return lang


def plot_text(text: str, /, **fields: object) -> str:
    """A picture's label in :func:`plot_language`, formatted with ``fields`` (see :func:`armkit.locale.translate`).

    Drawing modules import it as ``_`` so that ``pybabel extract`` finds their labels.
    """
    return translate(text, plot_language(), **fields)
