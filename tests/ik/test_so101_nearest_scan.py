"""SO-101 position-only IK (``armkit.ik(so101, xyz)``, :func:`armkit.ik.analytic.yaw_pitch3.position_ik`) against a
dense scan of its family of solutions.

With the roll kept at the start's, a position's solutions form a 1-D family, the tool pitch free; the answer
is meant to be the member nearest the start ``q0`` (or Newton's answer from ``q0``, nearer still). The
reference here is made from the definition: at 720 pitches (every 0.5 deg) the four closed-form branches of
the pitch mode are taken, and each is kept only where an independent FK (``armkit.fk``) puts the tool on the
target to 1e-9 m, inside the joint limits, with the roll of ``q0``: every kept one is a member, so the
nearest of them bounds the nearest member from above. The answer should be no farther. The pitch search
samples the family (7 pitches near the start's, 8 around the circle) and refines the best sample's branch,
so it misses a nearer basin in some cases: measured when this test was written, 21.6 % of random starts,
14.8 % of the default start (zero, clipped), 0.4 % of 5 mm teleoperation steps (1,000 targets each). The
rates asserted below leave room for the sample size; a search that got worse would fail them, one that
finds the nearest member always would pass with 0 %.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import armkit
from armkit import _jit_loader
from armkit.ik.analytic.yaw_pitch3 import fast_geometry, position_ik
from armkit.ik.result import default_tolerance
from test_so101_single_call import arm  # noqa: F401  (the SO-101 with its kernels, a module fixture)

PITCHES = 720


def solve(arm, p, q0):
    res = position_ik(arm, p, q0)
    return res if res is not None else armkit.ik(arm, p, q0)


def nearest_scanned_member(arm, p, q0):
    """Per target, the squared joint distance from ``q0`` of the nearest member found by the scan (inf: none)."""
    kern = _jit_loader.kernels("ik.analytic._yaw_pitch3_jit")
    g = fast_geometry(arm)
    n = len(p)
    grid = -math.pi + 2 * math.pi * np.arange(PITCHES) / PITCHES
    P = np.ascontiguousarray(np.repeat(p, PITCHES, axis=0))
    Q0 = np.ascontiguousarray(np.repeat(q0, PITCHES, axis=0))
    B = len(P)
    Q = np.empty((B, 4, 5))
    OK = np.empty((B, 4), dtype=bool)
    scratch = [np.empty((B, 4)), np.empty((B, 4)), np.empty((B, 4), dtype=bool), np.empty((B, 4), dtype=np.int64)]
    tol = default_tolerance(arm)
    kern.nearest_pitch(g, P, np.tile(grid, n), Q0, tol[0], tol[1], True, Q, scratch[0], scratch[1], OK, scratch[2],
                       scratch[3], np.empty(B, dtype=np.int64))
    q = Q.reshape(-1, 5)
    start = np.repeat(Q0, 4, axis=0)
    q = np.where(OK.reshape(-1, 1), q, start)                  # (the rows not claimed: any finite joints)
    on_target = np.linalg.norm(np.asarray(armkit.fk(arm, q))[:, :3, 3] - np.repeat(P, 4, axis=0), axis=1) <= 1e-9
    inside = np.all((q >= arm.lower - 1e-12) & (q <= arm.upper + 1e-12), axis=1)
    member = on_target & inside & (np.abs(q[:, 4] - start[:, 4]) <= 1e-12)   # the roll of q0 (to rounding)
    d = np.where(member, np.sum((q - start) ** 2, axis=1), np.inf)
    return d.reshape(n, PITCHES * 4).min(axis=1)


@pytest.mark.parametrize("start, most", [("random", 0.30), ("default", 0.22), ("5 mm step", 0.02)])
def test_no_farther_than_the_nearest_scanned_member(arm, start, most):  # noqa: F811
    n = 150
    q = arm.random_q(n, rng=41)
    p = np.asarray(armkit.fk(arm, q))[:, :3, 3].copy()
    if start == "random":
        q0 = arm.random_q(n, rng=42)
    elif start == "default":
        q0 = np.broadcast_to(np.clip(np.zeros(5), arm.lower, arm.upper), (n, 5)).copy()
    else:
        q0 = q.copy()
        p += np.array([0.005, 0.003, -0.002])
    res = solve(arm, p, q0)
    scanned = nearest_scanned_member(arm, p, q0)
    both = res.success & np.isfinite(scanned)
    assert both.mean() > 0.9
    ours = np.sum((res.q - q0) ** 2, axis=1)
    farther = ours[both] > scanned[both] + 1e-9
    assert farther.mean() <= most, farther.mean()
    # the scan is no better than the answer where the answer is a refined member: it is nearer in most cases
    assert (ours[both] < scanned[both] - 1e-9).mean() > 0.5
