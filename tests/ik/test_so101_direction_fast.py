"""``armkit.ik(so101, xyz, direction=...)`` by the compiled kernels (issue 20): the same answers as the NumPy path.

:func:`armkit.ik.partial.nearest_direction` runs ``_yaw_pitch3_jit.direction_branches`` and polishes the
candidates the kernel left, so it returns the successful configuration nearest ``q0`` as
:func:`armkit.ik.analytic.yaw_pitch3.solve_direction` does; rows it cannot settle go to the NumPy path.
Every answer is checked here by FK on its own. Timing lives in benchmarks, not here.
"""

from __future__ import annotations

import numpy as np

import armkit
from armkit.ik import partial
from armkit.ik.analytic.yaw_pitch3 import _solver_of
from armkit.ik.result import default_tolerance
from test_so101_single_call import arm  # noqa: F401  (the SO-101 with its kernels, a module fixture)




def targets(arm, n, seed):
    rng = np.random.default_rng(seed)
    q = rng.uniform(arm.lower, arm.upper, size=(n, arm.n))
    T = armkit.fk(arm, q)
    return T[:, :3, 3].copy(), T[:, :3, 2].copy(), rng.uniform(arm.lower, arm.upper, size=(n, arm.n))


def numpy_path(arm, p, d, q0):
    numeric = {"tol": default_tolerance(arm), "enforce_limits": True, "trace": False, "mask": None, "seed": None,
               "max_iterations": None, "restarts": None}
    return partial._direction_flat(arm, p, d, q0, "auto", _solver_of(arm), numeric)


def fk_check(arm, q, p, d):
    T = armkit.fk(arm, q)
    dp = np.linalg.norm(T[..., :3, 3] - p, axis=-1)
    cos = np.clip(np.einsum("...i,...i->...", T[..., :3, 2], d), -1.0, 1.0)
    return dp, np.arccos(cos)


def test_compiled_equals_numpy_on_many_targets(arm):
    p, d, q0 = targets(arm, 300, 7)
    tol = default_tolerance(arm)
    fast, solved = partial.nearest_direction(arm, p, d, q0, tol, True)
    slow = numpy_path(arm, p, d, q0)
    assert fast is not None and solved.mean() > 0.95      # the kernels answer nearly every row themselves
    assert np.all(slow.success)
    assert np.all(fast.success[solved])
    assert np.max(np.abs(fast.q[solved] - slow.q[solved])) < 1e-9      # the same configuration: nearest q0
    dp, ang = fk_check(arm, fast.q[solved], p[solved], d[solved])
    assert dp.max() <= tol[0] and ang.max() <= 1e-7
    assert np.all((fast.q[solved] >= arm.lower - 1e-12) & (fast.q[solved] <= arm.upper + 1e-12))


def test_ik_answers_like_the_numpy_path_single_and_batched(arm, monkeypatch):
    p, d, q0 = targets(arm, 60, 11)
    res = armkit.ik(arm, p, q0=q0, direction=d)
    single = [armkit.ik(arm, p[i], q0=q0[i], direction=d[i]) for i in range(10)]
    monkeypatch.setattr(partial, "nearest_direction", lambda *a: (None, np.zeros(len(a[1]), dtype=bool)))
    ref = armkit.ik(arm, p, q0=q0, direction=d)                  # the NumPy path only
    assert np.all(res.success) and np.all(ref.success)
    assert np.max(np.abs(res.q - ref.q)) < 1e-9
    for i, s in enumerate(single):
        assert bool(s.success) and np.max(np.abs(s.q - ref.q[i])) < 1e-9
    dp, ang = fk_check(arm, res.q, p, d)
    assert dp.max() <= default_tolerance(arm)[0] and ang.max() <= 1e-7


def test_a_single_call_never_reaches_the_numpy_path(arm, monkeypatch):
    p, d, q0 = targets(arm, 200, 3)
    fast, solved = partial.nearest_direction(arm, p, d, q0, default_tolerance(arm), True)
    i = int(np.flatnonzero(solved)[0])

    def refuse(*args, **kwargs):
        raise AssertionError("the NumPy path ran")

    monkeypatch.setattr(partial, "_direction_flat", refuse)
    res = armkit.ik(arm, p[i], q0=q0[i], direction=d[i])
    assert bool(res.success) and np.max(np.abs(res.q - fast.q[i])) < 1e-12


def test_unreachable_is_reported_as_unreachable(arm):
    rng = np.random.default_rng(5)
    u = rng.normal(size=(20, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    p = 2.0 * arm.reach * u                                       # twice the reach: nowhere near
    d = rng.normal(size=(20, 3))
    res = armkit.ik(arm, p, direction=d)
    assert not np.any(res.success)
    assert set(np.asarray(res.reason).tolist()) == {"unreachable"}
    res1 = armkit.ik(arm, p[0], direction=d[0])
    assert not bool(res1.success) and str(res1.reason) == "unreachable" and str(res1.message)


def test_mixed_batch_keeps_each_rows_answer(arm):
    p, d, q0 = targets(arm, 6, 13)
    p[2] = [5.0, 5.0, 5.0]                                        # one row unreachable: the NumPy path answers it
    res = armkit.ik(arm, p, q0=q0, direction=d)
    assert res.success.tolist() == [True, True, False, True, True, True]
    assert str(res.reason[2]) == "unreachable" and "unreachable" in str(res.message[2])
    dp, ang = fk_check(arm, res.q[res.success], p[res.success], d[res.success])
    assert dp.max() <= default_tolerance(arm)[0] and ang.max() <= 1e-7
