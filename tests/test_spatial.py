"""Spatial primitives: elementary transforms by hand (the homogeneous-transform seminar), conversions, log/exp laws."""

from __future__ import annotations

import re

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from armkit import spatial as sp
from armkit.errors import NotRigidError, ShapeError

angles = st.floats(-np.pi, np.pi, allow_nan=False)
vec3 = arrays(float, 3, elements=st.floats(-2, 2, allow_nan=False))


def test_elementary_rotations_by_hand():
    c, s = np.cos(0.3), np.sin(0.3)
    assert np.allclose(sp.rotx(0.3)[:3, :3], [[1, 0, 0], [0, c, -s], [0, s, c]], atol=1e-15)
    assert np.allclose(sp.roty(0.3)[:3, :3], [[c, 0, s], [0, 1, 0], [-s, 0, c]], atol=1e-15)
    assert np.allclose(sp.rotz(0.3)[:3, :3], [[c, -s, 0], [s, c, 0], [0, 0, 1]], atol=1e-15)
    assert np.array_equal(sp.transl(1, 2, 3)[:3, 3], [1, 2, 3])


def test_two_link_chain_of_the_transform_seminar_by_hand():
    # 0T1 = Rz(t1) Tx(l1), 1T2 = Rz(t2) Tx(l2); 0T2 translation = (l1 c1 + l2 c12, l1 s1 + l2 s12)
    l1, l2, t1, t2 = 0.7, 0.4, 0.5, -1.1
    T = sp.compose(sp.rotz(t1), sp.transl(l1, 0, 0), sp.rotz(t2), sp.transl(l2, 0, 0))
    expected = [l1 * np.cos(t1) + l2 * np.cos(t1 + t2), l1 * np.sin(t1) + l2 * np.sin(t1 + t2), 0]
    assert np.allclose(T[:3, 3], expected, atol=1e-15)


def test_batched_shapes():
    t = np.linspace(0, 1, 12).reshape(3, 4)
    assert sp.rotz(t).shape == (3, 4, 4, 4)
    assert sp.inverse(sp.rotz(t)).shape == (3, 4, 4, 4)
    assert sp.rpy_to_rotation(np.zeros((5, 3))).shape == (5, 3, 3)
    assert sp.se3_log(sp.rotx(t)).shape == (3, 4, 6)


@given(angles, angles, angles, vec3)
def test_inverse_is_inverse(a, b, c, p):
    T = sp.compose(sp.transl(p), sp.rotz(a), sp.roty(b), sp.rotx(c))
    assert np.allclose(T @ sp.inverse(T), np.eye(4), atol=1e-12)


@given(angles, st.floats(-1.5, 1.5), angles)
def test_rpy_matches_elementary_product_and_round_trips(r, p, y):
    R = sp.rpy_to_rotation([r, p, y])
    assert np.allclose(R, (sp.rotz(y) @ sp.roty(p) @ sp.rotx(r))[:3, :3], atol=1e-14)
    assert np.allclose(sp.rotation_to_rpy(R), [r, p, y], atol=1e-9)


def test_rpy_matches_scipy():
    from scipy.spatial.transform import Rotation

    a = np.random.default_rng(1).uniform(-1.5, 1.5, (50, 3))
    assert np.allclose(sp.rpy_to_rotation(a), Rotation.from_euler("xyz", a).as_matrix(), atol=1e-14)


@given(arrays(float, 4, elements=st.floats(-1, 1)).filter(lambda q: np.linalg.norm(q) > 0.1))
def test_quaternion_round_trip(q):
    q = q / np.linalg.norm(q)
    R = sp.quaternion_to_rotation(q)
    q2 = sp.rotation_to_quaternion(R)
    assert np.allclose(q2, q if q[3] >= 0 else -q, atol=1e-9) or np.isclose(abs(q[3]), 0, atol=1e-9)
    assert np.allclose(sp.quaternion_to_rotation(q2), R, atol=1e-12)


def test_quaternion_order_is_scalar_last():
    R = sp.quaternion_to_rotation([0, 0, np.sin(np.pi / 4), np.cos(np.pi / 4)])  # 90 deg about z
    assert np.allclose(R, sp.rotz(np.pi / 2)[:3, :3], atol=1e-15)


@given(vec3, st.floats(0.01, 3.1))
def test_axis_angle_round_trip(axis, angle):
    if np.linalg.norm(axis) < 1e-3:
        return
    R = sp.axis_angle_to_rotation(axis, angle)
    u, th = sp.rotation_to_axis_angle(R)
    assert np.isclose(th, angle, atol=1e-9)
    assert np.allclose(u, axis / np.linalg.norm(axis), atol=1e-7)


@given(vec3, vec3)
def test_se3_exp_log_round_trip(v, w):
    if np.linalg.norm(w) > 3.0:
        w = w / np.linalg.norm(w) * 3.0
    xi = np.concatenate([v, w])
    assert np.allclose(sp.se3_log(sp.se3_exp(xi)), xi, atol=1e-12)


@pytest.mark.filterwarnings("error")
@pytest.mark.parametrize("angle", [0.0, 1e-300, 1e-200, 1e-9, 1e-6, 1e-3, 0.0999, 0.1, 0.1001, 1.0, 3.0])
def test_se3_round_trip_at_small_and_large_angles(angle):
    # hypothesis found (0, 1, 1, 1e-6, 1e-6, 1e-6) off by 1e-5 when (1 - cos t) cancelled; now exact to rounding
    w = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8]) * angle
    xi = np.concatenate([[0.2, 1.0, -0.7], w])
    assert np.allclose(sp.se3_log(sp.se3_exp(xi)), xi, atol=1e-14)
    # the rotation part agrees with Rodrigues' formula written out here
    K = sp.skew(w)
    R = np.eye(3) + (np.sinc(angle / np.pi)) * K + (0.5 * np.sinc(angle / (2 * np.pi)) ** 2) * (K @ K)
    assert np.allclose(sp.se3_exp(xi)[:3, :3], R, atol=1e-15)


def test_se3_exp_of_pure_rotation_about_offset_axis():
    # rotating by pi/2 about the z axis through (1, 0, 0): the origin goes to (1, -1, 0); twist v = -w x r
    w = np.array([0, 0, np.pi / 2])
    v = -np.cross(w, [1.0, 0, 0])
    T = sp.se3_exp(np.concatenate([v, w]))
    assert np.allclose(T[:3, 3], [1, -1, 0], atol=1e-12)


def test_pose_error_by_hand():
    dp, dr = sp.pose_error(sp.transl(3, 4, 0), sp.compose(sp.transl(0, 0, 0), sp.rotx(np.pi)))
    assert dp == pytest.approx(5.0)
    assert dr == pytest.approx(np.pi)
    _, small = sp.pose_error(np.eye(4), sp.rotz(1e-10))
    assert small == pytest.approx(1e-10, rel=1e-6)


def test_bad_shapes_raise():
    with pytest.raises(ShapeError, match=r"\(\.\.\., 3\)"):
        sp.transl([1, 2])
    with pytest.raises(ShapeError, match="x, y, z, w"):
        sp.quaternion_to_rotation([1, 0, 0])
    with pytest.raises(ShapeError, match="non-zero"):
        sp.axis_angle_to_rotation([0, 0, 0], 1.0)


# ------------------------------------------------------------------------ check_transform
quat = arrays(float, 4, elements=st.floats(-1, 1)).filter(lambda q: np.linalg.norm(q) > 0.1)


def _pose(q, p):
    return sp.make_pose(sp.quaternion_to_rotation(q / np.linalg.norm(q)), p)


@given(quat, vec3)
def test_check_transform_accepts_every_rigid_pose(q, p):
    T = _pose(q, p)
    out = sp.check_transform(T)
    assert out.dtype == np.float64 and np.array_equal(out, T)
    assert np.array_equal(sp.check_transform(T.tolist()), T)          # nested lists too


@given(quat, vec3, st.integers(0, 2), st.floats(1e-5, 0.5))
@example(np.ones(4), np.zeros(3), 0, 0.35)   # 2 eps + eps^2 = 0.8225: on the edge of the third digit
def test_check_transform_rejects_a_stretched_axis_and_says_by_how_much(q, p, axis, eps):
    T = _pose(q, p) @ np.diag([1.0 + eps * (axis == 0), 1.0 + eps * (axis == 1), 1.0 + eps * (axis == 2), 1.0])
    # column `axis` has length 1 + eps: (R^T R)_aa - 1 = 2 eps + eps^2, by hand
    with pytest.raises(NotRigidError, match="not orthonormal") as info:
        sp.check_transform(T, what="target")
    # the message gives 3 significant digits; the hand value may sit on a rounding edge (0.8225 -> "0.822" or
    # "0.823" depending on the last bit), so the printed number is read and compared to half a unit of its last digit
    said = re.search(r"differs from I by ([0-9.e+-]+)\)", str(info.value))
    assert said is not None and str(info.value).startswith("target ")
    assert float(said[1]) == pytest.approx(2 * eps + eps * eps, rel=6e-3)
    assert isinstance(info.value, ValueError) and isinstance(info.value, ShapeError)


@given(quat, vec3)
def test_check_transform_rejects_a_reflection(q, p):
    with pytest.raises(NotRigidError, match=r"det R = -1 \(a reflection\), expected \+1"):
        sp.check_transform(_pose(q, p) @ np.diag([1.0, 1.0, -1.0, 1.0]))


def test_check_transform_last_row_must_be_exact():
    T = np.eye(4)
    T[3, 1] = 1e-12
    with pytest.raises(NotRigidError, match=r"last row is \(0, 1e-12, 0, 1\), expected exactly"):
        sp.check_transform(T)


@given(st.lists(st.tuples(quat, vec3), min_size=1, max_size=6), st.integers(0, 5), st.booleans())
def test_check_transform_batched_equals_looped(items, bad_at, spoil):
    T = np.stack([_pose(q, p) for q, p in items])
    if spoil:
        T[bad_at % len(T)] = T[bad_at % len(T)] @ np.diag([1.0, 1.0, -1.0, 1.0])
    looped = []
    for i, Ti in enumerate(T):
        try:
            sp.check_transform(Ti)
            looped.append(None)
        except NotRigidError as exc:
            looped.append(str(exc))
    first_bad = next((i for i, m in enumerate(looped) if m is not None), None)
    for batch, index in ((T, lambda i: f"T[{i}]"), (T.reshape(1, len(T), 4, 4), lambda i: f"T[0, {i}]")):
        if first_bad is None:
            assert np.array_equal(sp.check_transform(batch), batch)
        else:       # the same message, naming the first bad index of the batch
            with pytest.raises(NotRigidError) as info:
                sp.check_transform(batch)
            assert str(info.value) == looped[first_bad].replace("T is", index(first_bad) + " is", 1)


@pytest.mark.parametrize("bad, message", [
    (np.eye(3), r"T must have shape \(\.\.\., 4, 4\), got \(3, 3\)"),
    (np.zeros(4), r"T must have shape \(\.\.\., 4, 4\), got \(4,\)"),
    (np.full((4, 4), np.nan), "T contains NaN or infinite values"),
    (np.full((2, 4, 4), np.inf), "T contains NaN or infinite values"),
    ([[1, 0, 0, 0]] * 3 + [[0, 0, 0, 1j]], "T must be real numbers"),
    ("pose", "T must be numeric"),
])
def test_check_transform_shape_errors_name_the_argument(bad, message):
    with pytest.raises(ShapeError, match=message):
        sp.check_transform(bad)


@pytest.mark.parametrize("backend", ["numpy", "numba"])
@pytest.mark.parametrize("spoil, message", [
    (lambda T: T @ np.diag([1.0, 1.0, 1.0 + 1e-5, 1.0]), "not orthonormal"),
    (lambda T: T @ np.diag([1.0, 1.0, -1.0, 1.0]), "det R = -1"),
    (lambda T: T + np.outer([0, 0, 0, 1.0], [0, 0, 1e-12, 0]), "last row"),
])
def test_check_transform_of_a_big_batch_is_the_same_on_both_back_ends(backend, spoil, message):
    import armkit
    if backend == "numba":
        pytest.importorskip("numba")
    arm = armkit.load("ur5")
    T = armkit.fk(arm, arm.random_q(3000, rng=3).reshape(2, 1500, 6))   # 3,000 poses: the compiled pass
    armkit.set_backend(backend)
    try:
        assert sp.check_transform(T) is T
        T[1, 1234] = spoil(T[1, 1234])
        with pytest.raises(NotRigidError, match=r"^target\[1, 1234\] is not a rigid transform: .*" + message) as info:
            sp.check_transform(T, what="target")
        assert str(info.value) == str(pytest.raises(NotRigidError, sp.check_transform, T[1, 1234], what="x").value
                                      ).replace("x is", "target[1, 1234] is", 1)
    finally:
        armkit.set_backend("auto")
