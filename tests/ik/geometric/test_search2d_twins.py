"""Two solutions of a general 6R within one grid cell of the 2-D search: both are found.

The arm below (no two axes meet or are parallel: the class '6R-general', the 2-D search over q1, q2)
came out of benchmarks/bench_coverage.py's dense check: for this target two of its four solutions lie
0.0026 rad apart, inside one cell of the 100 x 100 grid; their windings cancel, and Newton from the cell
found only one of them. The real solutions of a general 6R come in pairs (the others are complex, in
conjugate pairs), so three solutions say that one is missing. The target is the FK of the one that was
missed (the test's own POE.fk); checked: it is found, every solution passes FK, the count is even, and
nothing Levenberg-Marquardt reaches from 300 random starts is missing.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from armkit.ik.geometric.poe import POE
from armkit.ik.geometric.search2d import gen_six_dof

from test_dense_check import ik_all_misses   # same folder, on pytest's path

H = np.array([[-0.9213647868700736, 0.29742220179060236, -0.25025379796897035],
              [-0.5773054039433662, 0.30168160467723326, -0.758753372300352],
              [0.25827941536977667, 0.9122257842244504, -0.3180186506988746],
              [-0.2338940749567354, 0.8709768175960093, -0.4320797899815044],
              [-0.0863613154885782, -0.9156521397369646, -0.3925848725845161],
              [0.5690190430034422, 0.7917123463247308, 0.2222811044070923]])
P = np.array([[0.027257924665504356, -0.4032826596077723, -0.46923729120820684],
              [-0.5227075416541064, 0.656956197219959, 1.272311675061557],
              [1.3817146166332388, 0.19405726103892906, -0.28706965695912756],
              [-1.6405171793798419, -0.7682694541144741, -0.4929397502693875],
              [0.47113736032531256, 1.1708621246789042, 0.21651857712773703],
              [0.1990746381701851, -1.4027747553893075, -0.9974912744590252],
              [0.3670683468483007, 0.07288533085964766, -0.18487396509383602]])
R_NT = np.array([[-0.34733397605899013, 0.23041578188455425, 0.9089926713310639],
                 [0.12553620928463755, -0.9491920755655117, 0.28857419122658734],
                 [0.9293006882777478, 0.2143431154531558, 0.3007611338327115]])
Q_GEN = np.array([1.327448389909279, -1.6874864131362841, -2.8228681407352547, -2.4371807548018305,
                  -0.7085201145803046, 2.795368735760448])


def _wrap(a):
    return (np.asarray(a) + math.pi) % (2 * math.pi) - math.pi


@pytest.fixture(scope="module")
def case():
    form = POE(H, P, R_NT, np.zeros(6, dtype=bool))
    R, p = form.fk(Q_GEN)
    return form, R, p


def test_both_of_two_close_solutions_are_found(case):
    form, R, p = case
    q = np.asarray(gen_six_dof(form, R, p).q)
    for x in q:                                           # every solution passes FK (the test's own POE.fk)
        Rq, pq = form.fk(x)
        assert np.abs(pq - p).max() < 1e-9 and np.abs(Rq - R).max() < 1e-9
    assert np.abs(_wrap(q - Q_GEN)).max(axis=1).min() < 1e-7   # the generating configuration is found
    assert len(q) % 2 == 0


def test_close_solutions_against_a_dense_search(case):
    """Every distinct solution Levenberg-Marquardt reaches from 300 random starts is among ``ik_all``'s."""
    form, R, p = case
    assert ik_all_misses(form, R, p, 13) == []
