"""The circular-shift MI / CMI tests warn where both means step or drift (issue 27, left14-level).

References, outside the code under test: planted facts and measured sizes. Two
independent AR(1) 0.5 series of 2000 frames sharing a step of 2 marginal sd: the
aligned pair co-varies through the step, which every rotation breaks, so the test
rejects a null of independent noises (p <= 0.01 here, by construction of the step);
the rule must name the level. The same series without the step: no warning. A
step in one series only leaves the rotations valid (the other is stationary): no
warning. AR(1) 0.99 pairs of 200 frames: measured 10.0 % rejections at 5 % (400
draws, left14-level), so the MI test has the effective-pairs rule too (at 8 estimated
pairs); two slow waves of half a period over the record (< 1 effective pair) must warn.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.information import (
    conditional_mutual_information_test,
    mutual_information_permutation_test,
)
from modalinfo.information.resampling import RotationNullWarning


def ar1(rng, n, rho):
    e = rng.standard_normal(n + 3000)
    return lfilter([1.0], [1.0, -rho], e)[3000:] * math.sqrt(1 - rho * rho)


def _pair(seed, step_x, step_y, n=2000, rho=0.5):
    rng = np.random.default_rng(seed)
    x, y = ar1(rng, n, rho), ar1(rng, n, rho)
    x[n // 2:] += step_x
    y[n // 2:] += step_y
    return x, y


def test_mi_circular_test_names_the_shared_level_step():
    x, y = _pair(30, 2.0, 2.0)
    with pytest.warns(RotationNullWarning, match="stationary in level") as rec:
        res = mutual_information_permutation_test(x, y, "gaussian", n_permutations=99,
                                                  permutation="circular", seed=1)
    assert len(rec) == 1
    assert res.pvalue <= 0.05  # the rejection the warning explains


def test_cmi_circular_test_names_the_shared_level_step():
    rng = np.random.default_rng(31)
    x, y = _pair(31, 2.0, 2.0)
    z = ar1(rng, 2000, 0.5)
    with pytest.warns(RotationNullWarning, match="stationary in level") as rec:
        conditional_mutual_information_test(x, y, z, method="gaussian", n_surrogates=49,
                                            seed=1)
    assert len(rec) == 1


@pytest.mark.parametrize("steps", [(0.0, 0.0), (2.0, 0.0)])
def test_no_warning_without_a_shared_change(steps):
    x, y = _pair(32, *steps)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mutual_information_permutation_test(x, y, "gaussian", n_permutations=99,
                                            permutation="circular", seed=1)


def test_mi_circular_test_warns_few_effective_pairs():
    # half a period of two slow waves: lag-1 autocorrelations ~0.9999, < 1 effective pair
    rng = np.random.default_rng(33)
    t = np.arange(200)
    x = np.sin(2 * np.pi * t / 400 + 0.3) + 0.01 * rng.standard_normal(200)
    y = np.cos(2 * np.pi * t / 350) + 0.01 * rng.standard_normal(200)
    with pytest.warns(RotationNullWarning, match="effective pairs"):
        mutual_information_permutation_test(x, y, "gaussian", n_permutations=99,
                                            permutation="circular", seed=1)
