"""``armkit._jit_twins.parallel_twin``: the ``parallel=True`` copy of a kernel keeps the serial kernel's reference
counting (a kernel compiled without counts, such as the batch driver ``_single._rows``, has a twin without them) and
gives the serial kernel's numbers."""

from __future__ import annotations

import numpy as np
import pytest

numba = pytest.importorskip("numba")

from armkit._jit_twins import parallel_twin  # noqa: E402


def _scaled(x, out):
    for i in numba.prange(x.shape[0]):
        row = x[i]   # a view: counted up and down where the kernel counts references
        for j in range(row.shape[0]):
            out[i, j] = 2.0 * row[j] + 1.0
    return out.shape[0]


@pytest.mark.parametrize("counted", [True, False])
def test_the_twin_keeps_the_serial_kernels_counting_and_its_numbers(counted):
    options = {} if counted else {"_nrt": False}
    serial = numba.njit(cache=False, **options)(_scaled)
    twin = parallel_twin(serial)
    assert twin.targetoptions.get("_nrt", True) is counted
    assert twin.targetoptions["parallel"] is True
    x = np.random.default_rng(3).normal(size=(257, 5))
    a, b = np.empty_like(x), np.empty_like(x)
    assert serial(x, a) == twin(x, b) == 257
    assert np.array_equal(a, b) and np.array_equal(a, 2.0 * x + 1.0)


def test_the_batch_drivers_twin_counts_no_references():
    from armkit.ik.analytic import _single

    assert _single._rows.targetoptions["_nrt"] is False
    assert _single._ROWS_PAR.targetoptions["_nrt"] is False
