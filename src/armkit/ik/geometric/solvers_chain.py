"""The chain for the solvers (:mod:`.solvers`): the ideal chain (:func:`align`), the reversed chain
(:func:`reverse`), and Newton steps on the true chain (:func:`polish`)."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from .classify import common_point
from .poe import POE
from .subproblems import rotm

Array = NDArray[np.float64]


# ----------------------------------------------------------------------------- the chain
def _points(P: Array) -> Array:
    """Points on axes 1..n (rows 0..n-1) and the tool origin (row n), world frame, q = 0."""
    return np.cumsum(P, axis=0)


def align(form: POE, meet: tuple[tuple[int, ...], ...] = (), parallel: tuple[tuple[int, ...], ...] = ()
          ) -> tuple[POE, float]:
    """The ideal chain for a solver, and how far it is from ``form``.

    Axes of each group in ``parallel`` (0-based joint indices) get one common direction (the
    mean, signs kept); the points of the axes of each group in ``meet`` are all moved to the
    point nearest to those axes (least squares), so that the P between them is 0. Exact
    robots only slide points along their axes (the same chain); for nearly meeting or
    parallel axes the returned chain is the nearest ideal one.

    Returns
    -------
    (POE, float)
        The ideal chain and the deviation: the largest axis-direction change (rad) or the
        largest distance of a moved point from its axis divided by the arm size.
    """
    H = np.array(form.H, dtype=float)
    pts = _points(np.asarray(form.P, dtype=float))
    n = form.n
    scale = _size(form)
    dev = 0.0
    for group in parallel:
        ref = H[group[0]]
        acc = np.zeros(3)
        for k in group:
            acc += H[k] if H[k] @ ref >= 0 else -H[k]
        acc /= np.linalg.norm(acc)
        for k in group:
            new = acc if H[k] @ ref >= 0 else -acc
            dev = max(dev, float(np.linalg.norm(new - H[k])))
            H[k] = new
    for group in meet:
        c, _ = common_point(H, pts, group)      # the point nearest to all the group's lines (the classifier's)
        for k in group:
            off = c - pts[k]
            dev = max(dev, float(np.linalg.norm(off - H[k] * (H[k] @ off))) / scale)
            pts[k] = c
    P = np.empty_like(form.P, dtype=float)
    P[0] = pts[0]
    P[1:n + 1] = pts[1:n + 1] - pts[:n]
    return POE(H, P, np.array(form.R_nT, dtype=float), np.array(form.prismatic, dtype=bool)), dev


def reverse(form: POE) -> POE:
    """The chain run backwards: from the tool (its frame at q = 0 is the new world) to the base.

    Its joint k is joint n-1-k with the axis reversed, and its FK at the same q (reversed) is
    the inverse of the original's: ``reverse(f).fk(q[::-1]) == inverse of f.fk(q)``.
    """
    Rt = np.asarray(form.R_nT, dtype=float).T
    H = -(np.asarray(form.H)[::-1] @ Rt.T)
    P = -(np.asarray(form.P)[::-1] @ Rt.T)
    return POE(np.ascontiguousarray(H), np.ascontiguousarray(P), np.ascontiguousarray(Rt),
               np.array(form.prismatic[::-1], dtype=bool))


def _size(form: POE) -> float:
    return max(float(np.linalg.norm(form.P, axis=1).sum()), 1e-12)


# --------------------------------------------------------------------------------- polishing
def _jacobian(form: POE, q: Array) -> tuple[Array, Array, Array]:
    """World-frame geometric Jacobian (6, n) (linear rows first) and the pose ``(R, p)`` at ``q``."""
    n = form.n
    R = np.eye(3)
    p = np.array(form.P[0], dtype=float)
    axes = np.empty((n, 3))
    origins = np.empty((n, 3))
    for k in range(n):
        axes[k] = R @ form.H[k]
        origins[k] = p
        if form.prismatic[k]:
            p = p + q[k] * axes[k]
        else:
            R = R @ rotm(form.H[k], float(q[k]))
        p = p + R @ form.P[k + 1]
    J = np.zeros((6, n))
    for k in range(n):
        if form.prismatic[k]:
            J[:3, k] = axes[k]
        else:
            J[:3, k] = np.cross(axes[k], p - origins[k])
            J[3:, k] = axes[k]
    return J, R @ form.R_nT, p


def _log_vec(Re: Array) -> Array:
    """Rotation vector of ``Re`` (small and moderate angles)."""
    w = 0.5 * np.array([Re[2, 1] - Re[1, 2], Re[0, 2] - Re[2, 0], Re[1, 0] - Re[0, 1]])
    s = float(np.linalg.norm(w))
    c = 0.5 * (np.trace(Re) - 1.0)
    th = math.atan2(s, c)
    return w if s < 1e-12 else w * (th / s)


def polish(form: POE, q: Array, R: Array, p: Array, steps: int = 8) -> Array:
    """A few Newton (least-squares) steps on the true chain ``form`` towards the target ``(R, p)``."""
    q = np.array(q, dtype=float)
    scale = _size(form)
    for _ in range(steps):
        J, Rq, pq = _jacobian(form, q)
        e = np.concatenate([p - pq, _log_vec(R @ Rq.T)])
        if np.linalg.norm(e[:3]) < 1e-15 * scale and np.linalg.norm(e[3:]) < 1e-15:
            break
        W = np.array([1.0 / scale] * 3 + [1.0] * 3)
        dq = np.linalg.lstsq(J * W[:, None], e * W, rcond=None)[0]
        q += dq
        if np.abs(dq).max() < 1e-15:
            break
    return q
