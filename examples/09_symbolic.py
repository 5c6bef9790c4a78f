"""Symbolic kinematics (docs/symbolic.md): FK and Jacobian as formulas, the c12 short-hand, NumPy code.

Run: python examples/09_symbolic.py [OUT_DIR]   (writes OUT_DIR/planar2_fk.py and planar2.tex, default out/)
"""

import sys
from pathlib import Path

import numpy as np

import armkit
from armkit.symbolic import derive
from armkit.symbolic.export import to_latex, to_numpy_source, to_text


def main(out_dir="out"):
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    arm = armkit.load("planar2")
    d = derive(arm)
    print("x of the tool:", d.T[0, 3])
    print("short-hand:   ", to_text(d)["T"][0, 3])
    print("parameters:   ", d.values)
    J = d.lambdify("J")                               # numeric Jacobian from the formulas
    q = np.array([0.3, 0.8])
    print("symbolic Jacobian == numeric:", np.allclose(J(q), armkit.jacobian(arm, q)))
    (out / "planar2_fk.py").write_text(to_numpy_source(d))
    (out / "planar2.tex").write_text(to_latex(d))
    print("wrote", out / "planar2_fk.py", "and", out / "planar2.tex")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
