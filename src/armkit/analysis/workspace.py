r"""Workspace analysis: where the arm's end point can go, sampled by batched forward kinematics.

:func:`workspace` draws uniform random joint vectors inside the joint limits, runs
batched FK, drops the samples whose links enter an :class:`Exclusion` (the ground, a body
box), and summarises the cloud: the outer and inner boundary radii about the shoulder
and the reachable volume (area for a planar arm) with an honest error bar.

Volume estimate
---------------
The end points are binned on a voxel grid of side ``h`` (pixels for a planar arm),
chosen so that an occupied voxel holds about 60 samples on average. Voxels with an
empty face neighbour are *boundary* voxels: the boundary surface passes through them
and each is between 0 and 1 full. The estimate counts them as half full,

.. math:: V = (N_{occ} - \tfrac12 N_{bnd})\,h^d,

and the error bar adds two terms: the discretisation bound
:math:`\tfrac12 N_{bnd} h^d` (the most the half-full assumption can be wrong by) and the
sampling term :math:`|V - V_{1/2}|`, the change of the estimate when only the first half
of the samples is used (voxels that a finite sample missed). The true value lies inside
``volume ± volume_error`` for a well-sampled workspace; the tests check that against the
analytic annulus of ``planar2`` and the spherical shell of ``fighter``.

Examples
--------
>>> import armkit
>>> from armkit.analysis import workspace
>>> ws = workspace(armkit.load("planar2"), samples=50_000, seed=1)
>>> ws.planar, round(ws.outer_radius, 2), round(ws.inner_radius, 2), ws.has_inner_boundary
(True, 1.5, 0.5, True)
>>> abs(ws.volume - 2 * 3.141592653589793) <= ws.volume_error      # annulus pi (1.5**2 - 0.5**2)
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Optional, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._text import Fielded
from ..errors import ArgumentError, ShapeError
from ..kinematics import fk, fk_frames, manipulability as _manipulability
from ..model.axes import joint_axes  # noqa: F401  (the one joint_axes, public here too)
from ..model.robot import Robot

__all__ = ["workspace", "WorkspaceResult", "Exclusion", "joint_axes", "is_planar", "shoulder_point",
           "skeleton", "skeleton_batch"]

Array = NDArray[np.float64]


def skeleton_batch(robot: Robot, frames: np.ndarray) -> np.ndarray:
    """Points of the drawn arm for a batch of configurations: ``(B, m, 3)`` from frames ``(B, n + 1, 4, 4)``.

    The frame origins of :func:`armkit.fk_frames` in order, with the corner of a DH row
    that has both an offset ``d`` and a length ``a`` (so that a link is drawn along the
    metal, not across the corner), and the last link's end before the tool transform.
    ``m`` is the same for every configuration (no points are dropped).
    """
    n = robot.n
    frames = np.asarray(frames, dtype=float)
    last = frames[:, n] @ np.linalg.inv(robot.tool)
    pts = [frames[:, 0, :3, 3]]
    for k in range(1, n + 1):
        j = robot.joints[k - 1]
        Fk = last if k == n else frames[:, k]
        offset = j.is_prismatic or j.d != 0.0
        if j.a != 0.0 and offset:
            if robot.convention == "standard":      # Tz(d) then Tx(a): corner = end - a x_k
                pts.append(Fk[:, :3, 3] - j.a * Fk[:, :3, 0])
            else:                                    # Tx(a_{k-1}) then Tz(d): corner = start + a x_{k-1}
                pts.append(frames[:, k - 1, :3, 3] + j.a * frames[:, k - 1, :3, 0])
        pts.append(Fk[:, :3, 3])
    if not np.allclose(robot.tool, np.eye(4)):
        pts.append(frames[:, n, :3, 3])
    return np.stack(pts, axis=1)


def skeleton(robot: Robot, frames: np.ndarray) -> np.ndarray:
    """Points of the drawn arm for one configuration, frames ``(n + 1, 4, 4)`` -> ``(m, 3)``, repeats removed."""
    pts = skeleton_batch(robot, np.asarray(frames)[None])[0]
    out = [pts[0]]
    for p in pts[1:]:
        if np.linalg.norm(p - out[-1]) > 1e-12 * max(1.0, robot.reach):
            out.append(p)
    return np.array(out)


def is_planar(robot: Robot) -> bool:
    """True when the arm moves in planes parallel to the world x-y plane.

    That is: every revolute axis is parallel to the world z axis and every prismatic axis is
    perpendicular to it (rotations about z keep both properties for every ``q``).
    """
    _, z = joint_axes(robot)
    dots = np.abs(z[:, 2])
    return bool(np.all(np.where(robot.prismatic, dots < 1e-9, dots > 1 - 1e-9)))


def shoulder_point(robot: Robot) -> Array:
    """The centre about which boundary radii are measured, shape ``(3,)``.

    The foot on joint axis 1 of the common perpendicular with joint axis 2 (the fighter's
    shoulder, 36 mm above the base); the point of axis 1 itself when the two are parallel
    (planar arms) or for a one-joint arm. Rotating joint 1 does not move this point.
    """
    p, z = joint_axes(robot)
    if robot.n == 1 or robot.prismatic[0]:
        return p[0]
    p1, z1 = p[0], z[0]
    p2, z2 = p[1], z[1]
    c = np.cross(z1, z2)
    if np.linalg.norm(c) < 1e-9:
        return p1
    # p1 + s z1 - (p2 + t z2) is perpendicular to both z1 and z2
    A = np.array([[z1 @ z1, -(z1 @ z2)], [z1 @ z2, -(z2 @ z2)]])
    b = np.array([(p2 - p1) @ z1, (p2 - p1) @ z2])
    s, _ = np.linalg.solve(A, b)
    return p1 + s * z1


@dataclass(frozen=True)
class Exclusion:
    """Space the arm may not enter: a ground plane and/or boxes (the robot's body).

    Parameters
    ----------
    ground_z : float, optional
        Every point of the arm must stay at ``z >= ground_z`` (world frame, length units).
    boxes : sequence of (lower, upper) corner pairs, each shape (3,)
        Axis-aligned boxes in the world frame, e.g. the body the arm sits on.
    points_per_link : int
        Points tested along each drawn link segment (both ends included).

    Parts of the arm that no joint moves (a base column along axis 1) are not tested:
    they belong to the body. A sample is dropped when any tested point is inside.
    """

    ground_z: Optional[float] = None
    boxes: tuple = ()
    points_per_link: int = 6

    def __post_init__(self) -> None:
        if self.ground_z is not None and not math.isfinite(float(self.ground_z)):
            raise ArgumentError.of("exclusion ground_z must be a finite number, got {got!r}", got=self.ground_z)
        boxes = []
        for i, box in enumerate(self.boxes):
            try:
                lo, hi = (np.asarray(c, dtype=float) for c in box)
            except (TypeError, ValueError) as exc:
                raise ShapeError.of("exclusion box {i} must be a (lower, upper) pair of 3-vectors, got {box!r}", i=i,
                                    box=box) from exc
            if lo.shape != (3,) or hi.shape != (3,) or not np.all(lo <= hi):
                raise ShapeError.of("exclusion box {i} must be (lower, upper) 3-vectors with lower <= upper, got {box!r}",
                                    i=i, box=box)
            boxes.append((tuple(lo.tolist()), tuple(hi.tolist())))
        object.__setattr__(self, "boxes", tuple(boxes))
        if int(self.points_per_link) < 2:
            raise ArgumentError.of("points_per_link must be at least 2, got {got}", got=self.points_per_link)

    def inside(self, points: Array) -> NDArray[np.bool_]:
        """True where a point ``(..., 3)`` is in the excluded space; shape ``(...)``."""
        bad = np.zeros(points.shape[:-1], dtype=bool)
        if self.ground_z is not None:
            bad |= points[..., 2] < self.ground_z - 1e-12
        for lo, hi in self.boxes:
            bad |= np.all((points > np.asarray(lo)) & (points < np.asarray(hi)), axis=-1)
        return bad

    def describe(self, unit: str) -> str:
        parts = []
        if self.ground_z is not None:
            parts.append(f"ground z >= {self.ground_z:g} {unit}")
        for lo, hi in self.boxes:
            parts.append("box [" + ", ".join(f"{a:g}..{b:g}" for a, b in zip(lo, hi)) + f"] {unit}")
        return "; ".join(parts) or "none"


@dataclass(frozen=True)
class WorkspaceResult:
    """The sampled workspace (see :func:`workspace`).

    Attributes
    ----------
    robot : Robot
    points : ndarray, shape (N, 3)
        End points of the kept samples (length units).
    q : ndarray, shape (N, n)
        Their joint vectors (rad / length units), all inside the limits.
    manipulability : ndarray, shape (N,), or None
        Yoshikawa's measure per sample when asked for.
    centre : ndarray, shape (3,)
        The shoulder point (:func:`shoulder_point`) the radii are measured from.
    outer_radius, inner_radius : float
        Largest and smallest distance of a sample from ``centre`` (in the x-y plane for a
        planar arm). ``has_inner_boundary`` is true when the inner radius exceeds half a voxel.
    volume, volume_error : float
        Reachable volume (area for a planar arm, ``unit**2``) and its error bar.
    voxel_size : float
        Side of the grid cells used for the estimate.
    samples, excluded : int
        Samples drawn, and samples dropped because the arm entered ``exclusion`` or collided.
    checked_against : tuple of str
        What the samples were checked against for collisions (``("ground", "torso")`` for the
        fighter by default; ``()``: not checked).
    """

    robot: Robot
    points: Array
    q: Array
    manipulability: Optional[Array]
    centre: Array
    outer_radius: float
    inner_radius: float
    has_inner_boundary: bool
    volume: float
    volume_error: float
    voxel_size: float
    planar: bool
    samples: int
    excluded: int
    exclusion: Optional[Exclusion] = None
    occupancy: Optional[NDArray[np.bool_]] = field(default=None, repr=False)
    grid_origin: Optional[Array] = field(default=None, repr=False)
    checked_against: tuple[str, ...] = ()

    @property
    def unit(self) -> str:
        return self.robot.unit

    @property
    def measure_name(self) -> str:
        """``"area"`` for a planar arm, ``"volume"`` otherwise."""
        return "area" if self.planar else "volume"

    @property
    def measure_unit(self) -> str:
        return f"{self.unit}²" if self.planar else f"{self.unit}³"

    def summary(self) -> str:
        """One readable line, e.g. for the CLI."""
        s = (f"{self.robot.name}: {len(self.points):,} of {self.samples:,} samples kept; "
             f"outer radius {self.outer_radius:.4g} {self.unit}, ")
        s += (f"inner radius {self.inner_radius:.4g} {self.unit}" if self.has_inner_boundary
              else "no inner boundary (reaches its shoulder)")
        s += f"; {self.measure_name} {format_measure(self.volume, self.volume_error)} {self.measure_unit}"
        return s + (f"; checked against: {', '.join(self.checked_against)}" if self.checked_against else "")


FLAT = 0.5
"""A spatial arm's workspace is *flat* (a SCARA's: a slab as high as its quill's stroke) when its thickness across
its plane is under this fraction of its outer radius (:func:`flat_frame`)."""


def flat_frame(ws: "WorkspaceResult") -> tuple[Array, float, float, Array, Array, Array] | None:
    """The middle plane of a flat workspace, or None (a planar arm's, or one that is not flat: :data:`FLAT`).

    Returns ``(mid, r_in, r_out, normal, e1, e2)``: the point of the slab's middle plane on the axis through the
    centre, the inner and outer radii about that axis in the plane (0.5 % and 99.5 % quantiles of the samples),
    the plane's unit normal (a world axis where it is within 0.999 of one: a SCARA's z), and two unit vectors in
    the plane, ``e1`` towards where the arm reaches on average (a SCARA with limited turns reaches to one side).

    >>> import armkit
    >>> mid, r_in, r_out, normal, e1, e2 = flat_frame(workspace(armkit.load("cobra600"), 20_000, scene=False))
    >>> round(float(mid[2]), 3), normal.tolist()          # the quill at mid-stroke: 0.387 - 0.105 m
    (0.282, [0.0, 0.0, 1.0])
    """
    if ws.planar:
        return None
    c = ws.centre
    d = ws.points - c
    _, _, vt = np.linalg.svd(d - d.mean(axis=0), full_matrices=False)
    normal = vt[2]                                          # the direction of least spread (sampled)
    k = int(np.argmax(np.abs(normal)))
    if abs(normal[k]) > 0.999:                              # a world axis (a SCARA's z): taken exactly
        normal = np.eye(3)[k]
    h = d @ normal
    r_out = ws.outer_radius
    if not r_out > 0.0 or h.max() - h.min() >= FLAT * r_out:
        return None
    mid = c + normal * 0.5 * (h.max() + h.min())            # the middle of the slab, on the axis through c
    inplane = d - h[:, None] * normal[None, :]
    radius = np.linalg.norm(inplane, axis=1)
    ahead = inplane.mean(axis=0)                            # where the arm reaches on average
    e1 = ahead / np.linalg.norm(ahead) if np.linalg.norm(ahead) > 0.1 * r_out else vt[0]
    return mid, float(np.quantile(radius, 0.005)), float(np.quantile(radius, 0.995)), normal, e1, np.cross(normal, e1)


def format_measure(value: float, error: float) -> str:
    """``(2.28 ± 0.17) × 10⁷`` style text for a value with its error bar."""
    e = int(math.floor(math.log10(abs(value)))) if value else 0
    if -2 <= e <= 3:
        return f"{value:.4g} ± {error:.2g}"
    s = 10.0 ** e
    sup = str(e).translate(str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹"))
    return f"({value / s:.3f} ± {error / s:.3f}) × 10{sup}"


def _moving_points(robot: Robot, exclusion: Exclusion, rng: np.random.Generator) -> NDArray[np.intp]:
    """Indices of the link points (see :func:`_link_points`) that some joint moves."""
    probe = robot.random_q(16, rng)
    pts = _link_points(robot, fk_frames(robot, probe), exclusion.points_per_link)
    spread = np.ptp(pts, axis=0).max(axis=-1)
    return np.flatnonzero(spread > 1e-9 * max(robot.reach, 1e-12))


def _link_points(robot: Robot, frames: Array, per_link: int) -> Array:
    sk = skeleton_batch(robot, frames)                       # (B, m, 3)
    t = np.linspace(0.0, 1.0, per_link)[None, :, None, None]  # (1, per_link, 1, 1)
    a, b = sk[:, :-1], sk[:, 1:]                             # (B, m-1, 3)
    pts = a[:, None] + (b - a)[:, None] * t                  # (B, per_link, m-1, 3)
    return pts.reshape(len(sk), -1, 3)


def _occupancy(cells: NDArray[np.intp], shape: tuple[int, ...]) -> NDArray[np.bool_]:
    flat = np.ravel_multi_index(tuple(cells.T), shape)
    return (np.bincount(flat, minlength=int(np.prod(shape))) > 0).reshape(shape)


def _erode(occ: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """Cells whose whole 3x3(x3) neighbourhood is occupied (separable erosion, outside = empty)."""
    out = occ
    for ax in range(occ.ndim):
        p = np.pad(out, [(1, 1) if i == ax else (0, 0) for i in range(occ.ndim)])
        sl = [slice(None)] * occ.ndim
        lo, mid, hi = (tuple(sl[:ax] + [slice(a, a + occ.shape[ax])] + sl[ax + 1:]) for a in (0, 1, 2))
        out = p[lo] & p[mid] & p[hi]
    return out


def _fill_pinholes(occ: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """Mark an empty cell occupied when all its 2d face neighbours are (a sampling gap, not a void)."""
    p = np.pad(occ, 1)
    full = np.ones_like(occ)
    for ax in range(occ.ndim):
        for a in (0, 2):
            sl = tuple(slice(a, a + occ.shape[i]) if i == ax else slice(1, 1 + occ.shape[i]) for i in range(occ.ndim))
            full &= p[sl]
    return occ | full


def _estimate(P: Array, lo: Array, h: float, shape: tuple[int, ...], min_fill: float = 4.0,
              max_levels: int = 3) -> tuple[float, float]:
    """Volume of the region the points ``P`` (N, d) sample, and half its boundary-cell volume.

    Cells whose neighbourhood is fully occupied count as full; boundary cells are split in
    2^d children (as long as they hold enough samples) and the children judged the same way;
    the boundary cells left at the end count as half full, the returned bound being that half.
    """
    d = P.shape[1]
    total = bound = 0.0
    region: NDArray[np.bool_] | None = None
    for level in range(max_levels + 1):
        hl = h / 2 ** level
        shp = tuple(int(v) * 2 ** level for v in shape)
        cells = np.minimum(((P - lo) / hl).astype(np.intp), np.array(shp) - 1)
        flat = np.ravel_multi_index(tuple(cells.T), shp)
        counts = np.bincount(flat, minlength=int(np.prod(shp))).reshape(shp)
        occ = _fill_pinholes(counts > 0)
        interior = _erode(occ)
        bnd = occ & ~interior
        if region is not None:
            interior &= region
            bnd &= region
        total += float(interior.sum()) * hl ** d
        nb = int(bnd.sum())
        fill = counts[bnd].mean() / 2 ** d if nb else 0.0
        if nb == 0 or level == max_levels or fill < min_fill:
            total += 0.5 * nb * hl ** d
            bound += 0.5 * nb * hl ** d
            break
        region = bnd
        for ax in range(d):
            region = np.repeat(region, 2, axis=ax)
    return total, bound


def workspace(robot: Robot, samples: int = 200_000, seed: int | np.random.Generator | None = 0,
              exclusion: Exclusion | None = None, manipulability: bool = False,
              per_voxel: float = 60.0, chunk: int = 250_000, scene: Any = None) -> WorkspaceResult:
    """Sample the reachable workspace of ``robot``.

    Parameters
    ----------
    robot : Robot
    samples : int
        Random joint vectors drawn uniformly inside the joint limits (joints without a
        finite limit use a full turn).
    seed : int or numpy Generator, optional
    exclusion : Exclusion, optional
        Ground plane and/or body boxes the arm's links may not enter.
    manipulability : bool
        Also compute Yoshikawa's manipulability of every kept sample (for colouring).
    per_voxel : float
        Mean samples per occupied voxel the grid is sized for (larger: fewer missed
        voxels, coarser boundary).
    chunk : int
        Samples per FK batch (bounds the memory).
    scene : None, False, armkit.Scene, path of a scene file or "robot"
        Drop the samples where the arm collides with the scene, the robot's body or itself
        (:func:`armkit.collision.in_collision`, the same check as IK). None (the default): the
        robot's own surroundings (the fighter's torso and ground; none for arms whose file has
        no collision keys); False: no check; a scene replaces the robot's ground
        (:func:`armkit.collision.resolve_scene`). ``checked_against`` says which.

    Returns
    -------
    WorkspaceResult
        Its ``volume ± volume_error`` is the area (planar arms) or volume; see the module
        docstring for how the error is made.
    """
    if not isinstance(samples, (int, np.integer)) or samples < 100:
        raise ArgumentError.of("samples must be an integer >= 100, got {samples!r}", samples=samples)
    if exclusion is not None and not isinstance(exclusion, Exclusion):
        raise ArgumentError.of("exclusion must be an armkit.analysis.Exclusion, got {kind}",
                               kind=type(exclusion).__name__)
    from .._limits import check_memory

    # what the result holds (q, points) and the voxel pass needs at once, checked before any allocation
    check_memory(float(samples) * 8.0 * (robot.n + 16 + (1 if manipulability else 0)),
                 Fielded.of("a workspace of {samples:,} samples of {robot!r}", samples=int(samples), robot=robot.name),
                 Fielded.of("use fewer samples (--samples/-n)"))
    checked: tuple[str, ...] = ()
    if scene is not None or getattr(robot, "collision", None) is not None:   # the one collision rule
        from ..collision import checked_against, resolve_scene

        scene = resolve_scene(robot, scene)
        checked = checked_against(robot, scene)
    rng = np.random.default_rng(seed)
    planar = is_planar(robot)
    q = robot.random_q(int(samples), rng)
    moving = _moving_points(robot, exclusion, rng) if exclusion is not None else None
    keep = np.ones(len(q), dtype=bool)
    points = np.empty((len(q), 3))
    for s in range(0, len(q), chunk):
        qs = q[s:s + chunk]
        if exclusion is None:
            points[s:s + chunk] = fk(robot, qs)[:, :3, 3]
        else:
            F = fk_frames(robot, qs)
            points[s:s + chunk] = F[:, -1, :3, 3]
            lp = _link_points(robot, F, exclusion.points_per_link)[:, moving]
            keep[s:s + chunk] = ~exclusion.inside(lp).any(axis=-1)
        if scene is not None:   # the same collision check as IK with a scene (armkit.collision)
            from ..collision import in_collision

            keep[s:s + chunk] &= ~in_collision(robot, qs, scene)
    excluded = int((~keep).sum())
    if excluded == len(q):
        raise ArgumentError.of("every sample of {robot!r} enters the exclusion ({what}); nothing is reachable",
                               robot=robot.name, what=exclusion.describe(robot.unit) if exclusion else
                               Fielded.of("the scene"))
    q, points = q[keep], points[keep]
    centre = shoulder_point(robot)
    dims = [0, 1] if planar else [0, 1, 2]
    rel = points[:, dims] - centre[dims]
    r = np.linalg.norm(rel, axis=1)
    outer, inner = float(r.max()), float(r.min())

    # voxel grid: a coarse pass sizes the cells so that an occupied one holds ~per_voxel samples
    P = points[:, dims]
    lo, hi = P.min(axis=0), P.max(axis=0)
    span = np.maximum(hi - lo, 1e-12 * max(robot.reach, 1.0))
    d = len(dims)
    h0 = float(span.max()) / 32.0
    shape0 = tuple(np.floor(span / h0).astype(int) + 1)
    occ0 = _occupancy(np.minimum(((P - lo) / h0).astype(np.intp), np.array(shape0) - 1), shape0)
    v0 = occ0.sum() * h0 ** d
    h = float((v0 * per_voxel / len(P)) ** (1.0 / d))
    h = min(h, float(span.max()) / 6.0)
    shape = tuple(np.floor(span / h).astype(int) + 1)
    occ = _occupancy(np.minimum(((P - lo) / h).astype(np.intp), np.array(shape) - 1), shape)
    vol, disc = _estimate(P, lo, h, shape)
    half, _ = _estimate(P[: len(P) // 2], lo, h, shape)
    error = disc + abs(vol - half)
    w = None
    if manipulability:     # in chunks: never a (samples, 6, n) Jacobian array
        w = np.empty(len(q))
        for s in range(0, len(q), chunk):
            w[s:s + chunk] = _manipulability(robot, q[s:s + chunk])
    return WorkspaceResult(robot=robot, points=points, q=q, manipulability=w, centre=centre,
                           outer_radius=outer, inner_radius=inner, has_inner_boundary=bool(inner > 0.5 * h),
                           volume=float(vol), volume_error=float(error), voxel_size=h, planar=planar,
                           samples=int(samples), excluded=excluded, exclusion=exclusion,
                           occupancy=occ, grid_origin=lo, checked_against=checked)
