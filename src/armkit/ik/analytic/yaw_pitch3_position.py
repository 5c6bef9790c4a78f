"""Yaw + three parallel pitch axes + roll (the SO-101): the position alone in closed form (issue 20).

``armkit.ik(so101, [x, y, z])`` with its default options answers here (:func:`position_route`, called by
:func:`armkit.ik`): a position fixes three of the five joints' freedoms, and with the roll kept at the
start's the solutions form a 1-D family, the tool pitch free. :func:`position_ik` returns the member
nearest the start (the compiled kernel ``_yaw_pitch3_teleop.position_nearest``), polished on the true
model and checked by FK; the branch label says which answer it is (``"front/elbow-up"`` ...: the closed
form's branch; ``"newton"``: Newton steps from the start, nearer than any member found; ``""``: a target
beyond the reach, the arm stretched towards it). The few targets the kernel leaves to Levenberg-Marquardt
get LM's answer, label ``"lm"``.

Split from :mod:`.yaw_pitch3`, which still answers for the names defined here (loading this module on
first use). One target takes a short path (:func:`_one`): one compiled call that also checks the input,
the result's fields made as the closed-form families' one-call path makes them (0-d arrays, the message
of a failure made when first read).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ... import _jit_loader
from ..._text import Fielded
from ...model.robot import Robot
from ..api import _normalise_q0, _normalise_target
from ..result import IKResult, _message, default_tolerance
from ._common import Array
from .yaw_pitch3 import _LABELS, fast_geometry, shoulder_reach

__all__ = ["position_ik", "position_route"]

_POSITION_MODULE = "ik.analytic._yaw_pitch3_teleop"
_POS_LABELS = np.append(_LABELS, ["newton", ""])   # 4: Newton steps from q0; -1: the arm stretched (unreachable)
_F64 = np.dtype(np.float64)
# 0-d values of the one-target path, copied per result (a result owns its arrays)
_LABELS_0D = [_POS_LABELS[k:k + 1].reshape(()) for k in range(len(_POS_LABELS))]   # [-1]: ""
_REASON_0D = (np.array("unreachable"), np.array("converged"))
_BOOL_0D = (np.array(False), np.array(True))
_ZERO_0D = np.array(0.0)
_NONE_0D = np.array(0, dtype=np.int64)
_TRUE_0D, _CONVERGED_0D = _BOOL_0D[1], _REASON_0D[1]
_LATER = IKResult._later


class _Record:
    """What :func:`position_ik` needs of a robot, made once (:func:`_position_record`)."""

    __slots__ = ("kern", "g", "reach", "tol", "ctx", "entry", "q0")

    def __init__(self, robot: Robot, kern: Any, g: Array):
        self.kern, self.g = kern, g
        self.reach = float(shoulder_reach(robot)[-1])  # type: ignore[index]
        self.tol = default_tolerance(robot)
        self.ctx = kern.pack_position(g, self.tol, self.reach)
        self.q0 = np.clip(np.zeros(robot.n), robot.lower, robot.upper)   # armkit.ik's default start
        self.q0.setflags(write=False)
        # the compiled function itself, without the dispatcher's typing of four arrays: _one hands it what its
        # one signature takes (float64, 1-D, C-contiguous; it only reads p and q0, so a read-only one is safe)
        self.entry = _jit_loader.compiled_entry(kern.position_one, self.ctx, np.empty(3), np.empty(5), np.empty(9))

    def __reduce__(self) -> tuple:
        """Pickled as None (a pickled robot's cache holds it): compiled code belongs to this process."""
        return (_none, ())

    def route(self, robot: Robot, target: Any, q0: Any) -> IKResult | None:
        """:func:`position_route` once the record is made (what :func:`armkit.ik` calls: no import, no lookup)."""
        if type(target) is np.ndarray and target.dtype is _F64 and target.shape == (3,) \
                and (q0 is None or (type(q0) is np.ndarray and q0.dtype is _F64)):
            return _one(robot, self, target, q0, False)
        return position_route(robot, target, q0)


def _none() -> None:
    return None


def _position_record(robot: Robot) -> Any:
    """The :class:`_Record` of :func:`position_ik` for ``robot``, made once (``robot.cache["yaw_pitch3_position"]``);
    False for an arm it does not serve; None while the Numba back end does not serve (asked again next time)."""
    rec = robot.cache.get("yaw_pitch3_position")
    if rec is not None:
        return rec

    kern = _jit_loader.kernels(_POSITION_MODULE)
    if kern is None:
        return None
    g = fast_geometry(robot) if type(robot) is Robot and robot.__dict__.get("collision") is None else None
    rec = False if g is None else _Record(robot, kern, g)
    robot.cache["yaw_pitch3_position"] = rec
    return rec


def _unreachable_message(robot: Robot, rec: Any, info: Array) -> Any:
    """The message of a target beyond the reach from the shoulder (``info``: the kernel's), as armkit.ik's LM
    path words it."""
    from .._numeric_report import _fmt, residual_note, unreachable_note

    unit = robot.unit
    text = unreachable_note(f"{_fmt(float(info[1]))} {unit}", f"{_fmt(rec.reach)} {unit}", "the shoulder")
    return Fielded.of("{text}; {residual}.", text=text, residual=residual_note(float(info[0]), None, unit))


def _position_fields(robot: Robot, rec: Any, code: NDArray[np.int64], q: Array, info: Array) -> dict[str, Any]:
    """The result fields ``(B,)`` of :func:`position_ik` from the kernel's answers (no row with the code LM)."""
    B = len(code)
    ok = code == 3
    message = np.full(B, "", dtype=object)
    for i in np.flatnonzero(~ok):     # beyond the reach from the shoulder
        message[i] = _unreachable_message(robot, rec, info[i])
    return dict(q=q, success=ok, position_error=info[:, 0].copy(), rotation_error=np.zeros(B),
                iterations=np.zeros(B, dtype=np.int64), branch=_POS_LABELS[info[:, 3].astype(np.int64)],
                within_limits=np.ones(B, dtype=bool), reason=np.where(ok, "converged", "unreachable"), message=message)


class _LaterUnreachable:
    """The message of a one-target failure, made when first read (:meth:`IKResult._later`)."""

    __slots__ = ("robot", "rec", "out")

    def __init__(self, robot: Robot, rec: Any, out: Array):
        self.robot, self.rec, self.out = robot, rec, out.copy()

    def __call__(self) -> str:
        return _message(_unreachable_message(self.robot, self.rec, self.out[5:]), ())


def _one(robot: Robot, rec: Any, target: Array, q0: Any, far: bool = True) -> IKResult | None:
    """:func:`position_ik` of one target ``(3,)`` (float64): one compiled call (which also checks the input), the
    fields as 0-d arrays. None where the general path answers: LM, input it must check or reject, and with
    ``far`` False a target beyond the reach (LM's closest configuration and message, as before the route)."""
    if q0 is None:
        q0 = rec.q0               # C-contiguous already
    elif type(q0) is not np.ndarray or q0.dtype is not _F64 or q0.shape != (5,):
        return None
    else:
        q0 = q0.ravel()           # ravel: C-contiguous, as the signature says
    out = np.empty(9)
    c = rec.entry(rec.ctx, target.ravel(), q0, out)
    if c == 3:                    # the common answer: its fields with no test more
        return _LATER((out[:5], _TRUE_0D.copy(), out[5, ...], _ZERO_0D.copy(), _NONE_0D.copy(),
                       _LABELS_0D[int(out[8])].copy(), _TRUE_0D.copy(), _CONVERGED_0D.copy(), ""))
    if c != -4 or not far:        # LM answers (-3), the input is not finite / q0 beyond 1e6 rad (-2)
        return None
    values = (out[:5], _BOOL_0D[0].copy(), out[5, ...], _ZERO_0D.copy(), _NONE_0D.copy(),
              _LABELS_0D[int(out[8])].copy(), _TRUE_0D.copy(), _REASON_0D[0].copy(), None)
    return _LATER(values, _LaterUnreachable(robot, rec, out))


def position_ik(robot: Robot, target: Any, q0: Any = None, seed: Any = None) -> IKResult | None:
    """:func:`armkit.ik` of a position alone (``target`` ``(3,)`` or ``(..., 3)``, float64) for a 5-joint
    yaw-pitch3 arm (the SO-101), in closed form; None where the general path answers (another arm, the NumPy
    back end, input it must check or reject: it raises the errors).

    The answer is the member of the position's 1-D family of solutions (the tool pitch free, the roll kept at
    ``q0``'s) nearest ``q0`` (default: zero, clipped to the limits, as :func:`armkit.ik`) inside the limits
    (:func:`._yaw_pitch3_teleop.position_nearest`), polished on the true model and checked by FK: ``success``,
    ``reason`` and the residual as LM gives them. "Nearest" is that of a sampled search (15 pitches, the best
    sample's branch refined): a dense scan of the pitch finds a nearer member for about 1 start in 5 far from the
    answer (21.6 % of random starts, 14.8 % of q0 = 0) and 1 in 250 of 5 mm teleoperation steps
    (tests/ik/test_so101_nearest_scan.py); the answer is always an exact, verified solution. A target beyond the reach from the shoulder fails as
    ``"unreachable"`` (``q``: the arm stretched towards it). The few targets the sampled pitches miss (about 1
    in 200, a narrow window at a joint limit) are solved by LM (``solve_lm`` with ``seed``), one target at a
    time, so a batch gives the same answers as single calls (a single call returns None for them: the general
    path, the same call as ever).
    """
    rec = robot.cache.get("yaw_pitch3_position")
    if rec is None:
        rec = _position_record(robot)
    if not rec or type(target) is not np.ndarray or target.dtype != np.float64 or not target.shape \
            or target.shape[-1] != 3:
        return None
    if target.shape == (3,):
        return _one(robot, rec, target, q0)
    lead = target.shape[:-1]
    p = target.reshape(-1, 3)
    if q0 is None:
        q0r = np.broadcast_to(rec.q0, (len(p), 5))
    elif type(q0) is np.ndarray and q0.dtype == np.float64 and q0.shape in ((5,), lead + (5,)):
        q0r = np.broadcast_to(q0, lead + (5,)).reshape(-1, 5)
        if not np.all(np.abs(q0r) <= 1e6):    # NaN, infinity or beyond any meaning: the general path
            return None
    else:
        return None
    if not np.isfinite(p).all():
        return None
    kern, g, reach, tol = rec.kern, rec.g, rec.reach, rec.tol
    B = len(p)
    q = np.empty((B, 5))
    info = np.empty((B, 4))
    code = np.empty(B, dtype=np.int64)
    # writable C-contiguous copies where they are not (a broadcast start is read-only): the kernel's one signature,
    # the one position_one's entry also compiles position_nearest for (a read-only array would compile another)
    kern.position_rows(g, np.require(p, _F64, ("C", "W")), np.require(q0r, _F64, ("C", "W")), tol[0], tol[1], reach,
                       q, info, code)
    lm = np.flatnonzero(code == -3)
    if len(lm) == 0:
        fields = _position_fields(robot, rec, code, q, info)
    else:
        from ..numeric import solve_lm

        done = np.flatnonzero(code != -3)
        part = _position_fields(robot, rec, code[done], q[done], info[done])
        fields = {k: np.empty((B,) + np.shape(v)[1:], dtype=object if k in ("branch", "message", "reason")
                              else np.asarray(v).dtype) for k, v in part.items()}
        for k, v in part.items():
            fields[k][done] = v
        for i in lm.tolist():
            r = solve_lm(robot, p[i:i + 1], np.ascontiguousarray(q0r[i:i + 1]), seed=seed)
            for k in fields:
                fields[k][i] = getattr(r, k)[0]
        fields["reason"] = fields["reason"].astype(str)
    if lead != (B,):
        fields = {k: v.reshape(lead + np.shape(v)[1:]) for k, v in fields.items()}
    return IKResult._of(**fields, trace=None)


def position_route(robot: Robot, target: Any, q0: Any) -> IKResult | None:
    """:func:`armkit.ik` ``(robot, target, q0)`` with every other option at its default, for one position
    ``(3,)`` of an arm :func:`position_ik` serves: its answer, or None (another arm or target, the NumPy back
    end, LM's targets, input the general path must reject, a target beyond the reach from the shoulder: LM
    fails it as "unreachable" with the closest configuration it finds, the same answer and message as before
    this route). A target or start that is not a float64 array (a list, say) is normalised as
    :func:`armkit.ik` normalises it (raising its errors)."""
    rec = robot.cache.get("yaw_pitch3_position")
    if rec is None:
        rec = _position_record(robot)
    if not rec:
        return None
    if type(target) is not np.ndarray or target.dtype is not _F64:
        flat, lead, position_only = _normalise_target(robot, target, None, True)
        if lead or not position_only or flat.shape != (1, 3):
            return None
        target = flat[0]
    elif target.shape != (3,):
        return None
    if q0 is not None and (type(q0) is not np.ndarray or q0.dtype is not _F64):
        q0 = _normalise_q0(robot, q0, ())[0]
    return _one(robot, rec, target, q0, False)
