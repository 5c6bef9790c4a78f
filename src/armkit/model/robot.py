"""The immutable robot model: a DH table compiled to one uniform chain form.

Every model, whatever convention it was written in, compiles to the same chain::

    T_base_link_k = base · Π_{i<=k} ( pre_i · M_i(q_i) · post_i )        (tool applied after link n)

where ``M_i`` is a rotation about (revolute) or a translation along (prismatic) the
local z axis and ``pre_i``/``post_i`` are constant poses. Standard DH puts the constant
part after the motion (``post``), modified DH before it (``pre``); a URDF importer fills
``pre`` with the joint origin. The kinematics kernels only ever see this form.

Three ways to write the joints, one compiled form:

* ``convention="standard"`` / ``"modified"``: DH rows (``theta, d, a, alpha``);
* ``convention="urdf"``: each joint has an ``origin`` (pose of the joint frame in the
  previous moving link's frame, fixed joints already folded in) and a unit ``axis``; the
  compiler turns ``origin · Rot(axis, q)`` into ``pre = origin · A``, ``M = Rz(q)``,
  ``post = A^T`` with ``A`` a rotation taking z to the axis (exact for axis-aligned axes).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any, Callable, Literal, Protocol, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import RobotDefinitionError, ShapeError
from .._checks import real_array
from .._text import Fielded
from ..spatial import check_transform

__all__ = ["Joint", "Robot", "Chain", "Link", "Shape", "REVOLUTE", "PRISMATIC", "axis_alignment",
           "CollisionKeys", "collision_keys", "read_collision_keys_with"]


class CollisionKeys(Protocol):
    """What reads and writes a robot file's collision keys (:mod:`armkit.collision.robot_file`)."""

    def attach(self, robot: "Robot", data: dict, text: str, path: str, allow_outside: bool = False) -> None: ...

    def surroundings(self, robot: "Robot", scale: float = 1.0, links: Any = None) -> dict[str, Any]: ...

    def carry_collision(self, source: "Robot", target: "Robot") -> None: ...


_collision_keys: Callable[[], CollisionKeys] | None = None


def read_collision_keys_with(reader: Callable[[], CollisionKeys]) -> None:
    """Name who reads the collision keys of robot files: ``reader()`` returns it, imported on first use.

    The model floor never imports the collision floor above it (docs/architecture.md);
    ``armkit/__init__.py``, the top floor, plugs :mod:`armkit.collision.robot_file` in here.
    """
    global _collision_keys
    _collision_keys = reader


def collision_keys() -> CollisionKeys:
    """The reader of a robot file's collision keys (see :func:`read_collision_keys_with`)."""
    if _collision_keys is None:
        raise RobotDefinitionError.of("no reader of the collision keys is plugged in (armkit/__init__.py does it)")
    return _collision_keys()

REVOLUTE: Literal["revolute"] = "revolute"
PRISMATIC: Literal["prismatic"] = "prismatic"
CONVENTIONS = ("standard", "modified", "urdf")
DH_CONVENTIONS = ("standard", "modified")
UNITS = {"m": 1.0, "mm": 1e-3, "cm": 1e-2}

Array = NDArray[np.float64]


def _rz(t: float) -> Array:
    c, s = math.cos(t), math.sin(t)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])


def _rx(t: float) -> Array:
    c, s = math.cos(t), math.sin(t)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def _tz(d: float) -> Array:
    T = np.eye(4)
    T[2, 3] = d
    return T


def _tx(a: float) -> Array:
    T = np.eye(4)
    T[0, 3] = a
    return T


def _real(v: object) -> float:
    """A real number as a float; NaN for anything else (bools, strings, complex, ints beyond float range)."""
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, float, np.integer, np.floating)):
        return math.nan
    try:
        return float(v)
    except OverflowError:
        return math.nan


@dataclass(frozen=True)
class Joint:
    """One row of a DH table.

    For a revolute joint ``theta`` is the constant offset added to ``q`` and ``d`` is
    fixed; for a prismatic joint ``d`` is the offset added to ``q`` and ``theta`` is fixed.
    ``alpha`` and ``a`` are the link twist and length (standard DH: of this row's link;
    modified DH: of the previous link, Craig's ``alpha_{i-1}, a_{i-1}``).

    Angles are radians, lengths in the robot's unit. ``lower``/``upper`` are the joint
    limits in radians (revolute) or length units (prismatic).
    """

    kind: Literal["revolute", "prismatic"] = REVOLUTE
    theta: float = 0.0
    d: float = 0.0
    a: float = 0.0
    alpha: float = 0.0
    lower: float = -math.pi
    upper: float = math.pi
    name: str = ""
    origin: tuple[tuple[float, ...], ...] | None = None
    axis: tuple[float, float, float] | None = None

    def __post_init__(self) -> None:
        if self.kind not in (REVOLUTE, PRISMATIC):
            raise RobotDefinitionError.of("joint {name!r}: type must be 'revolute' or 'prismatic', got {got!r}",
                                          name=self.name, got=self.kind)
        for fname in ("theta", "d", "a", "alpha", "lower", "upper"):
            v = getattr(self, fname)   # NumPy scalars are numbers too; stored as Python floats
            x = _real(v)
            if fname in ("lower", "upper"):
                if math.isnan(x):
                    raise RobotDefinitionError.of("joint {name!r}: lower limit must be a number, got {got}"
                                                  if fname == "lower" else
                                                  "joint {name!r}: upper limit must be a number, got {got}",
                                                  name=self.name, got=f"{v!r:.60}")
            elif not math.isfinite(x):
                raise RobotDefinitionError.of("joint {name!r}: {field} must be a finite number, got {got}",
                                              name=self.name, field=fname, got=f"{v!r:.60}")
            object.__setattr__(self, fname, x)
        if self.lower > self.upper:
            raise RobotDefinitionError.of("joint {name!r}: lower limit {lower} is greater than upper limit {upper}",
                                          name=self.name, lower=f"{self.lower:g}", upper=f"{self.upper:g}")
        if self.origin is not None or self.axis is not None:
            self._check_general()

    def _check_general(self) -> None:
        """Validate and normalise ``origin``/``axis`` of a joint given as origin + axis (URDF)."""
        if any(getattr(self, f) != 0.0 for f in ("theta", "d", "a", "alpha")):
            raise RobotDefinitionError.of("joint {name!r}: give either DH parameters or origin + axis, not both",
                                          name=self.name)
        origin = _pose(np.eye(4) if self.origin is None else self.origin, f"joint {self.name!r}: origin")
        try:
            axis = np.array((0.0, 0.0, 1.0) if self.axis is None else self.axis, dtype=float)
        except (TypeError, ValueError):
            raise RobotDefinitionError.of("joint {name!r}: axis must be 3 numbers, got {got!r}", name=self.name,
                                          got=self.axis) from None
        if axis.shape != (3,) or not np.all(np.isfinite(axis)):
            raise RobotDefinitionError.of("joint {name!r}: axis must be 3 finite numbers, got {got!r}", name=self.name,
                                          got=self.axis)
        # Normalised without overflow (issue 24): divided by its largest component first, so a huge but finite
        # axis such as (0, 0, 1e200) is the direction it names, (0, 0, 1); np.linalg.norm squared it to inf and
        # the axis became (0, 0, 0) silently. Only a zero (length under 1e-9), NaN or infinite axis is an error.
        scale = float(np.max(np.abs(axis)))
        unit = axis / scale if scale > 0.0 else axis
        length = float(np.linalg.norm(unit))         # between 1 and sqrt(3): no overflow, no underflow
        if scale * length < 1e-9:
            raise RobotDefinitionError.of("joint {name!r}: axis {axis} has zero length; a joint needs a direction to "
                                          "turn about or slide along", name=self.name, axis=tuple(axis.tolist()))
        axis = unit / length
        object.__setattr__(self, "origin", tuple(tuple(float(v) for v in row) for row in origin))
        object.__setattr__(self, "axis", (float(axis[0]), float(axis[1]), float(axis[2])))

    @property
    def is_prismatic(self) -> bool:
        return self.kind == PRISMATIC

    @property
    def is_general(self) -> bool:
        """True for a joint given as origin + axis (URDF) rather than a DH row."""
        return self.origin is not None

    @property
    def is_continuous(self) -> bool:
        """A revolute joint without limits (URDF ``continuous``)."""
        return not self.is_prismatic and math.isinf(self.lower) and math.isinf(self.upper)

    def origin_matrix(self) -> Array:
        """``origin`` as a ``(4, 4)`` array (identity for a DH joint)."""
        return np.eye(4) if self.origin is None else np.array(self.origin, dtype=float)

    def axis_vector(self) -> Array:
        """The unit joint axis ``(3,)`` in the joint frame (z for a DH joint)."""
        return np.array((0.0, 0.0, 1.0) if self.axis is None else self.axis, dtype=float)


def axis_alignment(axis: ArrayLike) -> Array:
    """A rotation ``A`` ``(4, 4)`` whose z column is the unit vector ``axis``.

    Built from coordinate axes so that axis-aligned inputs give exact 0/1 entries
    (no ``cos(pi/2) = 6e-17``): ``Rot(axis, q) = A Rz(q) A^T``.

    >>> axis_alignment([1.0, 0.0, 0.0])[:3, :3]
    array([[0., 0., 1.],
           [1., 0., 0.],
           [0., 1., 0.]])
    """
    z = np.asarray(axis, dtype=float)
    h = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = h - (h @ z) * z
    x = x / np.linalg.norm(x)
    y = np.cross(z, x)
    A = np.eye(4)
    A[:3, 0], A[:3, 1], A[:3, 2] = x, y, z
    return A


@dataclass(frozen=True, eq=False)
class Shape:
    """One piece of visual or collision geometry attached to a link (from URDF).

    Attributes
    ----------
    kind : {"box", "cylinder", "sphere", "mesh"}
    origin : ndarray, shape (4, 4)
        Pose of the shape in its link's frame.
    size : tuple of float
        box: full extents ``(x, y, z)``; cylinder: ``(radius, length)`` along local z;
        sphere: ``(radius,)``; mesh: ``()``.
    mesh_path : str or None
        The mesh file found on disk (absolute), or ``None`` when it could not be found.
    mesh_uri : str
        The file name as written in the URDF (``package://...``), empty for primitives.
    scale : tuple of 3 floats
    rgba : tuple of 4 floats or None
    """

    kind: str
    origin: Array
    size: tuple[float, ...] = ()
    mesh_path: str | None = None
    mesh_uri: str = ""
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0)
    rgba: tuple[float, float, float, float] | None = None


@dataclass(frozen=True, eq=False)
class Link:
    """A named link of the model and where it sits on the chain.

    Attributes
    ----------
    name : str
    frame : int
        Index into :func:`armkit.fk_frames` (``0`` the base, ``k`` the child link of moving
        joint ``k``, ``n`` the tool frame) of the frame this link is fixed to.
    offset : ndarray, shape (4, 4)
        Pose of the link in that frame: ``T_world_link = fk_frames(q)[frame] @ offset``.
    parent, joint : str or None
        The parent link and the joint connecting it (URDF); ``None`` for the root.
    joint_origin : ndarray, shape (4, 4) or None
        That joint's origin in the parent link (kept to write the URDF back).
    visuals, collisions : tuple of Shape
    """

    name: str
    frame: int
    offset: Array
    parent: str | None = None
    joint: str | None = None
    joint_origin: Array | None = None
    visuals: tuple[Shape, ...] = ()
    collisions: tuple[Shape, ...] = ()


@dataclass(frozen=True)
class Chain:
    """The uniform compiled form used by every kernel (see the module docstring).

    Attributes
    ----------
    pre, post : ndarray, shape (n, 4, 4)
    prismatic : ndarray of bool, shape (n,)
    base, tool : ndarray, shape (4, 4)
    fixed : ndarray, shape (n + 1, 4, 4)
        ``base·pre_1``, ``post_1·pre_2``, ..., ``post_n·tool``: what plain FK needs.
    """

    pre: Array
    post: Array
    prismatic: NDArray[np.bool_]
    base: Array
    tool: Array
    fixed: Array

    @classmethod
    def build(cls, pre: Array, post: Array, prismatic: NDArray[np.bool_], base: Array, tool: Array) -> "Chain":
        n = len(prismatic)
        fixed = np.empty((n + 1, 4, 4))
        fixed[0] = base @ pre[0]
        for k in range(1, n):
            fixed[k] = post[k - 1] @ pre[k]
        fixed[n] = post[n - 1] @ tool
        pre, post, base, tool, fixed = (np.ascontiguousarray(x, dtype=float) for x in (pre, post, base, tool, fixed))
        prismatic = np.ascontiguousarray(prismatic, dtype=bool)
        for x in (pre, post, prismatic, base, tool, fixed):
            x.setflags(write=False)
        return cls(pre, post, prismatic, base, tool, fixed)


def _pose(value: ArrayLike | None, what: str) -> Array:
    """A read-only copy of one pose of the robot's definition, checked by :func:`armkit.spatial.check_transform`
    (its message, as a :class:`RobotDefinitionError`)."""
    if value is None:
        T = np.eye(4)
    else:
        try:
            T = np.array(real_array(value, what), dtype=float)
            if T.shape != (4, 4):
                raise RobotDefinitionError.of("{what} must be a 4x4 pose, got shape {shape}", what=what, shape=T.shape)
            check_transform(T, what=what)
        except ShapeError as exc:
            keyed = getattr(exc, "fields", None)     # its template and fields, when it has them
            raise (RobotDefinitionError.of(exc.template, **keyed) if isinstance(keyed, dict) and keyed  # type: ignore[attr-defined]
                   else RobotDefinitionError(str(exc))) from None
    T.setflags(write=False)
    return T


def _array_value(a: ArrayLike | None) -> tuple[Any, ...] | None:
    """An array as (shape, values): equal exactly when the arrays are (``-0.0 == 0.0``), hashable."""
    if a is None:
        return None
    arr = np.asarray(a)
    return (arr.shape, tuple(arr.ravel().tolist()))


def _shape_value(s: Shape) -> tuple[Any, ...]:
    return (s.kind, _array_value(s.origin), tuple(s.size), s.mesh_path, s.mesh_uri, tuple(s.scale),
            None if s.rgba is None else tuple(s.rgba))


def _link_value(lk: Link) -> tuple[Any, ...]:
    return (lk.name, lk.frame, _array_value(lk.offset), lk.parent, lk.joint, _array_value(lk.joint_origin),
            tuple(_shape_value(s) for s in lk.visuals), tuple(_shape_value(s) for s in lk.collisions))


@dataclass(frozen=True, eq=False)
class Robot:
    """An immutable serial arm described by a DH table.

    Parameters
    ----------
    joints : sequence of Joint
        One DH row per joint, base to tip.
    convention : {"standard", "modified"}
        ``standard``: ``A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)`` (Denavit-Hartenberg,
        Spong, the club's fighting-robot report). ``modified``: ``A_i = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i)``
        (Craig, the modified-DH lecture).
    name, description, source : str
    unit : {"m", "mm", "cm"}
        Length unit of ``d``, ``a``, base/tool translations and every result.
    base, tool : array_like, shape (4, 4), optional
        ``T_world_base`` and ``T_lastlink_tool``; identity by default.

    Attributes
    ----------
    cache : dict
        The one per-robot cache: data *derived* from the fields above and kept so that it is
        computed once per robot (the closed-form solver, the LM constants, the DH twins,
        collision geometry, ...). Keys are short names chosen by the module that fills them
        (``"closed_form"``, ``"lm_constants"``, ...). It is never stale because a Robot is
        immutable; clearing it only costs recomputation. It takes no part in equality,
        hashing or ``repr``. Nothing but derived data belongs in it.

    Notes
    -----
    Two robots are equal (and hash equal) when their values are: joints, convention, name,
    unit, base and tool (exactly, element by element), description, source, link names,
    links (name, frame, offset, parent, joint, joint origin and shapes) and ignored joints.
    Two declared fields are not part of the value: ``collision``, the robot file's collision keys
    (``link_radius``, ``allow_collision``, ``[[body]]``, ``[[scene]]``) as read by
    :mod:`armkit.collision.robot_file` (None without them), and ``loaded_from``, the resolved path
    :func:`armkit.load` read the robot from (:func:`armkit.save` refuses to write onto it).

    Examples
    --------
    >>> import math
    >>> arm = Robot([Joint(a=1.0), Joint(a=0.5)], name="two-link")
    >>> arm == Robot([Joint(a=1.0), Joint(a=0.5)], name="two-link")
    True
    >>> arm.n, arm.joint_names
    (2, ('q1', 'q2'))
    >>> Robot([], name="empty")
    Traceback (most recent call last):
    ...
    armkit.errors.RobotDefinitionError: robot 'empty' has no joints; a serial arm needs at least one
    """

    joints: tuple[Joint, ...]
    convention: Literal["standard", "modified"] = "standard"
    name: str = "robot"
    unit: str = "m"
    base: Array = field(default_factory=lambda: np.eye(4))
    tool: Array = field(default_factory=lambda: np.eye(4))
    description: str = ""
    source: str = ""
    link_names: tuple[str, ...] = ()
    links: tuple[Link, ...] = ()
    ignored_joints: tuple[str, ...] = ()
    chain: Chain = field(init=False, repr=False, compare=False)
    cache: dict[str, Any] = field(init=False, repr=False, compare=False)
    _lower: Array = field(init=False, repr=False, compare=False)   # read-only (n,): the property lower
    _upper: Array = field(init=False, repr=False, compare=False)
    collision: Any = field(default=None, init=False, repr=False, compare=False)
    loaded_from: str | None = field(default=None, init=False, repr=False, compare=False)

    def __init__(self, joints: Sequence[Joint], convention: str = "standard", name: str = "robot",
                 unit: str = "m", base: ArrayLike | None = None, tool: ArrayLike | None = None,
                 description: str = "", source: str = "", link_names: Sequence[str] = (),
                 links: Sequence[Link] = (), ignored_joints: Sequence[str] = ()) -> None:
        joints = tuple(joints)
        if len(joints) == 0:
            raise RobotDefinitionError.of("robot {name!r} has no joints; a serial arm needs at least one", name=name)
        if not all(isinstance(j, Joint) for j in joints):
            raise RobotDefinitionError.of("joints must be armkit.Joint objects")
        for what, text in (("name", name), ("description", description), ("source", source)):
            if not isinstance(text, str):
                raise RobotDefinitionError.of("{what} must be a string, got {kind}", what=what,
                                              kind=type(text).__name__)
        if not isinstance(convention, str) or convention not in CONVENTIONS:
            raise RobotDefinitionError.of("convention must be one of {names}, got {got!r}", names=CONVENTIONS,
                                          got=convention)
        if not isinstance(unit, str) or unit not in UNITS:
            raise RobotDefinitionError.of("unit must be one of {names}, got {got!r}", names=tuple(UNITS), got=unit)
        general = [j.is_general for j in joints]
        if convention == "urdf" and not all(general):
            raise RobotDefinitionError.of("convention 'urdf' needs every joint given as origin + axis")
        if convention != "urdf" and any(general):
            raise RobotDefinitionError.of("convention {convention!r} needs DH rows; joints with origin + axis belong "
                                          "to convention 'urdf'", convention=convention)
        joints = tuple(j if j.name else Joint(j.kind, j.theta, j.d, j.a, j.alpha, j.lower, j.upper, f"q{i + 1}",
                                              j.origin, j.axis)
                       for i, j in enumerate(joints))
        names = [j.name for j in joints]
        if len(set(names)) != len(names):
            raise RobotDefinitionError.of("joint names must be unique, got {names}", names=names)
        if isinstance(link_names, str) or not all(isinstance(x, str) for x in link_names):
            raise RobotDefinitionError.of("link_names must be a sequence of strings (base link + one per joint), "
                                          "got {got}", got=f"{link_names!r:.80}")
        link_names = tuple(link_names) or tuple(f"link{i}" for i in range(len(joints) + 1))
        if len(link_names) != len(joints) + 1:
            raise RobotDefinitionError.of("link_names needs {n} names (base link + one per joint), got {got}",
                                          n=len(joints) + 1, got=len(link_names))
        set_ = object.__setattr__
        set_(self, "cache", {})
        set_(self, "joints", joints)
        set_(self, "convention", convention)
        set_(self, "name", name)
        set_(self, "unit", unit)
        set_(self, "base", _pose(base, "base"))
        set_(self, "tool", _pose(tool, "tool"))
        set_(self, "description", description)
        set_(self, "source", source)
        set_(self, "link_names", link_names)
        set_(self, "chain", self._compile())
        links = tuple(links)
        if not links:   # one link per chain frame; the last one sits before the tool
            tool_inv = np.array(np.linalg.inv(self.tool), dtype=np.float64)
            links = tuple(Link(nm, k, np.eye(4) if k < len(joints) else tool_inv, None if k == 0 else link_names[k - 1],
                               None if k == 0 else joints[k - 1].name)
                          for k, nm in enumerate(link_names))
        elif not all(isinstance(lk, Link) and 0 <= lk.frame <= len(joints) for lk in links):
            raise RobotDefinitionError.of("links must be armkit.model.Link objects with frame in 0..n")
        link_index = {lk.name: i for i, lk in enumerate(links)}
        if len(link_index) != len(links):
            raise RobotDefinitionError.of("link names must be unique, got {names}", names=[lk.name for lk in links])
        set_(self, "links", links)
        self.cache["link_index"] = link_index
        set_(self, "ignored_joints", tuple(ignored_joints))
        for attr, vals in (("_lower", [j.lower for j in joints]), ("_upper", [j.upper for j in joints])):
            arr = np.array(vals, dtype=float)
            arr.setflags(write=False)
            set_(self, attr, arr)

    # ------------------------------------------------------------------ compile
    def _compile(self) -> Chain:
        n = self.n
        pre = np.empty((n, 4, 4))
        post = np.empty((n, 4, 4))
        for i, j in enumerate(self.joints):
            if j.is_general:         # origin · A · M(q) · A^T  =  origin · Rot/Trans(axis, q)
                A = axis_alignment(j.axis_vector())
                pre[i] = j.origin_matrix() @ A
                post[i] = A.T
                continue
            # offsets commute with the joint motion (Rz with Rz, Tz with Tz), so they fold into constants
            if self.convention == "standard":
                if j.is_prismatic:   # Tz(q) · Rz(theta) Tz(d) Tx(a) Rx(alpha)
                    pre[i] = np.eye(4)
                    post[i] = _rz(j.theta) @ _tz(j.d) @ _tx(j.a) @ _rx(j.alpha)
                else:                # Rz(theta) · Rz(q) · Tz(d) Tx(a) Rx(alpha)
                    pre[i] = _rz(j.theta)
                    post[i] = _tz(j.d) @ _tx(j.a) @ _rx(j.alpha)
            else:                    # Rx(alpha) Tx(a) Rz(theta) Tz(d) · M(q)
                pre[i] = _rx(j.alpha) @ _tx(j.a) @ _rz(j.theta) @ _tz(j.d)
                post[i] = np.eye(4)
        prismatic = np.array([j.is_prismatic for j in self.joints])
        return Chain.build(pre, post, prismatic, np.asarray(self.base), np.asarray(self.tool))

    # --------------------------------------------------------------- properties
    @property
    def n(self) -> int:
        """Number of joints (degrees of freedom)."""
        return len(self.joints)

    @property
    def joint_names(self) -> tuple[str, ...]:
        return tuple(j.name for j in self.joints)

    @property
    def joint_types(self) -> str:
        """One letter per joint, e.g. ``"RRPRRR"``."""
        return "".join("P" if j.is_prismatic else "R" for j in self.joints)

    @property
    def prismatic(self) -> NDArray[np.bool_]:
        return self.chain.prismatic

    @property
    def lower(self) -> Array:
        """Lower joint limits, shape ``(n,)`` (rad or length units), read-only."""
        return self._lower

    @property
    def upper(self) -> Array:
        """Upper joint limits, shape ``(n,)``, read-only."""
        return self._upper

    @property
    def is_dh(self) -> bool:
        """True for a robot written as a DH table (standard or modified), false for URDF chains."""
        return self.convention in DH_CONVENTIONS

    @property
    def reach(self) -> float:
        """An upper bound on the distance from the first joint axis to the tool (length units)."""
        total = math.hypot(*(float(v) for v in self.tool[:3, 3]))     # hypot: no overflow on huge components
        if not self.is_dh:
            for j in self.joints:
                total += math.hypot(*(float(v) for v in j.origin_matrix()[:3, 3]))
                if j.is_prismatic:
                    total += max(abs(v) for v in (j.lower, j.upper) if math.isfinite(v)) if (
                        math.isfinite(j.lower) or math.isfinite(j.upper)) else 0.0
            return total
        for j in self.joints:
            d_max = max(abs(j.lower + j.d), abs(j.upper + j.d)) if j.is_prismatic else abs(j.d)
            total += math.hypot(j.a, d_max if math.isfinite(d_max) else 0.0)
        return total

    @property
    def unit_scale(self) -> float:
        """Metres per length unit (1 for m, 0.001 for mm)."""
        return UNITS[self.unit]

    def dh_table(self) -> Array:
        """The DH table as an ``(n, 4)`` array of columns ``(theta, d, a, alpha)`` (rad, length).

        For a URDF chain: the table of its standard-DH twin :meth:`to_dh`.
        """
        if not self.is_dh:
            return self.to_dh().dh_table()
        return np.array([[j.theta, j.d, j.a, j.alpha] for j in self.joints])

    def to_dh(self, convention: Literal["standard", "modified"] = "standard") -> "Robot":
        """An equivalent DH robot: the same FK for every ``q`` (to rounding), base and tool absorbing the rest.

        Works for any serial chain (URDF arms, or a DH arm in the other convention). Joint
        names, kinds and limits carry over; link frames follow the DH rules. The choices
        made where DH leaves freedom (parallel axes, intersecting axes, prismatic axes, the
        last frame) are listed in ``docs/urdf.md``.

        Raises
        ------
        RobotDefinitionError
            If two consecutive axes are so close to parallel (but not parallel) that no DH
            table reproduces the chain to 1e-9 of its reach.

        Examples
        --------
        >>> import armkit, numpy as np
        >>> ur5 = armkit.load("ur5")
        >>> twin = ur5.to_dh("modified")
        >>> q = ur5.random_q(rng=1)
        >>> bool(np.allclose(armkit.fk(twin, q), armkit.fk(ur5, q), atol=1e-12))
        True
        """
        if convention not in DH_CONVENTIONS:
            raise RobotDefinitionError.of("convention must be 'standard' or 'modified', got {got!r}", got=convention)
        if convention == self.convention:
            return self
        key = "dh twin " + convention
        twin = self.cache.get(key)
        if twin is None:
            from .dh_extract import chain_to_dh

            twin = self.cache[key] = chain_to_dh(self, convention)
            if self.collision is not None:   # the surroundings go with it (issue 24)
                collision_keys().carry_collision(self, twin)
        return twin  # type: ignore[no-any-return]

    def link_index(self, name: str) -> int:
        """Index of link ``name`` in :attr:`links`; the error lists the link names."""
        index = self.cache.get("link_index")
        if index is None:
            index = self.cache["link_index"] = {lk.name: i for i, lk in enumerate(self.links)}
        try:
            return index[name]  # type: ignore[no-any-return]
        except KeyError:
            names = [lk.name for lk in self.links]
            shown = ", ".join(names[:40]) + (f", ... ({len(names)} links)" if len(names) > 40 else "")
            raise RobotDefinitionError.of("robot {robot!r} has no link {link!r}; its links are: {names}",
                                          robot=self.name, link=name, names=shown) from None

    # ------------------------------------------------------------- validation
    def check_q(self, q: ArrayLike, what: str = "q") -> Array:
        """``q`` as a float array of shape ``(..., n)``; raise :class:`ShapeError` otherwise."""
        arr = real_array(q, what)    # complex, masked, non-numeric and too-large values are errors, not dropped
        if arr.ndim == 0 or arr.shape[-1] != self.n:
            raise ShapeError.of("{what} must have shape (..., {n}) for robot {robot!r}, got {shape}", what=what,
                                n=self.n, robot=self.name, shape=arr.shape)
        if not np.all(np.isfinite(arr)):
            raise ShapeError.of("{what} contains NaN or infinite values", what=what)
        return arr

    def within_limits(self, q: ArrayLike, tol: float = 1e-12) -> NDArray[np.bool_]:
        """True where every joint of ``q`` ``(..., n)`` lies inside its limits; shape ``(...)``."""
        arr = self.check_q(q)
        return np.all((arr >= self.lower - tol) & (arr <= self.upper + tol), axis=-1)

    def limit_violations(self, q: ArrayLike) -> list[str]:
        """Readable descriptions of the joints of one configuration ``(n,)`` that break their limits."""
        arr = self.check_q(q)
        out: list[str] = []
        for j, v in zip(self.joints, arr.reshape(-1, self.n)[0]):
            if v < j.lower - 1e-12 or v > j.upper + 1e-12:
                if j.is_prismatic:     # a template and its fields: the sentence in the user's language
                    out.append(Fielded.of("{joint} = {value} {unit} outside [{lower}, {upper}] {unit}", joint=j.name,
                                          value=f"{v:g}", unit=self.unit, lower=f"{j.lower:g}", upper=f"{j.upper:g}"))
                else:
                    out.append(Fielded.of("{joint} = {value} {unit} outside [{lower}, {upper}] {unit}", joint=j.name,
                                          value=f"{math.degrees(v):.3f}", unit="deg",
                                          lower=f"{math.degrees(j.lower):.3f}", upper=f"{math.degrees(j.upper):.3f}"))
        return out

    def random_q(self, count: int | None = None, rng: np.random.Generator | int | None = None) -> Array:
        """Uniform random configurations inside the limits, shape ``(count, n)`` or ``(n,)``."""
        g = np.random.default_rng(rng)
        lo = np.where(np.isfinite(self.lower), self.lower, -math.pi)
        hi = np.where(np.isfinite(self.upper), self.upper, math.pi)
        shape = (self.n,) if count is None else (count, self.n)
        return g.uniform(lo, hi, size=shape)

    def with_tool(self, tool: ArrayLike) -> "Robot":
        """A copy of this robot with another tool transform."""
        new_tool = _pose(tool, "tool")
        shift = np.linalg.inv(new_tool) @ self.tool    # links fixed to the tool frame keep their world pose
        links = tuple(lk if lk.frame < self.n else replace(lk, offset=shift @ lk.offset) for lk in self.links)
        return Robot(self.joints, self.convention, self.name, self.unit, self.base, new_tool,
                     self.description, self.source, self.link_names, links, self.ignored_joints)

    # ------------------------------------------------------------- value semantics
    def _value(self) -> tuple[Any, ...]:
        """Everything that makes this robot what it is, as nested tuples of plain values (kept in the cache)."""
        key = self.cache.get("value")
        if key is None:
            key = self.cache["value"] = (
                self.joints, self.convention, self.name, self.unit, _array_value(self.base),
                _array_value(self.tool), self.description, self.source, self.link_names,
                tuple(_link_value(lk) for lk in self.links), self.ignored_joints)
        return key  # type: ignore[no-any-return]

    def __eq__(self, other: object) -> bool:
        if self is other:
            return True
        if not isinstance(other, Robot):
            return NotImplemented
        return self._value() == other._value()

    def __hash__(self) -> int:
        h = self.cache.get("hash")
        if h is None:
            h = self.cache["hash"] = hash(self._value())
        return h  # type: ignore[no-any-return]

    def __getstate__(self) -> dict[str, Any]:
        # the memoised hash depends on this process's string hashing: another process recomputes it
        state = dict(self.__dict__)
        state["cache"] = {k: v for k, v in self.cache.items() if k != "hash"}
        return state

    def __repr__(self) -> str:
        kind = f"{self.convention} DH" if self.is_dh else "URDF chain"
        return f"Robot({self.name!r}, {self.n} DOF {self.joint_types}, {kind}, unit={self.unit!r})"
