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


def drop_unopened_connections(server: Any) -> int:
    """Close the connections of viser's ``server`` that never sent their opening request; the number closed.

    Browsers open a spare connection to a page's server that they may never use (Chromium does, on every
    page load). websockets waits up to its opening timeout (10 s) for that connection's request before its
    server can stop, and viser's ``stop()`` waits 6 s of it: without this, closing a view that a browser
    ever showed took 6 s (Ctrl-C in ``armkit view``, the end of every browser test). Each such connection's
    handler is cancelled on the server's event loop, which aborts its socket (websockets' own way out of a
    handshake); connections that are open are left to close as before. Any surprise in viser's or websockets'
    internals returns 0: the stop is then as slow as before, never wrong.
    """
    import asyncio

    try:
        from websockets.protocol import State

        loop = server._websock_server._background_event_loop

        async def cancel() -> int:
            n = 0
            for task in asyncio.all_tasks():
                coro: Any = task.get_coro()
                if getattr(coro, "__qualname__", "") != "Server.conn_handler" or coro.cr_frame is None:
                    continue
                connection = coro.cr_frame.f_locals.get("connection")
                if connection is not None and connection.protocol.state is State.CONNECTING:
                    task.cancel()
                    n += 1
            return n

        return int(asyncio.run_coroutine_threadsafe(cancel(), loop).result(timeout=1.0))
    except Exception:  # noqa: BLE001 - private parts of viser and websockets: when they differ, the slow stop
        return 0


def free_port(host: str = "127.0.0.1") -> int:
    """A TCP port that is free on ``host`` right now."""
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    with socket.socket(family, socket.SOCK_STREAM) as s:
        s.bind((host, 0))
        return int(s.getsockname()[1])
