"""Issue 10, items 2 and 4: every file armkit writes is written whole or not at all.

Every command that writes, pointed at every kind of unwritable path, exits 2 with
``cannot write PATH: reason`` and leaves nothing behind; an interrupted write leaves the
old file intact and exits 130 with ``interrupted; PATH not written``.
"""

from __future__ import annotations

import os
import threading
from pathlib import Path

import pytest

import armkit
from armkit._io import atomic_path, atomic_write, check_writable
from armkit.errors import WriteError, WriteInterrupted

from hardening_helpers import invoke

# (command line with {out} for the output file, a suffix it accepts)
WRITERS = [
    (("plot", "planar2", "0", "0", "-o", "{out}"), ".png"),
    (("workspace", "planar2", "-n", "300", "-o", "{out}"), ".png"),
    (("maps", "planar2", "--steps", "5", "--no-ik", "-o", "{out}"), ".png"),
    (("track", "planar2", "--path", "circle", "--frames", "2", "--method", "analytic", "-o", "{out}"), ".gif"),
    (("derive", "planar2", "--png", "{out}"), ".png"),
    (("singular", "planar2", "-o", "{out}"), ".png"),
    (("traj", "planar2", "--joint", "0,0", "0.5,0.5", "-o", "{out}"), ".csv"),
    (("traj", "planar2", "--joint", "0,0", "0.5,0.5", "--dt", "0.5", "-o", "{out}"), ".png"),
]


def _unwritable(kind: str, tmp_path: Path, suffix: str) -> Path:
    if kind == "directory":
        d = tmp_path / f"folder{suffix}"
        d.mkdir()
        return d
    if kind == "under_a_file":
        f = tmp_path / "plain.txt"
        f.write_text("x")
        return f / f"out{suffix}"
    if kind == "proc":
        return Path("/proc/armkit-test") / f"out{suffix}"
    if kind == "read_only_file":
        f = tmp_path / f"locked{suffix}"
        f.write_bytes(b"old contents")
        f.chmod(0o444)
        return f
    if kind == "bad_suffix":
        return tmp_path / "out.xyz"
    raise AssertionError(kind)


KINDS = ["directory", "under_a_file", "proc", "read_only_file", "bad_suffix"]


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("args,suffix", WRITERS, ids=[f"{w[0][0]}{w[1]}" for w in WRITERS])
def test_unwritable_output_exits_2_and_leaves_nothing(tmp_path, kind, args, suffix):
    if kind == "proc" and not Path("/proc").is_dir():
        pytest.skip("no /proc")
    out = _unwritable(kind, tmp_path, suffix)
    before = sorted(p.name for p in tmp_path.rglob("*"))
    old = out.read_bytes() if out.is_file() else None
    code, text, exc = invoke(*(a.format(out=out) for a in args))
    assert exc is None, f"traceback: {exc!r}"
    assert code == 2, text
    assert "cannot write" in text and out.name in text
    assert sorted(p.name for p in tmp_path.rglob("*")) == before       # no partial or temporary file
    if old is not None:
        assert out.read_bytes() == old


def test_check_writable_reasons(tmp_path):
    f = tmp_path / "f.txt"
    f.write_text("x")
    with pytest.raises(WriteError, match="is a folder"):
        check_writable(tmp_path)
    with pytest.raises(WriteError, match="is a file, not a folder"):
        check_writable(f / "a.png")
    with pytest.raises(WriteError, match=r"must end in \.png"):
        check_writable(tmp_path / "a.gif", (".png",))
    assert check_writable(tmp_path / "new" / "deeper" / "a.png", (".png",)).parent.is_dir()


def test_failed_write_keeps_the_old_file(tmp_path):
    p = tmp_path / "arm.toml"
    armkit.save(armkit.load("fighter"), p)
    old = p.read_bytes()
    with pytest.raises(RuntimeError):
        with atomic_path(p) as tmp:
            tmp.write_bytes(old[:10])            # half a file ...
            raise RuntimeError("disk on fire")   # ... then the writer fails
    assert p.read_bytes() == old and sorted(x.name for x in tmp_path.iterdir()) == ["arm.toml"]


def test_ctrl_c_while_writing_keeps_the_old_file(tmp_path):
    p = tmp_path / "pic.png"
    p.write_bytes(b"old picture")
    with pytest.raises(WriteInterrupted, match="interrupted; .*pic.png not written"):
        with atomic_path(p) as tmp:
            tmp.write_bytes(b"partial")
            raise KeyboardInterrupt
    assert p.read_bytes() == b"old picture" and len(list(tmp_path.iterdir())) == 1


def test_ctrl_c_during_a_gif_in_the_cli(tmp_path, monkeypatch):
    import armkit.viz.animation as anim

    out = tmp_path / "track.gif"
    code, _, exc = invoke("track", "planar2", "--path", "circle", "--frames", "3", "--method", "analytic", "-o", out)
    assert code == 0 and exc is None
    good = out.read_bytes()
    calls = {"n": 0}
    real = anim._gif_frame

    def interrupt_on_second_frame(*a, **k):
        calls["n"] += 1
        if calls["n"] == 2:
            raise KeyboardInterrupt
        return real(*a, **k)

    monkeypatch.setattr(anim, "_gif_frame", interrupt_on_second_frame)
    code, text, exc = invoke("track", "planar2", "--path", "circle", "--frames", "3", "--method", "analytic",
                             "-o", out)
    assert exc is None and code == 130
    assert "interrupted; " in text and "not written" in text
    assert out.read_bytes() == good and [p.name for p in tmp_path.iterdir()] == ["track.gif"]


def test_ctrl_c_during_savefig_in_the_cli(tmp_path, monkeypatch):
    from matplotlib.figure import Figure

    out = tmp_path / "arm.png"
    out.write_bytes(b"previous picture")

    def savefig(self, fname, *a, **k):
        Path(fname).write_bytes(b"\x89PNG partial")
        raise KeyboardInterrupt

    monkeypatch.setattr(Figure, "savefig", savefig)
    code, text, exc = invoke("plot", "planar2", "0", "0", "-o", out)
    assert exc is None and code == 130 and "not written" in text
    assert out.read_bytes() == b"previous picture" and len(list(tmp_path.iterdir())) == 1


def test_concurrent_writers_leave_one_whole_file(tmp_path):
    p = tmp_path / "same.bin"
    payloads = [bytes([k]) * (200_000 + k) for k in range(8)]
    threads = [threading.Thread(target=atomic_write, args=(p, data)) for data in payloads]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert p.read_bytes() in payloads
    assert [x.name for x in tmp_path.iterdir()] == ["same.bin"]


def test_written_files_get_normal_permissions(tmp_path):
    p = atomic_write(tmp_path / "a.txt", "x")
    umask = os.umask(0)
    os.umask(umask)
    assert p.stat().st_mode & 0o777 == 0o666 & ~umask


def test_shell_pictures_go_to_a_folder_per_session(tmp_path):
    from armkit.cli.shell import Shell

    a = Shell(armkit.load("planar2"), lang="en", plot="png", out_dir=tmp_path, session=True)
    import time

    time.sleep(1.05)
    b = Shell(armkit.load("planar2"), lang="en", plot="png", out_dir=tmp_path, session=True)
    pa, pb = a.execute("q 10 20").picture, b.execute("q 30 40").picture
    assert pa is not None and pb is not None and pa != pb and pa.name == pb.name == "step_001.png"
    assert pa.parent.parent == pb.parent.parent == tmp_path


def test_shell_stops_drawing_after_its_picture_cap(tmp_path, monkeypatch):
    import armkit.cli.shell as shell_mod

    monkeypatch.setattr(shell_mod, "MAX_PICTURES", 2)
    sh = shell_mod.Shell(armkit.load("planar2"), lang="en", plot="png", out_dir=tmp_path)
    assert sh.execute("q 1 1").picture and sh.execute("q 2 2").picture
    out = sh.execute("q 3 3")
    assert out.picture is None and "2 pictures" in out.text and sh.plot == "none"
