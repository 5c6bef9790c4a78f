"""The kernel store (armkit._kernel_store): compiled kernels kept once per machine for every install of the same
sources (issue 21: a new clone's ``make test`` compiled every kernel again, ~250 CPU-s).

End to end: two copies of the package in temporary folders, the first compiles a kernel and saves it, the second
loads it from the store without compiling (Numba's own cache log says which), and a copy with one source file
changed compiles again. Then the rules on made-up cache trees: only the data files an index names are kept, nothing
in a cache is ever overwritten, a cache with its own markers is left alone, a store that others may write is never
read, the newest builds are kept.
"""

from __future__ import annotations

import math
import os
import pickle
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import armkit
from armkit import _kernel_store as ks

PKG = Path(armkit.__file__).resolve().parent


def _copy_package(dest: Path) -> Path:
    """The package's sources and data (no caches) under ``dest``: an install of the same build elsewhere."""
    shutil.copytree(PKG, dest / "armkit", ignore=shutil.ignore_patterns("__pycache__"))
    return dest


def _run(root: Path, store: Path) -> str:
    """FK of the planar 2R arm in a process that imports armkit from ``root``, compiling on first use; returns what
    it printed (Numba's cache log is on stdout, armkit's notes on stderr)."""
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env.update(PYTHONPATH=str(root), ARMKIT_KERNEL_STORE=str(store), ARMKIT_JIT="wait", NUMBA_DEBUG_CACHE="1")
    code = ("import armkit, numpy as np\n"
            "assert armkit.__file__.startswith(%r)\n"
            "print(armkit.fk(armkit.load('planar2'), np.array([0.1, 0.2]))[0, 3])\n"
            "from armkit import _jit_loader\n"
            "_jit_loader.save_kernels()\n") % str(root)
    res = subprocess.run([sys.executable, "-c", code], env=env, cwd=root, capture_output=True, text=True,
                         timeout=300)
    assert res.returncode == 0, res.stderr[-2000:]
    a1, a2 = (j.a for j in armkit.load("planar2").joints)   # x = a1 cos q1 + a2 cos(q1 + q2)
    x = float(next(line for line in res.stdout.splitlines() if not line.startswith("[cache]")))
    assert abs(x - (a1 * math.cos(0.1) + a2 * math.cos(0.3))) < 1e-12
    return res.stdout + res.stderr


def test_a_second_install_of_the_same_sources_loads_the_kernels_and_a_changed_one_compiles(tmp_path):
    pytest.importorskip("numba")
    store = tmp_path / "store"
    first = _run(_copy_package(tmp_path / "a"), store)
    assert "[cache] data saved" in first                      # compiled there
    builds = [p for p in store.iterdir() if p.is_dir()]
    assert len(builds) == 1 and any(builds[0].rglob("*.nbc"))
    second = _run(_copy_package(tmp_path / "b"), store)
    assert "[cache] data loaded" in second and "[cache] data saved" not in second, second[-2000:]
    assert "compiling armkit's kernels" not in second
    changed = _copy_package(tmp_path / "c")
    errors = changed / "armkit" / "errors.py"
    errors.write_text(errors.read_text() + "\n# another build\n")
    third = _run(changed, store)
    assert "[cache] data saved" in third                      # another build: compiled, not copied
    assert len([p for p in store.iterdir() if p.is_dir()]) == 2


# ---- the rules, on made-up cache trees -------------------------------------------------------------------------
def _index(path: Path, names: dict) -> None:
    """A cache index in Numba's layout: its version, then the pickled (source stamp, {key: data file name})."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "wb") as f:
        pickle.dump("0.68.1", f)
        f.write(pickle.dumps((b"stamp", names)))


def _tree(root: Path) -> tuple[Path, list[Path]]:
    """A package with one kernel file: an index naming two data files, a stale data file no index names, the
    inlined-sources stamp and the build's marker files (one present)."""
    (root / "k").mkdir(parents=True)
    (root / "k" / "_jit.py").write_text("x = 1\n")
    cache = root / "k" / "__pycache__"
    _index(cache / "_jit.f-10.py311.nbi", {("sig", 1): "_jit.f-10.py311.1.nbc", ("sig", 2): "_jit.f-10.py311.2.nbc"})
    for name, data in (("_jit.f-10.py311.1.nbc", b"one"), ("_jit.f-10.py311.2.nbc", b"two"),
                       ("_jit.f-10.py311.3.nbc", b"stale"), ("_jit.armkit-deps", b"hash")):
        (cache / name).write_bytes(data)
    markers = [cache / "armkit-kernels-b.ready", cache / "armkit-kernels-b.parallel"]
    markers[0].write_text("")
    return cache, markers


def _files(root: Path) -> dict:
    return {p.relative_to(root).as_posix(): p.read_bytes() for p in root.rglob("*") if p.is_file()}


def test_save_keeps_the_named_data_files_and_restore_gives_them_back(tmp_path):
    cache, markers = _tree(tmp_path / "a")
    store = tmp_path / "store"
    assert ks.save(store, "b1", tmp_path / "a", markers)
    kept = _files(store / "b1")
    assert "k/__pycache__/_jit.f-10.py311.3.nbc" not in kept                  # stale: no index names it
    assert {"k/__pycache__/_jit.f-10.py311.1.nbc", "k/__pycache__/_jit.f-10.py311.2.nbc",
            "k/__pycache__/_jit.armkit-deps", "k/__pycache__/armkit-kernels-b.ready"} <= set(kept)
    assert "k/__pycache__/armkit-kernels-b.parallel" not in kept               # a marker that does not exist
    assert not ks.save(store, "b1", tmp_path / "a", markers)                  # the store has as many: no new copy
    # another install: the sources only
    other = tmp_path / "b"
    (other / "k").mkdir(parents=True)
    (other / "k" / "_jit.py").write_text("x = 1\n")
    want = [other / m.relative_to(tmp_path / "a") for m in markers]
    assert ks.restore(store, "b1", other, want)
    got = _files(other)
    for rel, data in _files(tmp_path / "a").items():
        if rel.endswith("3.nbc") or rel.endswith(".parallel"):
            assert rel not in got
        else:
            assert got[rel] == data, rel
    stamps = {p: p.stat().st_mtime_ns for p in other.rglob("*") if p.is_file()}
    assert not ks.restore(store, "b1", other, want)                           # its marker is there now
    assert stamps == {p: p.stat().st_mtime_ns for p in other.rglob("*") if p.is_file()}


def test_restore_never_overwrites_a_kernel_the_cache_has(tmp_path):
    _, markers = _tree(tmp_path / "a")
    store = tmp_path / "store"
    assert ks.save(store, "b1", tmp_path / "a", markers)
    other = tmp_path / "b"
    cache = other / "k" / "__pycache__"
    _index(cache / "_jit.f-10.py311.nbi", {("sig", 2): "_jit.f-10.py311.1.nbc"})   # its own numbering
    (cache / "_jit.f-10.py311.1.nbc").write_bytes(b"two, compiled here")
    before = _files(other)
    want = [other / m.relative_to(tmp_path / "a") for m in markers]
    assert not ks.restore(store, "b1", other, want)    # nothing copied: the only kernel is there; no marker either
    after = _files(other)
    assert {k: v for k, v in after.items() if k in before} == before
    assert not any(k.endswith(".ready") for k in after)
    # a cache with a marker of this build (making its own kernels) is left alone
    third = tmp_path / "c"
    (third / "k" / "__pycache__").mkdir(parents=True)
    mine = [third / m.relative_to(tmp_path / "a") for m in markers]
    mine[1].write_text("")
    assert not ks.restore(store, "b1", third, mine)
    assert _files(third) == {"k/__pycache__/armkit-kernels-b.parallel": b""}


@pytest.mark.skipif(not hasattr(os, "getuid"), reason="POSIX permissions")
def test_a_store_others_may_write_is_never_read_nor_written(tmp_path):
    _, markers = _tree(tmp_path / "a")
    store = tmp_path / "store"
    assert ks.save(store, "b1", tmp_path / "a", markers)
    other = tmp_path / "b"
    other.mkdir()
    want = [other / m.relative_to(tmp_path / "a") for m in markers]
    store.chmod(0o777)
    try:
        assert not ks.restore(store, "b1", other, want)
        assert not ks.save(store, "b2", tmp_path / "a", markers)
    finally:
        store.chmod(0o700)
    assert not any(other.rglob("*"))
    (store / "b1").chmod(0o757)
    assert not ks.restore(store, "b1", other, want)
    (store / "b1").chmod(0o700)
    inner = store / "b1" / "k" / "__pycache__"
    for bad, mode in ((inner, 0o777), (inner / "_jit.f-10.py311.1.nbc", 0o666)):   # a folder or a file inside
        bad.chmod(mode)
        assert not ks.restore(store, "b1", other, want)
        bad.chmod(0o700 if bad.is_dir() else 0o600)
    assert not any(other.rglob("*"))
    assert ks.restore(store, "b1", other, want)                  # all the user's own again: copied


def test_the_newest_builds_are_kept(tmp_path):
    _, markers = _tree(tmp_path / "a")
    store = tmp_path / "store"
    for k in range(ks.KEEP + 2):
        assert ks.save(store, f"b{k}", tmp_path / "a", markers)
        os.utime(store / f"b{k}", (1e9 + k, 1e9 + k))
    ks.save(store, "b-last", tmp_path / "a", markers)
    kept = sorted(p.name for p in store.iterdir())
    assert len(kept) == ks.KEEP and "b-last" in kept and f"b{ks.KEEP + 1}" in kept and "b0" not in kept


def test_the_build_follows_every_source_file_and_the_versions(tmp_path):
    _tree(tmp_path / "a")
    one = ks.build_id(tmp_path / "a", "numba 0.68.1")
    assert ks.build_id(tmp_path / "a", "numba 0.68.1") == one
    assert ks.build_id(tmp_path / "a", "numba 0.69.0") != one
    (tmp_path / "a" / "k" / "__pycache__" / "x.py").write_text("ignored\n")      # caches are not sources
    assert ks.build_id(tmp_path / "a", "numba 0.68.1") == one
    (tmp_path / "a" / "k" / "helpers.py").write_text("y = 2\n")
    assert ks.build_id(tmp_path / "a", "numba 0.68.1") != one


def test_where_the_store_is(monkeypatch):
    assert ks.store_root({"HOME": "/h", "XDG_CACHE_HOME": "/c"}) == Path("/c/armkit/kernels")
    monkeypatch.setattr(Path, "home", classmethod(lambda cls: Path("/h")))
    assert ks.store_root({"XDG_CACHE_HOME": "relative"}) == Path("/h/.cache/armkit/kernels")   # ignored, as XDG says
    monkeypatch.setattr(Path, "home", classmethod(lambda cls: Path("~")))                     # Python 3.11, no home
    assert ks.store_root({}) is None

    def nowhere(cls):
        raise RuntimeError("Could not determine home directory.")                              # Python 3.12 and later

    monkeypatch.setattr(Path, "home", classmethod(nowhere))
    assert ks.store_root({}) is None
    monkeypatch.undo()
    assert ks.store_root({"ARMKIT_KERNEL_STORE": "/s"}) == Path("/s")
    for off in ("off", "0", "", "OFF"):
        assert ks.store_root({"ARMKIT_KERNEL_STORE": off}) is None
    assert ks.store_root({"NUMBA_CACHE_DIR": "/n"}) is None            # its owner manages that cache
    assert ks.store_root({"NUMBA_CACHE_DIR": "/n", "ARMKIT_KERNEL_STORE": "/s"}) == Path("/s")


def test_a_save_that_fails_leaves_nothing_half_made(tmp_path, monkeypatch):
    """Two processes saving one build at once: the one whose rename fails (the other's copy took the place) removes
    its temporary folder, and the other's copy stays whole."""
    _, markers = _tree(tmp_path / "a")
    store = tmp_path / "store"
    real = os.replace

    def taken(src, dst):
        if Path(src).name.startswith(".tmp-"):
            shutil.copytree(src, dst)             # the other process's copy lands first
            real(src, dst)                         # and this rename then fails: a folder that is not empty
        real(src, dst)

    monkeypatch.setattr(ks.os, "replace", taken)
    with pytest.raises(OSError):
        ks.save(store, "b1", tmp_path / "a", markers)
    monkeypatch.undo()
    assert sorted(p.name for p in store.iterdir()) == ["b1"]
    assert ks._count(store / "b1") == len(ks.cache_files(tmp_path / "a", markers))


@pytest.mark.skipif(not hasattr(os, "getuid"), reason="POSIX permissions")
def test_a_store_saved_under_a_group_writable_umask_is_still_read(tmp_path):
    """Debian gives users the umask 002: files and folders the save makes would be writable by the group, and
    restore would refuse them. The save makes its copy the user's alone."""
    _, markers = _tree(tmp_path / "a")
    store = tmp_path / "store"
    before = os.umask(0o002)
    try:
        assert ks.save(store, "b1", tmp_path / "a", markers)
    finally:
        os.umask(before)
    other = tmp_path / "b"
    other.mkdir()
    assert ks.restore(store, "b1", other, [other / m.relative_to(tmp_path / "a") for m in markers])
