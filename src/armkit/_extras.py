"""Optional dependencies: the one place that imports them and names the pip extra when one is missing.

The core (``import armkit``, FK, Jacobians, IK, robot files, the core CLI commands) needs only
the packages in ``[project] dependencies``. Everything else loads on first use through
:func:`require`, which raises :class:`armkit.errors.MissingExtraError` (an ``ImportError``) with
the command that installs it; the CLI prints that as one line and exits with code 2.

>>> require("numpy", "this doctest").__name__
'numpy'
"""

from __future__ import annotations

import importlib
import sys
from types import ModuleType

from .errors import MissingExtraError

__all__ = ["EXTRAS", "require"]

EXTRAS: dict[str, str] = {
    # top-level module -> the extra in pyproject.toml's [project.optional-dependencies] that installs it
    "matplotlib": "viz",
    "PIL": "viz",
    "imageio": "viz",
    "imageio_ffmpeg": "viz",
    "sympy": "symbolic",
    "prompt_toolkit": "shell",
    "viser": "view",
    "coal": "scene",
    "dask": "scale",
    "distributed": "scale",
    "zarr": "scale",
}
"""Which extra brings which module (tests/test_errors.py checks it against pyproject.toml)."""


def require(module: str, what: str) -> ModuleType:
    """Import ``module`` (an optional dependency) or say which extra installs it.

    Parameters
    ----------
    module : str
        Dotted module name, e.g. ``"matplotlib.pyplot"``; its top-level package must be in
        :data:`EXTRAS` (core modules pass through too: the message then asks to reinstall).
    what : str
        What needs it, as the user would say it: ``"armkit view"``, ``"writing MP4"``.

    Returns
    -------
    module
        The imported module.

    Raises
    ------
    MissingExtraError
        The module cannot be imported: ``armkit view needs the 'view' extra (No module named
        'viser'): pip install 'armkit[view]'``.
    """
    loaded = sys.modules.get(module)   # already imported: ~0.1 us, where import_module takes ~10 (a hot loop of
    if loaded is not None:             # coal geometry asked 120,000 times while one Panda view opened: 1.5 s)
        return loaded
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        top = module.split(".")[0]
        raise MissingExtraError(what, EXTRAS.get(top, "all"), top, str(exc)) from None
