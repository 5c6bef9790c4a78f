r"""Trajectories: joint-space profiles through waypoints and Cartesian lines and arcs.

Joint space (:func:`joint_trajectory`): the arm stops at every waypoint (zero velocity
there) and every joint of a segment starts and finishes together. Profiles of a segment
of duration :math:`T` from :math:`q_a` to :math:`q_b` (:math:`\Delta = q_b - q_a`, :math:`\tau = t/T`):

* ``cubic``: :math:`q = q_a + \Delta (3\tau^2 - 2\tau^3)`; peak speed :math:`1.5\Delta/T`,
  peak acceleration :math:`6\Delta/T^2` (acceleration jumps at the ends);
* ``quintic``: :math:`q = q_a + \Delta (10\tau^3 - 15\tau^4 + 6\tau^5)`; zero velocity and
  acceleration at both ends; peak speed :math:`1.875\Delta/T`, peak acceleration
  :math:`(10/\sqrt 3)\Delta/T^2`;
* ``trapezoid`` (linear segment with parabolic blends): accelerate at :math:`a`, cruise
  at :math:`v`, decelerate; with only a duration the blends take a third of it each.

Time scaling: give ``duration`` (total, shared out in proportion to the largest joint
motion of each segment) or ``durations`` (one per segment), and/or the limits
``qd_max``/``qdd_max``; each segment gets the longest of the asked duration and the
shortest one that keeps every joint within the limits.

Cartesian (:func:`cartesian_path`, :func:`cartesian_line`, :func:`cartesian_arc`,
:func:`cartesian_waypoints` through any number of points with rounded corners): the
path parameter follows a quintic time scaling (rest to rest); ``method="ik"`` solves
:func:`armkit.ik` at every sample starting from the previous solution (the closed-form
branch nearest the previous frame, so the motion stays on one branch), ``method="rate"``
integrates resolved-rate control (:func:`armkit.motion.velocity.resolved_rate`).
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._io import atomic_path
from .._limits import CHUNK, check_memory
from .._text import Fielded
from ..errors import ArgumentError, ShapeError, UnreachableError
from ..ik import ik
from ..kinematics import fk
from ..model.robot import Robot
from ..spatial import axis_angle_to_rotation

__all__ = ["Trajectory", "PROFILES", "profile", "segment_duration", "joint_trajectory", "cartesian_path",
           "cartesian_line", "cartesian_arc", "cartesian_waypoints", "blended_polyline"]

Array = NDArray[np.float64]
PROFILES = ("cubic", "quintic", "trapezoid")


@dataclass(frozen=True)
class Trajectory:
    """A sampled trajectory.

    Attributes
    ----------
    t : ndarray, shape (N,)
        Time (s), increasing from 0.
    q, qd, qdd : ndarray, shape (N, n)
        Joint values, rates and accelerations (rad, rad/s, rad/s^2; length units for prismatic joints).
    positions : ndarray, shape (N, 3) or None
        Tool point (robot length unit) when known.
    targets : ndarray, shape (N, 3) or None
        Desired tool point of a Cartesian path.
    deviation : ndarray, shape (N,) or None
        ``|positions - targets|`` (length units).
    label : str
    """

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    positions: np.ndarray | None = None
    targets: np.ndarray | None = None
    deviation: np.ndarray | None = None
    label: str = ""
    notes: tuple[str, ...] = field(default=())

    def __post_init__(self) -> None:
        for name in ("t", "q", "qd", "qdd", "positions", "targets", "deviation"):
            v = getattr(self, name)
            if v is not None:
                v = np.array(v, dtype=float)
                v.setflags(write=False)
                object.__setattr__(self, name, v)

    def __len__(self) -> int:
        return len(self.t)

    @property
    def duration(self) -> float:
        return float(self.t[-1] - self.t[0])

    def to_csv(self, path: str | Path, joint_names: Sequence[str] | None = None) -> Path:
        """Write ``t, q.., qd.., qdd..`` (and ``x, y, z`` when known) as CSV with a header row."""
        n = self.q.shape[1]
        names = list(joint_names) if joint_names is not None else [f"q{i + 1}" for i in range(n)]
        header = ["t"] + names + [f"{m}_rate" for m in names] + [f"{m}_acc" for m in names]
        cols = [self.t[:, None], self.q, self.qd, self.qdd]
        if self.positions is not None:
            header += ["x", "y", "z"]
            cols.append(self.positions)
        p = Path(path)
        with atomic_path(p, (".csv",), "a CSV file") as tmp, tmp.open("w", newline="") as f:
            w = csv.writer(f)
            w.writerow(header)
            for s in range(0, len(self.t), 10_000):          # row blocks: no second copy of a long trajectory
                for row in np.hstack([c[s:s + 10_000] for c in cols]):
                    w.writerow([f"{v:.10g}" for v in row])
        return p


# ------------------------------------------------------------------------------------------- profiles
def profile(kind: str, tau: ArrayLike, blend: float = 1 / 3) -> tuple[Array, Array, Array]:
    r"""Normalised profile ``s, ds/dtau, d2s/dtau2`` on ``tau`` in [0, 1] (``s`` goes 0 -> 1).

    ``blend`` is the fraction of the time spent accelerating for ``"trapezoid"`` (0 < blend <= 1/2).

    >>> s, v, a = profile("quintic", [0.0, 0.5, 1.0])
    >>> s.tolist(), v.tolist(), a.tolist()
    ([0.0, 0.5, 1.0], [0.0, 1.875, 0.0], [0.0, 0.0, 0.0])
    """
    x = np.clip(np.asarray(tau, dtype=float), 0.0, 1.0)
    if kind == "cubic":
        return 3 * x ** 2 - 2 * x ** 3, 6 * x - 6 * x ** 2, 6 - 12 * x
    if kind == "quintic":
        return (10 * x ** 3 - 15 * x ** 4 + 6 * x ** 5, 30 * x ** 2 - 60 * x ** 3 + 30 * x ** 4,
                60 * x - 180 * x ** 2 + 120 * x ** 3)
    if kind == "trapezoid":
        b = float(blend)
        if not 0 < b <= 0.5:
            raise ArgumentError.of("blend must be in (0, 1/2], got {b}", b=b)
        v = 1.0 / (1.0 - b)              # cruise speed in s per tau
        a = v / b
        s = np.where(x < b, 0.5 * a * x ** 2,
                     np.where(x <= 1 - b, 0.5 * a * b ** 2 + v * (x - b), 1 - 0.5 * a * (1 - x) ** 2))
        sd = np.where(x < b, a * x, np.where(x <= 1 - b, v, a * (1 - x)))
        sdd = np.where(x < b, a, np.where(x <= 1 - b, 0.0, -a))
        return s, sd, sdd
    raise ArgumentError.of("profile must be one of {names}, got {kind!r}", names=PROFILES, kind=kind)


def segment_duration(kind: str, delta: ArrayLike, qd_max: ArrayLike | None = None,
                     qdd_max: ArrayLike | None = None) -> tuple[float, float]:
    """Shortest duration (s) that keeps every joint of a rest-to-rest segment within the limits, and the blend.

    ``delta`` ``(n,)`` is the joint motion; the blend fraction is for ``"trapezoid"`` (1/3 otherwise).

    >>> segment_duration("quintic", [1.0], qd_max=1.0)
    (1.875, 0.3333333333333333)
    """
    d = np.abs(np.asarray(delta, dtype=float))
    v = None if qd_max is None else np.broadcast_to(np.asarray(qd_max, dtype=float), d.shape)
    a = None if qdd_max is None else np.broadcast_to(np.asarray(qdd_max, dtype=float), d.shape)
    for lim, nm in ((v, "qd_max"), (a, "qdd_max")):
        if lim is not None and np.any(lim <= 0):
            raise ArgumentError.of("{name} must be positive, got {got}", name=nm, got=lim)
    if kind in ("cubic", "quintic"):
        kv, ka = (1.5, 6.0) if kind == "cubic" else (1.875, 10 / math.sqrt(3))
        T = 0.0
        if v is not None:
            T = max(T, float(np.max(kv * d / v)))
        if a is not None:
            T = max(T, float(np.max(np.sqrt(ka * d / a))))
        return T, 1 / 3
    if kind != "trapezoid":
        raise ArgumentError.of("profile must be one of {names}, got {kind!r}", names=PROFILES, kind=kind)
    if v is None and a is None:
        return 0.0, 1 / 3
    best_T, best_b = 0.0, 1 / 3
    for j in range(len(d)):
        if d[j] == 0:
            continue
        vj = math.inf if v is None else float(v[j])
        aj = math.inf if a is None else float(a[j])
        if aj == math.inf:                     # speed limit only: the 1/3 blends
            T, b = 1.5 * d[j] / vj, 1 / 3
        elif vj == math.inf or d[j] < vj ** 2 / aj:   # no cruise: a triangle
            T, b = 2 * math.sqrt(d[j] / aj), 0.5
        else:
            T = d[j] / vj + vj / aj
            b = (vj / aj) / T
        if T > best_T:
            best_T, best_b = T, b
    return best_T, best_b


def joint_trajectory(waypoints: ArrayLike, profile_kind: str = "quintic", duration: float | None = None,
                     durations: Sequence[float] | None = None, qd_max: ArrayLike | None = None,
                     qdd_max: ArrayLike | None = None, dt: float = 0.01, robot: Robot | None = None) -> Trajectory:
    """Joint-space trajectory through ``waypoints``, stopping at each.

    Parameters
    ----------
    waypoints : array_like, shape (m, n), m >= 2
        Joint values (rad / length units).
    profile_kind : {"cubic", "quintic", "trapezoid"}
    duration : float, optional
        Total time (s), shared out in proportion to each segment's largest joint motion.
    durations : sequence of float, optional
        One time per segment (s).
    qd_max, qdd_max : float or array_like of shape (n,), optional
        Joint speed and acceleration limits; segments are lengthened to honour them.
    dt : float
        Sample spacing (s); every waypoint is sampled exactly.
    robot : Robot, optional
        Checks the waypoints' shape and limits and fills ``positions``.

    Returns
    -------
    Trajectory

    Examples
    --------
    >>> tr = joint_trajectory([[0.0, 0.0], [1.0, -1.0]], "quintic", duration=2.0, dt=0.5)
    >>> tr.t.tolist(), tr.q[:, 0].round(4).tolist()
    ([0.0, 0.5, 1.0, 1.5, 2.0], [0.0, 0.1035, 0.5, 0.8965, 1.0])
    """
    W = np.asarray(waypoints, dtype=float)
    if W.ndim != 2 or W.shape[0] < 2:
        raise ShapeError.of("waypoints must have shape (m, n) with m >= 2, got {shape}", shape=W.shape)
    if not np.all(np.isfinite(W)):
        raise ShapeError.of("waypoints contain NaN or infinite values")
    if robot is not None:
        robot.check_q(W, "waypoints")
        for i, w in enumerate(W):
            bad = robot.limit_violations(w)
            if bad:
                raise ArgumentError.of("waypoint {i} is outside the joint limits: {joints}", i=i + 1,
                                       joints=_joined(bad, "; "))
    if profile_kind not in PROFILES:
        raise ArgumentError.of("profile must be one of {names}, got {kind!r}", names=PROFILES, kind=profile_kind)
    if not (isinstance(dt, (int, float, np.integer, np.floating)) and 0 < dt < math.inf):
        raise ArgumentError.of("dt must be a positive finite number of seconds, got {dt!r}", dt=dt)
    m = W.shape[0] - 1
    deltas = np.diff(W, axis=0)
    asked = _asked_durations(deltas, duration, durations, qd_max is None and qdd_max is None)
    notes: list[str] = []
    plan = []
    total = 1.0
    for k in range(m):
        T_min, blend = segment_duration(profile_kind, deltas[k], qd_max, qdd_max)
        T = max(float(asked[k]), T_min)
        if T == 0.0:   # a segment with no motion and no time asked
            continue
        if not math.isfinite(T):
            raise ArgumentError.of("segment {k} would take forever at these limits (qd_max={qd_max!r}, qdd_max={qdd_max!r})",
                                   k=k + 1, qd_max=qd_max, qdd_max=qdd_max)
        if T_min > asked[k] > 0:
            notes.append(Fielded.of("segment {k} lengthened from {asked:.3g} s to {minimum:.3g} s to honour the limits",
                                    k=k + 1, asked=float(asked[k]), minimum=T_min))
        if profile_kind == "trapezoid" and qd_max is None and qdd_max is None:
            blend = 1 / 3
        # at least 2 steps per segment, so that the samples hold the mid-segment peak speed
        steps_f = max(2.0, math.ceil(T / dt - 1e-9))
        total += steps_f
        plan.append((k, T, blend, steps_f))
    n = W.shape[1]
    check_memory(total * 8.0 * (3 * n + 5) * 3,
                 Fielded.of("a trajectory of {samples:,.0f} samples ({seconds:.4g} s at dt = {dt:g} s)", samples=total,
                            seconds=sum(p[1] for p in plan), dt=dt),
                 Fielded.of("use a larger dt (--dt), a shorter duration or larger speed/acceleration limits"))
    if not plan:
        raise ArgumentError.of("all waypoints are equal: there is nothing to move")
    t, q, qd, qdd = _sample_segments(W, deltas, plan, profile_kind, dt, notes)
    pos = None
    if robot is not None:     # in chunks: no (N, 4, 4) pose array for a long trajectory
        pos = np.concatenate([fk(robot, q[i:i + CHUNK])[:, :3, 3] for i in range(0, len(q), CHUNK)])
    return Trajectory(t, q, qd, qdd, positions=pos, label=Fielded.of("joint space, {profile}", profile=profile_kind),
                      notes=tuple(notes))


def _joined(parts: Sequence[str], sep: str) -> Fielded:
    """``sep.join(parts)`` that keeps the template and fields of each part (a joint's limit violation), so that the
    whole renders in the user's language."""
    fields: dict[str, Any] = {f"p{i}": p for i, p in enumerate(parts)}
    return Fielded.of(sep.join(f"{{p{i}}}" for i in range(len(parts))), **fields)


def _asked_durations(deltas: Array, duration: float | None, durations: Sequence[float] | None,
                     no_limits: bool) -> Array:
    """Time asked for each of the ``m`` segments (``deltas`` (m, n)); zeros when only limits set it."""
    m = deltas.shape[0]
    if durations is not None:
        asked = np.asarray(durations, dtype=float)
        if asked.shape != (m,) or not np.all((asked > 0) & np.isfinite(asked)):
            raise ArgumentError.of("durations needs {m} positive values (one per segment), got {got}", m=m,
                                   got=list(asked))
        return asked
    if duration is not None:
        if not 0 < duration < math.inf:
            raise ArgumentError.of("duration must be a positive finite number of seconds, got {duration!r}",
                                   duration=duration)
        size = np.max(np.abs(deltas), axis=1)
        return duration * (size / size.sum() if size.sum() > 0 else np.full(m, 1 / m))
    if no_limits:
        raise ArgumentError.of("give a duration, per-segment durations or the limits qd_max/qdd_max")
    return np.zeros(m)


def _sample_segments(W: Array, deltas: Array, plan: list[tuple[int, float, float, float]], profile_kind: str,
                     dt: float, notes: list[str]) -> tuple[Array, Array, Array, Array]:
    """``t, q, qd, qdd`` of the planned segments ``(k, T, blend, steps)``, each waypoint sampled once."""
    t_parts: list[np.ndarray] = []
    q_parts: list[np.ndarray] = []
    qd_parts: list[np.ndarray] = []
    qdd_parts: list[np.ndarray] = []
    t0 = 0.0
    for k, T, blend, steps_f in plan:
        steps = int(steps_f)
        if T / dt < 2 and steps == 2:
            notes.append(Fielded.of("dt = {dt:g} s is longer than half of segment {k} ({T:.3g} s): sampled at its "
                                    "start, middle and end", dt=dt, k=k + 1, T=T))
        tau = np.linspace(0.0, 1.0, steps + 1)
        s, sd, sdd = profile(profile_kind, tau, blend)
        first = 0 if not t_parts else 1
        t_parts.append(t0 + tau[first:] * T)
        q_parts.append(W[k] + s[first:, None] * deltas[k])
        qd_parts.append(sd[first:, None] * deltas[k] / T)
        qdd_parts.append(sdd[first:, None] * deltas[k] / T ** 2)
        t0 += T
    t, q, qd, qdd = (np.concatenate(p) for p in (t_parts, q_parts, qd_parts, qdd_parts))
    return t, q, qd, qdd


# ------------------------------------------------------------------------------------------ Cartesian
def _check_steps(steps: Any, n: int) -> int:
    """``steps`` of a Cartesian path: an integer of at least 2 whose samples fit the memory budget (issue 24).

    With 1 step the path has only its two rest points, so every speed it reports is 0 (a silent wrong value);
    ``steps = 10**8`` reached 3.9 GB before any check.
    """
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)):
        raise ArgumentError.of("steps must be a whole number, got {steps!r}", steps=steps)
    if steps < 2:
        raise ArgumentError.of("steps must be at least 2 (a rest-to-rest path of {samples} sample(s) has no speed to "
                               "report), got {steps}", samples=int(steps) + 1, steps=steps)
    # points, t, q, qd, qdd, positions, targets, deviation and np.gradient's temporaries
    check_memory((int(steps) + 1) * 8.0 * (3 * n + 12) * 3,
                 Fielded.of("a Cartesian path of {samples:,} samples", samples=int(steps) + 1),
                 Fielded.of("ask for fewer --steps"))
    return int(steps)


def _ik_solve(robot: Robot, target: Array, q_prev: Array) -> tuple[Array, bool, str]:
    # the branch nearest the previous sample, collisions or not: a path is continuous; `armkit traj` counts the
    # samples that collide with the robot's surroundings afterwards (armkit.collision.resolve_scene)
    res = ik(robot, target, q0=q_prev, scene=False)
    return np.asarray(res.q, dtype=float), bool(res.success), str(res.message)


def cartesian_path(robot: Robot, points: ArrayLike, q0: ArrayLike | None = None, duration: float = 2.0,
                   method: Literal["ik", "rate"] = "ik", qd_max: ArrayLike | None = None, gain: float = 10.0,
                   label: str = "Cartesian path", speed: float | None = None) -> Trajectory:
    """Follow a sampled Cartesian path of tool points, rest to rest.

    Parameters
    ----------
    robot : Robot
    points : array_like, shape (N, 2) or (N, 3)
        Tool points in order (``(N, 2)`` for planar arms), robot length unit; the samples
        are taken as equally spaced in the path parameter, which follows a quintic time
        scaling over ``duration``.
    q0 : array_like, shape (n,), optional
        Start configuration, or the reference for the first IK (zeros by default).
    duration : float
        Seconds; lengthened where a limit below asks for more.
    method : {"ik", "rate"}
        IK at every sample from the previous solution, or resolved-rate control.
    qd_max : float or array_like, optional
        Joint speed limit: for ``"ik"`` the time is stretched until every joint keeps it;
        for ``"rate"`` the commanded rates are clipped to it.
    gain : float
        Position feedback gain for ``"rate"`` (1/s).
    speed : float, optional
        Tool speed limit (length unit / s) for equally spaced samples: the duration is at
        least :math:`1.875 L / v` (the quintic's peak speed, :math:`L` the path length).

    Returns
    -------
    Trajectory
        With ``targets`` and ``deviation`` (distance from the desired point at each sample).

    Raises
    ------
    UnreachableError
        When IK fails at a sample (the message says which one and why).
    """
    P = np.asarray(points, dtype=float)
    if P.ndim != 2 or P.shape[1] not in (2, 3) or len(P) < 3:
        raise ShapeError.of("points must have shape (N, 2) or (N, 3) with N >= 3 (with 2 the rest-to-rest speeds are "
                            "all 0), got {shape}", shape=P.shape)
    _check_steps(len(P) - 1, robot.n)
    if duration <= 0:
        raise ArgumentError.of("duration must be positive, got {duration}", duration=duration)
    if speed is not None:
        if not speed > 0:
            raise ArgumentError.of("speed must be positive, got {speed}", speed=speed)
        duration = max(duration, 1.875 * float(np.linalg.norm(np.diff(P, axis=0), axis=1).sum()) / speed)
    N = len(P)
    k = P.shape[1]
    u = np.linspace(0.0, 1.0, N)                 # path parameter of each sample
    # time of each sample: invert the quintic scaling s(t/T) = u
    grid = np.linspace(0.0, 1.0, 4001)
    s_grid = profile("quintic", grid)[0]
    t = np.interp(u, s_grid, grid) * duration
    qstart = np.zeros(robot.n) if q0 is None else robot.check_q(q0, "q0").astype(float)
    targets3 = np.hstack([P, np.zeros((N, 1))]) if k == 2 else P
    if method == "ik":
        return _follow_by_ik(robot, P, t, qstart, qd_max, targets3, label)
    if method != "rate":
        raise ArgumentError.of("method must be 'ik' or 'rate', got {method!r}", method=method)
    from .velocity import resolved_rate

    # desired point and velocity: u(t) follows the quintic scaling, x(u) joins the samples
    def path(tt: float) -> tuple[Array, Array]:
        s_, sd_, _ = profile("quintic", tt / duration)
        uu, du = float(s_), float(sd_) / duration
        seg = int(np.clip(np.searchsorted(u, uu, side="right") - 1, 0, N - 2))
        tangent = (P[seg + 1] - P[seg]) / (u[seg + 1] - u[seg])
        return P[seg] + tangent * (uu - u[seg]), tangent * du

    dt = duration / max(N - 1, 1) / 10
    tr = resolved_rate(robot, qstart, path, duration, dt=dt, qd_max=qd_max, gain=gain)
    idx = np.clip(np.round(t / dt).astype(int), 0, len(tr.t) - 1)
    pos = tr.positions[idx]
    dev = np.linalg.norm(pos[:, :k] - P, axis=1)
    return Trajectory(tr.t[idx], tr.q[idx], tr.qd[idx], tr.qdd[idx], positions=pos, targets=targets3,
                      deviation=dev, label=Fielded.of("{path} via resolved rate", terms=("path",), path=label))


def _follow_by_ik(robot: Robot, P: Array, t: Array, qstart: Array, qd_max: ArrayLike | None, targets3: Array,
                  label: str) -> Trajectory:
    """IK at every sample from the previous solution; the clock stretched (uniformly) to keep ``qd_max``."""
    N, k = P.shape
    Q = np.empty((N, robot.n))
    q_prev = qstart
    for i in range(N):
        q_i, ok, msg = _ik_solve(robot, P[i], q_prev)
        if not ok:
            raise UnreachableError.of("sample {i} of {n} at ({point}) {unit}: {reason}", i=i + 1, n=N,
                                      point=", ".join(f"{v:g}" for v in P[i]), unit=robot.unit, reason=msg)
        Q[i] = q_i
        q_prev = q_i
    QD = np.asarray(np.gradient(Q, t, axis=0))
    QD[0] = QD[-1] = 0.0
    notes: tuple[str, ...] = ()
    if qd_max is not None:
        lim = np.broadcast_to(np.asarray(qd_max, dtype=float), (robot.n,))
        if not np.all(lim > 0):
            raise ArgumentError.of("qd_max must be positive, got {qd_max!r}", qd_max=qd_max)
        stretch = float(np.max(np.abs(QD) / lim))
        if stretch > 1.0:           # the path is fixed: a slower clock divides every rate by the same factor
            t, QD = t * stretch, QD / stretch
            notes = (Fielded.of("duration lengthened to {t:.3g} s to keep the joint speed limit", t=float(t[-1])),)
    QDD = np.asarray(np.gradient(QD, t, axis=0))
    pos = fk(robot, Q)[:, :3, 3]
    dev = np.linalg.norm(pos[:, :k] - P, axis=1)
    return Trajectory(t, Q, QD, QDD, positions=pos, targets=targets3, deviation=dev, label=Fielded.of("{path} via IK", terms=("path",), path=label),
                      notes=notes)


def blended_polyline(waypoints: ArrayLike, radius: float = 0.0, shape: Literal["circular", "parabolic"] = "circular",
                     steps: int = 100) -> Array:
    r"""Points along straight segments through ``waypoints``, corners rounded within ``radius`` of each waypoint.

    Parameters
    ----------
    waypoints : array_like, shape (m, 2) or (m, 3)
        Start, interior waypoints, end (length units), ``m >= 2``.
    radius : float
        Blend radius: the path leaves a segment where it comes within ``radius`` of an
        interior waypoint and joins the next one at the same distance (clipped to half of
        each neighbouring segment, so that blends never overlap). 0: sharp corners.
    shape : {"circular", "parabolic"}
        The corner: a circular arc tangent to both segments, or a parabola (quadratic
        Bezier curve with its control point on the waypoint, the path of a constant
        acceleration). Both stay within ``radius`` of the waypoint; the arc comes to
        :math:`r \tan(\varphi/4)` of it, the parabola to :math:`r \sin(\varphi/2)/2`
        (:math:`\varphi` the turning angle).
    steps : int
        The path is returned as ``steps + 1`` points equally spaced in arc length,
        exactly on the first and last waypoint.

    Returns
    -------
    ndarray, shape (steps + 1, 2 or 3)
    """
    W = np.asarray(waypoints, dtype=float)
    if W.ndim != 2 or W.shape[1] not in (2, 3) or len(W) < 2:
        raise ShapeError.of("waypoints must have shape (m, 2) or (m, 3) with m >= 2, got {shape}", shape=W.shape)
    if not np.all(np.isfinite(W)):
        raise ShapeError.of("waypoints contain NaN or infinite values")
    if not radius >= 0:
        raise ArgumentError.of("radius must be zero or positive, got {radius}", radius=radius)
    if shape not in ("circular", "parabolic"):
        raise ArgumentError.of("shape must be 'circular' or 'parabolic', got {shape!r}", shape=shape)
    if steps < 1:
        raise ArgumentError.of("steps must be at least 1, got {steps}", steps=steps)
    keep = np.r_[True, np.linalg.norm(np.diff(W, axis=0), axis=1) > 0]   # repeated points add nothing
    W = W[keep]
    if len(W) < 2:
        raise ArgumentError.of("the waypoints must not all be the same point")
    seg = np.linalg.norm(np.diff(W, axis=0), axis=1)
    pieces, sharp = [W[:1]], []
    for i in range(1, len(W) - 1):
        r = min(radius, 0.5 * seg[i - 1], 0.5 * seg[i])
        pieces.append(_corner(W[i - 1], W[i], W[i + 1], r, shape))
        d_in, d_out = W[i] - W[i - 1], W[i + 1] - W[i]
        turns = float(d_in @ d_out) <= (1 - 1e-12) * seg[i - 1] * seg[i]   # not a point on a straight run
        if len(pieces[-1]) == 1 and turns:     # a sharp corner is a sample (a straight run needs none: equal steps)
            sharp.append(sum(len(p) for p in pieces) - 1)      # index of the waypoint in the dense points
    pieces.append(W[-1:])
    dense = np.concatenate(pieces)
    arc = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(dense, axis=0), axis=1))]
    s = np.linspace(0.0, arc[-1], steps + 1)
    for j in sharp:                          # a sharp corner is a sample: the path goes through the waypoint
        k = int(np.argmin(np.abs(s - arc[j])))
        if 0 < k < steps:
            s[k] = arc[j]
    out = np.column_stack([np.interp(s, arc, dense[:, j]) for j in range(W.shape[1])])
    out[0], out[-1] = W[0], W[-1]
    return out


def _corner(a: Array, c: Array, b: Array, r: float, shape: str, samples: int = 513) -> Array:
    """Points of the rounded corner at ``c`` between segments ``a -> c`` and ``c -> b`` (just ``c`` if sharp)."""
    d_in = (c - a) / np.linalg.norm(c - a)
    d_out = (b - c) / np.linalg.norm(b - c)
    cos_turn = float(np.clip(d_in @ d_out, -1.0, 1.0))
    if r <= 0 or cos_turn > 1 - 1e-12:
        return c[None, :]
    p_in, p_out = c - r * d_in, c + r * d_out          # where the blend leaves and joins the segments
    s = np.linspace(0.0, 1.0, samples)[:, None]
    if shape == "parabolic" or cos_turn < -1 + 1e-9:   # a U-turn has no tangent arc: the parabola
        return (1 - s) ** 2 * p_in + 2 * s * (1 - s) * c + s**2 * p_out
    turn = math.acos(cos_turn)
    R = r / math.tan(turn / 2)                         # tangent length r = R tan(turn / 2)
    normal = d_out - cos_turn * d_in                   # towards the centre, in the plane of the corner
    centre = p_in + R * normal / np.linalg.norm(normal)
    e1 = (p_in - centre) / R
    e2 = d_in                                          # the arc starts moving along d_in
    ang = turn * s
    return centre + R * (np.cos(ang) * e1 + np.sin(ang) * e2)


def cartesian_line(robot: Robot, start: ArrayLike, end: ArrayLike, steps: int = 100, **kwargs: Any) -> Trajectory:
    """Straight line of the tool point from ``start`` to ``end`` (2 or 3 values each), ``steps + 1`` samples.

    Other keywords go to :func:`cartesian_path`. For ``method="rate"`` the arm must
    start on the line: pass ``q0`` (when omitted, IK of ``start`` gives it).
    """
    a, b = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    if a.shape != b.shape or a.shape not in ((2,), (3,)):
        raise ShapeError.of("start and end must both have 2 or 3 values, got {a} and {b}", a=a.shape, b=b.shape)
    steps = _check_steps(steps, robot.n)
    u = np.linspace(0.0, 1.0, steps + 1)[:, None]
    pts = a + u * (b - a)
    kwargs = dict(kwargs)
    if kwargs.get("method", "ik") == "rate" and kwargs.get("q0") is None:
        q, ok, msg = _ik_solve(robot, a, np.zeros(robot.n))
        if not ok:
            raise UnreachableError.of("the start point is not reachable: {reason}", reason=msg)
        kwargs["q0"] = q
    return cartesian_path(robot, pts, label="straight line", **kwargs)


def cartesian_waypoints(robot: Robot, waypoints: ArrayLike, blend: float = 0.0,
                        blend_shape: Literal["circular", "parabolic"] = "circular", steps: int = 100,
                        **kwargs: Any) -> Trajectory:
    """Straight lines of the tool point through any number of waypoints, corners rounded within ``blend``.

    The path (:func:`blended_polyline`) starts exactly on the first waypoint, ends exactly
    on the last, and passes within ``blend`` of every waypoint between (through it when
    ``blend`` is 0; the arm then slows through the corner only as the samples bend). It
    is sampled at ``steps + 1`` points equally spaced in arc length and followed rest to
    rest by :func:`cartesian_path` (other keywords: ``duration``, ``speed``, ``qd_max``,
    ``method``, ``q0``).

    Examples
    --------
    >>> import armkit
    >>> from armkit.motion import cartesian_waypoints
    >>> tr = cartesian_waypoints(armkit.load("planar2"), [[1.2, 0.2], [1.0, 0.8], [0.4, 1.0]], blend=0.1, steps=40)
    >>> tr.targets[0, :2].tolist(), tr.targets[-1, :2].tolist()
    ([1.2, 0.2], [0.4, 1.0])
    """
    W = np.asarray(waypoints, dtype=float)
    steps = _check_steps(steps, robot.n)
    pts = blended_polyline(W, blend, blend_shape, steps)
    kwargs = dict(kwargs)
    if kwargs.get("method", "ik") == "rate" and kwargs.get("q0") is None:
        q, ok, msg = _ik_solve(robot, pts[0], np.zeros(robot.n))
        if not ok:
            raise UnreachableError.of("the start point is not reachable: {reason}", reason=msg)
        kwargs["q0"] = q
    corners = len(W) - 2
    what = "straight line" if corners == 0 else (   # a template and its fields: the label in the user's language
        Fielded.of("{n} waypoints, {shape} blends of {blend}", terms=("shape",), n=len(W), shape=blend_shape,
                   blend=f"{blend:g}") if blend > 0 else Fielded.of("{n} waypoints, sharp corners", n=len(W)))
    return cartesian_path(robot, pts, label=what, **kwargs)


def cartesian_arc(robot: Robot, center: ArrayLike, start: ArrayLike, angle: float,
                  normal: ArrayLike = (0.0, 0.0, 1.0), steps: int = 100, **kwargs: Any) -> Trajectory:
    """Circular arc of the tool point: ``start`` turned about ``center`` by ``angle`` (rad) around ``normal``.

    ``center`` and ``start`` have 2 (planar, in the x-y plane) or 3 values.
    """
    c, p = np.asarray(center, dtype=float), np.asarray(start, dtype=float)
    if c.shape != p.shape or c.shape not in ((2,), (3,)):
        raise ShapeError.of("center and start must both have 2 or 3 values, got {c} and {p}", c=c.shape, p=p.shape)
    k = len(c)
    c3 = np.append(c, 0.0) if k == 2 else c
    p3 = np.append(p, 0.0) if k == 2 else p
    nrm = np.asarray(normal, dtype=float)
    if nrm.shape != (3,) or np.linalg.norm(nrm) == 0:
        raise ShapeError.of("normal must be a non-zero 3-vector, got {normal!r}", normal=normal)
    steps = _check_steps(steps, robot.n)
    u = np.linspace(0.0, 1.0, steps + 1)
    R = axis_angle_to_rotation(nrm / np.linalg.norm(nrm), angle * u)
    pts = c3 + np.einsum("nij,j->ni", R, p3 - c3)
    kwargs = dict(kwargs)
    if kwargs.get("method", "ik") == "rate" and kwargs.get("q0") is None:
        q, ok, msg = _ik_solve(robot, pts[0, :k], np.zeros(robot.n))
        if not ok:
            raise UnreachableError.of("the start point is not reachable: {reason}", reason=msg)
        kwargs["q0"] = q
    return cartesian_path(robot, pts[:, :k], label="arc", **kwargs)
