"""Live 3-D view of an arm in the browser, built on viser (``pip install viser``).

>>> import armkit                                   # doctest: +SKIP
>>> v = armkit.view("fighter")                      # doctest: +SKIP
live view: http://127.0.0.1:40213/
>>> v.set_target([100.0, 50.0, 80.0]).success      # doctest: +SKIP
array(True)
>>> v.wait()                                        # doctest: +SKIP
'page'

``v.wait()`` serves until the page's close button or Ctrl-C; in Jupyter ``v`` shows the page
inline (an iframe to the server).

See docs/view.md. This package is imported only when asked for: ``import armkit``
does not import viser. It lives under :mod:`armkit.viz` with the other pictures;
``armkit.view(robot)`` is the front door.
"""

from __future__ import annotations

from .server import IK_METHODS, View, ViewError, free_port, home_pose, view

__all__ = ["view", "View", "ViewError", "IK_METHODS", "free_port", "home_pose"]

