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
ValueError: unexpected '_' at position 1
"""

from __future__ import annotations

import math
import re

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
            raise ValueError(f"unexpected {bad[0]!r} at position {len(text) - len(bad) + 1}")
        if m.group(1):
            out.append(("num", float(m.group(1)), m.start(1)))
        elif m.group(2):
            out.append(("num", math.pi, m.start(2)))
        else:
            out.append((m.group(3), None, m.start(3)))
        pos = m.end()
    return out


def evaluate(text: str) -> float:
    """The value of ``text`` in the grammar above; ``ValueError`` with a short reason otherwise."""
    if len(text) > MAX_LENGTH:
        raise ValueError(f"expression longer than {MAX_LENGTH} characters")
    toks = _tokens(text)
    if not toks:
        raise ValueError("empty expression")
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
                raise ValueError("division by zero")
            v = v * w if op == "*" else v / w
        return v

    def factor(depth: int) -> float:
        if depth > MAX_DEPTH:
            raise ValueError(f"more than {MAX_DEPTH} nested levels")
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
                raise ValueError("missing ')'")
            take()
            return v
        raise ValueError("missing a number at the end" if kind == "end" else f"unexpected {kind!r}")

    value = expr(0)
    if i != len(toks):
        raise ValueError(f"unexpected {toks[i][0] if toks[i][0] != 'num' else 'number'!r} at position {toks[i][2] + 1}")
    if not math.isfinite(value):
        raise ValueError("the result is not a finite number")
    return value
