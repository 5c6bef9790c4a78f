"""Collision shapes and the :class:`Scene` that holds them.

A :class:`Shape` is a solid primitive with a pose in the world (scene shapes) or in a link
frame (a robot's own body): a half-space (``plane``), a box, a sphere, a cylinder, a capsule,
or a convex mesh. Lengths are in the scene's unit (``Scene.unit``; ``None`` means "the robot's
unit"), angles in radians (``rpy`` as in :func:`armkit.spatial.rpy_to_rotation`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any, Callable, Iterable, Iterator, NamedTuple, Protocol, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._text import Fielded
from ..errors import SceneError
from ..spatial import make_pose, rotation_to_rpy, rpy_to_rotation
from . import kernels as K

__all__ = ["Shape", "Scene", "SceneError", "KINDS", "KIND_TABLE", "ShapeKind", "Part", "kind_of"]

Array = NDArray[np.float64]
_UNITS = {"m": 1.0, "cm": 1e-2, "mm": 1e-3}


def _vec(value: ArrayLike, n: int, what: str) -> Array:
    try:
        v = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise SceneError.of("{what} must be {n} numbers, got {value!r}", what=what, n=n, value=value) from exc
    if v.shape != (n,):
        raise SceneError.of("{what} must be {n} numbers, got shape {shape}", what=what, n=n, shape=v.shape)
    if not np.all(np.isfinite(v)):
        raise SceneError.of("{what} contains NaN or infinite values", what=what)
    return v


def _positive(value: float, what: str, allow_zero: bool = False) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError) as exc:
        raise SceneError.of("{what} must be a number, got {value!r}", what=what, value=value) from exc
    if not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        raise SceneError.of("{what} must be a finite number >= 0, got {got!r}" if allow_zero else
                            "{what} must be a finite number > 0, got {got!r}", what=what, got=v)
    return v


def kind_of(kind: str) -> "ShapeKind":
    """The :class:`ShapeKind` row of ``kind``; an unknown kind raises SceneError listing the known ones."""
    row = KIND_TABLE.get(kind) if isinstance(kind, str) else None
    if row is None:
        raise SceneError.of("shape kind must be one of {names}; got {kind!r}", names=', '.join(KIND_TABLE), kind=kind)
    return row


def _pose(center: ArrayLike, rpy: ArrayLike) -> Array:
    return make_pose(rpy_to_rotation(_vec(rpy, 3, "rpy")), _vec(center, 3, Fielded.of("center")))


@dataclass(frozen=True, eq=False)
class Shape:
    """One solid.

    Attributes
    ----------
    kind : {"plane", "box", "sphere", "cylinder", "capsule", "mesh"}
        A key of :data:`KIND_TABLE`.
    pose : ndarray, shape (4, 4)
        Pose of the shape's own frame (world, or the link it is attached to). A plane's frame
        has its z axis along the normal and its origin on the plane; the solid is the side
        behind the normal (a half-space: the ground and everything under it).
    size : tuple of float
        box: full extents (x, y, z); sphere: (radius,); cylinder and capsule: (radius, length)
        along the local z axis, centred on the origin (a capsule's length is that of its
        segment, without the end caps); plane and mesh: ().
    name : str
        Shown in messages ("the forearm would hit the ground by 12 mm").
    allow : tuple of str
        Link names allowed to touch this shape (SRDF's disable-collisions).
    link : str or None
        For a robot's body: the link the shape moves with (``None``: the world).
    mesh_path : str or None, scale : (3,)
        Meshes: the file and its scale; collision uses the convex hull of the vertices.
    """

    kind: str
    pose: Array
    size: tuple[float, ...] = ()
    name: str = ""
    allow: tuple[str, ...] = ()
    link: str | None = None
    mesh_path: str | None = None
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0)

    def __post_init__(self) -> None:
        kind_of(self.kind)
        T = np.array(self.pose, dtype=float)
        if T.shape != (4, 4) or not np.all(np.isfinite(T)):
            raise SceneError.of("shape pose must be a finite 4x4 pose, got shape {shape}", shape=T.shape)
        T.setflags(write=False)
        object.__setattr__(self, "pose", T)
        object.__setattr__(self, "size", tuple(float(s) for s in self.size))
        object.__setattr__(self, "allow", tuple(self.allow))
        if not self.name:
            object.__setattr__(self, "name", self.kind)

    # ---------------------------------------------------------------- views
    @property
    def normal(self) -> Array:
        """A plane's unit normal (the pose's z axis)."""
        return self.pose[:3, 2]

    @property
    def offset(self) -> float:
        """A plane's offset: the plane is ``normal · x = offset``."""
        return float(self.pose[:3, 2] @ self.pose[:3, 3])

    @property
    def center(self) -> Array:
        return self.pose[:3, 3]

    @property
    def radius(self) -> float:
        return self.size[0]

    def segment(self) -> tuple[Array, Array]:
        """A capsule's (or cylinder's) axis end points in the pose's parent frame."""
        h = 0.5 * self.size[1]
        z = self.pose[:3, 2]
        return self.center - h * z, self.center + h * z

    def moved(self, T: ArrayLike) -> "Shape":
        """The same shape with its pose premultiplied by ``T`` (e.g. into the world)."""
        return replace(self, pose=np.asarray(T, dtype=float) @ self.pose)

    def scaled(self, factor: float) -> "Shape":
        """Lengths multiplied by ``factor`` (unit conversion)."""
        T = self.pose.copy()
        T[:3, 3] *= factor
        return replace(self, pose=T, size=tuple(s * factor for s in self.size),
                       scale=tuple(s * factor for s in self.scale))  # type: ignore[arg-type]

    def describe(self) -> str:
        """One line for people (the kind's ``describe`` in :data:`KIND_TABLE`)."""
        return KIND_TABLE[self.kind].describe(self)

    def __repr__(self) -> str:
        return f"Shape({self.name!r}: {self.describe()})"


class Scene:
    """The arm's surroundings: a list of :class:`Shape` in the world.

    Parameters
    ----------
    shapes : iterable of Shape
    unit : {"m", "cm", "mm"} or None
        Length unit of the shapes; ``None`` (the default for scenes built in Python) means the
        unit of the robot they are checked against.

    Examples
    --------
    >>> import armkit
    >>> scene = armkit.Scene([armkit.Scene.plane([0, 0, 1], 0.0, name="ground"),
    ...                       armkit.Scene.box([0.5, 0, 0.2], [0.4, 0.6, 0.4], name="table")])
    >>> [s.name for s in scene]
    ['ground', 'table']
    """

    def __init__(self, shapes: Iterable[Shape] = (), unit: str | None = None) -> None:
        shapes = tuple(shapes)
        for s in shapes:
            if not isinstance(s, Shape):
                raise SceneError.of("a Scene holds armkit Shapes (Scene.box(...), Scene.plane(...), ...); got {s!r}",
                                    s=s)
        if unit is not None and unit not in _UNITS:
            raise SceneError.of("unit must be one of {names} or None, got {unit!r}", names=', '.join(_UNITS), unit=unit)
        self.shapes: tuple[Shape, ...] = shapes
        self.unit = unit

    # ----------------------------------------------------------- constructors
    @staticmethod
    def plane(normal: ArrayLike, offset: float = 0.0, *, name: str = "", allow: Sequence[str] = ()) -> Shape:
        """The half-space ``normal · x <= offset``: a plane and everything behind it (the ground)."""
        n = _vec(normal, 3, Fielded.of("plane normal"))
        length = float(np.linalg.norm(n))
        if length < 1e-12:
            raise SceneError.of("plane normal must not be zero")
        n = n / length
        off = float(offset) / length
        if not math.isfinite(off):
            raise SceneError.of("plane offset must be a finite number, got {offset!r}", offset=offset)
        # a frame with z along n: x from the axis least aligned with n
        helper = np.eye(3)[int(np.argmin(np.abs(n)))]
        x = np.cross(helper, n)
        x /= np.linalg.norm(x)
        y = np.cross(n, x)
        T = np.eye(4)
        T[:3, 0], T[:3, 1], T[:3, 2], T[:3, 3] = x, y, n, n * off
        return Shape("plane", T, (), name or "ground" if n[2] > 0.999 else name or "plane", tuple(allow))

    @staticmethod
    def box(center: ArrayLike, size: ArrayLike, rpy: ArrayLike = (0.0, 0.0, 0.0), *, name: str = "",
            allow: Sequence[str] = ()) -> Shape:
        """A box with full extents ``size`` (x, y, z), centred at ``center``, turned by ``rpy`` (rad)."""
        sz = _vec(size, 3, Fielded.of("box size"))
        for v in sz:
            _positive(v, Fielded.of("box size"))
        return Shape("box", _pose(center, rpy), tuple(sz), name or "box", tuple(allow))

    @staticmethod
    def sphere(center: ArrayLike, radius: float, *, name: str = "", allow: Sequence[str] = ()) -> Shape:
        """A ball."""
        return Shape("sphere", _pose(center, (0, 0, 0)), (_positive(radius, Fielded.of("sphere radius")),),
                     name or "sphere", tuple(allow))

    @staticmethod
    def cylinder(center: ArrayLike, radius: float, length: float, rpy: ArrayLike = (0.0, 0.0, 0.0), *,
                 name: str = "", allow: Sequence[str] = ()) -> Shape:
        """A solid cylinder along its local z axis (turned by ``rpy``), centred at ``center`` (as in URDF)."""
        return Shape("cylinder", _pose(center, rpy),
                     (_positive(radius, Fielded.of("cylinder radius")),
                      _positive(length, Fielded.of("cylinder length"))),
                     name or "cylinder", tuple(allow))

    @staticmethod
    def capsule(a: ArrayLike, b: ArrayLike, radius: float, *, name: str = "", allow: Sequence[str] = ()) -> Shape:
        """The points within ``radius`` of the segment ``a -> b``."""
        pa, pb = _vec(a, 3, Fielded.of("capsule end a")), _vec(b, 3, Fielded.of("capsule end b"))
        r = _positive(radius, Fielded.of("capsule radius"))
        d = pb - pa
        length = float(np.linalg.norm(d))
        if length > 0:
            z = d / length
            helper = np.eye(3)[int(np.argmin(np.abs(z)))]
            x = np.cross(helper, z)
            x /= np.linalg.norm(x)
            R = np.column_stack([x, np.cross(z, x), z])
        else:
            R = np.eye(3)
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = R, 0.5 * (pa + pb)
        return Shape("capsule", T, (r, length), name or "capsule", tuple(allow))

    @staticmethod
    def mesh(path: str, pose: ArrayLike | None = None, scale: ArrayLike = (1.0, 1.0, 1.0), *, name: str = "",
             allow: Sequence[str] = ()) -> Shape:
        """A mesh file (anything coal/assimp reads: STL, OBJ, DAE); collision uses its convex hull."""
        T = np.eye(4) if pose is None else np.asarray(pose, dtype=float)
        sc = _vec(scale, 3, Fielded.of("mesh scale"))
        return Shape("mesh", T, (), name or "mesh", tuple(allow), None, str(path),
                     (float(sc[0]), float(sc[1]), float(sc[2])))

    @classmethod
    def load(cls, path: str) -> "Scene":
        """Read a scene file (TOML, see ``docs/scene.md``); errors name the file, line and field."""
        from .files import load_scene

        return load_scene(path)

    # ------------------------------------------------------------- editing
    def __iter__(self) -> Iterator[Shape]:
        return iter(self.shapes)

    def __len__(self) -> int:
        return len(self.shapes)

    def __add__(self, other: "Scene | Iterable[Shape]") -> "Scene":
        if isinstance(other, Scene):
            if self.unit is not None and other.unit is not None and self.unit != other.unit:
                other = other.in_unit(self.unit)
            return Scene(self.shapes + other.shapes, self.unit or other.unit)
        return Scene(self.shapes + tuple(other), self.unit)

    def with_shape(self, shape: Shape) -> "Scene":
        """A new scene with ``shape`` added."""
        return Scene(self.shapes + (shape,), self.unit)

    def without(self, name: str) -> "Scene":
        """A new scene without the shapes called ``name``."""
        return Scene([s for s in self.shapes if s.name != name], self.unit)

    def in_unit(self, unit: str) -> "Scene":
        """The same scene with lengths in ``unit`` (a scene without a unit is taken as already in it)."""
        if unit not in _UNITS:
            raise SceneError.of("unit must be one of {names}, got {unit!r}", names=', '.join(_UNITS), unit=unit)
        if self.unit is None or self.unit == unit:
            return Scene(self.shapes, unit)
        f = _UNITS[self.unit] / _UNITS[unit]
        return Scene([s.scaled(f) for s in self.shapes], unit)

    def __repr__(self) -> str:
        inner = ", ".join(repr(s) for s in self.shapes)
        return f"Scene([{inner}]" + (f", unit={self.unit!r})" if self.unit else ")")


# ------------------------------------------------------------------------------ the kind table
class Part(NamedTuple):
    """One piece of a shape's drawing: a ``primitive`` ("plane", "box", "sphere", "cylinder" or "mesh") at
    ``pose`` (4, 4) in the shape's own frame, with the primitive's ``size`` (as :class:`Shape` sizes)."""

    primitive: str
    pose: Array
    size: tuple[float, ...]


class Fields(Protocol):
    """What a kind's ``read`` gets from one file table (``[[shapes]]``, ``[[body]]``, ``[[scene]]``).

    ``number``/``vector`` raise the file's error naming the key when it is missing (no default) or
    malformed; ``angles`` is a vector in radians (the file's ``angle_unit`` applied); ``mesh_file``
    the resolved path of a mesh key. ``name`` and ``allow`` are the common keys, checked.
    """

    name: str
    allow: list[str]

    def number(self, key: str, default: float | None = None) -> float: ...

    def vector(self, key: str, default: list[float] | None = None) -> list[float]: ...

    def angles(self, key: str) -> list[float]: ...

    def mesh_file(self, key: str) -> str: ...


@dataclass(frozen=True)
class ShapeKind:
    """Everything armkit knows about one kind of :class:`Shape`: one row of :data:`KIND_TABLE`.

    Attributes
    ----------
    name : str
        The ``kind`` / file ``type``.
    keys : frozenset of str
        The file keys of this kind (besides ``type``, ``name``, ``allow``).
    read : callable (Fields) -> Shape
        Build the shape from a file table.
    write : callable (Shape, float) -> dict
        The file table of a shape (lengths times the factor; ``rpy`` in radians, the caller converts).
    kernel : int or None
        The item code of the compiled kernels (:mod:`armkit.collision._jit`): 1 a segment swept
        by a ball, 2 a box, 3 a half-space, 4 a cylinder; ``None``: pairs with it go through coal.
    kernel_size : callable (size) -> (3,) floats
        The item's size data for those kernels (a box: half extents; a cylinder: radius, 0, half length).
    swept : callable (T (..., 4, 4), size) -> (p0, p1, radius) or None
        For a segment swept by a ball (sphere, capsule): its segment's end points and radius. Such
        a shape meets everything through the segment kernels, its radius subtracted.
    segment_distance : callable (p0, p1, T, size) -> ndarray or None
        The NumPy signed distance of segments ``(..., 3)`` to this solid at ``T``: the reference
        kernel (:mod:`armkit.collision.kernels`) and the path without Numba. ``None``: coal.
    coal : callable (coal module, Shape) -> geometry
        The shape in coal's terms, in its own frame (the reference in tests; meshes).
    drawing : callable (Shape) -> tuple of Part
        How to draw the shape (the browser view, plots).
    describe : callable (Shape) -> str
        One line for people ("box at (1, 2, 3) size 1 x 2 x 3").
    """

    name: str
    keys: frozenset[str]
    read: Callable[[Fields], Shape]
    write: Callable[[Shape, float], dict[str, Any]]
    kernel: int | None
    kernel_size: Callable[[tuple[float, ...]], tuple[float, float, float]]
    swept: Callable[[Array, tuple[float, ...]], tuple[Array, Array, float]] | None
    segment_distance: Callable[[Array, Array, Array, tuple[float, ...]], Array] | None
    coal: Callable[[Any, Shape], Any]
    drawing: Callable[[Shape], tuple[Part, ...]]
    describe: Callable[[Shape], str]


def _rpy_of(s: Shape) -> list[float]:
    return [float(v) for v in rotation_to_rpy(np.asarray(s.pose)[:3, :3])]


def _xyz(v: ArrayLike, f: float) -> list[float]:
    return [float(x) * f + 0.0 for x in np.asarray(v, dtype=float)]


def _at(s: Shape) -> str:
    return ", ".join(f"{v:g}" for v in np.round(s.center, 6))


def _no_size(size: tuple[float, ...]) -> tuple[float, float, float]:
    return (0.0, 0.0, 0.0)


def _ball_segment(T: Array, size: tuple[float, ...]) -> tuple[Array, Array, float]:
    return T[..., :3, 3], T[..., :3, 3], size[0]


def _capsule_segment(T: Array, size: tuple[float, ...]) -> tuple[Array, Array, float]:
    h = 0.5 * size[1] * T[..., :3, 2]
    return T[..., :3, 3] - h, T[..., :3, 3] + h, size[0]


def _plane_distance(p0: Array, p1: Array, T: Array, size: tuple[float, ...]) -> Array:
    n = T[..., :3, 2]
    return K.segment_plane(p0, p1, n, np.einsum("...i,...i->...", n, T[..., :3, 3]))


def _box_distance(p0: Array, p1: Array, T: Array, size: tuple[float, ...]) -> Array:
    return K.segment_box(p0, p1, T, 0.5 * np.asarray(size))


def _cylinder_distance(p0: Array, p1: Array, T: Array, size: tuple[float, ...]) -> Array:
    return K.segment_cylinder_signed(p0, p1, T, size[0], 0.5 * size[1])


def _describe_plane(s: Shape) -> str:
    if np.allclose(s.normal, [0, 0, 1], atol=1e-12):
        return Fielded.of("floor at z = {z}", z=f"{s.offset:g}")     # a template and fields: any language
    nrm = ", ".join(f"{v:g}" for v in np.round(s.normal, 6))
    return Fielded.of("plane normal ({normal}) offset {offset}", normal=nrm, offset=f"{s.offset:g}")


def _mesh_coal(coal: Any, s: Shape) -> Any:
    from ._coal import mesh_hull

    return mesh_hull(coal, s)


_EYE = np.eye(4)
_EYE.setflags(write=False)

KIND_TABLE: dict[str, ShapeKind] = {k.name: k for k in (
    ShapeKind(
        "plane", frozenset({"normal", "offset"}),
        read=lambda f: Scene.plane(f.vector("normal"), f.number("offset", 0.0), name=f.name, allow=f.allow),
        write=lambda s, c: {"normal": [float(x) + 0.0 for x in s.normal], "offset": s.offset * c + 0.0},
        kernel=3, kernel_size=_no_size, swept=None, segment_distance=_plane_distance,
        coal=lambda coal, s: coal.Halfspace(np.array([0.0, 0.0, 1.0]), 0.0),
        drawing=lambda s: (Part("plane", _EYE, ()),), describe=_describe_plane),
    ShapeKind(
        "box", frozenset({"center", "size", "rpy"}),
        read=lambda f: Scene.box(f.vector("center"), f.vector("size"), f.angles("rpy"), name=f.name, allow=f.allow),
        write=lambda s, c: {"center": _xyz(s.center, c), "size": [v * c for v in s.size], "rpy": _rpy_of(s)},
        kernel=2, kernel_size=lambda z: (0.5 * z[0], 0.5 * z[1], 0.5 * z[2]), swept=None, segment_distance=_box_distance,
        coal=lambda coal, s: coal.Box(*s.size),
        drawing=lambda s: (Part("box", _EYE, s.size),),
        describe=lambda s: Fielded.of("box at ({at}) size {size}", at=_at(s), size=" x ".join(f"{v:g}" for v in s.size))),
    ShapeKind(
        "sphere", frozenset({"center", "radius"}),
        read=lambda f: Scene.sphere(f.vector("center"), f.number("radius"), name=f.name, allow=f.allow),
        write=lambda s, c: {"center": _xyz(s.center, c), "radius": s.size[0] * c},
        kernel=1, kernel_size=_no_size, swept=_ball_segment, segment_distance=None,
        coal=lambda coal, s: coal.Sphere(s.size[0]),
        drawing=lambda s: (Part("sphere", _EYE, s.size[:1]),),
        describe=lambda s: Fielded.of("sphere at ({at}) radius {radius}", at=_at(s), radius=f"{s.size[0]:g}")),
    ShapeKind(
        "cylinder", frozenset({"center", "radius", "length", "rpy"}),
        read=lambda f: Scene.cylinder(f.vector("center"), f.number("radius"), f.number("length"), f.angles("rpy"),
                                      name=f.name, allow=f.allow),
        write=lambda s, c: {"center": _xyz(s.center, c), "radius": s.size[0] * c, "length": s.size[1] * c,
                            "rpy": _rpy_of(s)},
        kernel=4, kernel_size=lambda z: (z[0], 0.0, 0.5 * z[1]), swept=None, segment_distance=_cylinder_distance,
        coal=lambda coal, s: coal.Cylinder(s.size[0], s.size[1]),
        drawing=lambda s: (Part("cylinder", _EYE, s.size[:2]),),
        describe=lambda s: Fielded.of("cylinder at ({at}) radius {radius} length {length}", at=_at(s),
                                       radius=f"{s.size[0]:g}", length=f"{s.size[1]:g}")),
    ShapeKind(
        "capsule", frozenset({"a", "b", "radius"}),
        read=lambda f: Scene.capsule(f.vector("a"), f.vector("b"), f.number("radius"), name=f.name, allow=f.allow),
        write=lambda s, c: {"a": _xyz(s.segment()[0], c), "b": _xyz(s.segment()[1], c), "radius": s.size[0] * c},
        kernel=1, kernel_size=_no_size, swept=_capsule_segment, segment_distance=None,
        coal=lambda coal, s: coal.Capsule(s.size[0], s.size[1]),
        drawing=lambda s: (Part("cylinder", _EYE, s.size[:2]),
                           Part("sphere", _shifted(-0.5 * s.size[1]), s.size[:1]),
                           Part("sphere", _shifted(0.5 * s.size[1]), s.size[:1])),
        describe=lambda s: Fielded.of("capsule at ({at}) radius {radius} length {length}", at=_at(s),
                                       radius=f"{s.size[0]:g}", length=f"{s.size[1]:g}")),
    ShapeKind(
        "mesh", frozenset({"path", "xyz", "rpy", "scale"}),
        read=lambda f: Scene.mesh(f.mesh_file("path"), _pose(f.vector("xyz", [0.0, 0.0, 0.0]), f.angles("rpy")),
                                  f.vector("scale", [1.0, 1.0, 1.0]), name=f.name, allow=f.allow),
        write=lambda s, c: {"path": str(s.mesh_path), "xyz": _xyz(s.center, c), "rpy": _rpy_of(s),
                            "scale": [v * c for v in s.scale]},
        kernel=None, kernel_size=_no_size, swept=None, segment_distance=None, coal=_mesh_coal,
        drawing=lambda s: (Part("mesh", _EYE, ()),), describe=lambda s: Fielded.of("mesh {path}", path=s.mesh_path)),
)}
"""The one table from a shape kind to its file keys, its kernels, its coal geometry and its drawing
(``docs/adding-a-primitive.md``)."""

KINDS = tuple(KIND_TABLE)


def _shifted(z: float) -> Array:
    T = np.eye(4)
    T[2, 3] = z
    return T
