"""The one-call path keeps its output buffers for the next call once no result holds them (issue 19, item 5).

``armkit.ik_all(robot, T)`` and ``armkit.ik(robot, T)`` for one pose write every number into three buffers and hand
out views of them (:func:`armkit.ik.analytic._one_buffers`; with every default, the sets of
:func:`armkit.ik.analytic._one_target_calls`, which keep the result object too). A call takes a set the record kept
only where nothing refers to its result (no weak reference either) or its arrays any more, so a result a caller
keeps, or any field or view of it, is never written again. These tests hold results and parts of results in each
way a caller can, make more calls, and compare what they hold with deep copies taken at once; and they check that
a loop which drops its results does reuse the buffers and the result (without that, each call makes three new
arrays, a result and two views: ~0.6 µs of a 2.5 µs call), with every field of the new call's answer, none of
the fields the dropped result made when read.
"""

from __future__ import annotations

import copy
import functools
import weakref

import numpy as np
import pytest
from test_single_call import compiled  # noqa: F401 (the fixture: the Numba back end)
from test_single_call_threads import FIELDS, _same

import armkit


def _targets(robot, k, seed):
    rng = np.random.default_rng(seed)
    q = rng.uniform(-np.pi, np.pi, (k, robot.n))
    T = armkit.fk(robot, q)
    T[::4, :3, 3] *= 1.6   # a quarter out of reach: failed branches, messages made from the buffers later
    return list(T)


def _record(robot, target):
    armkit.ik_all(robot, target)   # the record is made on the first call
    c = robot.cache.get("ik_fast")
    if not c or c.one is None:
        pytest.skip("no one-call kernel in use")
    return c


@pytest.mark.usefixtures("compiled")
@pytest.mark.parametrize("name", ["puma560", "ur5", "stanford", "planar3"])
@pytest.mark.parametrize("call", ["ik_all", "ik"])
@pytest.mark.parametrize("start", [False, True])
def test_results_kept_are_never_written_again(name, call, start):
    """``start``: a ``q0`` given, which the calls with every default do not take (their sets are the record's
    others: :func:`armkit.ik.analytic.run_one`'s)."""
    robot = armkit.load(name)
    fn = getattr(armkit, call)
    if start:
        q0 = np.full(robot.n, 0.1)
        fn = functools.partial(fn, q0=q0)
    targets = _targets(robot, 24, 5)
    want = [copy.deepcopy(fn(robot, t)) for t in targets]   # every field made at once, in arrays of their own
    _record(robot, targets[0])
    kept = [fn(robot, t) for t in targets]                   # nothing read yet: every field made from the buffers
    for _ in range(3):                                       # more calls, results dropped at once
        for t in targets[::-1]:
            fn(robot, t)
    for got, w in zip(kept, want):
        _same(got, w)


@pytest.mark.usefixtures("compiled")
@pytest.mark.parametrize("call", ["ik_all", "ik"])
@pytest.mark.parametrize("view", [False, True])
def test_a_field_or_view_kept_alone_holds_its_buffer(call, view):
    """A caller that keeps only one field (the result's own view of a buffer, or with ``view`` a view of it) and
    drops the result."""
    robot = armkit.load("puma560")
    fn = getattr(armkit, call)
    targets = _targets(robot, 12, 7)
    _record(robot, targets[0])
    for f in FIELDS:
        for t, other in zip(targets, targets[1:]):
            res = fn(robot, t)
            part = getattr(res, f)
            if view and isinstance(part, np.ndarray):
                part = part[1:] if part.ndim else part[...]   # a view of the field's view
            want = copy.deepcopy(part)
            del res   # dropped: its set is taken again only where nothing else refers to it
            for _ in range(4):
                armkit.ik_all(robot, other)
                armkit.ik(robot, other)
            if isinstance(part, np.ndarray):
                assert np.array_equal(part, want), f
                # and no later answer shares its memory (a field whose value never changes, such as the closed
                # form's iterations, would pass the comparison above either way)
                later = [armkit.ik_all(robot, other) for _ in range(3)] + [armkit.ik(robot, other) for _ in range(3)]
                for g in later:   # (held together: they take both kept sets of each call, then new ones)
                    for f2 in FIELDS:
                        assert not np.shares_memory(part, np.asarray(getattr(g, f2))), (f, f2)
            else:
                assert part == want, f


@pytest.mark.usefixtures("compiled")
@pytest.mark.parametrize("call", ["ik_all", "ik"])
def test_a_loop_that_drops_its_results_reuses_the_buffers(call):
    robot = armkit.load("ur5")
    fn = getattr(armkit, call)
    targets = _targets(robot, 40, 9)
    c = _record(robot, targets[0])
    bases = []
    reused = 0
    for t in targets:
        res = fn(robot, t)   # the previous result is alive during the call, as in a loop that keeps the last one
        base = res.q.base
        reused += len(bases) >= 2 and bases[-2]() is base   # the set of the call before the last one
        bases.append(weakref.ref(base))
        del base
    assert reused == len(targets) - 2      # the two sets the record keeps, in turn
    assert len(c.kept[call == "ik"]) <= 2


@pytest.mark.usefixtures("compiled")
@pytest.mark.parametrize("name", ["ur5", "puma560", "kinova"])
@pytest.mark.parametrize("call", ["ik_all", "ik"])
def test_a_result_read_and_dropped_is_handed_out_again_with_the_new_answer(name, call):
    """Every field read, then the result dropped: the next calls take its set and hand out the same object, whose
    fields (made when read from the buffers) are those of each new call, equal to a result made at once."""
    robot = armkit.load("example-robot-data:kinova" if name == "kinova" else name)   # kinova: the geometric family
    fn = getattr(armkit, call)
    targets = _targets(robot, 16, 11)
    want = [copy.deepcopy(fn(robot, t)) for t in targets]
    _record(robot, targets[0])
    ids = set()
    for _ in range(2):
        for t, w in zip(targets, want):
            res = fn(robot, t)
            ids.add(id(res))
            _same(res, w)   # every field read (made now from the buffers), then compared
            del res
    assert len(ids) == 1   # one set, one result, taken again each call (the loop holds none during the call)


@pytest.mark.usefixtures("compiled")
@pytest.mark.parametrize("call", ["ik_all", "ik"])
@pytest.mark.parametrize("hold", ["weak reference", "__dict__"])
def test_a_result_held_by_a_weak_reference_or_its_dict_is_never_handed_out_again(call, hold):
    """The result dropped, but a weak reference to it kept, or its own ``__dict__`` (``vars(result)``): its set is not
    taken again, so what the reference or the dict shows never changes."""
    robot = armkit.load("puma560")
    fn = getattr(armkit, call)
    targets = _targets(robot, 12, 13)
    _record(robot, targets[0])
    res = fn(robot, targets[0])
    want = copy.deepcopy(res)
    kept = weakref.ref(res) if hold == "weak reference" else vars(res)
    del res
    for t in targets[1:] * 3:
        other = fn(robot, t)
        if hold == "weak reference":
            assert other is not kept()
        del other
    if hold == "weak reference":
        _same(kept(), want)
    else:
        for f in FIELDS:   # (the fields the dict holds: q, success, trace and the maker of the others)
            if f in kept:
                got, w = kept[f], getattr(want, f)
                assert np.array_equal(got, w) if isinstance(w, np.ndarray) else got == w, f
        assert {"q", "success"} <= set(kept)
    # and each answer is still the batched path's
    _same(fn(robot, targets[5]), copy.deepcopy(fn(robot, targets[5])))
