"""The view's own page script: keyboard steps, typed values committed on Enter or blur, Korean line breaks.

viser's widgets send a number box's value on every keystroke and step a slider by its
``step`` (0.01°) per arrow key. The browser view wants:

- **Typed values commit on Enter or blur.** Typing ``500`` in the target's x box must solve
  IK once, for 500, not for 5, 50 and 500. The script holds back the ``input`` events of
  the listed number boxes (the joints' boxes and the typed target) until Enter, Tab or
  leaving the box, then lets one ``input`` event through with the whole value.
- **Arrow keys step 1° (0.1° with Shift)** on a revolute joint's slider; the value goes to
  the server through the slider's own number box, as a typed value would.
- **Korean words do not break mid-word** (``word-break: keep-all``).

It is sent once per server with viser's ``RunJavascriptMessage`` (kept for every browser
that connects later), and only reacts to the widgets whose ids it is given, so it never
touches anything else on the page. Nothing in it comes from the user: the ids are viser's
UUIDs and the steps are numbers, written as JSON.
"""

from __future__ import annotations

import json
from typing import Any, Iterable

__all__ = ["PAGE_CSS", "page_script", "install", "widget_id"]

PAGE_CSS = (
    # Hangul words stay whole (the browser's default breaks CJK text between any two syllables: 조|작성)
    "body, body * { word-break: keep-all; }"
)

_SCRIPT = r"""
(function () {
  const cfg = __CONFIG__;
  const A = window.__armkitView = window.__armkitView || {};
  A.deferred = new Set(cfg.deferred);
  A.steps = cfg.steps;
  A.commits = A.commits || 0;
  if (!document.getElementById("armkit-view-css")) {
    const style = document.createElement("style");
    style.id = "armkit-view-css";
    style.textContent = cfg.css;
    document.head.appendChild(style);
  }
  if (A.installed) return;
  A.installed = true;
  const setter = Object.getOwnPropertyDescriptor(HTMLInputElement.prototype, "value").set;

  // the widget (its viser id) whose row holds this element, among `ids`
  function owner(el, ids) {
    for (const id of ids) {
      const w = document.getElementById(id);
      if (!w) continue;
      if (w === el || w.contains(el)) return id;
      const row = w.closest(".mantine-Flex-root");
      if (row && row.contains(el)) return id;
    }
    return null;
  }
  // let the whole typed value through as one edit: the box is emptied (viser ignores an empty box), then
  // the value is put in at once, so the number formatter sees a plain insertion, not a diff of keystrokes
  function commit(input) {
    if (input.dataset.armkitDirty !== "1") return;
    delete input.dataset.armkitDirty;
    const typed = input.value;
    A.passing = true;
    try {
      setter.call(input, "");
      input.dispatchEvent(new Event("input", { bubbles: true }));
      setter.call(input, typed);
      try { input.setSelectionRange(typed.length, typed.length); } catch (e) { /* not a text box */ }
      input.dispatchEvent(new Event("input", { bubbles: true }));
    } finally {
      A.passing = false;
    }
    A.commits += 1;
  }
  // hold back per-keystroke values of the listed number boxes
  for (const type of ["input", "change"]) {
    document.addEventListener(type, function (ev) {
      const el = ev.target;
      if (A.passing || !(el instanceof HTMLInputElement) || el.getAttribute("role") === "slider") return;
      if (owner(el, A.deferred) === null) return;
      ev.stopPropagation();           // React listens below the document; other document listeners still hear it
      if (type === "input") el.dataset.armkitDirty = "1";   // a "change" (Enter, blur) is no new typing
    }, true);
  }
  document.addEventListener("keydown", function (ev) {
    const el = ev.target;
    if (el instanceof HTMLInputElement && (ev.key === "Enter" || ev.key === "Tab")) {
      if (owner(el, A.deferred) !== null) commit(el);
      return;
    }
    if (!(el instanceof Element) || el.getAttribute("role") !== "slider") return;
    if (!["ArrowRight", "ArrowUp", "ArrowLeft", "ArrowDown"].includes(ev.key)) return;
    const id = owner(el, Object.keys(A.steps));
    if (id === null) return;
    ev.preventDefault();
    ev.stopPropagation();           // React listens below the document; other document listeners still hear it
    const step = ev.shiftKey ? A.steps[id][1] : A.steps[id][0];
    const sign = (ev.key === "ArrowRight" || ev.key === "ArrowUp") ? 1 : -1;
    const lo = Number(el.getAttribute("aria-valuemin")), hi = Number(el.getAttribute("aria-valuemax"));
    const now = Number(el.getAttribute("aria-valuenow"));
    const next = Math.min(hi, Math.max(lo, Math.round((now + sign * step) * 1e6) / 1e6));
    const box = document.getElementById(id).closest(".mantine-Flex-root").querySelector("input:not([type=hidden])");
    if (!box || next === now) return;
    setter.call(box, String(next));
    box.dataset.armkitDirty = "1";
    commit(box);
  }, true);
  document.addEventListener("blur", function (ev) {
    if (ev.target instanceof HTMLInputElement) commit(ev.target);
  }, true);
})();
"""


def widget_id(handle: Any) -> str:
    """viser's id of a GUI widget (the ``id`` of its element in the page)."""
    return str(handle._impl.uuid)


def page_script(deferred: Iterable[str], steps: dict[str, tuple[float, float]]) -> str:
    """The script for widgets ``deferred`` (commit on Enter or blur) and slider ``steps`` (arrow, Shift+arrow)."""
    config = {"deferred": list(deferred), "steps": {k: [float(a), float(b)] for k, (a, b) in steps.items()},
              "css": PAGE_CSS}
    return _SCRIPT.replace("__CONFIG__", json.dumps(config))


def install(server: Any, deferred: Iterable[str], steps: dict[str, tuple[float, float]]) -> None:
    """Send the page script to every browser of ``server`` (now and later ones); safe to call again."""
    from viser import _messages

    # viser's own way to ship a script to the page (it sends plotly.js so); kept for late joiners
    server.gui._websock_interface.queue_message(_messages.RunJavascriptMessage(source=page_script(deferred, steps)))
