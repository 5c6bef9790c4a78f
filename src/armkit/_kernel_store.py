"""The kernel store: armkit's compiled kernels kept once per machine, for every install of the same sources.

Numba caches a compiled kernel next to its source (the package's ``__pycache__`` folders), so a new virtual
environment, a new clone or a reinstall of the same armkit compiles every kernel again (2-4 minutes of CPU). The store
keeps a copy of those cache files, per *build* (a hash of every ``.py`` file of the package and of the Numba,
llvmlite and Python versions and the machine), in ``$ARMKIT_KERNEL_STORE``, else ``$XDG_CACHE_HOME/armkit/kernels``
or ``~/.cache/armkit/kernels``; an install whose cache lacks them copies them back before it would compile.

Why a copy is safe: the build hash covers every source file (a kernel inlines helpers of other files, which
Numba's own stamp does not follow, see :func:`armkit._jit_loader.forget_stale_cache`), and Numba checks each entry
again when it loads it: each compiled overload carries the machine's CPU and features, and each cache index a stamp
of its source file, the SHA-256 of its contents in Numba 0.68 (checked 2026-12-07; where a Numba stamps the file's
modification time instead, a copied entry does not match the new file's and is compiled again: slower, never
wrong). A store folder not owned by this user, or writable by others, is
never read (its pickles would run as code). Nothing is copied where ``NUMBA_CACHE_DIR`` is set (its owner manages
that cache), and ``ARMKIT_KERNEL_STORE=off`` turns the store off.

The ground floor: this module imports only the standard library. :mod:`armkit._jit_loader` calls it
(:func:`armkit._jit_loader.restore_kernels`, :func:`armkit._jit_loader.save_kernels`).
"""

from __future__ import annotations

import glob
import hashlib
import os
import pickle
import shutil
from pathlib import Path
from typing import Mapping, Optional

__all__ = ["store_root", "build_id", "cache_files", "save", "restore", "KEEP"]

KEEP = 3
"""Builds kept in the store (the newest by the time they were saved); older ones are removed when one is saved."""
_MANIFEST = "armkit-store-files"


def store_root(env: Optional[Mapping[str, str]] = None) -> Optional[Path]:
    """The store's folder (not created here), or None where it is off: ``ARMKIT_KERNEL_STORE`` set to ``off``, ``0``
    or an empty string, ``NUMBA_CACHE_DIR`` set (the caller manages Numba's cache), or no home folder to be found."""
    if env is None:
        env = os.environ
    chosen = env.get("ARMKIT_KERNEL_STORE")
    if chosen is not None:
        return None if chosen.strip().lower() in ("", "0", "off") else Path(chosen)
    if env.get("NUMBA_CACHE_DIR"):
        return None
    xdg = env.get("XDG_CACHE_HOME")
    if xdg and Path(xdg).is_absolute():   # (a relative one is to be ignored, says the XDG specification)
        return Path(xdg) / "armkit" / "kernels"
    try:
        home = Path.home()
    except RuntimeError:                  # no home to be found: no store (not a folder named "~" here)
        return None
    return home / ".cache" / "armkit" / "kernels" if home.is_absolute() else None


def build_id(root: Path, versions: str) -> str:
    """The build of the package at ``root``: a hash of each ``.py`` file's path (relative) and contents, and of
    ``versions`` (the Numba, llvmlite and Python versions and the machine, from the caller)."""
    h = hashlib.sha256(versions.encode())
    for path in sorted(root.rglob("*.py")):
        if "__pycache__" in path.parts:
            continue
        h.update(path.relative_to(root).as_posix().encode() + b"\0")
        h.update(path.read_bytes())
    return h.hexdigest()[:20]


def _referenced(index: Path) -> Optional[list[str]]:
    """The data files (``*.nbc``) that Numba's cache index ``index`` names, or None where it cannot be read as one
    (another layout: the caller then takes every data file of the same function)."""
    try:
        with open(index, "rb") as f:
            pickle.load(f)                       # Numba's version
            _stamp, overloads = pickle.loads(f.read())
        return [str(name) for name in overloads.values()]
    except Exception:  # noqa: BLE001  (any failure: fall back to the file names)
        return None


def cache_files(root: Path, markers: list[Path]) -> list[Path]:
    """The files of the package's kernel cache under ``root`` worth keeping: every index in a ``__pycache__``
    folder and the data files it names (not the stale ones of older sources), the inlined-sources stamps, and those
    of ``markers`` (the build's marker files) that exist."""
    out: list[Path] = []
    for folder in sorted(root.rglob("__pycache__")):
        for index in sorted(folder.glob("*.nbi")):
            out.append(index)
            names = _referenced(index)
            stem = glob.escape(index.name[:-len(".nbi")])
            data = [folder / n for n in names] if names is not None else sorted(folder.glob(f"{stem}.*.nbc"))
            out.extend(p for p in data if p.is_file())
        out.extend(sorted(folder.glob("*.armkit-deps")))
    out.extend(m for m in markers if m.is_file())
    return out


def _safe(folder: Path) -> bool:
    """True where ``folder`` (or a file) is ours and writable by nobody else (its pickles are loaded as code)."""
    try:
        st = folder.stat()
    except OSError:
        return False
    if not hasattr(os, "getuid"):
        return True
    return st.st_uid == os.getuid() and not st.st_mode & 0o022


def save(store: Path, build: str, root: Path, markers: list[Path]) -> bool:
    """Copy the kernel cache under ``root`` (:func:`cache_files`) into ``store/build``, replacing a copy of fewer
    files; keep the :data:`KEEP` newest builds. True where a copy was made. Written into a temporary folder first
    and renamed into place, so a reader sees a whole copy or none."""
    files = cache_files(root, markers)
    if not any(f.suffix == ".nbi" for f in files):
        return False
    store.mkdir(mode=0o700, parents=True, exist_ok=True)
    if not _safe(store):
        return False
    target = store / build
    if _count(target) >= len(files):
        return False
    tmp = store / f".tmp-{build}-{os.getpid()}"
    old = store / f".old-{build}-{os.getpid()}"
    try:
        for f in files:
            dest = tmp / f.relative_to(root)
            dest.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(f, dest)
        (tmp / _MANIFEST).write_text(f"{len(files)}\n")
        for p in [tmp, *tmp.rglob("*")]:   # the user's alone, whatever the umask (restore reads no other)
            p.chmod(0o700 if p.is_dir() else 0o600)
        if target.exists():
            os.replace(target, old)
        os.replace(tmp, target)   # (another process's copy put there meanwhile: OSError, its copy stays)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
        shutil.rmtree(old, ignore_errors=True)
    _prune(store)
    return True


def _count(target: Path) -> int:
    """The number of files of the copy ``target`` (0: none, or unreadable)."""
    try:
        return int((target / _MANIFEST).read_text().strip())
    except (OSError, ValueError):
        return 0


def _prune(store: Path) -> None:
    """Remove all but the :data:`KEEP` newest builds (a folder whose name starts with a dot is a save at work)."""
    builds = sorted((p for p in store.iterdir() if p.is_dir() and not p.name.startswith(".")),
                    key=lambda p: p.stat().st_mtime, reverse=True)
    for old in builds[KEEP:]:
        shutil.rmtree(old, ignore_errors=True)


def restore(store: Path, build: str, root: Path, markers: list[Path]) -> bool:
    """Copy the store's copy of ``build`` into the package's cache under ``root``, where that cache has none of
    ``markers`` (the build's marker files: a cache with one has, or is making, its own kernels). A kernel whose index
    or data files are there already is left as it is (a cache file is never overwritten: another process may be
    reading it, and its index numbers its data files in its own order); each copied kernel's data files are written
    before the index that names them, each file to a temporary name and renamed. Then the copy's markers. True where
    a kernel was copied."""
    src = store / build
    if not (_safe(store) and _safe(src)) or any(m.exists() for m in markers):
        return False
    if not all(_safe(p) for p in src.rglob("*")):   # every file and folder of the copy: none another user could change
        return False
    copied = False
    for index in sorted(src.rglob("*.nbi")):
        dest = root / index.relative_to(src)
        stem = glob.escape(index.name[:-len(".nbi")])
        if dest.exists() or any(dest.parent.glob(f"{stem}.*.nbc")):
            continue
        for data in sorted(index.parent.glob(f"{stem}.*.nbc")):
            _copy(data, dest.parent / data.name)
        _copy(index, dest)
        copied = True
    for deps in sorted(src.rglob("*.armkit-deps")):
        dest = root / deps.relative_to(src)
        if not dest.exists():
            _copy(deps, dest)
    if copied:
        for m in markers:
            mark = src / m.relative_to(root)
            if mark.is_file():
                _copy(mark, m)
    return copied


def _copy(src: Path, dest: Path) -> None:
    """``src`` to ``dest`` by a temporary file beside it and a rename (a reader never sees half a file)."""
    dest.parent.mkdir(parents=True, exist_ok=True)
    tmp = dest.with_name(f"{dest.name}.tmp{os.getpid()}")
    shutil.copyfile(src, tmp)
    os.replace(tmp, dest)
