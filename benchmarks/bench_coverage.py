"""Every branch EAIK finds, armkit finds too: the coverage check of the analytic-IK issue, 10,000 targets per arm.

Run: ``.venv-bench/bin/python benchmarks/bench_coverage.py [--targets 10000]`` (the ``bench`` extra holds
EAIK; example-robot-data comes with the test extra). No times here: benchmarks/bench_analytic.py has them.

Arms:

* the bundled 6-joint arms and the example-robot-data arms armkit knows by name (UR3/5/10, Kinova Jaco2), and
  the bundled Puma and UR5 with joints turning the other way (:data:`REVERSED`: their own DH families answer),
  and as files that round their twists (:data:`ROUNDED`, ``rpy="1.5708"``: solved on their own axes by the
  geometric family, the branches named by the DH family of the ideal arm);
* the 7-joint arms (Panda, iiwa14, TIAGo's and Talos's arms, xArm7, Z1) with the joint armkit's class names
  (``sweep joint k``) held at a value: armkit's ``ik_all(robot, T, fixed={name: value})`` against EAIK's
  ``HPRobot(H, P, fixed_axes=[(k - 1, value)])`` (8 values drawn per arm, the targets split between them);
* random arms of each 6R class with a closed form, written as URDF files (joint axes and points drawn at
  random, then the class's relation imposed: axes that meet or are parallel), so that the whole path is
  checked: the URDF reader, the geometric classification, the solver, the FK check (``--arms`` arms a class,
  the targets shared between them);
* random arms of the classes EAIK refuses (the general 6R, the 1-D search classes), each target on its own arm,
  against a dense least-squares search instead (``--dense-targets``, ``--starts``): every distinct solution that
  Levenberg-Marquardt reaches from random starts must be among armkit's branches.

For each: the targets are the FK of random configurations (seeded, uniform in (-pi, pi], limits off on both
sides), EAIK's solutions are kept where FK puts the tool on the target to 1e-9 of the arm's size (EAIK flags
every answer of its own searches "least-squares", the exact ones too: those are kept, and counted apart), one
root listed twice counted once; armkit's successful branches are checked by FK too. Reported: EAIK's branches,
armkit's, **missing** (EAIK's, not within 1e-6 rad of any of armkit's after wrapping, nor the same branch a
little apart: within 1e-3 rad with the configuration halfway between also on the target to 1e-9, which happens
next to a singularity, where the target holds along a short segment of joint space, and where EAIK's search
stops its root 1e-6 rad short; those pairs are counted apart, "near"), extra (the reverse:
armkit's verified branches EAIK does not list), EAIK wrong (answers EAIK gives as exact, not least-squares,
whose FK misses the target by more than 1e-6 of the arm's size) and **armkit fails FK** (a branch called a success whose FK
misses by more than 1e-9 of the arm's size). The issue's goal: 0 missing, 0 failing FK.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

os.environ.setdefault("ARMKIT_JIT", "wait")

import armkit  # noqa: E402
from armkit.ik import closed_form_family  # noqa: E402
from armkit.ik.analytic import closed_form  # noqa: E402
from armkit.ik.geometric.classify import classify  # noqa: E402
from armkit.ik.geometric.poe import poe  # noqa: E402
from bench_analytic import _rounded  # noqa: E402  (the arm of a file that rounds its twists: one builder)

NAMED = ("ur5", "puma560", "example-robot-data:ur3", "example-robot-data:ur5", "example-robot-data:ur10",
         "example-robot-data:kinova")
REVERSED = (("puma560", (2,)), ("ur5", (2,)), ("ur5", (3,)), ("ur5", (1, 2)))
ROUNDED = ("puma560", "ur5")
"""Bundled arms with joints (0-based) turning the other way (:func:`armkit.model.axes.with_axes_reversed`): the DH
families solve them with those joints turned back (180 deg twists between parallel axes)."""
SEVEN = ("panda", "iiwa14", "example-robot-data:tiago", "example-robot-data:talos", "example-robot-data:xarm7",
         "example-robot-data:z1")
KINDS = {   # class drawn -> (which axes meet, which are parallel); joints numbered from 0
    "spherical wrist (4, 5, 6 meet)": ((3, 4, 5),), "spherical wrist, 1 and 2 meet": ((3, 4, 5), (0, 1)),
    "spherical wrist, 2 parallel 3": ((3, 4, 5), "p12"), "spherical base (1, 2, 3 meet)": ((0, 1, 2),),
    "three parallel (2, 3, 4)": ("p123",), "three parallel, 5 and 6 meet": ("p123", (4, 5)),
}
REFUSED = {   # classes EAIK has no solver for: armkit's searches against a dense least-squares search
    "general 6R (2-D search)": (), "5 and 6 meet (1-D search)": ((4, 5),), "2 parallel 3 (1-D search)": ("p12",),
    "2, 3, 4 meet (1-D search)": ((1, 2, 3),),
}


def _wrap(a: np.ndarray) -> np.ndarray:
    return (a + np.pi) % (2 * np.pi) - np.pi


def _unit(g: np.random.Generator) -> np.ndarray:
    v = g.normal(size=3)
    return v / np.linalg.norm(v)


def random_arm_urdf(g: np.random.Generator, relations: tuple) -> str:
    """A URDF of a random 6R arm with the given relations: a tuple of joints whose axes meet at one point, or
    ``"p12"`` / ``"p123"`` (joints 1-2 or 1-2-3, from 0, with parallel axes). Every link frame is parallel to the
    base at q = 0, so a joint's ``origin`` is the step from the previous joint's point and its ``axis`` the
    axis drawn; the tool frame gets a random rotation."""
    from scipy.spatial.transform import Rotation

    H = np.stack([_unit(g) for _ in range(6)])
    pts = g.normal(size=(6, 3)) * 0.5
    for rel in relations:
        if isinstance(rel, str):   # parallel axes, each either way round
            group = (1, 2) if rel == "p12" else (1, 2, 3)
            for k in group[1:]:
                H[k] = (1.0 if g.random() < 0.5 else -1.0) * H[group[0]]
        else:                      # axes through one point, each joint's point slid along its axis
            c = g.normal(size=3) * 0.5
            for k in rel:
                pts[k] = c + g.uniform(-0.5, 0.5) * H[k]
    tool = pts[5] + g.normal(size=3) * 0.3
    steps = np.vstack([pts[0], np.diff(pts, axis=0), tool - pts[5]])
    rpy = Rotation.from_matrix(Rotation.random(random_state=int(g.integers(2**31))).as_matrix()).as_euler("xyz")
    links = "".join(f'<link name="l{k}"/>' for k in range(7)) + '<link name="tool"/>'
    joints = "".join(
        f'<joint name="j{k + 1}" type="revolute"><parent link="l{k}"/><child link="l{k + 1}"/>'
        f'<origin xyz="{" ".join(repr(float(v)) for v in steps[k])}" rpy="0 0 0"/>'
        f'<axis xyz="{" ".join(repr(float(v)) for v in H[k])}"/>'
        f'<limit lower="-6.283185307179586" upper="6.283185307179586" effort="1" velocity="1"/></joint>'
        for k in range(6))
    joints += (f'<joint name="tool_joint" type="fixed"><parent link="l6"/><child link="tool"/>'
               f'<origin xyz="{" ".join(repr(float(v)) for v in steps[6])}" '
               f'rpy="{" ".join(repr(float(v)) for v in rpy)}"/></joint>')
    return f'<?xml version="1.0"?><robot name="random">{links}{joints}</robot>'


def _eaik(form, fixed: list | None = None):
    from eaik.IK_HP import HPRobot

    return HPRobot(np.ascontiguousarray(form.H), np.ascontiguousarray(form.P), fixed_axes=fixed or [])


def _distinct(Q: np.ndarray) -> np.ndarray:
    """The rows of ``Q`` more than 1e-6 rad apart (after wrapping) from every earlier row: EAIK's searches may list
    one root twice."""
    keep: list[int] = []
    for i in range(len(Q)):
        if all(np.abs(_wrap(Q[i] - Q[j])).max() > 1e-6 for j in keep):
            keep.append(i)
    return Q[keep]


def compare(robot, form, T: np.ndarray, eaik, res) -> dict:
    """Branch sets of the targets ``T`` (B, 4, 4): EAIK's exact, FK-verified solutions against ``res``, armkit's
    ``ik_all`` of the same targets (limits off)."""
    scale = max(1.0, robot.reach)
    Tfix = T.copy()
    Tfix[:, :3, :3] = T[:, :3, :3] @ form.R_nT.T   # EAIK's tool frame is the last joint's
    out = {"targets": len(T), "flagged": 0, "eaik wrong": 0, "near": 0, "eaik": 0, "armkit": 0, "missing": 0, "extra": 0, "fails FK": 0}
    for i in range(len(T)):
        sol = eaik.IK(Tfix[i])
        Q = np.asarray(sol.Q).reshape(-1, robot.n)
        ls = np.asarray(sol.is_LS).reshape(-1).astype(bool)
        if len(Q):
            err = np.abs(armkit.fk(robot, Q) - T[i]).max(axis=(1, 2))
            good = err <= 1e-9 * scale
            out["eaik wrong"] += int((~ls & (err > 1e-6 * scale)).sum())
            out["flagged"] += int((good & ls).sum())
            Q = _distinct(Q[good])
        ours = res.q[i][res.success[i]]
        if len(ours):
            out["fails FK"] += int((np.abs(armkit.fk(robot, ours) - T[i]).max(axis=(1, 2)) > 1e-9 * scale).sum())
        out["eaik"] += len(Q)
        out["armkit"] += len(ours)
        if len(Q) and len(ours):
            step = _wrap(Q[:, None] - ours[None])
            d = np.abs(step).max(axis=-1)
            found, used = d.min(axis=1) <= 1e-6, d.min(axis=0) <= 1e-6
            for a in np.where(~found)[0]:   # the same branch, a little apart (below)?
                for j in np.where(d[a] <= 1e-3)[0]:
                    mid = ours[j] + 0.5 * step[a, j]
                    if np.abs(armkit.fk(robot, mid) - T[i]).max() <= 1e-9 * scale:
                        found[a] = used[j] = True
                        out["near"] += 1
                        break
            out["missing"] += int((~found).sum())
            out["extra"] += int((~used).sum())
        else:
            out["missing"] += len(Q)
            out["extra"] += len(ours)
    return out


def _add(total: dict, part: dict) -> None:
    for k, v in part.items():
        total[k] = total.get(k, 0) + v


def named(name: str, targets: int, g: np.random.Generator, reversed_joints: tuple[int, ...] = (),
          rounded: bool = False) -> tuple[str, dict] | None:
    robot = _reversed(name, reversed_joints) if reversed_joints else armkit.load(name)
    if rounded:
        robot = _rounded(robot)
    form = poe(robot)
    cls = classify(robot)
    eaik = _eaik(form)
    if not eaik.hasKnownDecomposition():
        return cls.name, {"refused by EAIK": 1}
    T = armkit.fk(robot, g.uniform(-np.pi, np.pi, (targets, robot.n)))
    return cls.name, compare(robot, form, T, eaik, armkit.ik_all(robot, T, enforce_limits=False))


def _reversed(name: str, joints: tuple[int, ...]):
    from armkit.model.axes import with_axes_reversed

    return with_axes_reversed(armkit.load(name), joints)


def seven(name: str, targets: int, g: np.random.Generator, values: int = 8) -> tuple[str, dict] | None:
    robot = armkit.load(name)
    form = poe(robot)
    cls = classify(robot)
    k = cls.locked - 1
    joint = robot.joint_names[k]
    total: dict = {}
    for part in np.array_split(np.arange(targets), values):
        v = float(g.uniform(max(robot.lower[k], -np.pi), min(robot.upper[k], np.pi)))
        q = g.uniform(-np.pi, np.pi, (len(part), robot.n))
        q[:, k] = v
        T = armkit.fk(robot, q)
        eaik = _eaik(form, [(k, v)])
        if not eaik.hasKnownDecomposition():
            return cls.name, {"refused by EAIK": 1}
        res = armkit.ik_all(robot, T, enforce_limits=False, fixed={joint: v})
        _add(total, compare(robot, form, T, eaik, res))
    return f"{cls.name}, {joint} held", total


def random_class(kind: str, targets: int, arms: int, g: np.random.Generator, folder: Path) -> tuple[str, dict]:
    total: dict = {}
    names: set[str] = set()
    for a, part in enumerate(np.array_split(np.arange(targets), arms)):
        path = folder / f"arm{a}.urdf"
        path.write_text(random_arm_urdf(g, KINDS[kind]))
        robot = armkit.load(str(path), tip="tool")
        form = poe(robot)
        names.add(classify(robot).name)
        eaik = _eaik(form)
        if not eaik.hasKnownDecomposition():
            _add(total, {"refused by EAIK": 1})
            continue
        T = armkit.fk(robot, g.uniform(-np.pi, np.pi, (len(part), 6)))
        _add(total, compare(robot, form, T, eaik, armkit.ik_all(robot, T, enforce_limits=False)))
    return " / ".join(sorted(names)), total


def _near_or_equal(robot, T: np.ndarray, a: np.ndarray, b: np.ndarray) -> bool:
    """Within 1e-6 rad (wrapped), or the same branch a little apart (:func:`compare`'s rule)."""
    step = _wrap(a - b)
    gap = np.abs(step).max()
    if gap <= 1e-6:
        return True
    return bool(gap <= 1e-3 and np.abs(armkit.fk(robot, b + 0.5 * step) - T).max() <= 1e-9 * max(1.0, robot.reach))


def dense(kind: str, targets: int, starts: int, g: np.random.Generator, folder: Path,
          keep: Path | None = None) -> tuple[str, dict]:
    """``ik_all`` of random arms of a class EAIK refuses against every distinct solution that Levenberg-Marquardt
    (``method="lm"``, no restarts) reaches from ``starts`` random starts per target: the reference's resolution
    is its starts; it may miss solutions, armkit may not. ``keep``: a folder where each target with a missed
    solution leaves its arm (``missed-K.urdf``) and ``missed-K.npz`` (the target ``T``, the missed ``q``)."""
    out = {"targets": targets, "reference": 0, "armkit": 0, "missing": 0, "fails FK": 0}
    names: set[str] = set()
    for i in range(targets):
        path = folder / f"dense-{len(list(folder.iterdir()))}.urdf"
        path.write_text(random_arm_urdf(g, REFUSED[kind]))
        robot = armkit.load(str(path), tip="tool")
        names.add(f"{classify(robot).name} ({classify(robot).solver})")
        T = armkit.fk(robot, g.uniform(-np.pi, np.pi, 6))
        res = armkit.ik_all(robot, T, enforce_limits=False)
        ours = np.asarray(res.q)[np.asarray(res.success)]
        if len(ours):
            out["fails FK"] += int((np.abs(armkit.fk(robot, ours) - T).max(axis=(1, 2)) > 1e-9 * max(1.0, robot.reach))
                                   .sum())
        q0 = g.uniform(-np.pi, np.pi, (starts, 6))
        lm = armkit.ik(robot, np.broadcast_to(T, (starts, 4, 4)), q0=q0, method="lm", restarts=0, enforce_limits=False)
        ref: list[np.ndarray] = []
        for x in _wrap(np.asarray(lm.q)[np.asarray(lm.success)]):
            if not any(np.abs(_wrap(x - u)).max() <= 1e-6 for u in ref):
                ref.append(x)
        out["reference"] += len(ref)
        out["armkit"] += len(ours)
        missed = [u for u in ref if not any(_near_or_equal(robot, T, u, s) for s in ours)]
        out["missing"] += len(missed)
        if missed and keep is not None:
            k = len(list(keep.glob("missed-*.npz")))
            (keep / f"missed-{k}.urdf").write_text(path.read_text())
            np.savez(keep / f"missed-{k}.npz", T=T, q=np.array(missed))
    return " / ".join(sorted(names)), out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--targets", type=int, default=10_000)
    ap.add_argument("--arms", type=int, default=100, help="random arms per class (the targets shared between them)")
    ap.add_argument("--dense-targets", type=int, default=500,
                    help="targets per class EAIK refuses (each on its own random arm), checked by a dense search")
    ap.add_argument("--starts", type=int, default=200, help="random starts of the dense least-squares search")
    ap.add_argument("--dense-only", action="store_true", help="only the classes EAIK refuses (no EAIK needed)")
    ap.add_argument("--seed", type=int, default=2026,
                    help="where the generator of arms and targets starts (the README's numbers: 2026)")
    ap.add_argument("--keep-missed", type=Path, default=None, metavar="FOLDER",
                    help="write each arm and target with a missed solution of the dense check into FOLDER")
    args = ap.parse_args()
    g = np.random.default_rng(args.seed)
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        if not args.dense_only:
            against_eaik(args, g, Path(tmp))
        print(f"\nclasses EAIK refuses: {args.dense_targets} targets a class, each on its own random arm; reference: "
              f"Levenberg-Marquardt from {args.starts} random starts a target, every distinct solution it reaches\n")
        print("| arm | armkit's class (solver) | reference solutions | armkit branches | missing | armkit fails FK |")
        print("|---|---|---|---|---|---|")
        if args.keep_missed is not None:
            args.keep_missed.mkdir(parents=True, exist_ok=True)
        for kind in REFUSED:
            cls, c = dense(kind, args.dense_targets, args.starts, g, Path(tmp), args.keep_missed)
            print(f"| random: {kind} | {cls} | {c['reference']:,} | {c['armkit']:,} | {c['missing']} | {c['fails FK']} |",
                  flush=True)
    print(f"\n{time.perf_counter() - t0:.0f} s; load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")


def against_eaik(args: argparse.Namespace, g: np.random.Generator, tmp: Path) -> None:
    """The arms EAIK solves: its branches against armkit's."""
    try:
        import eaik  # noqa: F401
    except ImportError:
        sys.exit("EAIK is not installed: pip install eaik (the bench extra), or --dense-only")
    print(f"\n{args.targets:,} targets per arm (random arms: per class, {args.arms} arms), limits off on both sides\n")
    print("| arm | armkit's class | EAIK branches (of them flagged least-squares) | armkit branches | missing | near pairs | extra "
          "| armkit fails FK | EAIK wrong |")
    print("|---|---|---|---|---|---|---|---|---|")

    def row(label: str, cls: str, c: dict) -> None:
        if "refused by EAIK" in c and "eaik" not in c:
            print(f"| {label} | {cls} | EAIK refuses | | | | | | |", flush=True)
            return
        note = f" (EAIK refuses {c['refused by EAIK']} arms)" if c.get("refused by EAIK") else ""
        print(f"| {label} | {cls} | {c['eaik']:,} ({c['flagged']:,}) | {c['armkit']:,} | {c['missing']} | {c['near']} | {c['extra']} | "
              f"{c['fails FK']} | {c['eaik wrong']:,}{note} |", flush=True)

    for name in NAMED + SEVEN:
        try:
            armkit.load(name)
        except armkit.errors.ArmkitError as exc:   # example-robot-data not installed
            print(f"| {name} | skipped: {exc} | | | | | | | |")
            continue
        cls, c = (seven if name in SEVEN else named)(name, args.targets, g)
        row(name.removeprefix("example-robot-data:"), cls, c)
    for kind in KINDS:
        cls, c = random_class(kind, args.targets, args.arms, g, tmp)
        row(f"random: {kind}", cls, c)
    own = np.random.default_rng(7)   # their own draws: the rows above and the dense search below as before
    for name, joints in REVERSED:
        cls, c = named(name, args.targets, own, joints)
        row(f"{name}, joint{'s' if len(joints) > 1 else ''} {', '.join(str(k + 1) for k in joints)} reversed "
            f"(family {closed_form_family(_reversed(name, joints))})", cls, c)
    for name in ROUNDED:
        cls, c = named(name, args.targets, own, rounded=True)
        cf = closed_form(_rounded(armkit.load(name)))
        named_by = getattr(cf, "names_from", None)
        row(f"{name}, a file with rounded twists (family {cf.family}"
            f"{', names of ' + named_by.family if named_by is not None else ''})", cls, c)


if __name__ == "__main__":
    main()
