"""The live browser view (docs/view.md) from Python: start it, move the arm, show a path, close it.

Run: python examples/11_view.py   (open the printed address in a browser while it runs, or not: it
needs no browser and closes after a few seconds; ARMKIT_VIEW_SECONDS=60 keeps it open longer)
"""

import os
import sys
import time

import numpy as np

import armkit


def main(out_dir=None):
    v = armkit.view("fighter", host="127.0.0.1")      # port=None: a free port; prints its address once
    try:
        v.set_q(np.radians([30, 45, 60]))
        res = v.set_target([100.0, 50.0, 80.0])      # position only; the arm moves only on success
        print("IK target:", bool(res.success), res.branch, np.degrees(v.q).round(1))
        v.show_path(np.linspace(v.q, np.zeros(3), 20))   # a joint path, played in the page
        time.sleep(float(os.environ.get("ARMKIT_VIEW_SECONDS", "1")))
    finally:
        v.close()                                     # the port is free again
    print("closed")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
