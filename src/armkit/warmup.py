"""The warm-up: compile (or load from the cache) every Numba kernel armkit uses.

The top floor of armkit (docs/architecture.md): it exercises the public functions (``fk``,
``jacobian``, ``ik``, ``ik_all`` ...) so that each kernel is compiled with the argument types
they pass. :func:`warmup` does it in the calling process (``armkit warmup``); the back end
(:mod:`armkit._jit_loader`, the ground floor) starts :func:`_worker_main` in a new process
when the first kinematics call finds the kernels not cached yet.
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Callable, Optional

import numpy as np

from . import _jit_loader
from .ik import ik, ik_all
from .ik.api import closed_form_family
from .kinematics import fk, fk_frames, jacobian
from .model import Joint, Robot, load

__all__ = ["warmup", "Warmup"]


@dataclass(frozen=True)
class Warmup:
    """What :func:`warmup` did: ``seconds`` it took, the ``cache`` directory (None: not cached),
    whether anything had to be ``compiled`` (False: everything was cached already), and whether kernels were
    ``restored``: copied from the kernel store, compiled by another install of the same sources
    (:mod:`armkit._kernel_store`)."""
    seconds: float
    cache: Optional[Path]
    compiled: bool
    restored: bool = False


def _exercise_serial() -> None:
    """Call every kernel the public functions use, with the argument types they pass, on small inputs
    (below the thresholds of the multi-threaded kernels)."""
    _exercise_arms()
    _exercise_families()
    _exercise_so101()


def _exercise_later() -> None:
    """The one-thread kernels of :func:`_exercise_searches`: after the first marker, before the multi-threaded
    twins. Every call of the background mode waits for that marker; the searches (about a minute cold) serve only
    arms whose class has no closed form, which compile what they need on first use until this is done."""
    with _jit_loader.serial_only():
        _exercise_searches()


def _exercise_arms() -> None:
    """The first part of :func:`_exercise_serial`: FK, Jacobians, the closed forms, LM and the rigidity check on
    the bundled arms. The test suite compiles the parts in parallel processes (tests/conftest.py)."""
    for name in ("puma560", "ur5", "panda", "fighter", "planar2", "planar3"):
        arm = load(name)
        q = arm.random_q(rng=0)
        T = fk(arm, q)
        jacobian(arm, q)
        jacobian(arm, q, frame="tool")
        fk_frames(arm, q)
        Q = arm.random_q(16, rng=1)
        for batch in (Q, Q.copy()):
            fk(arm, batch)
            jacobian(arm, batch)
            fk_frames(arm, batch)
            batch.setflags(write=False)  # the second round: read-only input
        TT = fk(arm, arm.random_q(64, rng=2))
        pose = arm.n >= 6 or name == "planar3"
        one, many = (T, TT) if pose else (T[:3, 3], TT[:, :3, 3])
        family = closed_form_family(arm)
        if family is not None:
            ik(arm, one)
            ik(arm, many[:16])
            ik(arm, many)
            ik_all(arm, one)
            ik_all(arm, many[:16])
        far = np.array(one)
        if pose:
            far[:3, 3] *= 4.0
        else:
            far *= 4.0
        for target in (one, many[:4], many[:16], far):  # single, < 8 and >= 8 targets, unreachable
            ik(arm, target, method="lm", restarts=2)
        if name in ("planar3", "ur5"):                   # CCD's kernel (ik/_ccd_jit.py): one signature
            for target in (one, many[:16]):
                ik(arm, target, method="ccd", restarts=1, max_iterations=20)
    poses = np.tile(np.eye(4), (2, 1, 1))   # check_transform's pass over big batches
    _jit_loader.module("kinematics._jit").rigidity(poses, np.empty(2), np.empty(2), np.empty(2, dtype=bool))


def _exercise_families() -> None:
    """The second part of :func:`_exercise_serial`: the geometric solvers, their one-call kernel and the 7-joint
    sweep."""
    from .ik.geometric import solvers          # the geometric family's kernels (subproblems, 6R solvers): Numba
    from .ik.geometric.poe import poe

    for name, solve in (("puma560", solvers.spherical_wrist), ("ur5", solvers.three_parallel_two_intersecting),
                        ("ur5", solvers.three_parallel), ("stanford", solvers.spherical_wrist)):
        arm = load(name)
        T = fk(arm, arm.random_q(rng=3))
        solve(poe(arm), T[:3, :3], T[:3, 3])
    stanford = load("stanford")                # the geometric family's one-call kernel (ik/geometric/one_call.py)
    T = fk(stanford, stanford.random_q(rng=4))
    ik(stanford, T)
    ik_all(stanford, T)
    ik_all(stanford, fk(stanford, stanford.random_q(4, rng=5)))   # a few targets: one call each
    for name in ("puma560", "ur5"):            # a file that rounds its twists: its branches named by the ideal DH
        exact = load(name)                     # twin's family (_single.name_rows, each of its two kernels)
        rounded = Robot([replace(j, alpha=j.alpha + np.copysign(3.7e-6, j.alpha) if j.alpha else 0.0)
                         for j in exact.joints], name=f"{name}, rounded", base=exact.base, tool=exact.tool)
        pose = fk(rounded, rounded.random_q(rng=6))
        ik_all(rounded, pose).branch           # noqa: B018 (the names made)
        pose[:3, 3] *= 2.5                     # out of reach: padded branches, a name given twice (settle_rows)
        ik_all(rounded, pose).branch           # noqa: B018
    iiwa = load("iiwa14")                      # the sweep of 7-joint arms (solvers._sweep, ik.geometric.locked)
    ik_all(iiwa, fk(iiwa, iiwa.random_q(rng=3)))
    for a1 in (0.3, 0.0):                      # any other 3R arm (ik.analytic.geometric.Geometric3R): SP5, and SP3
        arm = Robot([Joint(d=0.1, a=a1, alpha=0.7), Joint(d=0.2, a=0.5, alpha=-1.1),     # + SP2 where axes 1, 2 meet
                     Joint(a=0.4, alpha=0.4)], name="three")
        ik_all(arm, fk(arm, arm.random_q(rng=2))[:3, 3])


def _exercise_searches() -> None:
    """The searches of the geometric family on two random 6R arms: the general 6R's 2-D search, and a 1-D search
    (two axes meet) one target at a time and in a batch."""
    general = _chain(7)                        # a general 6R: the 2-D search (ik/geometric/search2d.py)
    T = fk(general, general.random_q(rng=2))
    ik_all(general, T)
    ik(general, T)
    pair = _chain(7, meet=1)                   # axes 1 and 2 meet: a 1-D search, solved in Python and then one
    T = fk(pair, pair.random_q(24, rng=1))     # call (_single.post); a batch (> SMALL_BATCH): ik/geometric/batched.py
    ik(pair, T[0])
    ik_all(pair, T)


def _chain(seed: int, meet: int | None = None) -> Robot:
    """A 6R arm of random axes and points (seeded; no two axes meet or are parallel), or with the offset
    ``P[meet]`` zero, so that the axes of joints ``meet`` and ``meet + 1`` (counted from 1) meet."""
    g = np.random.default_rng(seed)
    H = g.normal(size=(6, 3))
    H /= np.linalg.norm(H, axis=1, keepdims=True)
    P = g.normal(size=(7, 3)) * 0.4
    if meet is not None:
        P[meet] = 0.0
    joints = []
    for k in range(6):
        origin = np.eye(4)
        origin[:3, 3] = P[k]
        joints.append(Joint(origin=tuple(map(tuple, origin.tolist())), axis=tuple(H[k].tolist()), lower=-np.pi,
                            upper=np.pi, name=f"j{k + 1}"))
    tool = np.eye(4)
    tool[:3, 3] = P[6]
    return Robot(joints, convention="urdf", name="chain", tool=tool)


def _exercise_so101() -> None:
    """The SO-101's kernels (ik/analytic/_yaw_pitch3_jit.py, _yaw_pitch3_teleop.py): every IK mode of
    ``armkit.ik`` (position, ``pitch=``, ``direction=``; one target, a few, a batch; beyond the reach) and each
    stage of the LeRobot class's ``inverse_kinematics`` (the pose held, a step, a target out of reach). Without
    them the first ``armkit.ik(so101, xyz)`` after a warm-up compiled for 49 s."""
    from .ik.analytic.yaw_pitch3 import position_ik
    from .lerobot import RobotKinematics

    kin = RobotKinematics("so101")
    arm = kin.robot
    q = arm.random_q(24, rng=6)
    T = fk(arm, q)
    p, z = T[:, :3, 3], T[:, :3, 2]
    for k in (None, 4, 24):                    # one target, a few (one call each), a batch
        tp, tz = (p[0], z[0]) if k is None else (p[:k], z[:k])
        ik(arm, tp)
        ik(arm, tp, pitch=-0.5)
        ik_all(arm, tp, pitch=-0.5)
        ik(arm, tp, direction=tz)
    ik(arm, 3.0 * p[0])
    ik(arm, 3.0 * p[0], pitch=0.0)
    position_ik(arm, p[0], arm.random_q(rng=1))
    position_ik(arm, p[:4], arm.random_q(4, rng=1))
    current = np.append(np.degrees(q[0]), 0.0)
    for step in (0.0, 0.01, 0.3):              # held, a step, beyond the reach
        X = kin.forward_kinematics(current)
        X[:3, 3] += step
        for w in (0.01, 0.0):
            kin.inverse_kinematics(current, X, orientation_weight=w)


def _exercise_parallel() -> None:
    """Compile the multi-threaded twin of every serial kernel for the signatures the serial one got."""
    _parallel_core()
    _parallel_families()


def _parallel_core() -> None:
    """The multi-threaded twins of the kernels :func:`_exercise_arms` compiles (FK, the IK check, the closed forms,
    LM, CCD, the collision checks of the fighter's surroundings)."""
    for name in ("kinematics._jit", "ik._jit_verify", "ik.analytic._jit", "ik.analytic._single", "ik._jit_lm",
                 "ik._ccd_jit"):
        for serial, parallel in _jit_loader.module(name).parallel_twins():
            for sig in list(serial.signatures):
                parallel.compile(sig)
    from .collision import _jit as collision_jit

    for serial, parallel in collision_jit.parallel_twins():
        for sig in list(serial.signatures):
            parallel.compile(sig)


def _parallel_families() -> None:
    """The multi-threaded twin of the geometric family's batch layout (ik/geometric/batched.py), for the signatures
    its serial kernel got in this process (:func:`_exercise_searches`' batch; none in the tests' warm-up part)."""
    from .ik.geometric import batched

    K = batched.kernels()
    if K is not None:
        for sig in list(K.serial.signatures):
            K.parallel.compile(sig)


def _run_serial_phase() -> None:
    with _jit_loader.serial_only():
        _exercise_serial()


def warmup(*, parallel: bool = True, say: Optional[Callable[[], None]] = None) -> Warmup:
    """Compile (or load from the cache) every Numba kernel armkit uses, now, in this process.

    For images and CI: run it (or ``armkit warmup``) once after installing, and later
    processes compile nothing. If a warm-up process is already at work, waits for it first.
    Afterwards the compiled kernels serve this process (back end ``"auto"``).

    Parameters
    ----------
    parallel : bool
        Also the multi-threaded kernels of big batches (about half of the time).
    say : callable, optional
        Called (no arguments) when the compiling starts, to tell the user in their language (``armkit warmup``
        does); None: the English note on stderr ("compiling armkit's kernels once, about 45 s in all").

    Returns
    -------
    Warmup
    """
    t0 = time.perf_counter()
    _jit_loader.install_cache_fallback()
    restored = _jit_loader.restore_kernels()
    first, second = _jit_loader.marker("ready"), _jit_loader.marker("parallel")

    def done() -> bool:
        return first is not None and first.exists() and (not parallel or (second is not None and second.exists()))

    if first is not None and not done():
        while _jit_loader.lock_alive() and not done():  # a warm-up process is at work: let it finish
            time.sleep(0.2)
    compiled = not done()
    if compiled:
        if say is None:
            _jit_loader.say_compiling(hint=False)
        else:
            say()
    with _jit_loader.compiling_here(parallel=True, backend="numba"):
        if compiled:
            if first is None or not first.exists():
                _run_serial_phase()
                if first is not None:
                    first.touch()
                    _jit_loader.forget_other_builds()
            _exercise_later()
            if parallel:
                _exercise_parallel()
                if second is not None:
                    second.touch()
    if compiled and done():
        _jit_loader.save_kernels()   # for the next install of the same sources on this machine
    return Warmup(seconds=time.perf_counter() - t0, cache=_jit_loader.cache_dir(), compiled=compiled,
                  restored=restored)


def _worker_main(parent: str) -> int:
    """The warm-up process: the one-thread kernels first (first marker), then the multi-threaded ones."""
    t0 = time.perf_counter()
    try:
        with _jit_loader.compiling_here(parallel=False):
            if hasattr(os, "nice"):
                os.nice(10)  # the caller's own work comes first on a busy machine
            _jit_loader.install_cache_fallback()
            first, second = _jit_loader.marker("ready"), _jit_loader.marker("parallel")
            if first is None or second is None:
                print("Numba's cache is off: nothing to warm up", flush=True)
                return 1
            _run_serial_phase()
            first.touch()
            _jit_loader.forget_other_builds()
            print(f"one-thread kernels compiled in {time.perf_counter() - t0:.1f} s (for process {parent})",
                  flush=True)
            _exercise_later()
            _exercise_parallel()
            second.touch()
            _jit_loader.save_kernels()
            print(f"all kernels compiled in {time.perf_counter() - t0:.1f} s", flush=True)
            return 0
    finally:
        _jit_loader.release_lock()
