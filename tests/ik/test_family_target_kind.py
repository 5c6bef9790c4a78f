"""``target_kind`` is part of the closed-form contract (issue 21): every family declares it, and it agrees with
``pose_only`` and with what ``armkit.ik`` accepts for that family."""

from __future__ import annotations

import numpy as np
import pytest

import armkit
from armkit.ik import analytic
from armkit.ik.analytic.geometric import Geometric, Geometric1R, Geometric2R, Geometric3R, GeometricGimbal
from armkit.ik.analytic.geometric_prismatic import GeometricPrismatic, GeometricPrismaticWrist, GeometricScara
from armkit.ik.geometric.locked import Locked

KINDS = ("position", "pose", "pitch")
# independent of the code: the families' targets as docs/ik.md's table states them
EXPECTED = {"planar-2r": "position", "yaw-pitch-pitch": "position", "planar-3r": "pose",
            "spherical-wrist": "pose", "ur": "pose", "yaw-pitch3": "pitch"}


def test_target_kind_is_in_the_protocol():
    assert "target_kind" in analytic.ClosedFormFamily.__annotations__


@pytest.mark.parametrize("cls", [*analytic.FAMILIES, Geometric, Geometric3R, Geometric2R, Geometric1R, GeometricGimbal, GeometricPrismatic, GeometricPrismaticWrist,
                                 GeometricScara, Locked], ids=lambda c: c.__name__)
def test_every_family_declares_a_known_target_kind(cls):
    assert cls.target_kind in KINDS
    assert cls.pose_only == (cls.target_kind != "position")
    if cls in analytic.FAMILIES:
        assert cls.target_kind == EXPECTED[cls.family]


def test_a_class_without_target_kind_does_not_satisfy_the_protocol():
    solver = analytic.closed_form(armkit.load("fighter"))

    class Without:
        family, branch_labels, m, pose_only, sf = solver.family, solver.branch_labels, solver.m, False, solver.sf
        geometry = None
        detect = solver.detect
        solve = solver.solve

    assert isinstance(solver, analytic.ClosedFormFamily)
    assert not isinstance(Without(), analytic.ClosedFormFamily)


def test_the_api_takes_pitch_only_for_a_pitch_family():
    assert analytic.closed_form(armkit.load("so101")).target_kind == "pitch"
    fighter = armkit.load("fighter")
    assert analytic.closed_form(fighter).target_kind == "position"
    with pytest.raises(armkit.ArmkitError, match="pitch"):
        armkit.ik(fighter, armkit.fk(fighter, np.zeros(3))[:3, 3], method="analytic", pitch=0.1)
