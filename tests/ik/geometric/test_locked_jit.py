"""The compiled layout of held and swept joints (:mod:`armkit.ik.geometric.locked_jit`) against the NumPy layout.

:meth:`armkit.ik.geometric.locked.Locked.solve` lays out the solvers' solutions as branches of the full arm
in one compiled call when the Numba back end serves; the NumPy code it replaces stays (the NumPy back end)
and is the reference here: the same branches to the bit, the same flags and messages. Independently of
both, every successful branch is checked by FK of the true 7-joint model and holds the swept or held
joint at its value.
"""

from __future__ import annotations

import numpy as np
import pytest

import armkit
from armkit.ik.geometric import locked

pytest.importorskip("numba")


def _targets(robot, count, rng_key):
    rng = np.random.default_rng(rng_key)
    return armkit.fk(robot, rng.uniform(0.9 * robot.lower, 0.9 * robot.upper, (count, robot.n)))


def _raw(solver, T, q0phi, compiled, monkeypatch):
    if not compiled:
        monkeypatch.setattr(locked, "_layout_kernels", lambda: None)
    try:
        return solver.solve(T, q0phi)
    finally:
        monkeypatch.undo()


@pytest.fixture(scope="module", params=[("panda", "panda_joint6"), ("iiwa14", "A3")])
def arm(request):
    from armkit._jit_loader import kernels

    if kernels("ik.geometric.locked_jit") is None:
        pytest.skip("the Numba back end does not serve (kernels compiling or NumPy chosen)")
    return armkit.load(request.param[0]), request.param[1]


@pytest.mark.parametrize("mode", ["sweep", "held", "held below zero"])
def test_compiled_layout_is_the_numpy_layout(arm, mode, monkeypatch):
    robot, joint = arm
    k = robot.joint_names.index(joint)
    if mode == "sweep":
        solver = locked.sweep_solver(robot)
    elif mode == "held":
        solver = locked.held_solver(robot, {k: 0.3})
    else:
        solver = locked.held_solver(robot, {k: -0.4})
    T = _targets(robot, 6, 3)
    T[-1, :3, 3] *= 10.0    # one target out of reach: least-squares candidates, every branch unreachable
    rng = np.random.default_rng(5)
    q0phi = rng.uniform(robot.lower, robot.upper, (len(T), robot.n)) + solver.sf.theta
    a = _raw(solver, T.copy(), q0phi, True, monkeypatch)
    b = _raw(solver, T.copy(), q0phi, False, monkeypatch)
    assert a.q.shape == b.q.shape == (len(T), solver.m, robot.n)
    np.testing.assert_array_equal(a.q, b.q)
    np.testing.assert_array_equal(a.unreachable, b.unreachable)
    np.testing.assert_array_equal(a.missing, b.missing)
    np.testing.assert_array_equal(a.label, b.label)
    np.testing.assert_array_equal(a.note, b.note)
    assert [a.why(i) for i in range(0, a.q.shape[0] * solver.m, 7)] == \
        [b.why(i) for i in range(0, b.q.shape[0] * solver.m, 7)]
    assert a.unreachable[-1].all()


def test_sweep_branches_hold_their_value_and_reach_the_target(arm):
    robot, joint = arm
    solver = locked.sweep_solver(robot)
    k = solver.swept[0]
    values = locked.sweep_values(robot, k)                 # the documented grid, independently
    for T in _targets(robot, 5, 11):
        res = armkit.ik_all(robot, T)
        assert res.success.any()
        labels = np.asarray(res.branch)
        for q, ok, lab in zip(res.q, res.success, labels):
            name, rest = lab.split("=")
            assert name == robot.joint_names[k]
            v = float(rest.split("/")[0])
            assert abs(v - values[np.argmin(np.abs(values - v))]) < 1e-4
            assert abs(q[k] - v) < 1e-4 or not ok and abs(((q[k] - v + np.pi) % (2 * np.pi)) - np.pi) < 1e-4
            if ok:
                F = armkit.fk(robot, q)
                assert np.abs(F[:3, 3] - T[:3, 3]).max() <= 1e-9 * max(robot.reach, 1.0)
                assert np.abs(F[:3, :3] - T[:3, :3]).max() <= 1e-9
