"""Planted-bug review 26 (stop 50): the effective-sample rule on groups of columns.

Fixes 40-a made ``convergence.effective_sample_rule`` take groups of columns (a CMI's
multivariate x or y): "the most persistent pair of columns (the largest product)"
counts, and "sorted samples (a column of x or y monotone) are not judged";
``conditional.count_failures`` returns the count and "the first of them". References:
Bartlett's n (1 - p) / (1 + p) of statsmodels' ``acf`` lag-1s corrected by
r + (1 + 3 r) / n (Marriott & Pope 1954), pair by pair by hand; the docstrings'
promises. Plants R26-B6 (``argmin``: the least persistent pair counted), R26-B7
(``all``: a group judged unless every column is monotone) and R26-B3 (the last reason
named) escaped tests/information/test_effective_sample_roads_fix40a.py, whose pairs
were single columns.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.signal import lfilter
from statsmodels.tsa.stattools import acf

from modalinfo.information import BiasRuleWarning, conditional_mutual_information
from modalinfo.information.conditional import count_failures
from modalinfo.information.convergence import effective_pairs, effective_sample_rule
from modalinfo.information.ksg import ksg_cmi


def _ar1(n, rho, seed):
    e = np.random.default_rng(seed).normal(size=n + 2000)
    return lfilter([1.0], [1.0, -rho], e)[2000:]


def _bartlett(a, b):
    n = a.size
    ra, rb = (acf(s, nlags=1, fft=False)[1] for s in (a, b))
    p = max(0.0, (ra + (1 + 3 * ra) / n) * (rb + (1 + 3 * rb) / n))
    return n * (1 - p) / (1 + p)


N = 1000
A = _ar1(N + 1, 0.999, 40)
WHITE = np.random.default_rng(41).standard_normal(N)
Y = A[:-1]  # the persistent mode's last sample


def test_a_group_counts_its_most_persistent_pair_of_columns():
    x = np.column_stack([WHITE, A[1:]])
    by_hand = [_bartlett(WHITE, Y), _bartlett(A[1:], Y)]
    assert by_hand[1] < 20 < 0.5 * N < by_hand[0]
    assert effective_pairs(x, Y) == pytest.approx(min(by_hand), rel=1e-6)
    assert "effective samples" in effective_sample_rule(x, Y)


def test_the_cmi_of_a_group_holding_a_persistent_column_warns():
    x = np.column_stack([WHITE, A[1:]])
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        conditional_mutual_information(x, Y)
    msgs = [str(w.message) for w in rec if issubclass(w.category, BiasRuleWarning)]
    assert len(msgs) == 1 and "effective samples" in msgs[0], msgs


def test_a_group_with_one_monotone_column_is_not_judged():
    ramp = np.arange(N, dtype=float)  # sorted samples: not read as time
    assert effective_sample_rule(np.column_stack([ramp, A[1:]]), Y) is None
    assert effective_sample_rule(A[1:], Y) is not None  # the persistent pair alone: judged


def test_count_failures_names_the_first_reason():
    assert count_failures([None, "first", None, "second"]) == (2, "first")
    assert count_failures([None, None]) == (0, None)


def _n_eff_given(a, b, z):
    """Bartlett by hand on numpy lstsq residuals of a and b on z and a constant."""
    design = np.column_stack([np.ones(a.size), z])
    ra = a - design @ np.linalg.lstsq(design, a, rcond=None)[0]
    rb = b - design @ np.linalg.lstsq(design, b, rcond=None)[0]
    return _bartlett(ra, rb)


def test_y_is_judged_by_its_residuals_on_z_too():
    # y = z + white: its residual on z is white, so (x, y | z) holds ~n effective pairs
    # although x and y are each persistent. Plant R26-B1 (y judged raw) escaped
    z = _ar1(N, 0.999, 50)
    y = z + np.random.default_rng(51).standard_normal(N)
    x = _ar1(N, 0.999, 52)
    assert _bartlett(x, y) < 20  # raw: persistent pair
    assert _n_eff_given(x, y, z) > 0.5 * N  # residuals on z: not
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        conditional_mutual_information(x, y, z)
    msgs = [str(w.message) for w in rec if issubclass(w.category, BiasRuleWarning)]
    assert not any("effective samples" in m for m in msgs), msgs


def test_a_point_estimate_warns_once_when_the_bias_rule_spoke_first():
    # KSG over 11 columns at n = 1000 fails the bias rule (ball side 0.59 > 0.4); the
    # persistent pair also fails the effective-sample rule (by hand below 20), but
    # "a point estimate: one warning at most" - the rule runs "last, when no other rule
    # spoke". Plant R26-B8 (judged left True after fallback='none' warned) escaped
    z = np.random.default_rng(1).standard_normal((N, 9))
    assert _n_eff_given(A[1:], Y, z) < 20
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        conditional_mutual_information(A[1:], Y, z, fallback="none")
    msgs = [str(w.message) for w in rec if issubclass(w.category, BiasRuleWarning)]
    assert len(msgs) == 1 and "neighbour ball" in msgs[0], msgs


def test_each_selection_gain_is_judged_given_the_inputs_before_it():
    # select_inputs' gains: "the target and each input given the inputs before it".
    # c1 = c0 + w: given c0, the target's and c1's residuals are white (n_eff ~ n by
    # hand), so of the two gains only the first (raw, both persistent) fails. Plant
    # R26-B5 (every gain judged raw: "2 of 2") escaped
    from modalinfo.information import selection

    rng = np.random.default_rng(60)
    c0 = _ar1(N, 0.999, 61)
    w = rng.standard_normal(N)
    C = np.column_stack([c0, c0 + w])
    y = c0 + 0.5 * w + rng.standard_normal(N)
    assert _bartlett(y, c0) < 20 and _n_eff_given(y, C[:, 1], c0) > 0.5 * N
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        selection._judge_gains(y, C, [0, 1], "ksg", {},  # the gains as the search's KSG
                               [ksg_cmi(y[:, None], C[:, :1], C[:, :0]),
                                ksg_cmi(y[:, None], C[:, 1:], C[:, :1])])
    msgs = [str(m.message) for m in rec]
    assert len(msgs) == 1 and "1 of 2 gains fail the effective-sample rule" in msgs[0], msgs


def test_the_map_never_judges_a_targets_own_past_as_its_largest_cell():
    # "no self-links": a persistent target (column 1) whose only source is white holds
    # ~n effective pairs with it (by hand), so the map is quiet, also where the source's
    # KSG TE estimate is below 0 (seed 0: -0.011 nats) and a self cell of 0 would be the
    # largest. Plant R26-B4 (target 0's row excluded for every target) escaped
    from modalinfo.information import transfer_entropy_map

    white = np.random.default_rng(0).standard_normal(N)
    series = np.column_stack([white, _ar1(N, 0.999, 100)])
    assert _bartlett(series[1:, 1], white[:-1]) > 0.5 * N
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        m = transfer_entropy_map(series, lags=1, history=0, n_surrogates=0, method="ksg")
    assert m.te[0, 1, 0] < 0  # the case: the source's estimate below the self cell's 0
    msgs = [str(w.message) for w in rec if issubclass(w.category, BiasRuleWarning)]
    assert msgs == [], msgs
