"""The task Jacobian the LM/Newton solvers use, against finite differences of the solvers' own error.

The solvers model the error as e(q + dq) ~ e(q) - J dq (armkit.ik.numeric, "The task error").
The linear rows are exact. The angular rows are R_t^T J_omega, exact only at zero rotation
error; the exact rows are Jr^-1(e_r) R_t^T J_omega (Jr^-1 the inverse right Jacobian of SO(3)),
so they differ from the rows used by at most |Jr^-1(e_r) - I| = sqrt(t^2/4 + c(t)^2 t^4) relative
to them, t = |e_r|. Both statements of the module docstring are checked here, for the NumPy
engine and for the Numba kernel (each against finite differences of its own residual).
"""

from __future__ import annotations

import importlib
import math

import numpy as np
import pytest

import armkit
from armkit import kinematics

numeric = importlib.import_module("armkit.ik.numeric")
H = 1e-6          # central differences: truncation ~H^2, rounding ~1e-16 / H


def _hat(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def _exp3(v: np.ndarray) -> np.ndarray:
    t = float(np.linalg.norm(v))
    K = _hat(v / t)
    return np.eye(3) + math.sin(t) * K + (1.0 - math.cos(t)) * K @ K


def _c(t: float) -> float:
    return 1.0 / t**2 - (1.0 + math.cos(t)) / (2.0 * t * math.sin(t))


def _jr_inv(e: np.ndarray) -> np.ndarray:
    """Inverse right Jacobian of SO(3): d log(R exp(d))/dd = Jr^-1(log R)."""
    K = _hat(e)
    return np.eye(3) + 0.5 * K + _c(float(np.linalg.norm(e))) * K @ K


def _bound(t: float) -> float:
    """|Jr^-1(e) - I|_2 for |e| = t (the matrix is normal: eigenvalues 0 and -c t^2 +- i t/2)."""
    return math.sqrt(t * t / 4.0 + _c(t) ** 2 * t**4)


def _target(robot, q, angle, rng):
    """A pose whose rotation is `angle` rad from fk(q) (about a random axis), position 1 % of the reach away."""
    T = armkit.fk(robot, q).copy()
    axis = rng.normal(size=3)
    T[:3, :3] = T[:3, :3] @ _exp3(angle * axis / np.linalg.norm(axis))
    T[:3, 3] += 0.01 * robot.reach * rng.normal(size=3) / math.sqrt(3.0)
    return T


def _fd(error, q, s, prismatic):
    """-de/dq by central differences, columns of prismatic joints per metre (the solvers' units)."""
    cols = []
    for k in range(len(q)):
        d = np.zeros(len(q))
        d[k] = H
        col = -(error(q + d) - error(q - d)) / (2.0 * H)
        cols.append(col / s if prismatic[k] else col)
    return np.stack(cols, axis=-1)


def _numpy_engine(robot, Tt):
    prob = numeric.Problem(robot, Tt[None], np.zeros((1, robot.n)), None, None, True)
    idx = np.array([0])

    def evaluate(q):
        e, _, J = numeric._evaluate(prob, q[None], idx)
        return e[0], J[0]
    return evaluate, prob.s


def _numba_engine(robot, Tt):
    jit_lm = pytest.importorskip("armkit.ik._jit_lm")
    P = kinematics.packed(robot)[1]   # the packed chain the solver's kernel reads
    s = robot.unit_scale
    w = np.ones(6)

    def evaluate(q):
        J = np.empty((6, robot.n))
        e = np.empty(6)
        X = jit_lm._pose_jacobian(P, q, s, J)
        jit_lm._rotate_rows(J, Tt, robot.n)
        jit_lm._residual(X, Tt, s, w, e)
        return e, J
    return evaluate, s


ENGINES = {"numpy": _numpy_engine, "numba": _numba_engine}
ROBOTS = ["ur5", "panda", "stanford", "fighter", "so101"]


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("name", ROBOTS)
@pytest.mark.parametrize("angle", [1e-4, 0.01, 0.1, 1.0, 2.5])
def test_task_jacobian_against_finite_differences_of_the_solvers_own_error(engine, name, angle):
    robot = armkit.load(name)
    rng = np.random.default_rng([ROBOTS.index(name), int(angle * 1e4)])
    for _ in range(3):
        q = robot.random_q(rng=rng)
        Tt = _target(robot, q, angle, rng)
        evaluate, s = ENGINES[engine](robot, Tt)
        e, J = evaluate(q)
        F = _fd(lambda x: evaluate(x)[0], q, s, robot.prismatic)
        scale = max(1.0, float(np.abs(F).max()))
        t = float(np.linalg.norm(e[3:]))
        assert t == pytest.approx(angle, rel=1e-9)
        # linear rows: exact
        np.testing.assert_allclose(J[:3], F[:3], rtol=0, atol=1e-7 * scale)
        # angular rows: Jr^-1(e_r) times the rows used is the exact derivative ...
        np.testing.assert_allclose(_jr_inv(e[3:]) @ J[3:], F[3:], rtol=0, atol=1e-7 * scale)
        # ... so the exact rows differ from the rows used by at most |Jr^-1 - I| relative to them
        off = np.linalg.norm(F[3:] - J[3:], 2) / np.linalg.norm(J[3:], 2)
        assert off <= _bound(t) + 1e-6
        assert off >= 0.1 * _bound(t) - 1e-6   # and the difference is real (not an exact Jacobian by accident)
        if angle <= 1e-4:   # near convergence the rows used are the derivative
            np.testing.assert_allclose(J[3:], F[3:], rtol=0, atol=1e-4 * scale)


def test_the_stated_numbers():
    """The figures quoted in armkit.ik.numeric's docstring."""
    assert _bound(1.0) == pytest.approx(0.507, abs=5e-4)
    assert _bound(0.1) == pytest.approx(0.0500, abs=5e-5)
    assert _bound(0.01) == pytest.approx(0.00500, abs=5e-6)
    assert "0.51 at 1 rad" in numeric.__doc__


def test_numba_and_numpy_task_jacobians_agree():
    pytest.importorskip("armkit.ik._jit_lm")
    robot = armkit.load("stanford")
    rng = np.random.default_rng(5)
    q = robot.random_q(rng=rng)
    Tt = _target(robot, q, 0.7, rng)
    e1, J1 = _numpy_engine(robot, Tt)[0](q)
    e2, J2 = _numba_engine(robot, Tt)[0](q)
    np.testing.assert_allclose(e1, e2, rtol=0, atol=1e-12)
    np.testing.assert_allclose(J1, J2, rtol=0, atol=1e-12)
