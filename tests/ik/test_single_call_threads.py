"""The one-call path shares one record per robot (``robot.cache``) between threads: every call takes output
buffers no other call or result holds (a kept set where none refers to it, taken out of the record's deque in one
step: tests/ik/test_one_call_buffers.py), and the record's work vector is used by one compiled call at a time (a
kernel holds the GIL from start to end), so threads calling :func:`armkit.ik` / :func:`armkit.ik_all` on one robot
at once get the answers a single thread gets, field by field (issue 19). A kernel reads nothing of its work space
that it did not write in the same call."""

from __future__ import annotations

import copy
import sys
import threading

import numpy as np
import pytest

import armkit
from armkit.ik.analytic._layout import NEAREST

FIELDS = ("q", "success", "position_error", "rotation_error", "iterations", "branch", "within_limits", "reason",
          "message")


def _same(a, b) -> None:
    for f in FIELDS:
        x, y = getattr(a, f), getattr(b, f)
        assert type(x) is type(y), f
        if isinstance(x, np.ndarray):
            assert x.dtype == y.dtype and x.shape == y.shape and np.array_equal(x, y), f
        else:
            assert x == y, f


@pytest.mark.parametrize("name", ["ur5", "puma560", "fighter", "stanford"])
def test_threads_sharing_a_record_get_the_serial_answers(name):
    robot = armkit.load(name)
    rng = np.random.default_rng(3)
    # half the targets from joint values beyond the limits: failed branches and the nearest-first fall-through
    lo = np.where(np.isfinite(robot.lower), robot.lower, -np.pi)
    hi = np.where(np.isfinite(robot.upper), robot.upper, np.pi)
    q = np.concatenate([rng.uniform(lo, hi, (40, robot.n)), rng.uniform(-np.pi, np.pi, (40, robot.n))])
    targets = list(armkit.fk(robot, q))
    # deep copies (the messages made now): a result must not change when other calls run
    want = [(copy.deepcopy(armkit.ik(robot, t)), copy.deepcopy(armkit.ik_all(robot, t))) for t in targets]
    errors: list[BaseException] = []
    start = threading.Barrier(4)

    def work(k: int) -> None:
        try:
            start.wait()
            for _ in range(5):
                for i in range(k, len(targets) - 1, 2):   # two threads on each half of the targets
                    got = [(armkit.ik(robot, targets[j]), armkit.ik_all(robot, targets[j])) for j in (i, i + 1)]
                    for j, (one, every) in zip((i, i + 1), got):   # each still holds its own values
                        _same(one, want[j][0])
                        _same(every, want[j][1])
        except BaseException as exc:   # noqa: BLE001 (reported by the main thread)
            errors.append(exc)

    threads = [threading.Thread(target=work, args=(k % 2,)) for k in range(4)]
    interval = sys.getswitchinterval()
    sys.setswitchinterval(1e-6)   # threads take turns every few calls, inside them too
    try:
        for t in threads:
            t.start()
        for t in threads:
            t.join()
    finally:
        sys.setswitchinterval(interval)
    assert not errors, errors[0]


def _record(name):
    from armkit.ik.analytic import closed_form, one_call_record

    robot = armkit.load(name)
    c = one_call_record(robot, closed_form(robot))
    if c is None or c.kernel is None:
        pytest.skip("the Numba back end is not in use")
    return robot, c


def test_no_one_call_kernel_releases_the_gil():
    """The record's work vector is safe to share only while no kernel runs without the GIL."""
    _record("stanford")   # the geometric family's kernel registered too
    from armkit.ik.analytic import _single

    kernels = list(_single.KERNELS.values()) + [_single.post]
    assert len(kernels) >= 7
    for k in kernels:
        assert not k.targetoptions.get("nogil", False), k


@pytest.mark.parametrize("name", ["planar2", "planar3", "fighter", "puma560", "ur5", "stanford"])
def test_kernels_read_no_work_space_they_did_not_write(name):
    """The same outputs, to the bit, whatever the work vector and the work ends of ``ib``/``bb`` hold before the
    call: garbage, NaN, zeros (each family's pieces, sized by ``_single.work``, written before they are read)."""
    robot, c = _record(name)
    rng = np.random.default_rng(8)
    q = rng.uniform(-np.pi, np.pi, (30, robot.n))
    T = armkit.fk(robot, q)
    T[::3, :3, 3] *= 1.5   # some out of reach
    m, lay = c.m, c.at
    for t in T:
        for ctx in (c.ctx, c.ctx_near):
            got = []
            for fill in (np.nan, 0.0, 1e300, -7.0):
                fb, ib, bb = np.full(c.fshape, fill), np.full(c.isize, -3, np.int64), np.full(c.bsize, fill != 0.0)
                c.wk[:] = fill
                r = c.entry(t.ravel(), c.q0, ctx, fb, ib, bb, c.wk)
                got.append((r, fb.reshape(-1)[:lay["fb"]].copy(), ib[:5 * m].copy(), bb[:2 * m].copy()))
            r0 = got[0][0]
            assert r0 & 3 == 0 or r0 & 3 == 1   # answered, or handed to the batched path
            for r, f, i, b in got[1:]:
                assert r == r0
                if r & 3:
                    continue
                if r & NEAREST:   # armkit.ik's nearest branch that succeeds: only its values are written
                    assert np.array_equal(f[:c.n], got[0][1][:c.n]) and b[0] == got[0][3][0]
                else:             # every value of every branch
                    assert np.array_equal(f, got[0][1]) and np.array_equal(i, got[0][2])
                    assert np.array_equal(b, got[0][3])
