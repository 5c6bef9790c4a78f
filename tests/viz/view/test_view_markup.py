"""Issue 24, item 4: the page keeps user strings as text.

A URDF whose robot, joint and link names, and a scene whose shape name, carry HTML, markdown and
script tags, shown in the live view through a real browser (headless chromium via Playwright): the
names are printed literally (the joint sliders' labels, the collision line naming the link and the
shape), and no element is made from them (no ``img``, ``b``, ``strong``, ``a`` or ``script`` of
theirs, no script run, no dialog).
"""

from __future__ import annotations

from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np
import pytest

import armkit
from armkit.viz.view import View

from _browser import open_page, wait_until

pytestmark = pytest.mark.browser

ROBOT = "<script>window.__armkit_pwned = 'robot'</script>"
J1 = "<img src=x onerror=\"window.__armkit_pwned = 'joint'\">"
J2 = "<b>bold</b> **bold** [link](http://x.invalid/joint)"
BASE = "<b>base</b>"
L1 = "**l1** <script>window.__armkit_pwned = 'link1'</script>"
L2 = "[l2](http://x.invalid/link) <img src=x onerror=\"window.__armkit_pwned = 'link2'\">"
SHAPE = ("<img src=x onerror=\"window.__armkit_pwned = 'shape'\"> <b>box</b> **box** [box](http://x.invalid/shape) "
         "<script>window.__armkit_pwned = 'shape2'</script>")


def _urdf(path: Path) -> Path:
    path.write_text(f"""<robot name={quoteattr(ROBOT)}>
  <link name={quoteattr(BASE)}/><link name={quoteattr(L1)}/><link name={quoteattr(L2)}/><link name="tool"/>
  <joint name={quoteattr(J1)} type="revolute"><parent link={quoteattr(BASE)}/><child link={quoteattr(L1)}/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name={quoteattr(J2)} type="revolute"><parent link={quoteattr(L1)}/><child link={quoteattr(L2)}/>
    <origin xyz="0.3 0 0"/><axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="tip" type="fixed"><parent link={quoteattr(L2)}/><child link="tool"/><origin xyz="0.3 0 0"/></joint>
</robot>
""", encoding="utf-8")
    return path


def _words(text: str) -> str:
    """Text with runs of white space as one space (HTML shows them so)."""
    return " ".join(text.split())


# elements the names would make if the page read them as HTML or markdown
MADE = """() => {
  const all = (sel) => Array.from(document.querySelectorAll(sel));
  return {
    img: all('img').filter(e => (e.getAttribute('src') || '') === 'x').length,
    b: all('b, strong').filter(e => /^(bold|box|base|l1)$/.test(e.textContent.trim())).length,
    a: all('a').filter(e => (e.getAttribute('href') || '').includes('x.invalid')).length,
    script: all('script').filter(e => e.textContent.includes('__armkit_pwned')).length,
    pwned: window.__armkit_pwned === undefined ? null : String(window.__armkit_pwned),
  };
}"""


def test_names_with_html_markdown_and_scripts_are_text(browser, tmp_path: Path) -> None:
    robot = armkit.load(_urdf(tmp_path / "evil.urdf"))
    assert robot.name == ROBOT and robot.joint_names == (J1, J2) and robot.link_names[:3] == (BASE, L1, L2)
    # a box the forearm (L2) passes through at q = 0: the collision line names the link and the shape
    scene = armkit.Scene([armkit.Scene.box([0.45, 0, 0.1], [0.1, 0.1, 0.1], name=SHAPE)])
    expected = armkit.collisions(robot, np.zeros(2), scene=scene).message()
    assert "<b>box</b>" in expected and "[l2](http://x.invalid/link)" in expected
    dialogs: list[str] = []
    with View(robot, lang="en", scene=scene) as v:
        page = browser.new_page()
        page.on("dialog", lambda d: (dialogs.append(d.message), d.dismiss()))
        page.goto(v.url)
        page.get_by_text("Home", exact=True).first.wait_for(timeout=60_000)
        v.set_q(np.zeros(2))
        assert v.obstacles.colliding == (SHAPE,)
        # printed literally: each joint's slider label, and the collision line with the link and shape names
        for name in (J1, J2):
            page.get_by_text(f"{name} (°)", exact=True).first.wait_for(timeout=10_000)
        wait_until(lambda: page.locator(".armkit-collision").count() == 1, 20, "the collision line")
        wait_until(lambda: _words(page.locator(".armkit-collision").first.inner_text())
                   == _words(f"⚠ collision: {expected}"), 20, "the collision line, literal")
        body = _words(page.locator("body").inner_text())
        for literal in (f"{J1} (°)", f"{J2} (°)", expected):
            assert _words(literal) in body
        # nothing made from them: no image, bold, link or script element, no script run, no dialog
        page.wait_for_timeout(1000)
        assert page.evaluate(MADE) == {"img": 0, "b": 0, "a": 0, "script": 0, "pwned": None}
        assert dialogs == []
        page.close()
