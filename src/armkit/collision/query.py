"""The public queries :func:`collisions` and :func:`clearance`, batched over configurations.

Which kernel a pair uses is read from :data:`armkit.collision.shapes.KIND_TABLE`: on the Numba
back end every pair of planes, boxes, spheres, capsules and cylinders is compiled
(:mod:`armkit.collision._jit`); without Numba, segments (capsules, balls) meet the other kinds
through the NumPy kernels of :mod:`armkit.collision.kernels`; meshes, and without Numba the
solid-solid pairs, go through coal (imported only then).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._jit_loader import kernels
from .._text import Fielded
from ..kinematics import fk_frames
from ..model.robot import Robot
from . import kernels as K
from .geometry import ArmGeometry, Solid, arm_geometry, robot_collision, robot_scene
from .shapes import KIND_TABLE, Scene, SceneError, Shape

__all__ = ["Collisions", "collisions", "clearance", "in_collision", "colliding_rows", "as_scene", "resolve_scene",
           "checked_against", "checked_note"]

Array = NDArray[np.float64]


@dataclass(frozen=True)
class Collisions:
    """What :func:`collisions` found, for one configuration or a batch ``(...)``.

    Attributes
    ----------
    colliding : ndarray of bool, shape (...)
        True where some checked pair overlaps (signed distance < 0).
    distance : ndarray, shape (...)
        The smallest signed distance over all pairs (robot unit): the clearance when positive,
        minus the deepest penetration when negative; ``inf`` when nothing is checked.
    pairs : tuple of (str, str)
        The checked pairs, arm solid first (``("forearm", "ground")``, ``("forearm", "turret")``).
    distances : ndarray, shape (..., len(pairs))
        Signed distance of every pair.
    closest : ndarray of int, shape (...)
        Index into ``pairs`` of the pair with the smallest distance (-1 when none).
    unit : str
    """

    colliding: NDArray[np.bool_]
    distance: Array
    pairs: tuple[tuple[str, str], ...]
    distances: Array
    closest: NDArray[np.int64]
    unit: str

    @property
    def depth(self) -> Array:
        """Penetration depth of the deepest pair, 0 where nothing collides; shape (...)."""
        return np.maximum(-self.distance, 0.0)

    def colliding_pairs(self, index: Any = ()) -> list[tuple[str, str, float]]:
        """``(solid, other, depth)`` of every overlapping pair of one configuration, deepest first."""
        d = np.asarray(self.distances)[index]
        if d.ndim != 1:
            raise SceneError("colliding_pairs(index) needs the index of one configuration, e.g. res.colliding_pairs(3)")
        order = np.argsort(d, kind="stable")
        return [(self.pairs[k][0], self.pairs[k][1], float(-d[k])) for k in order if d[k] < 0]

    def message(self, index: Any = ()) -> str:
        """A sentence for people: "the forearm hits the ground by 12.3 mm" ("" when clear)."""
        hits = self.colliding_pairs(index)
        if not hits:
            return ""
        a, b, depth = hits[0]
        a, b = a.replace("_", " "), b.replace("_", " ")
        fields = {"a": a, "b": b, "depth": f"{depth:.3g} {self.unit}"}
        if len(hits) > 1:     # a template and its fields: shown in the user's language from the catalogue
            return Fielded.of("the {a} hits the {b} by {depth} ({n} pairs in collision)", terms=("a", "b"),
                              n=len(hits), **fields)
        return Fielded.of("the {a} hits the {b} by {depth}", terms=("a", "b"), **fields)


def as_scene(robot: Robot, scene: Scene | Sequence[Shape] | str | None) -> Scene:
    """``scene`` as a :class:`Scene` in the robot's unit: ``None``/"robot" the robot's own, a path loads a file."""
    if scene is None or (isinstance(scene, str) and scene == "robot"):
        return robot_scene(robot)
    if isinstance(scene, str):
        scene = Scene.load(scene)
    if not isinstance(scene, Scene):
        scene = Scene(scene)
    return scene.in_unit(robot.unit)


def resolve_scene(robot: Robot, scene: Any) -> Scene | None:
    """The one collision rule: what ``scene=`` means for IK, workspaces, paths, the shell and the view.

    * ``None`` (the default): the robot's own surroundings, i.e. its body and its ground from the
      robot file (the fighter's torso and ground; ``docs/scene.md``), when the file has collision
      keys; a robot without them is not checked at all (nothing to check, no cost).
    * ``False`` (the CLI's ``--no-scene``): no collision check.
    * A :class:`Scene`, shapes, a scene file or ``"robot"``: that scene *replaces* the robot's
      ``[[scene]]`` surroundings (its ground); the robot's body (``[[body]]``) and self-collision
      are always checked, since they belong to the arm.

    Returns the scene in the robot's unit, or ``None`` for "no check".
    """
    if scene is False:
        return None
    if scene is None:
        if getattr(robot, "collision", None) is None:
            return None
        return robot_scene(robot)
    if isinstance(scene, Scene) and scene.unit == robot.unit:
        return scene
    return as_scene(robot, scene)


def checked_against(robot: Robot, scene: Scene | None) -> tuple[str, ...]:
    """The names of what a check against ``scene`` (a :func:`resolve_scene` answer) covers.

    The scene's shapes, then the robot's body (``("ground", "torso")`` for the fighter);
    ``("itself",)`` when only self-collision is checked, ``()`` for no check (``scene`` None).
    """
    if scene is None:
        return ()
    names = [s.name or s.kind for s in scene] + [s.name or s.kind for s in robot_collision(robot).body]
    return tuple(dict.fromkeys(names)) or ("itself",)


def checked_note(names: Sequence[str]) -> str:
    """``"checked against: ground, torso"`` (``"not checked for collisions"`` for no names); English."""
    return f"checked against: {', '.join(names)}" if names else "not checked for collisions"


# ------------------------------------------------------------------ solids in the world
def chain_frames(robot: Robot, q: Array) -> Array:
    """:func:`armkit.fk_frames` ``(B, n+1, 4, 4)`` of flat ``q`` ``(B, n)``, plus the flange (frame n without the tool)."""
    frames = fk_frames(robot, q)
    n = robot.n
    if not np.any(np.asarray(robot.tool)[:3, 3]):   # the flange point is the tool point: no copy
        return frames
    out = np.empty((frames.shape[0], n + 2, 4, 4))
    out[:, :n + 1] = frames
    out[:, n + 1] = frames[:, n] @ np.linalg.inv(np.asarray(robot.tool))
    return out


def _world(solid: Solid, frames: Array) -> tuple[str, Any]:
    """The solid in world coordinates: ("seg", (p0, p1, r)) or ("shape", (kind, T, size, shape))."""
    if solid.kind == "segment":
        i, j = solid.ends
        return "seg", (frames[:, i, :3, 3], frames[:, j, :3, 3], solid.size[0])
    T = frames[:, solid.frame] @ solid.local
    swept = KIND_TABLE[solid.kind].swept
    if swept is not None:
        return "seg", swept(T, solid.size)
    return "shape", (solid.kind, T, solid.size, solid.shape)


def _static(shape: Shape) -> tuple[str, Any]:
    swept = KIND_TABLE[shape.kind].swept
    if swept is not None:
        return "seg", swept(shape.pose, shape.size)
    return "shape", (shape.kind, shape.pose, shape.size, shape)


def _box_plane(T: Array, size: Sequence[float], n: Array, off: float) -> Array:
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * (0.5 * np.asarray(size))
    world = np.einsum("...ij,kj->...ki", T[..., :3, :3], corners) + T[..., None, :3, 3]
    return np.min(world @ n, axis=-1) - off


def _distance(a: tuple[str, Any], b: tuple[str, Any], batch: int) -> Array:
    """Signed distance between two world solids, shape (batch,)."""
    if a[0] == "shape" and b[0] == "seg":
        a, b = b, a
    if a[0] == "seg":
        p0, p1, r = a[1]
        if b[0] == "seg":
            q0, q1, r2 = b[1]
            return np.broadcast_to(K.segment_segment(p0, p1, q0, q1) - r - r2, (batch,))
        kind, T, size, _ = b[1]
        fn = KIND_TABLE[kind].segment_distance
        if fn is not None:
            return np.broadcast_to(fn(p0, p1, T, size) - r, (batch,))
    elif b[1][0] == "plane" and a[1][0] == "box" or a[1][0] == "plane" and b[1][0] == "box":
        box, pl = (a, b) if a[1][0] == "box" else (b, a)
        T = pl[1][1]
        n = T[..., :3, 2]
        off = np.einsum("...i,...i->...", n, T[..., :3, 3])
        return np.broadcast_to(_box_plane(box[1][1], box[1][2], n, off), (batch,))
    from ._coal import distances

    return distances(a, b, batch)


def _rows(item: tuple[str, Any], rows: NDArray[np.intp]) -> tuple[str, Any]:
    """A world solid restricted to some batch rows (static parts kept as they are)."""
    tag, data = item
    if tag == "seg":
        p0, p1, r = data
        return tag, (p0 if p0.ndim == 1 else p0[rows], p1 if p1.ndim == 1 else p1[rows], r)
    kind, T, size, shape = data
    return tag, (kind, T if T.ndim == 2 else T[rows], size, shape)


def _pair_distances(geo: ArmGeometry, frames: Array, scene_pairs: list[tuple[int, Shape]],
                    self_pairs: Sequence[tuple[int, int]]) -> Array:
    """Signed distances ``(B, P)``: scene pairs first, then self pairs; ``frames`` from :func:`chain_frames`."""
    B = frames.shape[0]
    out = np.empty((B, len(scene_pairs) + len(self_pairs)))
    cache: dict[int, tuple[str, Any]] = {}

    def world(i: int) -> tuple[str, Any]:
        if i not in cache:
            cache[i] = _world(geo.solids[i], frames)
        return cache[i]

    k = 0
    for i, shape in scene_pairs:
        out[:, k] = _distance(world(i), _static(shape), B)
        k += 1
    for i, j in self_pairs:
        out[:, k] = _distance(world(i), world(j), B)
        k += 1
    return out


SEGMENT = 0
"""The compiled kernels' code of an arm segment (between two chain frame origins); shapes' codes are
``KIND_TABLE[kind].kernel``."""


def _jit_item(kind: str, frame: int, local: Array, size: Sequence[float], ends: tuple[int, int]) -> tuple | None:
    """One item of the Numba kernels: (kind code, frame, end a, end b, L (4, 4), radius, half (3,)); None: no kernel."""
    L = np.zeros((4, 4))
    rad, half = 0.0, np.zeros(3)
    if kind == "segment":
        return SEGMENT, frame, ends[0], ends[1], L, size[0], half
    row = KIND_TABLE[kind]
    if row.kernel is None:
        return None
    size = tuple(size)
    if row.swept is not None:
        p0, p1, rad = row.swept(np.asarray(local, dtype=float), size)
        L[0, :3], L[1, :3] = p0, p1
    else:
        L[:] = local
        half = np.array(row.kernel_size(size), dtype=float)
    return row.kernel, frame, ends[0], ends[1], L, rad, half


def _jit_pack(geo: ArmGeometry, scene_pairs: list[tuple[int, Shape]], self_pairs: Sequence[tuple[int, int]]
              ) -> tuple[tuple, NDArray[np.int64], NDArray[np.int64]]:
    """The kernels' item arrays, the supported pairs ``(P', 2)`` and their columns in the full pair list."""
    items: list[tuple | None] = [_jit_item(s.kind, s.frame, s.local, s.size, s.ends) for s in geo.solids]
    shape_index: dict[int, int] = {}
    pairs, cols = [], []
    for col, (i, shape) in enumerate(scene_pairs):
        if items[i] is None or KIND_TABLE[shape.kind].kernel is None:
            continue
        if id(shape) not in shape_index:
            shape_index[id(shape)] = len(items)
            items.append(_jit_item(shape.kind, -1, shape.pose, shape.size, (0, 0)))
        pairs.append((i, shape_index[id(shape)]))
        cols.append(col)
    for col, (i, j) in enumerate(self_pairs, start=len(scene_pairs)):
        if items[i] is None or items[j] is None:
            continue
        pairs.append((i, j))
        cols.append(col)
    dummy = (3, -1, 0, 0, np.eye(4), 0.0, np.zeros(3))
    return _pack([it if it is not None else dummy for it in items]), np.array(pairs, dtype=np.int64).reshape(-1, 2), \
        np.array(cols, dtype=np.int64)


PACKS_KEPT = 16
"""Packed item arrays kept per robot (:func:`_packed`): one IK call checks its branches twice with the same
scene, a loop calls it thousands of times."""


def _packed(robot: Robot, geo: ArmGeometry, scene_pairs: list[tuple[int, Shape]],
            self_pairs: Sequence[tuple[int, int]]) -> tuple[tuple, NDArray[np.int64], NDArray[np.int64],
                                                            NDArray[np.int64]]:
    """:func:`_jit_pack` and the pair columns without a kernel, remembered in ``robot.cache`` under the scene
    shapes' contents (kind, pose, size: a caller that edits a shape in place gets a new pack), the arm's
    solids being fixed per robot (:func:`armkit.collision.geometry.arm_geometry`)."""
    key = (id(geo), tuple(self_pairs), tuple((i, s.kind, np.asarray(s.pose, dtype=float).tobytes(),
                                              tuple(float(v) for v in s.size)) for i, s in scene_pairs))
    packs = robot.cache.setdefault("collision_packs", {})
    hit = packs.get(key)
    if hit is not None and hit[0] is geo:
        return hit[1]
    packed, pairs, cols = _jit_pack(geo, scene_pairs, self_pairs)
    made = (packed, pairs, cols, np.setdiff1d(np.arange(len(scene_pairs) + len(self_pairs)), cols))
    if len(packs) >= PACKS_KEPT:
        packs.clear()
    packs[key] = (geo, made)
    return made


def _pack(full: list[tuple]) -> tuple:
    """The items' columns as the kernels' arrays ``(kind, fr, ia, ib, L, rad, half, bound)``."""
    kind = np.array([it[0] for it in full], dtype=np.int64)
    half = np.array([it[6] for it in full], dtype=float).reshape(-1, 3)
    packed = (kind, np.array([it[1] for it in full], dtype=np.int64), np.array([it[2] for it in full], dtype=np.int64),
              np.array([it[3] for it in full], dtype=np.int64), np.array([it[4] for it in full], dtype=float).reshape(-1, 4, 4),
              np.array([it[5] for it in full], dtype=float), half, np.linalg.norm(half, axis=1))
    return packed


def shape_distance(a: Shape, b: Shape) -> float:
    """Signed distance between two shapes placed in the world (their ``pose``): the gap, or minus the depth.

    The same kernels as :func:`collisions` (compiled where the Numba back end is in use and the
    pair has a compiled kernel, see :data:`armkit.collision.shapes.KIND_TABLE`); meshes through coal.

    Examples
    --------
    >>> from armkit.collision import Scene
    >>> from armkit.collision.query import shape_distance
    >>> round(shape_distance(Scene.cylinder([0, 0, 0], 0.5, 2.0), Scene.sphere([2, 0, 0], 0.5)), 12)
    1.0
    """
    _jit = _kernels()
    items = [_jit_item(s.kind, -1, s.pose, s.size, (0, 0)) for s in (a, b)]
    if _jit is None or items[0] is None or items[1] is None or a.kind == b.kind == "plane":
        return float(_distance(_static(a), _static(b), 1)[0])
    frames = np.broadcast_to(np.eye(4), (1, 1, 4, 4)).copy()
    return float(_jit.all_distances(frames, _pack(items), np.array([[0, 1]], dtype=np.int64))[0, 0])  # type: ignore[arg-type]


def _kernels() -> Any:
    """The Numba kernels (:mod:`armkit.collision._jit`) while the Numba back end is in use, else None."""
    return kernels("collision._jit")


BLOCK = 16384
"""Configurations per block on the Numba path: frames of a block stay in cache between FK and the check."""


class _Prepared:
    """What one check of a robot against one scene needs, built once (:func:`_prepared`): the pairs, their
    names, the packed kernel items (:func:`_packed`) and the inverse tool pose that gives the flange frame."""

    __slots__ = ("geo", "shapes", "poses", "sizes", "scene_pairs", "self_pairs", "names", "flange", "pack")

    def __init__(self, robot: Robot, geo: ArmGeometry, sc: Scene, self_collision: bool) -> None:
        self.geo = geo
        self.shapes = sc.shapes
        self.poses = tuple(s.pose.tobytes() for s in sc.shapes)
        self.sizes = tuple(s.size for s in sc.shapes)
        self.scene_pairs, self.self_pairs = _pairs(geo, sc, self_collision)
        self.names = tuple((geo.solids[i].name, s.name) for i, s in self.scene_pairs) + tuple(
            (geo.solids[j].name, geo.solids[i].name) if geo.solids[j].level > geo.solids[i].level
            else (geo.solids[i].name, geo.solids[j].name) for i, j in self.self_pairs)
        tool = np.asarray(robot.tool)
        self.flange: Array | None = np.linalg.inv(tool).astype(float) if np.any(tool[:3, 3]) else None
        self.pack: tuple | None = None    # _packed(...) on the first Numba check

    def holds(self, geo: ArmGeometry, sc: Scene) -> bool:
        """True while this record still describes ``sc`` (the same shapes, poses and sizes) on ``geo``."""
        return geo is self.geo and len(sc.shapes) == len(self.shapes) and all(
            a is b and a.pose.tobytes() == p and a.size == z
            for a, b, p, z in zip(sc.shapes, self.shapes, self.poses, self.sizes))


PREPARED_KEPT = 16
"""Prepared checks kept per robot (:func:`_prepared`), as :data:`PACKS_KEPT`."""


def _prepared(robot: Robot, sc: Scene, self_collision: bool) -> _Prepared:
    """The :class:`_Prepared` record of ``robot`` against ``sc``, remembered in ``robot.cache`` under the
    scene's shapes (kept alive by the record, so their ids stay theirs) and checked against their contents."""
    geo = arm_geometry(robot)
    key = (self_collision,) + tuple(map(id, sc.shapes))
    kept = robot.cache.setdefault("collision_prepared", {})
    rec = kept.get(key)
    if rec is not None and rec.holds(geo, sc):
        return rec  # type: ignore[no-any-return]
    rec = _Prepared(robot, geo, sc, self_collision)
    if len(kept) >= PREPARED_KEPT:
        kept.clear()
    kept[key] = rec
    return rec


def _frames(robot: Robot, q: Array, flange: Array | None) -> Array:
    """:func:`chain_frames` with the inverse tool pose given (``None``: no flange frame to add)."""
    frames = fk_frames(robot, q)
    if flange is None:
        return frames
    n = robot.n
    out = np.empty((frames.shape[0], n + 2, 4, 4))
    out[:, :n + 1] = frames
    np.matmul(frames[:, n], flange, out=out[:, n + 1])
    return out


def _evaluate(robot: Robot, geo: ArmGeometry, q: Array, scene_pairs: list[tuple[int, Shape]],
              self_pairs: Sequence[tuple[int, int]], only_min: bool = False, stop: float = -np.inf
              ) -> tuple[Array | None, Array, NDArray[np.int64] | None]:
    """``(distances (B, P) or None, min (B,), argmin (B,))`` by the Numba kernels where they apply, NumPy/coal otherwise."""
    B = q.shape[0]
    P = len(scene_pairs) + len(self_pairs)
    if P == 0:
        return np.empty((B, 0)), np.full(B, np.inf), np.full(B, -1, dtype=np.int64)
    _jit = _kernels()    # any batch: the NumPy pair loop costs ~3 ms for one fighter configuration, Numba ~20 us
    if _jit is None:
        d = _pair_distances(geo, chain_frames(robot, q), scene_pairs, self_pairs)
        arg = np.argmin(d, axis=1)
        return d, d[np.arange(B), arg], arg
    if B > BLOCK:   # block by block: FK frames and the check while the frames are in cache
        parts = [_evaluate(robot, geo, q[s:s + BLOCK], scene_pairs, self_pairs, only_min, stop)
                 for s in range(0, B, BLOCK)]
        d_all = None if only_min else np.concatenate([p_[0] for p_ in parts])  # type: ignore[misc]
        return d_all, np.concatenate([p_[1] for p_ in parts]), np.concatenate([p_[2] for p_ in parts])
    frames = np.ascontiguousarray(chain_frames(robot, q))
    return _evaluate_jit(_jit, geo, frames, _packed(robot, geo, scene_pairs, self_pairs), scene_pairs, self_pairs,
                         only_min, stop)


def _evaluate_prepared(robot: Robot, rec: _Prepared, q: Array, only_min: bool = False, stop: float = -np.inf,
                       closest: bool = True) -> tuple[Array | None, Array, NDArray[np.int64] | None]:
    """:func:`_evaluate` of a prepared check: the same kernels and results, without rebuilding its parts.
    ``closest=False``: the caller reads the distances only, and the closest pairs may be left out (None)."""
    if not rec.scene_pairs and not rec.self_pairs or q.shape[0] > BLOCK:
        return _evaluate(robot, rec.geo, q, rec.scene_pairs, rec.self_pairs, only_min, stop)
    _jit = _kernels()
    if _jit is None:
        return _evaluate(robot, rec.geo, q, rec.scene_pairs, rec.self_pairs, only_min, stop)
    if rec.pack is None:
        rec.pack = _packed(robot, rec.geo, rec.scene_pairs, rec.self_pairs)
    frames = np.ascontiguousarray(_frames(robot, q, rec.flange))
    return _evaluate_jit(_jit, rec.geo, frames, rec.pack, rec.scene_pairs, rec.self_pairs, only_min, stop, closest)


def _evaluate_jit(_jit: Any, geo: ArmGeometry, frames: Array, pack: tuple, scene_pairs: list[tuple[int, Shape]],
                  self_pairs: Sequence[tuple[int, int]], only_min: bool, stop: float, closest: bool = True
                  ) -> tuple[Array | None, Array, NDArray[np.int64] | None]:
    """:func:`_evaluate` on the Numba back end for one block of chain ``frames`` and its :func:`_packed` items."""
    B = frames.shape[0]
    packed, pairs, cols, rest = pack
    if only_min:
        dist, arg = _jit.min_distance(frames, packed, pairs, stop) if len(pairs) else (
            np.full(B, np.inf), np.full(B, -1, dtype=np.int64))
        if not closest and not len(rest):   # the distances alone (IK's yes/no check on every call)
            return None, dist, None
        arg = np.where(arg >= 0, cols[np.maximum(arg, 0)] if len(cols) else -1, -1)
        if len(rest):
            sp = [scene_pairs[c] for c in rest if c < len(scene_pairs)]
            selfp = [self_pairs[c - len(scene_pairs)] for c in rest if c >= len(scene_pairs)]
            d2 = _pair_distances(geo, frames, sp, selfp)
            a2 = np.argmin(d2, axis=1)
            m2 = d2[np.arange(B), a2]
            better = m2 < dist
            dist = np.where(better, m2, dist)
            arg = np.where(better, rest[a2], arg)
        return None, dist, arg
    P = len(scene_pairs) + len(self_pairs)
    if not len(rest):   # every pair compiled: the kernel's columns are the pairs in order
        d = _jit.all_distances(frames, packed, pairs)
        if not np.array_equal(cols, np.arange(P)):
            d_full = np.empty((B, P))
            d_full[:, cols] = d
            d = d_full
    else:
        d = np.empty((B, P))
        if len(pairs):
            d[:, cols] = _jit.all_distances(frames, packed, pairs)
        sp = [scene_pairs[c] for c in rest if c < len(scene_pairs)]
        selfp = [self_pairs[c - len(scene_pairs)] for c in rest if c >= len(scene_pairs)]
        d[:, rest] = _pair_distances(geo, frames, sp, selfp)
    arg = np.argmin(d, axis=1)
    return d, d[np.arange(B), arg], arg


def collisions(robot: Robot, q: ArrayLike, scene: Scene | Sequence[Shape] | str | None = None, *,
               self_collision: bool = True) -> Collisions:
    """Collision check of the arm at ``q`` against ``scene`` and itself.

    Parameters
    ----------
    robot : Robot
    q : array_like, shape (..., n)
    scene : Scene, list of Shape, path of a scene file, or None
        The surroundings; ``None`` uses the robot's own (its file's ``[[scene]]``, e.g. the
        fighter's ground). The robot's body (``[[body]]``) is always part of the arm.
    self_collision : bool
        Also check the arm's solids against each other (the pairs of :mod:`.geometry`).

    Returns
    -------
    Collisions
        ``colliding`` and ``distance`` of shape ``(...)``, and every pair's distance.

    Examples
    --------
    >>> import armkit, numpy as np
    >>> arm = armkit.load("planar2")
    >>> floor = armkit.Scene([armkit.Scene.plane([0, 1, 0], -0.2, name="floor")])   # y <= -0.2 is solid
    >>> res = armkit.collisions(arm, [[0.0, 0.0], [-np.pi / 2, 0.0]], floor)
    >>> res.colliding.tolist()
    [False, True]
    >>> res.message(1)      # link 2 reaches y = -1.5, its capsule (radius 0.045 m) 1.345 m past y = -0.2
    'the link2 hits the floor by 1.34 m (2 pairs in collision)'
    """
    sc = as_scene(robot, scene)
    qa = robot.check_q(q)
    return _collisions(robot, _prepared(robot, sc, self_collision), qa.reshape(-1, robot.n), qa.shape[:-1])


def _collisions(robot: Robot, rec: _Prepared, q: Array, lead: tuple[int, ...]) -> Collisions:
    """:func:`collisions` of checked ``q`` ``(B, n)`` by a prepared check, shaped ``lead``."""
    d, dist, closest = _evaluate_prepared(robot, rec, q)
    assert d is not None and closest is not None
    return Collisions(colliding=(dist < 0).reshape(lead), distance=dist.reshape(lead), pairs=rec.names,
                      distances=d.reshape(lead + (d.shape[1],)), closest=closest.reshape(lead), unit=robot.unit)


def clearance(robot: Robot, q: ArrayLike, scene: Scene | Sequence[Shape] | str | None = None, *,
              self_collision: bool = True) -> Array:
    """The smallest signed distance between the arm and ``scene`` (and itself), shape ``(...)``.

    Positive: the gap (robot unit); negative: minus the deepest penetration. See :func:`collisions`.
    """
    sc = as_scene(robot, scene)
    qa = robot.check_q(q)
    _, dist, _ = _evaluate_prepared(robot, _prepared(robot, sc, self_collision), qa.reshape(-1, robot.n),
                                    only_min=True, closest=False)
    return dist.reshape(qa.shape[:-1])


def in_collision(robot: Robot, q: ArrayLike, scene: Scene | Sequence[Shape] | str | None = None, *,
                 self_collision: bool = True) -> NDArray[np.bool_]:
    """True where the arm at ``q`` overlaps ``scene`` or itself, shape ``(...)``: the fast yes/no check.

    The same answer as ``collisions(...).colliding``; on the Numba back end each configuration
    stops at its first overlapping pair and skips pairs whose bounding spheres are apart.
    """
    sc = as_scene(robot, scene)
    qa = robot.check_q(q)
    _, dist, _ = _evaluate_prepared(robot, _prepared(robot, sc, self_collision), qa.reshape(-1, robot.n),
                                    only_min=True, stop=0.0, closest=False)
    return (dist < 0).reshape(qa.shape[:-1])


def colliding_rows(robot: Robot, q: Array, scene: Scene, messages: bool = True) -> tuple[NDArray[np.intp], list[str]]:
    """The rows of ``q`` that collide with ``scene`` or the arm itself, and a message for each: for IK.

    The same answer as ``np.flatnonzero(in_collision(robot, q, scene))`` and then
    ``collisions(robot, q[rows], scene).message(m)`` for each, in one call without checking the
    arguments again: ``q`` is a finite float array ``(B, n)`` the library made (IK solutions) and
    ``scene`` a :class:`Scene` in the robot's unit (a :func:`resolve_scene` answer).

    Returns
    -------
    rows : ndarray of int, shape (k,)
        Indices of the colliding configurations, increasing.
    messages : list of str
        ``Collisions.message`` of each, in the order of ``rows``; empty with ``messages=False`` (the yes/no
        check alone: no pair's depth is measured, no sentence made).
    """
    if scene.unit != robot.unit:
        scene = as_scene(robot, scene)
    rec = _prepared(robot, scene, True)
    rows = np.flatnonzero(_evaluate_prepared(robot, rec, q, only_min=True, stop=0.0, closest=False)[1] < 0)
    if not len(rows) or not messages:
        return rows, []
    return rows, _row_messages(robot, rec, q[rows])


def row_messages(robot: Robot, q: Array, scene: Scene) -> list[str]:
    """The messages :func:`colliding_rows` gives, for configurations ``q (k, n)`` found colliding by its yes/no
    check (``messages=False``): the sentences made later, for the rows whose message is read (IK with a scene)."""
    if scene.unit != robot.unit:
        scene = as_scene(robot, scene)
    return _row_messages(robot, _prepared(robot, scene, True), q)


def _row_messages(robot: Robot, rec: Any, q: Array) -> list[str]:
    hits = _collisions(robot, rec, q, (len(q),))
    return [hits.message(m) for m in range(len(q))]


def _pairs(geo: ArmGeometry, scene: Scene, self_collision: bool
           ) -> tuple[list[tuple[int, Shape]], list[tuple[int, int]]]:
    scene_pairs = [(i, s) for s in scene for i, sol in enumerate(geo.solids)
                   if sol.frame != 0 and not geo.allowed(sol.link, s)]
    return scene_pairs, (list(geo.self_pairs) if self_collision else [])
