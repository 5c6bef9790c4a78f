"""The multi-threaded twin of a one-thread kernel, made in one place.

Each batch driver of the compiled back end is written once, as a one-thread kernel whose outer
loop is a ``prange`` (Numba runs it as a plain ``range`` without ``parallel=True``). Its twin is
the same Python function compiled with ``parallel=True`` under another name: Numba names a
kernel's disk cache after the function, so the two never share a cache entry. A
``parallel=True`` kernel pays a thread-pool launch on every call and must not run inside another
parallel region, so small batches and nested callers use the one-thread kernel
(:func:`armkit._jit_loader.parallel_ok`); each module lists its pairs in ``parallel_twins()`` for
the warm-up. Imported only by the kernel modules, after Numba.
"""

from __future__ import annotations

import types
from typing import Any

from numba import njit

__all__ = ["parallel_twin"]


def parallel_twin(serial: Any) -> Any:
    """The ``parallel=True`` copy of the Numba kernel ``serial`` (named ``<name>_parallel``), compiled on first use,
    with the serial one's reference counting (``_nrt``: a kernel compiled without counts has a twin without them)."""
    py = serial.py_func
    copy = types.FunctionType(py.__code__, py.__globals__, py.__name__ + "_parallel", py.__defaults__, py.__closure__)
    copy.__qualname__ = py.__qualname__ + "_parallel"
    copy.__doc__ = py.__doc__
    counts = {"_nrt": serial.targetoptions["_nrt"]} if "_nrt" in serial.targetoptions else {}
    return njit(cache=True, parallel=True, **counts)(copy)
