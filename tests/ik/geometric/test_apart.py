"""The one-call kernel's shortcut with least-squares candidates (:func:`.solvers_check._apart`) against the check it
stands for (:func:`.solvers_check._check`).

For candidates of a random arm (a spherical wrist, axes 1 and 2 meeting, ideal = true chain) with some rows flagged
least-squares, ``_apart`` must answer -1 where the check would keep a least-squares row (one that passes), and
otherwise the others in their order, wrapped as the check wraps them: the passing rows of the check, to the bit.
"""

from __future__ import annotations

import numpy as np
import pytest

import armkit
from armkit.ik.analytic import closed_form
from armkit.ik.geometric import one_call as OC
from armkit.ik.geometric import solvers as G

from test_family import _random_arm   # same folder, on pytest's path

pytest.importorskip("numba")


def _parts(robot):
    cf = closed_form(robot)
    g = OC.geometry(cf.form, cf.solver, cf.m, cf.inverted)
    assert g is not None and not cf.inverted and g[OC.EXACT] == 1.0
    rows = lambda a, b, k: np.array(g[a:b]).reshape(k, 3)  # noqa: E731
    return (int(g[OC.WHICH]), int(g[OC.KIND]), rows(OC.HI, OC.PI, 6), rows(OC.PI, OC.RNT, 7),
            rows(OC.RNT, OC.PRISM, 3), g[OC.PRISM:OC.HT] != 0, rows(OC.HT, OC.PT, 6), rows(OC.PT, OC.REACH, 7),
            g[OC.TOL_P], g[OC.TOL_R])


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_apart_answers_as_the_check(seed):
    K = G.kernels()
    if K is None:
        pytest.skip("no Numba")
    rng = np.random.default_rng(seed)
    robot = _random_arm(rng, "spherical-wrist-meet")
    which, kind, Hi, Pi, RnT, prism, Ht, Pt, tol_p, tol_r = _parts(robot)
    seen = {"kept": 0, "apart": 0}
    for _ in range(30):
        t = armkit.fk(robot, rng.uniform(-np.pi, np.pi, 6))
        R, p = t[:3, :3].copy(), t[:3, 3].copy()
        Q0, LS0, SG0 = np.zeros((32, 6)), np.zeros(32, bool), np.zeros(32, bool)
        mc = K._closed_core(which, kind, Hi, Pi, RnT, prism, R, p, np.zeros(6), 64, Q0, LS0, SG0)
        if mc < 3 or LS0[:mc].any():
            continue
        for case in ("passes", "fails"):
            Q, LS, SG = Q0.copy(), LS0.copy(), SG0.copy()
            j = int(rng.integers(mc))
            LS[j] = True                   # flagged least-squares: an exact answer ("passes") or one moved off
            if case == "fails":
                Q[j] += 0.3
            W = np.full((8, 6), np.nan)
            k = K._apart(Q, LS, SG, prism, mc, W, False, Ht, Pt, RnT, R, p, tol_p, tol_r, np.empty(18),
                         np.empty((7, 3, 3)), np.empty((7, 3)))
            Qc, LSc, SGc, ST = Q.copy(), LS.copy(), SG.copy(), np.zeros(32, np.int64)
            ng, nf = K._check(mc, Ht, Pt, RnT, prism, R, p, tol_p, tol_r, Qc, LSc, SGc, ST)
            if case == "passes":
                assert k == -1 and ng == mc   # the check keeps the row: the kernel must go its long way
                seen["kept"] += 1
            else:
                assert k == mc - 1 == ng and nf == 1
                assert np.array_equal(W[:k], Qc[:k])   # the passing rows, in order, to the bit
                assert not LSc[:k].any()
                seen["apart"] += 1
    assert seen["kept"] > 0 and seen["apart"] > 0
