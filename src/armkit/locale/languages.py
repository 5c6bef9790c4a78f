"""The one list of the languages armkit speaks, with what each needs to be drawn (docs/languages.md).

Every place that asks "which languages are there?" reads :data:`TABLE`: the command line's
``--lang`` checks and help, the shell's ``lang`` command, the browser view's language list,
the locale lookup (``LANG=ko_KR.UTF-8``) and the plots' font set-up (:mod:`armkit.locale.fonts`).
A language is one :class:`Language` row plus its catalogue ``<code>/LC_MESSAGES/armkit.po``;
English is the language the code is written in and needs no catalogue.

>>> [lang.code for lang in TABLE.values()]
['en', 'ko']
>>> TABLE["ko"].native, TABLE["ko"].fonts.debian
('한국어', 'fonts-nanum')
>>> language_of("ko_KR.UTF-8"), language_of("C.UTF-8"), language_of("KO")
('ko', None, 'ko')
>>> "ko" in LANGUAGES, ", ".join(LANGUAGES)
(True, 'en, ko')
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterator, Optional, Sequence, overload

from ..errors import ArgumentError

__all__ = ["Fonts", "Language", "TABLE", "LANGUAGES", "SOURCE", "add", "remove", "language_of", "choices",
           "catalogue_dir"]

SOURCE = "en"
"""The language the messages are written in, in the code (every other language is read from a catalogue)."""


@dataclass(frozen=True)
class Fonts:
    """What a picture needs to draw a language's letters (matplotlib's own DejaVu Sans draws Latin, Greek and
    Cyrillic; a language written in other letters names fonts here).

    Attributes
    ----------
    families : tuple of str
        Font family names, in order of preference: the first one installed is used.
    file_words : tuple of str
        Words in a font *file's* name that say it has the letters (lower case, no ``-`` or ``_``): a font
        installed after matplotlib built its cache is found by its file and added.
    family_words : tuple of str
        Words in a family name that say it has the letters (the last resort, e.g. ``CJK``).
    debian : str
        The Debian/Ubuntu package that installs the first family (``make fonts`` installs it).
    glyphs : tuple of (int, int)
        The code point ranges (inclusive) of the language's own letters, which the font must draw, e.g. Hangul
        syllables ``0xAC00-0xD7A3``. Other signs of its messages (``±``, ``ω``, ``✓``, ``⁷``) may come from
        matplotlib's DejaVu Sans, which stays second in the font list (matplotlib falls back per glyph).
    sample : str
        A short text in those letters (a test draws it and checks no glyph is missing).
    script : str
        The letters' name in the language itself (``한글``): the missing-font warning names them.
    """

    families: tuple[str, ...]
    debian: str
    glyphs: tuple[tuple[int, int], ...]
    sample: str
    script: str
    file_words: tuple[str, ...] = ()
    family_words: tuple[str, ...] = ()

    def needs(self, text: str) -> bool:
        """Whether some letter of ``text`` lies in :attr:`glyphs` (text that needs this font)."""
        return any(lo <= ord(c) <= hi for c in text for lo, hi in self.glyphs)


@dataclass(frozen=True)
class Language:
    """One language: its code, its name in itself, its word for "language", and its font needs.

    Attributes
    ----------
    code : str
        The catalogue's folder name and what ``--lang`` takes (``ko``); a locale such as ``ko_KR.UTF-8``
        selects it by this prefix.
    native : str
        The language's name in itself (``한국어``): the browser view's language list shows it.
    word : str
        The word for "language" in it (``언어``): the view's list is titled with every language's word.
    fonts : Fonts or None
        What pictures need to draw it; ``None`` when matplotlib's default font draws it (English).
    particles : bool
        Whether its messages attach particles by the word before them (Korean ``{x:j:을/를}``, see
        :func:`armkit.locale.josa`).
    folder : Path or None
        Where its catalogue folder ``<code>/LC_MESSAGES/armkit.po`` lies; ``None``: ``armkit/locale`` (a language
        added from outside armkit, see :func:`add`, may keep its catalogue elsewhere).
    """

    code: str
    native: str
    word: str
    fonts: Optional[Fonts] = None
    particles: bool = False
    folder: Optional[Path] = field(default=None, compare=False)


HANGUL = Fonts(
    families=("NanumGothic", "NanumBarunGothic", "Noto Sans CJK KR", "Noto Sans KR", "Source Han Sans KR",
              "Malgun Gothic", "AppleGothic", "Apple SD Gothic Neo", "UnDotum", "Baekmuk Gulim"),
    debian="fonts-nanum",
    glyphs=((0xAC00, 0xD7A3),      # Hangul syllables (가-힣): every Korean message
            (0x1100, 0x11FF),      # Hangul jamo
            (0x3130, 0x318F)),     # compatibility jamo (ㄹ in the particle notes)
    sample="관절 자세 10⁷ — 한국어",
    script="한글",
    file_words=("nanum", "cjk", "notosanskr", "malgun", "applegothic", "undotum", "baekmuk", "sourcehansans"),
    family_words=("CJK", " KR", "Nanum"),
)
"""Fonts with Hangul (Korean)."""

TABLE: dict[str, Language] = {
    "en": Language("en", "English", "language"),
    "ko": Language("ko", "한국어", "언어", fonts=HANGUL, particles=True),
}
"""Every language armkit speaks, by code, in the order lists show them (English, the source, first)."""


class _Codes(Sequence[str]):
    """The codes of :data:`TABLE`, read at each use (a language added later is in it)."""

    @overload
    def __getitem__(self, i: int) -> str: ...

    @overload
    def __getitem__(self, i: slice) -> Sequence[str]: ...

    def __getitem__(self, i):  # type: ignore[no-untyped-def]
        return tuple(TABLE)[i]

    def __len__(self) -> int:
        return len(TABLE)

    def __iter__(self) -> Iterator[str]:
        return iter(tuple(TABLE))

    def __contains__(self, code: object) -> bool:
        return code in TABLE

    def __repr__(self) -> str:
        return repr(tuple(TABLE))


LANGUAGES: Sequence[str] = _Codes()
"""The codes of :data:`TABLE` (``("en", "ko")``): ``lang in LANGUAGES``, ``", ".join(LANGUAGES)``."""


def choices(sep: str = ", ") -> str:
    """The codes as one text for messages and help (``"en, ko"``; ``sep=" or "``: ``"en or ko"``)."""
    return sep.join(TABLE)


def language_of(value: str | None) -> str | None:
    """The code of :data:`TABLE` that a ``--lang`` value or a locale names (``ko``, ``KO``, ``ko_KR.UTF-8``,
    ``ko-KR``), or ``None`` (``C.UTF-8``, ``fr_FR``, empty)."""
    if not value:
        return None
    low = value.strip().lower()
    for code in sorted(TABLE, key=len, reverse=True):      # the longest code first (``pt_br`` before ``pt``)
        if low == code or (low.startswith(code) and low[len(code):len(code) + 1] in ("_", "-", ".", "@")):
            return code
    return None


def catalogue_dir(code: str) -> Path:
    """The folder that holds ``<code>/LC_MESSAGES/armkit.po`` (and ``.mo``) of a language."""
    folder = TABLE[code].folder if code in TABLE else None
    return folder if folder is not None else Path(__file__).parent


def add(language: Language) -> None:
    """Add ``language`` to :data:`TABLE` (or replace the row of its code): ``--lang``, the shell, the view and the
    plots take it from then on. armkit's own languages are rows written in :data:`TABLE`; this is for a language
    tried from outside (docs/languages.md runs it on a made-up one)."""
    if not language.code or not language.code.replace("_", "").isalnum() or language.code != language.code.lower():
        raise ArgumentError.of("a language code is lower-case letters and digits (e.g. 'ja', 'pt_br'), got "
                               "{code!r}", code=language.code)
    TABLE[language.code] = language
    _forget(language.code)


def remove(code: str) -> None:
    """Take the language ``code`` out of :data:`TABLE` again (the source language stays)."""
    if code == SOURCE:
        raise ArgumentError.of("{code!r} is the language of the code itself and cannot be removed", code=SOURCE)
    TABLE.pop(code, None)
    _forget(code)


def _forget(code: str) -> None:
    """Drop what was cached about ``code`` (its catalogue, its font)."""
    from . import _catalogue

    _catalogue.cache_clear()
    try:
        from .fonts import font_for
    except ImportError:      # pragma: no cover
        return
    font_for.cache_clear()
