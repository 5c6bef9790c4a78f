"""Conventions (docs/conventions.md): standard and modified DH give the same arm, twists are (v, omega),
arrays batch over leading axes, and a robot is a value.

Run: python examples/02_conventions.py
"""

import sys

import numpy as np

import armkit
from armkit import spatial


def main(out_dir=None):
    puma = armkit.load("puma560")                    # standard DH
    craig = puma.to_dh("modified")                   # the same arm in Craig's modified DH
    q = puma.random_q(1000, np.random.default_rng(0))                # (1000, 6): a batch of configurations
    gap = np.abs(armkit.fk(puma, q) - armkit.fk(craig, q)).max()
    print(f"standard vs modified DH over {len(q)} configurations: largest difference {gap:.1e}")
    T = armkit.fk(puma, q[:3])                       # (3, 4, 4): leading axes are the batch
    xi = spatial.se3_log(T)                          # (3, 6), ordered (v, omega)
    print("twist of the first tool pose (v, omega):", np.round(xi[0], 4))
    print("exp(log(T)) == T:", np.allclose(spatial.se3_exp(xi), T))
    J = armkit.jacobian(puma, q[0])                  # rows vx vy vz wx wy wz, base frame
    print("Jacobian shape", J.shape, "; manipulability", round(float(armkit.manipulability(puma, q[0])), 5))
    print("two loads of one file are equal values:", armkit.load("puma560") == puma)
    assert gap < 1e-9
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
