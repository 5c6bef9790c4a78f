"""The DH twin's self-check, moved out of the model (issue 21): FK of the twin against FK of the chain.

``model/dh_extract.py`` no longer imports the kinematics; it checks the twin's joint axes at
``q = 0`` and its tool pose (equal screws and home pose give equal FK at every ``q``, by the
product of exponentials). Here FK itself is compared, with :mod:`armkit.kinematics`, and the
geometric check is held against that FK check on chains with nearly parallel axes.
"""

from __future__ import annotations

import numpy as np
import pytest

import armkit
from armkit.errors import RobotDefinitionError
from armkit.model.dh_extract import CHECK_TOL, _axes_mismatch, chain_to_dh
from armkit.model.robot import Joint, Robot
from armkit.spatial import transl


def _fk_error(a: Robot, b: Robot) -> float:
    """The largest FK difference (rotation entries and position) of ``a`` and ``b``, at q = 0 and 16 random q."""
    qs = np.vstack([np.zeros(b.n), b.random_q(16, rng=0)])
    return float(np.abs(armkit.fk(a, qs) - armkit.fk(b, qs))[:, :3].max())


@pytest.mark.parametrize("name", armkit.bundled_robots())
@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_the_dh_twin_has_the_fk_of_the_chain(name, convention):
    r = armkit.load(name)
    twin = chain_to_dh(r, convention)
    assert twin.convention == convention and twin.n == r.n
    assert _fk_error(twin, r) <= CHECK_TOL * max(r.reach, 1.0)


def _bent(eps: float, kinds: str) -> Robot:
    """A URDF-style chain whose second axis leans by ``eps`` rad from the first (parallel when 0)."""
    joints = [Joint(kind="revolute" if k == "R" else "prismatic", origin=transl(0.3, 0.1 * i, 0.2),
                    axis=[0.0, np.sin(eps) if i == 1 else 0.0, 1.0], name=f"j{i}") for i, k in enumerate(kinds)]
    return Robot(joints, "urdf", name="bent")


@pytest.mark.parametrize("kinds", ["RRR", "RPR"])
@pytest.mark.parametrize("eps", [0.0, 1e-12, 1e-10, 1e-8, 1e-6, 1e-4])
def test_the_axes_check_agrees_with_an_fk_check(eps, kinds):
    """Where the twin is accepted its FK is the chain's; where it is refused an FK check refuses it too."""
    r = _bent(eps, kinds)
    tol = CHECK_TOL * max(r.reach, 1.0)
    unchecked = chain_to_dh(r, "standard", check=False)
    try:
        twin = chain_to_dh(r, "standard")
    except RobotDefinitionError as exc:
        assert "no DH table reproduces this chain" in str(exc)
        assert _fk_error(unchecked, r) > tol             # the FK check would have refused it as well
        assert _axes_mismatch(unchecked, r, r.reach) > tol
    else:
        assert _fk_error(twin, r) <= tol


def test_the_axes_check_sees_a_wrong_twin():
    """A twin with one DH length changed by 1e-6 of the reach is caught by the axes, like FK catches it."""
    r = armkit.load("puma560")
    twin = chain_to_dh(r, "standard")
    j = twin.joints[2]
    wrong = Robot([*twin.joints[:2], Joint(j.kind, j.theta, j.d, j.a + 1e-6 * r.reach, j.alpha, j.lower, j.upper,
                                           j.name), *twin.joints[3:]],
                  "standard", r.name, r.unit, twin.base, twin.tool)
    assert _axes_mismatch(twin, r, r.reach) <= CHECK_TOL * r.reach
    assert _axes_mismatch(wrong, r, r.reach) > CHECK_TOL * r.reach
    assert _fk_error(wrong, r) > CHECK_TOL * r.reach


def test_the_model_imports_neither_kinematics_nor_collision():
    """The floors (docs/architecture.md): nothing in armkit/model imports the floors above it."""
    import ast
    from pathlib import Path

    folder = Path(armkit.__file__).parent / "model"
    above = ("kinematics", "collision", "ik", "analysis", "motion", "reach", "viz", "symbolic", "cli")
    for path in folder.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.level >= 2:
                first = (node.module or "").split(".")[0]
                assert first not in above, f"{path.name}:{node.lineno} imports armkit.{node.module}"
