"""Shared test set-up: headless plotting, a CI hypothesis profile, fixtures found relative to this file."""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

os.environ.setdefault("MPLBACKEND", "Agg")
# an idle OpenMP thread (Numba's multi-threaded kernels) sleeps at once instead of spinning for the next parallel
# region: with two test workers on two cores, a worker's spinning thread took CPU from the other worker. The whole
# suite with its kernels cached took 222-224 s instead of 239-241 (two runs each, alternating, 2026-12-06). armkit
# itself keeps OpenMP's default: a spinning thread starts the next region sooner (a batched puma560 ik_all of 1,000
# targets 2.2-2.4 µs a target against 2.4 passive, for 25 % more CPU).
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
# compile Numba kernels in the test process on first use (no background warm-up process), so that the tests
# that compare the NumPy and Numba back ends always run both (docs/performance.md, "First use")
os.environ.setdefault("ARMKIT_JIT", "wait")

import numpy as np
import pytest
from hypothesis import HealthCheck, settings

# CI (CI=true) replays the same examples every run, so a landing never depends on luck; locally
# hypothesis keeps exploring new examples.
settings.register_profile("armkit", max_examples=60, deadline=None, derandomize=bool(os.environ.get("CI")),
                          suppress_health_check=[HealthCheck.too_slow])
settings.load_profile("armkit")

DATA = Path(__file__).parent / "data"
_SHARED_CACHE = "armkit_symbolic_cache"


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20261121)


def pytest_configure(config: pytest.Config) -> None:
    """The controller of a ``pytest -n N`` run makes one symbolic cache for all its workers (see below), and
    compiles the Numba kernels once for all of them (:func:`_compile_kernels_once`) before they start."""
    if not hasattr(config, "workerinput"):
        config.stash[_cache_key] = tempfile.mkdtemp(prefix="armkit-test-cache-")
        if _wants_kernels_first(config):
            _compile_kernels_once(config)


def pytest_sessionfinish(session: pytest.Session, exitstatus: int) -> None:
    """After a whole-suite run, the controller adds what the tests compiled on first use (the searches' kernels) to
    the kernel store (armkit._kernel_store), where the store held fewer of this build's files."""
    config = session.config
    if not hasattr(config, "workerinput") and _wants_kernels_first(config) and exitstatus == 0:
        try:
            from armkit import _jit_loader
        except ImportError:
            return
        _jit_loader.save_kernels()


def pytest_unconfigure(config: pytest.Config) -> None:
    folder = config.stash.get(_cache_key, None)
    if folder is not None:
        shutil.rmtree(folder, ignore_errors=True)


@pytest.hookimpl(optionalhook=True)
def pytest_configure_node(node) -> None:  # pytest-xdist's hook, called in the controller for each worker
    node.workerinput[_SHARED_CACHE] = node.config.stash[_cache_key]


_cache_key = pytest.StashKey[str]()


@pytest.fixture(scope="session", autouse=True)
def _symbolic_cache(request: pytest.FixtureRequest):
    """One on-disk cache of symbolic derivations for the whole test run (each robot is derived once per run).

    It starts empty (every derivation runs in the run) and is shared by the xdist workers, so that a robot
    derived by one worker (puma560 takes sympy ~10 s) is read by the other (the cache writes atomically);
    subprocesses (README commands, examples) inherit it through ``ARMKIT_CACHE_DIR``.
    """
    config = request.config
    folder = getattr(config, "workerinput", {}).get(_SHARED_CACHE) or config.stash[_cache_key]
    mp = pytest.MonkeyPatch()
    mp.setenv("ARMKIT_CACHE_DIR", folder)
    yield
    mp.undo()


# ---- the Numba kernels, compiled once for the whole run ------------------------------------------------------------
# In a fresh clone no kernel is cached, and with ARMKIT_JIT=wait every xdist worker compiled the kernels its tests
# touch, at the same time as the other worker compiled the same ones: the cold compile was paid once per worker.
# The controller of a whole-suite ``pytest -n N`` run (N >= 2) compiles them first, in three processes (both cores
# work), and the workers then load them from Numba's on-disk cache. ARMKIT_TEST_WARMUP=1 does this for any run,
# ARMKIT_TEST_WARMUP=0 never. With the kernels cached already (armkit warmup's marker files), it costs one check.

def _wants_kernels_first(config: pytest.Config) -> bool:
    flag = os.environ.get("ARMKIT_TEST_WARMUP", "")
    if flag in ("0", "1"):
        return flag == "1"
    workers = getattr(config.option, "numprocesses", None)
    whole = config.args_source == pytest.Config.ArgsSource.TESTPATHS   # no file or folder named: the whole suite
    return isinstance(workers, int) and workers >= 2 and whole


def _stamps() -> tuple:
    """The marker files of this build's kernels: ``armkit warmup``'s two, and the one this file writes when its
    parts (:data:`WARM_PARTS`) have compiled the same kernels (None where Numba's cache is off)."""
    from armkit import _jit_loader, kinematics  # noqa: F401  (kinematics names the kernel module the markers follow)

    _jit_loader.install_cache_fallback()
    return _jit_loader.marker("ready"), _jit_loader.marker("parallel"), _jit_loader.marker("tests")


def _kernels_cached() -> bool:
    """True when this build's kernels are all in Numba's cache (or when Numba's cache is off: nothing to share)."""
    first, second, ours = _stamps()
    if first is None or second is None or ours is None:
        return True
    return (first.exists() and second.exists()) or ours.exists()


def _compile_kernels_once(config: pytest.Config) -> None:
    """One process per part compiles the warm-up's kernels (:data:`WARM_PARTS`) into Numba's cache
    (``_warm_part``); the workers load them from there. A failure only costs time: the workers then compile on first
    use, as without this step. The marker written afterwards is this file's own (``armkit-kernels-<build>.tests``):
    armkit's markers keep meaning that ``armkit.warmup()`` ran."""
    import contextlib
    import subprocess
    import sys
    import time

    try:
        from armkit import _jit_loader

        if _kernels_cached() or _jit_loader.restore_kernels() and _kernels_cached():   # cached here, or compiled by
            return             # another clone of the same sources on this machine (armkit._kernel_store)
    except ImportError:        # no Numba: nothing to compile
        return
    capture = config.pluginmanager.get_plugin("capturemanager")

    def say(text: str) -> None:
        with capture.global_and_fixture_disabled() if capture is not None else contextlib.nullcontext():
            print(text, file=sys.stderr, flush=True)

    t0 = time.perf_counter()
    say(f"armkit tests: compiling the Numba kernels once for all workers, in {len(WARM_PARTS)} processes ...")
    here = str(Path(__file__).parent)
    run = "import sys; sys.path.insert(0, sys.argv[1]); import conftest; conftest._warm_part(sys.argv[2])"
    env = dict(os.environ, ARMKIT_JIT="wait", ARMKIT_BACKEND="auto")
    logs = [tempfile.TemporaryFile(mode="w+") for _ in WARM_PARTS]     # files, not pipes: neither can block
    parts = [subprocess.Popen([sys.executable, "-c", run, here, part], env=env, stdin=subprocess.DEVNULL,
                              stdout=log, stderr=subprocess.STDOUT, text=True)
             for part, log in zip(WARM_PARTS, logs)]
    outs = []
    for p, log in zip(parts, logs):
        p.wait()
        log.seek(0)
        outs.append(log.read())
        log.close()
    failed = [out for p, out in zip(parts, outs) if p.returncode]
    for out in failed:
        say("armkit tests: a kernel warm-up process failed (the workers compile on first use):\n" + out[-2000:])
    ours = _stamps()[2]
    if not failed and ours is not None:
        ours.touch()      # armkit's forget_other_builds() removes it with the other files of an older build
        _jit_loader.save_kernels()   # for the next clone of the same sources (armkit._kernel_store)
    say(f"armkit tests: the kernel warm-up took {time.perf_counter() - t0:.0f} s")


def _warm_part(part: str) -> None:
    """One part of :func:`armkit.warmup`'s work (:data:`WARM_PARTS`), run in its own process by
    :func:`_compile_kernels_once`: its serial kernels, then the multi-threaded twins of those. Anything the parts
    miss is compiled by the workers on first use, as before."""
    import importlib

    from armkit import _jit_loader

    warmup = importlib.import_module("armkit.warmup")     # the module (armkit.warmup is also the function's name)
    serial, parallel = WARM_PARTS[part]
    with _jit_loader.compiling_here(parallel=True, backend="numba"):
        with _jit_loader.serial_only():
            for name in serial:
                getattr(warmup, name)()
        if parallel is not None:
            getattr(warmup, parallel)()


WARM_PARTS = {"core": (("_exercise_arms",), "_parallel_core"),
              "families": (("_exercise_families",), "_parallel_families"),
              "so101": (("_exercise_so101",), None)}
"""The parts of armkit.warmup's work compiled before the workers start, each in its own process: (its serial
exercises in order, the function compiling their multi-threaded twins, or None). What every worker needs at once is
here, and the SO-101's kernels (:func:`armkit.warmup._exercise_so101`). Three processes on the two cores, not two:
the SO-101's kernels share little with the others, and the parts then end close together. Measured 2026-12-06 in a
fresh cache (each part's wall time, all started together): core 98 s, families 107 s, SO-101 55 s, all done in
107 s; with the SO-101 inside the families part (two processes, as until then) core 84 s and families 120 s, all
done in 120 s (a core idled for 36 s). The searches (``_exercise_later``) still compile in the tests that use
them first: in the core part with their batch twin they made it 107 s instead of 69 (2026-12-04), while a worker
that compiles lets the other go on with other tests."""
