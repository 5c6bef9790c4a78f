"""The one-call kernel's shortcut where some candidates are least-squares ones (issue 19, item 5).

Random arms of the closed-form classes with a meeting or a parallel pair have 4-6 branches of 8 on most targets: the
others are least-squares candidates (a position or a wrist out of reach). On a chain whose ideal form is the true
one, the kernel takes the shortcut past the check with the others where the check fails each least-squares
candidate (:func:`armkit.ik.geometric.solvers_check._apart`; where one passes, the check keeps it and the kernel
goes the long way: ``tests/ik/geometric/test_apart.py``). Either way the answer is the batched path's, to the bit,
and every branch is FK-checked.
"""

from __future__ import annotations

import numpy as np
import pytest
from test_single_call import _assert_same, _both, compiled  # noqa: F401 (the fixture: the Numba back end)

import armkit
from armkit.ik.analytic import closed_form
from armkit.model import Joint, Robot


def _unit(v):
    return v / np.linalg.norm(v)


def _pair_arm(rng: np.random.Generator, kind: str) -> Robot:
    """A random 6R arm with a spherical wrist (4, 5, 6 meet) and axes 1, 2 meeting (``"meet"``) or axes 2, 3
    parallel (``"parallel"``), or three parallel axes (2, 3, 4) with 5, 6 meeting (``"three"``): URDF joints."""
    H = np.array([_unit(rng.normal(size=3)) for _ in range(6)])
    pts = rng.normal(size=(6, 3)) * 0.3
    if kind == "meet":
        pts[1] = pts[0]
        pts[4] = pts[5] = pts[3]
    elif kind == "parallel":
        H[2] = H[1]
        pts[4] = pts[5] = pts[3]
    else:
        H[2] = H[3] = H[1]
        pts[5] = pts[4]
    joints, prev = [], np.eye(4)
    for k in range(6):
        A = np.eye(4)
        z = H[k]
        x = _unit(np.cross(z, [0.3, 0.5, 0.8]))
        A[:3, :3] = np.column_stack([x, np.cross(z, x), z])
        A[:3, 3] = pts[k]
        origin = np.linalg.inv(prev) @ A
        joints.append(Joint(name=f"j{k + 1}", kind="revolute", lower=-np.inf, upper=np.inf,
                            origin=tuple(map(tuple, origin)), axis=(0.0, 0.0, 1.0)))
        prev = A
    tool = np.eye(4)
    tool[:3, 3] = rng.normal(size=3) * 0.1
    return Robot(joints, convention="urdf", name=f"random pair arm ({kind})", tool=tool)


@pytest.mark.usefixtures("compiled")
@pytest.mark.parametrize("kind", ["meet", "parallel", "three"])
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_random_pair_arms_equal_the_batched_path(kind, seed):
    rng = np.random.default_rng(seed)
    robot = _pair_arm(rng, kind)
    cf = closed_form(robot)
    if cf is None or cf.family != "geometric":
        pytest.skip("a degenerate draw")
    T = armkit.fk(robot, rng.uniform(-np.pi, np.pi, (40, 6)))
    fewer = 0
    for t in T:
        fast, slow = _both(lambda: armkit.ik_all(robot, t))
        _assert_same(fast, slow)
        fewer += int(fast.success.sum()) < fast.success.size
        ok = fast.success
        np.testing.assert_allclose(armkit.fk(robot, fast.q[ok]), np.broadcast_to(t, (int(ok.sum()), 4, 4)),
                                   atol=1e-9)
        _assert_same(*_both(lambda: armkit.ik(robot, t)))
    assert fewer > 0   # targets with least-squares candidates: the case this covers
