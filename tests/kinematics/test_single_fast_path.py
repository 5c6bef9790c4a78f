"""The single-call fast path of ``fk`` and ``jacobian`` (issue 19): the compiled kernel called without
Numba's dispatcher, for one configuration given as a float64 1-D ndarray.

Reference: the batched path of the same functions (``q[None]``: the block kernels with their own
vectorised sine/cosine pass), which must give the same numbers bit for bit, on random DH arms of both
conventions with prismatic joints and random base and tool transforms, and on the bundled arms (URDF
ones included). Each check also proves that the fast path answered (the general path is made to fail).
Inputs the fast path must not take (another dtype, byte order, subclass, length, NaN, the NumPy back end)
still get the general path's answers and messages.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit import Robot, kinematics
from armkit.errors import ArgumentError, ShapeError
from test_kinematics import random_arm   # random DH arms of both conventions, prismatic joints included

jit = pytest.importorskip("armkit.kinematics._jit")
BUNDLED = sorted(armkit.bundled_robots())


def _variants(q: np.ndarray) -> list[np.ndarray]:
    """``q`` as the fast path may meet it: contiguous, strided, reversed, read-only, not 8-byte aligned."""
    n = q.shape[0]
    strided = np.zeros(2 * n)
    strided[::2] = q
    reversed_ = np.ascontiguousarray(q[::-1])[::-1]
    readonly = q.copy()
    readonly.setflags(write=False)
    raw = np.zeros(8 * n + 1, np.uint8)
    misaligned = raw[1:].view(np.float64)   # a float64 view one byte off
    misaligned[:] = q
    assert not misaligned.flags.aligned
    return [q, strided[::2], reversed_, readonly, misaligned]


def _general_path_forbidden(monkeypatch):
    def refuse(*args, **kwargs):
        raise AssertionError("the general path answered a plain single call")
    monkeypatch.setattr(kinematics, "_fk", refuse)
    monkeypatch.setattr(kinematics, "_jacobian", refuse)


def _check_fast_equals_batched(robot: Robot, q: np.ndarray) -> None:
    batched = {"fk": armkit.fk(robot, q[None])[0],
               "base": armkit.jacobian(robot, q[None])[0],
               "tool": armkit.jacobian(robot, q[None], frame="tool")[0]}
    before = q.copy()
    armkit.fk(robot, q)                        # the general path once: builds the robot's record, loads kernels
    armkit.jacobian(robot, q)
    with pytest.MonkeyPatch.context() as mp:
        _general_path_forbidden(mp)
        for x in _variants(q):
            T = armkit.fk(robot, x)
            assert T.shape == (4, 4) and T.flags.c_contiguous and T.flags.writeable and T.base is None
            assert np.array_equal(T, batched["fk"])
            assert np.array_equal(armkit.jacobian(robot, x), batched["base"])
            assert np.array_equal(armkit.jacobian(robot, x, frame="tool"), batched["tool"])
    assert np.array_equal(q, before)               # q untouched


@given(random_arm(max_joints=9, placed=True), st.integers(0, 2**32 - 1),   # past the kernel's 8-joint branch
       st.sampled_from([1.0, 1.0, 40.0, 2e5]))
@settings(max_examples=60, deadline=None)
def test_fast_single_call_equals_batched_bit_for_bit_on_random_arms(arm, seed, spread):
    # spread 40 and 2e5: joint values past one turn and past the short range reduction (libm's sin/cos)
    q = arm.random_q(rng=seed) * spread
    _check_fast_equals_batched(arm, q)


@pytest.mark.parametrize("name", BUNDLED)
@given(seed=st.integers(0, 2**32 - 1))
@settings(max_examples=8, deadline=None)
def test_fast_single_call_equals_batched_bit_for_bit_on_bundled_arms(name, seed):
    robot = armkit.load(name)
    _check_fast_equals_batched(robot, robot.random_q(rng=seed) * 1.5)


def test_results_are_fresh_arrays():
    robot = armkit.load("ur5")
    q = robot.random_q(rng=1)
    T1, T2 = armkit.fk(robot, q), armkit.fk(robot, q)
    J1, J2 = armkit.jacobian(robot, q), armkit.jacobian(robot, q)
    assert T1 is not T2 and not np.shares_memory(T1, T2) and np.array_equal(T1, T2)
    assert J1 is not J2 and not np.shares_memory(J1, J2) and np.array_equal(J1, J2)


class _Sub(np.ndarray):
    """An ndarray subclass: not the exact type the fast path takes."""


def test_what_the_fast_path_refuses_gets_the_general_answers():
    robot = armkit.load("puma560")
    q = robot.random_q(rng=4)
    armkit.fk(robot, q)
    armkit.jacobian(robot, q)
    T, J = armkit.fk(robot, q), armkit.jacobian(robot, q)
    # other dtypes, byte order and a subclass: converted by the general path, same numbers
    for x in (q.astype(np.float32), q.astype(np.float16), np.ma.masked_array(q), list(q), q.view(_Sub)):
        expected = armkit.fk(robot, np.array(x, dtype=np.float64)[None])[0]
        assert np.array_equal(armkit.fk(robot, x), expected)
    assert np.array_equal(armkit.fk(robot, q.astype(">f8")), T)
    assert np.array_equal(armkit.jacobian(robot, q.astype(">f8")), J)
    with pytest.raises(ShapeError, match=r"shape \(\.\.\., 6\)"):
        armkit.fk(robot, np.zeros(5))
    with pytest.raises(ShapeError, match=r"shape \(\.\.\., 6\)"):
        armkit.jacobian(robot, np.zeros(7))
    bad = q.copy()
    bad[2] = np.nan
    with pytest.raises(ShapeError, match="NaN or infinite"):
        armkit.fk(robot, bad)
    bad[2] = -np.inf
    with pytest.raises(ShapeError, match="NaN or infinite"):
        armkit.jacobian(robot, bad, frame="tool")
    with pytest.raises(ArgumentError, match="frame must be 'base' or 'tool', got 'world'"):
        armkit.jacobian(robot, q, frame="world")
    with pytest.raises(ArgumentError, match="robot must be an armkit.Robot, got the string"):
        armkit.fk("puma560", q)


def test_numpy_back_end_is_never_served_by_the_compiled_kernel(monkeypatch):
    robot = armkit.load("ur5")
    q = robot.random_q(rng=5)
    armkit.fk(robot, q)
    armkit.jacobian(robot, q)        # the fast path is armed
    calls = []
    monkeypatch.setattr(kinematics._numpy, "fk", lambda *a: calls.append("fk") or np.zeros((1, 4, 4)))
    monkeypatch.setattr(kinematics._numpy, "jacobian", lambda *a: calls.append("jac") or np.zeros((1, 6, 6)))
    armkit.set_backend("numpy")
    try:
        assert not armkit.fk(robot, q).any() and not armkit.jacobian(robot, q).any()
    finally:
        armkit.set_backend("auto")
    assert calls == ["fk", "jac"]


def test_entry_points_are_the_compiled_functions_of_the_one_signature_dispatchers():
    robot = armkit.load("ur5")
    armkit.fk(robot, np.zeros(6))
    armkit.jacobian(robot, np.zeros(6))
    for entry, dispatcher in ((jit.fk_one_entry, jit.fk_one_fast), (jit.jacobian_one_entry, jit.jacobian_one_fast)):
        assert len(dispatcher.signatures) == 1
        assert dispatcher.overloads[dispatcher.signatures[0]].entry_point is entry
