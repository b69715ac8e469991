"""Planted-bug review round 25 (review25, issue 27): which methods have a seed
stability to report (round 36 PART b, R03; the batch row, round 37 PART b, B06).

Reference: the definition of the seeds' comparison - the seeds draw the MI's (frame,
pixel) samples, for both MI methods, ``mi_greedy`` and ``mi_marginal``: two seeds give
two different ``mi_marginal`` score vectors (checked here with ``order_modes``), so
their agreement is a measurement and is reported, not "not assessed".
"""

import warnings

import numpy as np

from modalinfo.bases import Pupil, ZernikeBasis
from modalinfo.ordering import order_modes, ordering_stability
from modalinfo.telemetry import ModalLog


def test_mi_marginal_seeds_are_assessed():
    """R25-T2: mi_marginal is an MI method: its seeds act and are compared."""
    rng = np.random.default_rng(36)
    x = rng.standard_normal((400, 5)) * np.array([3.0, 2.0, 1.5, 1.0, 0.5])
    log = ModalLog(x, rate=1000.0, modes=[2, 3, 4, 5, 6], units="rad")
    basis = ZernikeBasis(Pupil(16), modes=[2, 3, 4, 5, 6])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the small budget's and coarse pupil's notes
        a, b = (order_modes(log, basis, "mi_marginal", sample_budget=500, seed=s,
                            n_resamples=0) for s in (0, 1))
        assert not np.array_equal(a.scores, b.scores)  # the seeds act
        stab = ordering_stability(log, basis, "mi_marginal", window=200, seeds=(0, 1, 2),
                                  sample_budget=500, n_resamples=0)
    assert stab.seeds_not_assessed is None
    assert "3 seeds on the whole log: median Spearman" in stab.summary()
    assert "not assessed" not in stab.summary()
