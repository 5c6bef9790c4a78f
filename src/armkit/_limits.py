"""Limits on what one request may allocate, checked before anything is allocated.

armkit streams big jobs in chunks where it can (FK, manipulability, workspace sampling);
what must be held at once (the samples a workspace result returns, the samples of a
trajectory, the frames of an animation) is checked against a memory budget first. Past
it, a :class:`~armkit.errors.LimitError` says how much the request needs, the limit, and
how to raise it: set ``ARMKIT_MEMORY_LIMIT`` (bytes, or with a suffix: ``8G``, ``500M``).
The default is 2 GiB.

>>> check_memory(1e6, "a small job")
>>> parse_size("1.5G")
1610612736
"""

from __future__ import annotations

import os
import re

from ._text import Fielded
from .errors import LimitError

__all__ = ["DEFAULT_MEMORY_LIMIT", "memory_limit", "check_memory", "parse_size", "format_size", "CHUNK",
           "DEFAULT_MESH_LIMIT_MB", "mesh_limit", "check_mesh_file"]

DEFAULT_MEMORY_LIMIT = 2 * 1024 ** 3
CHUNK = 100_000          # configurations per chunk in the streamed loops
_UNITS = {"": 1, "K": 1024, "M": 1024 ** 2, "G": 1024 ** 3, "T": 1024 ** 4}


def parse_size(text: str) -> int:
    """``"8G"``, ``"500M"``, ``"123456"`` -> bytes; LimitError for anything else."""
    # stripped first: with \s* at both ends, "1" + 100,000 spaces + "x" backtracked quadratically (issue 24)
    m = re.fullmatch(r"(\d+(?:\.\d*)?)\s*([KMGT]?)i?B?", str(text).strip(), re.IGNORECASE)
    if not m:
        raise LimitError.of("ARMKIT_MEMORY_LIMIT must be a size like 4G, 500M or 1000000 (bytes), got {text!r}",
                            text=text)
    return int(float(m.group(1)) * _UNITS[m.group(2).upper()])


def format_size(n: float) -> str:
    """Bytes as text with a binary unit: ``1.5 GiB``."""
    for unit in ("B", "KiB", "MiB", "GiB", "TiB"):
        if abs(n) < 1024 or unit == "TiB":
            return f"{n:.3g} {unit}" if unit != "B" else f"{int(n)} B"
        n /= 1024
    return f"{n:.3g} PiB"  # pragma: no cover


def memory_limit() -> int:
    """The budget in bytes: ``ARMKIT_MEMORY_LIMIT`` or 2 GiB."""
    text = os.environ.get("ARMKIT_MEMORY_LIMIT")
    return DEFAULT_MEMORY_LIMIT if not text else parse_size(text)


def check_memory(nbytes: float, what: str, hint: str = "") -> None:
    """Raise :class:`LimitError` when ``what`` needs more than the budget; ``hint`` says how to ask for less.

    ``what`` and ``hint`` are parts of the message: built by :meth:`armkit._text.Fielded.of`, they are shown in the
    user's language too."""
    limit = memory_limit()
    if not nbytes <= limit:     # also catches NaN and inf
        size = (Fielded.of("an unbounded amount") if nbytes != nbytes or nbytes == float("inf") else
                Fielded.of("about {size}", size=format_size(nbytes)))
        raise LimitError.of("{what} would need {size} of memory, more than the limit of {limit}; {hint}; or raise the "
                            "limit with ARMKIT_MEMORY_LIMIT (e.g. ARMKIT_MEMORY_LIMIT=16G)" if hint else
                            "{what} would need {size} of memory, more than the limit of {limit}; or raise the limit "
                            "with ARMKIT_MEMORY_LIMIT (e.g. ARMKIT_MEMORY_LIMIT=16G)",
                            what=what, size=size, limit=format_size(limit), hint=hint)


DEFAULT_MESH_LIMIT_MB = 200       # the largest mesh file read, in MB (ARMKIT_MESH_LIMIT_MB)


def mesh_limit() -> int:
    """The largest mesh file armkit reads, in bytes: ``ARMKIT_MESH_LIMIT_MB`` (megabytes) or 200 MB."""
    text = os.environ.get("ARMKIT_MESH_LIMIT_MB", "").strip()
    if not text:
        return DEFAULT_MESH_LIMIT_MB * 1024 ** 2
    try:
        mb = float(text)
    except ValueError:
        mb = float("nan")
    if not 0 < mb < 1e9:
        raise LimitError.of("ARMKIT_MESH_LIMIT_MB must be a positive number of megabytes, got {text!r}", text=text[:40])
    return int(mb * 1024 ** 2)


def check_mesh_file(path: str | os.PathLike[str]) -> None:
    """Raise :class:`LimitError` when the mesh file at ``path`` is larger than :func:`mesh_limit`, before it is read.

    A file that cannot be looked at passes: the mesh loader says why it cannot read it.
    """
    limit = mesh_limit()
    try:
        size = os.stat(path).st_size
    except (OSError, ValueError):
        return
    if size > limit:
        raise LimitError.of("mesh file {path!r} has {size}, more than the limit of {limit}; it was not read (raise the "
                            "limit with ARMKIT_MESH_LIMIT_MB, e.g. ARMKIT_MESH_LIMIT_MB=1000)", path=str(path)[:300],
                            size=format_size(size), limit=format_size(limit))
