"""Building a reachability map: split into blocks, run them (in-process or on Dask), merge, store.

One *block* is a unit of work that a worker can do alone: FK sampling of ``block_size``
configurations from the random stream ``(seed, block)``, or IK at the centre of every cell
of a few x-slabs. A block's answer (cells and sample counts) is a pure function of its
arguments. The driver adds answers into the map (a saturating sum; manipulability: the
maximum), marks the block done and, every few seconds, commits the map and the done-list to
the Zarr store as one new generation (``_map``). Hence

* the map is bit-for-bit the same whether the blocks ran in this process, in local worker
  processes or on a remote cluster, in whatever order (sum and max do not depend on order);
* a worker lost mid-block loses nothing: Dask runs the block again elsewhere, the answer is
  the same, and the driver merges each block's answer once;
* a build stopped at any point (Ctrl-C, a crash, the driver's machine lost) resumes from
  the last committed generation: exactly the blocks merged into it are skipped.
"""

from __future__ import annotations

import math
import os
import shutil
import warnings
import time
from pathlib import Path
from typing import Any, Callable, Iterator, Literal, Sequence

import numpy as np
from numpy.typing import NDArray

from .._extras import require
from .._version import __version__
from ..errors import ReachabilityError, warning_of
from ..kinematics import fk
from ..model import load
from ..model.robot import Robot
from ._grid import Grid
from ._map import DEFAULT_COVERAGE, ReachabilityMap, decide, robot_to_toml
from ._store import FORMAT, OLD_FORMATS, check_overwrite, checksum, clean_partial, robot_sha256, settings_sha256
from ._symmetry import roll_symmetric, yaw_frame, yaw_symmetric
from ._work import fk_block, ik_block

__all__ = ["reachability", "ReachabilityError", "default_samples", "FK_BLOCK"]

FK_BLOCK = 1_000_000
"""Default configurations per FK block (about 0.1-0.3 s of work; memory stays at SUB_BATCH)."""

SAMPLES_PER_CELL = 32
"""Default FK samples per cell of the map (see docs/reachability.md for the convergence study)."""

MAX_DEFAULT_SAMPLES = 2_000_000_000

CONNECT_TIMEOUT = "10s"
"""How long to wait for a Dask scheduler given by address before saying it cannot be reached."""

Progress = Callable[[int, int], None]


def default_samples(grid: Grid) -> int:
    """FK samples used when ``samples`` is not given: SAMPLES_PER_CELL per cell, in whole blocks."""
    want = min(MAX_DEFAULT_SAMPLES, SAMPLES_PER_CELL * grid.n_cells)
    return max(FK_BLOCK, int(math.ceil(want / FK_BLOCK)) * FK_BLOCK)


def _positive_int(value: Any, what: str) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise ReachabilityError.of("{what} must be a positive integer, got {value!r}", what=what, value=value)
    return int(value)


def _make_grid(robot: Robot, resolution: Any, orientations: Any, rolls: Any) -> Grid:
    if resolution is None:
        resolution = robot.reach / 20.0
    if isinstance(resolution, bool) or not isinstance(resolution, (int, float, np.floating, np.integer)) \
            or not math.isfinite(float(resolution)) or resolution <= 0:
        raise ReachabilityError.of("resolution must be a positive length in {unit}, got {resolution!r}",
                                   unit=robot.unit, resolution=resolution)
    if float(resolution) < robot.reach / 1000.0:
        raise ReachabilityError.of("resolution {resolution:g} {unit} is finer than reach/1000 ({limit:g} {unit}): the "
                                   "map would have over 10^9 voxels", resolution=float(resolution), unit=robot.unit,
                                   limit=robot.reach / 1000)
    position_only = robot.n < 6
    if orientations is None:
        orientations = 1 if position_only else 64
    orientations = _positive_int(orientations, "orientations")
    if rolls is None:
        rolls = 1 if (orientations == 1 or roll_symmetric(robot)) else 8
    rolls = _positive_int(rolls, "rolls")
    sym = yaw_symmetric(robot)
    # every reachable point lies within robot.reach of the first joint frame's origin
    grid = Grid.build(yaw_frame(robot), sym, robot.reach * (1 + 1e-9), float(resolution), orientations, rolls)
    if grid.n_cells > 4_000_000_000:
        raise ReachabilityError.of("the map would have {n_cells:,} cells; use a coarser resolution or fewer "
                                   "orientations", n_cells=grid.n_cells)
    return grid


# ------------------------------------------------------------------ executors
LOCAL_HOSTS = ("127.0.0.1", "localhost", "::1", "[::1]")


def _warn_if_remote(scheduler: str) -> None:
    """Say once, before connecting, that the work (the robot, the grid, the answers) will leave this machine."""
    from urllib.parse import urlsplit

    try:
        host = urlsplit(scheduler).hostname or ""
    except ValueError:
        host = ""
    if scheduler.startswith("inproc://") or host in LOCAL_HOSTS or host.startswith("127."):
        return
    warnings.warn(warning_of("the Dask scheduler {scheduler} is not on this machine: the robot, the map's settings "
                             "and its results travel over the network to it (use tls:// for an encrypted link)",
                             scheduler=scheduler), stacklevel=4)


def _client(scheduler: Any) -> tuple[Any, Callable[[], None]]:
    """A dask.distributed Client for ``scheduler`` (address or Client) and how to let it go."""
    Client = require("distributed", "a Dask scheduler (scheduler=)").Client
    if isinstance(scheduler, Client):
        return scheduler, lambda: None
    if not isinstance(scheduler, str) or "://" not in scheduler:
        raise ReachabilityError.of("scheduler must be a Dask scheduler address such as tcp://host:8786, 'local', or a "
                                   "distributed.Client; got {scheduler!r}", scheduler=scheduler)
    _warn_if_remote(scheduler)
    try:
        client = Client(scheduler, timeout=CONNECT_TIMEOUT)
    except (OSError, TimeoutError) as exc:
        raise ReachabilityError.of("cannot reach the Dask scheduler at {scheduler}: {exc}", scheduler=scheduler,
                                   exc=exc) from None
    except Exception as exc:     # an address Dask cannot parse or a protocol it lacks (inproc://, tls:// without certs)
        raise ReachabilityError.of("cannot use the Dask scheduler address {scheduler!r}: {type}: {exc}",
                                   scheduler=scheduler, type=type(exc).__name__, exc=str(exc)[:200]) from None
    return client, client.close


def _local_cluster(workers: int, dashboard: bool = False) -> tuple[Any, Callable[[], None]]:
    """An embedded Dask cluster on this machine. Every service (scheduler, nannies, workers) listens on
    127.0.0.1 only; the dashboard is off unless asked for, and then also on 127.0.0.1 (its URL is printed)."""
    distributed = require("distributed", "a reachability map built by several workers (workers=1 builds it in this process)")
    Client, LocalCluster = distributed.Client, distributed.LocalCluster
    import dask

    # Dask's scheduler always runs an HTTP server (identity, workers, logs, metrics); without the dashboard
    # it serves no route at all, and either way it listens on 127.0.0.1 only
    quiet: dict[str, Any] = {} if dashboard else {"distributed.scheduler.http.routes": [],
                                                   "distributed.worker.http.routes": []}
    with dask.config.set(quiet):
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                               dashboard_address="127.0.0.1:0" if dashboard else None,
                               worker_dashboard_address=None, silence_logs=40)
    client = Client(cluster)
    if dashboard:
        print(f"Dask dashboard: {client.dashboard_link}", flush=True)

    def close() -> None:
        client.close()
        cluster.close()
    return client, close


def _run_dask(client: Any, fn: Callable[..., Any], args: Sequence[tuple[Any, ...]], blocks: Sequence[int],
              token: str) -> Iterator[tuple[int, Any]]:
    from distributed import as_completed

    futures = {client.submit(fn, *a, key=f"armkit-reach-{token}-{b}", pure=False, retries=3): b
               for a, b in zip(args, blocks)}
    try:
        for fut in as_completed(list(futures)):
            b = futures.pop(fut)
            yield b, fut.result()
            fut.release()
    finally:
        for fut in futures:
            fut.cancel()


# ------------------------------------------------------------------ store
class _Store:
    """The Zarr group of a build, with generation-numbered partial results (see ``_map``)."""

    def __init__(self, path: str, attrs: dict[str, Any], grid: Grid, n_blocks: int, overwrite: bool) -> None:
        zarr = require("zarr", "building a reachability map")
        self.grid, self.n_blocks, self.path = grid, n_blocks, path
        self.group: Any
        p = Path(path)
        if overwrite:
            check_overwrite(p)      # only an armkit store is ever deleted (never ., home, a file, other folders)
            if p.exists():
                shutil.rmtree(p)
        if p.exists():
            try:
                g: Any = zarr.open_group(str(p), mode="r+")
                old: dict[str, Any] = dict(g.attrs)
            except Exception as exc:
                raise ReachabilityError.of("{path!r} exists and is not a Zarr reachability map ({type}); choose "
                                           "another path", path=path, type=type(exc).__name__) from None
            if old.get("format") in OLD_FORMATS:
                raise ReachabilityError.of("{path!r} holds a map of an older armkit format; use --overwrite "
                                           "(overwrite=True) to build it again", path=path)
            if old.get("format") != FORMAT:
                raise ReachabilityError.of("{path!r} exists and is not an armkit reachability map; choose another path",
                                           path=path)
            keys = ("robot_toml", "grid", "parameters")
            diff = [k for k in keys if _canon(old.get(k)) != _canon(attrs[k])]
            if diff:
                raise ReachabilityError.of("{path!r} holds a map built with other settings ({names} differ); use "
                                           "another path, or overwrite=True (--overwrite) to start again", path=path,
                                           names=', '.join(diff))
            if old.get("status") != "complete":
                clean_partial(p)    # chunk files a killed build left half-written
            self.group = g
        else:
            self.group = zarr.open_group(str(p), mode="w")
            self.group.attrs.update({**attrs, "status": "building", "generation": -1, "blocks_done": "",
                                     "generation_checksums": {}})
        nx, ny, nz, no = grid.shape
        self.cx = max(1, min(nx, 8_000_000 // max(1, ny * nz * no)))

    @property
    def complete(self) -> bool:
        return self.group.attrs.get("status") == "complete"

    def load(self, counts: NDArray[np.uint8], manip: NDArray[np.float32], done: NDArray[np.bool_]) -> None:
        """Fill the accumulators from the last committed generation; drop uncommitted ones."""
        gen = int(self.group.attrs.get("generation", -1))
        for name in list(self.group.array_keys()):
            if name.rsplit("_", 1)[-1].isdigit() and int(name.rsplit("_", 1)[-1]) != gen:
                del self.group[name]
        if gen < 0:
            return
        sums = self.group.attrs.get("generation_checksums", {})
        try:
            c = np.asarray(self.group[f"counts_{gen}"][...])
            m = np.asarray(self.group[f"manipulability_{gen}"][...])
            bits = bytes.fromhex(str(self.group.attrs.get("blocks_done", "")))
            d = np.unpackbits(np.frombuffer(bits, dtype=np.uint8), count=self.n_blocks).astype(bool)
            ok = (isinstance(sums, dict) and checksum(c) == sums.get("counts")
                  and checksum(m) == sums.get("manipulability") and c.size == counts.size and m.size == manip.size)
        except Exception:      # a damaged partial build: missing arrays or chunks, bad hex, wrong sizes
            ok = False
        if not ok:
            raise ReachabilityError.of("the unfinished build in {path!r} is damaged (its partial results do not match "
                                       "their checksums); use --overwrite (overwrite=True) to start again",
                                       path=self.path)
        counts[:] = c.reshape(-1)
        manip[:] = m.reshape(-1)
        done[:] = d

    def _write(self, name: str, data: NDArray[Any], chunks: tuple[int, ...]) -> None:
        if name in self.group:
            del self.group[name]
        arr = self.group.create_array(name, shape=data.shape, chunks=chunks, dtype=data.dtype, fill_value=0)
        arr[...] = data

    def commit(self, counts: NDArray[np.uint8], manip: NDArray[np.float32], done: NDArray[np.bool_]) -> None:
        """Write a new generation in full, then switch the attributes to it, then drop the old one."""
        g = self.grid
        old = int(self.group.attrs.get("generation", -1))
        new = old + 1
        ny, nz, no = g.shape[1:]
        self._write(f"counts_{new}", counts.reshape(g.shape), (self.cx, ny, nz, no))
        self._write(f"manipulability_{new}", manip.reshape(g.dims), (self.cx, ny, nz))
        sums = {"counts": checksum(counts.reshape(g.shape)), "manipulability": checksum(manip.reshape(g.dims))}
        self.group.attrs.update({"generation": new, "blocks_done": np.packbits(done).tobytes().hex(),
                                 "generation_checksums": sums})
        for name in (f"counts_{old}", f"manipulability_{old}"):
            if name in self.group:
                del self.group[name]

    def finish(self, counts: NDArray[np.uint8], hits: NDArray[np.bool_], manip: NDArray[np.float32],
               version: str) -> None:
        g = self.grid
        ny, nz, no = g.shape[1:]
        self._write("counts", counts.reshape(g.shape), (self.cx, ny, nz, no))
        self._write("hits", hits.reshape(g.shape), (self.cx, ny, nz, no))
        self._write("manipulability", manip.reshape(g.dims), (self.cx, ny, nz))
        index = hits.reshape(-1, g.n_orient).mean(axis=1).astype(np.float32).reshape(g.dims)
        self._write("index", index, (self.cx, ny, nz))
        sums = {"counts": checksum(counts.reshape(g.shape)), "hits": checksum(hits.reshape(g.shape)),
                "manipulability": checksum(manip.reshape(g.dims)), "index": checksum(index)}
        self.group.attrs.update({"status": "complete", "armkit_version": version, "checksums": sums})
        gen = int(self.group.attrs.get("generation", -1))
        for name in (f"counts_{gen}", f"manipulability_{gen}"):
            if name in self.group:
                del self.group[name]


def _canon(x: Any) -> Any:
    import json

    return json.dumps(x, sort_keys=True, default=str)


def reachability(robot: Robot | str, resolution: float | None = None, orientations: int | None = None,
                 scene: Any = None, *, rolls: int | None = None, method: Literal["fk", "ik"] = "fk",
                 samples: int | None = None, seed: int = 0, path: str | os.PathLike[str] | None = None,
                 overwrite: bool = False, scheduler: Any = None, workers: int | None = None,
                 block_size: int | None = None, restarts: int = 2, coverage: float = DEFAULT_COVERAGE,
                 flush_seconds: float = 10.0, dashboard: bool = False,
                 progress: Progress | None = None) -> ReachabilityMap:
    """Build a reachability map: which tool poses the arm reaches, cell by cell.

    Parameters
    ----------
    robot : Robot or str
        The arm (or a bundled name / robot file path).
    resolution : float, optional
        Voxel edge in the robot's length unit; default ``robot.reach / 20``.
    orientations : int, optional
        Approach directions per voxel (Fibonacci sphere); default 64, or 1 (position only)
        for arms with fewer than 6 joints.
    scene : armkit.Scene, sequence of shapes, path or "robot", optional
        Exclude configurations that collide with it or with the arm itself (``armkit.clearance``
        > 0); anything :func:`armkit.collision.as_scene` reads. Costs a collision check per sample.
    rolls : int, optional
        Roll bins about each approach direction; default 1 when the last joint turns the
        tool about its own z axis through 2 pi (the roll is then free, exactly), else 8.
    method : {"fk", "ik"}
        ``"fk"`` (default): sample joint space and bin the poses (RM4D); no solver can
        miss or invent a pose, and it is ~100x cheaper per cell than IK. ``"ik"``: solve IK
        at the centre of every cell (closed form where there is one, else LM with
        ``restarts``): the ground truth at the centres, slow for redundant arms.
    samples : int, optional
        FK configurations in all (method "fk"); default 32 per cell (at most 2e9), in whole blocks.
    seed : int
        Seeds every random stream: the same arguments give the same map, bit for bit.
    path : path, optional
        Zarr store to write (and to resume from when it holds an unfinished build of the
        same map). ``overwrite`` discards what is there.
    scheduler : str or distributed.Client, optional
        ``"tcp://host:8786"`` runs the blocks on that Dask cluster; ``None`` reads the
        ``ARMKIT_SCHEDULER`` environment variable, and without it runs on this machine:
        in this process (``workers=1``) or on an embedded Dask LocalCluster of
        ``workers`` processes. Default: the CPU count, or this process on a machine with
        at most 2 cores (there Numba's multi-threaded FK already uses both, and a cluster
        only adds its start-up; measured in docs/reachability.md).
    block_size : int, optional
        FK configurations per block (default 1,000,000) or x-slabs per IK block (default 1).
    restarts : int
        LM restarts per cell (method "ik" on arms without a closed form).
    coverage : float
        Method "fk": a cell with samples is reachable when its sample density is at least
        this fraction of the densest neighbouring cell (0: any sample will do, as in RM4D).
    dashboard : bool
        With a local cluster (``workers`` > 1): serve Dask's dashboard on 127.0.0.1 and print its
        URL. Off by default; every service of a local cluster listens on 127.0.0.1 only.
    progress : callable, optional
        Called as ``progress(blocks_done, blocks_total)``.

    Returns
    -------
    ReachabilityMap
    """
    from ._scene import check_scene

    if isinstance(robot, str):
        robot = load(robot)
    if not isinstance(robot, Robot):
        raise ReachabilityError.of("robot must be an armkit.Robot or a robot name, got {type}",
                                   type=type(robot).__name__)
    if method not in ("fk", "ik"):
        raise ReachabilityError.of("method must be 'fk' or 'ik', got {method!r}", method=method)
    scene = check_scene(robot, scene)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ReachabilityError.of("seed must be a non-negative integer, got {seed!r}", seed=seed)
    grid = _make_grid(robot, resolution, orientations, rolls)
    if isinstance(coverage, bool) or not isinstance(coverage, (int, float)) or not 0 <= coverage <= 1:
        raise ReachabilityError.of("coverage must be a number in [0, 1], got {coverage!r}", coverage=coverage)
    bs, total, sizes = _blocks(method, grid, samples, block_size)
    _check_build_memory(robot, grid, method, bs)
    n_blocks = len(sizes)
    restarts = int(restarts) if method == "ik" else restarts
    if workers is not None:
        workers = _positive_int(workers, "workers")
    params: dict[str, Any] = {"method": method, "samples": total if method == "fk" else None, "seed": int(seed),
                              "block_size": bs, "restarts": restarts if method == "ik" else None,
                              "scene": None if scene is None else _digest(repr(scene)),
                              "coverage": float(coverage) if method == "fk" else None}
    gattrs = grid.to_attrs()
    try:
        toml = robot_to_toml(robot)
    except Exception as exc:  # a robot the TOML writer cannot express yet
        raise ReachabilityError.of("robot {robot!r} cannot be written to a robot file ({exc})", robot=robot.name,
                                   exc=exc) from None
    _check_round_trip(robot, toml)
    attrs = {"format": FORMAT, "robot": robot.name, "robot_toml": toml, "robot_sha256": robot_sha256(toml),
             "grid": gattrs, "parameters": params, "settings_sha256": settings_sha256(gattrs, params)}

    counts = np.zeros(grid.n_cells, dtype=np.uint8)
    manip = np.zeros(int(np.prod(grid.dims)), dtype=np.float32)
    done = np.zeros(n_blocks, dtype=bool)
    store = None
    if path is not None:
        store = _Store(os.fspath(path), attrs, grid, n_blocks, overwrite)
        if store.complete:
            return ReachabilityMap.open(os.fspath(path))
        store.load(counts, manip, done)

    todo = [b for b in range(n_blocks) if not done[b]]
    args: list[tuple[Any, ...]]
    if method == "fk":
        fn: Callable[..., Any] = fk_block
        args = [(robot, gattrs, int(seed), b, sizes[b], scene) for b in todo]
    else:
        fn = ik_block
        args = [(robot, gattrs, int(seed), b, bs, restarts, scene) for b in todo]
    results, close = _execute(scheduler, workers, fn, args, todo, _token(attrs), bool(dashboard))
    _merge(results, close, counts, manip, done, store, progress, flush_seconds)
    hits = decide(counts.reshape(grid.shape), grid, coverage if method == "fk" else 0.0)
    if store is not None:
        store.finish(counts, hits, manip, __version__)
    params = {**params, "armkit_version": __version__}
    return ReachabilityMap(robot, grid, hits, manip.reshape(grid.dims), params, counts.reshape(grid.shape),
                           None if path is None else os.fspath(path))


MAX_BLOCKS = 1_000_000
"""Units of work in one build (the done-list, the futures): 10^12 FK samples in default blocks."""


def _check_build_memory(robot: Robot, grid: Grid, method: str, bs: int) -> None:
    """The driver's peak (per cell: the counts, the hits and decide()'s float32 density and its three
    neighbourhood passes, 18 B; per voxel: manipulability and index, 8 B) and, for IK, one block's targets
    and solutions (per cell of a block: a pose, q, the result's fields, about 128 + 24 n B), against the budget."""
    from .._limits import check_memory

    cells = float(grid.n_cells)
    voxels = float(np.prod([float(d) for d in grid.dims]))
    hint = "use a coarser resolution or fewer orientations/rolls"
    check_memory(18 * cells + 8 * voxels + 200 * grid.n_orient, f"a map of {cells:,.0f} cells", hint)
    if method == "ik":
        block_cells = float(bs) * grid.dims[1] * grid.dims[2] * grid.n_orient
        check_memory(block_cells * (128 + 24 * robot.n), f"an IK block of {block_cells:,.0f} cells", hint)


def _blocks(method: str, grid: Grid, samples: int | None, block_size: int | None) -> tuple[int, int, list[int]]:
    """Block size, total work (FK samples or cells) and the size of each block."""
    if method == "fk":
        bs = FK_BLOCK if block_size is None else _positive_int(block_size, "block_size")
        total = default_samples(grid) if samples is None else _positive_int(samples, "samples")
        if math.ceil(total / bs) > MAX_BLOCKS:
            raise ReachabilityError.of("{total:,} samples in blocks of {bs:,} make {units:,} units of work; at most "
                                       "{limit:,} (use fewer samples or a larger block_size)", total=total, bs=bs,
                                       units=math.ceil(total / bs), limit=MAX_BLOCKS)
        return bs, total, [min(bs, total - b * bs) for b in range(int(math.ceil(total / bs)))]
    bs = 1 if block_size is None else _positive_int(block_size, "block_size")
    return bs, grid.n_cells, [bs] * int(math.ceil(grid.dims[0] / bs))   # ik: blocks of x-slabs


def _execute(scheduler: Any, workers: int | None, fn: Callable[..., Any], args: list[tuple[Any, ...]],
             todo: list[int], token: str, dashboard: bool = False
             ) -> tuple[Iterator[tuple[int, Any]], Callable[[], None]]:
    """``(block, result)`` pairs as they finish, from a Dask scheduler, a local cluster or this process;
    and how to let the executor go."""
    if scheduler is None:
        scheduler = os.environ.get("ARMKIT_SCHEDULER") or None
    if scheduler == "local":
        scheduler = None
    if workers is None:     # up to 2 cores, this process is fastest: Numba's threaded FK already uses both
        cpus = os.cpu_count() or 1
        n_workers = 1 if cpus <= 2 else cpus
    else:
        n_workers = workers
    if scheduler is not None:
        client, close = _client(scheduler)
        return _run_dask(client, fn, args, todo, token), close
    if n_workers > 1 and len(todo) > 1:
        client, close = _local_cluster(min(n_workers, len(todo)), dashboard)
        return _run_dask(client, fn, args, todo, token), close
    return ((b, fn(*a)) for a, b in zip(args, todo)), lambda: None


def _merge(results: Iterator[tuple[int, Any]], close: Callable[[], None], counts: NDArray[np.uint8],
           manip: NDArray[np.float32], done: NDArray[np.bool_], store: "_Store | None", progress: Progress | None,
           flush_seconds: float) -> None:
    """Add each block's hits into ``counts``/``manip`` (in place), committing to ``store`` every ``flush_seconds``."""
    n_blocks = len(done)
    count = int(done.sum())
    if progress is not None:
        progress(count, n_blocks)
    last = time.monotonic()
    merged_since_commit = False
    try:
        for b, (cells, hits_here, vox, man) in results:
            counts[cells] = np.minimum(counts[cells].astype(np.int64) + hits_here, 255).astype(np.uint8)
            if len(vox):
                manip[vox] = np.maximum(manip[vox], man)
            done[b] = True
            merged_since_commit = True
            count += 1
            if progress is not None:
                progress(count, n_blocks)
            if store is not None and time.monotonic() - last > flush_seconds:
                store.commit(counts, manip, done)
                merged_since_commit = False
                last = time.monotonic()
    finally:
        close()
        if store is not None and count < n_blocks and merged_since_commit:
            store.commit(counts, manip, done)          # keep what is merged; the next run resumes


def _check_round_trip(robot: Robot, toml: str) -> None:
    """The stored robot file must give the same FK, or a reopened map would answer for another arm."""
    from ._map import robot_from_toml

    back = robot_from_toml(toml, robot.name)
    q = robot.random_q(16, rng=7)
    if back.n != robot.n or not np.allclose(fk(back, q), fk(robot, q), atol=1e-9 * max(1.0, robot.reach)):
        raise ReachabilityError.of("robot {robot!r} does not survive being written to a robot file (its FK changes); "
                                   "it cannot be stored in a map", robot=robot.name)


def _digest(text: str) -> str:
    import hashlib

    return hashlib.sha1(text.encode()).hexdigest()[:12]


def _token(attrs: dict[str, Any]) -> str:
    return _digest(_canon(attrs))
