"""A few targets at once take the one-call path target by target (``analytic.run_small_batch``): the same answers
as the batched path.

``armkit.ik(robot, T)`` and ``armkit.ik_all(robot, T)`` with ``T`` of shape ``(B, 4, 4)`` or ``(B, 3)`` (or any
leading shape of at most :data:`armkit.ik.analytic.ROWS` targets), default options, answer by one
compiled call per target and stack the results, instead of the batched NumPy path whose fixed cost (~0.3 ms)
dwarfs a few targets. Every field, its dtype and shape, the messages (made when read) and the order of the
branches must equal what the batched path gives (reached with ``api.ONE_CALL = False``), to the bit.
Timing lives in benchmarks/bench_analytic.py.
"""

from __future__ import annotations

import importlib
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import armkit
from armkit.ik.analytic import ROWS

from test_single_call import ARMS, _arm, _assert_same, _both, _target, compiled, twists_rounded  # noqa: F401

api = importlib.import_module("armkit.ik.api")
analytic = importlib.import_module("armkit.ik.analytic")


def _batch(robot, kind, us, fars):
    n = robot.n
    lo = np.where(np.isfinite(robot.lower), robot.lower, -np.pi)
    hi = np.where(np.isfinite(robot.upper), robot.upper, np.pi)
    return np.stack([_target(robot, kind, lo + (hi - lo) * (np.asarray(u[:n]) + 1.0) / 2.0, far)
                     for u, far in zip(us, fars)])


unit7 = st.lists(st.floats(-1.0, 1.0), min_size=7, max_size=7)


@settings(max_examples=40, deadline=None)
@given(name=st.sampled_from(sorted(ARMS)), data=st.data(), size=st.integers(1, 6),
       start=st.sampled_from(["none", "one", "each"]), enforce=st.booleans())
def test_a_few_targets_equal_the_batched_path(name, data, size, start, enforce):
    robot = _arm(name)
    us = data.draw(st.lists(unit7, min_size=size, max_size=size))
    fars = data.draw(st.lists(st.sampled_from([1.0, 1.0, 1.0, 1.4, 3.0]), min_size=size, max_size=size))
    targets = _batch(robot, ARMS[name], us, fars)
    v = np.asarray(data.draw(st.lists(unit7, min_size=size, max_size=size)))[:, :robot.n] * 4.0
    q0 = None if start == "none" else v[0] if start == "one" else v     # starts far out: branches outside limits
    for fn in (armkit.ik_all, armkit.ik):
        fast, slow = _both(lambda: fn(robot, targets, q0, enforce_limits=enforce))
        assert fast.q.shape[0] == size and fast.success.shape[0] == size
        _assert_same(fast, slow)


def test_any_leading_shape_and_the_path_is_taken(monkeypatch, rng):
    """(2, 3) targets come back as (2, 3) results, equal to the batched path's; the small path answered (counted);
    any number of targets takes the small path (in pieces above POOL_ROWS), but with api.ONE_CALL off."""
    robot = _arm("ur5")
    targets = np.stack([armkit.fk(robot, robot.random_q(rng=rng)) for _ in range(6)]).reshape(2, 3, 4, 4)
    armkit.ik(robot, targets[0, 0])        # the robot's one-call record made first (it sets api._run_small)
    calls = []
    real = analytic.run_small_batch
    monkeypatch.setattr(api, "_run_small", lambda *a: calls.append(len(a[2])) or real(*a))
    for fn in (armkit.ik_all, armkit.ik):
        fast, slow = _both(lambda: fn(robot, targets))
        assert fast.success.shape[:2] == (2, 3) and fast.q.shape[:2] == (2, 3)
        _assert_same(fast, slow)
    assert calls == [6, 6]
    many = armkit.fk(robot, robot.random_q(3 * analytic.POOL_ROWS + 5, rng=rng))
    assert ROWS == (sys.maxsize, sys.maxsize)
    armkit.ik(robot, many)
    armkit.ik_all(robot, many)
    assert calls == [6, 6, len(many), len(many)]
    _both(lambda: armkit.ik(robot, many))                 # (the batched path: not counted)
    assert calls == [6, 6, len(many), len(many), len(many)]


_TWISTS: dict = {}


@pytest.mark.parametrize("name", ["puma560", "ur5", "puma560-rounded", "puma560-twists"])
def test_many_targets_in_pieces_equal_the_batched_path(name, monkeypatch, driver_runs, rng):
    """More targets than POOL_ROWS (made 40 here) are answered in pieces of that many rows, joined
    (``_in_pieces``): with targets out of reach, a target at the home pose in the second piece (the batched path
    answers it alone) and no start, one, or one per target, every field and message the batched path's to the bit;
    one driver run per piece. ("puma560-twists": a file that rounds its twists, solved by the geometric family and
    named by the Puma's: ik's pieces keep what names it, not their buffers.)"""
    monkeypatch.setattr(analytic, "POOL_ROWS", 40)
    if name == "puma560-twists":
        robot = _TWISTS.get(name) or _TWISTS.setdefault(name, twists_rounded(armkit.load("puma560")))
        assert analytic.closed_form(robot).names_from is not None
    else:
        robot = _arm(name)
    B = 100
    q = robot.random_q(B, rng=rng)
    q[57] = 0.0
    targets = armkit.fk(robot, q)
    targets[::7, :3, 3] *= 3.0
    starts = rng.uniform(-4.0, 4.0, (B, robot.n))
    for fn in (armkit.ik_all, armkit.ik):
        for q0 in (None, starts[0], starts):
            driver_runs.clear()
            fast, slow = _both(lambda: fn(robot, targets, q0))
            assert len(driver_runs) == 3
            _assert_same(fast, slow)
            assert not fast.success.all() and fast.success.any()
    joined = armkit.ik_all(robot, targets)
    assert "reason" not in vars(joined) and "message" not in vars(joined)   # made when read
    assert joined.reason.shape == joined.message.shape == (B, joined.q.shape[1])


def test_failures_say_why_in_a_small_batch():
    """Unreachable targets among reachable ones: the messages (made when first read) are the batched path's."""
    robot = _arm("puma560")
    T = armkit.fk(robot, np.full(6, 0.3))
    far = T.copy()
    far[:3, 3] *= 5.0
    fast, slow = _both(lambda: armkit.ik(robot, np.stack([T, far, T])))
    assert list(fast.success) == [True, False, True]
    assert "message" not in fast.__dict__               # nothing made until read
    _assert_same(fast, slow)
    assert fast.message[1] and fast.message[0] == ""


def test_the_targets_changed_before_the_messages_are_read():
    """The sentences of a small batch are made when first read, from the targets as they were at the call: a caller
    that reuses its array in between changes nothing. The fields are arrays of their own (C order), not views of
    the call's buffers."""
    robot = _arm("ur5")
    T = armkit.fk(robot, np.full(6, 0.4))
    far = T.copy()
    far[:3, 3] *= 4.0
    for fn in (armkit.ik, armkit.ik_all):
        targets = np.stack([T, far, far])
        fast, slow = _both(lambda: fn(robot, targets))
        targets[:] = T                                   # the caller's array reused before anyone reads a message
        assert "message" not in fast.__dict__            # not made yet
        _assert_same(fast, slow)
        assert fast.message[1] != "" if fn is armkit.ik else any(fast.message[1])
        for f in ("q", "success", "position_error", "rotation_error", "iterations", "within_limits"):
            a = getattr(fast, f)
            assert a.flags.c_contiguous and a.flags.owndata, f


@pytest.fixture
def driver_runs(monkeypatch):
    """The batch driver's runs in this test, each as its ``parallel`` flag (``_single.rows_entry`` counted)."""
    single = importlib.import_module("armkit.ik.analytic._single")
    used = []
    real = single.rows_entry
    monkeypatch.setattr(single, "rows_entry", lambda parallel: used.append(parallel) or real(parallel))
    return used


def _with_kernel(name):
    robot = _arm(name)
    armkit.ik(robot, armkit.fk(robot, robot.random_q(rng=0)))     # the one-call record made
    rec = robot.cache.get("ik_fast")
    return bool(rec) and rec.kernel is not None


@pytest.mark.parametrize("name", sorted(ARMS))
def test_a_threaded_batch_equals_the_batched_path(name, driver_runs, rng):
    """From ROWS_PARALLEL targets the rows run on every thread (the driver's twin: its use counted) with one
    start per target, targets out of reach and branches outside the limits, read-only targets and starts: every field
    and message the batched path's, to the bit."""
    if not _with_kernel(name):
        pytest.skip("a family without a kernel: one call per target up to SMALL_BATCH, then the batched path")
    robot = _arm(name)
    B = analytic.ROWS_PARALLEL + 9
    fars = rng.choice([1.0, 1.0, 1.0, 1.4, 3.0], B)
    targets = np.stack([_target(robot, ARMS[name], q, far) for q, far in zip(robot.random_q(B, rng=rng), fars)])
    starts = rng.uniform(-4.0, 4.0, (B, robot.n))
    targets.setflags(write=False)                              # read-only arrays: the driver only reads them
    starts.setflags(write=False)
    for fn in (armkit.ik_all, armkit.ik):
        for q0 in (None, starts[0], starts):
            fast, slow = _both(lambda: fn(robot, targets, q0))
            _assert_same(fast, slow)
            assert not fast.success.all() and fast.success.any()     # failures of both kinds were made
    threaded = analytic._jit_loader.parallel_ok()
    assert driver_runs == [threaded] * 6


@pytest.fixture
def batched_runs(monkeypatch):
    """The batched path's runs for some rows of a batch (``api._batched``), each as its number of targets."""
    used = []
    real = api._batched
    monkeypatch.setattr(api, "_batched", lambda robot, t, *a: used.append(len(t)) or real(robot, t, *a))
    return used


@pytest.mark.parametrize("name", ["puma560", "ur5", "puma560-rounded", "ur5-rounded"])
def test_targets_for_the_batched_path_are_answered_alone(name, driver_runs, batched_runs, rng):
    """Targets with the wrist straight (q5 = 0: a note to give; the home pose too) among many: the driver answers
    the others (counted), the batched path those targets alone (counted), spliced in; every field and message the
    batched path's for the whole batch, to the bit, with no start, one start and a start per target (threaded from
    ROWS_PARALLEL targets), its note on those targets' branches only."""
    robot = _arm(name)
    q = robot.random_q(50, rng=rng)
    home = [3, 17, 40]
    q[17, 4] = 0.0
    q[40, 4] = 0.0
    q[3] = 0.0
    targets = armkit.fk(robot, q)
    starts = rng.uniform(-4.0, 4.0, (50, robot.n))
    for fn in (armkit.ik_all, armkit.ik):
        for q0 in (None, starts[0], starts):
            batched_runs.clear()
            fast, slow = _both(lambda: fn(robot, targets, q0))
            assert batched_runs and max(batched_runs) <= len(home)      # those targets alone (some families
            _assert_same(fast, slow)                                    # answer the home pose in the kernel)
    assert len(driver_runs) == 6
    if name.endswith("-rounded"):   # (twists 3.7e-6 off 90 degrees: the wrist is not exactly straight, no note)
        return
    notes = [[m.startswith("wrist singularity") for m in row] for row in armkit.ik_all(robot, targets).message]
    assert {i for i, row in enumerate(notes) if any(row)} == set(home)


def test_a_batch_whose_every_target_needs_the_batched_path_goes_there_whole(driver_runs, batched_runs, rng):
    """Every target with its wrist straight: the driver runs and answers none, the batched path all of them at once
    (not spliced), its answer to the bit."""
    robot = _arm("puma560")
    q = robot.random_q(20, rng=rng)
    q[:, 4] = 0.0
    targets = armkit.fk(robot, q)
    for fn in (armkit.ik_all, armkit.ik):
        fast, slow = _both(lambda: fn(robot, targets))
        _assert_same(fast, slow)
    assert len(driver_runs) == 2 and batched_runs == []


def test_without_the_kernel_address_the_batched_path_answers(driver_runs, monkeypatch, rng):
    """Where Numba does not give the kernel's address (``kernel_address`` 0: an internal renamed), the driver is
    never called and the batched path answers a few targets, with its own answer."""
    robot = _arm("ur5")
    assert _with_kernel("ur5")
    rec = robot.cache["ik_fast"]
    assert rec.address > 0
    monkeypatch.setattr(rec, "address", 0)
    targets = armkit.fk(robot, robot.random_q(5, rng=rng))
    for fn in (armkit.ik_all, armkit.ik):
        fast, slow = _both(lambda: fn(robot, targets))
        _assert_same(fast, slow)
    assert driver_runs == []
    sample = (targets[0].ravel(),)
    single = importlib.import_module("armkit.ik.analytic._single")
    assert single.kernel_address(lambda *a: 0, sample) == 0            # not a Numba kernel: no address
    from numba import njit

    assert single.kernel_address(njit(lambda t: t[0]), sample) == 0    # a kernel that returns a float: none
    assert single.kernel_address(njit(lambda t: np.int64(1)), sample) > 0   # an int64: its address


def _expected(fn, robot, targets):
    api.ONE_CALL = False
    try:
        return fn(robot, targets)
    finally:
        api.ONE_CALL = True


def test_the_driver_buffers_are_reused_only_when_no_result_holds_them(rng):
    """The batch driver keeps its buffers for the next batch (``analytic._row_buffers``): a set is taken again once
    no result refers to it, and never while one does. Results kept unread while later batches run (of the same size,
    smaller, larger) read every field and sentence of their own call, the batched path's; a result whose q alone was
    read keeps its other fields; results dropped at once leave their set to the next call, a batch in pieces too."""
    robot = _arm("puma560")
    assert _with_kernel("puma560")
    rec = robot.cache["ik_fast"]

    def batch(size):
        T = armkit.fk(robot, robot.random_q(size, rng=rng))
        T[::3, :3, 3] *= 3.0                               # out of reach: sentences to make later
        return T

    for fn in (armkit.ik_all, armkit.ik):
        rec.pool.clear()
        sizes = (40, 40, 20, 60, 40)
        targets = [batch(s) for s in sizes]
        results = [fn(robot, t) for t in targets]          # every one kept, none read
        results[1].q                                       # noqa: B018 (only q read: made with the call)
        for t, res in zip(targets, results):
            _assert_same(res, _expected(fn, robot, t))
        assert any("unreachable" in str(m) for m in np.ravel(results[0].message))
    rec.pool.clear()
    T = batch(50)
    armkit.ik_all(robot, T)                                # dropped at once
    first = id(rec.pool[0][0])                             # (its id: a reference here would hold it)
    armkit.ik_all(robot, T)
    assert len(rec.pool) == 1 and id(rec.pool[0][0]) == first   # the same set again
    kept = armkit.ik_all(robot, T)
    armkit.ik_all(robot, T)
    assert len(rec.pool) == 2 and id(rec.pool[0][0]) == first   # another set meanwhile, for the second call
    _assert_same(kept, _expected(armkit.ik_all, robot, T))
    big = batch(analytic.POOL_ROWS + 1)                   # bigger than a kept set: in pieces, each in a set
    _assert_same(armkit.ik(robot, big), _expected(armkit.ik, robot, big))   # of the pool's size, dropped at once
    assert len(rec.pool) == analytic.POOL and max(len(w[0]) for w in rec.pool) == analytic.POOL_ROWS
    first = sorted(id(w[0]) for w in rec.pool)
    armkit.ik_all(robot, big)                              # the next call's pieces take those two sets again
    assert sorted(id(w[0]) for w in rec.pool) == first


def test_threads_sharing_a_robot_get_their_own_answers(rng):
    """Two threads calling the batch driver on one robot (its pool shared): each result is its own call's."""
    import threading

    robot = _arm("ur5")
    assert _with_kernel("ur5")
    targets = [armkit.fk(robot, robot.random_q(40 + k, rng=rng)) for k in range(6)]
    expected = [_expected(armkit.ik_all, robot, t) for t in targets]
    failures = []

    def work(order):
        for _ in range(15):
            for k in order:
                res = armkit.ik_all(robot, targets[k])
                if not (np.array_equal(res.q, expected[k].q) and np.array_equal(res.branch, expected[k].branch)):
                    failures.append(k)

    threads = [threading.Thread(target=work, args=(order,)) for order in ((0, 1, 2, 3, 4, 5), (5, 4, 3, 2, 1, 0))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert failures == []


def test_ik_in_pieces_keeps_no_buffer_of_its_pieces(monkeypatch, rng):
    """ik's pieces are made compact as they come (``analytic._compact``): while its result lives, unread and then
    read, no set of the pool is held by it, and the next piece took the set the one before gave back (two sets at
    most for any number of pieces); ik_all's result holds its pieces' sets until it is dropped."""
    monkeypatch.setattr(analytic, "POOL_ROWS", 40)
    robot = _arm("puma560")
    armkit.ik(robot, armkit.fk(robot, robot.random_q(rng=rng)))   # the robot's one-call record made
    rec = robot.cache["ik_fast"]
    targets = armkit.fk(robot, robot.random_q(200, rng=rng))
    targets[::9, :3, 3] *= 3.0                                  # out of reach: sentences kept for later
    rec.pool.clear()
    res = armkit.ik(robot, targets)
    assert 1 <= len(rec.pool) <= analytic.POOL
    assert all(analytic._most_refs(w) <= analytic._FREE for w in rec.pool)
    assert "unreachable" in " ".join(res.message) and res.branch.shape == (200,)
    assert all(analytic._most_refs(w) <= analytic._FREE for w in rec.pool)
    _assert_same(res, _expected(armkit.ik, robot, targets))
    rec.pool.clear()
    every = armkit.ik_all(robot, targets)
    assert any(analytic._most_refs(w) > analytic._FREE for w in rec.pool)   # held by the result
    _assert_same(every, _expected(armkit.ik_all, robot, targets))
    del every
    assert all(analytic._most_refs(w) <= analytic._FREE for w in rec.pool)
