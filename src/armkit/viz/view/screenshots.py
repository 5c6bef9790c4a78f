"""The view's screenshots: what a connected browser renders, written to a PNG file atomically.

:class:`Screenshots` is a part of :class:`armkit.viz.view.View` (its base class); the page's
*Screenshot* button (:mod:`armkit.viz.view.panels`) and scripts call these methods.
"""

from __future__ import annotations

import io
import re
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..._extras import require
from ..._io import atomic_path
from ...errors import ViewError

if TYPE_CHECKING:
    from ...model import Robot

__all__ = ["Screenshots"]


class Screenshots:
    """The screenshot methods of :class:`armkit.viz.view.View` (a base class; the view holds the server)."""

    if TYPE_CHECKING:     # what the view provides
        robot: Robot
        server: Any
        url: str
        screenshot_dir: Path

    def screenshot_png(self, client: Any, width: int = 1280, height: int = 800) -> bytes:
        """A PNG of what ``client`` (a connected browser) renders now."""
        Image = require("PIL.Image", "a screenshot of the view")

        img = client.get_render(height=height, width=width, transport_format="png")
        buf = io.BytesIO()
        Image.fromarray(np.asarray(img)).save(buf, format="PNG")
        return buf.getvalue()

    def save_screenshot(self, path: Any = None, *, client: Any = None, width: int = 1280,
                        height: int = 800) -> Path:
        """Write what a connected browser shows to a PNG file and return its path.

        The file is written atomically (a temporary file in the same folder, renamed into
        place: :func:`armkit._io.atomic_path`), so a reader never sees half a picture.

        Parameters
        ----------
        path : str or Path, optional
            A ``.png`` file; default ``armkit-ROBOT-YYYYmmdd-HHMMSS.png`` in
            :attr:`screenshot_dir` (the current folder when the view started).
        client : viser.ClientHandle, optional
            The browser to render in; default the first one connected.
        width, height : int
            Size of the picture in pixels.

        Raises
        ------
        ViewError
            No browser has the view open (nothing renders the scene).
        WriteError
            ``path`` cannot be written.
        """
        if client is None:
            clients = list(self.server.get_clients().values())
            if not clients:
                raise ViewError.of("no browser shows the view: open {url} first, then take the screenshot",
                                   url=self.url)
            client = clients[0]
        return self.write_png(self.screenshot_png(client, width, height), path)

    def write_png(self, png: bytes, path: Any = None) -> Path:
        """Write PNG bytes to ``path`` (default: a new name in :attr:`screenshot_dir`) atomically."""
        if path is None:
            safe = re.sub(r"[^A-Za-z0-9_.-]", "_", self.robot.name) or "arm"
            stem = f"armkit-{safe}-{time.strftime('%Y%m%d-%H%M%S')}"
            path = Path(self.screenshot_dir) / f"{stem}.png"
            k = 2
            while path.exists():
                path = Path(self.screenshot_dir) / f"{stem}-{k}.png"
                k += 1
        with atomic_path(path, suffixes=(".png",), what="screenshot") as tmp:
            tmp.write_bytes(png)
        return Path(path)
