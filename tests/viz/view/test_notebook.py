"""Issue 23, item 3: the view in a notebook (examples/16_view_notebook.ipynb), run by a real Jupyter kernel.

nbclient executes the notebook cell by cell in an ipykernel whose Python is this one
(``sys.executable``: the kernelspec's ``python`` is replaced by it). After the cell that
displays the handle, the test reads the iframe's address from the cell's HTML output,
opens it in headless chromium (Playwright), executes the notebook's next cell (``v.q =
...``) and checks that the page shows the moved arm. The picture of the notebook cell (its
source and its HTML output with the live iframe, laid out as Jupyter shows a cell) goes
to a temporary folder, or to docs/img with ``make pictures``. One page load serves both: the cell's page, whose
iframe is the view's page, checked through the frame.
"""

from __future__ import annotations

import html
import os
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from _browser import dismiss_software_gl_notice, picture, text_of, wait_until

pytestmark = pytest.mark.browser
NOTEBOOK = Path(__file__).resolve().parents[3] / "examples" / "16_view_notebook.ipynb"


def _kernel_name(tmp: Path) -> str:
    """``python3`` when its kernelspec runs this Python; else a kernelspec installed for it into ``tmp``."""
    from jupyter_client.kernelspec import KernelSpecManager, NoSuchKernel

    try:
        argv0 = KernelSpecManager().get_kernel_spec("python3").argv[0]
    except NoSuchKernel:
        argv0 = ""
    if argv0 in ("python", "python3", sys.executable):       # jupyter_client runs "python" as sys.executable
        return "python3"
    subprocess.run([sys.executable, "-m", "ipykernel", "install", "--prefix", str(tmp), "--name", "armkit-test"],
                   check=True, capture_output=True)
    os.environ["JUPYTER_PATH"] = os.pathsep.join(filter(None, [str(tmp / "share" / "jupyter"),
                                                              os.environ.get("JUPYTER_PATH")]))
    return "armkit-test"


def _text(cell: Any) -> str:
    out = []
    for o in cell.get("outputs", []):
        if o.get("output_type") == "stream":
            if o.get("name") == "stdout":      # stderr: notes such as armkit's kernel compilation
                out.append(o["text"])
        elif "data" in o:
            out.append(o["data"].get("text/plain", ""))
        elif o.get("output_type") == "error":
            out.append("\n".join(o.get("traceback", [])))
    return "".join(out)


def _html(cell: Any) -> str:
    return "".join(o["data"]["text/html"] for o in cell.get("outputs", []) if "text/html" in o.get("data", {}))


def _cell_page(source: str, output_html: str, count: int) -> str:
    """One notebook cell as Jupyter lays it out: the prompt, the code, the HTML output."""
    return f"""<!doctype html><html><head><meta charset="utf-8"><style>
body {{ font-family: sans-serif; margin: 12px; background: #fff; }}
.cell {{ display: grid; grid-template-columns: 70px 1fr; row-gap: 6px; }}
.prompt {{ color: #307fc1; font-family: monospace; text-align: right; padding: 6px 8px 0 0; }}
.prompt.out {{ color: #bf5b3d; }}
pre {{ margin: 0; background: #f5f5f5; border: 1px solid #e0e0e0; padding: 6px 8px; font-size: 13px; }}
</style></head><body><div class="cell">
<div class="prompt">In [{count}]:</div><pre>{html.escape(source)}</pre>
<div class="prompt out">Out[{count}]:</div><div>{output_html}</div>
</div></body></html>"""


def test_notebook_shows_the_view_and_moves_the_arm(browser, docs_img: Path, tmp_path: Path) -> None:
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    nb = nbformat.read(NOTEBOOK, as_version=4)
    tags = {i: set(c.get("metadata", {}).get("tags", [])) for i, c in enumerate(nb.cells)}
    shown = next(i for i, t in tags.items() if "display" in t)
    move = next(i for i, t in tags.items() if "move" in t)
    # the kernel is stopped at the end without its graceful shutdown (the notebook's last cell closed the view)
    client = nbclient.NotebookClient(nb, kernel_name=_kernel_name(tmp_path), timeout=600, shutdown_kernel="immediate",
                                     resources={"metadata": {"path": str(tmp_path)}})
    with client.setup_kernel():
        check = nbformat.v4.new_code_cell("import sys; print(sys.executable)")
        client.execute_cell(check, 0)
        assert _text(check).strip() == sys.executable            # the kernel runs this Python (and this armkit)
        for i in range(shown + 1):
            client.execute_cell(nb.cells[i], i)
        printed = _text(nb.cells[1])
        assert not any("data" in o for o in nb.cells[1].outputs)      # nothing displayed besides (viser's banner)
        urls = re.findall(r"http://127\.0\.0\.1:\d+/", printed)
        assert printed.startswith("live view: ") and len(urls) == 1, printed          # the address, once
        frame = _html(nb.cells[shown])
        src = re.search(r'<iframe class="armkit-view" src="([^"]+)"', frame)
        assert src and src.group(1) == urls[0], frame
        # the cell (its source and its output, the live iframe) as a notebook shows it, in chromium
        cell_file = tmp_path / "cell.html"
        cell_file.write_text(_cell_page(nb.cells[shown].source, frame, 2), encoding="utf-8")
        pic = browser.new_page()
        pic.set_viewport_size({"width": 1000, "height": 700})
        pic.goto(cell_file.as_uri())
        assert [f.url for f in pic.frames[1:]] == [src.group(1)]         # the iframe shows the view's address
        page = pic.frame_locator("iframe.armkit-view")                  # the view's page, inside the iframe
        page.get_by_text("yaw (°)", exact=True).first.wait_for(timeout=60_000)
        dismiss_software_gl_notice(page)     # none shown (browser_context); it would cover the picture
        # the picture, before the arm moves
        picture(pic, str(docs_img / "view-notebook.png"))
        before = text_of(page, "end point (mm)")
        # the notebook's next cell moves the arm: the page follows
        client.execute_cell(nb.cells[move], move)
        assert [float(x) for x in re.findall(r"-?\d+\.\d+", _text(nb.cells[move]))] == [24.861, 14.353, 187.181]
        wait_until(lambda: text_of(page, "end point (mm)") == "24.861, 14.353, 187.181", 60, "the page follows v.q")
        assert before != "24.861, 14.353, 187.181"
        pic.close()
        # the rest of the notebook runs: IK from the notebook, then close
        for i in range(move + 1, len(nb.cells)):
            client.execute_cell(nb.cells[i], i)
        outputs = [_text(c) for c in nb.cells if c.cell_type == "code"]
        assert not any("Traceback" in o or "Error" in o for o in outputs), outputs
        assert "(True," in outputs[-2] and "closed" in _html(nb.cells[-1])
