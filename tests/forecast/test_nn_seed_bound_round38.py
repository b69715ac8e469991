"""``NeuralNetPredictor.random_state`` bound (adversarial round 38 PART a, R41 / R83).

Reference: scikit-learn's ``MLPRegressor`` takes an int seed in [0, 2**32 - 1] (numpy's
legacy ``RandomState`` bound); above it, it raised its own ``InvalidParameterError``
naming ``MLPRegressor`` and advising a ``RandomState`` or None, which this class refuses.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.forecast import NeuralNetPredictor


@pytest.mark.parametrize("seed", [2**32, 2**100])
def test_too_large_random_state_refused_in_our_words(seed):
    x = np.random.default_rng(0).standard_normal((120, 1))
    with pytest.raises(ValueError, match=r"`random_state` must be an int <= 4294967295"):
        NeuralNetPredictor(random_state=seed, n_patterns=50, max_iter=5).fit(x)


def test_largest_random_state_fits():
    x = np.random.default_rng(0).standard_normal((120, 1))
    NeuralNetPredictor(random_state=2**32 - 1, n_patterns=50, max_iter=5).fit(x)
