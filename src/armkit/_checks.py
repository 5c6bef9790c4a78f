"""One validator for numeric array arguments: real, unmasked, representable as float64.

NumPy's ``asarray(x, dtype=float)`` silently drops the imaginary part of complex input,
drops the mask of a masked array and raises ``OverflowError`` on Python integers beyond
float range. :func:`real_array` turns each of these into a :class:`~armkit.errors.ShapeError`
that names the argument. Finite-ness and shape are the caller's checks.

>>> real_array([1, 2], "q").tolist()
[1.0, 2.0]
>>> real_array([1 + 2j], "q")
Traceback (most recent call last):
...
armkit.errors.ShapeError: q must be real numbers; got complex values (give the real part explicitly: x.real)
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .errors import ShapeError

__all__ = ["real_array", "short_repr"]


def short_repr(value: Any, limit: int = 80) -> str:
    """``repr(value)`` cut to ``limit`` characters."""
    try:
        text = repr(value)
    except Exception:  # noqa: BLE001 - a repr that fails must not hide the real message
        text = f"<{type(value).__name__}>"
    return text if len(text) <= limit else text[:limit - 3] + "..."


def real_array(x: Any, what: str) -> np.ndarray:
    """``x`` as a float64 array; ShapeError for complex, masked, non-numeric or too-large values."""
    if isinstance(x, np.ma.MaskedArray):
        if np.ma.is_masked(x):
            raise ShapeError.of("{what} is a masked array with masked entries; fill them (x.filled(value)) or leave "
                                "those entries out", what=what)
        x = np.ma.getdata(x)
    if isinstance(x, str):
        raise ShapeError.of("{what} must be numeric, got the string {got}", what=what, got=short_repr(x))
    try:
        complex_ = np.iscomplexobj(x)
    except (TypeError, ValueError, OverflowError, RecursionError):
        complex_ = False
    if complex_:
        raise ShapeError.of("{what} must be real numbers; got complex values (give the real part explicitly: x.real)",
                            what=what)
    try:
        return np.asarray(x, dtype=float)
    except OverflowError:
        raise ShapeError.of("{what} holds a number too large for a float (beyond 1.8e308)", what=what) from None
    except RecursionError:
        raise ShapeError.of("{what} is nested too deeply", what=what) from None
    except (TypeError, ValueError) as exc:
        raise ShapeError.of("{what} must be numeric, got {got} ({reason})", what=what, got=short_repr(x),
                            reason=str(exc)) from None
