"""A small, safe arithmetic grammar for typed values: ``90/2``, ``45+15``, ``-(10 + 20) * 2``, ``pi/4``.

Numbers, ``pi``, ``+ - * /`` and parentheses, read by a hand-written recursive-descent
parser. Nothing typed is ever evaluated as Python: there are no names but ``pi``, no
calls, no attributes, no powers (``2**1000000`` cannot exhaust the machine), and the
input length and nesting depth are capped.

Grammar::

    expr   := term (("+" | "-") term)*
    term   := factor (("*" | "/") factor)*
    factor := ("+" | "-") factor | NUMBER | "pi" | "(" expr ")"

>>> evaluate("90/2")
45.0
>>> evaluate("-(10 + 20) * 2")
-60.0
>>> round(evaluate("pi/4"), 6)
0.785398
>>> evaluate("__import__('os')")
Traceback (most recent call last):
...
armkit.errors.ArgumentError: unexpected '_' at position 1
"""

from __future__ import annotations

import math
import re

from .errors import ArgumentError

__all__ = ["evaluate", "looks_arithmetic", "MAX_LENGTH", "MAX_DEPTH"]

MAX_LENGTH = 200     # characters of one expression
MAX_DEPTH = 20       # nested parentheses and signs

_TOKEN = re.compile(r"\s*(?:(\d+(?:\.\d*)?(?:[eE][+-]?\d+)?|\.\d+(?:[eE][+-]?\d+)?)|(pi|π)|([-+*/()]))",
                    re.IGNORECASE)
_CHARS = re.compile(r"^[\d.eE\s+\-*/()]*(?:(?:pi|π)[\d.eE\s+\-*/()]*)*$", re.IGNORECASE)


def looks_arithmetic(text: str) -> bool:
    """True when ``text`` uses only the grammar's characters (numbers, pi, + - * / and parentheses)."""
    return bool(text.strip()) and bool(_CHARS.match(text))


def _tokens(text: str) -> list[tuple[str, object, int]]:
    out: list[tuple[str, object, int]] = []
    pos = 0
    text = text.rstrip()
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if not m:
            bad = text[pos:].lstrip()
            raise ArgumentError.of("unexpected {char!r} at position {pos}", char=bad[0], pos=len(text) - len(bad) + 1)
        if m.group(1):
            out.append(("num", float(m.group(1)), m.start(1)))
        elif m.group(2):
            out.append(("num", math.pi, m.start(2)))
        else:
            out.append((m.group(3), None, m.start(3)))
        pos = m.end()
    return out


def evaluate(text: str) -> float:
    """The value of ``text`` in the grammar above; otherwise :class:`~armkit.errors.ArgumentError` (a ``ValueError``)
    with a short reason, kept as its template and fields."""
    if len(text) > MAX_LENGTH:
        raise ArgumentError.of("expression longer than {limit} characters", limit=MAX_LENGTH)
    toks = _tokens(text)
    if not toks:
        raise ArgumentError.of("empty expression")
    i = 0

    def peek() -> str:
        return toks[i][0] if i < len(toks) else "end"

    def take() -> tuple[str, object, int]:
        nonlocal i
        i += 1
        return toks[i - 1]

    def expr(depth: int) -> float:
        v = term(depth)
        while peek() in ("+", "-"):
            op = take()[0]
            w = term(depth)
            v = v + w if op == "+" else v - w
        return v

    def term(depth: int) -> float:
        v = factor(depth)
        while peek() in ("*", "/"):
            op = take()[0]
            w = factor(depth)
            if op == "/" and w == 0:
                raise ArgumentError.of("division by zero")
            v = v * w if op == "*" else v / w
        return v

    def factor(depth: int) -> float:
        if depth > MAX_DEPTH:
            raise ArgumentError.of("more than {limit} nested levels", limit=MAX_DEPTH)
        kind = peek()
        if kind in ("+", "-"):
            take()
            v = factor(depth + 1)
            return -v if kind == "-" else v
        if kind == "num":
            return float(take()[1])  # type: ignore[arg-type]
        if kind == "(":
            take()
            v = expr(depth + 1)
            if peek() != ")":
                raise ArgumentError.of("missing ')'")
            take()
            return v
        raise ArgumentError.of("missing a number at the end" if kind == "end" else "unexpected {kind!r}", kind=kind)

    value = expr(0)
    if i != len(toks):
        raise ArgumentError.of("unexpected {char!r} at position {pos}", char=toks[i][0] if toks[i][0] != "num" else "number",
                               pos=toks[i][2] + 1)
    if not math.isfinite(value):
        raise ArgumentError.of("the result is not a finite number")
    return value
