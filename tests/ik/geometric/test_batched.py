"""A batch of the geometric family in one compiled call (armkit.ik.geometric.batched).

Reference: the path before it, independent of the new kernel (the solvers' one-thread loop
``solvers.solve_batch``, then the layout in Python; forced by hiding ``Geometric._batched``). The new path
must give the same raw branches bit for bit (joint values, unreachable flags, notes, sentences), the threaded
kernel the same as the one-thread kernel, and, as a check of the answer itself, every successful branch of
``ik_all`` must reproduce its target by FK of the true model and the configuration a target was made from
must be among the branches.
"""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

import numpy as np
import pytest

import armkit
from armkit.ik.analytic import closed_form
from armkit.model.robot import Joint, Robot

sys.path.insert(0, str(Path(__file__).parent))
from test_family import _random_arm, _tup  # noqa: E402
from test_one_call import ARMS, _arm  # noqa: E402

batched = importlib.import_module("armkit.ik.geometric.batched")


@pytest.fixture(scope="module", autouse=True)
def compiled():
    if importlib.util.find_spec("numba") is None:
        pytest.skip("Numba is not available")
    armkit.set_backend("numba")
    yield
    armkit.set_backend("auto")


def _nearly(rng: np.random.Generator) -> Robot:
    """A spherical-wrist arm whose wrist axes only nearly meet (1e-7 apart, as in a calibrated file): the
    solvers work on the ideal chain, whose solutions miss the target on the true one by more than the check's
    1e-9 (times the arm's size) and less than :func:`armkit.ik.geometric.solvers.polish_reach`, and the Python
    polish touches them up."""
    robot = _random_arm(rng, "spherical-general")
    joints = list(robot.joints)
    j = joints[4]
    origin = np.array(j.origin)
    origin[:3, 3] += 1e-7 * np.array([0.3, -0.7, 0.2])
    joints[4] = Joint(name=j.name, kind=j.kind, lower=j.lower, upper=j.upper, origin=_tup(origin), axis=j.axis)
    return Robot(joints, convention="urdf", name="nearly-spherical", tool=robot.chain.tool)


def _targets(robot: Robot, rng: np.random.Generator, B: int = 120):
    q = rng.uniform(-np.pi, np.pi, (B, robot.n))
    q[::9, 4] = 0.0                      # the wrist straight: a singular wrist for the spherical classes
    T = armkit.fk(robot, q)
    T[::7, :3, 3] *= 4.0                 # out of reach
    return q, T


def _both(cf, T, q0):
    new = cf.solve(T, q0)
    cf._batched = lambda *a: None        # the path before: solve_batch, then the Python layout
    try:
        old = cf.solve(T, q0)
    finally:
        del cf._batched
    return new, old


def _assert_same_raw(new, old, m: int, B: int) -> None:
    for f in ("q", "unreachable", "note", "missing", "label"):
        a, b = getattr(new, f), getattr(old, f)
        assert a.dtype == b.dtype and a.shape == b.shape, f
        assert np.array_equal(a, b), f
    for i in range(B * m):
        assert new.why(i) == old.why(i)


@pytest.mark.parametrize("name", ARMS + ("nearly/4",))
def test_same_raw_branches_as_the_path_before(name):
    rng = np.random.default_rng(17)
    robot = _nearly(np.random.default_rng(4)) if name == "nearly/4" else _arm(name)
    cf = closed_form(robot)
    if cf is None or cf.family != "geometric":
        pytest.skip("not an arm of the geometric family (a degenerate random draw)")
    B = 40 if name.startswith("two-") else 120          # the 1-D searches take ~1 ms a target
    q, T = _targets(robot, rng, B)
    q0 = rng.uniform(-1.0, 1.0, (B, robot.n))
    new, old = _both(cf, T, q0)
    _assert_same_raw(new, old, cf.m, B)
    if name == "nearly/4":      # the case the kernel leaves to Python: it must have come up
        prep_name, out = cf._batched(T, q0)
        assert out[4].any()


def _kernel_run(name: str, seed: int, B: int, parallel: bool = False, tol: float | None = None) -> tuple:
    """The batch kernel (one-thread, or threaded) on ``B`` targets of ``_targets`` for the arm ``name``, the solver's
    check at ``tol`` (its own by default): ``(q, unreachable, singular, found, redo)``."""
    robot = _arm(name)
    cf = closed_form(robot)
    if cf is None or cf.family != "geometric":
        pytest.skip("degenerate random draw")
    from armkit.ik.geometric import solvers
    from armkit.kinematics import packed

    rng = np.random.default_rng(seed)
    _, T = _targets(robot, rng, B)
    q0 = rng.uniform(-1.0, 1.0, (B, robot.n))
    sname = cf.solver if cf.solver != "spherical_wrist" else solvers._wrist_case(cf.form)
    prep = solvers._prepare(cf.form, sname)
    tol = solvers.TOL if tol is None else tol
    out = (np.zeros((B, cf.m, 6)), np.zeros((B, cf.m), np.bool_), np.zeros((B, cf.m), np.bool_),
           np.zeros(B, np.int64), np.zeros(B, np.bool_))
    K = batched.kernels()
    (K.parallel if parallel else K.serial)(
        solvers._WHICH[prep.solve], prep.kind, cf.inverted, prep.exact, prep.Hi, prep.Pi, prep.RnT, prep.prism,
        prep.Ht, prep.Pt, np.ascontiguousarray(T), q0, solvers.SEARCH_N, tol * prep.scale, tol,
        prep.reach * prep.scale, prep.reach, packed(robot)[0], cf.sf.theta, *out)
    return out


@pytest.mark.parametrize("name", ("kinova", "stanford", "spherical-base/1", "three-parallel/2"))
def test_threads_give_the_same_bits(name):
    for a, b in zip(_kernel_run(name, 5, 200), _kernel_run(name, 5, 200, parallel=True)):
        assert np.array_equal(a, b)


@pytest.mark.parametrize("name", ("kinova", "spherical-base/1", "three-parallel/2"))
def test_the_shortcut_past_the_check_is_gated(name):
    """The batch kernel's shortcut past the solver's check (the FK of the robot in place of the check's, module
    docstring) keeps a target's branches only where that FK puts them within the gate. With the check's tolerances
    made 1e-30, no branch is within it: every target goes the long way, where the check fails every candidate, so
    each is left to the Python polish (``redo``: the Kinova's chain is not exact) or answered unreachable. A
    shortcut without its gate would answer them found."""
    for tol, found_some in ((None, True), (1e-30, False)):
        _, unreach, _, found, redo = _kernel_run(name, 6, 50, tol=tol)
        answered = ~redo & ~unreach.all(axis=1)
        assert answered.any() == found_some and (found[~redo] > 0).any() == found_some


@pytest.mark.parametrize("name", ("kinova", "stanford", "spherical-general/1", "spherical-base/1",
                                  "three-parallel/2"))
def test_batched_ik_all_is_right(name):
    """Every successful branch reproduces its target (FK of the true model, 1e-9 of the reach) and the
    configuration the target came from is one of them (angles compared modulo a turn)."""
    robot = _arm(name)
    cf = closed_form(robot)
    if cf is None or cf.family != "geometric":
        pytest.skip("degenerate random draw")
    rng = np.random.default_rng(23)
    lo = np.where(np.isfinite(robot.lower), robot.lower, -np.pi)
    hi = np.where(np.isfinite(robot.upper), robot.upper, np.pi)
    q = rng.uniform(lo, hi, (150, robot.n))
    T = armkit.fk(robot, q)
    res = armkit.ik_all(robot, T, enforce_limits=False)
    ok = res.success
    assert ok.any(axis=1).all()
    back = armkit.fk(robot, res.q[ok])
    Tb = np.broadcast_to(T[:, None], res.q.shape[:2] + (4, 4))[ok]
    assert np.abs(back - Tb).max() < 1e-9 * max(1.0, robot.reach)
    d = res.q - q[:, None]
    d = np.where(robot.prismatic, d, (d + np.pi) % (2 * np.pi) - np.pi)
    d = np.where(ok, np.abs(d).max(axis=-1), np.inf)
    assert (d.min(axis=1) < 1e-6).all()


def test_an_unreachable_targets_candidates_are_not_polished(monkeypatch):
    """On an arm whose ideal chain is not its true one, a failed candidate farther from the target than the chains'
    difference explains (an out-of-reach target's closest point) is not polished: nothing Newton's steps do to it
    passes the check. The answers, messages included, are those of polishing every failed candidate (the rule
    before, ``polish_reach`` infinite), by every path: one target, a few, a batch; ``ik_all`` and ``ik``."""
    from armkit.ik.geometric import solvers

    polished = []
    real = solvers.polish
    monkeypatch.setattr(solvers, "polish", lambda *a, **k: polished.append(1) or real(*a, **k))
    _, T = _targets(_nearly(np.random.default_rng(4)), np.random.default_rng(8), 60)
    far = T[::7]                                            # the targets out of reach
    answers = []
    reach_now = solvers.polish_reach
    for reach in (reach_now, lambda dev: np.inf):
        monkeypatch.setattr(solvers, "polish_reach", reach)
        robot = _nearly(np.random.default_rng(4))           # a new robot: its records made with this rule
        before = len(polished)
        got = [fn(robot, x) for fn in (armkit.ik_all, armkit.ik) for x in (far[0], far[:3], far, T)]
        got = [(r.q, r.success, r.position_error, r.rotation_error, r.branch, r.reason, r.message) for r in got]
        answers.append((got, len(polished) - before))
    (new, n_new), (old, n_old) = answers
    for a, b in zip(new, old):
        for x, y in zip(a, b):
            assert np.array_equal(np.asarray(x), np.asarray(y))
    assert n_old > 0 and n_new < n_old
    monkeypatch.setattr(solvers, "polish_reach", reach_now)
    robot = _nearly(np.random.default_rng(4))
    before = len(polished)
    armkit.ik_all(robot, far)
    armkit.ik(robot, far[1])
    assert len(polished) == before                          # out of reach: no candidate polished at all
