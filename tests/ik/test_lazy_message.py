"""The one-call path makes the sentences of failed branches only when ``message`` is read (issue 19).

:meth:`armkit.ik.result.IKResult._later` leaves ``message`` to a function called on first read. Such a
result must be the same in every way as one that holds its message from the start: the value and type
of ``message``, ``repr``, pickling, copying, indexing and ``dataclasses.replace``; and no sentence may
be made before someone reads it.
"""

from __future__ import annotations

import copy
import dataclasses
import importlib
import importlib.util
import pickle

import numpy as np
import pytest

import armkit
from armkit.ik.analytic import closed_form, single_call
from armkit.ik.result import IKResult

api = importlib.import_module("armkit.ik.api")


@pytest.fixture(scope="module", autouse=True)
def compiled():
    armkit.set_backend("numba")    # the one-call path serves the Numba back end only
    if importlib.util.find_spec("numba") is None or closed_form(armkit.load("ur5")) is None:
        pytest.skip("Numba is not available")
    yield
    armkit.set_backend("auto")


def _far_ur5_target() -> tuple:
    """A UR5 pose three times too far (every branch unreachable) and a Puma pose with branches out of limits."""
    ur5 = armkit.load("ur5")
    T = armkit.fk(ur5, np.array([0.3, -1.0, 1.2, 0.4, 0.9, -0.2]))
    T[:3, 3] *= 3.0
    return ur5, T


def _eager(robot, target, **kw):
    """The same call by the batched path (messages made at once)."""
    try:
        api.ONE_CALL = False
        return armkit.ik_all(robot, target, **kw), armkit.ik(robot, target, **kw)
    finally:
        api.ONE_CALL = True


def _same(a: IKResult, b: IKResult) -> None:
    for f in dataclasses.fields(IKResult):
        x, y = getattr(a, f.name), getattr(b, f.name)
        assert type(x) is type(y), f.name
        if isinstance(x, np.ndarray):
            assert x.dtype == y.dtype and x.shape == y.shape and np.array_equal(x, y), f.name
        else:
            assert x == y, f.name


def test_no_sentence_is_made_until_message_is_read(monkeypatch):
    ur5, T = _far_ur5_target()
    family = type(closed_form(ur5))
    calls = []
    real = family.reach_why      # the family's out-of-reach sentence
    monkeypatch.setattr(family, "reach_why", lambda self, *a: (calls.append(1), real(self, *a))[1])
    res = armkit.ik_all(ur5, T)
    one = armkit.ik(ur5, T)
    assert single_call(ur5, closed_form(ur5), T, None, None) is not None     # the one-call path answered
    assert not res.success.any() and not calls
    assert "message" not in vars(res) and "message" not in vars(one)
    assert res.message[0].startswith("unreachable") and calls
    made = len(calls)
    assert one.message.startswith("unreachable") and len(calls) > made
    made = len(calls)
    res.message, one.message     # noqa: B018 (read again: kept, not made again)
    assert len(calls) == made and "_later" not in vars(res)


@pytest.mark.parametrize("case", ["unreachable", "limits"])
def test_a_later_message_is_the_eager_one(case):
    if case == "unreachable":
        robot, T = _far_ur5_target()
    else:
        robot = armkit.load("puma560")
        T = armkit.fk(robot, np.array([0.2, 0.4, -0.3, 0.5, 0.6, 0.7]))
    every, one = armkit.ik_all(robot, T), armkit.ik(robot, T)
    slow_every, slow_one = _eager(robot, T)
    assert "message" not in vars(every)
    r = repr(every)      # repr reads the message: the same text as the eager result's
    assert r == repr(slow_every)
    _same(every, slow_every)
    _same(one, slow_one)
    if case == "limits":
        assert (every.reason == "joint limits").any()
        assert all(str(m).startswith("outside the joint limits") for m in every.message[every.reason == "joint limits"])
        assert getattr(every.message[~every.success][0], "template", "").startswith("outside the joint limits")


def test_pickle_copy_index_and_replace_make_the_message():
    ur5, T = _far_ur5_target()
    slow = _eager(ur5, T)[0]
    for make in (lambda r: pickle.loads(pickle.dumps(r)), copy.copy, copy.deepcopy,
                 lambda r: dataclasses.replace(r, iterations=r.iterations)):
        res = armkit.ik_all(ur5, T)
        assert "message" not in vars(res)
        out = make(res)
        assert "_later" not in vars(out)
        _same(out, slow)
    res = armkit.ik_all(ur5, T)
    part = res[:3]                       # indexing keeps the branch order and the sentences
    assert list(part.message) == list(slow.message[:3])
    one = armkit.ik(ur5, T)
    assert isinstance(pickle.loads(pickle.dumps(one)).message, str)
    assert pickle.loads(pickle.dumps(one)).message == _eager(ur5, T)[1].message


def test_a_caller_changing_its_arrays_does_not_change_the_later_message():
    """The sentences come from the kernel's private copy of the numbers and of the target."""
    ur5, T = _far_ur5_target()
    slow = _eager(ur5, T)[0]
    target = T.copy()
    res = armkit.ik_all(ur5, target)
    target[:] = 0.0
    res.position_error[:] = 0.0
    res.q[:] = 0.0
    assert list(res.message) == list(slow.message)
    planar = armkit.load("planar2")
    p = np.array([3.0, 0.4, 0.2])         # out of reach and off the arm's plane: the sentence reads the target
    slow = _eager(planar, p)[0]
    res = armkit.ik_all(planar, p)
    p[:] = 0.0
    assert list(res.message) == list(slow.message) and "off the arm's plane" in res.message[0]


def test_plain_results_are_unchanged():
    """A result built by the constructor holds its message: the class attribute reads None (the default)."""
    res = IKResult(q=np.zeros(2), success=np.bool_(True), position_error=np.float64(0.0),
                   rotation_error=np.float64(0.0), iterations=np.int64(0), branch=np.str_("x"),
                   within_limits=np.bool_(True), reason=np.str_("converged"))
    assert res.message == "" and IKResult.message is None
    assert pickle.loads(pickle.dumps(res)).message == ""


def test_batched_and_swept_results_make_their_sentences_when_read():
    """The batched path (and a 7-joint sweep through it) leaves the sentences for later too: the same sentences
    as the one-call path gives target by target, unchanged by a caller reusing its target array, and a part
    taken by indexing before any read gives the whole's sentences for its targets."""
    ur5 = armkit.load("ur5")
    rng = np.random.default_rng(19)
    T = armkit.fk(ur5, rng.uniform(-2.0, 2.0, (6, 6)))
    T[::2, :3, 3] *= 3.0                               # every other target out of reach: failed branches
    targets = T.copy()
    res = armkit.ik_all(ur5, targets)
    assert "message" not in vars(res)                  # nothing made yet
    part = res[1:4]
    assert "message" not in vars(part)
    targets[:] = 0.0
    each = [armkit.ik_all(ur5, t).message for t in T]
    assert [list(m) for m in res.message] == [list(m) for m in each]
    assert [list(m) for m in part.message] == [list(m) for m in each[1:4]]
    assert any("unreachable" in m for m in res.message[0])
    panda = armkit.load("example-robot-data:panda") if importlib.util.find_spec("example_robot_data") else None
    if panda is not None:
        swept = armkit.ik_all(panda, armkit.fk(panda, np.array([0.1, -0.4, 0.2, -2.0, 0.1, 1.8, 0.6])))
        assert "_later" in vars(swept)
        failed = [m for m, ok in zip(swept.message, swept.success) if not ok]
        assert failed and all(m for m in failed)        # every failed branch says why, once read


@pytest.mark.parametrize("method", ["lm", "ccd", "fabrik"])
def test_numeric_solvers_make_their_sentences_when_read(method):
    """LM, CCD and FABRIK leave ``message`` for its first read too: a batch's sentences read after the caller
    reused its target array, a copy was pickled and a part indexed are those of the same call read at once, and
    each says the result's own numbers (its iterations when it converged, its position error in the arm's unit)."""
    robot = armkit.load("planar3") if method != "lm" else armkit.load("puma560")
    rng = np.random.default_rng(23)
    T = armkit.fk(robot, rng.uniform(-1.5, 1.5, (5, robot.n)))
    T[1, :3, 3] *= 4.0                                 # one target out of reach: a failure and its sentence
    targets = T[:, :3, 3].copy() if method != "lm" else T.copy()
    q0 = np.zeros(robot.n)
    at_once = [str(m) for m in armkit.ik(robot, targets, q0=q0, method=method, seed=1).message]
    res = armkit.ik(robot, targets, q0=q0, method=method, seed=1)
    assert "_later" in vars(res)
    targets[:] = 0.0
    part = res[2:4]
    kept = pickle.loads(pickle.dumps(res))
    texts = [str(m) for m in res.message]
    assert texts == [str(m) for m in kept.message] == at_once
    assert [str(m) for m in part.message] == texts[2:4]
    assert not res.success[1] and texts[1]
    for i, text in enumerate(texts):
        if res.success[i]:
            assert text.startswith(f"converged in {int(res.iterations[i])} iterations")
        assert f" {robot.unit}" in text and "position error" in text
