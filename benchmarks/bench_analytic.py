"""Every branch, armkit against EAIK, on the same targets in the same run: missing branches and time.

Run: ``.venv-bench/bin/python benchmarks/bench_analytic.py [--targets 1000] [--threads 2]`` (the
``bench`` extra holds EAIK). For each arm, random configurations (seeded) give the targets; both
solvers get the same 4x4 poses. Reported per arm:

* **missing**: branches EAIK finds (FK-verified at 1e-9 of the arm's size) that armkit's
  ``ik_all`` does not (after wrapping angles to (-pi, pi]), and the reverse; limits off on both;
* **armkit fails FK**: branches armkit calls successful whose FK misses the target by more than
  1e-9 (must be 0); **EAIK fails FK**: EAIK's answers it does not flag least-squares that miss so
  (0 on every arm here: the rounded files, twists 3.7e-6 off 90 deg, keep their axes meeting and parallel, and
  EAIK solves them on their own axes, as armkit's geometric family does since 2026-12-07);
* times: one target per call (all branches; CPU time of the thread, which runs both), EAIK ``IK``
  against armkit's raw subproblem solver and armkit's public ``ik_all`` / ``ik`` (which also wrap,
  verify, polish and sort every branch; the sentences of failed branches are made when read), with the
  results dropped at once and, in two more columns, kept in a list (armkit's call then makes new buffers); batched
  (wall clock), EAIK ``IK_batched`` with ``--threads`` against armkit ``ik_all`` on
  the whole batch. The ratio is armkit / EAIK (below 1: armkit faster).

Then (also alone, without EAIK: ``--single-only``) one target per call on the bundled closed-form arms:
``ik_all`` and ``ik`` by the one compiled call against the batched path it replaced (issue 19, item 5).

Then (also alone, without EAIK: ``--searches-only``) what EAIK refuses: the sweep of the Panda and
the iiwa (32 values of the lockable joint), one joint held (``fixed=``), and the 1-D search of
random '6R-two-intersecting' arms, median milliseconds per target.

Then (also alone: ``--random-only``) random arms of each closed-form 6R class, one target per call, against
EAIK where installed: the classes without a DH pattern are solved by the geometric family.

Then (also alone: ``--small-only``, ``--big-only``) a few targets and many in one call: the rows driver against
the batched path (and EAIK's batched call).

Then (also alone: ``--names-only``) the branch names read on arms a DH family names (files that round their
twists, the Kinova's URDF): the compiled naming against the NumPy steps it replaced.

Then (also alone: ``--scara-only``) the SCARA (cobra600), which EAIK does not take: a batch of poses in one call,
its whole-batch form against the target-by-target loop, and LM.

EAIK takes a chain as axes ``H`` and offsets ``P`` with the tool frame's rotation equal to the
last joint frame's; armkit's :func:`armkit.ik.geometric.poe.poe` gives the same form plus
``R_nT``, so targets are handed to EAIK as ``T · diag(R_nT^T, 1)``.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

os.environ.setdefault("ARMKIT_JIT", "wait")

import armkit  # noqa: E402
from armkit.ik.analytic import closed_form  # noqa: E402
from armkit.ik.geometric import solvers as G  # noqa: E402
from armkit.ik.geometric.poe import poe  # noqa: E402

ERD = Path(sys.prefix) / "lib" / f"python{sys.version_info[0]}.{sys.version_info[1]}" / "site-packages" / \
    "cmeel.prefix" / "share" / "example-robot-data" / "robots"
ARMS = {"ur5": ("ur5", None), "puma560": ("puma560", None), "stanford": ("stanford", None),
        "ur5, axis 1 reversed": ("ur5", "flip"), "puma560, axis 1 reversed": ("puma560", "flip"),
        "kinova j2s6s200": (str(ERD / "kinova_description/robots/kinova.urdf"), "j2s6s200_end_effector"),
        "kinova j2s6s200, DH table": (str(ERD / "kinova_description/robots/kinova.urdf"), "dh:j2s6s200_end_effector"),
        "ur5 (URDF)": (str(ERD / "ur_description/urdf/ur5_robot.urdf"), "tool0"),
        "puma560, rounded file": ("puma560", "round"), "ur5, rounded file": ("ur5", "round")}


def _wrap(a: np.ndarray) -> np.ndarray:
    return (a + np.pi) % (2 * np.pi) - np.pi


def _flipped(robot):
    """The same arm with joint 1's axis reversed (same geometry, q1 -> -q1; :func:`armkit.model.axes.with_axes_reversed`):
    its DH twin has a twist one ulp off -pi/2 (round-off, so still an exact arm: the UR family answers it)."""
    from armkit.model.axes import with_axes_reversed

    return with_axes_reversed(robot)


def _rounded(robot):
    """The arm of a file that rounds its twists (``rpy="1.5708"``: 3.7e-6 off 90 deg): its axes still meet and lie
    parallel where the ideal arm's do, so the geometric family solves its own axes, naming the branches as the DH
    family of its ideal arm does (before 2026-12-07, third session: that family on the ideal arm, every branch
    touched up on the true one)."""
    from dataclasses import replace

    return armkit.Robot([replace(j, alpha=j.alpha + np.copysign(3.7e-6, j.alpha) if j.alpha else 0.0)
                         for j in robot.joints], name=f"{robot.name}, rounded", base=robot.base, tool=robot.tool)


def _arm(name: str, tip: str | None):
    """The arm of an :data:`ARMS` entry: ``tip`` "flip" (:func:`_flipped`), "round" (:func:`_rounded`), "dh:LINK"
    (:func:`_dh_table` of the URDF's chain to LINK), a URDF's tip link, or None."""
    if tip == "flip":
        return _flipped(armkit.load(name))
    if tip == "round":
        return _rounded(armkit.load(name))
    if tip and tip.startswith("dh:"):
        return _dh_table(armkit.load(name, tip=tip[3:]))
    return armkit.load(name, tip=tip) if tip else armkit.load(name)


def _dh_table(robot):
    """The arm as a standard-DH table: the DH twin of its URDF with the file's rounded twists (the Kinova's: 4.9e-12
    off 90 deg) set to multiples of 90 deg, as a DH table gives them (the Kinova's alpha_2 = 180 deg):
    an exact arm for the DH families, where the URDF's is the ideal arm of a file (the geometric family's)."""
    from armkit.ik.analytic._common import standard_form

    return standard_form(robot).as_robot(robot, f"{robot.name}, DH table")


def _best(fn, repeat: int) -> float:
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def _eaik_robot(form):
    from eaik.IK_HP import HPRobot

    return HPRobot(np.ascontiguousarray(form.H), np.ascontiguousarray(form.P))   # (n, 3) and (n + 1, 3)


def _compare(robot, form, T: np.ndarray, eaik) -> dict:
    """Branch sets: EAIK's verified solutions against armkit's successful branches."""
    scale = max(1.0, robot.reach)
    res = armkit.ik_all(robot, T, enforce_limits=False)
    Tfix = T.copy()
    Tfix[:, :3, :3] = T[:, :3, :3] @ form.R_nT.T
    missing = extra = bad = eaik_total = eaik_bad = 0
    for i in range(len(T)):
        sol = eaik.IK(Tfix[i])
        Q = np.asarray(sol.Q).reshape(-1, robot.n)
        ls = np.asarray(sol.is_LS).reshape(-1).astype(bool)
        if len(Q):
            back = armkit.fk(robot, Q)
            good = ~ls & (np.abs(back - T[i]).max(axis=(1, 2)) <= 1e-9 * scale)
            eaik_bad += int((~ls & ~good).sum())   # answers it calls exact that miss the target
            Q = Q[good]
        ours = res.q[i][res.success[i]]
        if len(ours):
            err = np.abs(armkit.fk(robot, ours) - T[i]).max(axis=(1, 2))
            bad += int((err > 1e-9 * scale).sum())
        eaik_total += len(Q)
        if len(Q) and len(ours):
            d = np.abs(_wrap(Q[:, None] - ours[None])).max(axis=-1)
            missing += int((d.min(axis=1) > 1e-6).sum())
            extra += int((d.min(axis=0) > 1e-6).sum())
        else:
            missing += len(Q)
            extra += len(ours)
    return {"eaik branches": eaik_total, "armkit branches": int(res.success.sum()), "missing": missing,
            "extra": extra, "armkit fails FK": bad, "eaik fails FK": eaik_bad}


def _median(fn, items) -> float:
    """Median seconds of ``fn(item)`` over ``items`` (one call each)."""
    ts = []
    for it in items:
        t0 = time.perf_counter()
        fn(it)
        ts.append(time.perf_counter() - t0)
    return float(np.median(ts))


def _two_intersecting_arm(g: np.random.Generator):
    """A random 6R chain whose only relation is axes 5 and 6 meeting (the 1-D search's class)."""
    from armkit.ik.geometric.poe import POE

    H = g.normal(size=(6, 3))
    H /= np.linalg.norm(H, axis=1, keepdims=True)
    pts = g.normal(size=(6, 3)) * 0.5
    c = g.normal(size=3) * 0.5
    pts[4], pts[5] = c + g.uniform(-0.5, 0.5) * H[4], c + g.uniform(-0.5, 0.5) * H[5]
    tool = pts[5] + g.normal(size=3) * 0.3
    Q, Rr = np.linalg.qr(g.normal(size=(3, 3)))
    Q = Q * np.sign(np.diag(Rr))
    Q = Q if np.linalg.det(Q) > 0 else -Q
    return POE(H, np.vstack([pts[0], np.diff(pts, axis=0), tool - pts[5]]), Q, np.zeros(6, dtype=bool))


def searches(targets: int) -> None:
    """Times of what EAIK refuses: the sweep of 7-joint arms, held joints, and the 1-D search (median ms per
    target, one target per call, the public ``ik_all`` with its FK checks for the first two)."""
    print(f"\nsearches and sweeps (EAIK refuses these arms): median ms per target, {targets} targets, one per call\n")
    print("| arm | call | ms per target | successful branches per target |")
    print("|---|---|---|---|")
    for name, joint in (("panda", "panda_joint6"), ("iiwa14", "A3")):
        robot = armkit.load(name)
        rng = np.random.default_rng(7)
        T = armkit.fk(robot, rng.uniform(0.9 * robot.lower, 0.9 * robot.upper, (targets, robot.n)))
        armkit.ik_all(robot, T[0])
        armkit.ik_all(robot, T[0], fixed={joint: 0.3})
        for call, fn in (("ik_all sweep (32 values)", lambda t: armkit.ik_all(robot, t)),
                         (f"ik_all fixed={{{joint!r}: 0.3}}", lambda t: armkit.ik_all(robot, t, fixed={joint: 0.3}))):
            ms = _median(fn, T) * 1e3
            ok = np.mean([np.sum(fn(t).success) for t in T[:20]])
            print(f"| {name} | {call} | {ms:.2f} | {ok:.1f} |")
    g = np.random.default_rng(11)
    times, counts = [], []
    for _ in range(targets):
        form = _two_intersecting_arm(g)
        R, p = form.fk(g.uniform(-np.pi, np.pi, 6))
        G.two_intersecting(form, R, p)      # the arm's preparation (alignment) once
        t0 = time.perf_counter()
        sol = G.two_intersecting(form, R, p)
        times.append(time.perf_counter() - t0)
        counts.append(len(sol.q))
    print(f"| random '6R-two-intersecting' arms | 1-D search (solvers.two_intersecting, {G.SEARCH_N} samples) | "
          f"{np.median(times) * 1e3:.2f} | {np.mean(counts):.1f} |")
    times, counts = [], []
    for _ in range(targets):
        form = _two_intersecting_arm(g)
        H = np.array(form.H)
        H[2] = H[1]                          # axes 2 ∥ 3; no axes meet (random points)
        pts = g.normal(size=(6, 3)) * 0.5
        form = type(form)(H, np.vstack([pts[0], np.diff(pts, axis=0), g.normal(size=3) * 0.3]), form.R_nT,
                          form.prismatic)
        R, p = form.fk(g.uniform(-np.pi, np.pi, 6))
        G.two_parallel(form, R, p)
        t0 = time.perf_counter()
        sol = G.two_parallel(form, R, p)
        times.append(time.perf_counter() - t0)
        counts.append(len(sol.q))
    print(f"| random '6R-two-parallel' arms | 1-D search (solvers.two_parallel, 240 samples) | "
          f"{np.median(times) * 1e3:.2f} | {np.mean(counts):.1f} |")
    print(f"\nload average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")


SINGLE_ARMS = ("ur5", "puma560", "fighter", "planar2", "planar3", "stanford", "ur5, axis 1 reversed")


def _read_eaik(sol) -> tuple:
    return sol.Q, sol.is_LS


def _read_armkit(res) -> tuple:
    return res.q, res.success


def _cpu_best(fn, items, repeat: int, keep: bool = False, clock=time.thread_time) -> float:
    """Least CPU seconds of this thread per item over ``repeat`` rounds (``time.thread_time``: on a shared,
    loaded machine the wall clock also counts the other processes' turns). ``keep``: every result kept in a list
    until the round ends, as ``[ik_all(arm, T) for T in poses]`` keeps them (a call then finds no kept buffers
    free: armkit's single call makes new ones). ``clock``: ``time.process_time`` for calls that work on other
    threads (EAIK's ``IK_batched`` runs on threads of its own even when given one, so the calling thread's time
    leaves its work out)."""
    return _cpu_best_each([(fn, items)], repeat, keep, clock)[0]


def _cpu_best_each(runs, repeat: int, keep: bool = False, clock=time.thread_time) -> list[float]:
    """:func:`_cpu_best` of each ``(fn, items)`` of ``runs``, the rounds taken in turn (one of each, then again): a
    peer and armkit see the same spells of this shared machine, so a slow spell cannot fall on one side only
    (before 2026-12-07, seventh session: all of one side's rounds, then the other's). For calls that run on the
    calling thread only; the threaded batches keep their rounds apart (see :func:`main`)."""
    best = [np.inf] * len(runs)
    for _ in range(repeat):
        for i, (fn, items) in enumerate(runs):
            kept: list = []
            add = kept.append
            t0 = clock()
            if keep:
                for it in items:
                    add(fn(it))
            else:
                for it in items:
                    fn(it)
            best[i] = min(best[i], (clock() - t0) / len(items))
            del kept
    return best


def single_calls(targets: int, repeat: int) -> None:
    """One target per call: ``ik_all`` and ``ik`` by the one compiled call (issue 19, item 5) and by the
    batched path it replaces (``armkit.ik.api.ONE_CALL = False``), µs per call (CPU time of the thread and
    wall clock), and how many calls the one-call path answered itself. The one-call path makes the sentences
    of failed branches only when ``message`` is read; the last column reads it (CPU time)."""
    import importlib

    from armkit.ik.analytic import single_call

    api = importlib.import_module("armkit.ik.api")
    print(f"\nsingle calls: µs per call, {targets} targets (FK of random joint values), best of {repeat}; "
          "CPU time of the thread (wall clock in brackets)\n")
    print("| arm | family | one call answered | ik_all one call | ik_all batched path | ik one call | "
          "ik batched path | ik_all one call, messages read |")
    print("|---|---|---|---|---|---|---|---|")
    for label in SINGLE_ARMS:
        name, tip = ARMS.get(label, (label, None))
        robot = _arm(name, tip)
        cf = closed_form(robot)
        rng = np.random.default_rng(7)
        lo = np.where(np.isfinite(robot.lower), robot.lower, -np.pi)
        hi = np.where(np.isfinite(robot.upper), robot.upper, np.pi)
        T = armkit.fk(robot, rng.uniform(lo, hi, (targets, robot.n)))
        items = list(T[:, :3, 3].copy() if not cf.pose_only else T)
        answered = sum(single_call(robot, cf, t, None, None) is not None for t in items)
        cells = []
        for fn in (armkit.ik_all, armkit.ik):
            for one in (True, False):
                api.ONE_CALL = one
                fn(robot, items[0])
                cpu = _cpu_best(lambda t: fn(robot, t), items, repeat)
                wall = _best(lambda: [fn(robot, t) for t in items], repeat) / len(items)
                cells.append(f"{cpu * 1e6:.1f} ({wall * 1e6:.1f})")
            api.ONE_CALL = True
        # the one-call path makes failed branches' sentences when ``message`` is read: the cost when it is
        read = _cpu_best(lambda t: armkit.ik_all(robot, t).message, items, repeat)
        cells.append(f"{read * 1e6:.1f}")
        print(f"| {label} | {cf.family} | {answered}/{len(items)} | " + " | ".join(cells) + " |", flush=True)
    print(f"\nload average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")


def small_batches(repeat: int) -> None:
    """A few targets in one call (``armkit.ik_all`` / ``armkit.ik`` of ``(B, 4, 4)``): any number
    (``armkit.ik.analytic.ROWS``; in pieces of ``POOL_ROWS`` above that) take the one-call kernel,
    each target into its row of one set of buffers by one compiled driver (threaded from ``ROWS_PARALLEL``
    targets);
    both columns of each size are timed (``api.ONE_CALL`` off: the batched path for every size), µs per call, CPU
    time of the process (every thread's: a threaded call's work on both), and EAIK's batched call of the same
    poses on one thread where EAIK is installed. Until 2026-12-07 (seventh session) this table took the calling
    thread's time, which left out all of EAIK's work: ``IK_batched`` solves on a thread of its own even when
    given one, and the calling thread only turns its answers into Python objects (the Puma's 1,024 targets: 0.8
    µs a target counted against 4.1 of wall clock and 4.2 of the process's time)."""
    import importlib

    from armkit.ik.analytic import POOL_ROWS

    CPU = time.process_time
    api = importlib.import_module("armkit.ik.api")
    try:
        import eaik  # noqa: F401
    except ImportError:
        eaik = None
    sizes = (1, 2, 8, 16, POOL_ROWS, POOL_ROWS + 1, 4 * POOL_ROWS)
    print(f"\nsmall batches: µs per call of B targets (by the rows driver, in pieces of {POOL_ROWS} above that), "
          f"best of {repeat}; CPU time of the process (every thread)\n")
    print("| arm | B | ik_all | ik_all batched path | ik | ik batched path | EAIK IK_batched (1 thread) |")
    print("|---|---|---|---|---|---|---|")
    for label in ("ur5", "puma560", "ur5, axis 1 reversed"):
        name, tip = ARMS.get(label, (label, None))
        robot = _arm(name, tip)
        rng = np.random.default_rng(11)
        T = armkit.fk(robot, rng.uniform(-np.pi, np.pi, (40_000, robot.n)))
        e = None
        if eaik is not None:
            form = poe(robot)
            e = _eaik_robot(form)
            Tfix = T.copy()
            Tfix[:, :3, :3] = T[:, :3, :3] @ form.R_nT.T
        for B in sizes:
            k = max(2, min(40, len(T) // B))   # batches of B targets (40, fewer of the biggest)
            batches = list(T[:k * B].reshape(k, B, 4, 4))
            cells = []
            for fn in (armkit.ik_all, armkit.ik):
                for one in (True, False):
                    api.ONE_CALL = one
                    fn(robot, batches[0])
                    cells.append(f"{_cpu_best(lambda t: fn(robot, t), batches, repeat, clock=CPU) * 1e6:.0f}")
                api.ONE_CALL = True
            if e is not None:
                eb = list(Tfix[:k * B].reshape(k, B, 4, 4))
                cells.append(f"{_cpu_best(lambda t: e.IK_batched(t, 1), eb, repeat, clock=CPU) * 1e6:.0f}")
            else:
                cells.append("-")
            print(f"| {label} | {B} | " + " | ".join(cells) + " |", flush=True)
    print(f"\nload average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")


def big_batches(targets: int, threads: int, repeat: int) -> None:
    """Many targets in one call (``armkit.ik_all`` / ``armkit.ik`` of ``(B, 4, 4)``, default options, wall clock,
    best of ``repeat``): the rows driver (in pieces of ``armkit.ik.analytic.POOL_ROWS`` rows) against the batched
    path (``api.ONE_CALL`` off), and EAIK's
    ``IK_batched`` on ``threads`` threads where installed (limits off there, on for armkit), µs per target."""
    import importlib

    api = importlib.import_module("armkit.ik.api")
    try:
        import eaik  # noqa: F401
    except ImportError:
        eaik = None
    print(f"\nbig batches: {targets:,} targets in one call, µs per target, wall clock, best of {repeat} "
          f"(ratio to the batched path; EAIK on {threads} threads)\n")
    print("| arm | ik_all | ik_all batched path | ik | ik batched path | EAIK IK_batched |")
    print("|---|---|---|---|---|---|")
    for label in ("ur5", "puma560", "kinova j2s6s200", "puma560, rounded file"):
        name, tip = ARMS[label]
        if name.endswith(".urdf") and not Path(name).is_file():
            continue
        robot = _arm(name, tip)
        T = armkit.fk(robot, np.random.default_rng(13).uniform(-np.pi, np.pi, (targets, robot.n)))
        cells = []
        for fn in (armkit.ik_all, armkit.ik):
            times = []
            for one in (True, False):
                api.ONE_CALL = one
                try:
                    fn(robot, T)
                    times.append(_best(lambda: fn(robot, T), repeat) / targets)
                finally:
                    api.ONE_CALL = True
            cells += [f"{times[0] * 1e6:.2f} ({times[0] / times[1]:.2g}x)", f"{times[1] * 1e6:.2f}"]
        if eaik is not None:
            form = poe(robot)
            e = _eaik_robot(form)
            Tfix = T.copy()
            Tfix[:, :3, :3] = T[:, :3, :3] @ form.R_nT.T
            e.IK_batched(Tfix, threads)
            cells.append(f"{_best(lambda: e.IK_batched(Tfix, threads), repeat) / targets * 1e6:.2f}")
        else:
            cells.append("-")
        print(f"| {label} | " + " | ".join(cells) + " |", flush=True)
    print(f"\nload average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")


def names_read(repeat: int) -> None:
    """The branch names of arms the geometric family solves and a DH family names (files that round their twists,
    the Kinova's URDF): ``ik_all`` and ``ik`` of one target with ``branch`` read (CPU time of the thread, µs a
    call), and of 1,000 targets in one call (wall clock, µs a target), by the compiled naming
    (``_single.name_rows``, the one-call kernel's branches for ``ik``) against the NumPy steps it replaced
    (``geometric._named_compiled`` and ``geometric._kernel_branches`` set to answer None), in the same run."""
    import importlib

    geometric = importlib.import_module("armkit.ik.analytic.geometric")
    named, kernel = geometric._named_compiled, geometric._kernel_branches
    print(f"\nbranch names read: µs a call of one target (CPU time, best of {repeat}) and µs a target of 1,000 in "
          "one call (wall clock); compiled naming / the NumPy steps\n")
    print("| arm | ik_all | ik_all, branch read | ik | ik, branch read | 1,000 ik_all, branch read |")
    print("|---|---|---|---|---|---|")
    for label in ("puma560, rounded file", "ur5, rounded file", "kinova j2s6s200"):
        name, tip = ARMS[label]
        if name.endswith(".urdf") and not Path(name).is_file():
            continue
        robot = _arm(name, tip)
        T = armkit.fk(robot, np.random.default_rng(17).uniform(-np.pi, np.pi, (1000, robot.n)))
        singles = list(T[:200])
        cells = [f"{_cpu_best(lambda t: armkit.ik_all(robot, t), singles, repeat) * 1e6:.1f}", "", "", "", ""]
        times: list = [[], [], []]
        for steps in (False, True):
            if steps:
                geometric._named_compiled = lambda *a: None
                geometric._kernel_branches = lambda *a: None
            try:
                armkit.ik_all(robot, T[:3]).branch
                armkit.ik(robot, T[:3]).branch
                times[0].append(_cpu_best(lambda t: armkit.ik_all(robot, t).branch, singles, repeat))
                times[1].append(_cpu_best(lambda t: armkit.ik(robot, t).branch, singles, repeat))
                times[2].append(_best(lambda: armkit.ik_all(robot, T).branch, repeat) / len(T))
            finally:
                geometric._named_compiled, geometric._kernel_branches = named, kernel
        cells[1] = f"{times[0][0] * 1e6:.1f} / {times[0][1] * 1e6:.1f}"
        cells[2] = f"{_cpu_best(lambda t: armkit.ik(robot, t), singles, repeat) * 1e6:.1f}"
        cells[3] = f"{times[1][0] * 1e6:.1f} / {times[1][1] * 1e6:.1f}"
        cells[4] = f"{times[2][0] * 1e6:.1f} / {times[2][1] * 1e6:.1f}"
        print(f"| {label} | " + " | ".join(cells) + " |", flush=True)


def scara_batches(repeat: int) -> None:
    """The SCARA (cobra600, ``geometric-scara``; EAIK takes revolute joints only): ``ik_all`` and ``ik`` of a batch
    of poses in one call, its whole-batch form against the target-by-target loop it replaced (forced by raising
    :data:`armkit.ik.analytic.geometric.MANY`) and against LM, µs per target (wall clock, best of ``repeat``)."""
    from armkit.ik.analytic import geometric

    robot = armkit.load("cobra600")
    print("\nSCARA batches (cobra600, poses; EAIK takes revolute joints only): µs per target, best of "
          f"{repeat}, wall clock\n")
    print("| targets | ik_all | ik_all, target by target | ik | ik, target by target | ik method='lm' |")
    print("|---|---|---|---|---|---|")
    many = geometric.MANY
    for B in (1000, 10000):
        T = armkit.fk(robot, robot.random_q(B, rng=B))
        columns = ((lambda: armkit.ik_all(robot, T), many), (lambda: armkit.ik_all(robot, T), 10**12),
                   (lambda: armkit.ik(robot, T), many), (lambda: armkit.ik(robot, T), 10**12),
                   (lambda: armkit.ik(robot, T, method="lm"), many))
        cells = []
        for fn, threshold in columns:
            geometric.MANY = threshold
            try:
                fn()   # the first call of a kind compiles or fills caches
                best = _best(fn, repeat)
            finally:
                geometric.MANY = many
            cells.append(f"{best / B * 1e6:.2f}")
        print(f"| {B:,} | " + " | ".join(cells) + " |", flush=True)
    print(f"\nload average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")


def random_classes(arms: int, targets: int, repeat: int) -> None:
    """One target per call on random arms of each closed-form 6R class (bench_coverage's URDF generator, so the
    arm goes through the URDF reader and the geometric classification as a user's would): armkit's ``ik_all``
    and ``ik`` against EAIK's ``IK`` (where EAIK is installed), median over the arms of the CPU-best time per
    target. The classes without a DH pattern (a general spherical wrist, three parallel axes at random angles) are
    the geometric family's: SP5 (the general wrist's position) and SP6 (three parallel axes) solve their quartic in
    closed form."""
    import tempfile

    from bench_coverage import KINDS, random_arm_urdf

    try:
        import eaik  # noqa: F401
    except ImportError:
        eaik = None
    print(f"\nrandom arms of each closed-form class: {arms} arms x {targets} targets, one target per call; median over "
          "the arms of the CPU-best µs per target (ratio armkit/EAIK)\n")
    print("| class drawn | armkit family | EAIK single | armkit ik_all single | armkit ik single | branches per target |")
    print("|---|---|---|---|---|---|")
    g = np.random.default_rng(5)
    with tempfile.TemporaryDirectory() as tmp:
        for kind, relations in KINDS.items():
            e_t, a_t, o_t, names, count = [], [], [], set(), []
            for a in range(arms):
                path = Path(tmp) / f"arm{a}.urdf"
                path.write_text(random_arm_urdf(g, relations))
                robot = armkit.load(str(path), tip="tool")
                cf = closed_form(robot)
                names.add(cf.family if cf is not None else "none")
                T = list(armkit.fk(robot, g.uniform(-np.pi, np.pi, (targets, 6))))
                armkit.ik_all(robot, T[0])
                armkit.ik(robot, T[0])
                count.append(np.mean([armkit.ik_all(robot, t, enforce_limits=False).success.sum() for t in T]))
                runs = [(lambda t: armkit.ik_all(robot, t), T), (lambda t: armkit.ik(robot, t), T)]
                if eaik is not None:
                    form = poe(robot)
                    e = _eaik_robot(form)
                    Tfix = [t.copy() for t in T]
                    for t in Tfix:
                        t[:3, :3] = t[:3, :3] @ form.R_nT.T
                    e.IK(Tfix[0])
                    runs.append((lambda t: e.IK(t), Tfix))
                # 100 targets make a round of ~0.3 ms: at least 5 rounds, taken in turn, against this machine's noise
                best = _cpu_best_each(runs, max(repeat, 5))
                a_t.append(best[0])
                o_t.append(best[1])
                if eaik is not None:
                    e_t.append(best[2])
            es = float(np.median(e_t)) if e_t else None
            aa, oo = float(np.median(a_t)), float(np.median(o_t))
            ratio = (lambda x: "" if es is None else f" ({x / es:.2g}x)")  # noqa: E731
            print(f"| {kind} | {' / '.join(sorted(names))} | {'-' if es is None else f'{es * 1e6:.1f}'} | "
                  f"{aa * 1e6:.1f}{ratio(aa)} | {oo * 1e6:.1f}{ratio(oo)} | {np.mean(count):.1f} |")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--targets", type=int, default=1000)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--searches-only", action="store_true",
                    help="only the sweep, held-joint and 1-D search times (no EAIK needed)")
    ap.add_argument("--search-targets", type=int, default=100)
    ap.add_argument("--single-only", action="store_true",
                    help="only the single-call times, one compiled call against the batched path (no EAIK needed)")
    ap.add_argument("--scara-only", action="store_true",
                    help="only the SCARA's batches (cobra600), its whole-batch form against the loop (no EAIK needed)")
    ap.add_argument("--small-only", action="store_true",
                    help="only the small batches (1-129 targets in one call), both paths, and EAIK's where installed")
    ap.add_argument("--random-only", action="store_true",
                    help="only the random arms of each closed-form class, one target per call (EAIK where installed)")
    ap.add_argument("--random-arms", type=int, default=10)
    ap.add_argument("--big-only", action="store_true",
                    help="only the big batches (--big-targets in one call), both paths, and EAIK's where installed")
    ap.add_argument("--big-targets", type=int, default=50_000)
    ap.add_argument("--names-only", action="store_true",
                    help="only the branch names read (rounded files, the Kinova's URDF), compiled against NumPy steps")
    ap.add_argument("--eaik-only", action="store_true",
                    help="only the table against EAIK (branches, single calls, batched calls)")
    args = ap.parse_args()
    if args.random_only:
        G.kernels()
        random_classes(args.random_arms, 100, args.repeat)
        return
    if args.scara_only:
        scara_batches(args.repeat)
        return
    if args.small_only:
        G.kernels()
        small_batches(args.repeat)
        return
    if args.names_only:
        G.kernels()
        names_read(args.repeat)
        return
    if args.big_only:
        G.kernels()
        big_batches(args.big_targets, args.threads, args.repeat)
        return
    if args.single_only:
        G.kernels()
        single_calls(min(args.targets, 300), args.repeat)
        return
    if args.searches_only:
        G.kernels()
        searches(args.search_targets)
        return
    try:
        import eaik  # noqa: F401
    except ImportError:
        sys.exit("EAIK is not installed: pip install eaik (the bench extra)")
    G.kernels()
    rows = []
    for label, (name, tip) in ARMS.items():
        if name.endswith(".urdf") and not Path(name).is_file():
            print(f"skip {label}: example-robot-data is not installed")
            continue
        robot = _arm(name, tip)
        form = poe(robot)
        if robot.prismatic.any():
            print(f"skip {label}: EAIK's HPRobot takes revolute joints only")
            continue
        cf = closed_form(robot)
        rng = np.random.default_rng(7)
        q = rng.uniform(-np.pi, np.pi, (args.targets, robot.n))
        T = armkit.fk(robot, q)
        eaik = _eaik_robot(form)
        armkit.ik_all(robot, T[:4])            # warm up every kernel on both sides
        Tfix = T.copy()
        Tfix[:, :3, :3] = T[:, :3, :3] @ form.R_nT.T
        eaik.IK(Tfix[0])
        cmp = _compare(robot, form, T, eaik)
        k = min(300, len(T))
        singles = list(T[:k])      # one call per target, CPU time of this thread (both run in it)
        e_singles = list(Tfix[:k])
        e_single, a_all, a_one = _cpu_best_each([(lambda t: eaik.IK(t), e_singles),
                                                 (lambda t: armkit.ik_all(robot, t), singles),
                                                 (lambda t: armkit.ik(robot, t), singles)], args.repeat)
        # the answer read as a caller reads it: EAIK's Q and is_LS (converted to NumPy when read), armkit's q and
        # success (made with the call; its other fields are made when first read: IKResult._deferred)
        e_read, a_read = _cpu_best_each([(lambda t: _read_eaik(eaik.IK(t)), e_singles),
                                         (lambda t: _read_armkit(armkit.ik_all(robot, t)), singles)], args.repeat)
        e_kept, a_kept = _cpu_best_each([(lambda t: eaik.IK(t), e_singles),
                                         (lambda t: armkit.ik_all(robot, t), singles)], args.repeat, keep=True)
        raw = None
        if cf is not None and cf.family == "geometric":
            fn = G.SOLVERS[cf.solver]
            f = cf.form
            raw = _cpu_best(lambda t: fn(f, t[:3, :3], t[:3, 3]), singles, args.repeat)
        for _ in range(3):   # both batched calls warmed up first: the steady state of a loop over batches (the
            # first rounds of a call whose buffers are new to the process touch fresh pages, slow on this machine)
            eaik.IK_batched(Tfix, args.threads)
            armkit.ik_all(robot, T)
        rounds = max(args.repeat, 15)   # a batch takes milliseconds: more rounds against this machine's noise
        # one side's rounds, then the other's (not in turn, as the single calls are): after a threaded call armkit's
        # OpenMP workers spin a while before they sleep, and an EAIK call right after one ran at a median of 4.0
        # against 2.8 ms (the Puma's 1,000 targets, 2026-12-07), a handicap to the peer
        e_batch = _best(lambda: eaik.IK_batched(Tfix, args.threads), rounds) / len(T)
        a_batch = _best(lambda: armkit.ik_all(robot, T), rounds) / len(T)
        rows.append((label, cf.family if cf else "none", cmp, e_single, raw, a_all, a_one, e_batch, a_batch, e_read,
                     a_read, e_kept, a_kept))
    us = lambda s: "-" if s is None else f"{s * 1e6:.1f}"  # noqa: E731
    print(f"\n{args.targets:,} targets per arm, limits off, {args.threads} EAIK threads; times in µs per target "
          "(ratio armkit/EAIK): single calls in CPU time of the thread, best of the rounds; batched calls in wall "
          "clock (EAIK's run on several threads)\n")
    print("| arm | armkit family | EAIK branches | armkit branches | missing | extra | armkit fails FK | EAIK fails FK | "
          "EAIK single | armkit raw solver | armkit ik_all single | armkit ik single | EAIK single, Q and is_LS read | "
          "armkit ik_all single, q and success read | EAIK single, results kept | armkit ik_all single, results kept "
          "| EAIK batched | armkit ik_all batched |")
    print("|" + "---|" * 18)
    for label, fam, c, es, raw, aa, a1, eb, ab, er, ar, ek, ak in rows:
        print(f"| {label} | {fam} | {c['eaik branches']:,} | {c['armkit branches']:,} | {c['missing']} | {c['extra']} "
              f"| {c['armkit fails FK']} | {c['eaik fails FK']:,} | {us(es)} | {us(raw)}{'' if raw is None else f' ({raw / es:.2g}x)'} | "
              f"{us(aa)} ({aa / es:.2g}x) | {us(a1)} ({a1 / es:.2g}x) | {us(er)} | {us(ar)} ({ar / er:.2g}x) | "
              f"{us(ek)} | {us(ak)} ({ak / ek:.2g}x) | {us(eb)} | {us(ab)} ({ab / eb:.2g}x) |")
    if args.eaik_only:
        return
    single_calls(min(args.targets, 300), args.repeat)
    small_batches(args.repeat)
    big_batches(args.big_targets, args.threads, args.repeat)
    names_read(args.repeat)
    searches(args.search_targets)
    random_classes(args.random_arms, 100, args.repeat)
    scara_batches(args.repeat)


if __name__ == "__main__":
    main()
