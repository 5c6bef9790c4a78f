"""Nothing missed: the searches and the held-joint closed form against a dense least-squares search.

The reference is independent of the subproblem solvers: armkit's Levenberg-Marquardt (``method="lm"``)
from many random starts on the same chain, rebuilt as a URDF-style robot from its
product-of-exponentials form. Every distinct solution LM converges to must be among the solver's
(same configuration to 1e-6 rad, up to whole turns); and the solver's solutions must pass FK.
The dense search has its own resolution (the starts): it can miss solutions, the solver may not.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import armkit
from armkit.ik.geometric import solvers as G
from armkit.ik.geometric.locked import lock
from armkit.ik.geometric.poe import POE, poe
from armkit.model.robot import Joint, Robot

from test_solvers import random_arm, random_q   # random arms of each class (same folder, on pytest's path)

STARTS = 300


def _wrapped(a: np.ndarray) -> np.ndarray:
    return (a + np.pi) % (2 * np.pi) - np.pi


def robot_of(form: POE) -> Robot:
    """The chain as a Robot without limits: every link frame parallel to the world at q = 0, joint k's
    origin at the point of axis k, its axis H[k] (the POE form read back, independent of the solvers)."""
    pts = np.cumsum(form.P, axis=0)
    joints = []
    for k in range(form.n):
        origin = np.eye(4)
        origin[:3, 3] = pts[k] - (pts[k - 1] if k else 0.0)
        joints.append(Joint(origin=origin, axis=tuple(form.H[k]), lower=-math.inf, upper=math.inf, name=f"j{k + 1}"))
    tool = np.eye(4)
    tool[:3, :3] = form.R_nT
    tool[:3, 3] = form.P[-1]
    return Robot(joints, convention="urdf", name="chain", tool=tool)


def dense_solutions(robot: Robot, T: np.ndarray, seed: int) -> list[np.ndarray]:
    """Distinct solutions (to 1e-6 rad) LM converges to from STARTS random starts."""
    starts = np.random.default_rng(seed).uniform(-math.pi, math.pi, (STARTS, robot.n))
    res = armkit.ik(robot, np.broadcast_to(T, (STARTS, 4, 4)), q0=starts, method="lm", restarts=0,
                    enforce_limits=False)
    out: list[np.ndarray] = []
    for x in _wrapped(np.asarray(res.q)[np.asarray(res.success)]):
        if not any(np.abs(_wrapped(x - u)).max() < 1e-6 for u in out):
            out.append(x)
    return out


def ik_all_misses(form: POE, R: np.ndarray, p: np.ndarray, seed: int) -> list[np.ndarray]:
    """What :func:`dense_solutions` reaches on the chain ``form`` for the target ``(R, p)`` and ``armkit.ik_all``
    (limits off) does not list; asserts the reference found at least two solutions."""
    robot = robot_of(form)
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, p
    res = armkit.ik_all(robot, T, enforce_limits=False)
    reference = dense_solutions(robot, T, seed)
    assert len(reference) >= 2
    return _missing(np.asarray(res.q)[np.asarray(res.success)], reference)


def _missing(found: np.ndarray, reference: list[np.ndarray]) -> list[np.ndarray]:
    return [u for u in reference if not any(np.abs(_wrapped(u - s)).max() < 1e-6 for s in found)]


@pytest.mark.parametrize("seed", [0, 3, 5])
def test_one_dimensional_search_misses_nothing_lm_finds(seed):
    """The 1-D search of the class '6R-two-intersecting' (only axes 5, 6 meet) on random arms."""
    g = np.random.default_rng(seed)
    form = random_arm(g, "ti")
    q = random_q(g, form)
    R, p = form.fk(q)
    sol = G.two_intersecting(form, R, p)
    robot = robot_of(form)
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, p
    assert np.allclose(armkit.fk(robot, q), T, atol=1e-12)         # the rebuilt robot is the same chain
    back = armkit.fk(robot, sol.q)
    assert np.abs(back - T).max() < 1e-9
    reference = dense_solutions(robot, T, seed + 1000)
    assert len(reference) >= 2
    assert _missing(sol.q, reference) == []


@pytest.mark.parametrize("name, joint", [("iiwa14", "A3"), ("panda", "panda_joint6")])
def test_held_joint_misses_nothing_lm_finds(name, joint):
    """``fixed=`` against LM on the 6-joint chain left (held value inside the limits, limits off)."""
    robot = armkit.load(name)
    k = robot.joint_names.index(joint)
    q = np.random.default_rng(k).uniform(0.8 * robot.lower, 0.8 * robot.upper)
    T = armkit.fk(robot, q)
    res = armkit.ik_all(robot, T, fixed={joint: q[k]}, enforce_limits=False)
    found = np.asarray(res.q)[np.asarray(res.success)]
    reduced = robot_of(lock(poe(robot), k, q[k]))
    reference = dense_solutions(reduced, T, 7)
    assert len(reference) >= 2
    assert _missing(np.delete(found, k, axis=1), reference) == []


def two_parallel_arm(g: np.random.Generator) -> POE:
    """A random 6R chain whose only relation is axes 2 ∥ 3 (the other axes and the points random)."""
    H = g.normal(size=(6, 3))
    H /= np.linalg.norm(H, axis=1, keepdims=True)
    H[2] = (1.0 if g.random() < 0.5 else -1.0) * H[1]
    pts = g.normal(size=(6, 3)) * 0.5
    tool = pts[5] + g.normal(size=3) * 0.3
    Q, Rr = np.linalg.qr(g.normal(size=(3, 3)))
    Q = Q * np.sign(np.diag(Rr))
    Q = Q if np.linalg.det(Q) > 0 else -Q
    return POE(H, np.vstack([pts[0], np.diff(pts, axis=0), tool - pts[5]]), Q, np.zeros(6, dtype=bool))


@pytest.mark.parametrize("seed", [0, 5])
def test_two_parallel_search_misses_nothing_lm_finds(seed):
    """The 1-D search of the class '6R-two-parallel' (only axes 2 ∥ 3), seed 0 with a root at a branch end."""
    from armkit.ik.geometric.classify import classify
    from armkit.ik.geometric.search import two_parallel

    g = np.random.default_rng(seed)
    form = two_parallel_arm(g)
    assert classify(form).name == "6R-two-parallel"
    q = g.uniform(-math.pi, math.pi, 6)
    R, p = form.fk(q)
    sol = two_parallel(form, R, p)
    robot = robot_of(form)
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, p
    assert np.abs(armkit.fk(robot, sol.q) - T).max() < 1e-9
    assert np.abs(_wrapped(sol.q - q)).max(axis=1).min() < 1e-7          # the generating q is found
    reference = dense_solutions(robot, T, seed + 500)
    assert len(reference) >= 2
    assert _missing(sol.q, reference) == []


@pytest.mark.parametrize("reverse", [False, True])
def test_two_parallel_arm_in_ik_all(reverse):
    """An arm of the class gets every branch from ``ik_all`` (the geometric family); read from tool to base
    (axes 4 ∥ 5, solved on the reversed chain) too."""
    from armkit.ik.analytic import closed_form
    from armkit.ik.geometric.classify import classify
    from armkit.ik.geometric.solvers import reverse as reversed_chain

    form = two_parallel_arm(np.random.default_rng(8))
    if reverse:
        form = reversed_chain(form)
    robot = robot_of(form)
    cls = classify(robot)
    assert cls.name == "6R-two-parallel" and cls.inverted == reverse
    assert closed_form(robot).family == "geometric"
    q = np.random.default_rng(9).uniform(-math.pi, math.pi, 6)
    T = armkit.fk(robot, q)
    res = armkit.ik_all(robot, T)
    assert res.q.shape == (16, 6)
    ok = np.asarray(res.success)
    assert np.abs(armkit.fk(robot, res.q[ok]) - T).max() < 1e-9
    assert np.abs(_wrapped(res.q[ok] - q)).max(axis=1).min() < 1e-7
    assert ok.sum() % 2 == 0            # real solutions of a generic 6R come in pairs
