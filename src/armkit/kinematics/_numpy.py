"""Vectorised NumPy kernels over the uniform chain (see :mod:`armkit.model.robot`).

These are the reference implementation and the path used when the JIT is off
(the CLI uses them so that it starts fast). ``q`` is ``(B, n)``; results are ``(B, ...)``.
"""

from __future__ import annotations

import numpy as np

from ..model.robot import Chain


def _move(X: np.ndarray, t: np.ndarray, prismatic: bool) -> np.ndarray:
    """``X @ M(t)`` for a batch of poses ``X`` (B, 4, 4): M = Rz(t) or Tz(t)."""
    if prismatic:
        X = X.copy()
        X[:, :3, 3] += t[:, None] * X[:, :3, 2]
        return X
    c, s = np.cos(t)[:, None], np.sin(t)[:, None]
    X = X.copy()
    col0 = X[:, :3, 0].copy()
    X[:, :3, 0] = c * col0 + s * X[:, :3, 1]
    X[:, :3, 1] = c * X[:, :3, 1] - s * col0
    return X


def fk(chain: Chain, q: np.ndarray) -> np.ndarray:
    X = np.broadcast_to(chain.fixed[0], (q.shape[0], 4, 4))
    for k in range(q.shape[1]):
        X = _move(X, q[:, k], bool(chain.prismatic[k])) @ chain.fixed[k + 1]
    return np.ascontiguousarray(X)


def frames(chain: Chain, q: np.ndarray) -> np.ndarray:
    B, n = q.shape
    out = np.empty((B, n + 1, 4, 4))
    X = np.broadcast_to(chain.base, (B, 4, 4))
    out[:, 0] = X
    for k in range(n):
        X = _move(X @ chain.pre[k], q[:, k], bool(chain.prismatic[k])) @ chain.post[k]
        out[:, k + 1] = X
    out[:, n] = out[:, n] @ chain.tool
    return out


def jacobian(chain: Chain, q: np.ndarray, tool_frame: bool) -> np.ndarray:
    B, n = q.shape
    z = np.empty((B, n, 3))
    p = np.empty((B, n, 3))
    X = np.broadcast_to(chain.base, (B, 4, 4))
    for k in range(n):
        A = X @ chain.pre[k]                # the frame whose z axis is joint k's axis
        z[:, k] = A[:, :3, 2]
        p[:, k] = A[:, :3, 3]
        X = _move(A, q[:, k], bool(chain.prismatic[k])) @ chain.post[k]
    E = X @ chain.tool
    J = np.zeros((B, 6, n))
    lin = np.cross(z, E[:, None, :3, 3] - p)
    pr = chain.prismatic
    J[:, :3, :] = np.where(pr[None, :, None], z, lin).transpose(0, 2, 1)
    J[:, 3:, :] = np.where(pr[None, :, None], 0.0, z).transpose(0, 2, 1)
    if tool_frame:
        Rt = np.swapaxes(E[:, :3, :3], 1, 2)
        J[:, :3] = Rt @ J[:, :3]
        J[:, 3:] = Rt @ J[:, 3:]
    return J
