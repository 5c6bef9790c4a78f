"""Target tracking (as in the CCD graphics assignment): a target moves, the arm follows with one IK solve per frame.

Each frame is warm-started from the previous frame's joints. With the closed form
(``method="analytic"``) the frame takes the branch nearest the previous frame's joints
(largest joint change, angles compared modulo 360°), so the arm does not flip between
elbow-up and elbow-down; its label changes only where the branches meet (a straight
elbow, a target crossing the first joint axis) and the motion stays continuous. Frames whose target is out of reach keep
the closest configuration the solver found and are flagged.

Examples
--------
>>> import armkit
>>> from armkit.viz import track
>>> res = track(armkit.load("planar2"), path="circle", method="analytic", frames=40)
>>> bool(res.reached.all()), len(set(res.branch))
(True, 1)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Optional

import numpy as np
from numpy.typing import NDArray

from ..errors import ArgumentError, LimitError, ShapeError
from ..ik import ik, ik_all
from ..ik.api import _analytic_solver
from ..kinematics import fk
from ..model.robot import Robot

__all__ = ["track", "TrackResult", "target_path", "PATHS", "TRACK_METHODS"]

PATHS = ("random", "circle", "figure8")
TRACK_METHODS = ("ccd", "fabrik", "lm", "newton", "analytic")
RETRY_STARTS = {"ccd": 2, "fabrik": 2}
"""Random starts for a frame the warm start missed where a solution may exist (:func:`_may_exist`): LM and Newton
take their defaults (cheap: compiled); a CCD or FABRIK start costs hundreds of sweeps, and 2 reached as many frames
of the bundled arms' random paths as their 20 (2026-12-05: ``armkit track ur5`` 75 s -> 14 s, the same 190 frames)."""
Array = NDArray[np.float64]


@dataclass(frozen=True)
class TrackResult:
    """Per-frame tracking data.

    Attributes
    ----------
    robot : Robot
    method : str
    path : str
        ``"random"``, ``"circle"``, ``"figure8"`` or the CSV file name.
    q : ndarray, shape (F, n)
        Joint values per frame.
    targets : ndarray, shape (F, 3)
    error : ndarray, shape (F,)
        Distance from the end point to the target (length units).
    reached : ndarray of bool, shape (F,)
        The IK solve met the tolerance (and the limits).
    out_of_reach : ndarray of bool, shape (F,)
        The target lies outside the workspace. Where the arm has a closed form for a position, it decides
        for every method alike (no branch reaches the point); elsewhere the solver's reason
        ``"unreachable"`` (beyond ``robot.reach``).
    branch : ndarray of str, shape (F,)
        The IK branch label per frame (the method name for numeric solvers).
    iterations : ndarray of int, shape (F,)
    tol : float
        Position tolerance used per frame (length units).
    colliding : ndarray of bool, shape (F,), or None
        With a scene: the frames where the arm collides (with the scene, its body or itself).
    checked_against : tuple of str
        What the frames were checked against (``("ground", "torso")`` for the fighter by
        default; ``()``: not checked).
    outside_limits : ndarray of bool, shape (F,)
        Not reached, and the closed form reaches the point only outside the joint limits.
    blocked : ndarray of bool, shape (F,)
        ``method="analytic"`` with a scene: not reached because every solution inside the limits
        collides. The frames not reached and in none of these three were missed by the method (a
        solution exists): ``stats()["frames_not_converged"]``.
    """

    robot: Robot
    method: str
    path: str
    q: Array
    targets: Array
    error: Array
    reached: NDArray[np.bool_]
    out_of_reach: NDArray[np.bool_]
    branch: NDArray[np.str_]
    iterations: NDArray[np.int64]
    tol: float
    colliding: Optional[NDArray[np.bool_]] = None
    checked_against: tuple[str, ...] = ()
    outside_limits: Optional[NDArray[np.bool_]] = None
    blocked: Optional[NDArray[np.bool_]] = None

    def stats(self) -> dict[str, Any]:
        """Tracking statistics: errors over the reached frames, frame counts, branch changes, joint jumps."""
        dq = np.diff(self.q, axis=0)
        rev = ~self.robot.prismatic
        dq[:, rev] = np.angle(np.exp(1j * dq[:, rev]))   # a step across ±180° is the same pose
        jump = float(np.degrees(np.abs(dq[:, rev]).max())) if len(dq) and rev.any() else 0.0
        err = self.error[self.reached]
        none = np.zeros(len(self.q), dtype=bool)
        limits = none if self.outside_limits is None else self.outside_limits
        blocked = none if self.blocked is None else self.blocked
        return {
            "frames": int(len(self.q)),
            "frames_reached": int(self.reached.sum()),
            "frames_out_of_reach": int(self.out_of_reach.sum()),
            "frames_outside_limits": int(limits.sum()),
            "frames_every_solution_collides": int(blocked.sum()),
            "frames_not_converged": int((~self.reached & ~self.out_of_reach & ~limits & ~blocked).sum()),
            "mean_error": float(err.mean()) if len(err) else float("nan"),
            "max_error": float(err.max()) if len(err) else float("nan"),
            "max_error_all_frames": float(self.error.max()),
            "tolerance": self.tol,
            "unit": self.robot.unit,
            "branch_changes": int(np.sum(self.branch[1:] != self.branch[:-1])),
            "largest_joint_step_deg": jump,
            "mean_iterations": float(self.iterations.mean()),
            **({} if self.colliding is None else {"frames_in_collision": int(self.colliding.sum()),
                                                  "checked_against": list(self.checked_against)}),
        }


def _frame_of_motion(robot: Robot) -> tuple[Array, float, float, bool, Array, Array]:
    """(centre, inner radius, outer radius, in a plane, in-plane unit vectors e1, e2) for the paths.

    A planar arm: its plane (x, y). A spatial arm whose workspace is flat (a SCARA's slab,
    :func:`armkit.analysis.workspace.flat_frame`): the middle plane of the slab, ``e1`` towards where the arm
    reaches on average. Any other arm: the workspace's centre and radii."""
    from ..analysis.workspace import flat_frame, workspace

    ws = workspace(robot, samples=20_000, seed=0, scene=False)   # the paths' size: the arm's reach alone
    c = ws.centre.copy()
    if ws.planar:
        c[2] = float(fk(robot, np.zeros(robot.n))[2, 3])
        return c, ws.inner_radius, ws.outer_radius, True, np.array([1.0, 0, 0]), np.array([0, 1.0, 0])
    flat = flat_frame(ws)
    if flat is not None:
        mid, r_in, r_out, _, e1, e2 = flat
        return mid, r_in, r_out, True, e1, e2
    return c, ws.inner_radius, ws.outer_radius, False, np.array([0, 1.0, 0]), np.array([-1.0, 0, 1.0]) / math.sqrt(2)


def target_path(robot: Robot, path: str = "circle", frames: int = 200, seed: Optional[int] = 0) -> Array:
    """Target positions ``(F, 3)`` for :func:`track`.

    ``circle`` and ``figure8`` lie well inside the workspace (between the inner and outer
    boundary radii, in the plane of a planar arm or the middle plane of a flat workspace such as a
    SCARA's, in a tilted plane in front of another spatial arm's shoulder); ``random`` is a smooth
    random curve (a few random sinusoids, in that plane where there is one) that may leave the
    workspace now and then; any other string is a CSV file with columns ``x, y[, z]`` (an optional
    header row), one row per frame.
    """
    if not isinstance(frames, (int, np.integer)) or frames < 2:
        raise ArgumentError.of("frames must be an integer >= 2, got {frames!r}", frames=frames)
    if path not in PATHS:
        return _read_csv(robot, Path(path))
    c, r_in, r_out, planar, e1, e2 = _frame_of_motion(robot)
    r_mid = 0.5 * (r_in + r_out)
    rho = 0.35 * (r_out - r_in)
    radial = e1 if planar else np.array([1.0, 0, 1.0]) / math.sqrt(2)
    p0 = c + r_mid * radial
    if not planar:
        e1, e2 = np.array([0, 1.0, 0]), np.cross(radial, [0, 1.0, 0])
    t = np.linspace(0.0, 2 * math.pi, frames, endpoint=False)
    if path == "circle":
        pts = p0 + rho * (np.cos(t)[:, None] * e1 + np.sin(t)[:, None] * e2)
    elif path == "figure8":
        pts = p0 + rho * (np.sin(t)[:, None] * e1 + (np.sin(t) * np.cos(t))[:, None] * e2 * 1.6)
    else:
        rng = np.random.default_rng(seed)
        amp = 0.62 * r_out
        axes = (e1, e2) if planar else (np.eye(3)[0], np.eye(3)[1], np.eye(3)[2])
        offs = np.zeros((frames, 3))
        for axis in axes:
            k = rng.integers(1, 4, size=3)
            ph = rng.uniform(0, 2 * math.pi, size=3)
            w = rng.uniform(0.3, 1.0, size=3)
            wave = (w[:, None] * np.sin(k[:, None] * t[None] + ph[:, None])).sum(axis=0) / w.sum()
            offs += amp * wave[:, None] * axis[None, :]
        base = c + 0.25 * r_out * e1 if planar else c + 0.3 * r_out * radial
        pts = base + offs
    return pts


MAX_CSV_BYTES = 8 * 1024 ** 2   # a target path file: about 200,000 rows


def _read_csv(robot: Robot, file: Path) -> Array:
    if not file.is_file():
        raise ArgumentError.of("path must be one of {names} or a CSV file; {file!r} is neither", names=", ".join(PATHS),
                               file=str(file))
    if file.stat().st_size > MAX_CSV_BYTES:
        raise LimitError.of("{file}: {size:,} bytes; a target CSV may have at most {limit:,} bytes (about {rows:,} "
                            "rows)", file=file, size=file.stat().st_size, limit=MAX_CSV_BYTES, rows=MAX_CSV_BYTES // 40)
    try:
        try:
            data = np.loadtxt(file, delimiter=",", ndmin=2)
        except ValueError:
            data = np.loadtxt(file, delimiter=",", ndmin=2, skiprows=1)
    except (ValueError, OSError) as exc:
        raise ArgumentError.of("{file}: cannot read target points as CSV numbers ({reason})", file=file,
                               reason=str(exc)) from exc
    if data.shape[1] not in (2, 3) or len(data) < 2:
        raise ShapeError.of("{file}: expected at least 2 rows of 2 (x, y) or 3 (x, y, z) columns, got {shape}", file=file,
                            shape=data.shape)
    if not np.all(np.isfinite(data)):
        raise ShapeError.of("{file}: contains NaN or infinite values", file=file)
    if data.shape[1] == 2:
        z = float(fk(robot, np.zeros(robot.n))[2, 3])
        data = np.column_stack([data, np.full(len(data), z)])
    return data


def _check_analytic(robot: Robot) -> None:
    """``method="analytic"`` follows a point: the arm needs a closed form for a position (its own, a planar arm's
    with the end angle kept, or with a wrist that never moves the point held); else an error naming the methods
    that work, in words that fit the API and the command line alike."""
    from ..analysis.workspace import is_planar
    from ..ik.analytic import closed_form

    own = closed_form(robot)
    if (own is not None and is_planar(robot)) or _analytic_solver(robot, True, None) is not None:
        return   # a planar arm keeps its end angle (phi); any other arm: armkit.ik's rule for a position
    if own is None:
        raise ArgumentError.of("method 'analytic' follows the target with a closed form for a position; robot "
                               "{robot!r} has none; track it with method 'lm', 'newton' or 'ccd'", robot=robot.name)
    raise ArgumentError.of("method 'analytic' follows the target with a closed form for a position; the closed form "
                           "of robot {robot!r} ({family}) needs more than a position; track it with method 'lm', "
                           "'newton' or 'ccd'",
                           robot=robot.name, family=own.family)


def _may_exist(one: Any, settled: bool) -> bool:
    """Whether a frame the warm-started numeric solve ``one`` missed may still have a solution in the limits. Where
    the closed form settles a point's failures (``settled``: :func:`armkit.ik.verdict.settles`), the solver's reason
    is its verdict: "unreachable" or "joint limits" mean none exists. Elsewhere only "unreachable" (beyond
    ``robot.reach``) is a proof."""
    return str(np.asarray(one.reason)) not in (("unreachable", "joint limits") if settled else ("unreachable",))


def _why_missed(robot: Robot, targets: Array, missed: NDArray[np.bool_], tol_p: float,
                analytic_scene: bool) -> Optional[tuple[NDArray[np.bool_], NDArray[np.bool_], NDArray[np.bool_]]]:
    """Why the frames ``missed`` (F,) were not reached, from the closed form's verdict on their points
    (:func:`armkit.ik.verdict.closed_form_verdict`), the same for every method: ``(out of reach, outside the
    limits, blocked)`` (F,) each. ``blocked``: an in-limit solution exists and the frame was missed by the closed
    form itself with a scene, so every such solution collides; the other missed frames with an in-limit solution
    were missed by the method. None where the arm has no exact closed form for a point (a planar arm of three or
    more joints: its end angle is free; the UR5): the solvers' own reasons stand."""
    from ..ik.verdict import LIMITS, UNREACHABLE, closed_form_verdict

    F = len(targets)
    out, limits, blocked = (np.zeros(F, dtype=bool) for _ in range(3))
    idx = np.flatnonzero(missed)
    if idx.size == 0:
        return out, limits, blocked
    v = closed_form_verdict(robot, targets[idx], True, (tol_p, 1e-6))
    if v is None:
        return None
    out[idx] = v.code == UNREACHABLE
    limits[idx] = v.code == LIMITS
    blocked[idx] = (v.code != UNREACHABLE) & (v.code != LIMITS) & analytic_scene
    return out, limits, blocked


def track(robot: Robot, path: str = "random", method: str = "ccd", frames: int = 200, seed: Optional[int] = 0,
          tol: Optional[float] = None, max_iterations: Optional[int] = None, q0: Optional[Any] = None,
          scene: Any = None) -> TrackResult:
    """Follow a moving target with one warm-started IK solve per frame.

    Parameters
    ----------
    robot : Robot
    path : {"random", "circle", "figure8"} or str
        The target's path (see :func:`target_path`), or a CSV file of points.
    method : {"ccd", "fabrik", "lm", "newton", "analytic"}
        IK per frame; ``analytic`` uses the closed form and keeps the branch.
    frames : int
        Number of frames for the generated paths (a CSV gives its own count).
    seed : int, optional
        Seed of the random path.
    tol : float, optional
        Position tolerance per frame (length units); default ``1e-6 × reach``.
    max_iterations : int, optional
        Per-frame iteration cap for the numeric methods.
    q0 : array_like, shape (n,), optional
        Joints before the first frame (default: zeros).
    scene : None, False, armkit.Scene, path of a scene file or "robot"
        The closed form picks per frame a branch that does not collide with it (and the robot's
        body and itself) where one reaches; numeric steps stay local (no random restarts); the
        frames that still collide are flagged in ``colliding``. None (the default): the robot's
        own surroundings (the fighter's torso and ground); False: no check
        (:func:`armkit.collision.resolve_scene`).

    Returns
    -------
    TrackResult
    """
    from ..ik.verdict import settles

    if method not in TRACK_METHODS:
        raise ArgumentError.of("method must be one of {names}, got {method!r}", names=", ".join(TRACK_METHODS),
                               method=method)
    if method == "analytic":
        _check_analytic(robot)
    targets = target_path(robot, path, frames, seed)
    F = len(targets)
    tol_p = float(tol) if tol is not None else 1e-6 * (robot.reach or 1.0)
    from ..analysis.workspace import is_planar

    planar = is_planar(robot)
    q_prev = np.zeros(robot.n) if q0 is None else robot.check_q(q0).astype(float)
    from ..collision import checked_against, resolve_scene

    scene = resolve_scene(robot, scene)            # the one collision rule: None is the robot's own surroundings
    pick_scene = False if scene is None else scene
    Q = np.empty((F, robot.n))
    reached = np.zeros(F, dtype=bool)
    out = np.zeros(F, dtype=bool)
    branch = np.empty(F, dtype=object)
    iters = np.zeros(F, dtype=np.int64)
    label: Optional[str] = None
    settled = method != "analytic" and settles(robot, True)   # a numeric failure's reason is the closed form's
    for k, p in enumerate(targets):
        if method == "analytic":
            kw: dict[str, Any] = {}
            tgt: Array = p
            phis: list[Optional[float]] = [None]
            if planar:
                tgt = p[:2]
                if robot.n >= 3:  # redundant for a point: keep the last end angle, or the nearest one that reaches
                    T = fk(robot, q_prev)
                    phi0 = math.atan2(T[1, 0], T[0, 0])
                    steps = np.radians(np.arange(2.0, 181.0, 2.0))
                    phis = [phi0] + [phi0 + s * d for d in steps for s in (1, -1)]
            for phi in phis:
                kw = {} if phi is None else {"phi": phi}
                res = ik_all(robot, tgt, q0=q_prev, tol=(tol_p, 1e-6), scene=pick_scene, **kw)
                ok = np.asarray(res.success)
                if ok.any():
                    break
            if not ok.any() and len(phis) > 1:
                kw = {"phi": phis[0]}
            names = [str(b) for b in np.asarray(res.branch)]
            if ok.any():
                qa = np.asarray(res.q, dtype=float)
                step = np.where(robot.prismatic, qa - q_prev, np.angle(np.exp(1j * (qa - q_prev))))
                dist = np.where(ok, np.abs(step).max(axis=-1), np.inf)
                pick = int(np.argmin(dist))                     # the branch nearest the last frame: no flips
                q_new = np.asarray(res.q)[pick].astype(float)
                label, reached[k] = names[pick], True
            else:
                one = ik(robot, tgt, q0=q_prev, method="analytic", tol=(tol_p, 1e-6), scene=False, **kw)
                out[k] = str(np.asarray(one.reason)) == "unreachable"
                # stretch towards the target from the last frame (local least squares: no jump to a far branch)
                near = ik(robot, p, q0=q_prev, method="lm", tol=(tol_p, 1e-6), restarts=0, scene=False)
                q_new = np.asarray(near.q, dtype=float)
            branch[k] = label or "analytic"
        else:
            # one local solve per frame from the last frame's joints (collisions flagged below); random starts only
            # where that fails and a solution may exist: not for a target beyond the reach, or one the closed form
            # puts out of reach or outside the limits (armkit.ik.verdict), where LM's 51 starts took 0.1 s a frame
            # for nothing (armkit track planar2 --method lm: 25 s, now 0.9 s)
            one = ik(robot, p, q0=q_prev, method=method, tol=(tol_p, 1e-6),  # type: ignore[arg-type]
                     max_iterations=max_iterations, restarts=0, scene=False)
            spent = int(np.asarray(one.iterations))
            if not bool(np.asarray(one.success)) and _may_exist(one, settled):
                one = ik(robot, p, q0=q_prev, method=method, tol=(tol_p, 1e-6),  # type: ignore[arg-type]
                         max_iterations=max_iterations, restarts=RETRY_STARTS.get(method), scene=False)
                spent += int(np.asarray(one.iterations))
            q_new = np.asarray(one.q, dtype=float)
            reached[k] = bool(np.asarray(one.success))
            out[k] = str(np.asarray(one.reason)) == "unreachable"
            iters[k] = spent
            branch[k] = method
        if not np.all(np.isfinite(q_new)):
            q_new = q_prev
        Q[k] = q_new
        q_prev = q_new
    err = np.linalg.norm(fk(robot, Q)[:, :3, 3] - targets, axis=1)
    why = _why_missed(robot, targets, ~reached, tol_p, method == "analytic" and scene is not None)
    limits = blocked = np.zeros(F, dtype=bool)
    if why is not None:
        out, limits, blocked = why
    name = path if path in PATHS else Path(path).name
    colliding = None
    if scene is not None:   # flag the frames where the arm collides (armkit.collision)
        from ..collision import in_collision

        colliding = in_collision(robot, Q, scene)
    return TrackResult(robot, method, name, Q, targets, err, reached, out, branch.astype(str), iters, tol_p,
                       colliding, checked_against(robot, scene), limits, blocked)
