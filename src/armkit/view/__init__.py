"""Live 3-D view of an arm in the browser, built on viser (``pip install viser``).

>>> import armkit                                   # doctest: +SKIP
>>> v = armkit.view("fighter")                      # doctest: +SKIP
>>> print(v.url)                                    # doctest: +SKIP
http://127.0.0.1:40213/
>>> v.set_target([100.0, 50.0, 80.0]).success      # doctest: +SKIP
array(True)
>>> v.close()                                       # doctest: +SKIP

See docs/view.md. This package is imported only when asked for: ``import armkit``
does not import viser.
"""

from __future__ import annotations

import sys
import types
from typing import Any, Optional

from .server import IK_METHODS, View, ViewError, free_port, view

__all__ = ["view", "View", "ViewError", "IK_METHODS", "free_port"]


class _CallableModule(types.ModuleType):
    """``armkit.view(robot)`` keeps working after ``import armkit.view`` replaced the lazy wrapper
    in ``armkit``'s namespace with this package (a package attribute and a function share the name)."""

    def __call__(self, robot: Any, port: Optional[int] = None, **kwargs: Any) -> View:
        return view(robot, port=port, **kwargs)


sys.modules[__name__].__class__ = _CallableModule
