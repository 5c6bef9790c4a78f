"""The geometric family's single call in one compiled call (armkit.ik.geometric.one_call).

Two references, both independent of the new kernel: the batched path (``armkit.ik.api.ONE_CALL = False``:
the family's Python ``solve``, then ``solve_all``), and the one-call path as it was before the kernel (the
family's Python ``solve``, then the ``post`` kernel: forced by hiding the family's ``geometry``). The
kernel must give the same fields bit for bit, the same messages, and, as a check of the answer itself,
every successful branch must reproduce the target by FK of the true model and the configuration the
target was made from must be among the branches.
"""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import armkit
from armkit.errors import ShapeError
from armkit.ik.analytic import closed_form, single_call
from armkit.model.robot import Joint, Robot

sys.path.insert(0, str(Path(__file__).parent))
from test_family import KINOVA, _random_arm, _tup  # noqa: E402

api = importlib.import_module("armkit.ik.api")
geometric = importlib.import_module("armkit.ik.analytic.geometric")
FIELDS = ("q", "success", "position_error", "rotation_error", "iterations", "branch", "within_limits", "reason",
          "message")
_ARMS: dict[str, Robot] = {}


def _arm(name: str) -> Robot:
    if name not in _ARMS:
        if name == "kinova":
            if not KINOVA.exists():
                pytest.skip("example-robot-data is not installed")
            robot = armkit.load(str(KINOVA), tip="j2s6s200_end_effector")
        elif name == "stanford":
            robot = armkit.load("stanford")
        else:                           # random arms of a class: "spherical-general/3"
            kind, seed = name.split("/")
            robot = (_search_arm if kind.startswith("two-") else _random_arm)(np.random.default_rng(int(seed)), kind)
        _ARMS[name] = robot
    return _ARMS[name]


def _search_arm(rng: np.random.Generator, kind: str) -> Robot:
    """A random 6R arm of a class solved by a 1-D search, in URDF form: axes 5 and 6 meet
    (``"two-intersecting"``) or axes 2 and 3 are parallel (``"two-parallel"``), nothing else."""
    def unit(v):
        return v / np.linalg.norm(v)

    H = np.array([unit(rng.normal(size=3)) for _ in range(6)])
    pts = rng.normal(size=(6, 3)) * 0.3
    if kind == "two-intersecting":
        pts[5] = pts[4]
    else:
        H[2] = H[1]
    joints, prev = [], np.eye(4)
    for k in range(6):
        A = np.eye(4)
        x = unit(np.cross(H[k], [0.3, 0.5, 0.8]))
        A[:3, :3] = np.column_stack([x, np.cross(H[k], x), H[k]])
        A[:3, 3] = pts[k]
        joints.append(Joint(name=f"j{k + 1}", kind="revolute", lower=-np.inf, upper=np.inf,
                            origin=_tup(np.linalg.inv(prev) @ A), axis=(0.0, 0.0, 1.0)))
        prev = A
    tool = np.eye(4)
    tool[:3, 3] = rng.normal(size=3) * 0.1
    return Robot(joints, convention="urdf", name=f"random-{kind}", tool=tool)


# (a Puma or UR whose file reverses an axis was one of them: the DH families answer it now, the Puma's and UR's own
# with that joint turned back, tests/ik/test_reversed_joint.py)
ARMS = ("kinova", "stanford", "spherical-general/1", "spherical-base/1", "three-parallel/2",
        "two-intersecting/3", "two-parallel/3")


@pytest.fixture(scope="module", autouse=True)
def compiled():
    if importlib.util.find_spec("numba") is None:
        pytest.skip("Numba is not available")
    armkit.set_backend("numba")    # the one-call path serves the Numba back end only
    yield
    armkit.set_backend("auto")


def _family(robot: Robot):
    cf = closed_form(robot)
    if cf is None or cf.family != "geometric":
        pytest.skip("not an arm of the geometric family (a degenerate random draw)")
    return cf


def _kernel_mode(robot: Robot, on: bool) -> None:
    """The family's one-call kernel (``on``) or the path before it (Python solve, then ``post``)."""
    cf = closed_form(robot)
    robot.cache.pop("closed_form_one_call", None)
    robot.cache.pop("ik_fast", None)
    cf._geometry = geometric._UNSET if on else None


def _assert_same(a, b) -> None:
    for f in FIELDS:
        x, y = getattr(a, f), getattr(b, f)
        assert type(x) is type(y), f
        if isinstance(x, np.ndarray):
            assert x.dtype == y.dtype and x.shape == y.shape, f
            assert np.array_equal(x, y), (f, x, y)      # bit for bit (NaN never occurs here)
        else:
            assert x == y, f


def _three_ways(robot: Robot, fn):
    """``fn()`` by the kernel, by the one-call path before it, and by the batched path."""
    try:
        _kernel_mode(robot, True)
        new = fn()
        _kernel_mode(robot, False)
        old = fn()
        api.ONE_CALL = False
        batched = fn()
    finally:
        api.ONE_CALL = True
        _kernel_mode(robot, True)
    return new, old, batched


@pytest.mark.parametrize("name", ARMS)
def test_the_kernel_serves_the_family(name, rng):
    """The family has a packed geometry and the registered kernel, and the kernel answers typical targets itself
    (else the comparisons below would compare a path with itself)."""
    robot = _arm(name)
    cf = _family(robot)
    _kernel_mode(robot, True)
    if name.startswith("two-"):       # the 1-D searches keep the Python solve (one_call.closed_form_only)
        assert cf.geometry is None
        return
    assert cf.geometry is not None
    armkit.ik_all(robot, armkit.fk(robot, robot.random_q(rng=rng)))
    assert robot.cache["closed_form_one_call"].kernel is not None
    hits = sum(single_call(robot, cf, armkit.fk(robot, robot.random_q(rng=rng)), None, None) is not None
               for _ in range(20))
    assert hits >= 15


@pytest.mark.parametrize("name", ARMS)
@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(u=st.lists(st.floats(-1.0, 1.0), min_size=6, max_size=6), v=st.lists(st.floats(-1.0, 1.0), min_size=6,
                                                                          max_size=6),
       far=st.sampled_from([1.0, 1.0, 1.0, 1.3, 3.0]), start=st.booleans(), enforce=st.booleans())
def test_same_results_as_before_and_as_batched(name, u, v, far, start, enforce):
    robot = _arm(name)
    _family(robot)
    lo = np.where(np.isfinite(robot.lower), robot.lower, -np.pi)
    hi = np.where(np.isfinite(robot.upper), robot.upper, np.pi)
    q = lo + (hi - lo) * (np.asarray(u) + 1.0) / 2.0
    target = armkit.fk(robot, q)
    target[:3, 3] *= far
    q0 = 4.0 * np.asarray(v) if start else None      # a start far from the limits: branches outside them
    for fn in (armkit.ik_all, armkit.ik):
        new, old, batched = _three_ways(robot, lambda: fn(robot, target, q0, enforce_limits=enforce))
        _assert_same(new, old)
        _assert_same(new, batched)
    # the answer itself: every successful branch reaches the target; the target's own q is a branch
    res = armkit.ik_all(robot, target, q0, enforce_limits=False)
    if res.success.any():
        got = armkit.fk(robot, res.q[res.success])
        assert np.abs(got[:, :3, 3] - target[:3, 3]).max() <= 1e-9 * max(1.0, robot.reach)
        assert np.abs(got[:, :3, :3] - target[:3, :3]).max() <= 1e-8
    # the closed forms find the target's own q away from singularities (the 1-D searches only to their stated
    # resolution: not asked here)
    if far == 1.0 and not name.startswith("two-") and np.linalg.cond(armkit.jacobian(robot, q)) < 1e4:
        d = np.where(robot.prismatic, res.q - q, (res.q - q + np.pi) % (2 * np.pi) - np.pi)
        assert np.abs(d).max(axis=1).min() < 1e-6


def test_unreachable_sentences_match():
    """A target far out of reach: every branch fails with the family's sentence, the same with and without the
    kernel (the kernel's numbers give it through ``reach_why``)."""
    robot = _arm("kinova")
    _family(robot)
    target = armkit.fk(robot, np.zeros(6))
    target[:3, 3] = [5.0 * robot.reach, 0.0, 0.0]
    new, old, batched = _three_ways(robot, lambda: armkit.ik_all(robot, target))
    assert not new.success.any()
    assert list(map(str, new.message)) == list(map(str, old.message)) == list(map(str, batched.message))
    assert all(str(m).startswith("unreachable") for m in new.message)


def test_limit_sentences_match():
    """The Stanford arm's boom slid past its limit: every branch fails by the limits, with the same sentences."""
    robot = _arm("stanford")
    _family(robot)
    target = armkit.fk(robot, np.zeros(6))
    target[:3, 3] *= 5.0
    new, old, batched = _three_ways(robot, lambda: armkit.ik_all(robot, target))
    assert not new.success.any() and (new.reason == "joint limits").all()
    assert list(map(str, new.message)) == list(map(str, old.message)) == list(map(str, batched.message))
    assert all("outside the joint limits" in str(m) for m in new.message)


@pytest.mark.parametrize("name", ("kinova", "spherical-base/1", "three-parallel/2", "stanford"))
def test_the_shortcut_past_the_check_is_gated(name, rng):
    """The one-call kernel's shortcut past the solver's check (:mod:`armkit.ik.geometric.one_call`) answers only
    where the FK of the robot puts every branch within its gate. With the check's tolerances made 1e-30 in the
    kernel's geometry (its ``TOL_P``, ``TOL_R``), no branch is within the gate: the kernel goes the long way, where
    the check fails every candidate, so no branch succeeds (the Kinova's chain is not exact: ``solve_batch`` would
    polish them, and the kernel leaves the target to the batched path, ``FALLBACK``; an exact chain's candidates
    are answered as unreachable). A shortcut without its gate would answer every branch as a success. Arms solved
    on the chain as given (the Kinova, three parallel axes, the Stanford arm's prismatic joint) and reversed
    (spherical wrist at the base)."""
    from armkit.ik.geometric import one_call

    robot = _arm(name)
    _family(robot)
    _kernel_mode(robot, True)
    m = closed_form(robot).m
    tried = 0
    for _ in range(8):
        target = armkit.fk(robot, robot.random_q(rng=rng))
        armkit.ik_all(robot, target)
        c = robot.cache["ik_fast"]
        g0 = int(c.ctx[1])
        strict = c.ctx.copy()
        strict[g0 + one_call.TOL_P] = strict[g0 + one_call.TOL_R] = 1e-30
        got = []
        for ctx in (c.ctx, strict):
            fb, ib, bb = np.empty(c.fshape), np.empty(c.isize, np.int64), np.empty(c.bsize, np.bool_)
            status = c.entry(target.ravel().copy(), c.q0, ctx, fb, ib, bb, c.wk) & 3
            got.append((status, int(bb[:m].sum()) if status == one_call.DONE else None))
        if got[0][0] != one_call.DONE:
            continue      # a target the kernel leaves to the batched path anyway (a singular wrist, say)
        tried += 1
        assert got[0][1] > 0      # answered: the branch the target was made from succeeds
        assert got[1] in ((one_call.FALLBACK, None), (one_call.DONE, 0)), got
    assert tried >= 5


def test_reach_why_counts_the_solutions():
    """``reach_why`` from the count the kernel leaves (its ``rho``) is the sentence of ``Raw.why``."""
    cf = _family(_arm("stanford"))
    assert "has 3 solutions" in cf.reach_why(False, 3.0, 0.0, None)
    assert "has 1 solution;" in cf.reach_why(False, 1.0, 0.0, None)
    assert cf.reach_why(False, 0.0, 0.0, None).startswith("no configuration")


def test_statuses_agree_with_the_one_call_module():
    from armkit.ik.analytic import _single
    from armkit.ik.geometric import one_call

    assert (one_call.DONE, one_call.FALLBACK, one_call.BAD_TARGET) == (_single.DONE, _single.FALLBACK,
                                                                        _single.BAD_TARGET)
    assert one_call.MAXSOL == importlib.import_module("armkit.ik.geometric.solvers").MAXSOL
    assert one_call.kernel() is _single.KERNELS["geometric"]


def test_bad_targets_still_raise():
    """A target that is not finite or not rigid: the kernel leaves it to the general path, which raises."""
    robot = _arm("stanford")
    _kernel_mode(robot, True)
    for value in (np.nan, 2.0):
        bad = armkit.fk(robot, np.zeros(6))
        bad[0, 0] = value
        for fn in (armkit.ik_all, armkit.ik):
            with pytest.raises(ShapeError):
                fn(robot, bad)
    skew = armkit.fk(robot, np.zeros(6))
    skew[0, 0] += 1e-3
    assert armkit.ik_all(robot, skew, check=False).shape == (closed_form(robot).m,)   # unchecked: answered


def test_solver_files_split_and_names_kept():
    """solvers.py split by class into files under 800 lines; the public names still come from solvers.py."""
    from armkit.ik.geometric import solvers

    folder = Path(solvers.__file__).parent
    for f in folder.glob("solvers*.py"):
        assert len(f.read_text().splitlines()) < 800, f.name
    for name in solvers.__all__:
        assert hasattr(solvers, name), name
    for name in solvers.KERNELS:       # the compiled namespace finds every core
        assert callable(getattr(solvers, name)), name
