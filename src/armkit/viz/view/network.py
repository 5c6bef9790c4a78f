"""The view's port and console handling: a free port, whether a port is free, viser kept quiet.

Re-exported by :mod:`armkit.viz.view.server` (and :mod:`armkit.viz.view`).
"""

from __future__ import annotations

import contextlib
import io
import socket
from typing import Any

__all__ = ["free_port"]


def _port_free(host: str, port: int) -> bool:
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    with socket.socket(family, socket.SOCK_STREAM) as s:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            s.bind((host, port))
        except OSError:
            return False
    return True


@contextlib.contextmanager
def _quiet() -> Any:
    """Nothing printed: stdout, and rich's global console (viser's banner; in Jupyter rich shows it as output)."""
    import rich
    import rich.console

    saved = rich._console
    rich._console = rich.console.Console(file=io.StringIO(), force_jupyter=False)
    try:
        with contextlib.redirect_stdout(io.StringIO()):
            yield
    finally:
        rich._console = saved


def free_port(host: str = "127.0.0.1") -> int:
    """A TCP port that is free on ``host`` right now."""
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    with socket.socket(family, socket.SOCK_STREAM) as s:
        s.bind((host, 0))
        return int(s.getsockname()[1])
