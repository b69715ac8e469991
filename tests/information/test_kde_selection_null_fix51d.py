"""The kde selection's null on an input that only follows a chosen one (fix51-d, issue 27).

References: the generating links. A mode w_t = z_t^2 + 0.3 e informs nothing about the
target beyond z_t, so a search that adds w after z must at least say it may be spurious;
the residual of w's fit on z must hold the noise's variance 0.09 (what is left once the
fit has the link); fix51-a's local mean left several times that in z's tails. A genuine second
input (y_t = sin 6 z_{t-1} + 0.3 x_{t-1} + e) must be added without a warning. Seeds
fixed.
"""

import warnings

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.information import BiasRuleWarning, select_inputs
from modalinfo.information.resampling import local_linear_split

from .test_nonlinear_nulls_fix51a import _log_with_square


def test_local_linear_split_keeps_a_steep_link_in_the_tails():
    """w = z^2 + 0.3 e, z AR(1) 0.6 of unit innovations (sd 1.25): the residual's mean
    square is the noise's 0.09 plus the leave-one-out line's own error (< 0.12 in all;
    measured 0.100). The local mean of fix51-a left 0.177 on this log, and 4.1 in the 2 %
    of rows of largest |z|, whose 20 neighbours are one-sided and far apart on a steep
    z^2; the line's extrapolation there leaves 0.31 (< 1 here). The parts sum to w; with
    5 z columns (more than k // 4 - 1 = 4) the split is the local mean and still sums to
    w."""
    rng = np.random.default_rng(11)
    z = lfilter([1.0], [1.0, -0.6], rng.standard_normal(2000))[:, None]
    w = z**2 + 0.3 * rng.standard_normal((2000, 1))
    fit, resid = local_linear_split(w, z, True)
    assert np.allclose(fit + resid, w, rtol=0, atol=1e-12)
    assert 0.08 < np.mean(resid**2) < 0.12
    tails = np.abs(z[:, 0]) > np.quantile(np.abs(z[:, 0]), 0.98)
    assert np.mean(resid[tails] ** 2) < 1.0
    z5 = np.column_stack([z, rng.standard_normal((2000, 4))])
    fit, resid = local_linear_split(w, z5, False)
    assert np.allclose(fit + resid, w, rtol=0, atol=1e-12)


@pytest.mark.slow
def test_kde_selection_does_not_add_a_following_input_silently():
    """The kde search added w[t] after z[t] on this log (fix51-a: 4 of 4 logs, silently;
    fix51-d: the local-linear null still added it in some logs, see docs/ADVERSARIAL.md).
    Where it adds w, fix50-e's local-permutation check, extended to the kde, must warn
    (``BiasRuleWarning``). ~35 s of CPU (one kde search with 19 surrogates and the
    check's 39 local permutations)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = select_inputs(_log_with_square(6100), 2, max_lag=3, method="kde",
                               n_surrogates=19, intervals=False, seed=0)
    picks = [(i.source, i.lag) for i in result.inputs]
    assert picks[0] == (1, 0)
    warned = [str(w.message) for w in caught if issubclass(w.category, BiasRuleWarning)]
    if any(source == 3 for source, _ in picks):
        assert any("local permutations" in m for m in warned), (picks, warned)


@pytest.mark.slow
def test_kde_selection_keeps_a_genuine_second_input_unwarned():
    """y_t = sin 6 z_{t-1} + 0.3 x_{t-1} + 0.3 e: x[t] informs beyond z[t]; the kde search
    adds it, and the local-permutation check does not flag it (a ``BiasRuleWarning`` is
    an error here: filterwarnings = error). ~35 s of CPU."""
    result = select_inputs(_log_with_square(6100, genuine=True), 2, max_lag=3,
                           method="kde", n_surrogates=19, intervals=False, seed=0)
    picks = [(i.source, i.lag) for i in result.inputs]
    assert picks[0] == (1, 0) and (0, 0) in picks
