"""Benchmarks of the live view, measured through a real browser (headless chromium via Playwright).

1. Latency from a slider move in the page (a key press on a joint slider's thumb) to the
   updated arm: the time, on the page's own clock, from the keydown event to the end-pose
   text showing the new value. The link poses travel in the same websocket batch as that
   text (``server.atomic()``), so this is the time until the page holds the moved arm
   (drawing the next frame adds at most one display frame). Goal: median < 50 ms.
2. Live IK while dragging the target gizmo (6-DOF ur5: closed form with every branch; 7-DOF
   panda: LM warm-started): a real mouse-down on the gizmo's arrow (the camera is placed so
   that the arrow is at a known pixel), then pointer moves synthesised in the page every
   animation frame; arm updates per second seen by the page (distinct end-pose values), drag
   events reaching the server and IK solves per second. Goal: >= 30 updates/s.
3. Memory over a tracking run (looping a circle path at 60 frames/s with a page connected):
   RSS of this process at the start and the end. Goal: flat over 10 minutes (``--minutes``).

4. ``--breakdown ur5``: one key press split into its parts, on the page's clock and the
   server's (same machine): page -> server, the server's update, server -> websocket,
   websocket -> the page's main thread (including the animation frames that were being
   rendered meanwhile), and the batch -> the end-pose text (one rendered frame and React's commit);
   ``render_frame_ms`` is the median main-thread cost of a frame that renders WebGL.

Run: .venv/bin/python benchmarks/bench_view.py [--minutes 10] [--skip-memory]
     [--window 800x600] [--chromium-flag=--use-angle=swiftshader] [--no-flush] [--breakdown ur5]
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np
from playwright.sync_api import TimeoutError as PlaywrightTimeout

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "viz" / "view"))

import armkit  # noqa: E402
from armkit.viz.view import View  # noqa: E402

import _browser  # noqa: E402
from _browser import browser_context, open_page, row, text_of  # noqa: E402

WATCH_JS = """
([label]) => {
  const lab = [...document.querySelectorAll('label')].find(l => l.textContent.trim() === label);
  const input = lab.closest('.mantine-Flex-root').querySelector('input');
  window.__input = input;
  window.__changes = [];
  let last = input.value;
  const poll = () => {                       // 1 ms polling of the end-pose text (React sets .value)
    const v = window.__input.value;
    if (v !== last) { last = v; window.__changes.push(performance.now()); }
    if (window.__watching) setTimeout(poll, 1);
  };
  window.__watching = true;
  poll();
  document.addEventListener('keydown', () => { window.__keydown = performance.now(); }, true);
}
"""


NO_FLUSH = False     # --no-flush: the view before each batch was flushed (viser windows messages for 1/60 s)


def _open(name: str) -> View:
    v = View(name, lang="en")
    if NO_FLUSH:
        v.server.flush = lambda: None         # type: ignore[method-assign]
    return v


def rss_mb() -> float:
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return float("nan")


def slider_latency(ctx, name: str, presses: int = 40) -> list[float]:
    with _open(name) as v:
        first = f"{v.robot.joint_names[1]} (°)"
        page = open_page(ctx, v.url, first)
        pose_label = f"end point ({v.robot.unit})"
        page.evaluate(WATCH_JS, [pose_label])
        thumb = row(page, first).locator("[role=slider]")
        thumb.focus()
        out = []
        for i in range(presses):
            before = page.evaluate("window.__changes.length")
            thumb.press("ArrowRight" if (i // 10) % 2 == 0 else "ArrowLeft")
            try:          # a page that stalls longer than this counts as an infinite latency
                page.wait_for_function(f"window.__changes.length > {before}", timeout=30_000)
            except PlaywrightTimeout:
                out.append(float("inf"))
                continue
            out.append(page.evaluate(f"window.__changes[{before}] - window.__keydown"))
            time.sleep(0.05)
        page.close()
        slider_latency.server_ms = statistics.median(list(v.update_ms)[-presses:])  # type: ignore[attr-defined]
    return out


PROBE_JS = """
(() => {
  // what the page does between a key press and the moved arm: the websocket worker's traffic
  // (send: the slider value leaves; recv: a batch from the server reaches the main thread),
  // the main thread's cost of each animation frame (a WebGL render when the scene changed)
  window.__log = [];
  const W = window.Worker;
  window.Worker = class extends W {
    constructor(...a) {
      super(...a);
      const post = this.postMessage.bind(this);
      this.postMessage = (m, t) => {
        if (m && m.type === 'send') window.__log.push(['send', performance.now()]);
        return t ? post(m, t) : post(m);
      };
      this.addEventListener('message', e => {
        if (e.data && e.data.type === 'message_batch') window.__log.push(['recv', performance.now()]);
      });
    }
  };
  window.__fcost = [];
  const ch = new MessageChannel();
  let start = 0;
  ch.port1.onmessage = () => { window.__fcost.push([start, performance.now() - start]); };
  const raf = () => { start = performance.now(); ch.port2.postMessage(0); requestAnimationFrame(raf); };
  requestAnimationFrame(raf);
})();
"""


def breakdown(ctx, name: str, presses: int = 20) -> dict:
    """Where a key press on a slider spends its time (medians, ms), on the page's and the server's clocks."""
    from websockets.asyncio.server import ServerConnection

    sent: list[float] = []
    orig_send = ServerConnection.send

    async def send(self, message, *a, **k):        # when the batch goes on the wire
        sent.append(time.time() * 1e3)
        return await orig_send(self, message, *a, **k)

    ServerConnection.send = send                   # type: ignore[method-assign]
    ctx.add_init_script(PROBE_JS)
    try:
        with _open(name) as v:
            stamps: list[tuple[float, float]] = []
            show = v.show_configuration

            def timed(q, extra=None):
                t0 = time.time() * 1e3
                show(q, extra)
                stamps.append((t0, time.time() * 1e3))

            v.show_configuration = timed           # type: ignore[method-assign]
            first = f"{v.robot.joint_names[1]} (°)"
            page = open_page(ctx, v.url, first)
            page.evaluate(WATCH_JS, [f"end point ({v.robot.unit})"])
            origin = page.evaluate("performance.timeOrigin")
            thumb = row(page, first).locator("[role=slider]")
            thumb.focus()
            rows = []
            for i in range(presses):
                n_log, before = page.evaluate("[window.__log.length, window.__changes.length]")
                thumb.press("ArrowRight" if (i // 10) % 2 == 0 else "ArrowLeft")
                page.wait_for_function(f"window.__changes.length > {before}", timeout=10_000)
                kd, done, log = page.evaluate(f"[window.__keydown, window.__changes[{before}], "
                                              f"window.__log.slice({n_log})]")
                out = next(t for kind, t in log if kind == "send" and t >= kd)
                back = next(t for kind, t in log if kind == "recv" and t >= out)
                s_in, s_out = stamps[-1]
                wire = next((t for t in sent if t >= s_in), float("nan"))
                frames = page.evaluate(f"window.__fcost.filter(f => f[0] + f[1] > {kd} - 1 && f[0] < {back})")
                rows.append({"total": done - kd, "page_to_server": s_in - (origin + out), "server": s_out - s_in,
                             "server_to_wire": wire - s_out, "wire_to_page": origin + back - wire,
                             "frames_in_the_way": sum(c for _, c in frames if c > 5),
                             "batch_to_text": done - back})
                time.sleep(0.15)
            costs = [c for _, c in page.evaluate("window.__fcost") if c > 5]
            page.close()
    finally:
        ServerConnection.send = orig_send           # type: ignore[method-assign]
    res = {k: statistics.median(r[k] for r in rows) for k in rows[0]}
    res["render_frame_ms"] = statistics.median(costs) if costs else float("nan")
    return res


DRAG_JS = """
([x0, y0, amp, seconds]) => new Promise(resolve => {
  // pointermove events synthesised in the page, one per animation frame (as a browser delivers a real
  // mouse), after a real pointerdown on the gizmo: no Playwright round trip per event
  const el = document.elementFromPoint(x0, y0);
  const t0 = performance.now();
  let k = 0;
  const step = () => {
    const t = performance.now() - t0;
    if (t > seconds * 1000) { resolve(k); return; }
    const x = x0 + amp * Math.sin(2 * Math.PI * 0.5 * t / 1000);
    el.dispatchEvent(new PointerEvent('pointermove', {bubbles: true, cancelable: true, composed: true,
      pointerId: 1, pointerType: 'mouse', isPrimary: true, clientX: x, clientY: y0, buttons: 1}));
    k += 1;
    requestAnimationFrame(step);
  };
  requestAnimationFrame(step);
})
"""


def drag_rate(ctx, name: str, seconds: float = 5.0) -> dict:
    """Drag the gizmo's x arrow in the page; count arm updates in the page, drag events and IK solves.

    The camera is put where the gizmo's place on the screen is known: looking against the
    target's y axis, with the target's z axis up, from 4 gizmo sizes away, so the gizmo's
    centre is the canvas centre and its x arrow points to the left (away from the panel),
    ``scale / (D tan(fov/2))`` half-heights long. A real ``mouse.down`` on the arrow starts the drag, then the page
    itself moves the pointer every animation frame (:data:`DRAG_JS`).
    """
    with _open(name) as v:
        r = v.robot
        q0 = np.clip(np.array([0.3, -1.0, 1.2, -1.2, -1.4, 0.4, 0.5][:r.n]), r.lower, r.upper)
        if name == "panda":
            q0 = np.array([0.0, -0.3, 0.0, -2.0, 0.0, 1.8, 0.8])
        v.set_q(q0)
        T = armkit.fk(r, q0)
        v.set_target(T)
        page = open_page(ctx, v.url, f"{r.joint_names[0]} (°)")
        client = list(v.server.get_clients().values())[0]
        s = r.unit_scale
        centre = T[:3, 3] * s
        scale = 0.22 * (r.reach or 1) * s           # the gizmo's size (panels.py)
        dist = 4.0 * scale
        cam = client.camera
        cam.up_direction = tuple(T[:3, 2])
        cam.position = tuple(centre + dist * T[:3, 1])
        cam.look_at = tuple(centre)
        time.sleep(1.5)
        box = page.locator("canvas").last.bounding_box()
        cx, cy = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        px_per_scale = (scale / dist) / math.tan(float(cam.fov) / 2) * box["height"] / 2
        page.evaluate(WATCH_JS, [f"end point ({r.unit})"])
        events = {"n": 0}
        orig = v.target_from_page

        def counted(t, position_only, dragging):
            events["n"] += 1
            orig(t, position_only, dragging)

        v.target_from_page = counted                 # type: ignore[method-assign]
        best = None
        for frac in (0.8, 0.7, 0.9, 0.6):
            x0, y0 = cx - frac * px_per_scale, cy       # left of the panel
            ik0, ev0, changes0 = v.ik_updates, events["n"], page.evaluate("window.__changes.length")
            page.mouse.move(x0, y0)
            page.mouse.down()
            t0 = time.perf_counter()
            moves = page.evaluate(DRAG_JS, [x0, y0, 0.25 * px_per_scale, seconds])
            dt = time.perf_counter() - t0
            page.mouse.up()
            time.sleep(0.5)
            solves, drag_events = v.ik_updates - ik0, events["n"] - ev0
            seen = page.evaluate("window.__changes.length") - changes0
            if drag_events > 3:
                server_ms = statistics.median(list(v.update_ms)[-max(solves, 1):])
                best = {"robot": name, "seconds": dt, "page_updates_per_s": seen / dt,
                        "drag_events_per_s": drag_events / dt, "ik_solves_per_s": solves / dt,
                        "pointer_moves_per_s": moves / dt, "server_ms": server_ms, "hit_at": frac,
                        "reached_last": bool(np.asarray(v.last_result.success)) if v.last_result else None}
                break
        page.close()
    return best or {"robot": name, "error": "the drag did not hit the gizmo"}


def memory_run(ctx, minutes: float) -> dict:
    with View("planar3", lang="en") as v:
        page = open_page(ctx, v.url, "q1 (°)")
        v.show_path("circle", method="lm", frames=200, fps=60)
        start = rss_mb()
        samples = [(0.0, start)]
        t0 = time.perf_counter()
        frames0 = v.updates
        while time.perf_counter() - t0 < minutes * 60:
            time.sleep(10)
            samples.append((time.perf_counter() - t0, rss_mb()))
            print(f"  memory: {samples[-1][0]:6.0f} s  RSS {samples[-1][1]:.1f} MB  frames {v.updates - frames0}",
                  flush=True)
        dt = time.perf_counter() - t0
        frames = v.updates - frames0
        text = text_of(page, "frame")
        page.close()
    rs = [m for _, m in samples]
    half = rs[len(rs) // 2]
    return {"minutes": dt / 60, "frames": frames, "frames_per_s": frames / dt, "rss_start_mb": start,
            "rss_mid_mb": half, "rss_end_mb": rs[-1], "rss_max_mb": max(rs), "last_frame_text": text}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--minutes", type=float, default=10.0, help="length of the tracking run for memory")
    ap.add_argument("--skip-memory", action="store_true")
    ap.add_argument("--presses", type=int, default=40)
    ap.add_argument("--latency-robots", default="fighter,ur5,panda")
    ap.add_argument("--skip-drag", action="store_true")
    ap.add_argument("--window", default="1000x640", help="browser window WxH (the tests use 1000x640)")
    ap.add_argument("--chromium-flag", action="append", default=[],
                    help="extra chromium flag, e.g. --use-angle=swiftshader, or !FLAG to drop one of the tests' flags "
                         "(repeatable; printed with the numbers)")
    ap.add_argument("--no-flush", action="store_true", help="A/B: do not flush each update batch (the old view)")
    ap.add_argument("--drag-robots", default="ur5,panda")
    ap.add_argument("--breakdown", default="", help="robots whose key-press latency is split into its parts")
    args = ap.parse_args()
    global NO_FLUSH
    NO_FLUSH = args.no_flush
    width, height = (int(x) for x in args.window.split("x"))
    for flag in args.chromium_flag:            # "!--disable-gpu" removes a flag of the tests' set
        if flag.startswith("!"):
            _browser.ARGS[:] = [a for a in _browser.ARGS if a != flag[1:]]
        else:
            _browser.ARGS.append(flag)
    print(f"window {width}x{height}, chromium flags: {' '.join(_browser.ARGS)}"
          f"{', batches not flushed (before)' if NO_FLUSH else ''}; load average {Path('/proc/loadavg').read_text().split()[0]}",
          flush=True)
    with browser_context(width, height) as ctx:
        for name in [n for n in args.latency_robots.split(",") if n]:
            lat = slider_latency(ctx, name, args.presses)
            stalled = sum(1 for x in lat if x == float("inf"))
            print(f"slider -> arm latency, {name}: median {statistics.median(lat):.1f} ms, "
                  f"p90 {np.percentile(lat, 90):.1f} ms, min {min(lat):.1f} ms over {len(lat)} key presses "
                  f"({stalled} not shown within 30 s) "
                  f"(server side {slider_latency.server_ms:.2f} ms per update; "
                  f"goal < 50 ms: {'met' if statistics.median(lat) < 50 else 'NOT met'}, "
                  f"ratio goal/median {50 / statistics.median(lat):.1f}x)", flush=True)
        for name in () if args.skip_drag else [n for n in args.drag_robots.split(",") if n]:
            d = drag_rate(ctx, name)
            if "error" in d:
                print(f"live IK while dragging, {name}: {d['error']}")
                continue
            print(f"live IK while dragging, {name}: {d['page_updates_per_s']:.1f} arm updates/s in the page, "
                  f"{d['pointer_moves_per_s']:.0f} pointer moves/s in the page, {d['drag_events_per_s']:.1f} drag "
                  f"events/s reached the server, {d['ik_solves_per_s']:.1f} IK solves/s over "
                  f"{d['seconds']:.1f} s; server {d['server_ms']:.2f} ms per IK + update, i.e. "
                  f"{1000 / d['server_ms']:.0f}/s possible; "
                  f"(goal >= 30/s: {'met' if d['page_updates_per_s'] >= 30 else 'NOT met'}, "
                  f"ratio {d['page_updates_per_s'] / 30:.1f}x)", flush=True)
        if not args.skip_memory:
            m = memory_run(ctx, args.minutes)
            print(f"memory over {m['minutes']:.1f} min of tracking ({m['frames']} frames, {m['frames_per_s']:.1f}/s): "
                  f"RSS start {m['rss_start_mb']:.1f} MB, middle {m['rss_mid_mb']:.1f} MB, end {m['rss_end_mb']:.1f} MB, "
                  f"max {m['rss_max_mb']:.1f} MB (end/start {m['rss_end_mb'] / m['rss_start_mb']:.3f})")
        for name in [n for n in args.breakdown.split(",") if n]:   # last: its page script stays in the context
            b = breakdown(ctx, name, args.presses)
            print(f"where a key press goes, {name} (medians over {args.presses}, ms): "
                  + ", ".join(f"{k} {val:.1f}" for k, val in b.items()), flush=True)


if __name__ == "__main__":
    main()
