"""Text the user controls, made safe to print: the one place that escapes it.

Robot names, joint names, descriptions, file paths and shell lines reach the terminal
through Rich, which reads ``[...]`` as markup and passes escape sequences straight to
the terminal. :func:`plain` makes any text inert (control characters shown as ``\\xNN``),
:func:`esc` also escapes Rich markup so that it prints literally inside armkit's own
markup, :func:`shorten` caps a long text and :func:`name_list` caps a list of names.

>>> esc("[/]arm")
'\\\\[/]arm'
>>> plain("red\\x1b[31m")
'red\\\\x1b[31m'
>>> name_list([f"j{i}" for i in range(100)], limit=3)
'j0, j1, j2, ... (100 in all)'
"""

from __future__ import annotations

import re
from typing import Any, Iterable

__all__ = ["plain", "esc", "shorten", "name_list", "MAX_MESSAGE", "Fielded"]

MAX_MESSAGE = 2000      # characters of one message shown before it is cut
_CONTROL = re.compile("[\x00-\x08\x0b-\x1f\x7f-\x9f\u200e\u200f\u202a-\u202e\u2066-\u2069]")


def _show(m: re.Match[str]) -> str:
    c = ord(m.group(0))
    return f"\\x{c:02x}" if c < 0x100 else f"\\u{c:04x}"


def plain(text: Any) -> str:
    """``str(text)`` with control characters (ANSI escapes, bell, carriage return, bidi overrides) shown as ``\\xNN``.

    Newlines and tabs are kept.
    """
    return _CONTROL.sub(_show, str(text))


def esc(text: Any) -> str:
    """:func:`plain`, then Rich markup escaped: the text prints literally inside armkit's markup."""
    from rich.markup import escape

    return escape(plain(text))


def shorten(text: str, limit: int = MAX_MESSAGE) -> str:
    """``text`` cut to ``limit`` characters, saying how much was left out."""
    if len(text) <= limit:
        return text
    return text[:limit] + f" ... ({len(text) - limit:,} more characters)"


def name_list(names: Iterable[Any], limit: int = 12, sep: str = ", ") -> str:
    """The first ``limit`` names joined by ``sep``, and how many there are in all when there are more."""
    names = list(names)
    if len(names) <= limit:
        return sep.join(str(n) for n in names)
    return sep.join(str(n) for n in names[:limit]) + f"{sep}... ({len(names):,} in all)"


class Fielded(str):
    """An English sentence that keeps the template and fields it was built from, so that a front end renders it
    in the user's language from the catalogue (:func:`armkit.locale.library.localize`) instead of reading the
    English back. It is a ``str`` everywhere else (printed, compared, written to JSON).

    ``terms`` names the fields whose values are words the catalogue may translate (``ground``, ``torso``);
    the other fields are names and numbers, shown as they are.

    >>> m = Fielded.of("the {a} hits the {b} by {depth}", terms=("a", "b"), a="forearm", b="ground", depth="13 mm")
    >>> m, m.template, m.fields["b"], m.terms
    ('the forearm hits the ground by 13 mm', 'the {a} hits the {b} by {depth}', 'ground', ('a', 'b'))
    """

    template: str
    fields: dict[str, Any]
    terms: tuple[str, ...]

    def __str__(self) -> str:    # str(m) keeps the template and fields (front ends call str() on messages)
        return self

    @classmethod
    def of(cls, template: str, /, terms: tuple[str, ...] = (), **fields: Any) -> "Fielded":
        text = cls(template.format(**fields))
        text.template, text.fields, text.terms = template, fields, tuple(terms)
        return text
