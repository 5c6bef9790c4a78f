"""The one-call path shares one record per robot (``robot.cache``) between threads: every call makes its own
buffers and work arrays, so threads calling :func:`armkit.ik` / :func:`armkit.ik_all` on one robot at once get
the answers a single thread gets, field by field (issue 19)."""

from __future__ import annotations

import copy
import sys
import threading

import numpy as np
import pytest

import armkit

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


@pytest.mark.parametrize("name", ["ur5", "puma560"])
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
