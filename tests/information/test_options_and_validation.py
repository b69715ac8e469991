"""Estimator options that other tests do not reach, and their validation messages.

Written to kill surviving mutants of the mutation run (docs/MUTATION.md). References:
- a direct O(n^2) numpy leave-one-out KDE entropy at a fixed bandwidth factor;
- the unbiased sample variance (``numpy.var(ddof=1)``) in ``0.5 ln(2 pi e s^2)``;
- the Gaussian-copula estimate is a function of the ranks of both variables only
  (monotone transforms of y as well as of x leave it unchanged);
- the documented validation contract: errors name the argument, the rule and the value.
"""

import numpy as np
import pytest

from modalinfo.information import BiasRuleWarning, entropy, mutual_information


def _direct_loo_entropy(x, h):
    sd = x.std()
    u = (x - x.mean()) / sd
    k = np.exp(-0.5 * (u[:, None] - u[None, :]) ** 2 / h**2) / (np.sqrt(2 * np.pi) * h)
    np.fill_diagonal(k, 0.0)
    return -np.mean(np.log(k.sum(1) / (x.size - 1))) + np.log(sd)


@pytest.mark.parametrize("h", [0.25, 0.6])
def test_kde_entropy_fixed_bandwidth_against_direct_sum(h):
    # a normal sample (no point farther than 5 h from all others, where the grid
    # estimate floors the density), scaled so that the ln(sd) term matters
    x = 3.0 * np.random.default_rng(40).standard_normal(800) + 1.0
    assert entropy(x, method="kde", bandwidth=h) == pytest.approx(_direct_loo_entropy(x, h),
                                                                  abs=1e-5)


def test_gaussian_entropy_uses_unbiased_variance():
    x = np.random.default_rng(41).standard_normal(12)
    want = 0.5 * np.log(2 * np.pi * np.e * np.var(x, ddof=1))
    assert entropy(x, method="gaussian") == pytest.approx(want, rel=1e-14)


def test_copula_estimate_depends_on_ranks_of_both_variables():
    rng = np.random.default_rng(42)
    x = rng.standard_normal(3000)
    y = 0.6 * x + 0.8 * rng.standard_normal(3000)
    base = mutual_information(x, y, method="kde", copula=True)
    for fy in (np.exp(y), y**3):
        assert mutual_information(x, fy, method="kde", copula=True) == pytest.approx(
            base, abs=1e-9)
        assert mutual_information(np.exp(x), fy, method="kde", copula=True,
                                  bandwidth="cv") == pytest.approx(
            mutual_information(x, y, method="kde", copula=True, bandwidth="cv"), abs=1e-9)


def test_validation_messages_name_the_argument():
    x = np.random.default_rng(43).standard_normal(200)
    y = x + np.random.default_rng(44).standard_normal(200)
    with pytest.raises(ValueError, match=r"`bins\[0\]` must be an int >= 1; got 0"):
        mutual_information(x, y, method="histogram", bins=(0, 5))
    with pytest.raises(ValueError, match=r"`bins\[1\]` must be an int >= 1; got 0"):
        mutual_information(x, y, method="histogram", bins=(5, 0))
    # one x bin: plug-in 0 and Miller-Madow (K_xy - K_x - K_y + 1) / 2n = 0, with the
    # bias rule's warning since audit 9 (one bin merges x's 200 values)
    with pytest.warns(BiasRuleWarning, match="at least 4 bins"):
        assert mutual_information(x, y, method="histogram", bins=(1, 5)) == 0.0
    with pytest.raises(ValueError, match=r"`bandwidth` must be one of 'scott', 'silverman'"):
        mutual_information(x, y, method="kde", bandwidth="wide")
    with pytest.raises(ValueError, match=r"`bandwidth` must be one of 'scott', 'silverman'"):
        entropy(x, method="kde", bandwidth="wide")
    with pytest.raises(ValueError, match=r"`bandwidth` must be > 0.0; got 0.0"):
        entropy(x, method="kde", bandwidth=0.0)
    with pytest.raises(TypeError, match=r"`bandwidth` must be a real number; got"):
        entropy(x, method="kde", bandwidth=[0.3])
    with pytest.raises(ValueError, match=r"`grid_size` must be an int >= 32; got 16"):
        entropy(x, method="kde", grid_size=16)
    with pytest.raises(ValueError, match=r"`bins` must be an int >= 1; got 0"):
        entropy(x, method="histogram", bins=0)
    with pytest.raises(ValueError, match=r"`bias_correction` must be one of"):
        entropy(x, method="histogram", bias_correction="jackknife")
    with pytest.raises(ValueError, match=r"`binning` must be one of 'uniform', 'quantile'"):
        entropy(x, method="histogram", binning="equal")
    with pytest.raises(ValueError, match=r"`binning` must be one of 'uniform', 'quantile'"):
        mutual_information(x, y, method="histogram", binning="equal")
    with pytest.raises(ValueError, match=r"`seed` must be an int >= 0; got -1"):
        mutual_information(x, y, method="ksg", seed=-1)
