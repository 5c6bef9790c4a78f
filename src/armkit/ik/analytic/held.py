"""A position target with joints held: every branch of the joints left, in closed form.

A SCARA's wrist turns the tool about the tool point but never moves it; so do the three wrist joints of
a 6R arm whose tool point is its wrist centre. For a position alone such an arm has more joints than the
target fixes, and its closed form (for a pose) does not apply. Holding those joints leaves a chain of
1 to 3 joints whose position closed form gives every branch (:class:`Held`):

* **automatically** (:func:`position_solver`): the trailing revolute joints whose axes pass through the
  tool point (:func:`idle_tail`) are held at the start ``q0``. They cannot move the tool point, so the
  branches are every solution there is, with the tool turned as at ``q0``.
* **by the user** (``armkit.ik_all(robot, p, fixed={"joint": value})``, :func:`held_solver`): any joints,
  at the given values; the branches are every solution with those values.

Holding joint ``k`` at ``t`` makes it part of a rigid link: the arm is rebuilt as a :class:`~armkit.Robot`
of the joints left (:func:`reduced`: each free joint's origin is the fixed chain since the previous free
joint, the held joints' motions included), so any family of :func:`armkit.ik.analytic.closed_form` that
solves a position solves it. :class:`Held` is a :class:`~armkit.ik.analytic.ClosedFormFamily` of the
full arm: :func:`armkit.ik.analytic.solve_all` wraps, verifies (FK of the full arm), messages and sorts
its branches like any other family's.

>>> import armkit, numpy as np
>>> cobra = armkit.load("cobra600")                    # a SCARA: shoulder, elbow, quill, wrist
>>> p = armkit.fk(cobra, [0.3, 0.5, 0.1, 0.7])[:3, 3]
>>> res = armkit.ik_all(cobra, p)                      # the wrist is held at q0 (it does not move the point)
>>> res.success.tolist(), bool(np.allclose(armkit.fk(cobra, res.q)[:, :3, 3], p, atol=1e-12))
([True, True], True)
>>> res.q[:, 3].tolist()                               # the wrist at its start, 0
[0.0, 0.0]
"""

from __future__ import annotations

import math
from typing import Any, Mapping

import numpy as np
from numpy.typing import NDArray

from ..._text import Fielded
from ...model.axes import joint_motion
from ...model.robot import Joint, Robot
from ..result import default_tolerance, verify
from ._common import Built, Raw, StandardForm

__all__ = ["Held", "reduced", "idle_tail", "position_solver", "held_solver", "MAX_LEFT"]

Array = NDArray[np.float64]
MAX_LEFT = 3
"""At most this many joints left: a position fixes three coordinates."""
IDLE_TOL = 1e-9
"""A joint axis passes through the tool point when the point is within this many reaches of it."""
_CACHE = "held_position"


def reduced(robot: Robot, held: Mapping[int, float]) -> Robot:
    """The arm with the joints ``held`` (0-based index -> value) fixed: a robot of the joints left.

    Each joint left is an origin + axis (z) joint whose origin is the fixed chain since the joint left
    before it (the held joints' motions at their values included); the tool takes what follows the last.
    FK of the reduced arm at the free values equals FK of ``robot`` with the held values put back.

    >>> import armkit, numpy as np
    >>> ur5 = armkit.load("ur5")
    >>> small = reduced(ur5, {3: 0.2, 4: -0.4, 5: 1.0})
    >>> small.n, bool(np.allclose(armkit.fk(small, [0.1, -0.5, 0.9]), armkit.fk(ur5, [0.1, -0.5, 0.9, 0.2, -0.4, 1.0])))
    (3, True)
    """
    ch = robot.chain
    acc = np.eye(4)
    joints = []
    for k, j in enumerate(robot.joints):
        if k in held:
            acc = acc @ ch.pre[k] @ joint_motion(float(held[k]), bool(ch.prismatic[k])) @ ch.post[k]
            continue
        joints.append(Joint(kind=j.kind, origin=acc @ ch.pre[k], axis=(0.0, 0.0, 1.0), lower=j.lower, upper=j.upper,
                            name=j.name))
        acc = np.array(ch.post[k])
    return Robot(joints, convention="urdf", name=robot.name, unit=robot.unit, base=ch.base, tool=acc @ ch.tool)


def idle_tail(robot: Robot) -> list[int]:
    """The trailing revolute joints (0-based, last first) whose axes pass through the tool point.

    Each turns the tool about the tool point and never moves it, whatever the other joints do: the point
    is fixed in the frame of the last such joint, on its axis, so it is fixed in the frame of the one before.

    >>> import armkit           # the SCARA's wrist; the UR5's flange turn; the Puma's wrist (its tool point is the centre)
    >>> idle_tail(armkit.load("cobra600")), idle_tail(armkit.load("ur5")), idle_tail(armkit.load("puma560"))
    ([3], [5], [5, 4, 3])
    """
    ch = robot.chain
    tol = IDLE_TOL * max(float(robot.reach), 1e-300)
    point = ch.tool[:, 3].copy()          # the tool point in the frame after the last joint's motion
    out = []
    for k in range(robot.n - 1, -1, -1):
        if ch.prismatic[k]:
            break
        local = ch.post[k] @ point        # in joint k's frame: its axis is z through the origin
        if math.hypot(local[0], local[1]) > tol:
            break
        out.append(k)
        point = ch.pre[k] @ local         # in the frame before joint k (its motion does not move the point)
    return out


class Held(Built):
    """Every branch of a position target with some joints held and the rest (1 to 3) solved in closed form.

    Parameters
    ----------
    robot : Robot
    held : mapping of int to float, or sequence of int
        0-based joint index -> value (``fixed=``), or the indices of idle joints held at each target's
        ``q0`` (:func:`position_solver`).
    """

    target_kind = "position"
    pose_only = False
    # no Gauss-Newton touch-up on the full arm (Built.polish_above): solve polishes on the reduced arm instead

    def __init__(self, robot: Robot, held: Mapping[int, float] | list[int]) -> None:
        from . import closed_form

        self.robot = robot
        self.at_start = not isinstance(held, Mapping)
        self.held: dict[int, float] = ({int(k): float(v) for k, v in held.items()} if isinstance(held, Mapping)
                                       else {int(k): 0.0 for k in held})
        self.free = np.array([k for k in range(robot.n) if k not in self.held], dtype=np.int64)
        self.small = reduced(robot, self.held)
        inner = closed_form(self.small) if 1 <= len(self.free) <= MAX_LEFT else None
        if inner is None or inner.target_kind != "position":
            raise LookupError(self.small)
        self.inner = inner
        self.m = inner.m
        self.branch_labels = inner.branch_labels
        names = robot.joint_names
        held_names = ", ".join(names[k] for k in sorted(self.held))
        self.family = f"{inner.family}, {held_names} held"
        if self.at_start:
            self.note = Fielded.of("{joints} held at the start q0 (turning about the tool point, never moving it)",
                                   joints=held_names)
        else:
            self.note = Fielded.of("{joints} held at {values}", joints=held_names,
                                   values=", ".join(f"{self.held[k]:.6g}" for k in sorted(self.held)))
        own = closed_form(robot)     # the joint table of solve_all is kept per robot: use the same DH offsets
        theta = np.zeros(robot.n) if own is None else np.asarray(own.sf.theta, dtype=float)
        eye = np.eye(4)
        z = np.zeros(robot.n)
        self.sf = StandardForm(theta, z, z, z, eye, eye, eye, eye, float(robot.reach), exact=True)

    def solve(self, target: Array, q0phi: Array) -> Raw:
        """Every branch for position targets ``(B, 3)``; ``q0phi`` ``(B, n)`` is ``q0`` plus ``sf.theta``.

        The reduced arm's family solves the joints left (and, on the ideal arm of a calibrated file, its
        branches are polished on the reduced arm, so the held joints never move); the held values go back
        in their places (at the start: each target's ``q0``)."""
        from . import POLISH_ABOVE, _polish

        inner, small = self.inner, self.small
        q0 = q0phi - self.sf.theta
        raw = inner.solve(target, np.ascontiguousarray(q0[:, self.free]) + inner.sf.theta)
        qs = raw.q - inner.sf.theta
        if not inner.sf.exact:
            tol = default_tolerance(self.robot)
            found = verify(small, qs, target[:, None], True, tol, False)
            qs = _polish(small, (qs, *found), target, True, tol, False, ideal=True,
                         above=getattr(inner, "polish_above", POLISH_ABOVE))[0]
        B, m = raw.unreachable.shape
        q = np.repeat(q0[:, None, :], m, axis=1)
        q[:, :, self.free] = qs
        if not self.at_start:
            for k, v in self.held.items():
                q[:, :, k] = v
        note = np.empty((B, m), dtype=object)
        note[...] = self.note        # the sentence itself in every cell (np.full would make it a plain str)
        for b, i in zip(*np.nonzero(raw.note != "")):   # the family's own note (rare) goes first
            note[b, i] = Fielded.of("{note}, {held}", note=raw.note[b, i], held=self.note)
        return Raw(q + self.sf.theta, raw.label, raw.unreachable, raw.why, note, raw.missing)


def _cached(robot: Robot, key: Any, make: Any) -> Any:
    store = robot.cache.setdefault(_CACHE, {})
    if key not in store:
        if len(store) >= 32:
            store.clear()
        store[key] = make()
    return store[key]


def position_solver(robot: Robot) -> Held | None:
    """The solver of a position target on ``robot`` with its idle wrist (:func:`idle_tail`) held at ``q0``, or
    None: the arm's own closed form takes a position, it has no idle joints, or the joints left have no
    position closed form (more than three, or none of their class)."""
    def make() -> Held | None:
        from . import closed_form

        own = closed_form(robot)
        if own is not None and own.target_kind == "position":
            return None
        idle = idle_tail(robot)
        if not idle or not 1 <= robot.n - len(idle) <= MAX_LEFT:   # none idle, all idle (a 1R whose tool is on
            return None                                            # its axis), or too many left
        try:
            return Held(robot, sorted(idle))
        except LookupError:
            return None
    return _cached(robot, "idle", make)  # type: ignore[no-any-return]


def held_solver(robot: Robot, held: Mapping[int, float]) -> Held:
    """The solver of a position target on ``robot`` with the joints ``held`` (0-based index -> value) fixed.

    Raises
    ------
    LookupError
        With the reduced arm when the joints left have no position closed form.
    """
    key = tuple(sorted((int(k), float(v)) for k, v in held.items()))
    return _cached(robot, key, lambda: Held(robot, held))  # type: ignore[no-any-return]
