"""``armkit view ROBOT``: the live browser view (viser is imported inside the command)."""

from __future__ import annotations

import ipaddress
import re
from typing import Optional

import typer

from ..errors import ArmkitError
from .common import _, console, current_language, fail, get_robot

from .common import Lang, RobotArg, check_lang  # noqa: E402  (the shared options)
_HOSTNAME = re.compile(r"^(?=.{1,253}$)[A-Za-z0-9](?:[A-Za-z0-9-]{0,61}[A-Za-z0-9])?(?:\.[A-Za-z0-9](?:[A-Za-z0-9-]{0,61}"
                       r"[A-Za-z0-9])?)*$")


def check_host(host: str) -> str:
    """``host`` if it is an IP address or a host name of this machine that a server can listen on; exit 2 otherwise.

    A name that does not resolve (``example.invalid``) or an address of another machine fails here, with one
    line, before the view starts (it was a ``socket.gaierror`` traceback, issue 24).
    """
    try:
        ipaddress.ip_address(host)
    except ValueError:
        if not _HOSTNAME.match(host):
            fail(_("--host must be an IP address or a host name, got {value!r}", value=host))
    reason = _bind_problem(host)
    if reason is not None:
        fail(_("cannot listen on --host {value!r}: {reason}", value=host, reason=reason))
    return host


def _bind_problem(host: str) -> Optional[str]:
    """Why a server cannot listen on ``host`` (the name does not resolve, the address is not this machine's),
    or None when it can: resolved and bound to a free port, then closed at once."""
    import socket

    try:
        infos = socket.getaddrinfo(host, 0, type=socket.SOCK_STREAM)
    except (socket.gaierror, UnicodeError, OSError) as exc:
        return _("the name does not resolve to an address ({reason})",
                 reason=getattr(exc, "strerror", None) or str(exc) or type(exc).__name__)
    last = ""
    for family, kind, proto, _name, addr in infos:
        try:
            with socket.socket(family, kind, proto) as s:
                s.bind(addr)
            return None
        except OSError as exc:
            last = exc.strerror or str(exc)
    return _("no address of this machine ({reason})", reason=last or "bind failed")


def check_port(port: Optional[int]) -> Optional[int]:
    if port is not None and not 1 <= port <= 65535:
        fail(_("--port must be between 1 and 65535, got {value}", value=port))
    return port


def view(robot: RobotArg,
         port: Optional[int] = typer.Option(None, "--port", "-p", help="TCP port (default: a free one)."),
         host: str = typer.Option("127.0.0.1", "--host",
                                  help="Address to listen on. The default serves this machine only; 0.0.0.0 lets "
                                       "anyone on your network move the arm."),
         lang: Lang = None,
         scene_file: Optional[str] = typer.Option(
             None, "--scene", help="Scene file (TOML, docs/scene.md) drawn translucent, red where the arm "
                                   "overlaps it; default: the robot's own surroundings (the fighter's ground)."),
         no_scene: bool = typer.Option(False, "--no-scene", help="Draw no surroundings and check no collisions (the "
                                                         "robot's body is still drawn).")
         ) -> None:
    """Serve a live 3-D view of the arm in the browser: joint sliders, draggable IK target, tracking, workspace.

    Prints the address and serves until Ctrl-C (exit 130) or the page's "Close the view" button (exit 0).
    Works offline (no internet needed).

    Example: armkit view fighter --lang ko

    Example: armkit view ur5 --port 8080

    Example: armkit view fighter --scene cell.toml
    """
    from rich.markup import escape

    lang = check_lang(lang)
    check_port(port)
    check_host(host)
    r = get_robot(robot)
    from ..viz.view import ViewError
    from ..viz.view import view as open_view
    from .common import scene_option

    try:
        scene = scene_option(r, scene_file, no_scene)
    except ArmkitError as exc:
        fail(escape(str(exc)))
    try:
        v = open_view(r, port=port, host=host, lang=lang or current_language(),
                      scene=False if scene is None else scene, quiet=True)   # no check: none drawn either
    except ViewError as exc:
        fail(escape(str(exc)))
    try:
        console.print(_("{robot} live view: {url}   (Ctrl-C to stop)", robot=f"[bold]{escape(r.name)}[/]",
                        url=escape(v.url)), soft_wrap=True)
        if host not in ("127.0.0.1", "localhost", "::1"):
            console.print("[yellow]" + _("note:") + "[/] " + _("listening on {host}: anyone who can reach this "
                                                                "machine on that address can open the view and move "
                                                                "the arm", host=escape(host)), soft_wrap=True)
        why = v.wait()
    except KeyboardInterrupt:
        why = "interrupt"
    finally:
        v.close()
    if why == "interrupt":
        raise SystemExit(130)


def register(app: typer.Typer) -> None:
    app.command()(view)


__all__ = ["register", "view", "check_host", "check_port", "attach_view"]


def attach_view(shell: object, robot: object, lang: Optional[str]) -> object:
    """For ``armkit shell --view``: serve the view, print its address, let the shell move it.

    Returns the :class:`~armkit.viz.view.View` (a context manager that closes it).
    """
    from rich.markup import escape

    from ..viz.view import ViewError
    from ..viz.view import view as open_view

    try:
        v = open_view(robot, lang=lang or current_language(), q=getattr(shell, "q", None),  # type: ignore[arg-type]
                      quiet=True)
    except ViewError as exc:
        fail(escape(str(exc)))
    shell.view = v  # type: ignore[attr-defined]
    console.print(_("live view: {url}", url=escape(v.url)), soft_wrap=True)

    return v
