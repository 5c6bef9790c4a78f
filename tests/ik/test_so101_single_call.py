"""One SO-101 target with ``pitch=`` or ``direction=``: one compiled call, the same result as the batched path.

:func:`armkit.ik.partial._pitch_one` and :func:`armkit.ik.partial._direction_one` answer a single
float64 target with one kernel call and build the result themselves; everything else (lists, batches,
failures, bad input) goes the batched way. The law checked here: whatever the fast path answers equals,
field by field (value, dtype, shape, type, repr), what the batched path answers for the same call with
the fast path switched off; and a single call equals its row of a batch. Timing lives in
benchmarks/bench_so101.py, not here.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import armkit
from armkit.errors import ArmkitError
from armkit.ik import partial
from armkit.ik.analytic.yaw_pitch3 import fast_geometry, pitch_of

FIELDS = ("q", "success", "position_error", "rotation_error", "iterations", "branch", "within_limits", "reason",
          "message", "trace")


@pytest.fixture(scope="module")
def arm():
    arm = armkit.load("so101")
    if fast_geometry(arm) is None:
        armkit.set_backend("numba")    # the kernels only serve the Numba back end
    if fast_geometry(arm) is None:
        pytest.skip("Numba is not available")
    return arm


def batched(arm, monkeypatch, **kw):
    """``armkit.ik(arm, **kw)`` with the one-call paths switched off."""
    with monkeypatch.context() as m:
        m.setattr(partial, "_pitch_one", lambda *a: None)
        m.setattr(partial, "_direction_one", lambda *a: None)
        return armkit.ik(arm, **kw)


def assert_same(a, b):
    for f in FIELDS:
        x, y = getattr(a, f), getattr(b, f)
        assert type(x) is type(y), f
        if isinstance(x, np.ndarray):
            assert (x.dtype, x.shape) == (y.dtype, y.shape), f
            assert x.tobytes() == y.tobytes() if x.dtype != object else x.tolist() == y.tolist(), f
        else:
            assert x == y, f
    assert repr(a) == repr(b)


def spy(monkeypatch, name):
    """Count the answers of ``partial.<name>`` that are not None (the fast path taken)."""
    real, taken = getattr(partial, name), []

    def counted(*a):
        out = real(*a)
        taken.append(out is not None)
        return out

    monkeypatch.setattr(partial, name, counted)
    return taken


def poses(arm, n, seed):
    q = arm.random_q(n, rng=seed)
    T = armkit.fk(arm, q)
    return q, T[:, :3, 3].copy(), T[:, :3, 2].copy(), pitch_of(arm, q)


def test_pitch_one_call_equals_the_batched_path(arm, monkeypatch):
    q, p, d, psi = poses(arm, 40, 1)
    q0 = np.zeros_like(q)
    q0[:, 4] = q[:, 4]
    taken = spy(monkeypatch, "_pitch_one")
    for i in range(len(p)):
        for kw in (dict(target=p[i], q0=q0[i], pitch=psi[i]), dict(target=p[i], pitch=float(psi[i])),
                   dict(target=p[i], q0=q[i] + 0.2, pitch=psi[i], tol=1e-5)):
            res = armkit.ik(arm, **kw)
            assert_same(res, batched(arm, monkeypatch, **kw))
            if kw.get("q0") is not q0[i] and not bool(res.success):
                continue       # another roll than the target's: that pitch may be out of reach there
            assert bool(res.success)
            # the answer on its own: the position and the pitch met (FK), inside the limits
            assert np.linalg.norm(armkit.fk(arm, res.q)[:3, 3] - kw["target"]) <= 1e-9
            assert abs(math.remainder(float(pitch_of(arm, res.q)) - float(kw["pitch"]), 2 * math.pi)) <= 1e-9
            assert arm.within_limits(res.q)
    assert sum(taken) >= 0.9 * len(taken)      # the fast path answered (almost) every call


def test_direction_one_call_equals_the_batched_path(arm, monkeypatch):
    q, p, d, _ = poses(arm, 30, 2)
    taken = spy(monkeypatch, "_direction_one")
    for i in range(len(p)):
        for kw in (dict(target=p[i], direction=d[i]), dict(target=p[i], q0=q[i] + 0.1, direction=d[i], seed=2),
                   dict(target=p[i], direction=3.0 * d[i])):
            res = armkit.ik(arm, **kw)
            assert_same(res, batched(arm, monkeypatch, **kw))
            assert bool(res.success)
            X = armkit.fk(arm, res.q)
            assert np.linalg.norm(X[:3, 3] - kw["target"]) <= 1e-9
            assert math.acos(min(1.0, float(X[:3, 2] @ d[i]))) <= 1e-7
    assert sum(taken) >= 0.9 * len(taken)


def test_a_single_call_is_its_row_of_a_batch(arm):
    q, p, d, psi = poses(arm, 12, 3)
    rows = armkit.ik(arm, p, q0=q[::-1], pitch=psi)
    drows = armkit.ik(arm, p, q0=q[::-1], direction=d)
    for i in range(len(p)):
        for one, row in ((armkit.ik(arm, p[i], q0=q[::-1][i], pitch=psi[i]), rows[i]),
                         (armkit.ik(arm, p[i], q0=q[::-1][i], direction=d[i]), drows[i])):
            for f in FIELDS[:-1]:     # indexing a batch gives NumPy scalars where a single call gives 0-d arrays
                x, y = np.asarray(getattr(one, f)), np.asarray(getattr(row, f))
                assert x.shape == y.shape and x.tolist() == y.tolist(), f


def test_what_the_fast_path_leaves_gets_the_batched_answer(arm, monkeypatch):
    q, p, d, psi = poses(arm, 3, 4)
    far = 3.0 * arm.reach * p[0] / np.linalg.norm(p[0])
    strided = np.asfortranarray(np.stack([p[0], p[0]]))[0]      # a (3,) view with a stride: taken, copied
    assert not strided.flags.c_contiguous
    calls = [dict(target=far, pitch=0.3), dict(target=far, direction=d[0]),               # unreachable: messages
             dict(target=list(p[0]), pitch=psi[0]), dict(target=p[0], pitch=np.array(psi[0])),
             dict(target=p[:2], pitch=psi[:2]), dict(target=p[0], direction=list(d[0])),
             dict(target=p[0], q0=np.full(5, 1e7), pitch=psi[0]), dict(target=strided, pitch=psi[0]),
             dict(target=strided, direction=d[0]), dict(target=p[0], direction=d[0], enforce_limits=False),
             dict(target=p[0], pitch=psi[0], enforce_limits=False)]
    for kw in calls:
        assert_same(armkit.ik(arm, **kw), batched(arm, monkeypatch, **kw))
    res = armkit.ik(arm, far, pitch=0.3)
    assert not bool(res.success) and str(res.reason) == "unreachable" and res.message


@pytest.mark.parametrize("kw", [dict(pitch=math.nan), dict(pitch=math.inf), dict(direction=np.zeros(3)),
                                dict(direction=np.array([np.nan, 0.0, 1.0])), dict(q0=np.full(5, np.nan), pitch=0.1),
                                dict(q0=np.zeros(4), pitch=0.1), dict(pitch=0.1, target=np.array([np.nan, 0, 0.1]))])
def test_bad_input_gets_the_same_error(arm, monkeypatch, kw):
    kw = dict(kw)
    kw.setdefault("target", np.array([0.2, 0.0, 0.1]))
    with pytest.raises(ArmkitError) as fast:
        armkit.ik(arm, **kw)
    with pytest.raises(ArmkitError) as slow:
        batched(arm, monkeypatch, **kw)
    assert type(fast.value) is type(slow.value) and str(fast.value) == str(slow.value)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(u=st.lists(st.floats(0.0, 1.0), min_size=5, max_size=5), v=st.lists(st.floats(0.0, 1.0), min_size=5, max_size=5),
       roll=st.floats(-math.pi, math.pi))
def test_property_single_call_equals_batched(arm, monkeypatch, u, v, roll):
    """For any configuration inside the limits (its FK the target) and any start: the same result both ways."""
    q = arm.lower + np.array(u) * (arm.upper - arm.lower)
    q0 = arm.lower + np.array(v) * (arm.upper - arm.lower)
    T = armkit.fk(arm, q)
    p, d = T[:3, 3].copy(), T[:3, 2].copy()
    psi = float(pitch_of(arm, q))
    for kw in (dict(target=p, q0=q0, pitch=psi), dict(target=p, q0=q0, direction=d), dict(target=p, pitch=roll)):
        assert_same(armkit.ik(arm, **kw), batched(arm, monkeypatch, **kw))


def test_split_kernel_modules_keep_their_names():
    """The teleoperation kernels moved to ``_yaw_pitch3_teleop``; they are still read from ``_yaw_pitch3_jit``."""
    from armkit import _jit_loader

    old = _jit_loader.module("ik.analytic._yaw_pitch3_jit")
    new = _jit_loader.module("ik.analytic._yaw_pitch3_teleop")
    if old is None:
        pytest.skip("Numba is not available")
    for name in ("teleop", "teleop_call", "teleop_ctx", "pack_context", "INVALID", "C_TOL", "C_INDEX", "C_SIZE"):
        assert getattr(old, name) is getattr(new, name)
    with pytest.raises(AttributeError):
        old.no_such_kernel   # noqa: B018
    import armkit.lerobot as lr

    assert lr.RobotKinematics.__module__ == "armkit.lerobot"
    assert set(lr.__all__) <= set(dir(lr))
