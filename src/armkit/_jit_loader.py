"""The back end: which kernels serve (Numba or NumPy), when armkit's Numba kernels are compiled,
where they are cached, and what serves until then.

The ground floor of armkit (docs/architecture.md): this module imports only the standard
library and :mod:`armkit.errors`, and knows nothing of the floors above it. It owns the
back-end state (:func:`set_backend`, :func:`get_backend`, :func:`jit_module`); the warm-up
that exercises the public functions lives on the top floor, :mod:`armkit.warmup`.

Compiling every kernel takes tens of seconds; a compiled kernel is cached on disk and loads in
milliseconds afterwards. So that the first call of a fresh install does not wait for that,
the back end ``"auto"`` (the default, see :func:`armkit.set_backend`) works like this:

* **The kernels are known to be cached** (a marker file next to the cache says that this
  build's kernels were all compiled there): they are used at once, as before.
* **They are not**: the first kinematics call starts one *warm-up process*
  (:func:`armkit.warmup._worker_main` in a new Python process) that compiles them into the
  cache, says so once on stderr, and the NumPy back end answers meanwhile (the same results,
  to about 1e-15 for kinematics; IK gives the same branches and messages, and for targets
  that need random restarts possibly another valid solution). When the warm-up process has
  written its first marker, the next ``fk``/``jacobian``/``fk_frames`` call switches to the
  compiled kernels. Large batches run on one thread until the multi-threaded kernels are
  cached too (second marker). The process keeps going if the caller exits, so the next
  run finds the cache warm. One warm-up process per cache at a time (a lock file).
* ``ARMKIT_JIT=wait`` restores compiling on first use in the calling process;
  ``armkit.set_backend("numba")`` and :func:`armkit.warmup` also compile in the calling process.

The cache goes where Numba puts it (``NUMBA_CACHE_DIR``, else the package's
``__pycache__``, else ``~/.cache/numba``); where none of those is writable (a read-only
install without a writable home) it goes to a private directory under the temp directory
(:func:`fallback_cache_dir`). Numba is imported on the first kinematics call, not at
``import armkit``.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import importlib
import os
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any, Callable, Iterator, Literal, Optional

from . import _kernel_store
from .errors import ArgumentError, ArmkitError

__all__ = ["set_backend", "get_backend", "jit_module", "serve", "load_jit", "backend_choice", "ready", "parallel_ok",
           "cache_dir", "fallback_cache_dir", "install_cache_fallback", "module", "kernels", "forget_stale_cache",
           "compiling_here", "serial_only", "marker", "lock_alive", "forget_other_builds", "say_compiling", "release_lock",
           "compiled_entry", "set_renderer", "restore_kernels", "save_kernels"]

_PKG = Path(__file__).resolve().parent
_SOURCES = ("kinematics/_jit.py", "ik/_jit_lm.py", "ik/_jit_verify.py", "ik/analytic/_jit.py", "ik/analytic/_layout.py",
            "ik/geometric/_kernels.py", "ik/geometric/subproblems.py", "ik/geometric/solvers.py", "ik/geometric/solvers_wrist.py",
            "ik/geometric/solvers_parallel.py", "ik/geometric/solvers_search.py", "ik/geometric/solvers_check.py",
            "ik/geometric/solvers_chain.py", "ik/geometric/one_call.py", "ik/geometric/locked_jit.py",
            "ik/geometric/batched.py", "ik/geometric/search.py",
            "ik/geometric/search2d.py", "ik/analytic/_yaw_pitch3_jit.py", "ik/analytic/_yaw_pitch3_teleop.py",
            "ik/analytic/_single.py", "ik/_ccd_jit.py", "ik/ccd.py", "collision/_jit.py", "collision/_jit_pairs.py",
            "_jit_loader.py", "_jit_twins.py", "_jit_shaped.py", "warmup.py")
COMPILE_SECONDS = 45
"""About how long compiling the one-thread kernels takes, the figure of the stderr note (the warm-up
process switched the caller to them after 44-53 s in benchmarks/bench_first_call.py on the shared
2-core machine at load average 8-11; the multi-threaded ones take about as long again)."""

_mode = os.environ.get("ARMKIT_JIT", "background")  # "background" or "wait"
_state: Optional[str] = None   # None: not decided yet; "ready"; "warming"; "sync" (compile in this process)
_parallel = False              # the multi-threaded kernels may be used (cached, or compiled here on demand)
_next_poll = 0.0
_next_parallel_poll = 0.0
_serial_only = False           # the warm-up's first phase: compile only the one-thread kernels
_worker: Any = None            # the warm-up process this process started
_told: set[str] = set()
_decide_lock = threading.Lock()

_backend = os.environ.get("ARMKIT_BACKEND", "auto")   # the choice: "auto", "numba" or "numpy"
_ACTIVE: Any = None   # the kernel module of serve() while Numba is the back end in use (the single-call fast
                      # path of armkit.kinematics reads only this)


# ------------------------------------------------------------------------------------ the back end
def set_backend(name: Literal["auto", "numba", "numpy"]) -> None:
    """Choose the kernels: ``"numba"``, ``"numpy"`` or ``"auto"`` (Numba when importable)."""
    global _backend, _ACTIVE
    if name not in ("auto", "numba", "numpy"):
        raise ArgumentError.of("backend must be 'auto', 'numba' or 'numpy', got {name!r}", name=name)
    if name == "numba" and load_jit() is None:
        raise ArmkitError.of("backend 'numba' requested but numba is not installed")
    _backend = name
    _ACTIVE = None


def get_backend() -> str:
    """The kernels in use now: ``"numba"`` or ``"numpy"``."""
    return "numba" if jit_module() is not None else "numpy"


def backend_choice() -> str:
    """The back end chosen by :func:`set_backend` (``"auto"``, ``"numba"`` or ``"numpy"``), not what serves now."""
    return _backend


_PRIMARY: Optional[str] = None   # the kernel module that stands for the Numba back end (set by armkit.kinematics)


def serve(name: str) -> None:
    """Name the kernel module that stands for the Numba back end: :func:`jit_module` returns it and its
    cache directory is :func:`cache_dir`. :mod:`armkit.kinematics` names its own (``"kinematics._jit"``);
    this floor knows no module above it."""
    global _PRIMARY, _ACTIVE
    _PRIMARY, _ACTIVE = name, None
    cache_dir.cache_clear()


def load_jit() -> Any:
    """The kernel module named by :func:`serve` (:func:`module`), or None when Numba is unavailable."""
    return None if _PRIMARY is None else module(_PRIMARY)


def jit_module(poll: bool = False) -> Any:
    """The kernel module named by :func:`serve` while the Numba back end serves, else None.

    With ``poll`` (``fk``, ``jacobian``, ``fk_frames``) the back end ``"auto"`` looks whether
    the warm-up process has finished (:func:`ready`).
    """
    global _ACTIVE
    if _backend == "numpy" or _backend == "auto" and not ready(poll):
        return None  # NumPy serves while the kernels compile in the background (fk, jacobian, fk_frames poll)
    _ACTIVE = load_jit()
    return _ACTIVE


# ---------------------------------------------------------------------------------------- cache
def fallback_cache_dir() -> Path:
    """The cache used when neither Numba's in-tree nor its user-wide cache is writable:
    ``<temp dir>/armkit-numba-<uid>``, created private (mode 0700) and used only if it is ours."""
    uid = os.getuid() if hasattr(os, "getuid") else 0
    path = Path(tempfile.gettempdir()) / f"armkit-numba-{uid}"
    path.mkdir(mode=0o700, exist_ok=True)
    st = path.stat()
    if hasattr(os, "getuid") and (st.st_uid != uid or st.st_mode & 0o022):
        raise OSError(f"{path} belongs to another user or is writable by others")  # never load foreign pickles
    return path


_installed = False


def install_cache_fallback() -> None:
    """Add a last Numba cache locator, for armkit's files only, that writes to :func:`fallback_cache_dir`.

    Numba tries ``NUMBA_CACHE_DIR``, the source's ``__pycache__`` and ``~/.cache/numba`` first;
    when none is writable it refuses to decorate a ``cache=True`` function at all, so this
    runs before armkit's kernel modules are imported (they call it first thing).
    """
    global _installed
    if _installed:
        return
    _installed = True
    from numba.core import caching

    impl = getattr(caching, "CacheImpl", None) or getattr(caching, "_CacheImpl", None)
    base = getattr(caching, "UserWideCacheLocator", None) or getattr(caching, "_UserWideCacheLocator", None)
    if impl is None or base is None or not hasattr(impl, "_locator_classes"):  # another Numba: its own rules
        return

    class ArmkitFallbackLocator(base):  # type: ignore[misc, valid-type]
        def __init__(self, py_func: Any, py_file: str) -> None:
            self._py_file = py_file
            self._lineno = py_func.__code__.co_firstlineno
            self._cache_path = str(fallback_cache_dir() / self.get_suitable_cache_subpath(py_file))

        @classmethod
        def from_function(cls, py_func: Any, py_file: str) -> Any:
            try:
                if not Path(py_file).resolve().is_relative_to(_PKG):
                    return None
            except (OSError, ValueError):
                return None
            try:
                return super().from_function(py_func, py_file)
            except OSError:
                return None

    impl._locator_classes = list(impl._locator_classes) + [ArmkitFallbackLocator]


# ------------------------------------------------------------------------------- the modules
_MODULES: dict[str, Any] = {}  # module name -> module (False: no Numba); process-wide like sys.modules, not per robot


def module(name: str) -> Any:
    """The kernel module ``armkit.<name>`` (``"kinematics._jit"``, ``"ik._jit_lm"``, ``"ik._jit_verify"``,
    ``"ik.analytic._jit"``), imported on first use; None when Numba is not importable.

    The one way armkit loads its JIT modules lazily; whether they serve a call is the back
    end's choice (:func:`kernels`).
    """
    mod = _MODULES.get(name)
    if mod is None:
        try:
            mod = importlib.import_module(f"armkit.{name}")
        except ImportError:  # numba missing or broken: the NumPy code serves
            mod = False
        _MODULES[name] = mod
    return mod or None


def compiled_entry(kernel: Any, *sample: Any) -> Any:
    """The compiled function of the Numba ``kernel`` for the types of the ``sample`` arguments (compiled now if
    it is not yet), which a hot caller then calls without the dispatcher typing every argument on every call; the
    ``kernel`` itself where it has no ``compile`` (not a Numba dispatcher). The caller must pass arguments of
    exactly those types (a read-only array where the kernel only reads it is the same type to the compiled code)."""
    compile_ = getattr(kernel, "compile", None)
    if compile_ is None:
        return kernel
    import numba

    return compile_(tuple(numba.typeof(a) for a in sample))


def kernels(name: str) -> Any:
    """:func:`module` while the Numba back end is in use (:func:`get_backend`), else None."""
    if jit_module() is None:
        return None
    return module(name)


def forget_stale_cache(namespace: dict[str, Any], depends_on: tuple[str, ...]) -> None:
    """Make the on-disk cache of one kernel module follow the other armkit files whose helpers it inlines.

    Numba's cache checks only the file that defines a kernel; a kernel that inlines helpers of
    another file (``ik/_jit_lm.py`` uses the pose helpers of ``kinematics/_jit.py``) would load
    stale code after those change. So a stamp file next to the cache holds a hash of those
    sources; when it differs, this module's cached kernels are deleted (compiled anew on first
    use) and the stamp rewritten. Call it at the end of the module, before any kernel runs.

    Parameters
    ----------
    namespace : dict
        The module's ``globals()``: its ``cache=True`` kernels are found there.
    depends_on : tuple of str
        The files it inlines from, relative to the package (``"kinematics/_jit.py"``).
    """
    h = hashlib.sha1()
    for rel in depends_on:
        h.update((_PKG / rel).read_bytes())
    digest = h.hexdigest()
    stem = Path(namespace["__file__"]).stem
    own = os.path.realpath(namespace["__file__"])
    # the module's own kernels only: one it imported from another file (ik/analytic/_jit.py holds the sine and
    # cosine of kinematics/_jit.py) caches in that file's folder, where a stamp of this stem (the same "_jit") would
    # delete that module's files and fight its own stamp on every import
    dirs = {Path(p) for obj in list(namespace.values())
            if (p := getattr(getattr(obj, "_cache", None), "_cache_path", None))
            and ((code := getattr(getattr(obj, "py_func", None), "__code__", None)) is None
                 or os.path.realpath(code.co_filename) == own)}
    for d in dirs:
        stamp = d / f"{stem}.armkit-deps"
        try:
            if stamp.exists() and stamp.read_text() == digest:
                continue
            for old in list(d.glob(f"{stem}.*.nbi")) + list(d.glob(f"{stem}.*.nbc")):
                old.unlink(missing_ok=True)
            stamp.write_text(digest)
        except OSError:  # a read-only cache: Numba then cannot write there either
            pass


@functools.lru_cache(maxsize=None)  # a fact of this process (where Numba caches), not of a robot
def cache_dir() -> Optional[Path]:
    """The directory where the kernels of :func:`serve` are cached (imports Numba), or None if caching is off."""
    kernels = load_jit()
    path = next((p for obj in vars(kernels).values() if (p := getattr(getattr(obj, "_cache", None), "_cache_path",
                                                                          None))), None) if kernels else None
    return Path(path) if path else None


@functools.lru_cache(maxsize=None)  # a fact of this build (hash of the kernel sources), not of a robot
def _key() -> str:
    """This build's kernels: their sources, the Numba and Python versions, the machine."""
    h = hashlib.sha1()
    for rel in _SOURCES:
        h.update((_PKG / rel).read_bytes())
    h.update(_versions().encode())
    return h.hexdigest()[:16]


@functools.lru_cache(maxsize=None)
def _versions() -> str:
    """The Numba and Python versions, the platform and the machine: what a build's kernels depend on besides their
    sources (:func:`_key`, and the kernel store's build with llvmlite's version)."""
    import numba

    return f"{numba.__version__} {sys.version} {sys.platform} {os.uname().machine if hasattr(os, 'uname') else ''}"


def forget_other_builds() -> None:
    """Remove the marker, lock and log files of other builds (older sources) from the cache directory."""
    d = cache_dir()
    if d is None:
        return
    for old in d.glob("armkit-kernels-*.*"):
        if not old.name.startswith(f"armkit-kernels-{_key()}."):
            try:
                old.unlink()
            except OSError:
                pass


def marker(suffix: str) -> Optional[Path]:
    """This build's marker file ``suffix`` (``"ready"``, ``"parallel"``, ``"lock"``, ``"log"``) in the cache
    directory; None when Numba's cache is off."""
    d = cache_dir()
    return None if d is None else d / f"armkit-kernels-{_key()}.{suffix}"


# ------------------------------------------------------------------------------- the kernel store
def _store() -> Optional[tuple[Path, str, list[Path]]]:
    """``(store folder, build, this build's marker files)`` of :mod:`armkit._kernel_store` for the package's own
    cache, or None where there is none to share: the store is off, Numba's cache is off or not in the package's
    ``__pycache__`` folders (``NUMBA_CACHE_DIR``, a read-only install)."""
    store = _kernel_store.store_root()
    d = cache_dir()
    if store is None or d is None or not d.resolve().is_relative_to(_PKG):
        return None
    import llvmlite

    versions = f"{_versions()} llvmlite {llvmlite.__version__}"
    return store, _kernel_store.build_id(_PKG, versions), _store_markers()


def _store_markers() -> list[Path]:
    """This build's marker files that the kernel store keeps with the kernels (``armkit warmup``'s two and the test
    suite's), where Numba's cache is on."""
    return [m for m in (marker("ready"), marker("parallel"), marker("tests")) if m is not None]


def restore_kernels() -> bool:
    """Copy this build's compiled kernels from the kernel store (:mod:`armkit._kernel_store`) into the package's
    cache, where the store has them and the cache has none of this build's marker files and no warm-up process at
    work: a new install of the same sources then compiles nothing. True where kernels were copied; never raises (a
    store that fails is no store)."""
    try:
        if lock_alive() or any(m.exists() for m in _store_markers()):   # a warm-up process at work, or this
            return False          # cache's own kernels: said before the build's hash is taken (5-9 ms)
        where = _store()
        return where is not None and _kernel_store.restore(where[0], where[1], _PKG, where[2])
    except (OSError, ImportError, ValueError):
        return False


def save_kernels() -> bool:
    """Copy the package's kernel cache into the kernel store (:mod:`armkit._kernel_store`) for later installs of
    the same sources, where the store holds fewer of this build's files. True where a copy was made; never raises."""
    try:
        where = _store()
        return where is not None and _kernel_store.save(where[0], where[1], _PKG, where[2])
    except (OSError, ImportError, ValueError):
        return False


# ------------------------------------------------------------------------------------ the state
def N_(text: str) -> str:
    """Mark a note's English wording for the catalogue (``make locale-update``); :func:`_say` renders it. (This
    floor imports nothing of :mod:`armkit.locale`, whose ``N_`` is the same identity.)"""
    return text


NOTE_COMPILING = N_("compiling armkit's kernels once, about {seconds} s in all (cached on disk for the next runs; "
                    "`armkit warmup` does it ahead of time)")
NOTE_COMPILING_NO_HINT = N_("compiling armkit's kernels once, about {seconds} s in all (cached on disk for the next "
                            "runs)")
NOTE_BACKGROUND = N_("compiling armkit's kernels once in the background, about {seconds} s; the NumPy back end "
                     "answers meanwhile (`armkit warmup` does this ahead of time)")
NOTE_FAILED = N_("the warm-up process failed (see {log}); compiling armkit's kernels here, on first use, about "
                 "{seconds} s in all")
"""The notes :func:`_say` prints: each a template and its fields, worded in the user's language by the front end's
renderer (:func:`set_renderer`), in English without one."""

_RENDER: list[Callable[[str, dict[str, Any]], str]] = []


def set_renderer(render: Callable[[str, dict[str, Any]], str]) -> None:
    """Have the notes on stderr worded by ``render(template, fields)``: the command line installs the catalogue's
    (:func:`armkit.locale._`, the user's ``--lang``), so that a Korean session's note is Korean. The library alone
    prints them in English, as its messages."""
    _RENDER[:] = [render]


def _say(template: str, what: str = "compiling", **fields: Any) -> None:
    """Print ``armkit: <the note>`` on stderr, once per process for each ``what``: ``template`` with ``fields``, in
    the renderer's language (:func:`set_renderer`; English when none is set, or when it fails)."""
    if what in _told:
        return
    _told.add(what)
    text = template.format(**fields)
    if _RENDER:
        try:
            text = _RENDER[0](template, fields)
        except Exception:  # noqa: BLE001  (a note must never stop the work it announces: the English)
            pass
    print(f"armkit: {text}", file=sys.stderr, flush=True)


def ready(poll: bool = False) -> bool:
    """True when the compiled kernels may be used now; False while the warm-up process compiles them.

    Called by :mod:`armkit.kinematics` for the back end ``"auto"``. The first call decides
    (and starts the warm-up process if needed). Later calls with ``poll`` look for its
    marker at most every 0.1 s (the NumPy calls meanwhile pay ~0.1 µs); only ``fk``,
    ``jacobian`` and ``fk_frames`` poll, so the back end changes only at their start, never
    between two reads of :func:`armkit.get_backend` inside one computation.
    """
    global _state, _next_poll, _parallel
    if _state in ("ready", "sync"):
        return True
    if _state is None:
        with _decide_lock:  # two threads' first calls: one decision, one warm-up process
            if _state is None:
                _state = _decide()
        return _state != "warming"
    if not poll:
        return False
    now = time.monotonic()
    if now < _next_poll:
        return False
    _next_poll = now + 0.1
    m = marker("ready")
    if m is not None and m.exists():
        _state = "ready"
        _parallel = bool((p := marker("parallel")) and p.exists())
        return True
    if _worker is not None:
        _worker.poll()  # reap our own warm-up process if it ended (a zombie's pid would look alive)
    if not lock_alive():
        # the warm-up process ended without its marker: compile here, on first use, as without it
        _state, _parallel = "sync", True
        _say(NOTE_FAILED, "failed", log=_log_path(), seconds=COMPILE_SECONDS)
        return True
    return False


def parallel_ok() -> bool:
    """True when big batches may use the multi-threaded kernels: they are cached (second marker), or
    compiled here on demand (``ARMKIT_JIT=wait``, ``set_backend("numba")``, no cache)."""
    global _parallel, _next_parallel_poll
    if _parallel:
        return True
    if _serial_only:
        return False
    if _mode == "wait":   # kernels are compiled in this process, on first use: the threaded ones too
        return True
    if _state == "ready":
        now = time.monotonic()
        if now >= _next_parallel_poll:
            _next_parallel_poll = now + 0.5
            p = marker("parallel")
            _parallel = bool(p and p.exists())
        return _parallel
    return True


def say_compiling(hint: bool = True) -> None:
    """Say once on stderr that the kernels are being compiled here (``hint``: name ``armkit warmup``)."""
    _say(NOTE_COMPILING if hint else NOTE_COMPILING_NO_HINT, seconds=COMPILE_SECONDS)


_here = 0   # how many compiling_here blocks are open (armkit warmup, the warm-up process)


def say_when_compiling() -> None:
    """:func:`say_compiling` when this process first compiles one of armkit's kernels, not before: kernels compiled
    here on first use (``ARMKIT_JIT=wait``, no warm-up marker) may all be in Numba's cache already, and then nothing
    is compiled and nothing is said. Numba's event API tells (its ``numba:compile`` event fires only for a kernel
    not found in the cache); where it is missing, :func:`say_compiling` at once, as before."""
    try:
        from numba.core import event
    except ImportError:
        say_compiling()
        return

    class _FirstCompile(event.Listener):  # type: ignore[misc, name-defined]
        def on_start(self, ev: Any) -> None:
            if "compiling" not in _told and not _here:   # (compiling_here: its caller says what it does)
                fn = getattr(ev.data.get("dispatcher"), "py_func", None)
                if (getattr(fn, "__module__", None) or "").startswith("armkit"):
                    say_compiling()

        def on_end(self, ev: Any) -> None:
            pass

    event.register("numba:compile", _FirstCompile())


def _decide() -> str:
    global _parallel, _worker
    try:
        install_cache_fallback()
    except ImportError:   # no Numba: nothing to compile; module() finds no kernels and NumPy answers
        return "sync"
    ready_marker = marker("ready")
    if ready_marker is not None and not ready_marker.exists():
        restore_kernels()   # compiled by another install of the same sources: copied, not compiled again
    if ready_marker is not None and ready_marker.exists():
        p = marker("parallel")
        _parallel = bool(p and p.exists())
        if not _parallel and _mode != "wait" and _take_lock():
            # a warm-up cut short after its first phase (Ctrl-C, a killed process): finish it in the
            # background, or big batches would stay on one thread for good
            try:
                _worker = _spawn()
            except (OSError, ValueError, TypeError):
                release_lock()
        return "ready"
    if _mode == "wait" or ready_marker is None:
        _parallel = True
        say_when_compiling()
        return "sync"
    if _take_lock():
        try:
            _worker = _spawn()
        except (OSError, ValueError, TypeError):  # no usable interpreter to start (embedded Python)
            release_lock()
            _parallel = True
            say_when_compiling()
            return "sync"
    _say(NOTE_BACKGROUND, seconds=COMPILE_SECONDS)
    return "warming"


# ------------------------------------------------------------------------- the warm-up process
def _lock_path() -> Path:
    m = marker("lock")
    assert m is not None
    return m


def _log_path() -> Path:
    m = marker("log")
    assert m is not None
    return m


def _take_lock() -> bool:
    """Create the lock file (False if a live warm-up process holds it); a stale lock (dead owner,
    or older than 15 minutes) is replaced."""
    path = _lock_path()
    for _ in range(2):
        try:
            fd = os.open(path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o600)
        except FileExistsError:
            if lock_alive():
                return False
            path.unlink(missing_ok=True)
            continue
        except OSError:
            return False
        with os.fdopen(fd, "w") as f:
            f.write(str(os.getpid()))
        return True
    return False


def lock_alive() -> bool:
    """True while a live warm-up process holds the lock file (one younger than 15 minutes)."""
    path = _lock_path()
    try:
        pid = int(path.read_text() or "0")
        age = time.time() - path.stat().st_mtime
    except (OSError, ValueError):
        return False
    if age > 900:
        return False
    if os.name == "nt":  # os.kill(pid, 0) would terminate the process there: trust the age
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:
        pass
    return True


def release_lock() -> None:
    """Remove the lock file (the warm-up process ends)."""
    try:
        _lock_path().unlink(missing_ok=True)
    except OSError:
        pass


_WORKER = "import sys; from armkit.warmup import _worker_main; sys.exit(_worker_main(sys.argv[1]))"
"""The warm-up process: a command line, so this floor starts it without importing the floor above."""


def _spawn() -> Any:
    env = dict(os.environ, ARMKIT_JIT="wait", ARMKIT_BACKEND="auto")
    env["PYTHONPATH"] = os.pathsep.join([str(_PKG.parent)] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep)
                                                              if p])
    log = open(_log_path(), "w")
    try:
        proc = subprocess.Popen([sys.executable, "-c", _WORKER, str(os.getpid())],
                                stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT, env=env,
                                start_new_session=True, close_fds=True)
    finally:
        log.close()
    # the lock now belongs to the worker
    _lock_path().write_text(str(proc.pid))
    return proc


# ------------------------------------------------------------ compiling in this process (armkit.warmup)
@contextlib.contextmanager
def compiling_here(parallel: bool, backend: Optional[str] = None) -> Iterator[None]:
    """Compile in this process for the duration: the kernels serve at once (``"sync"``), the
    multi-threaded ones too if ``parallel``; with ``backend``, that back end meanwhile.

    Afterwards the back end chosen before is restored and, where Numba's cache is on, the
    state is ``"ready"`` (the threaded kernels serve if the second marker exists).
    """
    global _state, _parallel, _here
    before = _backend
    _state, _parallel = "sync", parallel
    _here += 1
    if backend is not None:
        set_backend(backend)  # type: ignore[arg-type]
    try:
        yield
    finally:
        _here -= 1
        if backend is not None:
            set_backend(before)  # type: ignore[arg-type]
        first, second = marker("ready"), marker("parallel")
        if first is not None:
            _state = "ready"
            _parallel = bool(second is not None and second.exists())


@contextlib.contextmanager
def serial_only() -> Iterator[None]:
    """Only the one-thread kernels while inside (the warm-up's first phase): :func:`parallel_ok` says False."""
    global _serial_only
    _serial_only = True
    try:
        yield
    finally:
        _serial_only = False
