"""The random-state contract of the API (adversarial round 38 PART a).

References: numpy's seeding semantics (``np.random.default_rng(np.array(7))`` draws what
``default_rng(7)`` draws, so a 0-d integer array is that int) and the documented record
(``OrderingResult.seed`` / the synthetic logs' ``metadata["seed"]``: the int seed, None
only where the seed is not an int); Python's own iteration protocol for ``seeds``.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from modalinfo.bases import Pupil, ZernikeBasis
from modalinfo.ordering import order_modes, ordering_stability
from modalinfo.telemetry import synthetic


@pytest.fixture(scope="module")
def coeffs():
    return np.random.default_rng(0).standard_normal((300, 3))


@pytest.fixture(scope="module")
def basis():
    return ZernikeBasis(Pupil(16), modes=[2, 3, 4])


@pytest.mark.parametrize("seeds", [3, None, np.array(3)])
def test_one_seed_or_none_refused_naming_seeds(coeffs, basis, seeds):
    """Round 38 PART a R65 / R66: ``seeds=3`` or None raised "'int' object is not
    iterable" (no argument named); now a TypeError naming ``seeds``."""
    with pytest.raises(TypeError, match="`seeds` must be a sequence of ints"):
        ordering_stability(coeffs, basis, "variance", seeds=seeds)


def test_iterables_of_seeds_still_accepted(coeffs, basis):
    """A range, an iterator and an array of ints are sequences of seeds, as before."""
    for seeds in (range(2), iter([0, 1]), np.array([0, 1])):
        assert ordering_stability(coeffs, basis, "variance", seeds=seeds).seeds == (0, 1)


def test_zero_d_seed_recorded_as_its_int(coeffs, basis):
    """Round 38 PART a R84: ``seed=np.array(7)`` draws what ``seed=7`` draws (numpy) but
    the result recorded ``seed=None``, as for a Generator; now 7."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a = order_modes(coeffs, basis, "mi_greedy", sample_budget=500, seed=np.array(7))
        b = order_modes(coeffs, basis, "mi_greedy", sample_budget=500, seed=7)
    np.testing.assert_array_equal(a.mi, b.mi)  # the same draws
    assert a.seed == 7 and type(a.seed) is int
    assert order_modes(coeffs, basis, "variance", seed=np.random.default_rng(1)).seed is None


def test_synthetic_logs_record_a_zero_d_seed():
    """Round 38 PART a R85 / R86: ``kaos_like`` and ``open_loop_log`` recorded
    ``metadata["seed"] = None`` for ``seed=np.array(7)``; now 7, as for ``seed=7``."""
    log = synthetic.kaos_like(64, seed=np.array(7))
    assert log.metadata["seed"] == 7
    np.testing.assert_array_equal(log.coeffs, synthetic.kaos_like(64, seed=7).coeffs)
    ol = synthetic.open_loop_log(range(2, 4), n_frames=64, rate=500.0, diameter=8.0,
                                 layers=synthetic.Layer(0.15, 10.0), seed=np.array(7))
    assert ol.metadata["seed"] == 7
