"""The one-call path keeps its output buffers for the next call once no result holds them (issue 19, item 5).

``armkit.ik_all(robot, T)`` and ``armkit.ik(robot, T)`` for one pose write every number into three buffers and hand
out views of them (:func:`armkit.ik.analytic._one_buffers`). A call takes a set the record kept only where nothing
refers to its arrays any more, so a result a caller keeps, or any field or view of it, is never written again. These
tests hold results and parts of results in each way a caller can, make more calls, and compare what they hold with
deep copies taken at once; and they check that a loop which drops its results does reuse the buffers (without that,
each call makes three new arrays: ~0.3 µs of a 3.5 µs call).
"""

from __future__ import annotations

import copy
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
def test_results_kept_are_never_written_again(name, call):
    robot = armkit.load(name)
    fn = getattr(armkit, call)
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
def test_a_field_or_view_kept_alone_holds_its_buffer():
    """A caller that keeps only one field (a view of one buffer) or a view of a view, and drops the result."""
    robot = armkit.load("puma560")
    targets = _targets(robot, 12, 7)
    _record(robot, targets[0])
    for f in FIELDS:
        for t, other in zip(targets, targets[1:]):
            res = armkit.ik_all(robot, t)
            part = getattr(res, f)
            if isinstance(part, np.ndarray) and part.ndim:
                part = part[1:]   # a view of the field's view
            want = copy.deepcopy(part)
            del res   # freed at once: a result is in no reference cycle
            for _ in range(4):
                armkit.ik_all(robot, other)
                armkit.ik(robot, other)
            if isinstance(part, np.ndarray):
                assert np.array_equal(part, want), f
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
    assert len(c.spare) <= 2
    # and each answer is still the batched path's
    _same(fn(robot, targets[5]), copy.deepcopy(fn(robot, targets[5])))
