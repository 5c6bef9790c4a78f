"""derive --png: T and J laid out as matrices, every entry (constants too), with units (issue 11)."""

from __future__ import annotations

import re

import pytest
from typer.testing import CliRunner

import armkit
from armkit.cli import app

sp = pytest.importorskip("sympy")


def figure_texts(robot: str) -> list[str]:
    from armkit.symbolic import derive
    from armkit.symbolic.export import matrix_figure

    fig = matrix_figure(derive(armkit.load(robot)))
    texts = [t.get_text() for t in fig.texts]
    import matplotlib.pyplot as plt

    plt.close(fig)
    return texts


def test_fighter_every_entry_and_the_units():
    texts = figure_texts("fighter")
    # 16 entries of T and 18 of J, each its own mathtext cell, zeros and ones included
    cells = [t for t in texts if re.fullmatch(r"\$[^$]*\$", t) and t not in ("$x$", "$y$", "$z$")]
    assert texts.count("$0$") == 3 + 1 + 5            # T's bottom row and z-row zero, J's zero entries
    assert texts.count("$1$") == 1 + 1                # T44 and J61 (the yaw axis is z: wz = 1)
    assert "$s_{1}$" in texts and "$- c_{1}$" in texts  # rotation rows of J
    assert "$p$\n(mm)" in texts and "$v_x$ (mm)" in texts and "$\\omega_z$ (1)" in texts
    assert any(t.startswith("$q_{1}$\n(per rad)") for t in texts)
    assert len(cells) == 16 + 18


def test_planar2_png_via_the_cli(tmp_path):
    out = tmp_path / "d.png"
    res = CliRunner().invoke(app, ["derive", "planar2", "--png", str(out)])
    assert res.exit_code == 0, res.output
    assert out.stat().st_size > 5_000
    texts = figure_texts("planar2")
    # T = [[c12, -s12, 0, x], [s12, c12, 0, y], [0, 0, 1, 0], [0, 0, 0, 1]]: 8 zeros; J: rows vz, wx, wy: 6 zeros
    assert texts.count("$0$") == 8 + 6
    assert texts.count("$1$") == 1 + 1 + 2            # T33, T44, J wz row


def test_derive_output_spelling(tmp_path):
    """One -o/--output everywhere: derive -o takes a picture name (as --png) or the --python/--latex file."""
    runner = CliRunner()
    pic = tmp_path / "fk.png"
    res = runner.invoke(app, ["derive", "planar2", "-o", str(pic)])
    assert res.exit_code == 0 and pic.stat().st_size > 5_000, res.output
    mod = tmp_path / "fk.py"
    res = runner.invoke(app, ["derive", "planar2", "--python", "--output", str(mod)])
    assert res.exit_code == 0 and "def fk(q)" in mod.read_text(), res.output
    res = runner.invoke(app, ["derive", "planar2", "-o", str(tmp_path / "fk.txt")])
    assert res.exit_code == 2 and "--output" in res.output
    res = runner.invoke(app, ["singular", "planar2", "--plot", str(tmp_path / "m.png")])   # old spelling, hidden
    assert res.exit_code == 0 and (tmp_path / "m.png").exists(), res.output
    res = runner.invoke(app, ["singular", "planar2", "-o", str(tmp_path / "m2.png")])
    assert res.exit_code == 0 and (tmp_path / "m2.png").exists(), res.output
