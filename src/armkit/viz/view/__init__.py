"""Live 3-D view of an arm in the browser, built on viser (``pip install viser``).

>>> import armkit                                   # doctest: +SKIP
>>> v = armkit.view("fighter")                      # doctest: +SKIP
>>> print(v.url)                                    # doctest: +SKIP
http://127.0.0.1:40213/
>>> v.set_target([100.0, 50.0, 80.0]).success      # doctest: +SKIP
array(True)
>>> v.close()                                       # doctest: +SKIP

See docs/view.md. This package is imported only when asked for: ``import armkit``
does not import viser. It lives under :mod:`armkit.viz` with the other pictures;
``armkit.view(robot)`` is the front door.
"""

from __future__ import annotations

from .server import IK_METHODS, View, ViewError, free_port, view

__all__ = ["view", "View", "ViewError", "IK_METHODS", "free_port"]

