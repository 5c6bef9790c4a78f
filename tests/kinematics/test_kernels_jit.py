"""The Numba kernels against the NumPy reference back end and against numpy.sin/cos.

The NumPy back end is the reference (vectorised matrix products, NumPy's own sin/cos);
the Numba kernels use their own polynomial sine/cosine, blocks, threads and a
single-call path with its own input checks, so each of those is checked here.
"""

from __future__ import annotations

import numpy as np
import pytest

import armkit
from armkit import kinematics
from armkit.errors import ShapeError

jit = pytest.importorskip("armkit.kinematics._jit")
ROBOTS = sorted(armkit.bundled_robots())


def test_polynomial_sincos_matches_numpy():
    rng = np.random.default_rng(5)
    x = np.concatenate([np.linspace(-20.0, 20.0, 400_001),                 # every quadrant, many times
                        np.arange(-64, 65) * (np.pi / 4),                    # the reduction's seams
                        rng.uniform(-1e5, 1e5, 100_000),                     # the edge of the short reduction
                        [1e5 + 1.0, -3e7, 1e300, 0.0, -0.0, 5e-324]])        # math.sin/cos fallback
    s, c = np.empty_like(x), np.empty_like(x)
    assert jit.sincos_block(x, s, c) == 0
    assert np.abs(s - np.sin(x)).max() <= 4.5e-16
    assert np.abs(c - np.cos(x)).max() <= 4.5e-16


def test_polynomial_sincos_counts_non_finite_values():
    x = np.array([0.1, np.nan, np.inf, -np.inf, 2.0])
    s, c = np.empty_like(x), np.empty_like(x)
    assert jit.sincos_block(x, s, c) == 3
    assert s[0] == pytest.approx(np.sin(0.1), abs=1e-16) and c[4] == pytest.approx(np.cos(2.0), abs=1e-16)


def _both(f, *args, **kw):
    kinematics.set_backend("numba")
    try:
        a = f(*args, **kw)
        kinematics.set_backend("numpy")
        b = f(*args, **kw)
    finally:
        kinematics.set_backend("auto")
    return a, b


@pytest.mark.parametrize("name", ROBOTS)
def test_numba_equals_numpy_batched_and_single(name):
    robot = armkit.load(name)
    # around the parallel threshold, beyond +-pi, and one block boundary
    Q = robot.random_q(jit.PARALLEL_MIN + 1, rng=11) * 2.0
    scale = max(1.0, robot.reach)
    for f, kw in ((armkit.fk, {}), (armkit.jacobian, {}), (armkit.jacobian, {"frame": "tool"}), (armkit.fk_frames, {})):
        for sub in (Q, Q[: jit.PARALLEL_MIN - 1], Q[: jit.BLOCK + 1]):
            a, b = _both(f, robot, sub, **kw)
            assert a.shape == b.shape
            assert np.abs(a - b).max() <= 1e-14 * scale
        for q in Q[:5]:
            a, b = _both(f, robot, q, **kw)
            assert np.abs(a - b).max() <= 1e-14 * scale


def test_single_call_accepts_lists_ints_strided_and_readonly():
    robot = armkit.load("stanford")
    Q = robot.random_q(3, rng=1)
    F = np.asfortranarray(Q)                        # rows are strided views
    R = Q[0].copy()
    R.setflags(write=False)
    ref = armkit.fk(robot, Q)
    refJ = armkit.jacobian(robot, Q)
    assert np.allclose(armkit.fk(robot, F[1]), ref[1], rtol=0, atol=1e-15 * robot.reach)
    assert np.allclose(armkit.jacobian(robot, F[1]), refJ[1], rtol=0, atol=1e-15 * robot.reach)
    assert np.allclose(armkit.fk(robot, R), ref[0], rtol=0, atol=1e-15 * robot.reach)
    assert np.allclose(armkit.fk(robot, list(Q[2])), ref[2], rtol=0, atol=1e-15 * robot.reach)
    for other in (Q[0].astype(">f8"), Q[0].astype(np.float32), Q[0].astype(np.longdouble)):  # general path
        assert np.allclose(armkit.fk(robot, other), armkit.fk(robot, other.astype(float)), rtol=0, atol=0)
        assert np.allclose(armkit.jacobian(robot, other), armkit.jacobian(robot, other.astype(float)), rtol=0, atol=0)
    ints = np.array([1, 0, 2, 0, 1, 0])
    assert np.allclose(armkit.fk(robot, ints), armkit.fk(robot, ints.astype(float)), rtol=0, atol=0)


@pytest.mark.parametrize("bad, message", [
    (np.array([0.1, np.nan, 0, 0, 0, 0]), "NaN or infinite"),
    (np.zeros(5), r"shape \(\.\.\., 6\) for robot 'puma560', got \(5,\)"),
    (np.full((4000, 6), np.inf), "NaN or infinite"),                   # threaded batch
    (np.vstack([np.zeros((3, 6)), [[0, 0, np.nan, 0, 0, 0]]]), "NaN or infinite"),
    (np.zeros((2, 7)), r"got \(2, 7\)"),
    ("abc", "must be numeric"),
])
@pytest.mark.parametrize("f", [armkit.fk, armkit.jacobian, armkit.fk_frames])
def test_bad_input_raises_the_same_message_with_numba(f, bad, message):
    robot = armkit.load("puma560")
    kinematics.set_backend("numba")
    try:
        with pytest.raises(ShapeError, match=message):
            f(robot, bad)
    finally:
        kinematics.set_backend("auto")


def test_long_chain_single_call_matches_numpy():
    """More than 8 joints: the single-call kernel takes its other branch (no parking in out)."""
    rng = np.random.default_rng(3)
    joints = [armkit.Joint("prismatic" if i % 4 == 2 else "revolute", *rng.uniform(-1, 1, 4)) for i in range(10)]
    for convention in ("standard", "modified"):
        robot = armkit.Robot(joints, convention, name="snake", tool=armkit.spatial.transl([0.1, 0.0, 0.2]))
        for q in rng.uniform(-3, 3, (5, 10)):
            for f, kw in ((armkit.fk, {}), (armkit.jacobian, {}), (armkit.jacobian, {"frame": "tool"})):
                a, b = _both(f, robot, q, **kw)
                assert np.abs(a - b).max() <= 1e-14 * robot.reach


def test_packed_chain_has_the_prismatic_flag_in_its_own_field():
    arm = armkit.load("stanford")   # joint 3 prismatic
    assert arm.prismatic.any()
    F, P = kinematics.packed(arm)
    c, n = arm.chain, arm.n
    assert F.shape == (n + 1, jit.ROW) and P.shape == (2 * n + 2, jit.ROW)
    assert np.array_equal(F[:, jit.AFFINE].reshape(n + 1, 3, 4), c.fixed[:, :3])
    mats = np.concatenate([c.base[None], c.pre, c.post, c.tool[None]])
    assert np.array_equal(P[:, jit.AFFINE].reshape(2 * n + 2, 3, 4), mats[:, :3])
    assert np.array_equal(F[1:, jit.PRISMATIC], arm.prismatic.astype(float)) and F[0, jit.PRISMATIC] == 0.0
    assert np.array_equal(P[1:n + 1, jit.PRISMATIC], arm.prismatic.astype(float))
    assert not P[n + 1:, jit.PRISMATIC].any() and P[0, jit.PRISMATIC] == 0.0
    assert kinematics.packed(arm)[0] is F                          # built once, kept in the robot's cache
    assert not F.flags.writeable and not P.flags.writeable


def test_single_call_kernels_are_dispatchers_with_one_signature():
    armkit.fk(armkit.load("ur5"), np.zeros(6))   # compiles (or loads) fk_one_float64
    assert jit.fk_one_float64 is jit.fk_one      # the public dispatcher, no internal entry point
    assert len(jit.fk_one.signatures) == 1
    with pytest.raises(TypeError):              # any other argument types: refused at once, never compiled
        jit.fk_one_float64(np.zeros((7, jit.ROW), np.float32), np.zeros(6), np.empty((4, 4)))


def test_kernel_cache_that_inlines_another_file_clears_itself(tmp_path, monkeypatch):
    from armkit import _jit_loader

    pkg, cache = tmp_path / "pkg", tmp_path / "cache"
    pkg.mkdir()
    cache.mkdir()
    (pkg / "helpers.py").write_text("A = 1\n")
    monkeypatch.setattr(_jit_loader, "_PKG", pkg)

    class Kernel:   # what Numba's cache=True dispatcher offers: the directory of its cache files
        class _cache:
            _cache_path = str(cache)

    namespace = {"__file__": str(pkg / "kernels.py"), "kernel": Kernel()}

    def files():
        return sorted(p.name for p in cache.iterdir() if p.suffix in (".nbi", ".nbc"))

    def compiled():
        for name in ("kernels.kernel-10.py311.nbi", "kernels.kernel-10.py311.1.nbc", "other.kernel-3.py311.nbi"):
            (cache / name).write_bytes(b"x")

    compiled()
    _jit_loader.forget_stale_cache(namespace, ("helpers.py",))   # no stamp yet: this module's files go
    assert files() == ["other.kernel-3.py311.nbi"]
    compiled()
    _jit_loader.forget_stale_cache(namespace, ("helpers.py",))   # helpers unchanged: the cache stays
    assert len(files()) == 3
    (pkg / "helpers.py").write_text("A = 2\n")
    _jit_loader.forget_stale_cache(namespace, ("helpers.py",))   # helpers edited: compiled anew
    assert files() == ["other.kernel-3.py311.nbi"]


def test_kernel_imported_from_another_file_keeps_its_own_cache(tmp_path, monkeypatch):
    """A module holds kernels of another file (ik/analytic/_jit.py holds kinematics/_jit.py's sine and cosine): the
    stamp goes beside its own kernels only, so two modules of one stem ("_jit") never delete each other's cache
    files nor rewrite each other's stamp on every import (which made every run compile kinematics anew)."""
    from armkit import _jit_loader

    pkg, mine, theirs = tmp_path / "pkg", tmp_path / "mine", tmp_path / "theirs"
    for d in (pkg, mine, theirs):
        d.mkdir()
    (pkg / "helpers.py").write_text("A = 1\n")
    monkeypatch.setattr(_jit_loader, "_PKG", pkg)
    ns_other: dict = {}
    exec(compile("def f():\n    return 1\n", str(pkg / "other" / "_jit.py"), "exec"), ns_other)
    ns_mine: dict = {}
    exec(compile("def g():\n    return 2\n", str(pkg / "_jit.py"), "exec"), ns_mine)

    def kernel(fn, where):
        class Kernel:
            py_func = fn

            class _cache:
                _cache_path = str(where)
        return Kernel()

    (theirs / "_jit.f-1.py311.nbi").write_bytes(b"x")
    (theirs / "_jit.armkit-deps").write_text("their own digest")
    namespace = {"__file__": str(pkg / "_jit.py"), "g": kernel(ns_mine["g"], mine), "f": kernel(ns_other["f"], theirs)}
    _jit_loader.forget_stale_cache(namespace, ("helpers.py",))
    assert (theirs / "_jit.f-1.py311.nbi").exists()
    assert (theirs / "_jit.armkit-deps").read_text() == "their own digest"
    assert (mine / "_jit.armkit-deps").exists()


def test_lm_kernels_cache_is_tied_to_the_kinematics_kernels():
    lm = pytest.importorskip("armkit.ik._jit_lm")
    path = getattr(getattr(lm.lm_serial, "_cache", None), "_cache_path", None)
    if path is None:
        pytest.skip("Numba caching is off")
    import hashlib
    from pathlib import Path

    stamp = Path(path) / "_jit_lm.armkit-deps"
    expected = hashlib.sha1((Path(jit.__file__)).read_bytes()).hexdigest()
    assert stamp.read_text() == expected


@pytest.mark.parametrize("name", ["puma560", "stanford", "planar2", "so101"])
def test_batched_fk_gives_each_configuration_the_bits_of_its_single_call(name):
    """The batch kernel takes ``jit.LANES`` configurations side by side (``_fk_lanes``), in blocks of
    ``jit.BLOCK``: every size around both, angles beyond a turn and beyond the polynomial's range, each row the
    single call's pose to the bit (the same operations, in the same order)."""
    robot = armkit.load(name)
    rng = np.random.default_rng(5)
    kinematics.set_backend("numba")
    try:
        for B in (1, jit.LANES - 1, jit.LANES, jit.LANES + 1, jit.BLOCK - 1, jit.BLOCK + 3, jit.PARALLEL_MIN + 5):
            Q = rng.uniform(-8.0, 8.0, (B, robot.n))
            Q[::3] *= 1e5
            if robot.prismatic.any():
                Q[:, robot.prismatic] = rng.uniform(0.0, 0.5, (B, int(robot.prismatic.sum())))
            batch = armkit.fk(robot, Q)
            assert all(np.array_equal(batch[i], armkit.fk(robot, Q[i])) for i in range(B))
    finally:
        kinematics.set_backend("auto")
