"""Mutation round 36 (review36): the histogram CMI interval's grid-loss raise (fix53-b).

Plants that escaped stop 60's tests (docs/MUTATION.md, "Round 36"): the raise read only
in nats, never on columns with repeated values, never with equal-width bins.

References (outside the code): a bit is ln 2 nats (the interval in bits is the one in
nats over ln 2, the same seed and resamples); the documented scope of the raise (one x
and one y column without repeated values, rule-chosen quantile bins) on the iid Gaussian
triples of test_cmi_grid_loss_fix53b; the "normal" interval is symmetric about the
estimate, so the raise is ``high - (2 estimate - low)``.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from modalinfo.information import conditional_mutual_information_ci

from ._ar_coverage import iid_triple as _triple


def _ci(x, y, z, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the finite-sample bias rule's warning
        return conditional_mutual_information_ci(x, y, z, method="histogram",
                                                 n_resamples=19, seed=1, **kw)


def test_the_raise_in_bits_is_the_nats_one_over_ln_2():
    x, y, z = _triple(2000, 0.5, 53101)
    nats, bits = _ci(x, y, z), _ci(x, y, z, units="bits")
    raise_nats = nats.high - (2.0 * nats.estimate - nats.low)
    assert raise_nats > 0.05
    assert bits.high - (2.0 * bits.estimate - bits.low) == pytest.approx(
        raise_nats / math.log(2.0), rel=1e-9)
    assert "bits" in bits.note


@pytest.mark.parametrize("kind", ["repeated", "uniform"])
def test_no_raise_outside_its_scope(kind):
    x, y, z = _triple(2000, 0.5, 53101)
    opts = {}
    if kind == "repeated":
        x = np.round(x, 1)          # ~60 distinct values: ties in x
        assert np.unique(x).size < x.shape[0]
    else:
        opts["binning"] = "uniform"
    res = _ci(x, y, z, **opts)
    assert res.note == ""
    assert res.high - (2.0 * res.estimate - res.low) == pytest.approx(0.0, abs=1e-12)
