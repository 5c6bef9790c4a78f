"""Issue 21: one ``joint_axes`` (armkit.model.axes), used by the DH twin, the workspace and the pictures.

The reference is the kinematics' own frames (``fk_frames``): joint k's axis is the z axis of ``F_{k-1} · pre_k``.
"""

from __future__ import annotations

import importlib

import numpy as np
import pytest

import armkit
from armkit.kinematics import fk, fk_frames
from armkit.model import dh_extract
from armkit.model.axes import home_pose, joint_axes

ROBOTS = ("planar2", "planar3", "fighter", "puma560", "ur5", "stanford")


@pytest.mark.parametrize("name", ROBOTS)
def test_axes_are_the_z_axes_of_the_kinematics_frames(name):
    r = armkit.load(name)
    for q in [None, *r.random_q(3, rng=7)]:
        F = fk_frames(r, np.zeros(r.n) if q is None else q)
        A = F[:-1] @ r.chain.pre
        points, directions = joint_axes(r, q)
        np.testing.assert_allclose(points, A[:, :3, 3], atol=1e-12 * (1 + r.reach))
        np.testing.assert_allclose(directions, A[:, :3, 2], atol=1e-12)
        np.testing.assert_allclose(np.linalg.norm(directions, axis=1), 1.0, atol=1e-12)


@pytest.mark.parametrize("name", ROBOTS)
def test_home_pose_is_fk_at_zero(name):
    r = armkit.load(name)
    np.testing.assert_allclose(home_pose(r), fk(r, np.zeros(r.n)), atol=1e-12 * (1 + r.reach))


def test_a_hand_derived_planar_arm():
    """planar2 (links 1 and 1 m, both axes vertical): at q = (90 deg, 0) the elbow axis stands at (0, 1)."""
    points, directions = joint_axes(armkit.load("planar2"), [np.pi / 2, 0.0])
    np.testing.assert_allclose(points[:, :2], [[0.0, 0.0], [0.0, 1.0]], atol=1e-12)
    np.testing.assert_allclose(directions, [[0, 0, 1], [0, 0, 1]], atol=1e-12)


def test_one_name_one_function():
    """The workspace's joint_axes is this one; the DH twin has no joint_axes of its own."""
    workspace = importlib.import_module("armkit.analysis.workspace")   # (armkit.analysis.workspace is also a function)
    assert workspace.joint_axes is joint_axes and importlib.import_module("armkit.analysis").joint_axes is joint_axes
    assert dh_extract.joint_axes is joint_axes and "joint_axes" not in dh_extract.__all__


def test_one_configuration_only():
    r = armkit.load("planar2")
    with pytest.raises(armkit.ShapeError, match="one configuration"):
        joint_axes(r, np.zeros((3, 2)))
