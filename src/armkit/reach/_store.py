"""What a reachability store may hold, checked before anything is read, written or deleted.

A map store comes from outside as often as from this machine (a map built on a cluster, a
download), so nothing in it is trusted:

* :func:`read_attrs` reads the group's ``zarr.json`` itself (size-limited) and checks the
  format marker, the status and the attribute types;
* :func:`robot_of` parses the stored robot file *text* without writing a file;
* :func:`grid_of` checks the grid and the memory a map of that size needs (``ARMKIT_MEMORY_LIMIT``);
* :func:`load_arrays` checks each array's presence, dtype and shape, then its checksum (a
  deleted or damaged chunk would otherwise read as zeros: "unreachable");
* :func:`check_overwrite` lets ``overwrite=True`` delete only a folder that is an armkit store
  and holds nothing but what a store holds.

Every refusal is a :class:`~armkit.errors.MapFileError` (or ``ReachabilityError`` when building)
naming the store and what is wrong; the store is never modified by a check.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import warnings
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._limits import check_memory
from ..errors import ArmkitError, MapFileError, ReachabilityError, warning_of
from ..model.files import MAX_FILE_BYTES, _parse
from ..model.robot import Robot
from ..spatial import check_transform
from ._grid import Grid

__all__ = ["FORMAT", "OLD_FORMATS", "ARRAYS", "checksum", "read_attrs", "robot_of", "grid_of", "load_arrays",
           "check_overwrite", "clean_partial", "robot_sha256", "settings_sha256"]

FORMAT = "armkit.reachability/2"
"""Version 2 added the checksums of the arrays and the fingerprint of the stored robot."""
OLD_FORMATS = ("armkit.reachability/1",)

ARRAYS: dict[str, tuple[Any, int]] = {"counts": (np.uint8, 4), "hits": (np.bool_, 4),
                                      "manipulability": (np.float32, 3), "index": (np.float32, 3)}
"""The arrays of a complete map: dtype, and 4 (one value per cell) or 3 (one per voxel) dimensions."""

MAX_ATTRS_BYTES = 64 * 1024 ** 2
"""A group's ``zarr.json`` larger than this is refused unread (a robot file is at most 16 MiB)."""

_GENERATION = re.compile(r"(counts|manipulability)_[0-9]{1,9}")


def checksum(a: NDArray[Any]) -> str:
    """SHA-256 of an array's bytes (C order) with its dtype and shape."""
    a = np.ascontiguousarray(a)
    h = hashlib.sha256(f"{a.dtype.str}{a.shape}".encode())
    h.update(memoryview(a).cast("B"))  # type: ignore[arg-type]
    return h.hexdigest()


def robot_sha256(text: str) -> str:
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def settings_sha256(grid: Any, parameters: Any) -> str:
    """Fingerprint of the grid and the build parameters: an edited grid would answer for other places."""
    text = json.dumps({"grid": grid, "parameters": parameters}, sort_keys=True, default=str)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def _group_json(path: Path) -> dict[str, Any] | None:
    """The group's metadata document, or None when ``path`` holds no readable Zarr v3 group."""
    meta = path / "zarr.json"
    try:
        if not meta.is_file() or meta.is_symlink() or meta.stat().st_size > MAX_ATTRS_BYTES:
            return None
        doc = json.loads(meta.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError, RecursionError):
        return None
    if not isinstance(doc, dict) or doc.get("node_type") != "group" or not isinstance(doc.get("attributes"), dict):
        return None
    return doc


def read_attrs(path: str | os.PathLike[str], *, complete: bool = True) -> dict[str, Any]:
    """The attributes of the armkit map at ``path``, checked (MapFileError names what is wrong)."""
    p = Path(path)
    shown = os.fspath(path)
    try:
        exists, folder = p.exists(), p.is_dir()
    except (OSError, ValueError):     # a name the system cannot look up (too long: ENAMETOOLONG; a NUL byte)
        exists = folder = False
    if not exists:
        raise MapFileError.of("no reachability map at {shown!r}", shown=shown)
    if not folder:
        raise MapFileError.of("{shown!r} is a file; a reachability map is a folder (a Zarr store)", shown=shown)
    doc = _group_json(p)
    if doc is None:
        raise MapFileError.of("{shown!r} is not a Zarr reachability map (no readable zarr.json group metadata)",
                              shown=shown)
    attrs: dict[str, Any] = doc["attributes"]
    fmt = attrs.get("format")
    if fmt in OLD_FORMATS:
        raise MapFileError.of("{shown!r} was written by an older armkit (format {fmt!r}, without checksums); build it "
                              "again with armkit reach build ... --overwrite", shown=shown, fmt=fmt)
    if fmt != FORMAT:
        raise MapFileError.of("{shown!r} is not an armkit reachability map (format {fmt!r}, expected {expected!r})",
                              shown=shown, fmt=str(fmt)[:60], expected=FORMAT)
    if complete and attrs.get("status") != "complete":
        raise MapFileError.of("{shown!r} holds an unfinished build; run the same build again to resume it", shown=shown)
    for key, kind in (("robot", str), ("robot_toml", str), ("robot_sha256", str), ("grid", dict),
                      ("parameters", dict), ("settings_sha256", str)):
        if not isinstance(attrs.get(key), kind):
            raise MapFileError.of("{shown!r}: attribute {key!r} is missing or not a {kind}", shown=shown, key=key,
                                  kind=kind.__name__)
    if complete and not isinstance(attrs.get("checksums"), dict):
        raise MapFileError.of("{shown!r}: attribute 'checksums' is missing", shown=shown)
    return attrs


def robot_of(attrs: dict[str, Any], path: str) -> Robot:
    """The stored robot, parsed from its text (no file is written), checked against its fingerprint and name."""
    text = attrs["robot_toml"]
    if len(text) > MAX_FILE_BYTES:
        raise MapFileError.of("{path!r}: the stored robot file has {n:,} characters (at most {limit:,})",
                              path=path, n=len(text), limit=MAX_FILE_BYTES)
    if robot_sha256(text) != attrs["robot_sha256"]:
        raise MapFileError.of("{path!r}: the stored robot does not match its fingerprint (robot_sha256); the store was "
                              "edited or damaged", path=path)
    try:
        robot = _parse(text, f"{path} (stored robot)")
    except ArmkitError as exc:
        raise MapFileError.of("{path!r}: the stored robot cannot be read: {exc}", path=path, exc=exc) from None
    if robot.name != attrs["robot"]:
        raise MapFileError.of("{path!r}: the store names robot {stored!r} but holds robot {robot!r}", path=path,
                              stored=attrs["robot"][:60], robot=robot.name[:60])
    return robot


def grid_of(attrs: dict[str, Any], path: str) -> Grid:
    """The stored grid, checked (fingerprint, types, a rigid frame), and its memory against the budget."""
    if settings_sha256(attrs["grid"], attrs["parameters"]) != attrs["settings_sha256"]:
        raise MapFileError.of("{path!r}: the stored grid or parameters do not match their fingerprint "
                              "(settings_sha256); the store was edited or damaged", path=path)
    a = attrs["grid"]

    def numbers(v: Any) -> bool:
        return not isinstance(v, bool) and (isinstance(v, (int, float)) or
                                            (isinstance(v, list) and all(numbers(x) for x in v)))
    if not all(numbers(a.get(k)) for k in ("T_world_A", "lo", "resolution", "dims", "directions", "rolls")) \
            or not isinstance(a.get("symmetric"), bool):
        raise MapFileError.of("{path!r}: the stored grid is not valid", path=path)
    try:
        grid = Grid.from_attrs(attrs["grid"])
        ok = (grid.T_world_A.shape == (4, 4) and bool(np.all(np.isfinite(grid.T_world_A)))
              and grid.lo.shape == (3,) and bool(np.all(np.isfinite(grid.lo)))
              and np.isfinite(grid.resolution) and grid.resolution > 0 and len(grid.dims) == 3
              and all(d >= 1 for d in grid.dims) and grid.directions >= 1 and grid.rolls >= 1
              and (not grid.symmetric or grid.dims[1] == 1))
        if ok:
            check_transform(grid.T_world_A, what="the grid's frame")
    except (KeyError, TypeError, ValueError, OverflowError):     # NotRigidError and ShapeError are ValueErrors
        ok = False
    if not ok:
        raise MapFileError.of("{path!r}: the stored grid is not valid", path=path)
    cells = float(np.prod([float(d) for d in grid.shape]))
    voxels = float(np.prod([float(d) for d in grid.dims]))
    # counts + hits + the flat copy of hits, and the per-voxel manipulability, index and boundary work
    check_memory(3 * cells + 12 * voxels, f"reading the map {path!r}")
    return grid


def load_arrays(group: Any, attrs: dict[str, Any], grid: Grid, path: str) -> dict[str, NDArray[Any]]:
    """Read every array of a complete map, checking presence, dtype, shape and checksum."""
    sums = attrs["checksums"]
    out: dict[str, NDArray[Any]] = {}
    for name, (dtype, ndim) in ARRAYS.items():
        shape = grid.shape if ndim == 4 else grid.dims
        try:
            arr = group[name]
            if tuple(arr.shape) != tuple(shape) or np.dtype(arr.dtype) != np.dtype(dtype):
                raise MapFileError.of("{path!r}: array {name!r} has shape {shape} and dtype {dtype}; the grid needs "
                                      "{needs} and {needs_dtype}", path=path, name=name, shape=tuple(arr.shape),
                                      dtype=arr.dtype, needs=tuple(shape), needs_dtype=np.dtype(dtype))
            data = np.asarray(arr[...])
        except MapFileError:
            raise
        except KeyError:
            raise MapFileError.of("{path!r}: array {name!r} is missing", path=path, name=name) from None
        except Exception as exc:      # zarr and its codecs raise many types for damaged chunks
            raise MapFileError.of("{path!r}: array {name!r} cannot be read ({type})", path=path, name=name,
                                  type=type(exc).__name__) from None
        if checksum(data) != sums.get(name):
            raise MapFileError.of("{path!r}: array {name!r} does not match its checksum: chunks are missing or "
                                  "damaged; build the map again", path=path, name=name)
        out[name] = data
    return out


def _store_entries_ok(p: Path) -> str | None:
    """None when every entry of ``p`` is one a store holds; else the first stranger's name."""
    for entry in sorted(p.iterdir()):
        name = entry.name
        if name == "zarr.json" and entry.is_file() and not entry.is_symlink():
            continue
        if (name in ARRAYS or _GENERATION.fullmatch(name)) and entry.is_dir() and not entry.is_symlink():
            continue
        if name.endswith(".partial") and entry.is_file():
            continue
        return name
    return None


def check_overwrite(path: str | os.PathLike[str]) -> None:
    """Refuse (ReachabilityError, naming it) to let ``overwrite`` delete anything but an armkit map store."""
    p = Path(path)
    shown = os.fspath(path)
    if not os.path.lexists(p):
        return
    if p.is_symlink():
        raise ReachabilityError.of("will not overwrite {shown!r}: it is a symbolic link; remove it yourself",
                                   shown=shown)
    if not p.is_dir():
        raise ReachabilityError.of("will not overwrite {shown!r}: it is a file, not a reachability map", shown=shown)
    real = p.resolve()
    here = Path.cwd().resolve()
    special = {Path("/"), Path.home().resolve()}
    if p.name in ("", ".", "..") or real in special or real == here or real in here.parents:
        raise ReachabilityError.of("will not overwrite {shown!r}: it is the current, home or root folder or one above "
                                   "them; give the map's own folder, e.g. map.zarr", shown=shown)
    doc = _group_json(p)
    fmt = None if doc is None else doc["attributes"].get("format")
    if not (isinstance(fmt, str) and fmt.startswith("armkit.reachability/")):
        raise ReachabilityError.of("will not overwrite {shown!r}: it is not an armkit reachability map (no armkit "
                                   "format marker); delete it yourself or choose another path", shown=shown)
    stranger = _store_entries_ok(p)
    if stranger is not None:
        raise ReachabilityError.of("will not overwrite {shown!r}: it holds {stranger!r}, which is not part of a "
                                   "reachability map; move it away or choose another path", shown=shown,
                                   stranger=stranger[:80])


def clean_partial(path: str | os.PathLike[str]) -> int:
    """Remove the ``*.partial`` files a killed write left in a store (the build owns the store); warn once."""
    removed = 0
    for f in Path(path).rglob("*.partial"):
        try:
            if f.is_file() and not f.is_symlink():
                f.unlink()
                removed += 1
        except OSError:
            pass
    if removed:
        warnings.warn(warning_of("removed {n} unfinished chunk file(s) left in {path!r} by an interrupted write",
                                 n=removed, path=os.fspath(path)), stacklevel=3)
    return removed
