"""The 1-D searches act on an odd count: the twin of a solution found is looked for (solvers_check._paired).

The arm below (only axes 5 and 6 meet: the class '6R-two-intersecting', searched over q1) came out of
benchmarks/bench_coverage.py's dense check: for this target its two solutions lie 0.07 rad apart, the
search found one of them, and the other was missing. The real solutions of a 6R come in pairs (the others
are complex, in conjugate pairs), so one solution says that one is missing. The target is the FK of the one
that was missed (the test's own POE.fk); checked: it is found, every solution passes FK, the count is even,
and nothing Levenberg-Marquardt reaches from 300 random starts is missing.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from armkit.ik.geometric import solvers as G
from armkit.ik.geometric.poe import POE

from test_dense_check import ik_all_misses   # same folder, on pytest's path

H = np.array([[-0.3805095955108391, 0.922286535800985, 0.0678232526822186],
              [-0.9740962392449966, -0.16509279234294566, -0.15453441883659272],
              [-0.402588038371625, -0.723128045761676, -0.5612563592450301],
              [0.7627829227962857, 0.6128665020046766, -0.20629314920982592],
              [0.8320465326101575, -0.18484096931860147, 0.5230032348205642],
              [0.7241056674329921, 0.30161689393248853, 0.6202404627932131]])
P = np.array([[0.1604531681599257, -1.5112347516448557, 0.25910697458050486],
              [0.258970018765712, 0.7599365139806585, 1.024278993797313],
              [-0.6366300420847565, 0.9635098968014395, -1.6946851528656055],
              [0.26071377950830926, 0.7125373514353751, 0.3298034392417458],
              [-0.37687184588931893, -0.32516033699001834, 0.6017357179023125],
              [-0.3571628327406504, 0.05772249617464109, -0.23222163224858178],
              [0.19036448111382276, -0.14834616235672315, -0.17676273367628947]])
R_NT = np.array([[-0.8339556694557925, -0.22927532367423875, 0.5019469766186602],
                 [-0.24271004696833848, -0.6645013469202973, -0.706774216452283],
                 [0.4955903292873738, -0.7112459391062874, 0.49851724104753703]])
Q_GEN = np.array([-1.0230442061359053, 2.518021161518157, 1.069510402495878, 1.6522080417056144,
                  2.0496860078814287, -1.4080111190816298])


def _wrap(a):
    return (np.asarray(a) + math.pi) % (2 * math.pi) - math.pi


@pytest.fixture(scope="module")
def case():
    form = POE(H, P, R_NT, np.zeros(6, dtype=bool))
    R, p = form.fk(Q_GEN)
    return form, R, p


@pytest.mark.parametrize("jit", [True, False], ids=["compiled", "plain"])
def test_the_twin_of_a_solution_is_found(case, jit):
    form, R, p = case
    q = np.asarray(G.two_intersecting(form, R, p, jit=jit).q)
    for x in q:                                           # every solution passes FK (the test's own POE.fk)
        Rq, pq = form.fk(x)
        assert np.abs(pq - p).max() < 1e-9 and np.abs(Rq - R).max() < 1e-9
    assert np.abs(_wrap(q - Q_GEN)).max(axis=1).min() < 1e-7   # the generating configuration is found
    assert len(q) % 2 == 0


def test_odd_count_against_a_dense_search(case):
    """Every distinct solution Levenberg-Marquardt reaches from 300 random starts is among ``ik_all``'s."""
    form, R, p = case
    assert ik_all_misses(form, R, p, 17) == []
