"""Rotations and rigid-body poses on NumPy arrays (the homogeneous-transform seminar's transforms).

Every function is batched over leading axes: a rotation is ``(..., 3, 3)``, a pose
``(..., 4, 4)``, a twist ``(..., 6)`` ordered ``(v, omega)``. Angles are radians.

Examples
--------
>>> import numpy as np
>>> from armkit.spatial import rotz, transl, compose, inverse
>>> T = compose(transl(1.0, 0.0, 0.0), rotz(np.pi / 2))
>>> np.round(T @ [1.0, 0.0, 0.0, 1.0], 12)
array([1., 1., 0., 1.])
>>> np.allclose(compose(T, inverse(T)), np.eye(4))
True
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _jit_loader
from ._checks import real_array
from ._text import Fielded
from .errors import ArmkitError, NotRigidError, ShapeError

__all__ = [
    "check_transform", "rotx", "roty", "rotz", "transl", "make_pose", "compose", "inverse",
    "rpy_to_rotation", "rotation_to_rpy", "quaternion_to_rotation", "rotation_to_quaternion",
    "axis_angle_to_rotation", "rotation_to_axis_angle",
    "so3_log", "so3_exp", "se3_log", "se3_exp", "pose_error", "skew",
]

Array = NDArray[np.float64]


def _angles(theta: ArrayLike) -> Array:
    return np.asarray(theta, dtype=float)


def _elementary(theta: ArrayLike, i: int, j: int, degrees: bool = False) -> Array:
    t = np.radians(_angles(theta)) if degrees else _angles(theta)
    c, s = np.cos(t), np.sin(t)
    T = np.zeros(t.shape + (4, 4))
    T[...] = np.eye(4)
    T[..., i, i] = c
    T[..., j, j] = c
    T[..., i, j] = -s
    T[..., j, i] = s
    return T


def rotx(theta: ArrayLike, degrees: bool = False) -> Array:
    """Pose of a pure rotation by ``theta`` (rad) about x: the homogeneous-transform seminar's A(x, t).

    Parameters
    ----------
    theta : array_like, shape (...)
    degrees : bool, optional
        ``theta`` is in degrees (default radians), as in :func:`rpy_to_rotation`.

    Returns
    -------
    T : ndarray, shape (..., 4, 4)

    Examples
    --------
    >>> np.round(rotx(np.pi / 2)[:3, :3], 12) + 0.0
    array([[ 1.,  0.,  0.],
           [ 0.,  0., -1.],
           [ 0.,  1.,  0.]])
    >>> bool(np.allclose(rotx(30, degrees=True), rotx(np.pi / 6)))
    True
    """
    return _elementary(theta, 1, 2, degrees)


def roty(theta: ArrayLike, degrees: bool = False) -> Array:
    """Pose of a pure rotation by ``theta`` (rad, or deg with ``degrees=True``) about y, shape ``(..., 4, 4)``."""
    return _elementary(theta, 2, 0, degrees)


def rotz(theta: ArrayLike, degrees: bool = False) -> Array:
    """Pose of a pure rotation by ``theta`` (rad, or deg with ``degrees=True``) about z, shape ``(..., 4, 4)``."""
    return _elementary(theta, 0, 1, degrees)


def transl(x: ArrayLike, y: ArrayLike | None = None, z: ArrayLike | None = None) -> Array:
    """Pose of a pure translation.

    Call as ``transl(p)`` with ``p`` of shape ``(..., 3)`` or ``transl(x, y, z)``.

    Returns
    -------
    T : ndarray, shape (..., 4, 4)
    """
    if y is None and z is None:
        p = np.asarray(x, dtype=float)
    else:
        p = np.stack(np.broadcast_arrays(_angles(x), _angles(0.0 if y is None else y),
                                         _angles(0.0 if z is None else z)), axis=-1)
    if p.shape[-1:] != (3,):
        raise ShapeError.of("translation must have shape (..., 3), got {shape}", shape=p.shape)
    T = np.zeros(p.shape[:-1] + (4, 4))
    T[...] = np.eye(4)
    T[..., :3, 3] = p
    return T


def make_pose(R: ArrayLike, p: ArrayLike) -> Array:
    """Pose from rotation ``R`` (..., 3, 3) and position ``p`` (..., 3), shape ``(..., 4, 4)``."""
    R = np.asarray(R, dtype=float)
    p = np.asarray(p, dtype=float)
    shape = np.broadcast_shapes(R.shape[:-2], p.shape[:-1])
    T = np.zeros(shape + (4, 4))
    T[..., :3, :3] = R
    T[..., :3, 3] = p
    T[..., 3, 3] = 1.0
    return T


def _rigidity(R: Any) -> tuple[tuple[Any, ...], Any]:
    """``(|(R^T R - I)_ij| for the 6 distinct entries, det R)`` of the rotation part of rows given as lists of
    Python floats (one pose) or of ``(B,)`` arrays (a batch): one formula for both."""
    (a, b, c, *_), (d, e, f, *_), (g, h, k, *_) = R[:3]
    orth = (abs(a * a + d * d + g * g - 1.0), abs(b * b + e * e + h * h - 1.0), abs(c * c + f * f + k * k - 1.0),
            abs(a * b + d * e + g * h), abs(a * c + d * f + g * k), abs(b * c + e * f + h * k))
    return orth, a * (e * k - f * h) - b * (d * k - f * g) + c * (d * h - e * g)


def _not_rigid(what: str, orth: float, det: float, last: Any, tol: float) -> ArmkitError:
    """The error for a pose that is not rigid, built from templates and fields (the message in any language)."""
    why: Fielded
    if not orth <= tol:
        why = Fielded.of("its rotation part is not orthonormal (R^T R differs from I by {orth:.3g})", orth=orth)
    elif not abs(det - 1.0) <= tol:
        why = Fielded.of("det R = {det:.6g} (a reflection), expected +1" if det < 0 else
                         "det R = {det:.6g}, expected +1", det=det)
    else:
        why = Fielded.of("its last row is ({row}), expected exactly (0, 0, 0, 1)",
                         row=", ".join(f"{v:.6g}" for v in last))
    return NotRigidError.of("{what} is not a rigid transform: {why} (tolerance {tol:g})", what=what, why=why, tol=tol)


_COMPILED_FROM = 1024
"""Batches from this many poses on are measured by the compiled kernel ``kinematics._jit.rigidity`` when the
Numba back end is in use (the same numbers as the NumPy formula)."""


def check_transform(T: ArrayLike, *, what: str = "T", tol: float = 1e-6) -> Array:
    r"""Validate pose(s) and return them as a float64 array: the one pose validator of armkit.

    A pose is a 4x4 matrix :math:`\begin{pmatrix} R & p \\ 0 & 1 \end{pmatrix}` with
    :math:`|R^T R - I|_{max} \le tol`, :math:`|\det R - 1| \le tol` and a last row of exactly
    ``(0, 0, 0, 1)`` (a NumPy-made pose has it; kernels never read it, so anything else is a
    mistake). Batched over leading axes; the message of a bad batch names the first bad index.
    Hot loops that built their poses themselves pass ``check=False`` to the functions that call this.

    Parameters
    ----------
    T : array_like, shape (..., 4, 4)
    what : str
        The argument's name, for the messages (``"target"``, ``"tool"`` ...).
    tol : float
        Tolerance of the rotation part.

    Returns
    -------
    T : ndarray, shape (..., 4, 4), float64 (``T`` itself when it already is one)

    Raises
    ------
    ShapeError
        Not numeric, not ``(..., 4, 4)``, or NaN/infinite values; the message shows the shape expected and got.
    NotRigidError
        Not a rigid transform (a :class:`ShapeError` too); the message says by how much.

    Examples
    --------
    >>> check_transform(rotz(0.3)).shape
    (4, 4)
    >>> check_transform(np.diag([1.0, 1.0, -1.0, 1.0]), what="tool")
    Traceback (most recent call last):
    ...
    armkit.errors.NotRigidError: tool is not a rigid transform: det R = -1 (a reflection), expected +1 (tolerance 1e-06)

    References
    ----------
    pytransform3d's ``check_transform`` (A. Fabisch, JOSS 4(33), 2019) is the model.
    """
    A = T if type(T) is np.ndarray and T.dtype == np.float64 else real_array(T, what)
    if A.ndim < 2 or A.shape[-2:] != (4, 4):
        raise ShapeError.of("{what} must have shape (..., 4, 4), got {shape}", what=what, shape=A.shape)
    if A.ndim == 2:   # one pose: the same formula on Python floats (a dozen NumPy calls cost more)
        rows = A.tolist()
        if not math.isfinite(sum(rows[0]) + sum(rows[1]) + sum(rows[2]) + sum(rows[3])) and not np.isfinite(A).all():
            raise ShapeError.of("{what} contains NaN or infinite values", what=what)   # (a finite sum may overflow)
        parts, det = _rigidity(rows)
        worst = max(parts)
        if not (worst <= tol and abs(det - 1.0) <= tol and rows[3] == [0.0, 0.0, 0.0, 1.0]):
            raise _not_rigid(what, worst, det, rows[3], tol)
        return A
    if not np.isfinite(A).all():
        raise ShapeError.of("{what} contains NaN or infinite values", what=what)
    flat = np.ascontiguousarray(A).reshape(-1, 4, 4)
    kernels = _jit_loader.kernels("kinematics._jit") if len(flat) >= _COMPILED_FROM else None
    if kernels is not None:   # one compiled pass instead of ~30 NumPy passes (~0.1 instead of ~1.5 ms per 10,000)
        orth, det, last_ok = np.empty(len(flat)), np.empty(len(flat)), np.empty(len(flat), dtype=bool)
        kernels.rigidity(flat, orth, det, last_ok)
    else:
        entries = np.ascontiguousarray(np.moveaxis(flat[:, :3, :3], 0, -1))   # (3, 3, B): entry (i, j) of every pose
        orth_parts, det = _rigidity(entries)
        orth = np.maximum.reduce(orth_parts)
        last_ok = (flat[:, 3, 0] == 0.0) & (flat[:, 3, 1] == 0.0) & (flat[:, 3, 2] == 0.0) & (flat[:, 3, 3] == 1.0)
    bad = ~((orth <= tol) & (np.abs(det - 1.0) <= tol) & last_ok)
    if bad.any():
        i = int(np.argmax(bad))
        index = tuple(int(v) for v in np.unravel_index(i, A.shape[:-2]))
        raise _not_rigid(f"{what}[{', '.join(map(str, index))}]", float(orth[i]), float(det[i]), flat[i, 3].tolist(),
                         tol)
    return A


def compose(*poses: ArrayLike) -> Array:
    """Product ``T1 @ T2 @ ...`` of poses, broadcast over leading axes."""
    out = np.asarray(poses[0], dtype=float)
    for T in poses[1:]:
        out = out @ np.asarray(T, dtype=float)
    return out


def inverse(T: ArrayLike) -> Array:
    """Inverse of a rigid pose using ``R^T`` (exact, no general matrix inverse).

    Parameters
    ----------
    T : array_like, shape (..., 4, 4)
    """
    T = np.asarray(T, dtype=float)
    Rt = np.swapaxes(T[..., :3, :3], -1, -2)
    out = np.zeros_like(T)
    out[..., :3, :3] = Rt
    out[..., :3, 3] = -np.einsum("...ij,...j->...i", Rt, T[..., :3, 3])
    out[..., 3, 3] = 1.0
    return out


def skew(w: ArrayLike) -> Array:
    """Skew-symmetric matrix ``[w]x`` with ``[w]x v = w x v``; ``(..., 3) -> (..., 3, 3)``."""
    w = np.asarray(w, dtype=float)
    S = np.zeros(w.shape[:-1] + (3, 3))
    S[..., 0, 1], S[..., 0, 2] = -w[..., 2], w[..., 1]
    S[..., 1, 0], S[..., 1, 2] = w[..., 2], -w[..., 0]
    S[..., 2, 0], S[..., 2, 1] = -w[..., 1], w[..., 0]
    return S


def _rotation(R: ArrayLike) -> Array:
    R = np.asarray(R, dtype=float)
    if R.shape[-2:] == (4, 4):
        R = R[..., :3, :3]
    if R.shape[-2:] != (3, 3):
        raise ShapeError.of("rotation must have shape (..., 3, 3) or (..., 4, 4), got {shape}", shape=R.shape)
    return R


def _scipy_rotation():
    from scipy.spatial.transform import Rotation  # imported on use: keeps `import armkit` light

    return Rotation


def _from_scipy(make, lead: tuple[int, ...]) -> Array:
    return np.asarray(make.as_matrix()).reshape(lead + (3, 3))


def rpy_to_rotation(rpy: ArrayLike, degrees: bool = False) -> Array:
    """Rotation from roll-pitch-yaw ``(..., 3)``: ``R = Rz(yaw) Ry(pitch) Rx(roll)`` (fixed XYZ).

    Written out in NumPy rather than through scipy so that loading a robot file and the
    CLI do not pay scipy's import time.

    Examples
    --------
    >>> R = rpy_to_rotation([0.0, 0.0, 90.0], degrees=True)
    >>> np.round(R @ [1.0, 0.0, 0.0], 12) + 0.0
    array([0., 1., 0.])
    """
    a = np.asarray(rpy, dtype=float)
    if a.shape[-1:] != (3,):
        raise ShapeError.of("rpy must have shape (..., 3), got {shape}", shape=a.shape)
    if degrees:
        a = np.radians(a)
    cr, cp, cy = np.cos(a[..., 0]), np.cos(a[..., 1]), np.cos(a[..., 2])
    sr, sp, sy = np.sin(a[..., 0]), np.sin(a[..., 1]), np.sin(a[..., 2])
    R = np.empty(a.shape[:-1] + (3, 3))
    R[..., 0, 0], R[..., 0, 1], R[..., 0, 2] = cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr
    R[..., 1, 0], R[..., 1, 1], R[..., 1, 2] = sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr
    R[..., 2, 0], R[..., 2, 1], R[..., 2, 2] = -sp, cp * sr, cp * cr
    return R


def rotation_to_rpy(R: ArrayLike, degrees: bool = False) -> Array:
    """Roll-pitch-yaw ``(..., 3)`` of a rotation, inverse of :func:`rpy_to_rotation`.

    Pitch lies in ``[-pi/2, pi/2]``. At gimbal lock (pitch = +-pi/2) roll and yaw are not
    unique; roll is set to 0 and yaw carries the whole rotation about z.

    Examples
    --------
    >>> np.round(rotation_to_rpy(rpy_to_rotation([10.0, 20.0, 30.0], degrees=True), degrees=True), 9)
    array([10., 20., 30.])
    """
    R = _rotation(R)
    pitch = np.arctan2(-R[..., 2, 0], np.hypot(R[..., 0, 0], R[..., 1, 0]))
    lock = np.hypot(R[..., 0, 0], R[..., 1, 0]) < 1e-12
    roll = np.where(lock, 0.0, np.arctan2(R[..., 2, 1], R[..., 2, 2]))
    yaw = np.where(lock, np.arctan2(-R[..., 0, 1], R[..., 1, 1]), np.arctan2(R[..., 1, 0], R[..., 0, 0]))
    out = np.stack([roll, pitch, yaw], axis=-1)
    return np.degrees(out) if degrees else out


def quaternion_to_rotation(quat: ArrayLike) -> Array:
    """Rotation from a unit quaternion in scalar-last order ``(x, y, z, w)``, ``(..., 4)``."""
    qa = np.asarray(quat, dtype=float)
    if qa.shape[-1:] != (4,):
        raise ShapeError.of("quaternion must have shape (..., 4) ordered (x, y, z, w), got {shape}", shape=qa.shape)
    Rot = _scipy_rotation()
    return _from_scipy(Rot.from_quat(qa.reshape(-1, 4)), qa.shape[:-1])


def rotation_to_quaternion(R: ArrayLike) -> Array:
    """Unit quaternion ``(x, y, z, w)`` with ``w >= 0`` of a rotation, ``(..., 4)``."""
    R = _rotation(R)
    Rot = _scipy_rotation()
    q = Rot.from_matrix(R.reshape(-1, 3, 3)).as_quat(canonical=True)
    return q.reshape(R.shape[:-2] + (4,))


def axis_angle_to_rotation(axis: ArrayLike, angle: ArrayLike) -> Array:
    """Rotation by ``angle`` (rad) about ``axis`` (normalised here), ``(..., 3, 3)``."""
    axis = np.asarray(axis, dtype=float)
    n = np.linalg.norm(axis, axis=-1, keepdims=True)
    if np.any(n == 0):
        raise ShapeError.of("axis must be a non-zero vector")
    return so3_exp(axis / n * np.asarray(angle, dtype=float)[..., None])


def rotation_to_axis_angle(R: ArrayLike) -> tuple[Array, Array]:
    """Unit axis ``(..., 3)`` and angle in ``[0, pi]`` ``(...)``; axis is ``(0, 0, 1)`` at angle 0."""
    w = so3_log(R)
    angle = np.linalg.norm(w, axis=-1)
    safe = np.where(angle > 0, angle, 1.0)[..., None]
    axis = np.where(angle[..., None] > 0, w / safe, [0.0, 0.0, 1.0])
    return axis, angle


def so3_exp(w: ArrayLike) -> Array:
    """Rodrigues' formula: rotation vector ``(..., 3)`` -> rotation ``(..., 3, 3)``."""
    w = np.asarray(w, dtype=float)
    th = np.linalg.norm(w, axis=-1)[..., None, None]
    K = skew(w)
    a, b, _ = _exp_coefficients(th)
    return np.eye(3) + a * K + b * (K @ K)


def so3_log(R: ArrayLike) -> Array:
    """Rotation ``(..., 3, 3)`` -> rotation vector ``(..., 3)`` with norm in ``[0, pi]``.

    Uses scipy's quaternion route, which stays accurate near 0 and near pi.
    """
    R = _rotation(R)
    Rot = _scipy_rotation()
    return Rot.from_matrix(R.reshape(-1, 3, 3)).as_rotvec().reshape(R.shape[:-2] + (3,))


def _exp_coefficients(th: Array) -> tuple[Array, Array, Array]:
    """``sin(t)/t``, ``(1 - cos t)/t^2`` and ``(t - sin t)/t^3``, accurate for every ``t >= 0``.

    The first two come from ``sinc`` (``(1 - cos t)/t^2 = sinc^2(t/2) / 2``: no cancellation,
    no underflow); the third switches to its Taylor series below 0.1, where the truncation
    error is under 1e-16.
    """
    a = np.sinc(th / np.pi)
    b = 0.5 * np.sinc(th / (2.0 * np.pi)) ** 2
    small = th < 0.1
    t2 = th * th
    tc = np.where(small, 1.0, th)  # the closed form is only used (and only evaluated safely) above 0.1
    c = np.where(small, 1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0 - t2**3 / 362880.0,
                 (tc - np.sin(tc)) / tc**3)
    return a, b, c


def se3_exp(xi: ArrayLike) -> Array:
    """Twist ``(..., 6)`` ordered ``(v, omega)`` -> pose ``(..., 4, 4)``."""
    xi = np.asarray(xi, dtype=float)
    if xi.shape[-1:] != (6,):
        raise ShapeError.of("twist must have shape (..., 6) ordered (v, omega), got {shape}", shape=xi.shape)
    v, w = xi[..., :3], xi[..., 3:]
    th = np.linalg.norm(w, axis=-1)[..., None, None]
    K = skew(w)
    _, b, c = _exp_coefficients(th)
    V = np.eye(3) + b * K + c * (K @ K)
    return make_pose(so3_exp(w), np.einsum("...ij,...j->...i", V, v))


def se3_log(T: ArrayLike) -> Array:
    """Pose ``(..., 4, 4)`` -> twist ``(..., 6)`` ordered ``(v, omega)``, inverse of :func:`se3_exp`."""
    T = np.asarray(T, dtype=float)
    w = so3_log(T[..., :3, :3])
    th = np.linalg.norm(w, axis=-1)[..., None, None]
    K = skew(w)
    # V^-1 = I - K/2 + (1 - (th/2) cot(th/2)) / th^2 K^2; below th = 0.1 the bracket cancels,
    # so its Taylor series (truncation error < 1e-16 there) takes over
    small = th < 0.1
    ths = np.where(small, 1.0, th)
    t2 = th * th
    coef = np.where(small, 1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0 + t2**3 / 1209600.0,
                    (1.0 - 0.5 * ths / np.tan(0.5 * ths)) / ths**2)
    Vinv = np.eye(3) - 0.5 * K + coef * (K @ K)
    v = np.einsum("...ij,...j->...i", Vinv, T[..., :3, 3])
    return np.concatenate([v, w], axis=-1)


def pose_error(T_actual: ArrayLike, T_target: ArrayLike) -> tuple[Array, Array]:
    """Position error (length units) and rotation angle (rad, in ``[0, pi]``) between poses.

    Parameters
    ----------
    T_actual, T_target : array_like, shape (..., 4, 4)

    Returns
    -------
    position_error : ndarray, shape (...)
        ``|p_actual - p_target|``.
    rotation_error : ndarray, shape (...)
        Angle of ``R_actual^T R_target``.

    Examples
    --------
    >>> dp, dr = pose_error(transl(0.0, 0.0, 0.5), rotz(0.25))
    >>> float(dp), round(float(dr), 12)
    (0.5, 0.25)
    """
    A = np.asarray(T_actual, dtype=float)
    B = np.asarray(T_target, dtype=float)
    dp = np.linalg.norm(A[..., :3, 3] - B[..., :3, 3], axis=-1)
    Rerr = np.swapaxes(A[..., :3, :3], -1, -2) @ B[..., :3, :3]
    # angle via atan2(|axis part|, trace part): accurate for small and large angles alike
    s = 0.5 * np.sqrt((Rerr[..., 2, 1] - Rerr[..., 1, 2]) ** 2 + (Rerr[..., 0, 2] - Rerr[..., 2, 0]) ** 2
                      + (Rerr[..., 1, 0] - Rerr[..., 0, 1]) ** 2)
    c = 0.5 * (np.trace(Rerr, axis1=-2, axis2=-1) - 1.0)
    return dp, np.arctan2(s, c)
