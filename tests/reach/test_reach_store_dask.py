"""Zarr store (metadata, reopen, resume after an interruption or a crash mid-commit) and Dask runs
(a real dask.distributed LocalCluster of 2 worker processes on 127.0.0.1, one worker killed mid-run)."""

from __future__ import annotations

import os
import threading
from pathlib import Path

import numpy as np
import pytest

import armkit
from armkit.reach import MapFileError, ReachabilityError, ReachabilityMap, reachability

KW = dict(resolution=20.0, samples=240_000, block_size=20_000, seed=3)     # fighter: 12 blocks, mm


def _same(a: ReachabilityMap, b: ReachabilityMap) -> None:
    assert np.array_equal(a.counts, b.counts)
    assert np.array_equal(a.hits, b.hits)
    assert np.array_equal(a.manipulability, b.manipulability)


@pytest.fixture(scope="module")
def reference() -> ReachabilityMap:
    return reachability("fighter", workers=1, **KW)


def test_store_metadata_and_reopen(tmp_path: Path, reference: ReachabilityMap) -> None:
    import zarr

    p = tmp_path / "f.zarr"
    m = reachability("fighter", workers=1, path=p, **KW)
    _same(m, reference)
    attrs = dict(zarr.open_group(str(p), mode="r").attrs)
    assert attrs["format"] == "armkit.reachability/2" and attrs["status"] == "complete"
    assert set(attrs["checksums"]) == {"counts", "hits", "manipulability", "index"}
    assert attrs["robot"] == "fighter" and attrs["armkit_version"] == armkit.__version__
    assert attrs["parameters"]["samples"] == 240_000 and attrs["parameters"]["seed"] == 3
    assert "[[joints]]" in attrs["robot_toml"]
    back = ReachabilityMap.open(p)
    _same(back, reference)
    assert back.robot.name == "fighter" and np.allclose(back.robot.dh_table(), reference.robot.dh_table())
    T = armkit.fk(back.robot, back.robot.random_q(100, rng=0))
    assert np.array_equal(back.reachable(T), reference.reachable(T))
    # a finished store is returned as it is; other settings on the same path are refused
    assert np.array_equal(reachability("fighter", workers=1, path=p, **KW).counts, reference.counts)
    with pytest.raises(ReachabilityError, match="other settings"):
        reachability("fighter", workers=1, path=p, **{**KW, "seed": 4})
    _same(reachability("fighter", workers=1, path=p, overwrite=True, **KW), reference)


def test_open_errors(tmp_path: Path) -> None:
    with pytest.raises(MapFileError, match="no reachability map"):
        ReachabilityMap.open(tmp_path / "missing.zarr")
    (tmp_path / "junk").mkdir()
    with pytest.raises(MapFileError):
        ReachabilityMap.open(tmp_path / "junk")
    with pytest.raises(ReachabilityError, match="not an armkit reachability map|not a Zarr"):
        reachability("fighter", workers=1, path=tmp_path / "junk", **KW)


def test_resume_after_interrupt_equals_uninterrupted(tmp_path: Path, reference: ReachabilityMap) -> None:
    p = tmp_path / "r.zarr"

    def stop_after_five(done: int, total: int) -> None:
        if done >= 5:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        reachability("fighter", workers=1, path=p, flush_seconds=0.0, progress=stop_after_five, **KW)
    with pytest.raises(MapFileError, match="unfinished"):
        ReachabilityMap.open(p)
    seen: list[int] = []
    m = reachability("fighter", workers=1, path=p, progress=lambda d, t: seen.append(d), **KW)
    assert seen[0] == 5                       # five blocks were skipped
    _same(m, reference)
    _same(ReachabilityMap.open(p), reference)


def test_crash_mid_commit_leaves_a_consistent_generation(tmp_path: Path, reference: ReachabilityMap) -> None:
    import zarr

    p = tmp_path / "c.zarr"

    def stop(done: int, total: int) -> None:
        if done >= 4:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        reachability("fighter", workers=1, path=p, flush_seconds=0.0, progress=stop, **KW)
    g = zarr.open_group(str(p), mode="r+")
    gen = int(g.attrs["generation"])
    # the next generation was being written when the power went: half an array, never committed
    junk = g.create_array(f"counts_{gen + 1}", shape=(3,), chunks=(3,), dtype="uint8", fill_value=0)
    junk[...] = np.array([255, 255, 255], dtype=np.uint8)
    m = reachability("fighter", workers=1, path=p, **KW)
    _same(m, reference)


@pytest.fixture(scope="module")
def cluster():
    from distributed import Client, LocalCluster

    c = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                     dashboard_address=":0", silence_logs=40)
    client = Client(c)
    yield client
    client.close()
    c.close()


def test_dask_cluster_equals_single_process(cluster, reference: ReachabilityMap) -> None:
    m = reachability("fighter", scheduler=cluster.scheduler.address, **KW)
    _same(m, reference)


def test_environment_variable_picks_the_cluster(cluster, reference: ReachabilityMap, monkeypatch) -> None:
    monkeypatch.setenv("ARMKIT_SCHEDULER", cluster.scheduler.address)
    _same(reachability("fighter", **KW), reference)


def test_killing_a_worker_mid_run_gives_the_same_map(cluster, tmp_path: Path) -> None:
    kw = dict(resolution=20.0, samples=600_000, block_size=30_000, seed=5)
    ref = reachability("fighter", workers=1, **kw)
    killed = threading.Event()

    def kill_one(done: int, total: int) -> None:
        if done >= 3 and not killed.is_set():
            killed.set()
            victim = sorted(cluster.scheduler_info()["workers"])[0]
            try:
                cluster.run(os._exit, 1, workers=[victim])
            except Exception:   # the worker dies before it can answer
                pass

    m = reachability("fighter", scheduler=cluster, path=tmp_path / "k.zarr", progress=kill_one, **kw)
    assert killed.is_set()
    _same(m, ref)
    _same(ReachabilityMap.open(tmp_path / "k.zarr"), ref)


def test_bad_scheduler_address(monkeypatch) -> None:
    monkeypatch.setattr("armkit.reach._build.CONNECT_TIMEOUT", "1s")
    with pytest.raises(ReachabilityError, match="scheduler must be a Dask scheduler address"):
        reachability("fighter", scheduler="not-an-address", **KW)
    with pytest.raises(ReachabilityError, match="cannot reach the Dask scheduler"):
        reachability("fighter", scheduler="tcp://127.0.0.1:1", **KW)
