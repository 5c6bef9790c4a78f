"""Laws and broadcasting for spatial, fk, jacobian and ik (in the manner of jaxlie's group-axiom and broadcast tests).

Two ideas, each written once and run over every object:

* broadcasting: a function called on batches whose leading axes mix size-1 and full axes gives,
  at every index, what it gives on that index's single inputs (batched == looped);
* laws: identities that hold for every pose, rotation or robot (``exp(log(T)) == T``,
  ``inverse(T) @ T == I``, FK of a batch == FK looped, ...).
"""

from __future__ import annotations

from typing import Any, Callable

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit import spatial

ROBOTS = armkit.bundled_robots()

# leading (batch) shapes of two arguments: size-1 axes mixed with batches, and the single case ()
SHAPE_PAIRS = [((), ()), ((3,), ()), ((), (4,)), ((1,), (4,)), ((2, 1), (1, 3)), ((2, 3), (3,)), ((1, 1), (2, 1))]


# ----------------------------------------------------------------------------- random objects
def _rotations(rng: np.random.Generator, lead: tuple[int, ...]) -> np.ndarray:
    """Uniform random rotations, shape lead + (3, 3) (from unit quaternions, written out here)."""
    q = rng.normal(size=lead + (4,))
    w, x, y, z = np.moveaxis(q / np.linalg.norm(q, axis=-1, keepdims=True), -1, 0)
    R = np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
                  2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                  2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1)
    return R.reshape(lead + (3, 3))


def _poses(rng: np.random.Generator, lead: tuple[int, ...]) -> np.ndarray:
    T = np.zeros(lead + (4, 4))
    T[..., :3, :3] = _rotations(rng, lead)
    T[..., :3, 3] = rng.uniform(-2, 2, lead + (3,))
    T[..., 3, 3] = 1.0
    return T


def _angles(rng: np.random.Generator, lead: tuple[int, ...]) -> np.ndarray:
    return rng.uniform(-3.0, 3.0, lead)


def _vectors(n: int, scale: float = 1.0) -> Callable[[np.random.Generator, tuple[int, ...]], np.ndarray]:
    return lambda rng, lead: rng.uniform(-scale, scale, lead + (n,))


# (name, function, makers of each argument, each argument's core ndim)
UNARY: list[tuple[str, Callable[..., Any], Callable[..., np.ndarray], int]] = [
    ("rotx", spatial.rotx, _angles, 0),
    ("roty", spatial.roty, _angles, 0),
    ("rotz", spatial.rotz, _angles, 0),
    ("transl", spatial.transl, _vectors(3), 1),
    ("inverse", spatial.inverse, _poses, 2),
    ("skew", spatial.skew, _vectors(3), 1),
    ("rpy_to_rotation", spatial.rpy_to_rotation, _vectors(3, 1.4), 1),
    ("rotation_to_rpy", spatial.rotation_to_rpy, _rotations, 2),
    ("quaternion_to_rotation", spatial.quaternion_to_rotation, _vectors(4), 1),
    ("rotation_to_quaternion", spatial.rotation_to_quaternion, _rotations, 2),
    ("rotation_to_axis_angle", spatial.rotation_to_axis_angle, _rotations, 2),
    ("so3_exp", spatial.so3_exp, _vectors(3, 2.0), 1),
    ("so3_log", spatial.so3_log, _rotations, 2),
    ("se3_exp", spatial.se3_exp, _vectors(6, 2.0), 1),
    ("se3_log", spatial.se3_log, _poses, 2),
]
BINARY: list[tuple[str, Callable[..., Any], tuple[Callable[..., np.ndarray], ...], tuple[int, int]]] = [
    ("make_pose", spatial.make_pose, (_rotations, _vectors(3)), (2, 1)),
    ("compose", spatial.compose, (_poses, _poses), (2, 2)),
    ("pose_error", spatial.pose_error, (_poses, _poses), (2, 2)),
    ("axis_angle_to_rotation", spatial.axis_angle_to_rotation, (_vectors(3), _angles), (1, 0)),
]


def _pick(index: tuple[int, ...], lead: tuple[int, ...]) -> tuple[int, ...]:
    """The element of an argument with leading shape ``lead`` that broadcasting pairs with ``index``."""
    own = index[len(index) - len(lead):] if lead else ()
    return tuple(0 if size == 1 else i for i, size in zip(own, lead))


def assert_batched_equals_looped(fn: Callable[..., Any], args: list[np.ndarray], cores: list[int]) -> None:
    """``fn(*args)[index] == fn(*(a[picked] for a in args))`` at every index of the broadcast batch."""
    leads = [a.shape[:a.ndim - c] for a, c in zip(args, cores)]
    batch = np.broadcast_shapes(*leads)
    out = fn(*args)
    outs = out if isinstance(out, tuple) else (out,)
    for o in outs:
        assert np.shape(o)[:len(batch)] == batch, (np.shape(o), batch)
    for index in np.ndindex(*batch):
        single = fn(*(a[_pick(index, lead)] for a, lead in zip(args, leads)))
        for o, s in zip(outs, single if isinstance(single, tuple) else (single,)):
            np.testing.assert_allclose(np.asarray(o)[index], s, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("name, fn, make, core", UNARY, ids=[u[0] for u in UNARY])
@pytest.mark.parametrize("lead", [(), (1,), (4,), (2, 1, 3)], ids=str)
def test_spatial_unary_batched_equals_looped(name, fn, make, core, lead):
    rng = np.random.default_rng(abs(hash((name, lead))) % 2**32)
    assert_batched_equals_looped(fn, [make(rng, lead)], [core])


@pytest.mark.parametrize("name, fn, makers, cores", BINARY, ids=[b[0] for b in BINARY])
@pytest.mark.parametrize("leads", SHAPE_PAIRS, ids=str)
def test_spatial_binary_broadcasts_size_one_axes(name, fn, makers, cores, leads):
    rng = np.random.default_rng(7)
    args = [make(rng, lead) for make, lead in zip(makers, leads)]
    assert_batched_equals_looped(fn, args, list(cores))


def test_the_broadcast_check_can_fail():
    # a function that ignores broadcasting (always uses the first element) must be caught
    def first_only(T: np.ndarray) -> np.ndarray:
        return np.broadcast_to(spatial.inverse(T.reshape(-1, 4, 4)[0]), T.shape)

    with pytest.raises(AssertionError):
        assert_batched_equals_looped(first_only, [_poses(np.random.default_rng(0), (3,))], [2])


# ----------------------------------------------------------------------------- laws, written once
LAWS: dict[str, Callable[[np.ndarray], None]] = {}


def law(fn: Callable[[np.ndarray], None]) -> Callable[[np.ndarray], None]:
    LAWS[fn.__name__] = fn
    return fn


@law
def inverse_is_a_two_sided_inverse(T: np.ndarray) -> None:
    eye = np.broadcast_to(np.eye(4), T.shape)
    np.testing.assert_allclose(spatial.inverse(T) @ T, eye, atol=1e-12)
    np.testing.assert_allclose(spatial.compose(T, spatial.inverse(T)), eye, atol=1e-12)


@law
def inverse_of_inverse_is_the_pose(T: np.ndarray) -> None:
    np.testing.assert_allclose(spatial.inverse(spatial.inverse(T)), T, atol=1e-12)


@law
def se3_exp_of_log_is_the_pose(T: np.ndarray) -> None:
    np.testing.assert_allclose(spatial.se3_exp(spatial.se3_log(T)), T, atol=1e-9)


@law
def so3_exp_of_log_is_the_rotation(T: np.ndarray) -> None:
    np.testing.assert_allclose(spatial.so3_exp(spatial.so3_log(T)), T[..., :3, :3], atol=1e-9)


@law
def quaternion_round_trip(T: np.ndarray) -> None:
    R = T[..., :3, :3]
    np.testing.assert_allclose(spatial.quaternion_to_rotation(spatial.rotation_to_quaternion(R)), R, atol=1e-12)


@law
def rpy_round_trip(T: np.ndarray) -> None:
    R = T[..., :3, :3]
    np.testing.assert_allclose(spatial.rpy_to_rotation(spatial.rotation_to_rpy(R)), R, atol=1e-9)


@law
def axis_angle_round_trip(T: np.ndarray) -> None:
    R = T[..., :3, :3]
    np.testing.assert_allclose(spatial.axis_angle_to_rotation(*spatial.rotation_to_axis_angle(R)), R, atol=1e-9)


@law
def pose_error_is_zero_to_itself_and_symmetric(T: np.ndarray) -> None:
    dp, dr = spatial.pose_error(T, T)
    np.testing.assert_allclose(dp, 0.0, atol=1e-12)
    np.testing.assert_allclose(dr, 0.0, atol=1e-7)
    U = T[::-1]
    np.testing.assert_allclose(spatial.pose_error(T, U), spatial.pose_error(U, T), atol=1e-9)


@law
def pose_error_angle_is_the_log_norm(T: np.ndarray) -> None:
    U = T[::-1]
    rel = spatial.inverse(T) @ U
    np.testing.assert_allclose(spatial.pose_error(T, U)[1], np.linalg.norm(spatial.so3_log(rel), axis=-1),
                               atol=1e-9)


@law
def log_of_a_product_of_rotations_about_one_axis_adds(T: np.ndarray) -> None:
    w = spatial.so3_log(T)
    a = spatial.so3_exp(0.3 * w) @ spatial.so3_exp(0.5 * w)
    np.testing.assert_allclose(a, spatial.so3_exp(0.8 * w), atol=1e-12)


@pytest.mark.parametrize("name", sorted(LAWS))
@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31), n=st.integers(2, 5))
def test_spatial_law(name, seed, n):
    LAWS[name](_poses(np.random.default_rng(seed), (n,)))


def test_laws_can_fail():
    # the laws are real checks: a pose whose rotation is not orthonormal breaks inverse()
    T = _poses(np.random.default_rng(1), (3,))
    T[..., 0, 0] += 0.5
    with pytest.raises(AssertionError):
        LAWS["inverse_is_a_two_sided_inverse"](T)


# ----------------------------------------------------------------------------- fk, jacobian and ik
def _q(robot: armkit.Robot, lead: tuple[int, ...], seed: int = 0) -> np.ndarray:
    return robot.random_q(int(np.prod(lead, dtype=int)), np.random.default_rng(seed)).reshape(lead + (robot.n,))


@pytest.mark.parametrize("name", ROBOTS)
@pytest.mark.parametrize("lead", [(), (1,), (5,), (2, 1, 3)], ids=str)
def test_fk_jacobian_frames_batched_equal_looped_on_every_robot(name, lead):
    arm = armkit.load(name)
    q = _q(arm, lead)
    for fn in (armkit.fk, armkit.jacobian, armkit.fk_frames, armkit.manipulability):
        assert_batched_equals_looped(lambda x, fn=fn: fn(arm, x), [q], [1])


@pytest.mark.parametrize("name", ROBOTS)
def test_jacobian_tool_frame_is_the_base_frame_rotated(name):
    # a law tying two outputs: J_tool = blockdiag(R^T, R^T) J_base, R the tool rotation
    arm = armkit.load(name)
    q = _q(arm, (4,), seed=3)
    R = armkit.fk(arm, q)[..., :3, :3]
    Rt = np.swapaxes(R, -1, -2)
    Jb, Jt = armkit.jacobian(arm, q, frame="base"), armkit.jacobian(arm, q, frame="tool")
    np.testing.assert_allclose(Jt[:, :3], Rt @ Jb[:, :3], atol=1e-9 * arm.reach)
    np.testing.assert_allclose(Jt[:, 3:], Rt @ Jb[:, 3:], atol=1e-9)


def _ik_fields(res: armkit.IKResult) -> list[np.ndarray]:
    return [np.asarray(res.q), np.asarray(res.success), np.asarray(res.position_error)]


@pytest.mark.parametrize("name", ["puma560", "ur5", "planar3"])
def test_ik_one_q0_row_against_a_batch_of_targets(name):
    arm = armkit.load(name)
    q_true = _q(arm, (4,), seed=5)
    T = armkit.fk(arm, q_true)
    q0 = q_true[:1] * 0.9   # shape (1, n): one guess for every target
    batched = armkit.ik(arm, T, q0=q0, method="lm", seed=0)
    assert np.shape(batched.q) == (4, arm.n)
    for i in range(4):
        single = armkit.ik(arm, T[i], q0=q0[0], method="lm", seed=0)
        assert bool(batched.success[i]) == bool(single.success)
        np.testing.assert_allclose(armkit.fk(arm, batched.q[i]), armkit.fk(arm, single.q), atol=1e-6 * arm.reach)
    assert np.all(batched.success)


@pytest.mark.parametrize("leads", [((2, 1), (1, 3)), ((1,), (3,)), ((), (3,)), ((3,), (1,)),
                                   ((2, 3), (3,))],
                         ids=str)
def test_ik_closed_form_broadcasts_q0_against_targets(leads):
    arm = armkit.load("puma560")
    lead_T, lead_q = leads
    T = armkit.fk(arm, _q(arm, lead_T, seed=2))
    q0 = _q(arm, lead_q, seed=4)
    res = armkit.ik(arm, T, q0=q0, method="analytic")
    batch = np.broadcast_shapes(lead_T, lead_q)
    assert np.shape(res.q) == batch + (arm.n,)
    for index in np.ndindex(*batch):
        single = armkit.ik(arm, T[_pick(index, lead_T)], q0=q0[_pick(index, lead_q)], method="analytic")
        np.testing.assert_allclose(res.q[index], single.q, atol=1e-9)
        assert bool(res.success[index]) == bool(single.success)


def test_ik_q0_that_does_not_broadcast_is_refused_with_both_shapes():
    arm = armkit.load("puma560")
    T = armkit.fk(arm, _q(arm, (2,), seed=2))
    with pytest.raises(ValueError, match=r"q0 must broadcast to the targets' shape \(2, 6\), got \(3, 6\)"):
        armkit.ik(arm, T, q0=_q(arm, (3,), seed=4), method="analytic")
