"""The store is untrusted input: opening never writes a file, overwrite deletes only a store, damage is refused.

The three high findings of the hardening round, each reproduced as the hostile user did it:
``reach build --overwrite`` emptying a folder of the user's files, a map whose stored robot name
made ``open`` write ``<name>.toml`` anywhere, and a local cluster serving on every interface.
"""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from armkit.cli import app
from armkit.errors import LimitError
from armkit.reach import MapFileError, ReachabilityError, ReachabilityMap, reachability

runner = CliRunner()
KW = dict(resolution=0.1, samples=100_000, workers=1)      # planar2 in metres: a map in about a second


@pytest.fixture(scope="module")
def store(tmp_path_factory) -> Path:
    p = tmp_path_factory.mktemp("safety") / "planar2.zarr"
    reachability("planar2", path=p, **KW)
    return p


def _copy(store: Path, tmp_path: Path) -> Path:
    dst = tmp_path / "copy.zarr"
    shutil.copytree(store, dst)
    return dst


def _edit_attrs(p: Path, **changes) -> None:
    meta = p / "zarr.json"
    doc = json.loads(meta.read_text())
    doc["attributes"].update(changes)
    meta.write_text(json.dumps(doc))


def _tree(p: Path) -> dict[str, bytes]:
    return {str(f.relative_to(p)): f.read_bytes() for f in sorted(p.rglob("*")) if f.is_file()}


# ------------------------------------------------------------------ overwrite deletes only a store
def test_overwrite_refuses_a_folder_of_user_files(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    notes = tmp_path / "notes"
    notes.mkdir()
    (notes / "t.txt").write_text("keep")
    r = runner.invoke(app, ["reach", "build", "fighter", "-o", "notes", "--overwrite", "--samples", "100000",
                            "--workers", "1"])
    assert r.exit_code == 2, r.output
    assert "will not overwrite" in r.output and "notes" in r.output and "Traceback" not in r.output
    assert (notes / "t.txt").read_text() == "keep"


@pytest.mark.parametrize("where", [".", "..", "~"])
def test_overwrite_refuses_current_parent_and_home(tmp_path: Path, monkeypatch, where: str) -> None:
    work = tmp_path / "work"
    work.mkdir()
    (work / "keep.txt").write_text("keep")
    monkeypatch.chdir(work)
    monkeypatch.setenv("HOME", str(work))
    target = str(work) if where == "~" else where
    with pytest.raises(ReachabilityError, match="will not overwrite"):
        reachability("planar2", path=target, overwrite=True, **KW)
    assert (work / "keep.txt").read_text() == "keep"


def test_overwrite_refuses_a_plain_file_and_a_store_with_strangers(tmp_path: Path, store: Path) -> None:
    f = tmp_path / "file.zarr"
    f.write_text("mine")
    with pytest.raises(ReachabilityError, match="it is a file"):
        reachability("planar2", path=f, overwrite=True, **KW)
    assert f.read_text() == "mine"
    c = _copy(store, tmp_path)
    (c / "thesis.tex").write_text("mine")
    with pytest.raises(ReachabilityError, match="thesis.tex"):
        reachability("planar2", path=c, overwrite=True, **KW)
    assert (c / "thesis.tex").read_text() == "mine"


def test_overwrite_replaces_a_real_store(tmp_path: Path, store: Path) -> None:
    c = _copy(store, tmp_path)
    m = reachability("planar2", path=c, overwrite=True, seed=1, **KW)
    assert m.parameters["seed"] == 1 and ReachabilityMap.open(c).parameters["seed"] == 1


# ------------------------------------------------------------------ opening never writes
@pytest.mark.parametrize("name", ["../../escaped", "/tmp/armkit-escaped-abs", "config"])
def test_open_writes_no_file_named_by_the_map(tmp_path: Path, store: Path, monkeypatch, name: str) -> None:
    c = _copy(store, tmp_path)
    doc = json.loads((c / "zarr.json").read_text())["attributes"]
    _edit_attrs(c, robot=name, robot_toml=doc["robot_toml"].replace('name = "planar2"', f'name = "{name}"'))
    work = tmp_path / "deep" / "er"
    work.mkdir(parents=True)
    monkeypatch.chdir(work)
    before = {p for p in Path("/tmp").glob("armkit-escaped*")}
    with pytest.raises(MapFileError, match="fingerprint"):        # edited text: refused before parsing
        ReachabilityMap.open(c)
    assert {p for p in Path("/tmp").glob("armkit-escaped*")} == before
    assert not list(tmp_path.rglob("*.toml")) and not (tmp_path / "escaped.toml").exists()


def test_open_parses_the_stored_robot_without_a_file(tmp_path: Path, store: Path, monkeypatch) -> None:
    import hashlib

    c = _copy(store, tmp_path)
    doc = json.loads((c / "zarr.json").read_text())["attributes"]
    text = doc["robot_toml"].replace('name = "planar2"', 'name = "../../../x"')
    _edit_attrs(c, robot="../../../x", robot_toml=text, robot_sha256=hashlib.sha256(text.encode()).hexdigest())
    writes: list[str] = []
    real_open = open

    def watch(file, mode="r", *a, **k):      # any file opened for writing while the map opens is a finding
        if any(ch in mode for ch in "wax+"):
            writes.append(str(file))
        return real_open(file, mode, *a, **k)

    monkeypatch.setattr("builtins.open", watch)
    m = ReachabilityMap.open(c)
    assert m.robot.name == "../../../x" and writes == []
    assert not (tmp_path / "x.toml").exists()


# ------------------------------------------------------------------ damage is refused, not read as "unreachable"
def _damage_cases():
    def drop_chunk(c):
        chunk = next(f for f in sorted((c / "hits").rglob("*")) if f.is_file() and f.name != "zarr.json")
        chunk.unlink()

    def flip_byte(c):
        chunk = next(f for f in sorted((c / "counts").rglob("*")) if f.is_file() and f.name != "zarr.json")
        b = bytearray(chunk.read_bytes())
        b[len(b) // 2] ^= 0xFF
        chunk.write_bytes(bytes(b))

    def truncate_meta(c):
        meta = c / "zarr.json"
        meta.write_bytes(meta.read_bytes()[: len(meta.read_bytes()) // 2])

    def drop_array(c):
        shutil.rmtree(c / "manipulability")

    def other_robot(c):
        from armkit import load
        from armkit.model import dumps

        _edit_attrs(c, robot_toml=dumps(load("fighter")))

    def old_format(c):
        _edit_attrs(c, format="armkit.reachability/1")

    def bad_grid(c):
        doc = json.loads((c / "zarr.json").read_text())["attributes"]
        _edit_attrs(c, grid={**doc["grid"], "dims": [10 ** 6, 10 ** 6, 10 ** 6]})

    def wrong_name(c):
        _edit_attrs(c, robot="fighter")

    return [drop_chunk, flip_byte, truncate_meta, drop_array, other_robot, old_format, bad_grid, wrong_name]


@pytest.mark.parametrize("damage", _damage_cases(), ids=lambda f: f.__name__)
def test_damaged_store_is_refused_and_left_alone(tmp_path: Path, store: Path, damage) -> None:
    c = _copy(store, tmp_path)
    damage(c)
    before = _tree(c)
    with pytest.raises((MapFileError, LimitError)):     # LimitError: a grid too big for the memory budget
        ReachabilityMap.open(c)
    r = runner.invoke(app, ["reach", "query", str(c), "1.0", "0", "0"])
    assert r.exit_code == 2 and "Traceback" not in r.output and str(c.name) in r.output, r.output
    assert _tree(c) == before


def test_the_intact_store_answers(store: Path) -> None:
    m = ReachabilityMap.open(store)
    T = np.eye(4)
    T[:3, 3] = [1.2, 0.0, 0.0]
    assert bool(m.reachable(T)) and not bool(m.reachable(np.eye(4)))


def test_a_killed_build_leaves_partial_files_that_the_next_build_removes(tmp_path: Path) -> None:
    p = tmp_path / "k.zarr"
    with pytest.raises(KeyboardInterrupt):
        def stop(done: int, total: int) -> None:
            if done >= 1:
                raise KeyboardInterrupt
        reachability("planar2", path=p, resolution=0.1, samples=400_000, block_size=100_000, workers=1,
                     flush_seconds=0.0, progress=stop)
    leftover = p / "counts_0" / "c" / "junk.0123abcd.partial"
    leftover.parent.mkdir(parents=True, exist_ok=True)
    leftover.write_bytes(b"half")
    with pytest.warns(UserWarning, match="unfinished chunk"):
        m = reachability("planar2", path=p, resolution=0.1, samples=400_000, block_size=100_000, workers=1)
    assert not leftover.exists()
    ref = reachability("planar2", resolution=0.1, samples=400_000, block_size=100_000, workers=1)
    assert np.array_equal(m.counts, ref.counts)


# ------------------------------------------------------------------ network
def _listening() -> list[str]:
    import psutil

    return [c.laddr.ip for c in psutil.Process().net_connections(kind="inet") if c.status == psutil.CONN_LISTEN]


@pytest.mark.parametrize("dashboard", [False, True])
def test_local_cluster_listens_on_loopback_only(dashboard: bool, capsys) -> None:
    from armkit.reach._build import _local_cluster

    before = set(_listening())
    client, close = _local_cluster(2, dashboard)
    try:
        ips = _listening()
        assert ips and all(ip in ("127.0.0.1", "::1") for ip in ips), ips
        assert not (set(ips) - before) & {"0.0.0.0", "::"}
        workers = client.scheduler_info()["workers"]
        assert len(workers) == 2 and all(a.startswith("tcp://127.0.0.1:") for a in workers)
        import psutil

        pids = set(client.run(os.getpid).values())
        for pid in pids | {psutil.Process(p).ppid() for p in pids}:    # each worker process and its nanny
            socks = psutil.Process(pid).net_connections(kind="inet")
            assert all(s.laddr.ip in ("127.0.0.1", "::1") for s in socks if s.status == psutil.CONN_LISTEN)
        import urllib.error
        import urllib.request

        port = client.cluster.scheduler.http_server.port
        try:      # the scheduler's identity route: served only with the dashboard
            with urllib.request.urlopen(f"http://127.0.0.1:{port}/json/identity.json", timeout=5) as resp:
                status = resp.status
        except urllib.error.HTTPError as exc:
            status = exc.code
        assert status == (200 if dashboard else 404)
    finally:
        close()
    out = capsys.readouterr().out
    assert ("Dask dashboard: http://127.0.0.1:" in out) == dashboard


def test_remote_scheduler_warns_that_data_leaves(monkeypatch) -> None:
    monkeypatch.setattr("armkit.reach._build.CONNECT_TIMEOUT", "1s")
    with pytest.warns(UserWarning, match="not on this machine"), \
            pytest.raises(ReachabilityError, match="cannot reach|cannot use"):
        reachability("planar2", scheduler="tcp://192.0.2.1:8786", **{**KW, "workers": None})


@pytest.mark.parametrize("address", ["inproc://nothing", "tls://127.0.0.1:1", "tcp://[zz]:1", "ucx://x:1"])
def test_odd_scheduler_addresses_are_one_line_errors(monkeypatch, tmp_path: Path, address: str) -> None:
    monkeypatch.setattr("armkit.reach._build.CONNECT_TIMEOUT", "1s")
    r = runner.invoke(app, ["reach", "build", "planar2", "-o", str(tmp_path / "m.zarr"), "--scheduler", address])
    assert r.exit_code == 2 and "Traceback" not in r.output and "scheduler" in r.output, r.output


# ------------------------------------------------------------------ memory: checked before allocating
@pytest.mark.parametrize("kw, match", [
    (dict(robot="panda", orientations=2000, resolution=0.05), "cells would need"),
    (dict(robot="ur5", rolls=100_000), "cells"),
    (dict(robot="planar2", samples=10 ** 23), "units of work"),
])
def test_huge_maps_are_refused_before_allocating(kw, match: str) -> None:
    import tracemalloc

    robot = kw.pop("robot")
    tracemalloc.start()
    try:
        with pytest.raises((ReachabilityError, LimitError), match=match):
            reachability(robot, workers=1, **kw)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 200 * 1024 ** 2, peak


def test_an_ik_block_is_checked_against_the_budget(monkeypatch) -> None:
    """A map that fits (13^3 voxels x 2,000 orientations: 76 MiB) whose IK block does not (one x-slab of
    169 voxels x 2,000 orientations of 7-joint solutions: about 95 MiB) under an 85 MiB budget."""
    from armkit import load

    monkeypatch.setenv("ARMKIT_MEMORY_LIMIT", "85M")
    with pytest.raises(LimitError, match="an IK block"):
        reachability("panda", method="ik", orientations=2000, rolls=1, resolution=load("panda").reach / 5,
                     workers=1)


def test_many_orientations_need_no_quadratic_table() -> None:
    """The neighbouring orientation bins come from a k-d tree: 20,000 directions no longer build a 3.2 GB
    table of dot products. The neighbours are the nearest ones (checked against the brute force on 500)."""
    from armkit.reach._grid import Grid

    g = Grid.build(np.eye(4), True, 1.0, 0.5, 500, 1)
    nb = g.direction_neighbours()
    dirs = g._tables()[0]
    brute = np.argsort(-(dirs @ dirs.T), axis=1, kind="stable")[:, 1:7]
    d_nb = np.sort(np.take_along_axis(dirs @ dirs.T, nb, axis=1), axis=1)
    d_bf = np.sort(np.take_along_axis(dirs @ dirs.T, brute, axis=1), axis=1)
    assert np.allclose(d_nb, d_bf, atol=1e-12)
    big = Grid.build(np.eye(4), True, 1.0, 0.5, 20_000, 1)
    assert big.direction_neighbours().shape == (20_000, 6)


@pytest.mark.parametrize("opts", [["--step", "0.0001"], ["--yaws", "100000000"]])
def test_base_placement_candidates_are_bounded(store: Path, tmp_path: Path, opts: list[str]) -> None:
    tasks = tmp_path / "t.csv"
    tasks.write_text("x,y,z\n0.5,0,0\n")
    r = runner.invoke(app, ["reach", "base", str(store), str(tasks), *opts])
    assert r.exit_code == 2 and "candidate base poses" in r.output and "Traceback" not in r.output, r.output


@pytest.mark.parametrize("name", ["x" * 300, "bad\x00name"])
def test_a_name_the_system_cannot_look_up_is_no_map(tmp_path: Path, name: str) -> None:
    """A path too long for the system (ENAMETOOLONG) or with a NUL byte: MapFileError "no reachability map", as
    for a missing one, not the OSError or ValueError of the lookup."""
    with pytest.raises(MapFileError, match="no reachability map at"):
        ReachabilityMap.open(str(tmp_path / name))


def test_a_broken_symbolic_link_is_no_map(tmp_path: Path) -> None:
    """A link to nothing is "no reachability map", as before the lookup above was guarded (not "is a file")."""
    link = tmp_path / "gone.zarr"
    link.symlink_to(tmp_path / "nothing")
    with pytest.raises(MapFileError, match="no reachability map at"):
        ReachabilityMap.open(str(link))
