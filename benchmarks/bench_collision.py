"""Collision checking: armkit's batched kernels beside coal's own loop, accuracy against coal, IK with a scene,
and the workspace/IK consistency check (issue 13).

    python benchmarks/bench_collision.py speed        # configurations per second, armkit and coal, same run
    python benchmarks/bench_collision.py accuracy     # 10,000 configurations per bundled arm against coal
    python benchmarks/bench_collision.py ik           # IK with a table and a wall: flagged-but-wrong counts
    python benchmarks/bench_collision.py consistency  # workspace points vs IK finding a collision-free solution
    python benchmarks/bench_collision.py kernels --before OLD/src/armkit/collision/_jit.py
                                                      # this tree's Numba kernels against an older file's, same data
    python benchmarks/bench_collision.py cylinder     # a scene with a cylinder beside the same with a capsule

Timing is wall time, best of 3, after a warm-up call of the same size. No assertion here: the numbers go
into docs/scene.md.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

import armkit
from armkit.collision import Scene, arm_geometry, clearance, collisions, in_collision
from armkit.collision.query import _pairs, as_scene, chain_frames


def ten_shapes(robot) -> Scene:
    """A ground, a table, a wall, a ball, a pole and five random boxes, sized to the arm's reach."""
    R = robot.reach
    rng = np.random.default_rng(0)
    shapes = [Scene.plane([0, 0, 1], -0.05 * R, name="ground"),
              Scene.box([0.6 * R, 0, 0.2 * R], [0.4 * R, 0.8 * R, 0.4 * R], name="table"),
              Scene.box([0, -0.7 * R, 0.5 * R], [2 * R, 0.05 * R, R], name="wall"),
              Scene.sphere([0.4 * R, 0.4 * R, 0.6 * R], 0.1 * R, name="ball"),
              Scene.capsule([-0.5 * R, 0.5 * R, 0], [-0.5 * R, 0.5 * R, R], 0.05 * R, name="pole")]
    for k in range(5):
        shapes.append(Scene.box(rng.uniform(-0.8, 0.8, 3) * R, rng.uniform(0.05, 0.2, 3) * R, rng.uniform(-1, 1, 3),
                                name=f"box{k}"))
    return Scene(shapes)


def table_and_wall(robot) -> Scene:
    R = robot.reach
    return Scene([Scene.box([0.45 * R, 0.0, -0.05 * R], [0.5 * R, 0.8 * R, 0.1 * R], name="table"),
                  Scene.box([0.0, -0.55 * R, 0.3 * R], [2 * R, 0.04 * R, 1.2 * R], name="wall")])


def best(fn, repeat=3):
    fn()
    t = []
    for _ in range(repeat):
        s = time.perf_counter()
        fn()
        t.append(time.perf_counter() - s)
    return min(t)


# ----------------------------------------------------------------------------- coal, the peer
def coal_setup(robot, scene):
    """coal objects for every checked pair (capsules re-placed per configuration), as a coal user would write it."""
    import coal

    geo = arm_geometry(robot)
    sc = as_scene(robot, scene)
    scene_pairs, self_pairs = _pairs(geo, sc, True)
    static = {}
    for s in sc:
        T = s.pose
        if s.kind == "plane":
            static[id(s)] = (coal.Halfspace(s.normal, s.offset), coal.Transform3s())
        elif s.kind == "box":
            static[id(s)] = (coal.Box(*s.size), coal.Transform3s(T[:3, :3].copy(), T[:3, 3].copy()))
        elif s.kind == "sphere":
            static[id(s)] = (coal.Sphere(s.size[0]), coal.Transform3s(T[:3, :3].copy(), T[:3, 3].copy()))
        elif s.kind == "capsule":
            static[id(s)] = (coal.Capsule(*s.size), coal.Transform3s(T[:3, :3].copy(), T[:3, 3].copy()))
    return geo, scene_pairs, self_pairs, static


def coal_loop(robot, q, setup, distance=True):
    """Per configuration: FK, place the capsules, then coal.distance (or coal.collide) for every pair."""
    import coal

    geo, scene_pairs, self_pairs, static = setup
    req = coal.DistanceRequest() if distance else coal.CollisionRequest()
    caps = {i: s for i, s in enumerate(geo.solids) if s.kind == "segment"}
    out = np.empty(len(q))
    F = chain_frames(robot, q)
    for b in range(len(q)):
        placed = {}
        for i, s in caps.items():
            p0, p1 = F[b, s.ends[0], :3, 3], F[b, s.ends[1], :3, 3]
            d = p1 - p0
            L = float(np.linalg.norm(d))
            z = d / L if L > 0 else np.array([0.0, 0.0, 1.0])
            x = np.cross([0.0, 0.0, 1.0] if abs(z[2]) < 0.9 else [1.0, 0.0, 0.0], z)
            x /= np.linalg.norm(x)
            R = np.column_stack([x, np.cross(z, x), z])
            placed[i] = (coal.Capsule(s.size[0], L), coal.Transform3s(R, 0.5 * (p0 + p1)))
        m = np.inf
        for i, shape in scene_pairs:
            g, t = placed[i]
            g2, t2 = static[id(shape)]
            if distance:
                m = min(m, coal.distance(g, t, g2, t2, req, coal.DistanceResult()))
            elif coal.collide(g, t, g2, t2, req, coal.CollisionResult()):
                m = -1.0
                break
        for i, j in self_pairs:
            if m < 0 and not distance:
                break
            (g, t), (g2, t2) = placed[i], placed[j]
            if distance:
                m = min(m, coal.distance(g, t, g2, t2, req, coal.DistanceResult()))
            elif coal.collide(g, t, g2, t2, req, coal.CollisionResult()):
                m = -1.0
        out[b] = m
    return out


def speed(args):
    print(f"# collision check speed, {os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f}")
    print("| arm | pairs | armkit yes/no (Numba) | armkit clearance (Numba) | armkit every pair (Numba) | "
          "armkit every pair (NumPy) | coal loop: collide | coal loop: distance | FK frames alone |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name in args.robots:
        robot = armkit.load(name)
        scene = ten_shapes(robot)
        q = robot.random_q(args.n, rng=1)
        armkit.set_backend("numba")
        res = collisions(robot, q[:2000], scene)
        t_yes = best(lambda: in_collision(robot, q, scene))
        t_min = best(lambda: clearance(robot, q, scene))
        t_all = best(lambda: collisions(robot, q, scene))
        t_fk = best(lambda: armkit.fk_frames(robot, q))
        armkit.set_backend("numpy")
        qn = q[: args.n // 20]
        t_np = best(lambda: collisions(robot, qn, scene), 1) * 20
        armkit.set_backend("numba")
        setup = coal_setup(robot, scene)
        qc = q[: args.coal]
        t_cc = best(lambda: coal_loop(robot, qc, setup, False), 1) * args.n / len(qc)
        t_cd = best(lambda: coal_loop(robot, qc, setup, True), 1) * args.n / len(qc)
        # the answers agree
        ref = coal_loop(robot, q[:300], setup, True)
        agree = np.abs(clearance(robot, q[:300], scene) - ref).max()
        rate = lambda t: f"{args.n / t / 1e6:.3g} M/s"
        print(f"| {name} | {len(res.pairs)} | {rate(t_yes)} | {rate(t_min)} | {rate(t_all)} | {rate(t_np)} | "
              f"{rate(t_cc)} | {rate(t_cd)} | {rate(t_fk)} |   (clearance vs coal on 300: max diff {agree:.1e})")


def accuracy(args):
    import sys

    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests", "collision"))
    from test_query import every_primitive, reference

    print("| arm | configurations | pairs | max diff, apart, exact pairs (robot unit) | ... / reach | "
          "cylinder pairs apart: max diff to coal / reach (armkit vs dense sampling) | overlapping pairs (max diff) | "
          "colliding configurations | yes/no disagreements |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name in args.robots_all:
        robot = armkit.load(name)
        scene = every_primitive(robot)
        n = args.acc if name != "so101" else max(args.acc // 20, 100)
        q = robot.random_q(n, rng=11)
        res = collisions(robot, q, scene)
        ref = np.array([reference(robot, qk, scene) for qk in q])
        post = np.array([p[1] == "post" for p in res.pairs])[None, :]
        diff = np.abs(res.distances - ref)
        apart = (ref > 0) & ~post
        cyl_apart = (ref > 0) & post
        over = (ref < 0) & ~post
        cyl_over = (ref < 0) & post
        # the cylinder pairs apart, checked against dense sampling of the exact point-cylinder distance
        geo = arm_geometry(robot)
        F = chain_frames(robot, q)
        post_shape = [s for s in scene if s.name == "post"][0]
        Tc = post_shape.pose
        worst_dense = 0.0
        cols = [c for c in range(len(res.pairs)) if res.pairs[c][1] == "post"]
        t = np.linspace(0.0, 1.0, 4001)
        for c in cols:
            solid = [x for x in geo.solids if x.name == res.pairs[c][0]][0]
            if solid.kind != "segment":
                continue
            p0 = F[:, solid.ends[0], :3, 3] - Tc[:3, 3]
            p1 = F[:, solid.ends[1], :3, 3] - Tc[:3, 3]
            x = (p0[:, None] + t[None, :, None] * (p1 - p0)[:, None]) @ Tc[:3, :3]
            dd = np.hypot(np.maximum(np.hypot(x[..., 0], x[..., 1]) - post_shape.size[0], 0),
                          np.maximum(np.abs(x[..., 2]) - 0.5 * post_shape.size[1], 0)).min(axis=1) - solid.size[0]
            ok = res.distances[:, c] > 0
            # dense sampling can only over-estimate the minimum: armkit must be <= it, and close
            worst_dense = max(worst_dense, float(np.max(np.abs(res.distances[ok, c] - dd[ok]), initial=0.0)))
        print(f"| {name} | {n:,} | {len(res.pairs)} | {diff[apart].max():.1e} | {diff[apart].max() / robot.reach:.1e} | "
              f"{diff[cyl_apart].max(initial=0) / robot.reach:.1e} (dense: {worst_dense / robot.reach:.1e}) | "
              f"{int((ref < 0).sum()):,} ({diff[over].max(initial=0):.1e}; cylinder depths within 1e-8 of the reach of "
              f"coal's or below: "
              f"{bool(np.all(res.distances[cyl_over] >= ref[cyl_over] - 1e-8 * robot.reach))}) | "
              f"{int(res.colliding.sum()):,} | "
              f"{int((res.colliding != (np.where(post & (ref < 0), res.distances, ref).min(axis=1) < 0)).sum())} |")


def ik_check(args):
    from armkit.ik.api import closed_form_family

    from armkit.collision import kernels  # noqa: F401

    print("| arm | method | targets | solved collision-free | failed: collision | flagged but wrong |"
          " successes checked by coal |")
    print("|---|---|---|---|---|---|---|")
    import sys

    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests", "collision"))
    from test_query import reference

    for name in args.robots_all:
        robot = armkit.load(name)
        scene = table_and_wall(robot)
        n = args.targets
        q = robot.random_q(n, rng=2)
        T = armkit.fk(robot, q)
        closed = closed_form_family(robot) is not None and name != "so101"   # so101: position-only LM
        position = name in ("fighter", "planar2")
        target = T[..., :3, 3] if position else T
        if name == "so101":
            target = T[..., :3, 3]
        method = "auto" if closed else "lm"
        if closed:
            res = armkit.ik_all(robot, target, scene=scene)
            ok = res.success
            qs = res.q[ok]
            reason = res.reason
            tq = np.broadcast_to(target[:, None], res.q.shape[:2] + target.shape[1:])[ok]
        else:
            res = armkit.ik(robot, target, method="lm", seed=3, scene=scene, mask=None if not position else None)
            ok = res.success
            qs = res.q[ok]
            reason = res.reason
            tq = target[ok]
        hit = collisions(robot, qs, scene).colliding if len(qs) else np.zeros(0, bool)
        Tq = armkit.fk(robot, qs)
        if tq.shape[-2:] == (4, 4):
            miss = np.linalg.norm(Tq[:, :3, 3] - tq[:, :3, 3], axis=1) > 1e-9 / robot.unit_scale
        else:
            miss = np.linalg.norm(Tq[:, :3, 3] - tq, axis=1) > 1e-9 / robot.unit_scale
        rng = np.random.default_rng(0)
        sub = rng.choice(len(qs), min(len(qs), args.coal_checks), replace=False) if len(qs) else []
        coal_bad = sum(reference(robot, qs[k], scene).min() < 0 for k in sub)
        print(f"| {name} | {method}{' (every branch)' if closed else ''} | {n:,} | {int(ok.sum()):,} | "
              f"{int((np.asarray(reason) == 'collision').sum()):,} | {int((hit | miss).sum())} | "
              f"{len(sub)} ({coal_bad} colliding) |")


def consistency(args):
    from armkit.analysis.workspace import workspace

    print("| arm | scene | workspace points checked | IK finds a collision-free solution | agreement |")
    print("|---|---|---|---|---|")
    for name, scene_name in (("fighter", "robot"), ("planar2", "table+wall"), ("puma560", "table+wall"),
                             ("ur5", "table+wall")):
        robot = armkit.load(name)
        scene = as_scene(robot, "robot") if scene_name == "robot" else table_and_wall(robot)
        ws = workspace(robot, samples=20_000, seed=4, scene=scene)
        rng = np.random.default_rng(5)
        pick = rng.choice(len(ws.points), min(args.points, len(ws.points)), replace=False)
        pts = ws.points[pick]
        if name in ("fighter", "planar2"):
            target = pts[:, :2] if name == "planar2" else pts
            res = armkit.ik_all(robot, target, scene=scene)
            found = res.success.any(axis=1)
        else:   # 6-DOF arms: the workspace is of tool positions, so position-only IK (LM with restarts)
            res = armkit.ik(robot, pts, method="lm", seed=1, scene=scene, restarts=5)
            found = res.success
        print(f"| {name} | {scene_name} | {len(pts):,} | {int(found.sum()):,} | {found.mean() * 100:.2f} % |")


def kernels(args):
    """The Numba kernels of this tree and of ``--before`` (an older ``collision/_jit.py``) on the same packed
    data in one process, timed alternately (best of ``--reps``): on a shared machine the ratio is what holds."""
    import importlib.util
    import sys

    from armkit.collision import _jit as now

    if not args.before:
        raise SystemExit("kernels needs --before PATH (an older src/armkit/collision/_jit.py)")
    spec = importlib.util.spec_from_file_location("armkit.collision._jit_before", args.before)
    old = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = old
    spec.loader.exec_module(old)   # its "from .. import _jit_loader" resolves in armkit.collision
    armkit.set_backend("numba")
    seen = {}
    real_min, real_all = now.min_distance, now.all_distances
    now.min_distance = lambda f, it, pr, stop=-np.inf: seen.setdefault("min", (f, it, pr)) and real_min(f, it, pr, stop)
    now.all_distances = lambda f, it, pr: seen.setdefault("all", (f, it, pr)) and real_all(f, it, pr)

    def race(label, fn_old, fn_new):
        fn_old(), fn_new()
        t_old, t_new = [], []
        for _ in range(args.reps):
            for fn, ts in ((fn_old, t_old), (fn_new, t_new)):
                s = time.perf_counter()
                fn()
                ts.append(time.perf_counter() - s)
        print(f"| {label} | {min(t_old) * 1e3:.2f} ms | {min(t_new) * 1e3:.2f} ms | {min(t_new) / min(t_old):.3f} |")

    print(f"# Numba collision kernels, before ({args.before}) and now, {os.cpu_count()} CPUs")
    print("| kernel | before | now | now/before |\n|---|---|---|---|")
    for name in args.robots:
        robot = armkit.load(name)
        scene = ten_shapes(robot)
        seen.clear()
        q = robot.random_q(4096, rng=1)
        clearance(robot, q, scene)
        collisions(robot, q, scene)
        f, it, pr = seen["min"]
        for stop, what in ((0.0, "yes/no"), (-np.inf, "clearance")):
            race(f"{name} {what}, {len(f)} configurations, {len(pr)} pairs",
                 lambda: old.min_distance(f, it, pr, stop), lambda: real_min(f, it, pr, stop))
        race(f"{name} every pair", lambda: old.all_distances(*seen["all"]), lambda: real_all(*seen["all"]))
        race(f"{name} clearance, 512 configurations (serial twin)",
             lambda: old.min_distance(f[:512], it, pr), lambda: real_min(f[:512], it, pr))
    now.min_distance, now.all_distances = real_min, real_all


def pole_scenes(robot):
    """The ground, a table and a pole: once a capsule, once a cylinder of the same radius and length."""
    R = robot.reach
    base = [Scene.plane([0, 0, 1], -0.05 * R, name="ground"),
            Scene.box([0.6 * R, 0, 0.2 * R], [0.4 * R, 0.8 * R, 0.4 * R], name="table")]
    capsule = Scene.capsule([-0.5 * R, 0.5 * R, 0], [-0.5 * R, 0.5 * R, R], 0.05 * R, name="pole")
    cylinder = Scene.cylinder([-0.5 * R, 0.5 * R, 0.5 * R], 0.05 * R, R, name="pole")
    return Scene(base + [capsule]), Scene(base + [cylinder])


def cylinder(args):
    """Issue 21: a cylinder anywhere in the scene used to send every check to the slow path (1.6 -> 160 us per
    configuration); now it is a compiled kernel like the others. Per configuration, batches of ``--batch``."""
    print(f"# a scene with a cylinder beside the same with a capsule, {os.cpu_count()} CPUs, "
          f"load average {os.getloadavg()[0]:.1f}")
    print("| arm | check | capsule pole | cylinder pole | cylinder/capsule |\n|---|---|---|---|---|")
    armkit.set_backend("numba")
    for name in args.robots:
        robot = armkit.load(name)
        with_capsule, with_cylinder = pole_scenes(robot)
        q = robot.random_q(args.batch, rng=1)
        T = armkit.fk(robot, q[5])
        target = T[:3, 3] if robot.n < 6 else T
        rows = (("yes/no (in_collision)", lambda sc: in_collision(robot, q, sc), args.batch),
                ("clearance", lambda sc: clearance(robot, q, sc), args.batch),
                ("every pair (collisions)", lambda sc: collisions(robot, q, sc), args.batch),
                ("one ik(..., scene=) call", lambda sc: armkit.ik(robot, target, scene=sc), 1))
        for label, fn, per in rows:
            fn(with_capsule), fn(with_cylinder)
            t_cap, t_cyl = np.inf, np.inf
            for _ in range(args.reps):   # alternately, best of: a busy machine slows both alike
                t_cap = min(t_cap, best(lambda: fn(with_capsule), 1) / per)
                t_cyl = min(t_cyl, best(lambda: fn(with_cylinder), 1) / per)
            unit, f = ("us", 1e6) if per > 1 else ("ms", 1e3)
            print(f"| {name} | {label} | {t_cap * f:.2f} {unit} | {t_cyl * f:.2f} {unit} | {t_cyl / t_cap:.2f} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("what", choices=["speed", "accuracy", "ik", "consistency", "kernels", "cylinder"])
    ap.add_argument("--robots", nargs="+", default=["ur5", "puma560"])
    ap.add_argument("--robots-all", nargs="+", default=armkit.bundled_robots())
    ap.add_argument("-n", type=int, default=1_000_000, help="configurations for the speed runs")
    ap.add_argument("--coal", type=int, default=2000, help="configurations for coal's (slow) loop")
    ap.add_argument("--acc", type=int, default=10_000, help="configurations per arm for the accuracy run")
    ap.add_argument("--targets", type=int, default=10_000, help="IK targets per arm")
    ap.add_argument("--coal-checks", type=int, default=300, help="IK successes re-checked with coal per arm")
    ap.add_argument("--points", type=int, default=1000, help="workspace points per arm")
    ap.add_argument("--before", help="kernels: an older collision/_jit.py to compare with")
    ap.add_argument("--reps", type=int, default=25, help="kernels: alternating repetitions (best of)")
    ap.add_argument("--batch", type=int, default=2000, help="cylinder: configurations per batched call")
    args = ap.parse_args()
    {"speed": speed, "accuracy": accuracy, "ik": ik_check, "consistency": consistency,
     "kernels": kernels, "cylinder": cylinder}[args.what](args)


if __name__ == "__main__":
    main()
