"""A branch that lives only between two samples of the 1-D search (an island) is found.

The arm below (axes 2, 3, 4 meet: the class '6R-spherical-middle', searched over q6) came out of
benchmarks/bench_coverage.py's dense check: for this target, SP3 has solutions for q6 only on an interval
about 0.015 rad wide, less than the search's step (1.5 degrees), and no sample of the search fell inside
it, so the search answered "unreachable" while Levenberg-Marquardt from random starts reached four
configurations. The target is the FK of one of them (the test's own POE.fk), so the law checked is the
plain one: the configuration that generated the target is among the solutions, every solution passes FK,
and nothing Levenberg-Marquardt reaches from 300 random starts is missing.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from armkit.ik.geometric import solvers as G
from armkit.ik.geometric.poe import POE

from test_dense_check import ik_all_misses   # same folder, on pytest's path

H = np.array([[0.5053153615672773, 0.6757777664671428, -0.5366384217634921],
              [0.04729237999017623, 0.7659360173609043, -0.6411750526214985],
              [-0.6918896663948987, 0.08534183610622581, -0.7169417413890572],
              [0.8872417968246721, -0.4347714929497068, -0.1541938484039179],
              [0.30326317191973284, -0.23578198367482572, -0.9232758551654792],
              [0.23284351596827574, 0.6478158895760275, 0.7253402444951966]])
P = np.array([[0.05031570840882769, -0.3713389598056643, 0.2822082593913328],
              [0.18813578117787214, 0.32357461777997404, -0.2454298968218931],
              [-0.2941806326171596, -0.03957366153247477, -0.23699240663794577],
              [0.5615439096784283, -0.16900546890998713, 0.2527425888862121],
              [-0.8605716281267273, -0.40081602865218224, 0.18667076843502353],
              [1.4472699845353179, 1.2999233750216392, -0.07775770554331046],
              [-0.015886001604538347, 0.41729972452990793, -0.0614875305375758]])
R_NT = np.array([[0.43198391734457847, 0.806107223621593, 0.4044515288396359],
                 [-0.8728085775357639, 0.486609716312829, -0.037632047113394525],
                 [-0.2271455087287207, -0.3367523244389478, 0.9137848706612168]])
Q_GEN = np.array([-0.9723891439896288, -3.118913592061787, 0.8457404282423275, 1.6313918826583436,
                  0.7101891304933359, 0.29854948072365195])


def _wrap(a):
    return (np.asarray(a) + math.pi) % (2 * math.pi) - math.pi


@pytest.fixture(scope="module")
def case():
    form = POE(H, P, R_NT, np.zeros(6, dtype=bool))
    R, p = form.fk(Q_GEN)
    return form, R, p


@pytest.mark.parametrize("jit", [True, False], ids=["compiled", "plain"])
def test_island_narrower_than_a_step_is_found(case, jit):
    form, R, p = case
    sol = G.spherical_middle(form, R, p, jit=jit)
    q = np.asarray(sol.q)
    assert len(q) >= 1, "the search lost the island"
    for x in q:                                           # every solution passes FK (the test's own POE.fk)
        Rq, pq = form.fk(x)
        assert np.abs(pq - p).max() < 1e-9 and np.abs(Rq - R).max() < 1e-9
    assert np.abs(_wrap(q - Q_GEN)).max(axis=1).min() < 1e-7   # the generating configuration is found


def test_island_against_a_dense_search(case):
    """Every distinct solution Levenberg-Marquardt reaches from 300 random starts is among ``ik_all``'s."""
    form, R, p = case
    assert ik_all_misses(form, R, p, 11) == []
