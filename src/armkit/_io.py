"""Every file armkit writes goes through here: a temporary file in the same folder, renamed into place.

:func:`atomic_path` yields a temporary path (same folder, same suffix, so writers that pick
the format from the extension, like Matplotlib and imageio, still work); when the body
finishes, the file is flushed to disk and renamed over ``path`` with :func:`os.replace`.
If anything goes wrong the temporary file is removed and the old ``path`` is untouched:
an ``OSError`` becomes :class:`~armkit.errors.WriteError` (``cannot write PATH: reason``),
Ctrl-C becomes :class:`~armkit.errors.WriteInterrupted` (``interrupted; PATH not written``).
A process killed outright (SIGKILL) leaves at most a hidden ``.NAME.PID.XXXX.tmp.SUFFIX`` file,
never a partial ``path``; the next write of ``path`` removes it, with a warning, once no
process of that PID is alive (:func:`clean_stale`).

:func:`check_writable` answers early, before a long computation: an existing folder, a
path under a regular file or under ``/proc``, a read-only file or folder, or a suffix the
writer does not know are refused with a :class:`~armkit.errors.WriteError`.

>>> import tempfile, pathlib
>>> d = pathlib.Path(tempfile.mkdtemp())
>>> atomic_write(d / "a.txt", "hello").read_text()
'hello'
>>> with atomic_path(d / "b.txt") as tmp:
...     _ = tmp.write_text("world")
>>> sorted(p.name for p in d.iterdir())
['a.txt', 'b.txt']
"""

from __future__ import annotations

import errno
import os
import stat
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator, Optional, Sequence

from .errors import WriteError, WriteInterrupted

__all__ = ["atomic_path", "atomic_write", "check_writable", "clean_stale"]


N_ = str   # armkit.locale.N_, the catalogue's mark (pybabel -k N_), without importing the locale here
OS_REASONS = {errno.ENAMETOOLONG: N_("the name is too long"), errno.EACCES: N_("permission denied"),
              errno.EPERM: N_("permission denied"), errno.ENOENT: N_("no such file or folder"),
              errno.ENOTDIR: N_("a part of the folder path is a file, not a folder"), errno.EISDIR: N_("it is a folder"),
              errno.EROFS: N_("the file system is read-only"), errno.ENOSPC: N_("no space left on the device"),
              errno.ELOOP: N_("too many symbolic links"), errno.EEXIST: N_("it exists already")}
"""armkit's words for the OS errors it meets most, in English: the reasons of :class:`WriteError`, and of the command
line's one-line OS errors in the current language (:func:`armkit.cli.common.os_reason`). Others keep the system's."""


def _reason(exc: OSError) -> str:
    return OS_REASONS.get(exc.errno or 0) or exc.strerror or str(exc)


def check_writable(path: str | os.PathLike[str], suffixes: Optional[Sequence[str]] = None,
                   what: str = "output") -> Path:
    """Refuse, with :class:`WriteError`, an output path that cannot be written; return it as a Path.

    Creates the missing parent folders (as the writers always did) and tries a temporary
    file there, so a folder that exists but refuses files is found before any work is done.
    """
    p = Path(os.fspath(path))
    if not p.name or p.name in (".", ".."):
        raise WriteError(p, "it is a folder; give a file name")
    try:
        st = p.stat()
    except (FileNotFoundError, NotADirectoryError):
        st = None
    except OSError as exc:
        raise WriteError(p, _reason(exc)) from None
    if st is not None and stat.S_ISDIR(st.st_mode):
        raise WriteError(p, "it is a folder; give a file name")
    if suffixes is not None and p.suffix.lower() not in tuple(s.lower() for s in suffixes):
        if p.suffix:
            raise WriteError(p, "{what} must end in {suffixes}, got {got!r}", what=what,
                             suffixes=", ".join(suffixes), got=p.suffix)
        raise WriteError(p, "{what} must end in {suffixes}; the name has no suffix", what=what,
                         suffixes=", ".join(suffixes))
    if st is not None:
        if not stat.S_ISREG(st.st_mode):
            raise WriteError(p, "it is not a regular file")
        if not st.st_mode & (stat.S_IWUSR | stat.S_IWGRP | stat.S_IWOTH) or not os.access(p, os.W_OK):
            raise WriteError(p, "the file is read-only")
    parent = p.parent
    try:
        parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=parent, prefix=f".{p.name}.", suffix=".probe")
        os.close(fd)
        os.unlink(tmp)
    except FileExistsError:
        raise WriteError(p, "a part of the folder path is a file, not a folder") from None
    except OSError as exc:
        raise WriteError(p, _reason(exc)) from None
    return p


def _mode_for(p: Path) -> int:
    try:
        return stat.S_IMODE(p.stat().st_mode)
    except OSError:
        umask = os.umask(0)
        os.umask(umask)
        return 0o666 & ~umask


@contextmanager
def atomic_path(path: str | os.PathLike[str], suffixes: Optional[Sequence[str]] = None,
                what: str = "output") -> Iterator[Path]:
    """Yield a temporary path next to ``path``; rename it to ``path`` when the body succeeds.

    Raises
    ------
    WriteError
        ``path`` cannot be written (see :func:`check_writable`) or writing failed.
    WriteInterrupted
        Ctrl-C during the write; the temporary file is removed, ``path`` is untouched.
    """
    p = check_writable(path, suffixes, what)
    clean_stale(p)
    try:
        fd, name = tempfile.mkstemp(dir=p.parent, prefix=f".{p.stem}.{os.getpid()}.", suffix=f".tmp{p.suffix}")
        os.close(fd)
    except OSError as exc:
        raise WriteError(p, _reason(exc)) from None
    tmp = Path(name)
    try:
        yield tmp
        os.chmod(tmp, _mode_for(p))
        with open(tmp, "rb+") as f:
            os.fsync(f.fileno())
        os.replace(tmp, p)
    except KeyboardInterrupt:
        _remove(tmp)
        raise WriteInterrupted(p) from None
    except WriteError:
        _remove(tmp)
        raise
    except OSError as exc:
        _remove(tmp)
        raise WriteError(p, _reason(exc)) from None
    except BaseException:
        _remove(tmp)
        raise


def atomic_write(path: str | os.PathLike[str], data: str | bytes, encoding: str = "utf-8",
                 suffixes: Optional[Sequence[str]] = None, what: str = "output") -> Path:
    """Write ``data`` (text or bytes) to ``path`` atomically; return ``path`` as a Path."""
    raw = data.encode(encoding) if isinstance(data, str) else bytes(data)
    with atomic_path(path, suffixes, what) as tmp:
        with open(tmp, "wb") as f:
            f.write(raw)
    return Path(os.fspath(path))


def _remove(tmp: Path) -> None:
    try:
        tmp.unlink()
    except OSError:
        pass


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:         # it exists but is not ours (EPERM)
        return True
    return True


def clean_stale(path: str | os.PathLike[str]) -> int:
    """Remove the temporary files that a killed write of ``path`` left beside it; warn once; return how many.

    Only files named as :func:`atomic_path` names them, ``.STEM.PID.XXXX.tmp.SUFFIX``, whose process
    is gone, are removed: a write still running in another process keeps its file.
    """
    import re
    import warnings

    p = Path(os.fspath(path))
    pattern = re.compile(re.escape(f".{p.stem}.") + r"([0-9]{1,10})\.[A-Za-z0-9_]{1,16}" + re.escape(f".tmp{p.suffix}"))
    removed = 0
    try:
        entries = list(os.scandir(p.parent))
    except OSError:
        return 0
    for e in entries:
        m = pattern.fullmatch(e.name)
        if m is None or int(m.group(1)) == os.getpid() or _alive(int(m.group(1))):
            continue
        try:
            if e.is_file(follow_symlinks=False):
                os.unlink(e.path)
                removed += 1
        except OSError:
            pass
    if removed:
        warnings.warn(f"removed {removed} unfinished temporary file(s) of {p} left by an interrupted write",
                      stacklevel=3)
    return removed
