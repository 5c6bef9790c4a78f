"""The result of every IK solver: :class:`IKResult`, batched and honest.

``success`` is only ever true when forward kinematics of the returned ``q`` meets the
tolerance; this module's :func:`verify` is the one place that decides it.
"""

from __future__ import annotations

from dataclasses import MISSING, dataclass, field, fields
from typing import Any, ClassVar, Optional

import numpy as np
from numpy.typing import NDArray

from .. import _jit_loader
from ..kinematics import fk, get_backend
from ..model.robot import Robot
from ..spatial import pose_error

__all__ = ["IKResult", "REASONS", "default_tolerance", "verify", "DEFAULT_TOLERANCE", "DEFAULT_MAX_ITERATIONS",
           "DEFAULT_RESTARTS", "DEFAULT_NEWTON_RESTARTS", "DEFAULT_MAX_SWEEPS", "DEFAULT_SWEEP_RESTARTS"]

REASONS = ("converged", "unreachable", "singular", "max iterations", "joint limits", "collision")
"""The values ``IKResult.reason`` can take."""


DEFAULT_TOLERANCE = 1e-9
"""Default tolerance of every solver's FK check: this many metres (whatever the robot's unit) and radians."""
DEFAULT_MAX_ITERATIONS = 100
"""Levenberg-Marquardt and Newton: steps per attempt."""
DEFAULT_RESTARTS = 50
"""Levenberg-Marquardt (and Newton through :func:`armkit.ik`): attempts from random configurations after the first."""
DEFAULT_NEWTON_RESTARTS = 20
""":func:`armkit.ik.numeric.solve_newton` called directly: attempts from random configurations after the first."""
DEFAULT_MAX_SWEEPS = 2000
"""CCD sweeps and FABRIK backward/forward passes per attempt (both converge linearly: far more than LM steps)."""
DEFAULT_SWEEP_RESTARTS = 20
"""CCD and FABRIK: attempts from random configurations after the first."""


def default_tolerance(robot: Robot) -> tuple[float, float]:
    """Default ``(position, rotation)`` tolerance: :data:`DEFAULT_TOLERANCE` m (1e-6 mm for a mm arm) and rad."""
    return DEFAULT_TOLERANCE / robot.unit_scale, DEFAULT_TOLERANCE


@dataclass(frozen=True)
class IKResult:
    """What an IK solver found, for one target or a batch of targets.

    Attributes (shapes for a batch of targets with leading shape ``(...)``; ``ik_all``
    adds a branch axis ``m`` before ``n``: ``q`` is ``(..., m, n)``, the others ``(..., m)``)

    q : ndarray, shape (..., n)
        Joint values (rad / length units): the solution, or for a failure the closest
        configuration found.
    success : ndarray of bool, shape (...)
        True only where FK of ``q`` meets the tolerance (checked, not assumed) and, when
        limits are enforced, ``q`` is within them.
    position_error : ndarray, shape (...)
        ``|p(q) - p_target|`` in the robot's length unit.
    rotation_error : ndarray, shape (...)
        Angle of the rotation between ``R(q)`` and the target rotation (rad); 0 for
        position-only targets.
    iterations : ndarray of int, shape (...)
        Iterations used (0 for closed-form solutions).
    branch : ndarray of str, shape (...)
        A readable label: ``"elbow-up"``, ``"front/elbow-down"``, ``"lm"``, ...
    within_limits : ndarray of bool, shape (...)
    reason : ndarray of str, shape (...)
        One of :data:`REASONS`.
    message : str, or ndarray of str with shape (...) for a batch
        A sentence for people: why it failed, and by how much. A plain ``str`` for a
        single target (``shape == ()``). The single-call path makes it when it is first
        read (:meth:`_later`): the same value either way.
    trace : ndarray or None
        Per-iteration error norms when the solver was asked for a trace.

    A result of the single-call paths of :func:`armkit.ik` and :func:`armkit.ik_all` holds ``q`` and
    ``success`` and makes its other fields when one is first read (:meth:`_deferred`): the same values,
    ``repr``, equality and pickling as a result built at once.

    Besides the fields, ``checked_against`` (a tuple of str, not a field) names what a success was
    checked against for collisions: ``("ground", "torso")`` for the fighter by default, ``()``
    when nothing was checked (see :func:`armkit.collision.resolve_scene`).
    """

    q: NDArray[np.float64]
    success: NDArray[np.bool_]
    position_error: NDArray[np.float64]
    rotation_error: NDArray[np.float64]
    iterations: NDArray[np.int64]
    branch: NDArray[np.str_]
    within_limits: NDArray[np.bool_]
    reason: NDArray[np.str_]
    message: Any = field(default=None)   # str for a single target, ndarray of str for a batch
    trace: Optional[NDArray[np.float64]] = None
    checked_against: ClassVar[tuple[str, ...]] = ()   # set per result by armkit.ik / ik_all (not a field)

    def __post_init__(self) -> None:
        object.__setattr__(self, "message", _message(self.message, np.shape(self.success)))

    @classmethod
    def _of(cls, **fields: Any) -> "IKResult":
        """``IKResult(**fields)`` built without the frozen dataclass's ``__init__`` (~1 µs less: the
        solvers' single-call paths). The fields are the class's own (no list here); ``message`` is
        normalised as in ``__post_init__``, so both make the same object."""
        self = object.__new__(cls)
        d = self.__dict__
        d.update(_OPTIONAL)
        d.update(fields)
        if len(d) != len(_FIELDS):
            raise TypeError(f"IKResult fields are {_FIELDS}, got {tuple(fields)}")
        d["message"] = _message(d["message"], np.shape(d["success"]))
        return self

    @classmethod
    def _later(cls, values: tuple, later: Any = None) -> "IKResult":
        """A result of the fields ``values`` (every field but ``trace``, in order, already normalised; ``trace``
        None), built without ``__init__``: the single-call paths. With ``later``, ``message`` is made by
        ``later()`` when first read (a call whose failed branches nobody asks about makes no sentence); the
        result is then the same in every way (value, type, repr, equality, pickling) as one given the message."""
        self = _result_of(*values)
        if later is not None:
            d = self.__dict__
            del d["message"]
            d["_later"] = later
        return self

    @classmethod
    def _deferred(cls, make: tuple, q: Any, success: Any) -> "IKResult":
        """A result given ``q`` and ``success`` (the fields nearly every caller reads) whose other fields are
        made when first read: ``make[0](make, "rest")`` returns a dict of the fields but ``q``, ``success`` and
        ``message`` (the first read of one makes them all), ``make[0](make, "message")`` the message's text or a
        function that makes it (as :meth:`_later` takes). The single-call paths of :func:`armkit.ik` and
        :func:`armkit.ik_all` answer this way: their compiled call leaves every number in three buffers that the
        result holds (kept for a later call once nothing refers to them: ``analytic._one_buffers``; with every
        default, the result object too, handed out again with its fields cleared: ``analytic._one_target_calls``),
        and the views, the label arrays and the texts a call would make of them cost about half as much as the
        solve (2 µs of a UR5's ``ik_all``). The values are those the result would have held (the arguments in
        ``make`` are the call's own, copied where a caller could change them); the result is the same in every
        way (value, type, repr, equality, pickling) as one built at once. Two threads reading a field first at
        the same time may each get their own view of the same numbers."""
        self = _NEW(cls)
        d = self.__dict__
        d["q"] = q
        d["success"] = success
        d["trace"] = None
        d["_make"] = make
        return self

    def __getstate__(self) -> dict:
        """Pickling and copying: the fields with the message made (:meth:`_later`, :meth:`_deferred`)."""
        d = self.__dict__
        _made(d)
        if "message" not in d:
            self.message   # noqa: B018 (made now)
        return {k: v for k, v in d.items() if k != "_later"}

    def _map(self, per_target: Any, trace: Any) -> "IKResult":
        """A result with ``per_target`` applied to every field but ``trace`` (given as is), built as :meth:`_of`.
        Of a result whose fields but ``q`` and ``success`` are not made yet (:meth:`_deferred`), those two now and the
        others when first read (a batch's branch names can cost more than its solve: ``Geometric.name_branches``)."""
        new = object.__new__(IKResult)
        d, src = new.__dict__, self.__dict__
        if src.get("_make") is not None and "reason" not in src and "checked_against" not in src:
            d["q"], d["success"], d["trace"] = per_target(src["q"]), per_target(src["success"]), trace
            shape = np.shape(d["success"])

            def make(made: tuple, which: str) -> Any:
                if which == "message":
                    return lambda: _message(per_target(self.message), shape)
                return {f: per_target(getattr(self, f)) for f in _PER_TARGET if f not in ("q", "success", "message")}
            d["_make"] = (make,)
            return new
        _made(src)
        for f in _PER_TARGET:
            if f != "message" or "message" in src:
                d[f] = per_target(src[f])
        d["trace"] = trace
        if "message" in d:
            d["message"] = _message(d["message"], np.shape(d["success"]))
        else:                          # not made yet (_later): the part's messages are made from the whole's, when read
            shape = np.shape(d["success"])
            d["_later"] = lambda: _message(per_target(self.message), shape)
        if "checked_against" in src:   # what the collision check covered goes with every part
            d["checked_against"] = src["checked_against"]
        return new

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(np.shape(self.success))

    def __getitem__(self, index) -> "IKResult":
        """The result(s) for some targets, e.g. ``res[3]``; branch axis kept for ``ik_all``."""
        def pick(a: Any) -> Any:
            return np.asarray(a)[index]

        return self._map(pick, self.trace if self.trace is None or self.shape == () else pick(self.trace))


class _LaterMessage:
    """``IKResult.message`` where a result was built by :meth:`IKResult._later`: a non-data descriptor, so a
    result that holds its message (every other) reads it from its ``__dict__`` as a plain attribute; one that
    does not makes it on first read and keeps it."""

    def __get__(self, obj: Any, owner: Any = None) -> Any:
        if obj is None:
            return None   # the field's default, as the dataclass left it on the class
        d = obj.__dict__
        later = d.get("_later")
        if later is None:
            if "message" in d:
                return d["message"]
            make = d.get("_make")
            if make is None:
                raise AttributeError("message")
            later = make[0](make, "message")   # a deferred result (IKResult._deferred): its text, or a maker
            if not callable(later):
                d["message"] = later
                return later
        message = later()
        d["message"] = message
        d.pop("_later", None)
        return message


setattr(IKResult, "message", _LaterMessage())


def _made(d: dict) -> None:
    """Make every field of a result built by :meth:`IKResult._deferred` (its ``__dict__`` ``d``) not made yet
    (``message`` perhaps left to :meth:`IKResult._later`)."""
    make = d.get("_make")
    if make is not None:
        if "reason" not in d:
            d.update(make[0](make, "rest"))
        if "message" not in d and "_later" not in d:
            v = make[0](make, "message")
            d["_later" if callable(v) else "message"] = v
        d.pop("_make", None)


class _Deferred:
    """A field of :class:`IKResult` (all but ``message`` and ``trace``) on the class: a non-data descriptor, so a
    result that holds the field (every result but one of :meth:`IKResult._deferred`, until it is read) reads it
    from its ``__dict__`` as a plain attribute; a deferred one makes it (with the others but ``message``) on
    first read and keeps them."""

    __slots__ = ("name",)

    def __init__(self, name: str) -> None:
        self.name = name

    def __get__(self, obj: Any, owner: Any = None) -> Any:
        if obj is None:
            return self
        d = obj.__dict__
        make = d.get("_make")
        if make is not None:
            d.update(make[0](make, "rest"))
        try:
            return d[self.name]   # (without _make: made meanwhile by another thread's _made)
        except KeyError:
            raise AttributeError(self.name) from None


for _f in fields(IKResult):
    if _f.name not in ("message", "trace"):
        setattr(IKResult, _f.name, _Deferred(_f.name))

_NEW = object.__new__


def _result_of(q: Any, success: Any, position_error: Any, rotation_error: Any, iterations: Any, branch: Any,
               within_limits: Any, reason: Any, message: Any) -> IKResult:
    """A result of the fields given one by one (already normalised: ``message`` a str for one target, an array of
    str for several; ``trace`` None), built without ``__init__``: what :meth:`IKResult._later` builds, called
    directly by the single-call path of :func:`armkit.ik` when its answer succeeded (~0.15 µs less than building
    and unpacking a tuple)."""
    self = _NEW(IKResult)
    d = self.__dict__
    d["q"] = q
    d["success"] = success
    d["position_error"] = position_error
    d["rotation_error"] = rotation_error
    d["iterations"] = iterations
    d["branch"] = branch
    d["within_limits"] = within_limits
    d["reason"] = reason
    d["message"] = message
    d["trace"] = None
    return self


_FIELDS = tuple(f.name for f in fields(IKResult))
_PER_TARGET = tuple(f for f in _FIELDS if f != "trace")   # the fields with the targets' leading shape
_OPTIONAL = {f.name: f.default for f in fields(IKResult) if f.default is not MISSING}


def _message(message: Any, shape: tuple[int, ...]) -> Any:
    """``message`` as a ``str`` for a single result, an array of str for a batch ("" where none was given)."""
    if message is None:
        return "" if shape == () else np.full(shape, "", dtype=object)
    if np.ndim(message) == 0:
        return str(np.asarray(message, dtype=object).item())
    return message


def verify(robot: Robot, q: NDArray[np.float64], target: NDArray[np.float64], position_only: bool,
           tol: tuple[float, float] | None = None, enforce_limits: bool = True
           ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_], NDArray[np.bool_]]:
    """FK check of candidate solutions.

    Parameters
    ----------
    q : ndarray, shape (..., n)
    target : ndarray, shape (..., 4, 4) or (..., 3)
        Broadcast against ``q``'s leading axes.
    position_only : bool
        Compare positions only (``target`` may still be a pose).

    Returns
    -------
    position_error, rotation_error, ok, within_limits : ndarrays, shape (...)
    """
    tol = tol or default_tolerance(robot)
    if type(q) is np.ndarray and type(target) is np.ndarray:
        one = _verify_one(robot, q, target, position_only, tol, enforce_limits)
        if one is not None:
            return one

    T = fk(robot, q)
    target = np.asarray(target, dtype=float)
    kernels = _jit_loader.kernels("ik._jit_verify")
    if kernels is not None:
        lead = T.shape[:-2]
        is_pose = target.shape[-2:] == (4, 4)
        tail = target.shape[-2:] if is_pose else target.shape[-1:]
        rows, per = _target_rows(lead, target.shape[:-len(tail)])
        own = (target.reshape(rows + tail) if target.size == np.prod(rows + tail)
               else np.broadcast_to(target, rows + tail))
        if is_pose:
            tgt, pose = own, not position_only
        else:  # a point target: put it in column 3 of an otherwise unused pose array
            tgt, pose = np.zeros(rows + (4, 4)), False
            tgt[..., :3, 3] = own
        limits = robot.cache.get("limit_rows")
        if limits is None:
            limits = robot.cache["limit_rows"] = np.ascontiguousarray(np.stack([robot.lower, robot.upper]), dtype=float)
        dp, dr, within = kernels.errors(T.reshape(-1, 4, 4), np.ascontiguousarray(tgt).reshape(-1, 4, 4), pose,
                                        np.ascontiguousarray(q, dtype=float).reshape(-1, robot.n), limits, per=per)
        dp, dr, within = dp.reshape(lead), dr.reshape(lead), within.reshape(lead)
    elif target.shape[-2:] == (4, 4):
        dp, dr = pose_error(T, target)
    else:
        dp = np.linalg.norm(T[..., :3, 3] - target, axis=-1)
        dr = np.zeros_like(dp)
    if kernels is None:
        if position_only:
            dr = np.zeros_like(dp)
        within = robot.within_limits(q)
    ok = (dp <= tol[0]) & (dr <= tol[1])
    if enforce_limits:
        ok &= within
    return dp, dr, ok, within


def _target_rows(lead: tuple[int, ...], target_lead: tuple[int, ...]) -> tuple[tuple[int, ...], int]:
    """How :func:`verify`'s kernel reads targets with leading shape ``target_lead`` against candidates with leading
    shape ``lead`` (the two broadcast): ``(shape, per)``, the targets broadcast to ``shape`` and candidate ``i`` of
    the flattened ``lead`` checked against target ``i // per``. Targets that vary along the first axes of
    ``lead`` only (``(B, 1)`` against ``(B, m)``: every branch of a target) keep their own rows, not one copy per
    candidate (0.5 µs a target of ``ik_all`` on the UR5); any other broadcast is spelt out (``per`` 1).

    >>> _target_rows((5, 8), (5, 1)), _target_rows((5, 8), ()), _target_rows((5, 8), (1, 8))
    (((5,), 8), ((), 40), ((5, 8), 1))
    """
    padded = (1,) * (len(lead) - len(target_lead)) + tuple(target_lead)
    k = len(padded)
    while k and padded[k - 1] == 1:
        k -= 1
    if padded[:k] != lead[:k]:
        return lead, 1
    return lead[:k], int(np.prod(lead[k:], dtype=np.int64))


_ONE: dict = {}  # the functions of the one-candidate path once resolved (not a data cache: saves ~0.5 µs a call)


def _verify_one(robot: Robot, q: NDArray[np.float64], target: NDArray[np.float64], position_only: bool,
                tol: tuple[float, float], enforce_limits: bool
                ) -> Optional[tuple[NDArray[np.float64], NDArray[np.float64], Any, NDArray[np.bool_]]]:
    """:func:`verify` of one candidate on the Numba back end, without the batch machinery.

    ``q`` (n,) with ``target`` (4, 4) or (3,), or ``q`` (1, n) with ``target`` (1, 4, 4) or
    (1, 3), all float64: the same values and shapes as the general path (~2 µs instead of
    ~12 µs); ``None`` for anything else (the general path takes it).
    """
    nd = q.ndim
    if q.dtype != np.float64 or target.dtype != np.float64 or nd == 0 or q.shape[-1] != robot.n:
        return None
    if nd == 2:
        if q.shape[0] != 1 or target.ndim < 2 or target.shape[0] != 1:
            return None
        q1, t1 = q[0], target[0]
    elif nd == 1 and 1 <= target.ndim <= 2:
        q1, t1 = q, target
    else:
        return None
    if not _ONE:
        if get_backend() != "numba":
            return None
        kernels = _jit_loader.module("ik._jit_verify")
        _ONE.update(fk=fk, pose=kernels.check_pose, point=kernels.check_point, backend=get_backend)
    elif _ONE["backend"]() != "numba":
        return None
    shape = t1.shape
    if shape == (4, 4):
        T = _ONE["fk"](robot, q1)
        dp, dr, within = _ONE["pose"](T, t1, not position_only, q1, robot.lower, robot.upper, 1e-12)
    elif shape == (3,):
        T = _ONE["fk"](robot, q1)
        dp, dr, within = _ONE["point"](T, t1, q1, robot.lower, robot.upper, 1e-12)
    else:
        return None
    ok = dp <= tol[0] and dr <= tol[1] and (within or not enforce_limits)
    if nd == 1:
        return np.array(dp), np.array(dr), np.bool_(ok), np.array(within)
    return np.array([dp]), np.array([dr]), np.array([ok]), np.array([within])
