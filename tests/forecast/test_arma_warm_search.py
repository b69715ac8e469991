"""The order search's warm starts (issue 30, aic4): what they guarantee by construction.

References (outside the search):
- nested models: ARMA(p - 1, q) and ARMA(p, q - 1) are ARMA(p, q) with one coefficient
  zero, so a search that starts each (p, q) from the better of its neighbours' fits and
  only accepts steps that lower the conditional sum of squares (CSS) gives every
  candidate a CSS no larger than its neighbours' (checked on two modes of the shipped
  KAOS log, where the Hannan-Rissanen starts alone broke it 3 and 5 times: high-order
  fits ended far above their nested neighbours);
- statsmodels ``hannan_rissanen(..., unbiased=False)`` with the same long-AR order, the
  Hannan-Rissanen start of every candidate with ``p <= q`` (the same regression rows,
  see ``test_hannan_rissanen_and_intervals.py``): its CSS, from ``scipy.signal.lfilter``
  on the same standardised series and burn-in, bounds the candidate's from above;
- the same data fitted twice, and one column fitted alone or inside a log: the same
  bits.
"""

import warnings
from pathlib import Path

import numpy as np
from scipy.signal import lfilter
from statsmodels.tsa.arima.estimators.hannan_rissanen import hannan_rissanen

from modalinfo.forecast import ARMAPredictor
from modalinfo.io import load

N, BURN, K = 3000, 50, 3
DATA = Path(__file__).resolve().parents[2] / "data"


def _series():
    """A closed-loop-like mode (AR root near 1 partly cancelled) and a plain ARMA(2, 3)."""
    e = np.random.default_rng(30).standard_normal((N + 500, 2))
    a = lfilter([1.0, -0.9, 0.1], [1.0, -1.2, 0.205], e[:, 0])[500:]
    b = lfilter([1.0, -0.5, 0.2, 0.15], [1.0, -1.3, 0.4], e[:, 1])[500:]
    return np.column_stack([a, b])


def _log_sigma2(crit, p, q, n=N):
    """``log sigma^2`` of the standardised series from the AIC table (penalty 2 (p + q + 1))."""
    return (crit[p, q] - 2.0 * (p + q + 1)) / (n - BURN)


def test_each_candidate_is_no_worse_than_its_nested_neighbours():
    x = np.ascontiguousarray(np.asarray(load(DATA / "kaos_closedloop.npz").coeffs)[:, [0, 3]])
    n, k = x.shape[0], 5
    crit = ARMAPredictor(order="aic", max_order=k, burn_in=BURN).fit(x).criterion_
    for m in range(x.shape[1]):
        for p in range(k + 1):
            for q in range(1, k + 1):
                here = _log_sigma2(crit[m], p, q, n)
                for pp, qq in ((p - 1, q), (p, q - 1)):
                    if pp >= 0:
                        # rounding of the padded start's re-enforced roots and of log/exp
                        assert here <= _log_sigma2(crit[m], pp, qq, n) + 1e-11, (m, p, q, pp, qq)


def test_each_candidate_is_no_worse_than_its_hannan_rissanen_start():
    x = _series()
    long_order = 35          # the default for N = 3000: max(20, ceil(10 log10 N))
    crit = ARMAPredictor(order="aic", max_order=K, burn_in=BURN).fit(x).criterion_
    checked = 0
    for m in range(x.shape[1]):
        xc = (x[:, m] - x[:, m].mean()) / x[:, m].std()
        for q in range(1, K + 1):
            for p in range(q + 1):
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")  # statsmodels' own chatter
                    ref, _ = hannan_rissanen(xc, ar_order=p, ma_order=q, demean=False,
                                             initial_ar_order=long_order, unbiased=False)
                ar, ma = np.r_[1.0, -ref.ar_params], np.r_[1.0, ref.ma_params]
                if max(np.abs(np.roots(ar)).max(initial=0), np.abs(np.roots(ma)).max()) > 0.99:
                    continue         # the search enforces such a start's roots first
                e = lfilter(ar, ma, xc)[BURN:]
                start = np.log(e @ e / (N - BURN))
                # the start agrees with the search's own to ~1e-10 (regression sums in
                # another order): far below the Newton steps' decrease, but allowed
                assert _log_sigma2(crit[m], p, q) <= start + 1e-8, (m, p, q)
                checked += 1
    assert checked >= 12     # most of the 2 x 9 candidates with p <= q have causal starts


def test_search_is_bit_reproducible_and_per_mode():
    x = _series()
    make = lambda: ARMAPredictor(order="aic", max_order=K, burn_in=BURN)  # noqa: E731
    a, b = make().fit(x).params_, make().fit(x).params_
    alone = make().fit(x[:, 1]).params_
    for key in ("orders", "phi", "theta", "sigma2", "criterion"):
        assert np.array_equal(a[key], b[key]), key
    assert np.array_equal(a["criterion"][1], alone["criterion"][0])
    p, q = a["orders"][1]
    assert np.array_equal(a["phi"][1, :p], alone["phi"][0, :p])
    assert np.array_equal(a["theta"][1, :q], alone["theta"][0, :q])
