"""The drop-in ``RobotKinematics`` of :mod:`armkit.lerobot` (LeRobot's class, solved by armkit), and the
check of numeric input (:func:`_finite`) that the calibration half of that module uses too.

Import it from :mod:`armkit.lerobot` (``from armkit.lerobot import RobotKinematics``); this file holds it
so that each file stays short. Importing it needs NumPy only; the class loads armkit's model and
solvers when it is built.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np

from . import _jit_loader
from .errors import ArgumentError, UnreachableError
from .ik import closed_form_family, ik
from .ik.result import IKResult, default_tolerance
from .kinematics import fk
from .model import load
from .spatial import check_transform

__all__ = ["RobotKinematics"]


def _finite(values: Any, what: str) -> np.ndarray:
    """``values`` as a float array; :class:`~armkit.errors.ArgumentError` naming ``what`` for text, non-numbers,
    NaN or infinite values."""
    if isinstance(values, (str, bytes)):
        raise ArgumentError.of("{what} must be numbers, got the string {value}", what=what, value=repr(values)[:100])
    try:
        a = np.asarray(values, dtype=float)
    except (TypeError, ValueError, OverflowError) as exc:
        raise ArgumentError.of("{what} must be numbers, got {value} ({reason})", what=what, value=repr(values)[:150],
                               reason=str(exc)[:100]) from None
    if not np.all(np.isfinite(a)):
        raise ArgumentError.of("{what} holds NaN or infinite values", what=what)
    return a


_STAGES = ("pose", "direction", "pitch", "position")   # the compiled kernel's codes 0-3
_PLAIN = (float, int, np.float64)                         # weights the compiled call takes as they are


def _entry(kernel: Any, ctx: np.ndarray, k: int) -> Any:
    """The compiled ``kernel`` (``teleop_ctx``) itself for the one signature :meth:`RobotKinematics.inverse_kinematics`
    calls it with (``ctx``; float64 C-contiguous 1-D joints of length ``k`` and up, a 4x4 pose; a bool; two float64
    outputs), without the dispatcher's typing of its six arguments on every call; the dispatcher where it has none
    (another back end). The joints and pose are only read, so a read-only array of that type is safe."""
    return _jit_loader.compiled_entry(kernel, ctx, np.empty(k), np.empty((4, 4)), True, np.empty(k), np.empty(9))


def _rotation_angle(Tq: np.ndarray, T: np.ndarray) -> float:
    """The angle (rad) between the rotations of two poses, precise near 0 and near pi."""
    E = Tq[:3, :3].T @ T[:3, :3]
    sin = np.linalg.norm([E[2, 1] - E[1, 2], E[0, 2] - E[2, 0], E[1, 0] - E[0, 1]]) / 2.0
    return math.atan2(float(sin), (float(np.trace(E)) - 1.0) / 2.0)
class RobotKinematics:
    """LeRobot's ``lerobot.model.kinematics.RobotKinematics`` (same constructor, methods and units), solved by
    armkit, and honest about failure.

    Swap ``from lerobot.model.kinematics import RobotKinematics`` for
    ``from armkit.lerobot import RobotKinematics``; nothing else changes (docs/so101.md).

    Parameters
    ----------
    urdf_path : str
        A URDF file (LeRobot's examples use ``so101_new_calib.urdf``) or a bundled armkit robot
        name (``"so101"``).
    target_frame_name : str
        The end-effector link: the chain runs from the URDF's root to it.
    joint_names : list of str, optional
        The order of the joint values in and out (LeRobot passes its motor names, ``gripper``
        included). Joints off the chain (the jaw) are carried through unchanged. Default: the
        chain's joints, then the URDF's other moving joints.
    strict : bool, keyword only
        Raise :class:`~armkit.errors.UnreachableError` when IK cannot put the end-effector at the
        desired position (default False: return the closest configuration, as LeRobot does).

    Attributes
    ----------
    robot : armkit.Robot
    last_result : armkit.IKResult or None
        The last ``inverse_kinematics`` call's result (success, reason, errors, message).
    last_stage : str or None
        What the returned joints meet: ``"pose"`` (the whole 4x4 pose), ``"direction"`` (the position
        and the gripper's approach axis, the rotation about it free), ``"pitch"`` (the position and
        the approach axis turned into the arm's vertical plane), ``"position"``, or ``"failed"``.
    last_pose_error : tuple of float or None
        ``(position error in m, rotation error in rad)`` of the returned joints against the whole
        desired pose, measured by FK.

    Notes
    -----
    With ``orientation_weight == 0`` IK solves the position only. Otherwise, on a 5-joint arm (which
    cannot take an arbitrary orientation) it tries, from ``current_joint_pos``: the whole pose (LM with
    restarts); the position with the desired approach direction (the target's z axis; LM from the
    current joints only, no restarts, to stay fast when it cannot be met); the position with that
    direction's pitch (closed form, the roll kept; arms of the SO-101's shape); the position alone.
    The first that succeeds is returned. The weights only decide whether orientation counts: the position is always
    met exactly when it can be (LeRobot's placo solver takes one weighted step and reports nothing).

    For a 5-joint arm of the SO-101's shape with the Numba back end, one compiled call
    (:func:`armkit.ik.analytic._yaw_pitch3_teleop.teleop_call`) does the same stages in closed form, nearest
    the current joints (the whole pose as a direction solution whose x axis matches too; with
    ``orientation_weight == 0``, the position with the current pitch and roll); where no pose, direction or
    pitch is met, the position alone by Newton steps from the current joints (inside the limits), and LM
    (the NumPy path's last stage) where those do not converge. What it does not settle (a direction within
    1e-4 of vertical, a target on the pan axis, a stretched elbow, any failure) takes the path above, but for
    a desired position beyond the reach measured from the shoulder: no stage can meet it, so the call fails at
    once (``last_stage`` "failed", ``last_result.reason`` "unreachable", the arm stretched towards it) instead of
    trying each stage in NumPy (~0.3 ms instead of ~20 ms).
    Every direction start is polished as the batched ``armkit.ik(..., direction=)`` polishes it, so a call
    gives the same joints as that path (giving up slow starts early made a sustained loop faster, but 4 in
    1,000 steps then jumped to another solution 107-122 deg away on one joint). docs/lerobot.md has the timings.
    """

    def __init__(self, urdf_path: str, target_frame_name: str = "gripper_frame_link",
                 joint_names: list[str] | None = None, *, strict: bool = False):
        if not isinstance(target_frame_name, str):
            raise ArgumentError.of("target_frame_name must be a link name, got {value}",
                                   value=repr(target_frame_name)[:100])
        self.urdf_path = str(urdf_path)
        self.target_frame_name = target_frame_name
        self.strict = bool(strict)
        with warnings.catch_warnings():   # a URDF copied without its meshes: kinematics need none
            warnings.filterwarnings("ignore", message=r".*mesh file\(s\) not found")
            self.robot = load(urdf_path, tip=target_frame_name)
        chain = tuple(self.robot.joint_names)
        known = chain + tuple(self.robot.ignored_joints)
        if joint_names is None:
            names = list(known)
        else:
            if isinstance(joint_names, str):
                raise ArgumentError.of("joint_names must be a list of joint names, got the string {value}",
                                       value=repr(joint_names)[:100])
            names = [str(n) for n in joint_names]
            unknown = [n for n in names if n not in known]
            if unknown:
                raise ArgumentError.of("joint_names: no moving joint {name!r} in {path}; its joints are {names}",
                                       name=unknown[0][:100], path=self.urdf_path, names=", ".join(known))
            missing = [n for n in chain if n not in names]
            if missing:
                raise ArgumentError.of("joint_names lacks {name!r}, a joint of the chain to {frame!r} ({names})",
                                       name=missing[0], frame=target_frame_name, names=", ".join(chain))
            if len(set(names)) != len(names):
                raise ArgumentError.of("joint_names names a joint twice: {names}", names=str(names)[:300])
        self.joint_names = names
        self._index = np.array([names.index(n) for n in chain], dtype=np.int64)
        self._k = len(names)
        self._last_result: Any = None
        self._fast_answer: tuple[np.ndarray, str] | None = None   # (info, stage): last_result, built when read
        self._pose_error: Any = None    # a tuple, or the compiled call's info (its first two values)
        self.last_stage: str | None = None

        self._pitch = closed_form_family(self.robot) == "yaw-pitch3"
        if self._pitch:
            self._pan_point = fk(self.robot, np.zeros(self.robot.n), link=self.robot.links[1].name)[:3, 3]

        self._tol = default_tolerance(self.robot)
        self._ctx: np.ndarray | None = None    # the compiled call's constants (geometry, tolerances, indices)
        self._teleop: Any = None               # and the call itself, while the Numba back end serves
        self._numpy = False                    # whether the last call took the NumPy path (benchmarks count them)
        self._info = np.empty(9)               # the compiled call's report, rewritten by each call it answers (read
                                               # only through last_result / last_pose_error, which each call resets)

    @property
    def last_result(self) -> Any:
        """The last ``inverse_kinematics`` call's :class:`~armkit.IKResult` (None before the first call)."""
        if self._last_result is None and self._fast_answer is not None:
            from .ik.analytic.yaw_pitch3 import branch_label

            info, stage = self._fast_answer
            err = {"pose": info[1], "direction": info[2], "pitch": info[2]}.get(stage, 0.0)
            self._last_result = IKResult(q=info[4:9].copy(), success=np.array(True),
                                         position_error=np.float64(info[0]),
                                         rotation_error=np.float64(err), iterations=np.int64(0),
                                         branch=np.array(branch_label(int(info[3])), dtype=object),
                                         within_limits=np.array(True), reason=np.str_("converged"),
                                         message=np.array("", dtype=object))
        return self._last_result

    @last_result.setter
    def last_result(self, value: Any) -> None:
        self._last_result, self._fast_answer = value, None

    @property
    def last_pose_error(self) -> tuple[float, float] | None:
        """``(position error in m, rotation error in rad)`` of the last answer against the whole desired pose."""
        e = self._pose_error
        if isinstance(e, np.ndarray):
            e = self._pose_error = (float(e[0]), float(e[1]))
        return e

    @last_pose_error.setter
    def last_pose_error(self, value: tuple[float, float] | None) -> None:
        self._pose_error = value

    def __repr__(self) -> str:
        return (f"RobotKinematics({self.urdf_path!r}, target_frame_name={self.target_frame_name!r}, "
                f"joint_names={self.joint_names!r}, strict={self.strict})")

    def _chain_q(self, joint_pos_deg: Any, what: str) -> np.ndarray:
        a = _finite(joint_pos_deg, what)
        if a.ndim == 0 or a.shape[-1] < len(self.joint_names):
            raise ArgumentError.of("{what} must hold at least {n} values (degrees, in the order {names}); got shape "
                                   "{shape}", what=what, n=len(self.joint_names), names=", ".join(self.joint_names),
                                   shape=a.shape)
        return np.radians(a[..., self._index])

    def forward_kinematics(self, joint_pos_deg: Any) -> np.ndarray:
        """The 4x4 pose of ``target_frame_name`` in the URDF's root frame (metres) for joint values in degrees.

        Extra values beyond ``joint_names`` are ignored, as LeRobot does; ``(..., k)`` input gives ``(..., 4, 4)``.
        """
        return np.asarray(fk(self.robot, self._chain_q(joint_pos_deg, "joint_pos_deg")))

    def inverse_kinematics(self, current_joint_pos: Any, desired_ee_pose: Any, position_weight: float = 1.0,
                           orientation_weight: float = 0.01) -> np.ndarray:
        """Joint values (degrees) that put ``target_frame_name`` at ``desired_ee_pose`` (4x4, metres).

        ``current_joint_pos`` (degrees, in ``joint_names`` order, extra values kept) is the start; the
        answer has its length, with joints off the chain (the jaw) unchanged. See the class notes for
        what is solved, ``last_result`` / ``last_stage`` / ``last_pose_error`` for what was reached.
        """
        call = self._teleop
        if call is None or _jit_loader._ACTIVE is None:
            call = self._compiled_call()
        if call is not None:      # one compiled call; None where the NumPy path must answer (it says why)
            if type(orientation_weight) in _PLAIN and type(position_weight) in _PLAIN \
                    and orientation_weight >= 0 and position_weight >= 0:       # (NaN fails >= 0, inf is caught below)
                cc: np.ndarray | None
                try:
                    cc = np.ascontiguousarray(current_joint_pos, dtype=np.float64)
                    Tc = np.ascontiguousarray(desired_ee_pose, dtype=np.float64)
                except (TypeError, ValueError, OverflowError):
                    cc = Tc = None       # the NumPy path says what is wrong
                if cc is not None and Tc is not None and cc.ndim == 1 and cc.shape[0] >= self._k \
                        and Tc.shape == (4, 4) and orientation_weight != math.inf and position_weight != math.inf:
                    out = np.empty(cc.shape[0])
                    info = self._info
                    code = call(self._ctx, cc, Tc, orientation_weight > 0, out, info)
                    if code >= 0:
                        self._numpy = False
                        stage = _STAGES[code]
                        self._last_result, self._fast_answer = None, (info, stage)
                        self.last_stage, self._pose_error = stage, info
                        return out
                    if code == -3:   # no pose, direction or pitch from here: the position alone, as the NumPy path ends
                        fast = self._position_only(cc, Tc)
                        if fast is not None:
                            return fast

        self._numpy = True
        cur = _finite(current_joint_pos, "current_joint_pos")
        if cur.ndim != 1:
            raise ArgumentError.of("current_joint_pos must be one configuration (a 1-D array), got shape {shape}",
                                   shape=cur.shape)
        q0 = np.clip(self._chain_q(cur, "current_joint_pos"), self.robot.lower, self.robot.upper)
        T = _finite(desired_ee_pose, "desired_ee_pose")
        if T.shape != (4, 4):
            raise ArgumentError.of("desired_ee_pose must be a 4x4 pose, got shape {shape}", shape=T.shape)
        check_transform(T, what="desired_ee_pose")
        for w, name in ((position_weight, "position_weight"), (orientation_weight, "orientation_weight")):
            if isinstance(w, bool) or not isinstance(w, (int, float, np.floating, np.integer)) \
                    or not math.isfinite(w) or w < 0:
                raise ArgumentError.of("{name} must be a finite number >= 0, got {value}", name=name, value=repr(w)[:100])
        p, z = T[:3, 3], T[:3, 2]
        attempts: list[tuple[str, Any]] = []
        if orientation_weight > 0:
            attempts.append(("pose", lambda: ik(self.robot, T, q0, seed=0, check=False)))
            if self.robot.n < 6:
                attempts.append(("direction", lambda: ik(self.robot, p, q0, direction=z, restarts=0)))
                if self._pitch:
                    pitch = self._pitch_of(p, z)
                    if pitch is not None:
                        attempts.append(("pitch", lambda: ik(self.robot, p, q0, pitch=pitch)))
        attempts.append(("position", lambda: ik(self.robot, p, q0)))
        res, stage = None, "failed"
        for name, solve in attempts:
            res = solve()
            if bool(res.success):
                stage = name
                break
        assert res is not None
        self.last_result, self.last_stage = res, stage
        q = np.asarray(res.q, dtype=float)
        Tq = fk(self.robot, q)
        self.last_pose_error = (float(np.linalg.norm(Tq[:3, 3] - p)), _rotation_angle(Tq, T))
        if stage == "failed" and self.strict:
            raise UnreachableError.of("IK found no joint values that put {frame} at ({x:.4f}, {y:.4f}, {z:.4f}) m: "
                                      "{reason}", frame=self.target_frame_name, x=float(p[0]), y=float(p[1]),
                                      z=float(p[2]), reason=str(res.message))
        out = cur.copy()
        out[self._index] = np.degrees(q)
        return out

    def _compiled_call(self) -> Any:
        """The compiled :meth:`inverse_kinematics` (:func:`armkit.ik.analytic._yaw_pitch3_teleop.teleop_ctx`) for a
        5-joint arm of the SO-101's shape while the Numba back end serves, else None. Its constants (geometry,
        tolerances, the chain's indices) are packed once (``self._ctx``); the kernel is kept for the next calls."""
        if not self._pitch:
            return None
        from .ik.analytic.yaw_pitch3 import fast_geometry

        kern: Any = _jit_loader.kernels("ik.analytic._yaw_pitch3_teleop")
        if kern is None:
            return None
        if self._ctx is None:
            g = fast_geometry(self.robot)
            if g is None:
                return None
            from .ik.analytic.yaw_pitch3 import shoulder_reach

            self._ctx = kern.pack_context(g, self._tol, self._index, float(shoulder_reach(self.robot)[-1]))  # type: ignore[index]
        self._teleop = _entry(kern.teleop_ctx, self._ctx, self._k)
        return self._teleop

    def _position_only(self, cur: np.ndarray, T: np.ndarray) -> np.ndarray | None:
        """The last stage of :meth:`inverse_kinematics` alone (the kernel found no pose, direction or pitch): the
        position's closed form nearest the current joints (:func:`armkit.ik.analytic.yaw_pitch3.position_ik`; LM
        where it leaves the target to LM). A target beyond the reach from the shoulder fails here at once: no
        stage can meet its position, so the NumPy path would end in the same failure, ~100x slower."""
        from .ik.analytic.yaw_pitch3 import position_ik

        q0 = np.clip(np.radians(cur[self._index]), self.robot.lower, self.robot.upper)
        p = np.ascontiguousarray(T[:3, 3])
        res = position_ik(self.robot, p, q0)
        self._numpy = res is None
        if res is None:
            res = ik(self.robot, p, q0)
        ok = bool(res.success)
        if not ok and not (res.reason == "unreachable" and str(res.branch) == ""):   # position_ik's failure: beyond
            return None            # the NumPy path says why (and raises in strict mode)      # the shoulder's reach
        q = np.asarray(res.q, dtype=float)
        Tq = fk(self.robot, q)
        self.last_result, self.last_stage = res, "position" if ok else "failed"
        self.last_pose_error = (float(np.linalg.norm(Tq[:3, 3] - p)), _rotation_angle(Tq, T))
        if not ok and self.strict:
            raise UnreachableError.of("IK found no joint values that put {frame} at ({x:.4f}, {y:.4f}, {z:.4f}) m: "
                                      "{reason}", frame=self.target_frame_name, x=float(p[0]), y=float(p[1]),
                                      z=float(p[2]), reason=str(res.message))
        out = cur.copy()
        out[self._index] = np.degrees(q)
        return out

    def _pitch_of(self, p: np.ndarray, z: np.ndarray) -> float | None:
        """The pitch (armkit.ik's ``pitch=``) of direction ``z`` at target ``p``: its angle above the horizontal,
        on the outward side when ``z`` points away from the pan axis; None straight above the pan axis."""
        out = (p - self._pan_point)[:2]
        r = float(np.hypot(*out))
        if r < 1e-9:
            return None
        horizontal = float(z[:2] @ out) / r
        return math.atan2(float(z[2]), horizontal)


RobotKinematics.__module__ = "armkit.lerobot"   # where users import it from (and where docs and pickles name it)
