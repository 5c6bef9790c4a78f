"""The SO-101 as LeRobot drives it: calibration files, servo readings, and a drop-in ``RobotKinematics``.

Importing this module needs NumPy only (no LeRobot, no placo); the kinematics class loads
armkit's model and solvers when it is built. See docs/so101.md, "Calibration and LeRobot".

Servo readings and joint angles
===============================
LeRobot's ``lerobot-calibrate`` writes one JSON object per robot, keyed by motor name, each
motor with ``id``, ``drive_mode``, ``homing_offset``, ``range_min`` and ``range_max``
(LeRobot's ``MotorCalibration``, ``src/lerobot/motors/motors_bus.py``). For the SO-101 follower
and leader the motors are ``shoulder_pan``, ``shoulder_lift``, ``elbow_flex``, ``wrist_flex``,
``wrist_roll`` (LeRobot's "body", normalised in ``degrees`` by default or ``range_m100_100``
with ``use_degrees=False``) and ``gripper`` (always ``range_0_100``).

A *tick* is the STS3215's ``Present_Position``: 0..4095 for one turn. The servo applies the
homing offset itself (``Present_Position = Actual_Position - Homing_Offset``, LeRobot's
``feetech.py``, ``_get_half_turn_homings``), and calibration writes the offset that puts the
pose the user holds ("the middle of the range of motion") at tick 2047. So the ticks are
read *after* the offset, and the offset never enters the formulas below; it is kept for
reference. With ``a = range_min``, ``b = range_max``, ``mid = (a + b) / 2``, ``R = 4095``
(the STS3215's resolution 4096, minus one) and LeRobot's ``MotorsBus._normalize`` /
``_unnormalize``:

==================  ===========================================  =====================================
mode                tick ``t`` -> value ``v``                    clamped to ``[a, b]``?  drive_mode
==================  ===========================================  =====================================
``degrees``         ``v = (t - mid) * 360 / R``                  no                      not applied
``range_m100_100``  ``v = (t_c - a) / (b - a) * 200 - 100``      yes (``t_c``)           ``v -> -v``
``range_0_100``     ``v = (t_c - a) / (b - a) * 100``            yes (``t_c``)           ``v -> 100 - v``
==================  ===========================================  =====================================

The inverse (a value to ticks) clamps the range modes' values to ``[-100, 100]`` /
``[0, 100]`` (as ``_unnormalize`` does) and not the degrees. LeRobot truncates the tick it
writes with ``int()``; :meth:`Calibration.from_q` rounds to the nearest tick instead, so that
ticks -> q -> ticks is exact (``int()`` turns 2047.9999999 into 2047).

Joint angles: LeRobot feeds its ``degrees`` values unchanged, as URDF joint angles in degrees,
to its ``RobotKinematics`` with ``so101_new_calib.urdf`` (``robot_kinematic_processor.py``;
its examples load that file), the URDF whose zero is each joint's calibrated middle. armkit
bundles that same file (``armkit.load("so101")``, TheRobotStudio/SO-ARM100 commit fda892c).
So, for every arm joint ``j``::

    q_j [rad] = sign_j * radians(v_j) + radians(offset_j)     v_j: LeRobot's degrees value

with ``sign_j = +1`` and ``offset_j = 0`` by default (LeRobot's own assumption); give
``signs=`` / ``offsets_deg=`` to :meth:`Calibration.load` when your arm's zero or direction
differs (e.g. an arm calibrated in another pose). A value in a range mode is first turned
back into ticks (undoing ``drive_mode``), so a pose gives the same ``q`` in every mode.

The older URDF (``so101_old_calib.urdf``, zero = arm stretched out horizontally; not bundled)
differs by (armkit's fit of the two files, 5e-6 m): ``q_new = q_old + (0, +90, -90, 0, +2.789) deg``
(:data:`OLD_TO_NEW_OFFSET_DEG`), with its base frame turned by +90 deg about z.

Readings are checked: a tick outside 0..4095 (or a value that maps outside it) raises
:class:`~armkit.errors.ArgumentError`; one outside the calibrated range is mapped as LeRobot
maps it (degrees and q unclamped, range modes clamped to the range's end) with one
:class:`CalibrationRangeWarning` per call naming every motor concerned.
"""

from __future__ import annotations

import json
import math
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from ._lerobot_kinematics import RobotKinematics, _finite
from .errors import ArgumentError, CalibrationInputError, CalibrationRangeWarning
from .locale import N_

__all__ = ["Calibration", "MotorCalibration", "RobotKinematics", "CalibrationRangeWarning", "CalibrationInputError",
           "ARM_MOTORS",
           "GRIPPER", "MODES", "MAX_TICK", "OLD_TO_NEW_OFFSET_DEG", "old_calib_to_new", "new_calib_to_old"]

ARM_MOTORS = ("shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex", "wrist_roll")
"""The SO-101's arm motors, which are the bundled URDF's chain joints, in chain order."""
GRIPPER = "gripper"
MODES = ("ticks", "degrees", "range_m100_100", "range_0_100")
"""Raw ``Present_Position`` ticks, then LeRobot's ``MotorNormMode`` values in lower case."""
MAX_TICK = 4095
"""The STS3215's largest position (resolution 4096); LeRobot's ``max_res``."""
MAX_FILE_BYTES = 1024 ** 2

OLD_TO_NEW_OFFSET_DEG = (0.0, 90.0, -90.0, 0.0, math.degrees(0.0486795))
"""``q_new_calib - q_old_calib`` in degrees for (pan, lift, elbow, wrist_flex, wrist_roll); the roll's
2.789 deg is the ``rpy`` pitch (0.0486795 rad) that ``so101_new_calib.urdf`` adds to the wrist_roll joint."""


def old_calib_to_new(q_old: Any) -> np.ndarray:
    """Joint angles (rad, ``(..., 5)``) of ``so101_old_calib.urdf`` as angles of the bundled ``so101_new_calib``."""
    q = np.asarray(q_old, dtype=float)
    return q + np.radians(OLD_TO_NEW_OFFSET_DEG)


def new_calib_to_old(q_new: Any) -> np.ndarray:
    """The inverse of :func:`old_calib_to_new`."""
    q = np.asarray(q_new, dtype=float)
    return q - np.radians(OLD_TO_NEW_OFFSET_DEG)


@dataclass(frozen=True)
class MotorCalibration:
    """One motor of a LeRobot calibration file (the same fields as LeRobot's ``MotorCalibration``)."""

    id: int
    drive_mode: int
    homing_offset: int
    range_min: int
    range_max: int

    @property
    def mid(self) -> float:
        """The middle of the calibrated range, LeRobot's zero of the degrees mode (ticks)."""
        return (self.range_min + self.range_max) / 2

    @property
    def span(self) -> int:
        return self.range_max - self.range_min


_FIELDS = ("id", "drive_mode", "homing_offset", "range_min", "range_max")


def _bad(template: str, **fields: Any) -> CalibrationInputError:
    """A file error; ``template`` starts with ``calibration file {source}:`` and is marked ``N_`` where written."""
    return CalibrationInputError(template, **{k: (v[:200] if isinstance(v, str) else v) for k, v in fields.items()})


def _motor(source: str, name: str, entry: Any) -> MotorCalibration:
    if not isinstance(entry, dict):
        raise _bad(N_("calibration file {source}: motor {name!r} must be an object with the fields {fields}; got "
                      "{kind}"), source=source, name=name, fields=", ".join(_FIELDS), kind=type(entry).__name__)
    values = {}
    for key in _FIELDS:
        if key not in entry:
            raise _bad(N_("calibration file {source}: motor {name!r}: missing field {key!r} (a LeRobot calibration "
                          "has {fields})"), source=source, name=name, key=key, fields=", ".join(_FIELDS))
        v = entry[key]
        if isinstance(v, bool) or not isinstance(v, int):
            raise _bad(N_("calibration file {source}: motor {name!r}: field {key!r} must be an integer, got {value}"),
                       source=source, name=name, key=key, value=repr(v)[:100])
        values[key] = v
    extra = sorted(set(entry) - set(_FIELDS))
    if extra:
        raise _bad(N_("calibration file {source}: motor {name!r}: unknown field {key!r} (the fields are {fields})"),
                   source=source, name=name, key=extra[0], fields=", ".join(_FIELDS))
    if values["drive_mode"] not in (0, 1):
        raise _bad(N_("calibration file {source}: motor {name!r}: field 'drive_mode' must be 0 or 1, got {value}"),
                   source=source, name=name, value=values["drive_mode"])
    for key in ("range_min", "range_max"):
        if not 0 <= values[key] <= MAX_TICK:
            raise _bad(N_("calibration file {source}: motor {name!r}: field {key!r} must be a tick in 0..{top}, got "
                          "{value}"), source=source, name=name, key=key, top=MAX_TICK, value=values[key])
    if values["range_min"] >= values["range_max"]:
        raise _bad(N_("calibration file {source}: motor {name!r}: range_min ({low}) must be less than range_max "
                      "({high})"), source=source, name=name, low=values["range_min"], high=values["range_max"])
    return MotorCalibration(**values)


def _mode(mode: Any, what: str = "mode") -> str:
    if not isinstance(mode, str) or mode.lower() not in MODES:
        raise ArgumentError.of("{what} must be one of {names}; got {value}", what=what, names=", ".join(MODES),
                               value=repr(mode)[:200])
    return mode.lower()


def _fmt(x: np.ndarray) -> str:
    flat = np.ravel(x)
    shown = ", ".join(f"{v:g}" for v in flat[:3])
    return shown + (f" (and {flat.size - 3} more)" if flat.size > 3 else "")


class Calibration:
    """A LeRobot calibration of an SO-101 (follower or leader): servo readings <-> the bundled URDF's angles.

    Parameters
    ----------
    motors : mapping of str to MotorCalibration
        In the file's order; the five arm motors are required, ``gripper`` is optional.
    source : str
        Where it came from (the file), for messages.
    signs, offsets_deg : mapping of str to float, optional
        Per arm motor: ``q = sign * radians(degrees value) + radians(offset)``; default +1 and 0
        (LeRobot's own mapping onto ``so101_new_calib.urdf``).

    Examples
    --------
    >>> cal = Calibration.load("examples/so101_calibration.json")      # doctest: +SKIP
    >>> cal.to_q([2048, 2048, 2048, 2048, 2048, 2048], mode="ticks")    # doctest: +SKIP
    """

    def __init__(self, motors: Mapping[str, MotorCalibration], source: str = "<dict>",
                 signs: Mapping[str, float] | None = None, offsets_deg: Mapping[str, float] | None = None):
        self.source = str(source)
        self.motors: dict[str, MotorCalibration] = dict(motors)
        missing = [m for m in ARM_MOTORS if m not in self.motors]
        if missing:
            raise _bad(N_("calibration file {source}: no motor {name!r}; an SO-101 calibration has the motors "
                          "{names}"), source=self.source, name=missing[0], names=", ".join(ARM_MOTORS + (GRIPPER,)))
        unknown = [m for m in self.motors if m not in ARM_MOTORS + (GRIPPER,)]
        if unknown:
            raise _bad(N_("calibration file {source}: unknown motor {name!r}; an SO-101 calibration has the motors "
                          "{names}"), source=self.source, name=unknown[0], names=", ".join(ARM_MOTORS + (GRIPPER,)))
        ids = [c.id for c in self.motors.values()]
        if len(set(ids)) != len(ids):
            dup = next(i for i in ids if ids.count(i) > 1)
            raise _bad(N_("calibration file {source}: two motors have the id {id}"), source=self.source, id=dup)
        self.motor_names: tuple[str, ...] = tuple(self.motors)
        self.arm_order: tuple[str, ...] = tuple(m for m in self.motor_names if m != GRIPPER)
        self.signs = self._per_joint(signs, "signs", 1.0)
        self.offsets_deg = self._per_joint(offsets_deg, "offsets_deg", 0.0)
        if any(s not in (1.0, -1.0) for s in self.signs):
            raise ArgumentError.of("signs must be +1 or -1 per joint, got {value}",
                                   value=str(dict(zip(ARM_MOTORS, self.signs))))

    @staticmethod
    def _per_joint(given: Mapping[str, float] | None, what: str, default: float) -> tuple[float, ...]:
        if given is None:
            return (default,) * len(ARM_MOTORS)
        if not isinstance(given, Mapping):
            raise ArgumentError.of("{what} must be a dict {{motor name: value}}, got {value}", what=what,
                                   value=repr(given)[:100])
        bad = [k for k in given if k not in ARM_MOTORS]
        if bad:
            raise ArgumentError.of("{what}: unknown arm motor {name!r}; the arm motors are {names}", what=what,
                                   name=str(bad[0])[:100], names=", ".join(ARM_MOTORS))
        out = tuple(float(_finite(given.get(m, default), f"{what}[{m!r}]")) for m in ARM_MOTORS)
        return out

    # ------------------------------------------------------------------ reading
    @classmethod
    def load(cls, path: str | Path, *, signs: Mapping[str, float] | None = None,
             offsets_deg: Mapping[str, float] | None = None) -> "Calibration":
        """Read a calibration JSON written by ``lerobot-calibrate``
        (``~/.cache/huggingface/lerobot/calibration/robots/so101_follower/<id>.json``).

        Raises :class:`~armkit.errors.ArgumentError` naming the file, the motor and the field.
        """
        source = str(path)
        p = Path(path)
        try:
            if not p.is_file():
                raise _bad(N_("calibration file {source}: not found") if not p.exists()
                           else N_("calibration file {source}: not a file"), source=source)
            size = p.stat().st_size
            if size > MAX_FILE_BYTES:
                raise _bad(N_("calibration file {source}: {size} bytes; a calibration file has a few hundred"),
                           source=source, size=f"{size:,}")
            text = p.read_text(encoding="utf-8")
        except OSError as exc:
            raise _bad(N_("calibration file {source}: cannot read it ({reason})"), source=source,
                       reason=str(exc.strerror or exc)) from None
        except UnicodeDecodeError:
            raise _bad(N_("calibration file {source}: not UTF-8 text (a calibration file is JSON)"),
                       source=source) from None
        try:
            data = json.loads(text)
        except json.JSONDecodeError as exc:
            raise _bad(N_("calibration file {source}: not valid JSON (line {line}, column {column}: {reason})"),
                       source=source, line=exc.lineno, column=exc.colno, reason=exc.msg) from None
        except RecursionError:
            raise _bad(N_("calibration file {source}: nested too deeply to be a calibration file"),
                       source=source) from None
        return cls.from_dict(data, source, signs=signs, offsets_deg=offsets_deg)

    @classmethod
    def from_dict(cls, data: Any, source: str = "<dict>", *, signs: Mapping[str, float] | None = None,
                  offsets_deg: Mapping[str, float] | None = None) -> "Calibration":
        """A calibration from the parsed JSON: ``{motor name: {"id": .., "drive_mode": .., ...}}``."""
        if not isinstance(data, dict):
            raise _bad(N_("calibration file {source}: must be a JSON object {{motor name: {{...}}}}, got {kind}"),
                       source=source, kind=type(data).__name__)
        motors = {str(name): _motor(source, str(name), entry) for name, entry in data.items()}
        return cls(motors, source, signs=signs, offsets_deg=offsets_deg)

    def to_dict(self) -> dict[str, dict[str, int]]:
        """The JSON object LeRobot reads (``json.dump(cal.to_dict(), f, indent=4)`` writes the file back)."""
        return {m: {k: getattr(c, k) for k in _FIELDS} for m, c in self.motors.items()}

    def __repr__(self) -> str:
        return f"Calibration({self.source!r}, motors={list(self.motor_names)})"

    # ------------------------------------------------------------------ per-motor formulas (LeRobot's)
    def normalize(self, motor: str, ticks: Any, mode: str) -> np.ndarray:
        """LeRobot's ``MotorsBus._normalize`` of one motor: ticks -> ``mode`` value (no checks, no warning)."""
        c = self.motors[motor]
        t = np.asarray(ticks, dtype=float)
        mode = _mode(mode)
        if mode == "ticks":
            return t
        if mode == "degrees":                          # unclamped, drive_mode not applied
            return (t - c.mid) * 360.0 / MAX_TICK
        tc = np.clip(t, c.range_min, c.range_max)
        if mode == "range_m100_100":
            v = (tc - c.range_min) / c.span * 200.0 - 100.0
            return -v if c.drive_mode else v
        v = (tc - c.range_min) / c.span * 100.0
        return 100.0 - v if c.drive_mode else v

    def unnormalize(self, motor: str, values: Any, mode: str) -> np.ndarray:
        """LeRobot's ``MotorsBus._unnormalize`` of one motor: ``mode`` value -> ticks, as real numbers (LeRobot
        then truncates with ``int()``)."""
        c = self.motors[motor]
        v = np.asarray(values, dtype=float)
        mode = _mode(mode)
        if mode == "ticks":
            return v
        if mode == "degrees":
            return v * MAX_TICK / 360.0 + c.mid
        if mode == "range_m100_100":
            v = np.clip(-v if c.drive_mode else v, -100.0, 100.0)
            return (v + 100.0) / 200.0 * c.span + c.range_min
        v = np.clip(100.0 - v if c.drive_mode else v, 0.0, 100.0)
        return v / 100.0 * c.span + c.range_min

    # ------------------------------------------------------------------ readings -> q
    def _modes(self, mode: Any, gripper_mode: Any) -> tuple[str, str]:
        m = _mode(mode)
        g = (m if m == "ticks" else "range_0_100") if gripper_mode is None else _mode(gripper_mode, "gripper_mode")
        return m, g

    def _columns(self, values: Any) -> dict[str, np.ndarray]:
        """``values`` (dict or array in the file's motor order) as {motor: array of the leading shape}."""
        if isinstance(values, Mapping):
            cols: dict[str, np.ndarray] = {}
            for key, v in values.items():
                name = key[:-4] if isinstance(key, str) and key.endswith(".pos") else key
                if name not in self.motors:
                    raise ArgumentError.of("unknown motor {name!r}; the motors of {source} are {names}",
                                           name=str(key)[:100], source=self.source, names=", ".join(self.motor_names))
                cols[name] = _finite(v, str(name))
            missing = [m for m in ARM_MOTORS if m not in cols]
            if missing:
                raise ArgumentError.of("no value for the motor {name!r}; give every arm motor: {names}",
                                       name=missing[0], names=", ".join(ARM_MOTORS))
            try:
                shape = np.broadcast_shapes(*(c.shape for c in cols.values()))
            except ValueError:
                raise ArgumentError.of("the motors' values have shapes that do not broadcast together: {shapes}",
                                       shapes=", ".join(f"{k} {c.shape}" for k, c in cols.items())) from None
            return {k: np.broadcast_to(c, shape) for k, c in cols.items()}
        a = _finite(values, "values")
        n_all, n_arm = len(self.motor_names), len(self.arm_order)
        if a.ndim == 0 or a.shape[-1] not in (n_all, n_arm):
            raise ArgumentError.of(
                N_("values must be a dict {{motor name: value}} or an array (..., {n}) in the file's motor order "
                   "({names}) or (..., {n_arm}) without the gripper; got shape {shape}") if n_arm != n_all else
                N_("values must be a dict {{motor name: value}} or an array (..., {n}) in the file's motor order "
                   "({names}); got shape {shape}"),
                n=n_all, names=", ".join(self.motor_names), n_arm=n_arm, shape=a.shape)
        names = self.motor_names if a.shape[-1] == n_all else self.arm_order
        return {m: a[..., i] for i, m in enumerate(names)}

    def _check_ticks(self, ticks: Mapping[str, np.ndarray], modes: Mapping[str, str], given: str) -> None:
        """ArgumentError for a tick outside 0..4095 (a reading given in ticks: exactly; a tick derived from
        another unit: after rounding to the nearest tick)."""
        for m, t in ticks.items():
            raw = modes[m] == "ticks" and given == "reading"
            slack = 0.0 if raw else 0.5
            bad = (t < -slack) | (t > MAX_TICK + slack)
            if not np.any(bad):
                continue
            if raw:
                raise CalibrationInputError(
                    N_("{motor}: reading {value} is outside 0..{top}, the STS3215's positions (a value above 32767 is "
                       "a negative reading in sign-magnitude; LeRobot configures the servos so that they read 0..{top})"),
                    motor=m, value=_fmt(t[bad]), top=MAX_TICK)
            if given == "q":
                raise CalibrationInputError(N_("{motor}: the joint angle would be tick {value}, outside 0..{top} (the "
                                               "STS3215's positions)"), motor=m, value=_fmt(np.rint(t[bad])), top=MAX_TICK)
            raise CalibrationInputError(N_("{motor}: the {mode} value would be tick {value}, outside 0..{top} (the "
                                           "STS3215's positions)"), motor=m, mode=modes[m], value=_fmt(np.rint(t[bad])),
                                        top=MAX_TICK)

    def _range_notes(self, ticks: Mapping[str, np.ndarray], modes: Mapping[str, str],
                     values: Mapping[str, np.ndarray] | None = None) -> list[tuple[str, dict[str, Any]]]:
        """One note (a template and its fields) per motor whose tick lies outside its calibrated range (or, given ``values`` in a range
        mode, whose value lies outside -100..100 / 0..100)."""
        notes = []
        for m, t in ticks.items():
            c, mode = self.motors[m], modes[m]
            if values is not None and mode.startswith("range"):
                v = values[m]
                lo = -100.0 if mode == "range_m100_100" else 0.0
                out = (v < lo) | (v > 100.0)
                if np.any(out):
                    notes.append((N_("{motor} value {value} (mode {mode} covers {low}..100; clamped to the end, as "
                                     "LeRobot's _unnormalize does)"), dict(motor=m, value=_fmt(v[out]), mode=mode,
                                                                            low=f"{lo:g}")))
                continue
            out = (t < c.range_min - 1e-9) | (t > c.range_max + 1e-9)
            if np.any(out):
                far = np.max(np.maximum(c.range_min - t[out], t[out] - c.range_max))
                fields: dict[str, Any] = dict(motor=m, value=_fmt(np.rint(t[out])), low=c.range_min, high=c.range_max)
                if mode.startswith("range"):
                    text = (N_("{motor} at tick {value} (calibrated {low}..{high}; clamped to the range's end, as "
                               "LeRobot's range modes do; far outside: did the reading wrap at 4096, or is the "
                               "calibration stale?)") if far > 512 else
                            N_("{motor} at tick {value} (calibrated {low}..{high}; clamped to the range's end, as "
                               "LeRobot's range modes do)"))
                else:
                    text = (N_("{motor} at tick {value} (calibrated {low}..{high}; mapped without clamping, as "
                               "LeRobot's degrees mode does; far outside: did the reading wrap at 4096, or is the "
                               "calibration stale?)") if far > 512 else
                            N_("{motor} at tick {value} (calibrated {low}..{high}; mapped without clamping, as "
                               "LeRobot's degrees mode does)"))
                notes.append((text, fields))
        return notes

    def _warn(self, notes: list[tuple[str, dict[str, Any]]], level: int) -> None:
        """One :class:`CalibrationRangeWarning` naming every note; the warning carries ``template``, ``fields``
        and ``notes`` (templates and fields), for a front end to show it in the user's language."""
        if notes:
            head = N_("outside the calibrated range of {source}: {notes}")
            text = "; ".join(t.format(**f) for t, f in notes)
            w = CalibrationRangeWarning(head.format(source=self.source, notes=text))
            w.template, w.fields, w.notes = head, {"source": self.source}, notes  # type: ignore[attr-defined]
            warnings.warn(w, stacklevel=level + 1)

    def _to_ticks(self, values: Any, mode: str, gripper_mode: str | None
                  ) -> tuple[dict[str, np.ndarray], list[tuple[str, dict[str, Any]]]]:
        m, g = self._modes(mode, gripper_mode)
        cols = self._columns(values)
        modes = {name: (g if name == GRIPPER else m) for name in cols}
        ticks = {name: self.unnormalize(name, v, modes[name]) for name, v in cols.items()}
        self._check_ticks(ticks, modes, "reading")
        return ticks, self._range_notes(ticks, modes, cols)

    def to_ticks(self, values: Any, mode: str, *, gripper_mode: str | None = None) -> dict[str, np.ndarray]:
        """Readings in ``mode`` as ticks (real numbers) per motor, checked and warned about as in :meth:`to_q`."""
        ticks, notes = self._to_ticks(values, mode, gripper_mode)
        self._warn(notes, 2)
        return ticks

    def to_q(self, values: Any, mode: str, *, gripper_mode: str | None = None,
             with_gripper: bool = False) -> np.ndarray:
        """Servo readings -> the bundled URDF's arm joint angles ``q`` (rad).

        Parameters
        ----------
        values : dict or array_like
            ``{motor name: value}`` (LeRobot's ``"shoulder_pan.pos"`` keys work too; values may be
            arrays of one shape) or an array ``(..., n_motors)`` in the file's motor order
            (``(..., 5)`` without the gripper also works).
        mode : {"ticks", "degrees", "range_m100_100", "range_0_100"}
            The unit of the arm motors' values.
        gripper_mode : str, optional
            The gripper's unit; default ``"ticks"`` with ``mode="ticks"``, else ``"range_0_100"`` (LeRobot's).
        with_gripper : bool
            Append the jaw angle (rad, the URDF's ``gripper`` joint, by the degrees formula) as a 6th value.

        Returns
        -------
        ndarray, shape (..., 5) (or (..., 6) with the jaw)
            ``(shoulder_pan, shoulder_lift, elbow_flex, wrist_flex, wrist_roll)``.

        Raises ArgumentError for a reading outside 0..4095 (or a value that maps outside it); warns once
        (:class:`CalibrationRangeWarning`) about every motor outside its calibrated range.
        """
        ticks, notes = self._to_ticks(values, mode, gripper_mode)
        if with_gripper and GRIPPER not in ticks:
            raise ArgumentError.of(N_("with_gripper=True needs a gripper value") if GRIPPER in self.motors else
                                   N_("with_gripper=True needs a gripper value, and {source} has no gripper motor"),
                                   source=self.source)
        self._warn(notes, 2)
        q = [self.signs[i] * np.radians(self.normalize(m, ticks[m], "degrees")) + math.radians(self.offsets_deg[i])
             for i, m in enumerate(ARM_MOTORS)]
        if with_gripper:
            q.append(np.radians(self.normalize(GRIPPER, ticks[GRIPPER], "degrees")))
        return np.stack(q, axis=-1)

    # ------------------------------------------------------------------ q -> readings
    def from_q(self, q: Any, mode: str, *, gripper_mode: str | None = None,
               gripper: Any = None) -> dict[str, Any]:
        """The bundled URDF's joint angles (rad) -> the motors' values in ``mode``: the inverse of :meth:`to_q`.

        ``q`` is ``(..., 5)``, or ``(..., 6)`` with the jaw angle (rad) last; ``gripper=`` gives the
        gripper's value directly in ``gripper_mode`` instead (default as in :meth:`to_q`). Returns
        ``{motor name: value}`` in the file's motor order: floats (ints for ticks, rounded to the nearest
        tick), arrays of the leading shape for a batch. A joint angle whose tick lies outside 0..4095
        raises ArgumentError; outside the calibrated range it is warned about once, and clamped in the
        range modes as LeRobot's ``_normalize`` does.
        """
        m, g = self._modes(mode, gripper_mode)
        qa = _finite(q, "q")
        if qa.ndim == 0 or qa.shape[-1] not in (5, 6):
            raise ArgumentError.of("q must have 5 joint angles (rad, {names}) or 6 with the jaw last; got shape {shape}",
                                   names=", ".join(ARM_MOTORS), shape=qa.shape)
        jaw = qa.shape[-1] == 6
        if jaw and gripper is not None:
            raise ArgumentError.of("give the jaw angle as q's 6th value or gripper=, not both")
        if (jaw or gripper is not None) and GRIPPER not in self.motors:
            raise ArgumentError.of("{source} has no gripper motor", source=self.source)
        ticks = {name: self.unnormalize(name, (np.degrees(qa[..., i]) - self.offsets_deg[i]) * self.signs[i],
                                        "degrees") for i, name in enumerate(ARM_MOTORS)}
        modes = {name: m for name in ARM_MOTORS}
        notes: list[tuple[str, dict[str, Any]]] = []
        if jaw:
            ticks[GRIPPER] = self.unnormalize(GRIPPER, np.degrees(qa[..., 5]), "degrees")
            modes[GRIPPER] = g
        self._check_ticks(ticks, modes, "q")
        if gripper is not None:
            gv = _finite(gripper, "gripper")
            gm = {GRIPPER: g}
            ticks[GRIPPER] = self.unnormalize(GRIPPER, gv, g)
            modes[GRIPPER] = g
            self._check_ticks({GRIPPER: ticks[GRIPPER]}, gm, "reading")
            notes = self._range_notes({GRIPPER: ticks[GRIPPER]}, gm, {GRIPPER: gv})
        arm = {k: t for k, t in ticks.items() if k != GRIPPER or gripper is None}
        self._warn(self._range_notes(arm, modes) + notes, 2)
        out: dict[str, Any] = {}
        for name in self.motor_names:
            if name not in ticks:
                continue
            mm = modes[name]
            if name == GRIPPER and gripper is not None and mm != "ticks":   # given in its own unit: as given
                v = np.clip(gv, -100.0 if mm == "range_m100_100" else 0.0, 100.0) if mm != "degrees" else gv
            elif mm == "ticks":
                v = np.rint(ticks[name]).astype(np.int64)
            else:
                v = self.normalize(name, ticks[name], mm)
            out[name] = v.item() if np.ndim(v) == 0 else v
        return out
