"""Playwright helpers for the view tests and benchmarks: Debian's chromium, headless, no downloads.

Never ``playwright install``: it downloads a browser. Chromium comes from apt
(``make test`` installs it when missing).
"""

from __future__ import annotations

import os
import re
import shutil
import tempfile
import time
from contextlib import contextmanager
from typing import Any, Iterator

CHROMIUM = os.environ.get("ARMKIT_CHROMIUM", "/usr/bin/chromium")
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
        "--disable-background-networking", "--disable-component-update", "--disable-sync"]
# An init script for every page and frame: WebGL keeps its renderer's name to itself (as privacy-minded browsers
# do), so viser skips its software-rendering check and never shows its "Software WebGL rendering detected" note
# (true here, harmless, but it covers the top left of the canvas and of the docs' pictures; closing it waited for
# its entry animation and its close animation, 1.5-5 s a page on the shared machine). Nothing else in the page
# reads the renderer's name: three.js and viser draw the same either way.
RENDERER_NAME_HIDDEN = """(() => {
  for (const ctx of [window.WebGLRenderingContext, window.WebGL2RenderingContext]) {
    if (!ctx) continue;
    const getExtension = ctx.prototype.getExtension;
    ctx.prototype.getExtension = function (name) {
      return name === "WEBGL_debug_renderer_info" ? null : getExtension.call(this, name);
    };
  }
})();"""
# Without antialiasing (the tests' own runs; `make pictures` keeps it for the docs): SwiftShader, chromium's software
# WebGL, then draws each frame once instead of multisampling it. Measured on the 2-core test machine (chromium 156,
# load 4-6): the GPU process's CPU while a fighter page stays open (it draws about one frame a second when nothing
# moves) fell by about half, and a run of browser start, three page loads, nine screenshots and 9 s open
# took 22.9 CPU-s instead of 25.6 (all processes, mean of 3 alternating runs each). The tests count pixels of a
# colour (an arm, a red obstacle, the DH arrows), which the blending of the edges does not change.
NO_ANTIALIASING = ["--webgl-antialiasing-mode=none", "--webgl-msaa-sample-count=0"]
INSTALL_HINT = ("cannot start chromium for the browser tests ({why}). Install Debian's chromium: "
                "`sudo apt-get install -y chromium` (or `make chromium`); never `playwright install`. "
                "Set ARMKIT_CHROMIUM to use another chromium binary.")


@contextmanager
def browser_context(width: int = 1000, height: int = 640, antialiasing: bool = True) -> Iterator[Any]:
    """A persistent Chromium context with a fresh user-data dir, removed afterwards.

    ``antialiasing=False`` draws WebGL without multisampling (:data:`NO_ANTIALIASING`): cheaper, with jagged edges.
    """
    from playwright.sync_api import sync_playwright

    profile = tempfile.mkdtemp(prefix="armkit-chromium-")
    args = ARGS if antialiasing else [*ARGS, *NO_ANTIALIASING]
    try:
        with sync_playwright() as p:
            ctx = p.chromium.launch_persistent_context(
                profile, executable_path=CHROMIUM, args=args, headless=True,
                viewport={"width": width, "height": height}, accept_downloads=True)
            ctx.add_init_script(RENDERER_NAME_HIDDEN)
            try:
                yield ctx
            finally:
                ctx.close()
    finally:
        shutil.rmtree(profile, ignore_errors=True)


def open_page(ctx: Any, url: str, ready_label: str) -> Any:
    """Open ``url`` and wait until the panel shows ``ready_label``."""
    page = ctx.new_page()
    page.goto(url)
    page.get_by_text(ready_label, exact=True).first.wait_for(timeout=60_000)
    dismiss_software_gl_notice(page)
    return page


def dismiss_software_gl_notice(page: Any, wait_ms: int = 0) -> None:
    """Close viser's "Software WebGL rendering detected" note if the page shows it.

    A context from :func:`browser_context` hides the renderer's name, so viser shows no such note and this
    returns at once. ``wait_ms`` > 0 first waits that long for the note to appear (a context without the
    init script, whose headless chromium renders WebGL in software).
    """
    note = page.locator(".mantine-Notification-root", has_text="Software WebGL rendering detected")
    if wait_ms > 0:
        try:
            note.first.wait_for(timeout=wait_ms)
        except Exception:  # noqa: BLE001 - a browser with a GPU shows no such note
            return
    if note.count() == 0:
        return
    note.first.locator("button").first.click()
    note.first.wait_for(state="detached", timeout=5_000)


def pixels(png: bytes) -> Any:
    """A PNG screenshot as an int array ``(height, width, 3)`` of its RGB values."""
    import io

    import numpy as np
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)


def settled(page: Any, target: Any = None, interval: float = 0.25, agree: int = 2, timeout: float = 60.0,
            tolerance: int = 20) -> Any:
    """A screenshot (PNG bytes) of ``target`` (default: the page) once it has stopped changing.

    Shots ``interval`` s apart are compared; the last one is returned once ``agree`` shots in a row each differ
    from the one before in fewer than ``tolerance`` pixels (a channel sum over 60). This waits for what a fixed
    sleep hoped for: the page has drawn the last change (a mesh loaded, the camera placed).
    """
    import numpy as np

    shoot = (page if target is None else target).screenshot
    last = shoot()
    run = 0
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        time.sleep(interval)
        now = shoot()
        a, b = pixels(last), pixels(now)
        run = run + 1 if a.shape == b.shape and int((np.abs(a - b).sum(axis=-1) > 60).sum()) < tolerance else 0
        if run >= agree:
            return now
        last = now
    raise AssertionError(f"the page kept changing for {timeout} s")


def row(page: Any, label: str) -> Any:
    """The panel row whose label is exactly ``label``."""
    lab = page.locator("label").filter(has_text=re.compile(rf"^{re.escape(label)}$")).first
    return lab.locator("xpath=ancestor::div[contains(@class,'mantine-Flex-root')][1]")


def text_of(page: Any, label: str) -> str:
    """Value of the (read-only) text box labelled ``label``."""
    return str(row(page, label).locator("input").first.input_value())


def numbers_of(page: Any, label: str) -> list[float]:
    return [float(x) for x in text_of(page, label).split(",")]


def type_number(page: Any, label: str, value: float) -> None:
    """Type ``value`` into the number box of the slider labelled ``label`` and press Enter."""
    box = row(page, label).locator("input.mantine-NumberInput-input, input[type=text]").last
    box.click()
    box.fill(f"{value}")
    box.press("Enter")


def type_joint(page: Any, view: Any, j: int, label: str, degrees: float) -> None:
    """:func:`type_number` into joint ``j``'s box, then wait until the view holds the value and the page shows the
    end point of the new configuration. The server answers a typed value by sending every slider's value back;
    a box typed into while that reply is on its way (a loaded machine: seen once in a clean clone's run) can have
    its text replaced by the old value before Enter commits it, so the next box waits for the reply."""
    import numpy as np

    from armkit import fk
    from armkit.viz.view.panels import format_numbers

    type_number(page, label, degrees)
    wait_until(lambda: abs(view.q[j] - np.radians(degrees)) < 1e-12, what=f"{label} = {degrees}")
    end = format_numbers(fk(view.robot, view.q)[:3, 3], 3)
    wait_until(lambda: text_of(page, "end point (mm)") == end, what=f"the end point after {label} = {degrees}")


def open_folder(page: Any, title: str) -> None:
    """Expand a collapsed panel folder."""
    page.get_by_text(title, exact=True).first.click()


def tick(page: Any, text: str, done: Any, tries: int = 3, wait: float = 10.0) -> None:
    """Click the checkbox labelled ``text`` until the server says so (``done()`` true). A click that lands while the
    folder around it is still opening is lost now and then (a full suite's run on 2026-12-07 waited 20 s for the
    workspace cloud of a click that never arrived); the next try clicks again only where the first did not reach the
    server within ``wait`` seconds."""
    for k in range(tries):
        page.get_by_text(text).click()
        try:
            wait_until(done, wait, f"the box {text!r} ticked")
            return
        except AssertionError:
            if k == tries - 1:
                raise


def picture(page: Any, path: str) -> None:
    """Save a screenshot of ``page`` to ``path``; for the docs (``make pictures``) once the page has settled.

    The tests' own screenshots go to a temporary folder and nobody looks at them: they are taken at once.
    """
    if os.environ.get("ARMKIT_UPDATE_PICTURES") == "1":
        settled(page, interval=0.5)
    page.screenshot(path=path)


def wait_until(cond: Any, timeout: float = 60.0, what: str = "condition") -> None:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if cond():
            return
        time.sleep(0.02)
    raise AssertionError(f"timed out after {timeout} s waiting for {what}")
