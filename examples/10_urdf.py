"""URDF arms (docs/urdf.md): any arm as URDF, read back with a chosen tip, its equivalent DH table.

Run: python examples/10_urdf.py [OUT_DIR]   (writes OUT_DIR/puma560.urdf, default out/)
"""

import sys
from pathlib import Path

import numpy as np

import armkit


def main(out_dir="out"):
    out = Path(out_dir)
    puma = armkit.load("puma560")
    path = armkit.save(puma, out / "puma560.urdf")    # any robot as URDF (metres)
    urdf = armkit.load(path)                          # the chain base -> tip written in the file
    q = puma.random_q(100, np.random.default_rng(0))
    print(f"{urdf.name}: {urdf.n} joints, convention {urdf.convention}; links {', '.join(urdf.link_names)}")
    print("FK of the URDF == FK of the DH model:", np.allclose(armkit.fk(urdf, q), armkit.fk(puma, q)))
    short = armkit.load(path, tip=urdf.link_names[3])  # a shorter chain: stop at the third joint's link
    print("tip", urdf.link_names[3], "->", short.n, "joints")
    dh = urdf.to_dh()                                  # its standard DH twin
    print("equivalent DH table agrees:", np.allclose(armkit.fk(dh, q), armkit.fk(urdf, q)))
    so101 = armkit.load("so101")                       # a bundled URDF with meshes
    frames = armkit.link_frames(so101, np.zeros(so101.n))
    print(f"so101: {len(so101.links)} links with frames {frames.shape}")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
