"""The kde entropy's lattice refusal sits at n / 10 distinct values (review12, round 12).

Reference (outside the code): the rule as documented (a sample of ``<= n / 10`` distinct
values is a lattice: ``method='kde'`` refused, the histogram named) and the exact
entropy of the dequantised law of a sample spread evenly over L integers, ``ln L``
(uniform density on [0, L), unit cells). 2000 samples on exactly 200 integers (10 each)
are refused; on exactly 250 (8 each) the kde runs, and lands near ``ln 250`` (measured
0.06 nats off; 0.2 allowed).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from modalinfo.information import entropy


def _even(levels: int, n: int = 2000) -> np.ndarray:
    return np.random.default_rng(3).permutation(np.repeat(np.arange(levels), n // levels))


def test_n_over_10_levels_is_a_lattice():
    x = _even(200).astype(float)
    assert np.unique(x).size == 200 and x.size == 2000
    with pytest.raises(ValueError, match=r"`x` takes only 200 distinct values.*histogram"):
        entropy(x, method="kde")


def test_more_levels_are_estimated():
    x = _even(250).astype(float)
    assert np.unique(x).size == 250 and x.size == 2000
    assert entropy(x, method="kde") == pytest.approx(math.log(250), abs=0.2)
