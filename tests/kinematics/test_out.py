"""``out=`` of ``fk`` and ``jacobian``, and the single-call fast path (issue 19).

References: the looped single calls for a batch (each a different code path: the single-call kernel
against the batch kernels, one-thread and threaded), the call without ``out=`` for the call with it,
and the NumPy back end (its own matrix products and ``numpy.sin``/``cos``) for the Numba one.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, strategies as st

import armkit
from armkit import kinematics
from armkit.errors import ArgumentError, ShapeError

jit = pytest.importorskip("armkit.kinematics._jit")
ROBOTS = sorted(armkit.bundled_robots())


def _result_shape(f, robot, lead):
    return lead + ((4, 4) if f is armkit.fk else (6, robot.n))


@given(name=st.sampled_from(ROBOTS), lead=st.sampled_from([(), (1,), (3,), (2, 3), (jit.BLOCK + 3,)]),
       seed=st.integers(0, 2**32 - 1), f=st.sampled_from([armkit.fk, armkit.jacobian]),
       frame=st.sampled_from(["base", "tool"]))
def test_out_equals_a_new_result_and_batched_equals_looped(name, lead, seed, f, frame):
    robot = armkit.load(name)
    q = robot.random_q(int(np.prod(lead, dtype=int)), rng=seed).reshape(lead + (robot.n,)) * 1.5
    kw = {"frame": frame} if f is armkit.jacobian else {}
    new = f(robot, q, **kw)
    out = np.full(_result_shape(f, robot, lead), np.nan)
    got = f(robot, q, out=out, **kw)
    assert got is out                                   # written in place and returned, like a NumPy ufunc
    assert np.array_equal(out, new)                      # bit for bit: the same kernels
    looped = np.array([f(robot, x, **kw) for x in q.reshape(-1, robot.n)]).reshape(new.shape)
    assert np.abs(looped - new).max(initial=0.0) <= 1e-14 * max(1.0, robot.reach)


@pytest.mark.parametrize("f", [armkit.fk, armkit.jacobian])
def test_out_of_a_threaded_batch_equals_the_looped_single_calls(f):
    robot = armkit.load("panda")
    Q = robot.random_q(jit.PARALLEL_MIN + 5, rng=4)          # from PARALLEL_MIN on: the threaded kernel
    out = np.empty(_result_shape(f, robot, (len(Q),)))
    assert f(robot, Q, out=out) is out
    idx = [0, 1, jit.BLOCK, len(Q) // 2, len(Q) - 1]
    looped = np.array([f(robot, Q[i]) for i in idx])
    assert np.abs(out[idx] - looped).max() <= 1e-14 * robot.reach


@pytest.mark.parametrize("backend", ["numba", "numpy"])
def test_out_with_the_numpy_back_end_and_with_a_link(backend):
    robot = armkit.load("so101")
    Q = robot.random_q(4, rng=2)
    link = robot.links[2].name
    kinematics.set_backend(backend)
    try:
        for f, kw, shape in ((armkit.fk, {}, (4, 4, 4)), (armkit.fk, {"link": link}, (4, 4, 4)),
                             (armkit.jacobian, {"frame": "tool"}, (4, 6, robot.n))):
            out = np.empty(shape)
            assert f(robot, Q, out=out, **kw) is out
            assert np.array_equal(out, f(robot, Q, **kw))
        kinematics.set_backend("numpy")
        reference = armkit.fk(robot, Q, link=link)
    finally:
        kinematics.set_backend("auto")
    out = np.empty((4, 4, 4))
    assert np.abs(armkit.fk(robot, Q, link=link, out=out) - reference).max() <= 1e-14 * robot.reach


def _bad_outs(shape):
    good = np.empty(shape)
    ro = np.empty(shape)
    ro.setflags(write=False)
    bigger = np.empty(shape[:-1] + (shape[-1] * 2,))
    return [
        (good.tolist(), ArgumentError, r"out must be a numpy\.ndarray .*got list"),
        (np.empty(shape, np.float32), ArgumentError, "out must have dtype float64, got float32"),
        (np.empty(shape, ">f8"), ArgumentError, "out must have dtype float64, got >f8"),
        (np.empty((shape[0] + 1,) + shape[1:]), ShapeError,
         rf"out must have shape \({shape[0]}, {shape[1]}, {shape[2]}\) .*got \({shape[0] + 1}, "),
        (np.empty(shape[1:]), ShapeError, "out must have shape"),
        (bigger[..., ::2], ArgumentError, "out must be C-contiguous"),
        (ro, ArgumentError, "out must be writable"),
    ]


@pytest.mark.parametrize("backend", ["numba", "numpy"])
@pytest.mark.parametrize("f", [armkit.fk, armkit.jacobian])
def test_a_wrong_out_is_refused_naming_it_with_expected_and_got(f, backend):
    robot = armkit.load("ur5")
    Q = robot.random_q(3, rng=1)
    kinematics.set_backend(backend)
    try:
        for bad, error, message in _bad_outs(_result_shape(f, robot, (3,))):
            with pytest.raises(error, match=message) as info:
                f(robot, Q, out=bad)
            assert info.value.template and info.value.fields is not None   # a catalogue key (and its fields)
    finally:
        kinematics.set_backend("auto")


def test_out_overlapping_q_is_refused():
    robot = armkit.load("puma560")
    buf = np.zeros(64)
    with pytest.raises(ArgumentError, match="out must not overlap q"):
        armkit.fk(robot, buf[:6], out=buf[:16].reshape(4, 4))
    with pytest.raises(ArgumentError, match="out must not overlap q"):
        armkit.jacobian(robot, buf[:6], out=buf[4:40].reshape(6, 6))


def test_out_with_nan_still_raises_the_shape_error():
    robot = armkit.load("puma560")
    Q = np.zeros((3, 6))
    Q[1, 2] = np.nan
    with pytest.raises(ShapeError, match="NaN or infinite"):
        armkit.fk(robot, Q, out=np.empty((3, 4, 4)))
    with pytest.raises(ShapeError, match=r"shape \(\.\.\., 6\)"):
        armkit.jacobian(robot, np.zeros(5), out=np.empty((6, 6)))


def test_single_call_fast_path_survives_a_cleared_cache_and_a_wrong_frame():
    robot = armkit.load("stanford")
    q = robot.random_q(rng=3)
    T, J = armkit.fk(robot, q), armkit.jacobian(robot, q, frame="tool")
    robot.cache.clear()                                   # the cache only ever costs recomputation
    assert np.array_equal(armkit.fk(robot, q), T)
    assert np.array_equal(armkit.jacobian(robot, q, frame="tool"), J)
    with pytest.raises(ArgumentError, match="frame must be 'base' or 'tool', got 'world'"):
        armkit.jacobian(robot, q, frame="world")
    with pytest.raises(ArgumentError, match="robot must be an armkit.Robot, got NoneType"):
        armkit.fk(None, q)


def test_fast_single_call_kernels_have_one_signature_and_a_writable_private_f():
    robot = armkit.load("ur5")
    armkit.fk(robot, np.zeros(6))
    armkit.jacobian(robot, np.zeros(6))
    for name, twin in (("fk_one_fast", jit.fk_one_w), ("jacobian_one_fast", jit.jacobian_one_w)):
        kernel = getattr(jit, name)
        assert kernel is twin and len(kernel.signatures) == 1
    with pytest.raises(TypeError):                       # other argument types: refused at once, never compiled
        jit.fk_one_fast(np.zeros((7, jit.ROW), np.float32), np.zeros(6), np.empty((4, 4)))
    F, shape = robot.cache["single_call"]
    assert F.flags.writeable and shape == (6, 6)
    assert np.array_equal(F, kinematics.packed(robot)[0]) and F is not kinematics.packed(robot)[0]
