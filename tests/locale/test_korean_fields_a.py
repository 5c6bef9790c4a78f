"""Issue 21 item 2, part A: the errors and notes of motion/, viz/ (tracking, animation, arm), analysis/, spatial,
the array and memory checks, the arithmetic of typed values, kinematics and the closed-form exports keep their
template and fields, and a Korean user reads them in Korean (rendered from the catalogue, never parsed back).

One error (or note) per converted module, raised through the public API; each is checked with the helpers of
test_korean_everywhere.py: no run of English words outside the field values, and the English is the error's text.
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from test_korean_everywhere import ENV, _catalogue, _leaves, app, english_runs, english_words, runner

import armkit
from armkit.locale.library import PATTERNS, fielded, localize


@pytest.fixture(scope="module")
def planar2():
    return armkit.load("planar2")


@pytest.fixture(scope="module")
def fighter():
    return armkit.load("fighter")


def _korean(msg, extra_values: tuple = ()) -> str:
    """``msg`` (an error or a Fielded note) keeps its template and fields, the catalogue has the template (and its
    parts'), its Korean has Hangul and no English run outside the field values, and its English is its text."""
    keyed = fielded(msg) or fielded(str(msg))
    assert keyed is not None, msg
    ko_entries = _catalogue()
    assert ko_entries.get(keyed[0]), keyed[0]
    for v in keyed[1].values():       # a part's template too (a list of parts, "{p0}; {p1}", has no words)
        if fielded(v) is not None and re.search("[A-Za-z]", re.sub(r"\{\w+\}", "", fielded(v)[0])):
            assert ko_entries.get(fielded(v)[0]), fielded(v)[0]
    ko = localize(msg, "ko")
    assert re.search(r"[가-힣]", ko), ko
    assert english_runs(ko, tuple(_leaves(msg)) + extra_values) == [], (str(msg), ko)
    assert localize(msg, "en") == str(msg) != ko
    return ko


def _raised(call, *args, **kwargs) -> BaseException:
    with pytest.raises(Exception) as info:
        call(*args, **kwargs)
    return info.value


# ---------------------------------------------------------------------------------------------------- motion
def test_trajectory_errors(planar2):
    from armkit.motion import blended_polyline, cartesian_line, joint_trajectory, profile

    e = _raised(joint_trajectory, [[0.0, 0.0]])
    assert str(e) == "waypoints must have shape (m, n) with m >= 2, got (1, 2)"      # the English as before
    assert localize(e, "ko") == "경유점 배열은 (m, n) 모양이고 m >= 2여야 합니다(입력: (1, 2))"
    _korean(e)
    _korean(_raised(profile, "jerky", [0.5]))
    _korean(_raised(blended_polyline, [[0.0, 0.0], [1.0, 1.0]], radius=-1.0))
    _korean(_raised(cartesian_line, planar2, [1.2, 0.2], [0.6, 0.9], steps=1))


def test_a_waypoint_outside_the_limits_names_its_joints_in_korean(fighter):
    from armkit.motion import joint_trajectory

    far = np.radians([0.0, 0.0, 400.0])
    e = _raised(joint_trajectory, [np.zeros(3), far], duration=1.0, robot=fighter)
    assert str(e).startswith("waypoint 2 is outside the joint limits: ") and " outside [" in str(e), str(e)
    ko = _korean(e)
    assert "outside" not in ko and "한계" in ko, ko


def test_trajectory_notes_are_korean():
    from armkit.motion import joint_trajectory

    tr = joint_trajectory([[0.0], [1.0]], duration=0.1, qd_max=1.0, dt=0.01)
    assert tr.notes and tr.notes[0] == "segment 1 lengthened from 0.1 s to 1.88 s to honour the limits", tr.notes
    assert localize(tr.notes[0], "ko") == "한계를 지키도록 1번째 구간을 0.1 s에서 1.88 s로 늘렸습니다"
    coarse = joint_trajectory([[0.0], [1.0]], duration=1.0, dt=0.8)
    assert any(n.startswith("dt = 0.8 s is longer than half of segment 1") for n in coarse.notes), coarse.notes
    for note in (*tr.notes, *coarse.notes):
        _korean(note)


def test_a_memory_limit_says_what_and_how_in_korean(planar2, monkeypatch):
    from armkit.errors import LimitError
    from armkit.motion import cartesian_line

    monkeypatch.setenv("ARMKIT_MEMORY_LIMIT", "1M")
    e = _raised(cartesian_line, planar2, [1.2, 0.2], [0.6, 0.9], steps=100_000)
    assert isinstance(e, LimitError)       # 100,001 samples x 8 B x (3 n + 12 arrays) x 3 = 43,200,432 B = 41.2 MiB
    assert str(e) == ("a Cartesian path of 100,001 samples would need about 41.2 MiB of memory, more than the limit "
                      "of 1 MiB; ask for fewer --steps; or raise the limit with ARMKIT_MEMORY_LIMIT "
                      "(e.g. ARMKIT_MEMORY_LIMIT=16G)"), str(e)
    ko = _korean(e)
    assert "--steps를 줄이세요" in ko and "직교 좌표 경로" in ko, ko


def test_velocity_errors_and_messages(planar2):
    from armkit.motion import joint_rates, resolved_rate

    _korean(_raised(joint_rates, planar2, [0.0, 1.0], [0.1, 0.0], method="inverse"))
    _korean(_raised(resolved_rate, planar2, [0.0, 1.0], lambda t: (np.zeros(2), np.zeros(2)), -1.0))
    near = joint_rates(planar2, [0.0, 0.0], [0.0, 0.1])           # stretched: singular
    far = joint_rates(planar2, [0.0, 1.0], [0.0, 0.1])
    assert near.singular and near.message.startswith("near a singularity"), near.message
    assert far.message.startswith("well-conditioned"), far.message
    for msg in (near.message, far.message):
        _korean(msg)
    # the velocity's sentences are rendered from their fields now, no longer matched back
    assert not any(p.startswith(("near a singularity", "well-conditioned")) for p in PATTERNS)


def test_moved_and_missing_attributes():
    import armkit.kinematics
    import armkit.motion
    import armkit.viz

    moved = _raised(getattr, armkit.motion, "plot_trajectory")
    assert isinstance(moved, AttributeError) and "armkit.viz.plot_trajectory" in str(moved)
    _korean(moved)
    for module in (armkit.viz, armkit.kinematics, armkit.motion):
        e = _raised(getattr, module, "no_such_thing")
        assert isinstance(e, AttributeError) and str(e) == f"module {module.__name__!r} has no attribute 'no_such_thing'"
        _korean(e)


# ------------------------------------------------------------------------------------------------------ viz
def test_tracking_errors(planar2, tmp_path):
    from armkit.viz.tracking import target_path, track

    _korean(_raised(target_path, planar2, "circle", frames=1))
    _korean(_raised(track, planar2, "circle", method="magic", frames=4))
    bad = tmp_path / "targets.csv"
    bad.write_text("1,2\n3,nan\n", encoding="utf-8")
    e = _raised(target_path, planar2, str(bad), frames=4)
    assert str(e) == f"{bad}: contains NaN or infinite values"
    _korean(e, (str(tmp_path),))
    _korean(_raised(target_path, planar2, str(tmp_path / "none.csv")), (str(tmp_path),))


def test_animation_and_arm_errors(planar2, tmp_path):
    pytest.importorskip("matplotlib")
    from armkit.viz import plot_arm, render_animation

    _korean(_raised(render_animation, planar2, np.zeros((3, 2)), tmp_path / "a.txt"))
    _korean(_raised(render_animation, planar2, np.zeros((3, 2)), tmp_path / "a.gif", fps=0))
    _korean(_raised(plot_arm, planar2, np.zeros((2, 2)), labels=["only one"]))


# ------------------------------------------------------------------------------------------------- analysis
def test_analysis_errors(planar2):
    from armkit.analysis import Exclusion, workspace
    from armkit.analysis.maps import fk_maps

    _korean(_raised(workspace, planar2, samples=5))
    _korean(_raised(Exclusion, boxes=[((0, 0, 0), (1, 1))]))
    _korean(_raised(fk_maps, planar2, [0.0, 1.0], [0.0, 1.0], joints=(0, 0)))
    _korean(_raised(fk_maps, planar2, [0.0, np.nan], [0.0, 1.0]))


def test_singularity_errors():
    pytest.importorskip("sympy")
    pytest.importorskip("matplotlib")
    from armkit.analysis.singularity import plot_manipulability

    _korean(_raised(plot_manipulability, armkit.load("planar2"), None, joints=(1, 5)))


# ---------------------------------------------------------------------------------- spatial, checks, arithmetic
def test_a_pose_that_is_not_rigid_says_why_in_korean():
    from armkit.errors import NotRigidError
    from armkit.spatial import check_transform

    e = _raised(check_transform, np.diag([1.0, 1.0, -1.0, 1.0]), what="tool")
    assert isinstance(e, NotRigidError)
    assert str(e) == "tool is not a rigid transform: det R = -1 (a reflection), expected +1 (tolerance 1e-06)"
    assert localize(e, "ko") == "tool은 강체 변환이 아닙니다: det R = -1(반사)이며, +1이어야 합니다 (허용 오차 1e-06)"
    batch = np.tile(np.eye(4), (3, 1, 1))
    batch[2, 3] = [0.0, 0.0, 0.5, 1.0]
    e = _raised(check_transform, batch, what="targets")
    assert str(e).startswith("targets[2] is not a rigid transform: its last row is (0, 0, 0.5, 1)"), str(e)
    _korean(e)
    skewed = np.eye(4)
    skewed[0, 1] = 0.1
    _korean(_raised(check_transform, skewed))


def test_array_checks_and_arithmetic():
    from armkit import _arith
    from armkit._checks import real_array
    from armkit.spatial import rpy_to_rotation

    _korean(_raised(real_array, [1 + 2j], "q"))
    _korean(_raised(real_array, "abc", "q"), ("'abc'",))
    _korean(_raised(rpy_to_rotation, [1.0, 2.0]))
    for text in ("1/0", "2*(3", "", "1 + _", "1 +"):
        e = _raised(_arith.evaluate, text)
        assert isinstance(e, ValueError)                       # still a ValueError for generic code
        _korean(e)


def test_kinematics_errors(fighter):
    from armkit.kinematics import fk, jacobian

    e = _raised(fk, "fighter", [0.0, 0.0, 0.0])
    assert str(e) == "robot must be an armkit.Robot, got the string 'fighter'; load it first: armkit.load('fighter')"
    _korean(e)
    _korean(_raised(jacobian, fighter, [0.0, 0.0, 0.0], frame="world"))


def test_closed_form_exports_name_the_arms_in_korean():
    pytest.importorskip("sympy")
    from armkit.symbolic.ik_equations import ik_equations
    from armkit.symbolic.ik_export import to_ik_source

    puma = armkit.load("puma560")
    for call in (ik_equations, to_ik_source):
        ko = _korean(_raised(call, puma))
        assert "'puma560'" in ko, ko


# ----------------------------------------------------------------------------------------------- the CLI
def test_a_trajectory_note_is_korean_on_the_command_line():
    """`armkit traj` warns with the trajectory's notes (lengthened segments) in the user's language."""
    argv = ["traj", "planar2", "--joint", "0,0", "90,90", "--deg", "--duration", "0.1", "--qd-max", "1",
            "--lang", "ko"]
    res = runner.invoke(app, argv, env=ENV)
    assert res.exit_code == 0, res.stdout + (res.stderr or "")
    err = res.stderr or ""
    assert "늘렸습니다" in err and english_words(err) == [], err
