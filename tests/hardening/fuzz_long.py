"""Issue 24, item 8: the fuzz and corruption suite, long run (``make fuzz``; ``make fuzz SEED=123``).

Five surfaces, each a generator of hostile inputs driven by a :class:`random.Random` and a judge that
puts the answer in one outcome class:

``store``  a tiny reachability map (planar2, 0.1 m voxels) copied and corrupted: byte flips and
           truncation of random files, deleted files and arrays, JSON edits of any ``zarr.json``
           (junk types, huge numbers, nested junk, small numeric nudges), chunks swapped between
           arrays, stray files. ``ReachabilityMap.open`` must return the original map or raise
           ``MapFileError``/``LimitError``; ``armkit reach query MAP 1 0 0`` must agree (exit 0/1/2,
           no traceback); the store's bytes must not change.
``urdf``   the bundled ``so101.urdf`` with elements deleted, duplicated or moved, attributes set to
           junk (huge, nan, empty, unicode, entities, paths), DOCTYPEs and text damage.
           ``armkit.load`` must succeed (and then FK of random q is finite) or raise ``ArmkitError``.
``scene``  a scene file with every shape kind, edited as data (junk values) and as text.
           ``load_scene`` must succeed (and a collision query with the fighter then answers) or raise
           ``ArmkitError``.
``cli``    ``reach build/show/query/base``, ``so101 pose``, ``info``, ``view`` (the server is never
           started: ``armkit.viz.view.view`` is replaced by a stub), ``convert`` with option values
           replaced, added, dropped and duplicated: exit 0, 1 or 2 and no traceback.
``commands`` the same for the computing commands: ``fk``, ``jacobian``, ``ik``, ``velocity``, ``singular``,
           ``derive``, ``workspace``, ``maps``, ``traj``, ``track`` and ``plot`` on bundled arms and a URDF, every
           option of each (added 2026-12-05: its first runs found ``maps`` at 6 GB past the 2 GiB memory limit
           and ``singular so101`` running for over 15 minutes). Not in the quick test: one case can take a minute.

Outcome classes: ``ok`` (accepted, and right), ``clean error`` (the documented error), ``traceback``
(any other exception, or "Traceback" in the output), ``hang`` (past the time bound), ``wrong value``
(accepted but not the original map / a non-finite FK / a CLI answer that disagrees with the API),
``modified`` (opening changed the store's files), ``runaway`` (the process's peak memory grew by
more than 1 GiB in one case).

The quick, Hypothesis-driven part (``tests/hardening/test_fuzz_quick.py``, in ``make test``) uses
the same generators and judges. This file is not collected by pytest (no ``test_`` prefix).
Output paths given to writing commands stay inside a scratch folder (the tests may run as root:
an atomic write onto ``/dev/null`` would replace the device).
"""

from __future__ import annotations

import argparse
import contextlib
import copy
import json
import math
import os
import random
import resource
import shutil
import signal
import sys
import tempfile
import time
import traceback
import warnings
import xml.etree.ElementTree as ET
from collections import Counter
from pathlib import Path
from typing import Any, Callable, Iterator

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
SO101 = ROOT / "src" / "armkit" / "robots" / "so101.urdf"
CALIBRATION = ROOT / "examples" / "so101_calibration.json"

OK, CLEAN, TRACEBACK, HANG, WRONG, MODIFIED, RUNAWAY = (
    "ok", "clean error", "traceback", "hang", "wrong value", "modified", "runaway")
OUTCOMES = (OK, CLEAN, TRACEBACK, HANG, WRONG, MODIFIED, RUNAWAY)
BAD = (TRACEBACK, HANG, WRONG, MODIFIED, RUNAWAY)
SURFACES = ("store", "urdf", "scene", "cli", "commands")


# ---------------------------------------------------------------------------------------------- time bound
class Hang(BaseException):
    """Raised by the alarm: a BaseException, so no ``except Exception`` in armkit swallows it."""


@contextlib.contextmanager
def time_limit(seconds: float) -> Iterator[None]:
    """Raise :class:`Hang` after ``seconds`` (main thread only; a no-op elsewhere)."""
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def alarm(signum: int, frame: Any) -> None:
        raise Hang(f"still running after {seconds} s")

    old = signal.signal(signal.SIGALRM, alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def _exc_line(exc: BaseException) -> str:
    tb = traceback.extract_tb(exc.__traceback__)
    where = f" at {Path(tb[-1].filename).name}:{tb[-1].lineno}" if tb else ""
    return f"{type(exc).__name__}: {str(exc)[:300]}{where}"


# ---------------------------------------------------------------------------------------------- junk values
HUGE = [1e308, -1e308, 1.7976931348623157e308, 10 ** 30, -(10 ** 30), 2 ** 63, 2 ** 64 + 1, 10 ** 400]
JSON_JUNK: list[Any] = [None, True, False, 0, -1, 1, 0.5, -0.0, 1e-320, *HUGE, float("nan"), float("inf"),
                        float("-inf"), "", "x", "é☃\u202e\x00", "<b>bold</b>", "1e308", "nan", "x" * 10_000, [],
                        {}, [1, 2, 3], [[[[]]]], {"a": {"b": [1, {"c": None}]}}, [None] * 5, ["a", 1, None],
                        {"": ""}, [0, 0, 0], [1e308, 1e308, 1e308], [-1, -1, -1]]


def _deep(depth: int) -> Any:
    v: Any = 0
    for _ in range(depth):
        v = [v]
    return v


def json_junk(rnd: random.Random, like: Any = None) -> Any:
    """A hostile JSON value; with ``like`` a number, often a small nudge of it (a plausible edit)."""
    if isinstance(like, (int, float)) and not isinstance(like, bool) and rnd.random() < 0.4:
        return rnd.choice([like + 1, like - 1, like * 2, -like, like + 1e-9, like * (1 + 1e-12), like / 3])
    if isinstance(like, list) and like and rnd.random() < 0.3:
        out = list(like)
        i = rnd.randrange(len(out))
        out[i] = json_junk(rnd, out[i])
        if rnd.random() < 0.3:
            out.append(json_junk(rnd))
        elif rnd.random() < 0.3:
            out.pop()
        return out
    r = rnd.random()
    if r < 0.05:
        return _deep(rnd.choice([50, 500, 5000]))
    if r < 0.1:
        return rnd.uniform(-1e6, 1e6)
    return copy.deepcopy(rnd.choice(JSON_JUNK))


def _short(v: Any, n: int = 40) -> str:
    try:
        return repr(str(v)[:n])
    except RecursionError:
        return "<deeply nested>"


def _paths(doc: Any, prefix: tuple = ()) -> list[tuple]:
    """Every path (tuple of keys/indices) into a JSON document, the root excluded."""
    out: list[tuple] = []
    if isinstance(doc, dict):
        for k, v in doc.items():
            out.append(prefix + (k,))
            out.extend(_paths(v, prefix + (k,)))
    elif isinstance(doc, list) and len(doc) <= 64:
        for i, v in enumerate(doc):
            out.append(prefix + (i,))
            out.extend(_paths(v, prefix + (i,)))
    return out


def _get(doc: Any, path: tuple) -> Any:
    for k in path:
        doc = doc[k]
    return doc


def edit_json(doc: Any, rnd: random.Random) -> str:
    """Change one place of ``doc`` in place (replace, delete, add a key); describe it."""
    paths = _paths(doc)
    if not paths:
        return "nothing to edit"
    path = rnd.choice(paths)
    parent = _get(doc, path[:-1])
    key = path[-1]
    op = rnd.random()
    if op < 0.15 and isinstance(parent, dict):
        del parent[key]
        return f"deleted {'/'.join(map(str, path))}"
    if op < 0.25 and isinstance(parent, (dict, list)):
        if isinstance(parent, dict):
            extra = rnd.choice(["junk", "__proto__", "", "é", key + "_"]) if isinstance(key, str) else "junk"
            parent[extra] = json_junk(rnd)
            return f"added {extra!r} beside {'/'.join(map(str, path))}"
        parent.append(json_junk(rnd))
        return f"appended to {'/'.join(map(str, path[:-1]))}"
    old = parent[key]
    parent[key] = json_junk(rnd, old)
    return f"{'/'.join(map(str, path))}: {_short(old)} -> {_short(parent[key])}"


# ---------------------------------------------------------------------------------------------- stores
def tree(p: Path) -> dict[str, bytes]:
    """Every file under ``p`` (and every symbolic link's target name), for the before/after comparison."""
    out: dict[str, bytes] = {}
    for f in sorted(p.rglob("*")):
        if f.is_symlink():
            out[str(f.relative_to(p))] = b"-> " + os.readlink(f).encode()
        elif f.is_file():
            out[str(f.relative_to(p))] = f.read_bytes()
    return out


def corrupt_store(c: Path, rnd: random.Random) -> list[str]:
    """One to three random corruptions of the store ``c``; returns what was done."""
    done: list[str] = []
    for _ in range(rnd.choice([1, 1, 1, 2, 3])):
        files = [f for f in sorted(c.rglob("*")) if f.is_file() and not f.is_symlink()]
        metas = [f for f in files if f.name == "zarr.json"]
        chunks = [f for f in files if f.name != "zarr.json"]
        op = rnd.choice(["flip", "flip", "flip_meta", "truncate", "delete_file", "delete_array", "json", "json",
                         "json", "json_root", "json_root", "swap_chunks", "stray", "empty"])
        if op in ("flip", "flip_meta") and files:
            f = rnd.choice(metas if op == "flip_meta" and metas else files)
            b = bytearray(f.read_bytes())
            if not b:
                continue
            for _ in range(rnd.choice([1, 1, 2, 4])):
                i = rnd.randrange(len(b))
                b[i] ^= rnd.randrange(1, 256)
            f.write_bytes(bytes(b))
            done.append(f"flip bytes of {f.relative_to(c)}")
        elif op == "truncate" and files:
            f = rnd.choice(files)
            data = f.read_bytes()
            n = rnd.randrange(len(data)) if data else 0
            f.write_bytes(data[:n])
            done.append(f"truncate {f.relative_to(c)} to {n}")
        elif op == "delete_file" and files:
            f = rnd.choice(files)
            f.unlink()
            done.append(f"delete {f.relative_to(c)}")
        elif op == "delete_array":
            arrays = [d for d in sorted(c.iterdir()) if d.is_dir()]
            if arrays:
                d = rnd.choice(arrays)
                shutil.rmtree(d)
                done.append(f"delete array {d.name}")
        elif op in ("json", "json_root") and metas:
            f = c / "zarr.json" if op == "json_root" and (c / "zarr.json").is_file() else rnd.choice(metas)
            try:
                doc = json.loads(f.read_text(encoding="utf-8"))
            except (ValueError, UnicodeDecodeError):
                continue
            what = edit_json(doc, rnd)
            try:
                f.write_text(json.dumps(doc), encoding="utf-8")
            except (ValueError, RecursionError):
                continue
            done.append(f"edit {f.relative_to(c)}: {what}")
        elif op == "swap_chunks" and len(chunks) >= 2:
            a, b = rnd.sample(chunks, 2)
            da, db = a.read_bytes(), b.read_bytes()
            a.write_bytes(db)
            b.write_bytes(da)
            done.append(f"swap {a.relative_to(c)} <-> {b.relative_to(c)}")
        elif op == "stray" and chunks:
            f = rnd.choice(chunks)
            stray = f.parent / rnd.choice(["1", "9", "0.partial", "junk", ".hidden"])
            if not stray.exists():
                stray.write_bytes(rnd.randbytes(rnd.randrange(0, 64)))
                done.append(f"stray file {stray.relative_to(c)}")
        elif op == "empty" and files:
            f = rnd.choice(files)
            f.write_bytes(b"")
            done.append(f"empty {f.relative_to(c)}")
    return done or ["nothing"]


def same_map(a: Any, b: Any) -> list[str]:
    """What differs between two maps (robot, grid, arrays); [] when they are the same."""
    from armkit.model import dumps

    diff = []
    if dumps(a.robot) != dumps(b.robot):
        diff.append("robot")
    ga, gb = a.grid, b.grid
    for f in ("symmetric", "resolution", "dims", "directions", "rolls"):
        if getattr(ga, f) != getattr(gb, f):
            diff.append(f"grid.{f}")
    for f in ("lo", "T_world_A"):
        if not np.array_equal(np.asarray(getattr(ga, f)), np.asarray(getattr(gb, f))):
            diff.append(f"grid.{f}")
    for f in ("hits", "manipulability", "counts"):
        x, y = getattr(a, f), getattr(b, f)
        if (x is None) != (y is None) or (x is not None and not np.array_equal(x, y, equal_nan=True)):
            diff.append(f)
    return diff


class StoreFuzz:
    """The original map (built once under ``root``) and a judge for corrupted copies of it."""

    QUERY = ("1", "0", "0")

    def __init__(self, root: Path, bound: float = 20.0) -> None:
        import armkit
        from armkit.reach import ReachabilityMap

        self.root = root
        self.bound = bound
        self.path = root / "orig.zarr"
        if not self.path.exists():
            armkit.reachability("planar2", resolution=0.1, samples=100_000, workers=1, path=self.path)
        self.orig = ReachabilityMap.open(self.path)
        self.orig_tree = tree(self.path)
        code, out, exc = cli(["reach", "query", str(self.path), *self.QUERY], 60)
        assert code == 0 and exc is None, out
        self.orig_code = code

    def case(self, rnd: random.Random, work: Path) -> tuple[str, str]:
        from armkit.errors import LimitError, MapFileError
        from armkit.reach import ReachabilityMap

        c = work / "c.zarr"
        if c.exists():
            shutil.rmtree(c)
        shutil.copytree(self.path, c, symlinks=True)
        what = "; ".join(corrupt_store(c, rnd))
        before = tree(c)
        outcome, detail = OK, ""
        opened = False
        try:
            with time_limit(self.bound):
                m = ReachabilityMap.open(c)
            opened = True
            diff = same_map(self.orig, m)
            if diff:
                outcome, detail = WRONG, f"opened, but {', '.join(diff)} differ"
        except (MapFileError, LimitError):
            outcome = CLEAN
        except Hang:
            return HANG, f"{what} | open: still running after {self.bound} s"
        except Exception as exc:  # noqa: BLE001 - the finding
            outcome, detail = TRACEBACK, f"open: {_exc_line(exc)}"
        code, out, exc = cli(["reach", "query", str(c), *self.QUERY], self.bound)
        if code == "hang":
            return HANG, f"{what} | reach query: still running after {self.bound} s"
        if exc is not None or "Traceback" in out or code not in (0, 1, 2):
            return TRACEBACK, f"{what} | reach query exit {code}: {exc or out[-300:]}"
        if outcome == OK and code != self.orig_code:
            outcome, detail = WRONG, f"open gave the original map, reach query exit {code} (expected {self.orig_code})"
        elif outcome == CLEAN and code != 2:
            outcome, detail = WRONG, f"open refused the store, reach query exit {code}: {out[-200:]}"
        elif outcome == WRONG and code != 2:
            detail += f"; reach query exit {code}"
        if tree(c) != before:
            return MODIFIED, f"{what} | opened={opened}: the store's files changed"
        return outcome, f"{what} | {detail}" if detail else what


# ---------------------------------------------------------------------------------------------- CLI runner
def cli(args: list[str], bound: float, env: dict[str, str] | None = None) -> tuple[Any, str, BaseException | None]:
    """Run ``armkit ARGS`` in-process: (exit code or "hang", stdout + stderr, a non-SystemExit exception)."""
    from typer.testing import CliRunner

    from armkit.cli import app

    runner = CliRunner()
    try:
        with time_limit(bound):
            res = runner.invoke(app, [str(a) for a in args], env={"COLUMNS": "200", **(env or {})})
    except Hang:
        return "hang", "", None
    exc = res.exception if not isinstance(res.exception, SystemExit) else None
    return res.exit_code, res.output, exc


# ---------------------------------------------------------------------------------------------- URDF
ATTR_JUNK = ["", " ", "nan", "NaN", "inf", "-inf", "1e308", "-1e308", "1e400", "1e-400", "0 0 1e200", "0 0 0",
             "nan nan nan", "inf 0 0", "1e308 1e308 1e308", "1 2", "1 2 3 4", "x y z", "0x10", "١٢٣", "1_0",
             "☃", "\u202e", "é", "&amp;", "&lt;b&gt;bold&lt;/b&gt;", "<img src=x onerror=alert(1)>", "A" * 10_000,
             "  1   2   3  ", "-0", "1e-320", "revolute", "prismatic", "continuous", "fixed", "floating", "planar",
             "package://../../etc/passwd", "/etc/passwd", "file:///etc/passwd", "/dev/zero", "so101_assets",
             ".", "..", "base_link", "gripper_frame_link", "shoulder_link", "gripper", "1 0 0", "0 1 0"]
URDF_DOCTYPES = [
    '<!DOCTYPE robot [<!ENTITY x "yyyy">]>',
    '<!DOCTYPE robot [<!ENTITY xxe SYSTEM "file:///etc/passwd">]>',
    '<!DOCTYPE robot [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">'
    '<!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;">]>',
    '<!DOCTYPE robot SYSTEM "http://example.invalid/robot.dtd">',
]


def _num_attr(rnd: random.Random) -> str:
    return " ".join(rnd.choice(["0", "1", "-1", "1e308", "1e-308", "3.14159", "1e154", "1e155", "nan", "inf",
                                f"{rnd.uniform(-10, 10):.6g}"]) for _ in range(rnd.choice([1, 3, 3, 3, 2, 4])))


def mutate_urdf(text: str, rnd: random.Random) -> tuple[str, list[str]]:
    """The URDF ``text`` with one to four random element, attribute or text mutations."""
    root = ET.fromstring(text.encode())
    done: list[str] = []
    for _ in range(rnd.choice([1, 1, 2, 3, 4])):
        elems = list(root.iter())
        parents = {ch: p for p in elems for ch in p}
        op = rnd.choice(["delete", "duplicate", "move", "attr", "attr", "attr", "num", "num", "rename_attr",
                         "add_attr", "tag", "text"])
        e = rnd.choice(elems[1:])
        p = parents[e]
        if op == "delete":
            p.remove(e)
            done.append(f"delete <{e.tag} {e.attrib.get('name', '')}>")
        elif op == "duplicate":
            p.insert(list(p).index(e) + 1, copy.deepcopy(e))
            done.append(f"duplicate <{e.tag} {e.attrib.get('name', '')}>")
        elif op == "move":
            target = rnd.choice(elems)
            if target is not e and e not in list(target.iter()):
                p.remove(e)
                target.append(e)
                done.append(f"move <{e.tag}> into <{target.tag}>")
        elif op in ("attr", "num", "rename_attr") and e.attrib:
            k = rnd.choice(sorted(e.attrib))
            if op == "rename_attr":
                v = e.attrib.pop(k)
                e.set(rnd.choice(["xyz ", "XYZ", "nme", k + "x", "rpy"]).strip(), v)
                done.append(f"rename {e.tag}@{k}")
            else:
                e.set(k, rnd.choice(ATTR_JUNK) if op == "attr" else _num_attr(rnd))
                done.append(f"{e.tag}@{k} = {e.attrib[k][:40]!r}")
        elif op == "add_attr":
            k = rnd.choice(["name", "xyz", "rpy", "lower", "upper", "type", "filename", "scale", "effort",
                            "velocity", "link", "junk"])
            e.set(k, rnd.choice(ATTR_JUNK + [_num_attr(rnd)]))
            done.append(f"add {e.tag}@{k}")
        elif op == "tag":
            old = e.tag
            e.tag = rnd.choice(["joint", "link", "origin", "axis", "limit", "mimic", "parent", "child", "junk",
                                "robot", "mesh", "box"])
            done.append(f"<{old}> -> <{e.tag}>")
        elif op == "text":
            e.text = rnd.choice(ATTR_JUNK)
            done.append(f"text of <{e.tag}>")
    out = ET.tostring(root, encoding="unicode")
    r = rnd.random()
    if r < 0.08:
        out = rnd.choice(URDF_DOCTYPES) + "\n" + out.replace("<robot ", "<robot junk=\"&x;\" ", 1) \
            if rnd.random() < 0.3 else rnd.choice(URDF_DOCTYPES) + "\n" + out
        done.append("doctype")
    elif r < 0.14:
        n = rnd.randrange(len(out))
        out = out[:n]
        done.append(f"truncated at {n}")
    elif r < 0.2:
        b = bytearray(out.encode())
        for _ in range(rnd.choice([1, 3, 10])):
            i = rnd.randrange(len(b))
            b[i] ^= rnd.randrange(1, 256)
        out = b.decode("utf-8", errors="replace")
        done.append("byte flips")
    return out, done or ["none"]


def fk_finite(robot: Any, rnd: random.Random) -> str:
    """'' when FK of zeros and of a few random q within the limits is finite; else what was not."""
    import armkit

    qs = [np.zeros(robot.n)]
    lo, hi = np.asarray(robot.lower, float), np.asarray(robot.upper, float)
    lo = np.where(np.isfinite(lo), lo, -math.pi)
    hi = np.where(np.isfinite(hi), hi, math.pi)
    for _ in range(3):
        qs.append(np.array([rnd.uniform(a, b) if b > a else a for a, b in zip(lo, hi)]))
    for q in qs:
        T = armkit.fk(robot, q)
        if not np.all(np.isfinite(T)):
            return f"fk({np.round(q, 4).tolist()}) is not finite"
    return ""


class UrdfFuzz:
    def __init__(self, bound: float = 20.0) -> None:
        self.text = SO101.read_text(encoding="utf-8")
        self.bound = bound

    def case(self, rnd: random.Random, work: Path) -> tuple[str, str]:
        import armkit
        from armkit.errors import ArmkitError

        text, done = mutate_urdf(self.text, rnd)
        p = work / rnd.choice(["robot.urdf", "so101.urdf", "r☃.urdf"])
        p.write_text(text, encoding="utf-8")
        tip = rnd.choice([None, "gripper_frame_link", "gripper_frame_link", "wrist_link", "base_link", "nope", ""])
        what = f"{'; '.join(done)} | tip={tip!r}"
        try:
            with time_limit(self.bound), warnings.catch_warnings():
                warnings.simplefilter("ignore")
                robot = armkit.load(p, tip=tip)
                bad = fk_finite(robot, rnd)
            if bad:
                return WRONG, f"{what} | {bad}"
            return OK, what
        except ArmkitError:
            return CLEAN, what
        except Hang:
            return HANG, f"{what} | still running after {self.bound} s"
        except Exception as exc:  # noqa: BLE001 - the finding
            return TRACEBACK, f"{what} | {_exc_line(exc)}"


# ---------------------------------------------------------------------------------------------- scenes
SCENE = {
    "unit": "m", "angle_unit": "deg", "name": "cell", "description": "every kind",
    "shapes": [
        {"type": "plane", "name": "ground", "normal": [0, 0, 1], "offset": 0},
        {"type": "box", "name": "table", "center": [0.5, 0, 0.2], "size": [0.4, 0.6, 0.4], "rpy": [0, 0, 30]},
        {"type": "sphere", "name": "ball", "center": [0, 0.3, 0.2], "radius": 0.05},
        {"type": "cylinder", "name": "pipe", "center": [0, -0.3, 0.2], "radius": 0.02, "length": 0.3,
         "rpy": [90, 0, 0]},
        {"type": "capsule", "name": "post", "a": [0.3, 0.3, 0], "b": [0.3, 0.3, 0.5], "radius": 0.03,
         "allow": ["base"]},
    ],
}
SCENE_STRINGS = ["plane", "box", "sphere", "cylinder", "capsule", "mesh", "m", "cm", "mm", "km", "deg", "rad", "",
                 "☃", "\u202e", "<b>x</b>", "x" * 10_000, "/etc/passwd", "/dev/zero", "../../etc/hostname", ".",
                 "nope.stl", "base", "link1"]


def toml_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)        # a JSON string is a valid TOML basic string
    if isinstance(v, list):
        depth = 0
        while isinstance(v, list) and len(v) == 1 and isinstance(v[0], list):
            depth, v = depth + 1, v[0]      # [[[...]]]: built without recursion
        return "[" * depth + "[" + ", ".join(toml_value(x) for x in v) + "]" + "]" * depth
    if isinstance(v, dict):
        return "{" + ", ".join(f"{json.dumps(str(k))} = {toml_value(x)}" for k, x in v.items()) + "}"
    return '"none"'              # TOML has no null


def to_toml(doc: dict[str, Any]) -> str:
    lines = []
    rows = doc.get("shapes")
    for k, v in doc.items():
        if k == "shapes" and isinstance(v, list) and all(isinstance(r, dict) for r in v):
            continue
        lines.append(f"{json.dumps(str(k))} = {toml_value(v)}")
    if isinstance(rows, list) and all(isinstance(r, dict) for r in rows):
        for r in rows:
            lines.append("\n[[shapes]]")
            lines.extend(f"{json.dumps(str(k))} = {toml_value(v)}" for k, v in r.items())
    return "\n".join(lines) + "\n"


def _scene_junk(rnd: random.Random, like: Any = None) -> Any:
    v = json_junk(rnd, like)
    if v is None or (isinstance(v, int) and not isinstance(v, bool) and abs(v) >= 2 ** 63):
        v = rnd.choice(SCENE_STRINGS + [1e308, float("nan")])
    if isinstance(v, list) and any(x is None for x in v):
        v = [rnd.choice([1, "x", 1e308]) if x is None else x for x in v]
    depth, x = 0, v
    while isinstance(x, list) and x:
        depth, x = depth + 1, x[0]
    if depth > 500:
        v = _deep(500)       # the serialiser here is recursive; 500 levels still test the reader's own limit
    return v


def mutate_scene(rnd: random.Random) -> tuple[str, list[str]]:
    doc = copy.deepcopy(SCENE)
    done: list[str] = []
    for _ in range(rnd.choice([1, 1, 2, 3])):
        op = rnd.random()
        if op < 0.45:
            paths = _paths(doc)
            path = rnd.choice(paths)
            parent = _get(doc, path[:-1])
            old = parent[path[-1]]
            if isinstance(parent, dict) and rnd.random() < 0.15:
                del parent[path[-1]]
                done.append(f"delete {path}")
            else:
                parent[path[-1]] = (rnd.choice(SCENE_STRINGS) if isinstance(old, str) and rnd.random() < 0.5
                                    else _scene_junk(rnd, old))
                done.append(f"{path} = {_short(parent[path[-1]])}")
        elif op < 0.6:
            row = copy.deepcopy(rnd.choice(SCENE["shapes"]))
            row["type"] = rnd.choice(SCENE_STRINGS[:6])
            if row["type"] == "mesh":
                row = {"type": "mesh", "path": rnd.choice(SCENE_STRINGS), "scale": rnd.choice([[1, 1, 1], [0, 0, 0],
                                                                                            [1e308, 1, 1]])}
            if isinstance(doc.get("shapes"), list):
                doc["shapes"].append(row)
                done.append(f"add a {row['type']}")
        elif op < 0.7 and isinstance(doc.get("shapes"), list):
            doc["shapes"] = doc["shapes"] * rnd.choice([2, 10, 100])
            done.append("repeat shapes")
        elif op < 0.8:
            k = rnd.choice(["unit", "angle_unit", "shapes", "junk", "name"])
            doc[k] = _scene_junk(rnd)
            done.append(f"top {k}")
        else:
            done.append("text")
    text = to_toml(doc)
    if "text" in done:
        lines = text.splitlines()
        r = rnd.random()
        if r < 0.3 and lines:
            del lines[rnd.randrange(len(lines))]
        elif r < 0.6 and lines:
            i = rnd.randrange(len(lines))
            lines.insert(i, lines[i])
        elif r < 0.8:
            lines = lines[: rnd.randrange(len(lines) + 1)]
        else:
            b = bytearray("\n".join(lines).encode())
            for _ in range(3):
                i = rnd.randrange(len(b))
                b[i] ^= rnd.randrange(1, 256)
            lines = b.decode("utf-8", errors="replace").splitlines()
        text = "\n".join(lines) + "\n"
    return text, done or ["none"]


class SceneFuzz:
    def __init__(self, bound: float = 20.0) -> None:
        import armkit

        self.bound = bound
        self.robot = armkit.load("fighter")

    def case(self, rnd: random.Random, work: Path) -> tuple[str, str]:
        import armkit
        from armkit.collision.files import load_scene
        from armkit.errors import ArmkitError

        text, done = mutate_scene(rnd)
        p = work / "scene.toml"
        p.write_text(text, encoding="utf-8")
        what = "; ".join(done)
        try:
            with time_limit(self.bound), warnings.catch_warnings():
                warnings.simplefilter("ignore")
                scene = load_scene(p)
                q = np.radians([rnd.uniform(-90, 90) for _ in range(self.robot.n)])
                try:
                    res = armkit.collisions(self.robot, q, scene=scene)
                    res.message()
                    d = np.asarray(armkit.clearance(self.robot, q, scene=scene))
                except ArmkitError:
                    return OK, what + " | loaded; the collision query refused it"
                if np.any(np.isnan(d)):
                    return WRONG, f"{what} | clearance is NaN"
            return OK, what
        except ArmkitError:
            return CLEAN, what
        except Hang:
            return HANG, f"{what} | still running after {self.bound} s"
        except Exception as exc:  # noqa: BLE001 - the finding
            return TRACEBACK, f"{what} | {_exc_line(exc)}"


# ---------------------------------------------------------------------------------------------- CLI
ARG_JUNK = ["", " ", "-1", "0", "1", "2", "1e308", "-1e308", "nan", "inf", "-inf", "1e23", "99999999999999999999",
            str(2 ** 63), "0x10", "1_000", "1,2", "1,2,3", ",,,", "1,,3", "nan,nan,nan", "1e308,1e308,1e308",
            "☃", "\u202e", "é", "ko", "en", "fr", "x" * 10_000, "[red]x[/]", "<b>x</b>", "%s%n", "-", "--",
            "-x", "planar2", "fighter", "so101", "ur5", "lm", "ik", "fk", "standard", "modified"]
READ_PATHS = ["/dev/null", "/dev/zero", "/dev/urandom", "/", "/etc/passwd", "/proc/self/status", "/nonexistent/x",
              "{S}", "{S}/file.txt", "{S}/map.zarr", "{S}/so101.urdf", "{S}/tasks.csv", "{S}/calib.json",
              "{S}/scene.toml", "{S}/planar.toml", "{S}/map.zarr/zarr.json", "{S}/sub/missing.zarr"]
WRITE_PATHS = ["{S}", "{S}/file.txt", "{S}/map.zarr", "{S}/out{n}.zarr", "{S}/out{n}.png", "{S}/out{n}.svg",
               "{S}/out{n}.urdf", "{S}/out{n}.toml", "{S}/sub/deep/x{n}.toml", "{S}/☃{n}.urdf", "{S}/x{n}.gif",
               "{S}/so101.urdf", "{S}/planar.toml", "."]

# (args, the tokens that are outputs (index), the options of the command with what their value is)
CLI_BASES: list[tuple[list[str], dict[str, str]]] = [
    (["reach", "build", "planar2", "-o", "{S}/b{n}.zarr", "--resolution", "0.1", "--samples", "100000",
      "--workers", "1"],
     {"-o": "w", "--output": "w", "--resolution": "v", "--orientations": "v", "--rolls": "v", "--method": "v",
      "--samples": "v", "--seed": "v", "--coverage": "v", "--block-size": "v", "--workers": "workers",
      "--overwrite": "flag", "--json": "flag", "--lang": "v", "--scheduler": "scheduler", "--dashboard": "flag"}),
    (["reach", "show", "{S}/map.zarr", "--json"], {"-o": "w", "--output": "w", "--json": "flag", "--lang": "v"}),
    (["reach", "show", "{S}/map.zarr", "-o", "{S}/p{n}.png"], {"-o": "w", "--json": "flag", "--lang": "v"}),
    (["reach", "query", "{S}/map.zarr", "1", "0", "0"],
     {"--rpy": "v", "--deg": "flag", "--json": "flag", "--lang": "v"}),
    (["reach", "query", "{S}/map.zarr", "0.5", "0", "0.5", "--rpy", "0,0,0", "--deg", "--json"],
     {"--rpy": "v", "--deg": "flag", "--json": "flag", "--lang": "v"}),
    (["reach", "base", "{S}/map.zarr", "{S}/tasks.csv", "--top", "2"],
     {"--top": "v", "--floor-z": "v", "--step": "v", "--yaws": "v", "--json": "flag", "--lang": "v"}),
    (["so101", "pose", "0", "10", "20", "30", "40", "-c", "{S}/calib.json", "--degrees"],
     {"-c": "r", "--calibration": "r", "--ticks": "flag", "--degrees": "flag", "--range-m100-100": "flag",
      "--json": "flag"}),
    (["so101", "pose", "2048", "2048", "2048", "2048", "2048", "2048", "-c", "{S}/calib.json", "--ticks", "--json"],
     {"-c": "r", "--ticks": "flag", "--degrees": "flag", "--json": "flag"}),
    (["info", "fighter"], {"--json": "flag", "--dh": "flag", "--convention": "v", "--base": "v", "--tip": "v",
                           "--allow-outside": "flag"}),
    (["info", "{S}/so101.urdf", "--tip", "gripper_frame_link", "--dh"],
     {"--json": "flag", "--dh": "flag", "--convention": "v", "--base": "v", "--tip": "v"}),
    (["convert", "fighter", "{S}/c{n}.urdf"], {"--convention": "v"}),
    (["convert", "{S}/so101.urdf", "{S}/c{n}.toml", "--tip", "gripper_frame_link"],
     {"--convention": "v", "--base": "v", "--tip": "v"}),
    (["view", "fighter", "--lang", "en"], {"--port": "v", "-p": "v", "--host": "v", "--lang": "v", "--scene": "r",
                                          "--no-scene": "flag"}),
    (["view", "{S}/planar.toml", "--scene", "{S}/scene.toml", "--port", "8080"],
     {"--port": "v", "--host": "v", "--lang": "v", "--scene": "r", "--no-scene": "flag"}),
]
WRITES = ("build", "show", "convert")          # commands that write: no system paths anywhere in their arguments

# the computing commands (the ``commands`` surface): every option of each, values from ARG_JUNK and the paths a
# writing command may take (each writes a picture, a text or a table where -o says)
ROBOT_OPTS = {"--base": "v", "--tip": "v", "--allow-outside": "flag", "--json": "flag"}
FK = {"--deg": "flag", "--strict": "flag", "--link": "v", "--links": "flag"}
JAC = {"--deg": "flag", "--strict": "flag", "--frame": "v"}
IK = {"--rpy": "v", "--quat": "v", "--deg": "flag", "--method": "v", "--branch": "v", "--all": "flag", "--seed": "v",
      "--phi": "v", "--pitch": "v", "--direction": "v", "--trace": "flag", "--scene": "r", "--no-scene": "flag",
      "--sweep": "v", "--fixed": "v"}
VEL = {"--deg": "flag", "--ee-vel": "v", "--q-vel": "v", "--method": "v", "--damping": "v"}
SING = {"-o": "w", "--output": "w", "--budget": "v"}
DERIVE = {"--latex": "flag", "--python": "flag", "--ik": "flag", "--fragment": "flag", "-o": "w", "--png": "w",
          "--links": "flag", "--no-cache": "flag", "--budget": "v"}
WORK = {"-n": "v", "--samples": "v", "--seed": "v", "--ground": "v", "--box": "v", "--manipulability": "flag",
        "-o": "w", "--scene": "r", "--no-scene": "flag"}
MAPS = {"-o": "w", "--steps": "v", "--joints": "v", "--q1": "v", "--q2": "v", "--x": "v", "--y": "v", "--branch": "v",
        "--z": "v", "--phi": "v", "--no-ik": "flag"}
TRAJ = {"--joint": "flag", "--line": "flag", "--blend": "v", "--blend-shape": "v", "--speed": "v", "--arc": "v",
        "--deg": "flag", "--profile": "v", "--duration": "v", "--qd-max": "v", "--qdd-max": "v", "--steps": "v",
        "--method": "v", "--dt": "v", "-o": "w", "--scene": "r", "--no-scene": "flag", "--refuse-collisions": "flag"}
TRACK = {"--path": "v", "--method": "v", "--frames": "v", "--fps": "v", "--seed": "v", "-o": "w",
         "--no-animation": "flag", "--scene": "r", "--no-scene": "flag", "--refuse-collisions": "flag"}
PLOT = {"--deg": "flag", "--all-branches": "v", "-o": "w", "--no-frames": "flag", "--scene": "r", "--no-scene": "flag",
        "--strict": "flag"}
SIX = ["0", "0.1", "0.2", "0.3", "0.4", "0"]
POSE = ["--rpy", "180,0,0", "--deg"]
COMMAND_BASES: list[tuple[list[str], dict[str, str]]] = [(args, {**ROBOT_OPTS, **opts}) for args, opts in [
    (["fk", "fighter", "30", "45", "60", "--deg"], FK), (["fk", "{S}/so101.urdf", *SIX], FK), (["fk", "ur5", *SIX], FK),
    (["jacobian", "puma560", *SIX], JAC), (["jacobian", "{S}/planar.toml", "0.3", "0.4"], JAC),
    (["ik", "fighter", "24.861", "14.353", "187.181"], IK), (["ik", "ur5", "0.3", "0.2", "0.4", *POSE], IK),
    (["ik", "planar2", "1.2", "0.3"], IK),
    (["ik", "panda", "0.4", "0.1", "0.5", *POSE, "--fixed", "panda_joint3=0"], IK),
    (["ik", "{S}/so101.urdf", "0.2", "0.0", "0.1", "--pitch", "0.3"], IK),
    (["ik", "stanford", "0.3", "0.2", "0.4", *POSE, "--method", "lm"], IK),
    (["velocity", "fighter", "30", "45", "60", "--deg", "--ee-vel", "1,0,0"], VEL),
    (["velocity", "ur5", *SIX, "--q-vel", "1,0,0,0,0,0"], VEL),
    (["singular", "fighter"], SING), (["singular", "planar2", "-o", "{S}/s{n}.png"], SING),
    (["derive", "planar2"], DERIVE), (["derive", "fighter", "--budget", "2"], DERIVE),
    (["workspace", "fighter", "-n", "2000"], WORK),
    (["workspace", "planar2", "-n", "2000", "-o", "{S}/w{n}.png"], WORK),
    (["maps", "planar2", "--steps", "21", "-o", "{S}/m{n}.png"], MAPS),
    (["maps", "fighter", "--steps", "21", "-o", "{S}/m{n}.png"], MAPS),
    (["traj", "planar2", "--joint", "0,0", "1,1", "--deg"], TRAJ),
    (["traj", "planar2", "--line", "1.2,0.3", "0.8,0.8", "-o", "{S}/t{n}.csv"], TRAJ),
    (["traj", "fighter", "--line", "24,14,187", "60,10,150", "--steps", "20"], TRAJ),
    (["track", "planar3", "--frames", "20", "--no-animation"], TRACK),
    (["track", "planar2", "--frames", "10", "-o", "{S}/k{n}.gif", "--path", "circle"], TRACK),
    (["plot", "fighter", "30", "45", "60", "--deg", "-o", "{S}/p{n}.png"], PLOT),
    (["plot", "puma560", "--all-branches", "0.4,0.2,0.3", "-o", "{S}/p{n}.png"], PLOT)]]
SYMBOLIC_BOUND = 150.0
"""The ``commands`` surface's bound on one case (s): ``derive`` and ``singular`` may use their budgets of 60 s of
CPU for the derivation and 60 s for the determinant (``derive so101`` does), and then say so."""
ARG_JUNK += ["180,0,0", "0,0,0,1", "elbow-up", "front/elbow-down", "base", "tool", "dls", "pinv", "0:90", "0:90:0",
             "0:0", "1:2:-1", "circle", "figure8", "ccd", "fabrik", "newton", "analytic", "quintic", "trapezoid",
             "cubic", "rate", "parabolic", "A1=0", "panda_joint3=1e308", "x=1", "=", "1e-300", "2,3", "0,5",
             "1,1,1,1,1,1", "tool0", "link2", "link9", "3", "10", "100000000"]


class ViewStarted(Exception):
    """Raised by the stub that replaces ``armkit.viz.view.view``: the command would have served the page."""


def _stub_view(*a: Any, **k: Any) -> Any:
    raise ViewStarted("the view would start here")


class CliFuzz:
    def __init__(self, scratch: Path, store: Path, bound: float = 30.0, heavy: bool = False,
                 bases: list[tuple[list[str], dict[str, str]]] | None = None) -> None:
        """``heavy``: also local Dask clusters (--workers N) and --scheduler addresses (seconds each); ``bases``:
        the commands mutated (default :data:`CLI_BASES`; :data:`COMMAND_BASES` for the ``commands`` surface, whose
        commands all write)."""
        self.bases = CLI_BASES if bases is None else bases
        self.S = scratch
        self.bound = bound
        self.heavy = heavy
        self.n = 0
        scratch.mkdir(parents=True, exist_ok=True)
        if not (scratch / "map.zarr").exists():
            shutil.copytree(store, scratch / "map.zarr")
        shutil.copy(SO101, scratch / "so101.urdf")
        shutil.copy(CALIBRATION, scratch / "calib.json")
        (scratch / "file.txt").write_text("keep\n")
        (scratch / "tasks.csv").write_text("1.0,0,0\n0.8,0.3,0\n")
        (scratch / "planar.toml").write_text((ROOT / "src/armkit/robots/planar2.toml").read_text())
        (scratch / "scene.toml").write_text(to_toml(SCENE))
        self.keep = {p: tree(scratch / p) if (scratch / p).is_dir() else (scratch / p).read_bytes()
                     for p in ("map.zarr", "so101.urdf", "calib.json", "file.txt", "tasks.csv", "planar.toml")}

    def _fill(self, s: str) -> str:
        return s.replace("{S}", str(self.S)).replace("{n}", str(self.n))

    def _value(self, rnd: random.Random, kind: str, writes: bool) -> str:
        if kind == "w":
            return self._fill(rnd.choice(WRITE_PATHS))
        if kind == "workers":
            return rnd.choice(["1", "0", "-1", "1e308", "x", "99999999999"] + (["2"] if self.heavy else []))
        if kind == "scheduler":
            pool = ["", "x", "tcp://", "tls://", "inproc://", "ucx://", "tcp://[::1", "tcp://999.1.1.1:1",
                    "☃://x", "x" * 10_000]
            if self.heavy:
                pool += ["tcp://127.0.0.1:1", "tcp://localhost:9"]
            return rnd.choice(pool)
        pool = ARG_JUNK + ([] if writes else READ_PATHS) + (WRITE_PATHS[:4] if writes else [])
        return self._fill(rnd.choice(pool))

    def mutate(self, rnd: random.Random) -> list[str]:
        self.n += 1
        base, opts = rnd.choice(self.bases)
        writes = self.bases is COMMAND_BASES or base[1] in WRITES or base[0] in WRITES
        args = [self._fill(a) for a in base]
        if not self.heavy and "--scheduler" in opts:
            opts = {k: v for k, v in opts.items() if k != "scheduler"}
        fixed = 2 if base[0] in ("reach", "so101") else 1        # the command words stay
        for _ in range(rnd.choice([1, 1, 2, 3])):
            op = rnd.random()
            if op < 0.45 and len(args) > fixed:
                i = rnd.randrange(fixed, len(args))
                kind = opts.get(args[i - 1], "v")
                if kind == "flag":
                    kind = "v"
                if base[0] == "convert" and i == 2:
                    kind = "w"                       # convert SRC DST: the destination
                args[i] = self._value(rnd, kind, writes)
            elif op < 0.75 and opts:
                k = rnd.choice(sorted(opts))
                kind = opts[k]
                if kind == "flag":
                    args.append(k)
                else:
                    args += [k, self._value(rnd, kind, writes)]
            elif op < 0.88 and len(args) > fixed:
                del args[rnd.randrange(fixed, len(args))]
            else:
                i = rnd.randrange(fixed, len(args) + 1)
                args.insert(i, self._value(rnd, "v", writes))
        return args

    def case(self, rnd: random.Random, work: Path) -> tuple[str, str]:
        import armkit.viz.view as view_pkg

        args = self.mutate(rnd)
        shown = " ".join(a if len(a) < 60 else a[:20] + f"...({len(a)} chars)" for a in args)
        real = view_pkg.view
        view_pkg.view = _stub_view          # the CLI imports it inside the command: never serve the page
        cwd = os.getcwd()
        os.chdir(self.S)
        try:
            t0 = time.perf_counter()
            code, out, exc = cli(args, self.bound)
            took = time.perf_counter() - t0
        finally:
            os.chdir(cwd)
            view_pkg.view = real
        changed = [p for p, v in self.keep.items()
                   if (tree(self.S / p) if (self.S / p).is_dir() else
                       (self.S / p).read_bytes() if (self.S / p).is_file() else None) != v]
        for p in changed:            # put it back for the next case
            self._restore(p)
        if isinstance(exc, ViewStarted):
            return OK, f"{shown} | the view would start"
        if code == "hang":
            return HANG, f"{shown} | still running after {self.bound} s"
        if exc is not None or "Traceback" in out:
            return TRACEBACK, f"{shown} | exit {code}: {_exc_line(exc) if exc else out[-400:]}"
        if code not in (0, 1, 2):
            return TRACEBACK, f"{shown} | exit {code}: {out[-300:]}"
        if changed and not (base_writes_onto(args, changed)):
            return MODIFIED, f"{shown} | exit {code}; changed {changed}"
        return (OK if code in (0, 1) else CLEAN), f"{shown} | exit {code} in {took:.1f} s"

    def _restore(self, p: str) -> None:
        dst = self.S / p
        if dst.is_dir() and not dst.is_symlink():
            shutil.rmtree(dst)
        elif dst.exists() or dst.is_symlink():
            dst.unlink()
        if p == "map.zarr":
            shutil.copytree(self._store_src, dst)
        else:
            dst.write_bytes(self.keep[p])  # type: ignore[arg-type]

    @property
    def _store_src(self) -> Path:
        return self.S.parent / "orig.zarr"


def base_writes_onto(args: list[str], changed: list[str]) -> bool:
    """True when the command was asked to write onto the changed file (convert/show -o onto it: the user's wish)."""
    return all(any(a.endswith(p) for a in args)
               and (("convert" in args or "-o" in args or "--output" in args) and p != "map.zarr"
                    or p == "map.zarr" and "build" in args and "--overwrite" in args) for p in changed)


# ---------------------------------------------------------------------------------------------- the run
def peak_rss_bytes() -> int:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def run_case(fuzz: Any, rnd: random.Random, work: Path) -> tuple[str, str]:
    before = peak_rss_bytes()
    outcome, detail = fuzz.case(rnd, work)
    grew = peak_rss_bytes() - before
    if grew > 1024 ** 3 and outcome not in BAD:
        return RUNAWAY, f"{detail} | peak memory grew by {grew / 1024 ** 3:.1f} GiB"
    return outcome, detail


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=None, help="master seed (default: random; printed first)")
    ap.add_argument("--minutes", type=float, default=10.0, help="wall time for all surfaces together")
    ap.add_argument("--surfaces", default=",".join(SURFACES), help="comma-separated: store,urdf,scene,cli,commands")
    ap.add_argument("--bound", type=float, default=30.0, help="seconds one case may take before it is a hang")
    ap.add_argument("--light", action="store_true", help="no local Dask clusters or --scheduler addresses")
    ap.add_argument("--show", type=int, default=5, help="findings printed per surface and class")
    a = ap.parse_args(argv)
    seed = a.seed if a.seed is not None else random.SystemRandom().randrange(2 ** 32)
    print(f"seed {seed}   (rerun: make fuzz SEED={seed})", flush=True)
    surfaces = [s for s in a.surfaces.split(",") if s]
    os.environ.setdefault("ARMKIT_MEMORY_LIMIT", "2G")
    warnings.simplefilter("ignore")
    with tempfile.TemporaryDirectory(prefix="armkit-fuzz-") as tmp:
        root = Path(tmp)
        store = StoreFuzz(root, a.bound)
        makers: dict[str, Callable[[], Any]] = {
            "store": lambda: store, "urdf": lambda: UrdfFuzz(a.bound), "scene": lambda: SceneFuzz(a.bound),
            "cli": lambda: CliFuzz(root / "cli", store.path, a.bound, heavy=not a.light),
            "commands": lambda: CliFuzz(root / "commands", store.path, max(a.bound, SYMBOLIC_BOUND),
                                        bases=COMMAND_BASES)}
        fuzzers = {s: makers[s]() for s in surfaces}
        counts: dict[str, Counter[str]] = {s: Counter() for s in surfaces}
        findings: dict[str, dict[str, list[str]]] = {s: {} for s in surfaces}
        end = time.monotonic() + 60 * a.minutes
        i = 0
        while time.monotonic() < end:
            s = surfaces[i % len(surfaces)]
            case_seed = (seed * 1_000_003 + i) % 2 ** 63
            rnd = random.Random(case_seed)
            work = root / "work" / s
            if work.exists():
                shutil.rmtree(work, ignore_errors=True)
            work.mkdir(parents=True)
            try:
                outcome, detail = run_case(fuzzers[s], rnd, work)
            except Exception as exc:  # noqa: BLE001 - a failure of the harness itself is reported, not fatal
                outcome, detail = TRACEBACK, f"(harness) {_exc_line(exc)}"
            counts[s][outcome] += 1
            if outcome in BAD:
                findings[s].setdefault(outcome, []).append(f"case seed {case_seed}: {detail}")
            i += 1
            if i % 200 == 0:
                print(f"  {i} cases, {sum(sum(c[o] for o in BAD) for c in counts.values())} findings", flush=True)
    print()
    print(f"{'surface':<8}" + "".join(f"{o:>13}" for o in OUTCOMES) + f"{'cases':>9}")
    for s in surfaces:
        print(f"{s:<8}" + "".join(f"{counts[s][o]:>13}" for o in OUTCOMES) + f"{sum(counts[s].values()):>9}")
    total = Counter()
    for c in counts.values():
        total.update(c)
    print(f"{'all':<8}" + "".join(f"{total[o]:>13}" for o in OUTCOMES) + f"{sum(total.values()):>9}")
    for s in surfaces:
        for o, items in findings[s].items():
            print(f"\n{s} / {o}: {len(items)}")
            for line in items[: a.show]:
                print("  " + line[:1500])
    print(f"\nseed {seed}")
    return 1 if any(total[o] for o in BAD) else 0


def replay(surface: str, case_seed: int, bound: float = 30.0) -> tuple[str, str]:
    """Run one case again (the seed printed with a finding): ``python fuzz_long.py --replay cli:1234``."""
    with tempfile.TemporaryDirectory(prefix="armkit-fuzz-") as tmp:
        root = Path(tmp)
        store = StoreFuzz(root, bound)
        fuzz = {"store": lambda: store, "urdf": lambda: UrdfFuzz(bound), "scene": lambda: SceneFuzz(bound),
                "cli": lambda: CliFuzz(root / "cli", store.path, bound, heavy=True),
                "commands": lambda: CliFuzz(root / "commands", store.path, max(bound, SYMBOLIC_BOUND),
                                            bases=COMMAND_BASES)}[surface]()
        work = root / "work"
        work.mkdir()
        return run_case(fuzz, random.Random(case_seed), work)


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "--replay":
        surf, _, sd = sys.argv[2].partition(":")
        print(*replay(surf, int(sd)), sep="\n")
        sys.exit(0)
    sys.exit(main())
