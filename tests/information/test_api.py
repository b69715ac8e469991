"""Public API of modalinfo.information: dispatch, units, caching and input validation.

References: the identity 1 bit = ln 2 nats; MutualInformation.fit(x).score(y) must
equal the one-shot estimate exactly (same arithmetic); a constant variable carries
no information (MI = 0); input-validation rules of DESIGN.md.
"""

import math

import numpy as np
import pytest

from modalinfo.information import (
    METHODS,
    MutualInformation,
    entropy,
    mutual_information,
    mutual_information_ci,
    mutual_information_permutation_test,
)


@pytest.fixture(scope="module")
def pair():
    rng = np.random.default_rng(31)
    x = rng.standard_normal(3000)
    return x, 0.5 * x + rng.standard_normal(3000)


@pytest.mark.parametrize("method", METHODS)
def test_bits_are_nats_over_ln2(pair, method):
    x, y = pair
    nats = mutual_information(x, y, method=method)
    bits = mutual_information(x, y, method=method, units="bits")
    assert bits == pytest.approx(nats / math.log(2.0), rel=1e-12)
    assert entropy(x, method=method, units="bits") == pytest.approx(
        entropy(x, method=method) / math.log(2.0), rel=1e-12)


@pytest.mark.parametrize("method", METHODS)
def test_fit_score_equals_one_shot_and_cache_is_reused(pair, method):
    x, y = pair
    rng = np.random.default_rng(0)
    est = MutualInformation(method).fit(x)
    ys = [y, np.sin(y), y + rng.standard_normal(y.size), y]
    for yy in ys:
        assert est.score(yy) == pytest.approx(mutual_information(x, yy, method=method),
                                              rel=1e-12, abs=1e-14)
    assert est.estimate(x, y) == est.score(y)


@pytest.mark.parametrize("method", METHODS)
def test_constant_input_gives_zero(pair, method):
    x, _ = pair
    c = np.full(x.size, 3.0)
    assert mutual_information(x, c, method=method) == 0.0
    assert mutual_information(c, x, method=method) == 0.0
    assert MutualInformation(method).fit(c).score(x) == 0.0
    assert entropy(c, method=method) == -math.inf


@pytest.mark.parametrize("method", METHODS)
def test_symmetry(pair, method):
    x, y = pair
    a = mutual_information(x, y, method=method)
    b = mutual_information(y, x, method=method)
    # histogram (same bins on both axes), KSG and Gaussian are exactly symmetric;
    # KDE whitens in a different order, equal up to the grid error (~1e-4 nats)
    assert a == pytest.approx(b, abs=1e-3 if method == "kde" else 1e-12)


def test_bad_inputs(pair):
    x, y = pair
    with pytest.raises(ValueError, match=r"`x` and `y` must have the same length; got 3000 and 29"):
        mutual_information(x, y[:-1], method="kde")
    with pytest.raises(ValueError, match=r"`x` needs at least 10 samples along axis 0; got 5"):
        mutual_information(x[:5], y[:5], method="kde")
    bad = y.copy()
    bad[3] = np.nan
    with pytest.raises(ValueError, match=r"`y` must be finite; got 1 NaN"):
        mutual_information(x, bad, method="kde")
    with pytest.raises(ValueError, match=r"`x` must be 1-D; got 2-D with shape \(3000, 1\)"):
        mutual_information(x[:, None], y, method="kde")
    with pytest.raises(ValueError, match=r"`method` must be one of 'kde', 'histogram'"):
        mutual_information(x, y, method="binning")
    with pytest.raises(ValueError, match=r"`units` must be one of 'nats', 'bits'; got 'bans'"):
        mutual_information(x, y, units="bans", method="kde")
    with pytest.raises(TypeError, match=r"method='histogram' does not accept option\(s\) bandw"):
        mutual_information(x, y, method="histogram", bandwidth=0.3)
    with pytest.raises(ValueError, match=r"`bins` must be one of 'hacine-gharbi'"):
        mutual_information(x, y, method="histogram", bins="rice")
    with pytest.raises(ValueError, match=r"`bins` must be an int >= 1; got 0"):
        mutual_information(x, y, method="histogram", bins=0)
    with pytest.raises(ValueError, match=r"`bins` as a sequence must be a pair"):
        mutual_information(x, y, method="histogram", bins=(3, 4, 5))
    with pytest.raises(ValueError, match=r"`bias_correction` must be one of"):
        mutual_information(x, y, method="histogram", bias_correction="jackknife")
    with pytest.raises(ValueError, match=r"`bandwidth` must be > 0.0; got -0.1"):
        mutual_information(x, y, method="kde", bandwidth=-0.1)
    with pytest.raises(ValueError, match=r"`grid_size` must be an int >= 32; got 8"):
        mutual_information(x, y, method="kde", grid_size=8)
    with pytest.raises(TypeError, match=r"`copula` must be a bool; got 'yes'"):
        mutual_information(x, y, method="kde", copula="yes")
    with pytest.raises(ValueError, match=r"`k` must be an int >= 1; got 0"):
        mutual_information(x, y, method="ksg", k=0)
    with pytest.raises(TypeError, match=r"`x` must be a numeric array"):
        mutual_information(["a"] * 20, y[:20], method="kde")
    est = MutualInformation("histogram")
    with pytest.raises(RuntimeError, match=r"not fitted"):
        est.score(y)
    with pytest.raises(ValueError, match=r"`y` must have the same length as `x` \(3000\); got 10"):
        est.fit(x).score(y[:10])
    with pytest.raises(TypeError, match=r"entropy method='gaussian' does not accept option\(s\) k"):
        entropy(x, method="gaussian", k=3)


def test_bad_inputs_uncertainty(pair):
    x, y = pair
    with pytest.raises(ValueError, match=r"`method`='ksg' cannot be bootstrapped"):
        mutual_information_ci(x, y, method="ksg")
    with pytest.raises(ValueError, match=r"`confidence_level` must be < 1.0; got 1.0"):
        mutual_information_ci(x, y, confidence_level=1.0)
    with pytest.raises(ValueError, match=r"`n_resamples` must be an int >= 10; got 2"):
        mutual_information_ci(x, y, n_resamples=2)
    with pytest.raises(ValueError, match=r"`bootstrap` must be one of 'block', 'iid'"):
        mutual_information_ci(x, y, bootstrap="stationary")
    with pytest.raises(ValueError, match=r"`interval`='bca' needs bootstrap='iid'"):
        mutual_information_ci(x, y, interval="bca")
    with pytest.raises(ValueError, match=r"`block_length` must be an int <= 3000; got 5000"):
        mutual_information_ci(x, y, block_length=5000)
    with pytest.raises(ValueError, match=r"`block_length` must be None, 'auto' or an int"):
        mutual_information_ci(x, y, block_length="long")
    with pytest.raises(ValueError, match=r"`n_permutations` must be an int >= 1; got 0"):
        mutual_information_permutation_test(x, y, n_permutations=0, method="histogram")
    with pytest.raises(ValueError, match=r"`permutation` must be one of 'shuffle', 'circular'"):
        mutual_information_permutation_test(x, y, permutation="block", method="histogram")
    with pytest.raises(ValueError, match=r"`min_shift` must be an int <= 1500; got 2000"):
        mutual_information_permutation_test(x, y, permutation="circular", min_shift=2000,
                                            method="histogram")
    with pytest.raises(ValueError, match=r"`x` and `y` must have the same length"):
        mutual_information_permutation_test(x, y[:100], method="histogram")
