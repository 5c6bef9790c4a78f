"""First use of the Numba kernels (issue 15): where they are cached, what answers while they compile.

Each scenario runs in a fresh Python process with its own empty cache, so nothing here depends on
(or disturbs) the cache of the test run itself. No timing is asserted (benchmarks/bench_first_call.py
measures the times); the tests check the behaviour: NumPy answers at once and says so on stderr,
the switch happens at the start of an ``fk`` call, big batches stay on one thread until the
multi-threaded kernels are cached, and a read-only install without a writable home still caches.
"""

from __future__ import annotations

import json
import os
import shutil
import stat
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import armkit
from armkit import _jit_loader

SRC = Path(armkit.__file__).resolve().parent.parent
pytest.importorskip("numba")


def _run(code: str, env: dict[str, str], timeout: float = 600) -> subprocess.CompletedProcess:
    full = {k: v for k, v in os.environ.items() if not k.startswith(("ARMKIT_", "NUMBA_"))}
    full.update(env)
    full.setdefault("PYTHONPATH", str(SRC))
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], env=full, capture_output=True, text=True,
                          timeout=timeout)


def _last_json(out: str) -> dict:
    return json.loads(out.strip().splitlines()[-1])


def test_background_mode_answers_with_numpy_then_switches_at_an_fk_call(tmp_path):
    # the warm-up process is replaced by a stand-in that never finishes; the test writes its markers
    code = """
        import json, time, numpy as np, armkit
        from armkit import _jit_loader as L
        from armkit.kinematics import _jit

        class Worker:
            def poll(self):
                return None
        L._spawn = lambda: Worker()
        arm = armkit.load("puma560")
        q = arm.random_q(rng=0)
        out = {}
        T = armkit.fk(arm, q)
        out["first"] = armkit.get_backend()
        out["numpy_fk_ok"] = bool(np.allclose(T, armkit.fk(arm, q[None])[0]))
        out["compiled_before"] = len(_jit.fk_one.signatures) + len(_jit._fk_serial.signatures)
        out["ik_first"] = bool(armkit.ik(arm, T).success)
        L.marker("ready").touch()
        time.sleep(0.15)
        out["before_fk"] = armkit.get_backend()      # get_backend never switches by itself
        T2 = armkit.fk(arm, q)                       # fk polls: the compiled kernels from now on
        out["after_fk"] = armkit.get_backend()
        out["same"] = float(np.abs(T2 - T).max())
        Q = arm.random_q(5000, rng=1)
        armkit.fk(arm, Q)
        out["parallel_before"] = len(_jit._fk_parallel.signatures)
        L.marker("parallel").touch()
        time.sleep(0.6)
        armkit.fk(arm, Q)
        out["parallel_after"] = len(_jit._fk_parallel.signatures)
        print(json.dumps(out))
    """
    res = _run(code, {"NUMBA_CACHE_DIR": str(tmp_path / "cache")})
    assert res.returncode == 0, res.stderr
    out = _last_json(res.stdout)
    assert out["first"] == "numpy" and out["numpy_fk_ok"] and out["ik_first"]
    assert out["compiled_before"] == 0                  # nothing compiled in the caller while warming
    assert out["before_fk"] == "numpy" and out["after_fk"] == "numba"
    assert out["same"] < 1e-12
    assert out["parallel_before"] == 0 and out["parallel_after"] >= 1
    assert res.stderr.count("armkit: compiling armkit's kernels once in the background") == 1


def test_wait_mode_compiles_on_first_use_and_says_so_once_and_only_then(tmp_path):
    code = """
        import armkit
        arm = armkit.load("fighter")
        armkit.fk(arm, [0.1, 0.2, 0.3])
        armkit.fk(arm, [0.1, 0.2, 0.4])
        print(armkit.get_backend())
    """
    res = _run(code, {"NUMBA_CACHE_DIR": str(tmp_path / "cache"), "ARMKIT_JIT": "wait"})
    assert res.returncode == 0, res.stderr
    assert res.stdout.split() == ["numba"]
    assert res.stderr.count("armkit: compiling armkit's kernels once, about") == 1
    again = _run(code, {"NUMBA_CACHE_DIR": str(tmp_path / "cache"), "ARMKIT_JIT": "wait"})   # all in the cache now
    assert again.returncode == 0, again.stderr
    assert again.stdout.split() == ["numba"]
    assert "compiling" not in again.stderr   # nothing compiled, nothing said (it said "about 45 s" before)


def _unwritable(path: Path) -> None:
    """Make Numba's in-tree cache impossible below ``path`` even for root: a *file* named __pycache__."""
    for d in [path, *(p for p in path.rglob("*") if p.is_dir() and p.name != "__pycache__")]:
        cache = d / "__pycache__"
        if cache.is_dir():
            shutil.rmtree(cache)
        cache.write_text("not a directory")
    for p in [path, *path.rglob("*")]:
        p.chmod(p.stat().st_mode & ~(stat.S_IWUSR | stat.S_IWGRP | stat.S_IWOTH))


def test_read_only_install_without_writable_home_caches_in_a_private_temp_dir(tmp_path):
    pkg = tmp_path / "site" / "armkit"
    shutil.copytree(SRC / "armkit", pkg, ignore=shutil.ignore_patterns("__pycache__"))
    _unwritable(pkg)
    home = tmp_path / "home-is-a-file"
    home.write_text("")
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    code = """
        import json, numpy as np, armkit
        from armkit import _jit_loader as L
        arm = armkit.load("fighter")
        T = armkit.fk(arm, np.radians([30.0, 45.0, 60.0]))
        print(json.dumps({"file": armkit.__file__, "backend": armkit.get_backend(), "cache": str(L.cache_dir()),
                          "p": np.round(T[:3, 3], 3).tolist()}))
    """
    try:
        env = {"PYTHONPATH": str(pkg.parent), "HOME": str(home), "TMPDIR": str(tmp), "ARMKIT_JIT": "wait"}
        res = _run(code, env)
        assert res.returncode == 0, res.stderr
        out = _last_json(res.stdout)
        assert out["file"].startswith(str(pkg))
        assert out["backend"] == "numba"
        assert out["p"] == [24.861, 14.353, 187.181]
        private = tmp / f"armkit-numba-{os.getuid()}"
        assert Path(out["cache"]).is_relative_to(private)
        assert any(private.rglob("*.nbi")), "no Numba index file in the fallback cache"
        assert stat.S_IMODE(private.stat().st_mode) == 0o700
        # the second process loads what the first compiled
        res2 = _run(code, env)
        assert res2.returncode == 0, res2.stderr
        assert _last_json(res2.stdout)["backend"] == "numba"
    finally:
        for p in [tmp_path / "site", *(tmp_path / "site").rglob("*")]:
            if p.is_dir():
                p.chmod(0o755)


def test_fallback_cache_dir_refuses_a_directory_others_can_write(tmp_path, monkeypatch):
    monkeypatch.setattr(_jit_loader.tempfile, "gettempdir", lambda: str(tmp_path))
    d = tmp_path / f"armkit-numba-{os.getuid()}"
    d.mkdir(mode=0o777)
    d.chmod(0o777)
    with pytest.raises(OSError, match="another user or is writable by others"):
        _jit_loader.fallback_cache_dir()
    d.chmod(0o700)
    assert _jit_loader.fallback_cache_dir() == d


def test_warmup_with_everything_cached_compiles_nothing_and_the_cli_says_so(tmp_path):
    code = """
        import json, armkit
        from armkit import _jit_loader as L
        L.marker("ready").touch()
        L.marker("parallel").touch()
        w = armkit.warmup()
        print(json.dumps({"compiled": w.compiled, "cache": str(w.cache), "backend": armkit.get_backend()}))
    """
    env = {"NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    res = _run(code, env)
    assert res.returncode == 0, res.stderr
    out = _last_json(res.stdout)
    assert out["compiled"] is False and out["backend"] == "numba"
    assert Path(out["cache"]).is_relative_to(tmp_path / "cache")
    cli = _run("import sys; from armkit.cli import main; sys.argv = ['armkit', 'warmup', '--json']; main()", env)
    assert cli.returncode == 0, cli.stderr
    assert json.loads(cli.stdout)["compiled"] is False


def test_a_warm_up_cut_short_after_its_first_phase_is_finished_in_the_background(tmp_path):
    # ready marker without the parallel one (a warm-up killed between its phases): the next process
    # starts a warm-up for the threaded kernels instead of staying on one thread for good; in wait
    # mode the threaded kernels are compiled in the process on first use
    code = """
        import json, armkit
        from armkit import _jit_loader as L
        spawned = []

        class Worker:
            def poll(self):
                return None
        L._spawn = lambda: spawned.append(1) or Worker()
        L.marker("ready").touch()
        arm = armkit.load("ur5")
        armkit.fk(arm, arm.random_q(rng=0))
        print(json.dumps({"spawned": len(spawned), "parallel_ok": L.parallel_ok(), "state": L._state}))
    """
    res = _run(code, {"NUMBA_CACHE_DIR": str(tmp_path / "cache")})
    assert res.returncode == 0, res.stderr
    out = _last_json(res.stdout)
    assert out == {"spawned": 1, "parallel_ok": False, "state": "ready"}
    res = _run(code, {"NUMBA_CACHE_DIR": str(tmp_path / "cache2"), "ARMKIT_JIT": "wait"})
    assert res.returncode == 0, res.stderr
    out = _last_json(res.stdout)
    assert out["spawned"] == 0 and out["parallel_ok"] is True


def test_after_the_warm_up_the_so101_searches_and_scenes_compile_nothing_more():
    """Every kernel a user's call needs is in the warm-up: in a fresh process (the run's own cache, so the kernels
    load instead of compiling), the warm-up's exercises run first, then calls it does not make itself (other
    targets, the LeRobot class's steps, another general 6R, 3R arms of each case, a scene with every primitive): no
    Numba function of armkit gains a signature. The first ``armkit.ik(so101, xyz)`` after ``armkit warmup``
    compiled for 49 s before the SO-101's position IK was in the warm-up."""
    code = """
        import json, sys, types
        import numpy as np
        import armkit
        from armkit import warmup as _
        import importlib
        W = importlib.import_module("armkit.warmup")
        from armkit import _jit_loader
        from numba.core.dispatcher import Dispatcher

        def signatures():
            out = {}
            for name, mod in list(sys.modules.items()):
                if name.startswith("armkit.") and mod is not None:
                    for attr, f in list(vars(mod).items()):
                        if isinstance(f, Dispatcher):
                            out[f"{name}.{attr}"] = len(f.signatures)
                        elif isinstance(f, types.SimpleNamespace):   # a module's compiled set (kernels())
                            for part, g in vars(f).items():
                                if isinstance(g, Dispatcher):
                                    out[f"{name}.{attr}.{part}"] = len(g.signatures)
            return out

        with _jit_loader.compiling_here(parallel=True, backend="numba"):
            with _jit_loader.serial_only():
                W._exercise_serial()
            W._exercise_later()
        before = signatures()
        with _jit_loader.serial_only():
            so = armkit.load("so101")
            P = armkit.fk(so, so.random_q(6, rng=11))
            for p, z in zip(P[:, :3, 3], P[:, :3, 2]):
                armkit.ik(so, p, q0=so.random_q(rng=12))
                armkit.ik(so, p, pitch=0.3)
                armkit.ik(so, p, direction=z)
            from armkit.lerobot import RobotKinematics
            kin = RobotKinematics("so101")
            cur = np.zeros(6)
            for step in (0.002, 0.05):
                X = kin.forward_kinematics(cur)
                X[:3, 3] += step
                cur = kin.inverse_kinematics(cur, X)
            general = W._chain(21)
            armkit.ik_all(general, armkit.fk(general, general.random_q(rng=3)))
            for a1, al2, a2 in ((0.25, -0.9, 0.4), (0.0, -0.9, 0.4), (0.25, 0.0, 0.4), (0.25, -0.9, 0.0)):
                three = armkit.Robot([armkit.Joint(d=0.15, a=a1, alpha=0.6), armkit.Joint(d=0.1 if a2 else 0.0, a=a2,
                                      alpha=al2), armkit.Joint(a=0.3, alpha=0.2)], name="three")   # other 3R arms of
                armkit.ik_all(three, armkit.fk(three, three.random_q(rng=5))[:3, 3])   # each case, meeting, parallel
            fighter = armkit.load("fighter")
            scene = armkit.Scene([armkit.Scene.plane([0, 0, 1], -5.0), armkit.Scene.box([150, 0, 100], [40, 40, 40]),
                                  armkit.Scene.sphere([0, 150, 100], 20), armkit.Scene.cylinder([-150, 0, 100], 15, 60),
                                  armkit.Scene.capsule([0, -150, 50], [0, -150, 150], 10)])
            from armkit.collision import clearance, collisions
            Q = fighter.random_q(8, rng=4)
            collisions(fighter, Q, scene)
            clearance(fighter, Q, scene)
        after = signatures()
        print(json.dumps({k: [before.get(k, 0), v] for k, v in after.items() if v > before.get(k, 0)}))
    """
    env = {"ARMKIT_JIT": "wait"}
    for key in ("NUMBA_CACHE_DIR", "ARMKIT_CACHE_DIR"):
        if key in os.environ:
            env[key] = os.environ[key]
    res = _run(code, env)
    assert res.returncode == 0, res.stderr[-3000:]
    assert _last_json(res.stdout) == {}
