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
INSTALL_HINT = ("cannot start chromium for the browser tests ({why}). Install Debian's chromium: "
                "`sudo apt-get install -y chromium` (or `make chromium`); never `playwright install`. "
                "Set ARMKIT_CHROMIUM to use another chromium binary.")


@contextmanager
def browser_context(width: int = 1000, height: int = 640) -> Iterator[Any]:
    """A persistent Chromium context with a fresh user-data dir, removed afterwards."""
    from playwright.sync_api import sync_playwright

    profile = tempfile.mkdtemp(prefix="armkit-chromium-")
    try:
        with sync_playwright() as p:
            ctx = p.chromium.launch_persistent_context(
                profile, executable_path=CHROMIUM, args=ARGS, headless=True,
                viewport={"width": width, "height": height}, accept_downloads=True)
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
    page.get_by_text(ready_label, exact=True).first.wait_for(timeout=30_000)
    dismiss_software_gl_notice(page)
    return page


def dismiss_software_gl_notice(page: Any, wait_ms: int = 1500) -> None:
    """Close viser's "Software WebGL rendering detected" note (headless chromium has no GPU here).

    It is true and harmless, but it covers the top left of the screenshots in the docs.
    """
    note = page.locator(".mantine-Notification-root", has_text="Software WebGL rendering detected")
    try:
        note.first.wait_for(timeout=wait_ms)
    except Exception:  # noqa: BLE001 - a browser with a GPU shows no such note
        return
    note.first.locator("button").first.click()
    note.first.wait_for(state="detached", timeout=5_000)


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


def open_folder(page: Any, title: str) -> None:
    """Expand a collapsed panel folder."""
    page.get_by_text(title, exact=True).first.click()


def wait_until(cond: Any, timeout: float = 30.0, what: str = "condition") -> None:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if cond():
            return
        time.sleep(0.02)
    raise AssertionError(f"timed out after {timeout} s waiting for {what}")
