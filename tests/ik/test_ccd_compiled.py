"""CCD's two back ends (the compiled kernel of ``ik/_ccd_jit.py`` and the NumPy loop of ``ik/ccd.py``) and its
restart draws.

The laws: both back ends give the same answer (configuration, success, sweeps, starts, reasons, trace) on any
serial chain; a target's answer does not depend on the other targets of its batch (its restart draws depend on
the seed, its index and the attempt only); the draws are splitmix64 (S. Vigna's reference values).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import armkit
from armkit import Joint, Robot, _jit_loader
from armkit.ik import ccd
from armkit.ik.ccd import solve_ccd

numba = pytest.importorskip("numba")


def _solve(backend: str, *args, **kwargs):
    """solve_ccd on the back end ``"numba"`` or ``"numpy"``, the back end chosen before restored afterwards."""
    before = _jit_loader.backend_choice()
    armkit.set_backend(backend)
    try:
        assert armkit.get_backend() == backend
        return solve_ccd(*args, **kwargs)
    finally:
        armkit.set_backend(before)


@st.composite
def arms(draw):
    """1 to 6 joints, revolute or prismatic, random DH rows and limits, either convention."""
    n = draw(st.integers(1, 6))
    joints = []
    for _ in range(n):
        kind = draw(st.sampled_from(["revolute", "revolute", "prismatic"]))
        theta, d, a, alpha = (draw(st.floats(-1.5, 1.5)) for _ in range(4))
        if kind == "revolute":
            lo = draw(st.floats(-3.5, -0.3))
            hi = draw(st.floats(0.3, 3.5))
        else:
            lo = draw(st.floats(-0.6, -0.05))
            hi = draw(st.floats(0.05, 0.6))
        joints.append(Joint(kind, theta, d, a, alpha, lo, hi))
    return Robot(joints, draw(st.sampled_from(["standard", "modified"])))


def _same(a, b, arm):
    """The two results of ``arm`` agree field by field.

    A target that failed ends at the best of its iterates, next to a minimum of the error where the error is flat
    (quadratic): iterates 1e-8 apart, or the ends of two attempts at the same minimum (a redundant arm), differ in
    error by round-off only, so which one is best may differ by round-off. There the errors must agree to round-off,
    the configurations need not. A successful target's end points agree to 1e-9 and its joints to 1e-6 rad: the two
    back ends order the same floating-point operations differently, and a degenerate arm amplifies the difference
    sweep after sweep. Two coaxial joints share one rotation, any split of it between them is as good, and CCD's
    split follows the round-off (1.1e-8 rad after 60 sweeps; three coaxial joints and a link 2**-23 long gave 1.15e-9
    rad; hypothesis found both on 2026-12-04). The end point does not depend on the split. Nor, to speak of, on a
    joint whose axis passes within 1e-6 of it (its column of the position Jacobian below 1e-6 per rad: a 6R arm
    whose last two axes are parallel 1e-10 apart, the end point on them, left joint 5 to round-off, 2.8e-6 rad
    apart; hypothesis, 2026-12-06): such a joint's value is not compared.
    """
    assert np.array_equal(a.success, b.success)
    ok = a.success
    moves = np.linalg.norm(armkit.jacobian(arm, a.q[ok])[..., :3, :], axis=-2) > 1e-6   # (k, n)
    gap = np.abs(a.q[ok] - b.q[ok])
    assert (gap[moves] <= 1e-6).all(), gap[moves].max()
    ends = [armkit.fk(arm, r.q[ok])[..., :3, 3] for r in (a, b)]
    assert np.allclose(ends[0], ends[1], atol=1e-9, rtol=0)
    assert np.allclose(a.position_error, b.position_error, atol=1e-12, rtol=0)
    assert np.array_equal(a.iterations, b.iterations)
    assert list(a.reason) == list(b.reason)
    # the sweeps and starts (the residual after them is FK's, which differs in the last digits between back ends)
    assert [m.split(";")[0].split(":")[0] for m in a.message] == [m.split(";")[0].split(":")[0] for m in b.message]
    if a.trace is not None or b.trace is not None:
        assert a.trace.shape == b.trace.shape
        assert np.allclose(a.trace, b.trace, atol=1e-9, rtol=0, equal_nan=True)


@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(arm=arms(), data=st.data())
def test_compiled_equals_numpy(arm, data):
    seed = data.draw(st.integers(0, 2**31 - 1))
    rng = np.random.default_rng(seed)
    B = data.draw(st.integers(1, 5))
    p = armkit.fk(arm, arm.random_q(B, rng=rng))[:, :3, 3]
    p += rng.normal(scale=data.draw(st.sampled_from([0.0, 0.05, 1.0])), size=p.shape)  # some unreachable
    q0 = arm.random_q(B, rng=rng)
    kw = dict(seed=seed, trace=True, restarts=data.draw(st.integers(0, 3)),
              max_iterations=data.draw(st.integers(1, 60)), enforce_limits=data.draw(st.booleans()))
    _same(_solve("numba", arm, p, q0, **kw), _solve("numpy", arm, p, q0, **kw), arm)


@pytest.mark.parametrize("name", ["planar3", "ur5", "stanford"])
def test_compiled_equals_numpy_on_bundled_arms(name):
    arm = armkit.load(name)
    rng = np.random.default_rng(5)
    p = armkit.fk(arm, arm.random_q(6, rng=rng))[:, :3, 3]
    p[0] *= 3.0                                    # out of reach: no restarts, the closest configuration
    q0 = np.zeros((6, arm.n))
    kw = dict(seed=3, trace=True, max_iterations=60, restarts=4)   # few sweeps: restarts happen
    a, b = _solve("numba", arm, p, q0, **kw), _solve("numpy", arm, p, q0, **kw)
    _same(a, b, arm)
    assert a.reason[0] == "unreachable"


@pytest.mark.parametrize("backend", ["numba", "numpy"])
@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**31 - 1), i=st.integers(0, 5), others=st.integers(0, 2**31 - 1))
def test_target_does_not_depend_on_its_batch(backend, seed, i, others):
    # few sweeps per attempt and targets near full stretch: restarts are drawn for some targets
    arm = armkit.load("planar3")
    rng = np.random.default_rng(others)
    a = np.random.default_rng(seed).uniform(-np.pi, np.pi, 6)
    r = np.random.default_rng(seed).uniform(1.2, 2.095, 6)
    p = np.stack([r * np.cos(a), r * np.sin(a), np.zeros(6)], axis=-1)
    q0 = np.zeros((6, 3))
    kw = dict(seed=seed, trace=True, max_iterations=40, restarts=5)
    res = _solve(backend, arm, p, q0, **kw)
    other = p.copy()
    mask = np.arange(6) != i
    other[mask] = rng.uniform(-2.5, 2.5, (5, 3)) * [1.0, 1.0, 0.0]   # other targets, some unreachable
    one = _solve(backend, arm, other, q0, **kw)
    assert np.array_equal(one.q[i], res.q[i])
    assert one.success[i] == res.success[i] and one.iterations[i] == res.iterations[i]
    assert one.message[i] == res.message[i]
    t1, t0 = one.trace[i][:one.iterations[i]], res.trace[i][:res.iterations[i]]
    assert np.array_equal(t1, t0)


@pytest.mark.parametrize("backend", ["numba", "numpy"])
def test_batched_equals_looped_without_restarts(backend):
    arm = armkit.load("ur5")
    p = armkit.fk(arm, arm.random_q(5, rng=11))[:, :3, 3]
    res = _solve(backend, arm, p, np.zeros((5, 6)), restarts=0, seed=0, trace=True)
    for i in range(5):
        one = _solve(backend, arm, p[i:i + 1], np.zeros((1, 6)), restarts=0, seed=0, trace=True)
        assert np.array_equal(one.q[0], res.q[i]) and one.iterations[0] == res.iterations[i]
        assert np.array_equal(one.trace[0][:one.iterations[0]], res.trace[i][:res.iterations[i]])


def test_long_trace_is_complete():
    # more sweeps than the kernel's first trace buffer holds (256 a target): solved again with room for all
    arm = armkit.load("planar3")
    p = np.array([[2.086, 0.0, 0.0], [1.0, 0.5, 0.0]])   # 14 mm inside the reach: over a thousand sweeps
    a = _solve("numba", arm, p, np.zeros((2, 3)), trace=True)
    b = _solve("numpy", arm, p, np.zeros((2, 3)), trace=True)
    assert a.iterations[0] > 256
    assert a.trace.shape == (2, a.iterations.max())
    assert np.all(a.trace[1, a.iterations[1]:] == a.trace[1, a.iterations[1] - 1])   # padded with its last error
    _same(a, b, arm)


def _splitmix64_reference(state: int) -> tuple[int, int]:
    """splitmix64 from its definition (Steele, Lea and Flood 2014; Vigna's splitmix64.c), in Python integers."""
    m = 2**64
    state = (state + 0x9E3779B97F4A7C15) % m
    z = state
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) % m
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) % m
    return state, z ^ (z >> 31)


def test_splitmix64_reference_values():
    # the first outputs from state 0, as published with the reference implementation
    published = [0xE220A8397B1DCDAF, 0x6E789E6AA1B965F4, 0x06C45D188009454F]
    s = np.zeros(1, np.uint64)
    for want in published:
        s, u = ccd._splitmix64(s)
        assert u[0] == (want >> 11) / 2.0**53


@given(st.lists(st.integers(0, 2**64 - 1), min_size=1, max_size=8))
def test_splitmix64_matches_its_definition(states):
    s = np.array(states, dtype=np.uint64)
    for _ in range(3):
        s, u = ccd._splitmix64(s)
        ref = [_splitmix64_reference(x) for x in states]
        states = [r[0] for r in ref]
        assert s.tolist() == states
        assert u.tolist() == [(r[1] >> 11) / 2.0**53 for r in ref]
        assert np.all((u >= 0.0) & (u < 1.0))


def test_compiled_draws_equal_numpy_draws():
    from armkit.ik import _ccd_jit

    seeds = np.array([0, 1, 2**63 + 5, 2**64 - 1], dtype=np.uint64)
    for attempt in (1, 2, 7):
        state = ccd._start_state(seeds, np.full(4, attempt, np.uint64))
        for i, sd in enumerate(seeds):
            ref = (int(sd) * 1000003 + attempt) % 2**64          # the start state, by its definition
            assert int(state[i]) == ref
            k = _ccd_jit._state(sd, np.uint64(attempt))
            assert int(k) == ref
        s2, u2 = ccd._splitmix64(state)
        for i in range(4):
            ks, ku = _ccd_jit._next(np.uint64(state[i]))
            assert int(ks) == int(s2[i]) and ku == u2[i]
