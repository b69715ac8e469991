"""An MI ordering holds one copy of its contributions (round 42 PART b, S02 / S16).

docs/ADVERSARIAL.md, "Round 42 PART b, issue 27": ``modalinfo reorder`` of a 20,000 x 400
log (gaussian, ``--resamples 0``) passed its memory check (3 log copies + 1 copy of the
contributions, ``ordering.cost.ordering_memory_bytes``: 793 MiB) and ran out of memory
allocating a (200000, 400) float64 array in ``_nodal`` (the pile warning's exact-zero
flags gathered ``view.matrix[pixels]``, a second copy); below 40,000 samples the pile
warning's dict of every mode's masked row was another.

Reference: tracemalloc's peak of the traced allocations during ``order_modes``, against
the float64 size of the (M, n) contributions, 8 M n bytes, computed here. One copy plus
the per-sample index and sum arrays (a few n-length arrays, < 0.35 of a copy at M >= 40)
stays below 1.5 copies; a second copy reaches 2.1 - 2.3 (measured before the fix).
"""

from __future__ import annotations

import tracemalloc
import warnings

import numpy as np
import pytest

from modalinfo.bases import Pupil, ZernikeBasis
from modalinfo.ordering import order_modes


@pytest.mark.parametrize(("n_modes", "budget"), [(100, 20_000), (40, 100_000)])
def test_order_modes_peak_is_one_copy_of_the_contributions(n_modes, budget):
    rng = np.random.default_rng(0)
    coeffs = rng.standard_normal((400, n_modes)) * np.arange(2, n_modes + 2) ** -0.9
    basis = ZernikeBasis(Pupil(32), range(2, n_modes + 2))
    tracemalloc.start()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            order_modes(coeffs, basis, "mi_marginal", estimator="gaussian",
                        sample_budget=budget, seed=0, n_resamples=0)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    copies = peak / (8.0 * n_modes * budget)
    assert copies < 1.5, f"{copies:.2f} copies of the contributions"
