r"""Forward kinematics, frames, geometric Jacobians and manipulability, batched.

All functions take ``q`` of shape ``(..., n)`` in radians (prismatic joints in the
robot's length unit) and broadcast over the leading axes; a single configuration is
just ``(n,)``.

Two interchangeable back ends compute the same numbers: Numba kernels (compiled once,
cached on disk) and vectorised NumPy. ``set_backend("auto")`` (the default) uses Numba
when it imports; the CLI picks ``"numpy"`` so that it starts in a fraction of a second.

Examples
--------
>>> import numpy as np, armkit
>>> arm = armkit.load("planar2")
>>> T = armkit.fk(arm, [0.0, np.pi / 2])
>>> np.round(T[:3, 3], 12) + 0.0                    # x = L1 c1 + L2 c12, y = L1 s1 + L2 s12
array([1. , 0.5, 0. ])
>>> armkit.jacobian(arm, np.zeros((5, 2))).shape    # batched
(5, 6, 2)
"""

from __future__ import annotations

from typing import Any, Literal, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import _jit_loader
from .._jit_loader import get_backend, set_backend   # the back end's state lives on the ground floor
from .._text import Fielded, shorten
from ..errors import ArgumentError, ArmkitError, ShapeError
from ..model.robot import Robot
from . import _numpy

__all__ = ["fk", "fk_frames", "link_frames", "jacobian", "manipulability", "condition_number", "is_singular",
           "SINGULAR_THRESHOLD", "task_rows", "movable_rows", "set_backend", "get_backend"]

Array = NDArray[np.float64]

SINGULAR_THRESHOLD = 1e-6
"""``is_singular`` is true where the smallest singular value of the task Jacobian (lengths in
metres, see :func:`task_rows`) is below this: about 1e-6 rad from an exact singularity of a
metre-sized arm."""

_jit_loader.serve("kinematics._jit")   # these kernels stand for the Numba back end (and say where the cache is)
_jit_module = _jit_loader.jit_module   # the kernels while Numba serves, else None (poll=True: fk, jacobian, fk_frames)
_load_jit = _jit_loader.load_jit


def __getattr__(name: str) -> object:
    """``kinematics._backend`` and ``kinematics._ACTIVE``: the back end's state, read from its owner."""
    if name in ("_backend", "_ACTIVE"):
        return getattr(_jit_loader, name)
    raise AttributeError(Fielded.of("module {module!r} has no attribute {name!r}", module=__name__, name=name))


_ndarray, _empty = np.ndarray, np.empty  # module-level names: the single-call path counts nanoseconds
_float64 = np.dtype(np.float64)  # native float64 (a byte-swapped '>f8' is another object: general path)
_fk_entry: Any = None    # kinematics._jit.fk_one_entry, once the general path has loaded it
_jac_entry: Any = None   # kinematics._jit.jacobian_one_entry, likewise


def packed(robot: Robot) -> tuple[Array, Array]:
    """The kernels' packed chain constants ``(F, P)`` of ``robot`` (layout: ``kinematics._jit.pack``).

    Built once per robot and kept in its cache (``robot.cache["packed_chain"]``); the FK,
    Jacobian and frame kernels read ``F`` or ``P``, the LM kernel ``P``.
    """
    FP = robot.cache.get("packed_chain")
    if FP is None:
        jit = _load_jit()
        assert jit is not None, "packed is only called with the Numba back end"
        c = robot.chain
        FP = robot.cache["packed_chain"] = jit.pack(c.fixed, c.prismatic, c.base, c.pre, c.post, c.tool)
    return FP  # type: ignore[no-any-return]


def _flat(robot: Robot, q: ArrayLike) -> tuple[Array, tuple[int, ...]]:
    arr = robot.check_q(q)
    return np.ascontiguousarray(arr.reshape(-1, robot.n)), arr.shape[:-1]


def _flat_unchecked(robot: Robot, q: ArrayLike) -> tuple[Array, tuple[int, ...]]:
    """Like :func:`_flat` but leaves the NaN/inf check to the kernel (it counts them for free)."""
    if type(q) is np.ndarray and q.dtype.kind in "fiu":
        arr = q.astype(float, copy=False)
    else:   # lists, complex, masked, object arrays: the one validator (never drop a mask or an imaginary part)
        arr = robot.check_q(q)
    if arr.ndim == 0 or arr.shape[-1] != robot.n:
        robot.check_q(arr)
    return np.ascontiguousarray(arr.reshape(-1, robot.n)), arr.shape[:-1]


def _not_a_robot(robot: object) -> ArmkitError:
    """The error for a first argument that is not a Robot (``fk(None, q)``, ``fk("fighter", q)``): an
    ArgumentError saying a Robot is needed, and for a name how to load it, not an AttributeError from inside."""
    if isinstance(robot, str):
        shown = shorten(repr(robot), 80)
        return ArgumentError.of("robot must be an armkit.Robot, got the string {shown}; load it first: "
                                "armkit.load({shown})", shown=shown)
    return ArgumentError.of("robot must be an armkit.Robot, got {kind}", kind=type(robot).__name__)


def fk(robot: Robot, q: ArrayLike, link: str | None = None, *, out: Array | None = None) -> Array:
    r"""Pose of the tool in the world frame, ``T_world_tool`` (or of the named ``link``).

    .. math:: T = T_{base} \, A_1(q_1) \cdots A_n(q_n) \, T_{tool}

    Parameters
    ----------
    robot : Robot
    q : array_like, shape (..., n)
        Joint values (rad for revolute, length units for prismatic joints).
    link : str, optional
        A link name (see ``robot.links``: URDF link names, or ``link0 .. linkn`` of a DH
        arm): the pose of that link instead of the tool.
    out : ndarray, shape (..., 4, 4), optional
        Where to write the result: a C-contiguous, writable float64 array of exactly the
        result's shape, not overlapping ``q`` (``np.empty(q.shape[:-1] + (4, 4))``). It is
        returned. Reusing one buffer for repeated big batches spares allocating and touching
        fresh memory on every call, most of a first big batch's extra time (measured by
        ``benchmarks/bench_first_call.py --first-batch``). If ``q`` is rejected, ``out`` may
        have been partly written.

    Returns
    -------
    T : ndarray, shape (..., 4, 4)

    Examples
    --------
    >>> import armkit, numpy as np
    >>> T = armkit.fk(armkit.load("fighter"), np.radians([30, 45, 60]))
    >>> np.round(T[:3, 3], 3)
    array([ 24.861,  14.353, 187.181])
    >>> np.round(armkit.fk(armkit.load("planar2"), [0.0, 0.0], link="link1")[:3, 3], 12) + 0.0
    array([1., 0., 0.])
    >>> buf = np.empty((2, 4, 4))
    >>> armkit.fk(armkit.load("planar2"), np.zeros((2, 2)), out=buf) is buf
    True
    """
    # the single-call fast path: every test is one cheap Python operation; anything unusual (a list, another
    # dtype, a batch, a link, out=, the NumPy back end, a Robot not seen yet) goes to the general path. These
    # tests are also what makes the direct call of the compiled kernel safe (kinematics._jit.__getattr__)
    kernel = _fk_entry
    if kernel is not None and type(q) is _ndarray and q.dtype is _float64 and q.ndim == 1 and link is None \
            and out is None and _jit_loader._ACTIVE is not None:
        try:
            F = robot.cache["single_call"][0]
        except (AttributeError, KeyError, TypeError):   # not a Robot, or its packed chain not built yet
            return _fk(robot, q, link, out)
        T = _empty((4, 4))
        try:
            kernel(F, q, T)  # the compiled kernel itself: no dispatcher, no copy, no extra pass
            return T
        except (ValueError, TypeError):  # wrong length or NaN: the general path says what is wrong
            pass
    return _fk(robot, q, link, out)


def _fk(robot: Robot, q: ArrayLike, link: str | None, out: Array | None) -> Array:
    """:func:`fk` for every argument, checked."""
    global _fk_entry
    if not isinstance(robot, Robot):   # one check at the entry (issue 24)
        raise _not_a_robot(robot)
    if link is not None:
        k = robot.link_index(link)
        lk = robot.links[k]
        return _into(out, np.asarray(fk_frames(robot, q)[..., lk.frame, :, :] @ lk.offset), q)
    jit = _jit_loader._ACTIVE or _jit_module(True)
    if jit is None:
        flat, lead = _flat(robot, q)
        return _into(out, _numpy.fk(robot.chain, flat).reshape(lead + (4, 4)), q)
    F = packed(robot)[0]
    if type(q) is _ndarray and q.ndim == 1 and q.dtype is _float64 and out is None:
        kernel = _fk_entry = jit.fk_one_entry   # from now on fk's fast path calls it
        T = _empty((4, 4))
        try:
            kernel(_single_call(robot)[0], q, T)
            return T
        except (ValueError, TypeError):  # wrong length or NaN: the batch path below
            pass
    flat, lead = _flat_unchecked(robot, q)
    dest = None if out is None else _out_array(out, lead + (4, 4), flat).reshape(flat.shape[0], 4, 4)
    T, bad = _batch_into(jit, (jit._fk_serial, jit._fk_parallel), (F, flat), dest, (flat.shape[0], 4, 4))
    if bad:
        robot.check_q(q)  # raises ShapeError naming the problem
    return T.reshape(lead + (4, 4)) if out is None else out


def _single_call(robot: Robot) -> tuple[Array, tuple[int, int]]:
    """``(F, (6, n))``: what the single-call fast paths read from the robot's cache in one lookup.

    ``F`` is a private *writable* copy of the packed constants (:func:`packed`): Numba's dispatcher types a
    writable array on its quick path and a read-only one on a slower one (~0.05 µs a call); the kernels never
    write it.
    """
    entry = robot.cache.get("single_call")
    if entry is None:
        entry = robot.cache["single_call"] = (np.array(packed(robot)[0]), (6, robot.n))
    return entry  # type: ignore[no-any-return]


def _batch_into(jit: Any, kernels: tuple[Any, Any], args: tuple[object, ...], dest: Array | None,
                shape: tuple[int, ...]) -> tuple[Array, int]:
    """Run the one-thread or the multi-threaded kernel of a batch (``args`` then the output) into ``dest``
    (a new array of ``shape`` when None): ``(output, number of non-finite values of q)``.

    The choice of kernel is ``fk_batch``'s (``kinematics._jit``): threads from ``PARALLEL_MIN`` configurations
    on, when the threaded kernels may be used."""
    if dest is None:
        dest = _empty(shape)
    serial, parallel = kernels
    kernel = parallel if shape[0] >= jit.PARALLEL_MIN and _jit_loader.parallel_ok() else serial
    return dest, int(kernel(*args, dest))


def _out_array(out: object, shape: tuple[int, ...], q: Array) -> Array:
    """``out`` checked as the destination of a result of ``shape`` computed from ``q`` (the kernels' input)."""
    if type(out) is not np.ndarray:
        raise ArgumentError.of("out must be a numpy.ndarray (np.empty({shape})), got {type}",
                               shape=shape, type=type(out).__name__)
    if out.dtype != _float64:
        raise ArgumentError.of("out must have dtype float64, got {dtype}", dtype=str(out.dtype))
    if out.shape != shape:
        raise ShapeError.of("out must have shape {expected} (the shape of the result), got {shape}",
                            expected=shape, shape=out.shape)
    if not out.flags.c_contiguous:
        raise ArgumentError.of("out must be C-contiguous (as np.empty({shape}) is), got a strided view",
                               shape=shape)
    if not out.flags.writeable:
        raise ArgumentError.of("out must be writable, got a read-only array")
    if np.may_share_memory(out, q):
        raise ArgumentError.of("out must not overlap q (the result would overwrite the joint values it is "
                               "computed from)")
    return out


def _into(out: Array | None, result: Array, q: ArrayLike) -> Array:
    """``result``, or ``out`` (checked) holding it: the NumPy back end's and the link path's ``out=``."""
    if out is None:
        return result
    _out_array(out, result.shape, q if isinstance(q, np.ndarray) else np.empty(0))
    out[...] = result
    return out


def fk_frames(robot: Robot, q: ArrayLike) -> Array:
    """Every link frame in the world: ``(..., n + 1, 4, 4)``.

    For a URDF arm, ``frames[..., k]`` (``k = 1 .. n-1``) is the child link of moving
    joint ``k``; other links (fixed ones, named ones) come from :func:`link_frames` or
    ``fk(robot, q, link=name)``.

    ``frames[..., 0]`` is the base frame ``T_world_base``; ``frames[..., k]`` for
    ``k = 1 .. n-1`` is link frame ``k`` of the DH convention in use (standard DH: the
    frame at the far end of link ``k``, on joint axis ``k + 1``; modified DH: the frame on
    joint axis ``k``); ``frames[..., n]`` is the last link frame with the tool applied,
    so it equals :func:`fk`. The origins are the points a plot joins with lines.
    """
    if not isinstance(robot, Robot):   # one check at the entry (issue 24)
        raise _not_a_robot(robot)
    c = robot.chain
    jit = _jit_module(True)
    if jit is not None:
        flat, lead = _flat_unchecked(robot, q)
        out, bad = jit.frames_batch(packed(robot)[1], flat)
        if bad:
            robot.check_q(q)
    else:
        flat, lead = _flat(robot, q)
        out = _numpy.frames(c, flat)
    return out.reshape(lead + (robot.n + 1, 4, 4))


def link_frames(robot: Robot, q: ArrayLike) -> Array:
    """World pose of every link in ``robot.links``: ``(..., len(robot.links), 4, 4)``.

    Link ``i`` is ``fk_frames(robot, q)[..., links[i].frame] @ links[i].offset``: for a
    URDF arm every link of the chain (fixed ones included) and the links hanging off it at
    their ``q = 0`` place; for a DH arm the ``n + 1`` link frames.

    Examples
    --------
    >>> import armkit
    >>> arm = armkit.load("so101")
    >>> armkit.link_frames(arm, arm.random_q(4, rng=0)).shape[:2] == (4, len(arm.links))
    True
    """
    frames = fk_frames(robot, q)
    idx = [lk.frame for lk in robot.links]
    offsets = np.stack([lk.offset for lk in robot.links])
    return np.asarray(frames[..., idx, :, :] @ offsets)


def jacobian(robot: Robot, q: ArrayLike, frame: Literal["base", "tool"] = "base", *,
             out: Array | None = None) -> Array:
    r"""Geometric Jacobian, rows ``(v, omega)``: ``(..., 6, n)``.

    Column ``i`` of a revolute joint is :math:`(z_i \times (p_e - p_i),\ z_i)`, of a
    prismatic joint :math:`(z_i, 0)`, where :math:`z_i, p_i` are joint ``i``'s axis and a
    point on it and :math:`p_e` is the tool origin. ``frame="base"`` expresses both parts
    in the world frame; ``frame="tool"`` in the tool frame (rotated by :math:`R_e^T`). In
    both, ``v`` is the velocity of the tool origin.

    Parameters
    ----------
    robot : Robot
    q : array_like, shape (..., n)
    frame : {"base", "tool"}
    out : ndarray, shape (..., 6, n), optional
        Where to write the result, as in :func:`fk`: a C-contiguous, writable float64 array
        of exactly the result's shape, not overlapping ``q``; it is returned.

    Returns
    -------
    J : ndarray, shape (..., 6, n)
    """
    kernel = _jac_entry   # the fast path's tests make the direct call safe, as in fk
    if kernel is not None and type(q) is _ndarray and q.dtype is _float64 and q.ndim == 1 and out is None \
            and _jit_loader._ACTIVE is not None:
        if frame == "base":
            flag = 0
        elif frame == "tool":
            flag = 1
        else:
            return _jacobian(robot, q, frame, out)
        try:
            F, shape = robot.cache["single_call"]
        except (AttributeError, KeyError, TypeError):   # not a Robot, or its packed chain not built yet
            return _jacobian(robot, q, frame, out)
        J = _empty(shape)  # (6, n): the kernel checks len(q) == n
        try:
            kernel(F, q, flag, J)  # the compiled kernel itself (an int flag, as its signature says)
            return J
        except (ValueError, TypeError):  # wrong length or NaN: the general path says what is wrong
            pass
    return _jacobian(robot, q, frame, out)


def _jacobian(robot: Robot, q: ArrayLike, frame: str, out: Array | None) -> Array:
    """:func:`jacobian` for every argument, checked."""
    global _jac_entry
    if not isinstance(robot, Robot):   # one check at the entry (issue 24)
        raise _not_a_robot(robot)
    tool_frame = frame == "tool"
    if not tool_frame and frame != "base":
        raise ArgumentError.of("frame must be 'base' or 'tool', got {frame!r}", frame=frame)
    jit = _jit_loader._ACTIVE or _jit_module(True)
    if jit is None:
        flat, lead = _flat(robot, q)
        return _into(out, _numpy.jacobian(robot.chain, flat, tool_frame).reshape(lead + (6, robot.n)), q)
    F = packed(robot)[0]
    if type(q) is _ndarray and q.ndim == 1 and q.dtype is _float64 and out is None:
        kernel = _jac_entry = jit.jacobian_one_entry   # from now on jacobian's fast path calls it
        Fw, shape = _single_call(robot)
        J = _empty(shape)
        try:
            kernel(Fw, q, int(tool_frame), J)
            return J
        except (ValueError, TypeError):  # wrong length or NaN: the batch path below
            pass
    flat, lead = _flat_unchecked(robot, q)
    n = robot.n
    dest = None if out is None else _out_array(out, lead + (6, n), flat).reshape(flat.shape[0], 6, n)
    J, bad = _batch_into(jit, (jit._jacobian_serial, jit._jacobian_parallel), (F, flat, tool_frame), dest,
                         (flat.shape[0], 6, n))
    if bad:
        robot.check_q(q)
    return J.reshape(lead + (6, n)) if out is None else out


def movable_rows(robot: Robot) -> tuple[int, ...]:
    """The twist rows ``(vx, vy, vz, wx, wy, wz)`` = 0-5 the arm changes at all (its Jacobian's nonzero rows at
    random configurations): a SCARA never turns its tool about x or y.

    >>> import armkit
    >>> movable_rows(armkit.load("cobra600")), movable_rows(armkit.load("planar2"))
    ((0, 1, 2, 5), (0, 1, 5))
    """
    if not isinstance(robot, Robot):   # one check at the entry (issue 24)
        raise _not_a_robot(robot)
    rows = robot.cache.get("movable_rows")   # a property of the arm: found once (a rate loop asks every step)
    if rows is None:
        probe = robot.random_q(8, rng=0)
        J = np.abs(_numpy.jacobian(robot.chain, probe, False))
        rows = robot.cache["movable_rows"] = tuple(r for r in range(6) if J[:, r, :].max() > 1e-12)
    return rows  # type: ignore[no-any-return]


def task_rows(robot: Robot) -> tuple[int, ...]:
    """The Jacobian rows that make up the arm's task, used by the manipulability measures.

    Position first, then as many orientation components as the arm has joints left,
    counting only components the arm can change at all: all six rows for a 6- or 7-DOF arm,
    ``(vx, vy, vz)`` for the 3-DOF fighter arm, ``(vx, vy)`` for a 2R planar arm and
    ``(vx, vy, wz)`` for a 3R planar arm (the x, y, phi task of its closed form).

    Examples
    --------
    >>> import armkit
    >>> [task_rows(armkit.load(n)) for n in ("planar2", "planar3", "fighter")]
    [(0, 1), (0, 1, 5), (0, 1, 2)]
    """
    movable = movable_rows(robot)
    pos = [r for r in movable if r < 3]
    rot = [r for r in movable if r >= 3]
    return tuple(pos + rot[: max(0, robot.n - len(pos))])


def _task_jacobian(robot: Robot, q: ArrayLike, rows: Sequence[int] | None) -> Array:
    """Task rows of the Jacobian with lengths in metres (prismatic columns per metre), so mm and m arms agree."""
    J = jacobian(robot, q).copy()
    J[..., :3, :] *= robot.unit_scale
    J[..., :, robot.prismatic] /= robot.unit_scale
    return J[..., list(task_rows(robot) if rows is None else rows), :]


_SVD_CHUNK = 100_000   # configurations per chunk: a (chunk, 6, n) Jacobian, never one for the whole batch


def _singular_values(robot: Robot, q: ArrayLike, rows: Sequence[int] | None) -> Array:
    if not isinstance(robot, Robot):   # one check at the entry (issue 24)
        raise _not_a_robot(robot)
    qa = robot.check_q(q)
    count = qa.size // robot.n
    if count <= _SVD_CHUNK:
        return np.asarray(np.linalg.svd(_task_jacobian(robot, qa, rows), compute_uv=False), dtype=float)
    flat = qa.reshape(count, robot.n)       # many configurations: in chunks, memory bounded by one chunk
    first = np.asarray(np.linalg.svd(_task_jacobian(robot, flat[:_SVD_CHUNK], rows), compute_uv=False), dtype=float)
    out = np.empty((count,) + first.shape[1:])
    out[:_SVD_CHUNK] = first
    for s in range(_SVD_CHUNK, count, _SVD_CHUNK):
        out[s:s + _SVD_CHUNK] = np.linalg.svd(_task_jacobian(robot, flat[s:s + _SVD_CHUNK], rows), compute_uv=False)
    return out.reshape(qa.shape[:-1] + first.shape[1:])


def manipulability(robot: Robot, q: ArrayLike, rows: Sequence[int] | None = None) -> Array:
    r"""Yoshikawa's manipulability :math:`w = \sqrt{\det(J J^T)}`, shape ``(...)``.

    ``J`` holds the task rows of the geometric Jacobian (:func:`task_rows`, or ``rows``
    given as indices into ``(vx, vy, vz, wx, wy, wz)``), lengths in metres; ``w`` is the
    product of its singular values and vanishes exactly at the singularities of that task.

    Examples
    --------
    >>> import armkit, numpy as np
    >>> arm = armkit.load("planar2")                     # 2R: w = L1 L2 |sin q2|
    >>> round(float(armkit.manipulability(arm, [0.3, np.pi / 2])), 12)
    0.5
    """
    s = _singular_values(robot, q, rows)
    return np.asarray(np.prod(s, axis=-1), dtype=float)


def condition_number(robot: Robot, q: ArrayLike, rows: Sequence[int] | None = None) -> Array:
    """Condition number ``sigma_max / sigma_min`` of the task Jacobian (lengths in metres), ``(...)``; inf at a singularity."""
    s = _singular_values(robot, q, rows)
    with np.errstate(divide="ignore"):
        return np.where(s[..., -1] > 0, s[..., 0] / np.where(s[..., -1] > 0, s[..., -1], 1.0), np.inf)


def is_singular(robot: Robot, q: ArrayLike, threshold: float = SINGULAR_THRESHOLD,
                rows: Sequence[int] | None = None) -> NDArray[np.bool_]:
    """True where the smallest singular value of the task Jacobian (lengths in metres) is below ``threshold``.

    The default :data:`SINGULAR_THRESHOLD` = 1e-6 flags configurations within about
    1e-6 rad of an exact singularity of a metre-sized arm.
    """
    return _singular_values(robot, q, rows)[..., -1] < threshold
