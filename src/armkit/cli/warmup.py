"""``armkit warmup``: compile and cache every Numba kernel now (for images and CI)."""

from __future__ import annotations

import typer

from .._jit_loader import COMPILE_SECONDS
from ..warmup import warmup as run
from .common import EXIT_FAILED, JsonOut, _, console, esc, print_json


def warmup(parallel: bool = typer.Option(True, "--parallel/--no-parallel",
                                         help="Also the multi-threaded kernels of big batches (about half the time)."),
           json_out: JsonOut = False) -> None:
    """Compile armkit's Numba kernels once and cache them on disk, so that no later run waits for it.

    Run it after installing armkit into an image or a CI environment. The cache goes to NUMBA_CACHE_DIR if set, else next to the package, else ~/.cache/numba, else a private directory in the temp directory (read-only installs). Kernels another install of the same sources compiled on this machine are copied from the kernel store (~/.cache/armkit/kernels; ARMKIT_KERNEL_STORE=off turns it off).

    Example: armkit warmup
    """
    def say() -> None:   # in the user's language (the library's own note is English)
        console.print(_("compiling armkit's kernels once, about {seconds} s in all", seconds=COMPILE_SECONDS))

    try:
        done = run(parallel=parallel, say=(lambda: None) if json_out else say)   # --json: stdout JSON, stderr quiet
    except ImportError as exc:
        console.print(_("cannot compile armkit's kernels: {reason} (the NumPy back end works without them)",
                        reason=esc(exc)))
        raise SystemExit(EXIT_FAILED) from None
    if json_out:
        print_json({"seconds": round(done.seconds, 3), "cache": None if done.cache is None else str(done.cache),
                    "compiled": done.compiled, "restored": done.restored})
        return
    where = _("not cached (Numba's cache is off)") if done.cache is None else _("cached in {path}",
                                                                              path=esc(done.cache))
    if done.compiled:
        console.print(_("armkit's kernels compiled in {seconds} s, {where}", seconds=f"{done.seconds:.1f}",
                        where=where))
    elif done.restored:
        console.print(_("armkit's kernels copied from the kernel store (compiled by another install of the same "
                        "sources), {where}: nothing to compile", where=where))
    else:
        console.print(_("armkit's kernels were already compiled, {where}: nothing to do", where=where))



def register(app: typer.Typer) -> None:
    app.command("warmup")(warmup)
