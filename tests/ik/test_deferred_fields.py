"""The single-call path makes a result's fields when one is first read (issue 19).

:meth:`armkit.ik.result.IKResult._deferred` holds ``q`` and ``success`` and keeps the buffers of the compiled
call to make the other fields on first read. Such a result must be the same in every way as the one the
batched path builds at once: every field's value, type, dtype and shape, ``repr``, equality, pickling; nothing is made before a
read; a caller that changes its target array before reading changes nothing; two results share no array;
threads reading one result at the same time all see the same fields.
"""

from __future__ import annotations

import copy
import dataclasses
import importlib
import pickle
import threading
import time

import numpy as np
import pytest
from test_single_call import _assert_same, compiled  # noqa: F401 (the fixture: the Numba back end)

import armkit
from armkit.ik.result import IKResult

api = importlib.import_module("armkit.ik.api")


def _eager(call, robot, target):
    """The same call by the batched path (every field made at once)."""
    try:
        api.ONE_CALL = False
        return call(robot, target)
    finally:
        api.ONE_CALL = True


def _same(a: IKResult, b: IKResult) -> None:
    """Every field the same, type by type and bit for bit (``_assert_same`` of the single-call tests), and the
    same dtype, text widths included."""
    _assert_same(a, b)
    for f in dataclasses.fields(IKResult):
        x = getattr(a, f.name)
        if isinstance(x, np.ndarray):
            assert x.dtype == getattr(b, f.name).dtype, f.name


def _targets(robot):
    """A pose every branch of which is reachable, one out of reach, and one with branches outside the limits."""
    q = np.array([0.3, -1.0, 1.2, 0.4, 0.9, -0.2, 0.1][:robot.n])
    T = armkit.fk(robot, q)
    far = T.copy()
    far[:3, 3] *= 3.0
    rng = np.random.default_rng(6)
    edge = armkit.fk(robot, np.clip(rng.uniform(-3.0, 3.0, robot.n), robot.lower, robot.upper))
    return {"reachable": T, "out of reach": far, "near the limits": edge}


ROBOTS = ["ur5", "puma560", "stanford", "cobra600", "planar3"]


@pytest.mark.parametrize("name", ROBOTS)
@pytest.mark.parametrize("call", [armkit.ik, armkit.ik_all], ids=["ik", "ik_all"])
def test_a_deferred_result_is_the_eager_one(name, call):
    robot = armkit.load(name)
    for case, T in _targets(robot).items():
        res = call(robot, T)
        slow = _eager(call, robot, T)
        if "_make" in vars(res):
            assert set(vars(res)) == {"_make", "trace", "q", "success"}, case   # the rest made when read
        assert repr(res) == repr(slow), case
        _same(res, slow)
        assert res == res


def test_the_single_call_path_makes_each_field_when_it_is_read():
    ur5 = armkit.load("ur5")
    T = _targets(ur5)["reachable"]
    for call in (armkit.ik, armkit.ik_all):
        res = call(ur5, T)
        assert set(vars(res)) == {"_make", "trace", "q", "success"}
        branch = res.branch      # the first read of a field but q, success and message makes them all
        rest = {"position_error", "rotation_error", "iterations", "branch", "within_limits", "reason"}
        assert set(vars(res)) == {"_make", "trace", "q", "success"} | rest and res.branch is branch   # kept
        copy.copy(res)   # copying (as pickling) makes every field first
        assert {f.name for f in dataclasses.fields(IKResult)} <= set(vars(res)) and "_make" not in vars(res)


@pytest.mark.parametrize("case", ["reachable", "out of reach", "near the limits"])
def test_changing_the_target_before_the_first_read_changes_nothing(case):
    ur5 = armkit.load("ur5")
    T = _targets(ur5)[case]
    slow_all, slow_one = _eager(armkit.ik_all, ur5, T), _eager(armkit.ik, ur5, T)
    target = T.copy()
    every, one = armkit.ik_all(ur5, target), armkit.ik(ur5, target)
    target[:] = np.nan
    _same(every, slow_all)
    _same(one, slow_one)


def test_a_sentence_that_reads_the_target_reads_it_as_it_was():
    planar = armkit.load("planar2")
    p = np.array([3.0, 0.4, 0.2])         # out of reach and off the arm's plane: the sentence reads the target
    slow_all, slow_one = _eager(armkit.ik_all, planar, p), _eager(armkit.ik, planar, p)
    target = p.copy()
    every, one = armkit.ik_all(planar, target), armkit.ik(planar, target)
    target[:] = 0.0
    _same(every, slow_all)
    _same(one, slow_one)
    assert "off the arm's plane" in every.message[0] and "off the arm's plane" in one.message


def test_results_share_no_array_and_pickle_alike():
    ur5 = armkit.load("ur5")
    T = _targets(ur5)
    a, b = armkit.ik_all(ur5, T["reachable"]), armkit.ik_all(ur5, T["reachable"])
    b.q[:] = 0.0
    b.position_error[:] = 1.0
    assert not np.array_equal(a.q, b.q) and (a.position_error < 1e-9).all()
    c = armkit.ik_all(ur5, T["out of reach"])
    back = pickle.loads(pickle.dumps(c))      # pickling makes the fields (and the sentences) first
    assert "_make" not in vars(back) and "_later" not in vars(back)
    _same(back, _eager(armkit.ik_all, ur5, T["out of reach"]))


def test_threads_reading_one_result_see_the_same_fields():
    """A thread that reads while another is making the fields (slowed down here, so that the two overlap) makes
    them too: it never finds a field missing."""
    ur5 = armkit.load("ur5")
    T = _targets(ur5)["out of reach"]
    slow = _eager(armkit.ik_all, ur5, T)
    for _ in range(3):
        res = armkit.ik_all(ur5, T)
        make = vars(res)["_make"]

        def slowly(f):
            def made(*args):
                time.sleep(0.005)      # lets the other threads run while this one is making a field
                return f(*args)
            return made

        vars(res)["_make"] = (slowly(make[0]),) + make[1:]
        seen, errors = [], []
        start = threading.Barrier(4)

        def read(res=res, seen=seen, errors=errors, start=start):
            start.wait()
            try:
                seen.append((res.branch.tolist(), res.reason.tolist(), res.q.copy(), list(res.message)))
            except Exception as exc:   # an AttributeError here: a field read while another thread made them
                errors.append(exc)

        threads = [threading.Thread(target=read) for _ in range(4)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        assert not errors and len(seen) == 4
        for branch, reason, q, message in seen:
            assert branch == slow.branch.tolist() and reason == slow.reason.tolist()
            assert np.array_equal(q, slow.q) and message == list(slow.message)
