"""derive --ik --python: the closed-form IK branches exported as functions agree with armkit.ik_all (issue 11).

The test executes OUR generated module text (never user text) and compares every branch with the solver on
random targets, inside and outside the reach."""

from __future__ import annotations

import numpy as np
import pytest
from typer.testing import CliRunner

import armkit
from armkit.cli import app

pytest.importorskip("sympy")

runner = CliRunner()


def load_generated(robot: str, tmp_path) -> dict:
    out = tmp_path / f"{robot}_ik.py"
    res = runner.invoke(app, ["derive", robot, "--ik", "--python", "-o", str(out)])
    assert res.exit_code == 0, res.output
    text = out.read_text()
    assert "import numpy as np" in text and "BRANCHES" in text
    ns: dict = {}
    exec(compile(text, str(out), "exec"), ns)           # our own generated file
    return ns


def wrap(a):
    return np.angle(np.exp(1j * np.asarray(a)))


def test_fighter_every_branch_matches_ik_all(tmp_path):
    ns = load_generated("fighter", tmp_path)
    r = armkit.load("fighter")
    assert sorted(ns["BRANCHES"]) == sorted(["front/elbow-down", "front/elbow-up", "back/elbow-down", "back/elbow-up"])
    rng = np.random.default_rng(11)
    P = armkit.fk(r, r.random_q(300, rng=rng))[:, :3, 3]          # reachable targets
    far = rng.normal(size=(40, 3)) * 400.0                          # mostly out of reach
    targets = np.vstack([P, far])
    res = armkit.ik_all(r, targets, scene=False)     # the closed form alone: no collision verdicts
    labels = np.asarray(res.branch).astype(str)
    checked = 0
    for name, f in ns["BRANCHES"].items():
        q = np.stack(f(targets[:, 0], targets[:, 1], targets[:, 2]), axis=-1)
        hit = labels == name
        qa = np.asarray(res.q)[hit]                                  # ik_all's solution of this branch per target
        ok = np.asarray(res.success)[hit]
        mine = np.isfinite(q).all(axis=-1)
        rr = np.hypot(targets[:, 0], targets[:, 1]) ** 2 + (targets[:, 2] - 36.0) ** 2   # from the shoulder
        reach = (rr >= 22.8**2 - 1e-6) & (rr <= 177.2**2 + 1e-6)                         # |a3 - a2| .. a2 + a3
        assert np.array_equal(mine, reach) and np.array_equal(ok, reach), name          # NaN exactly out of reach
        np.testing.assert_allclose(wrap(q[ok] - qa[ok]), 0.0, atol=1e-7)
        # the exported solution puts the end point on the target
        np.testing.assert_allclose(armkit.fk(r, q[mine])[:, :3, 3], targets[mine], atol=1e-8)
        checked += int(ok.sum())
    assert checked >= 4 * 290


def test_planar2_both_branches_match_ik_all(tmp_path):
    ns = load_generated("planar2", tmp_path)
    r = armkit.load("planar2")
    rng = np.random.default_rng(3)
    xy = rng.uniform(-1.7, 1.7, size=(500, 2))
    rad = np.hypot(*xy.T)
    inside = (rad > 0.5 + 1e-9) & (rad < 1.5 - 1e-9)
    res = armkit.ik_all(r, xy)
    qa = np.asarray(res.q)
    down = np.stack(ns["ik_elbow_down"](xy[:, 0], xy[:, 1]), axis=-1)
    up = np.stack(ns["ik_elbow_up"](xy[:, 0], xy[:, 1]), axis=-1)
    for q, sign in ((down, 1), (up, -1)):
        assert np.array_equal(np.isfinite(q).all(axis=-1), inside)        # NaN exactly out of reach
        assert np.all(sign * q[inside, 1] >= 0)
        # the same solution as one of ik_all's two branches (ik_all names them by the elbow's side, not q2's sign)
        err = np.min([np.linalg.norm(wrap(q[inside] - qa[inside, b]), axis=-1) for b in range(2)], axis=0)
        assert err.max() < 1e-9
        np.testing.assert_allclose(armkit.fk(r, q[inside])[:, :2, 3], xy[inside], atol=1e-12)


def test_ik_export_mistakes_exit_2(tmp_path):
    for args, msg in ((["derive", "puma560", "--ik", "--python"], "planar 2R"),
                      (["derive", "fighter", "--ik", "--png", str(tmp_path / "x.png")], "--png"),
                      (["derive", "fighter", "--ik", "--python", "-o", str(tmp_path / "x.txt")], "--output")):
        res = runner.invoke(app, args)
        assert res.exit_code == 2 and msg in res.output and "Traceback" not in res.output, res.output
