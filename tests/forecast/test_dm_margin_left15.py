"""The Diebold-Mariano rule's margin ``_DM_MARGIN_Z``, pinned in the fast tier.

Reference: the one-sided 95 % normal quantile ``scipy.stats.norm.ppf(0.95)`` and the
documented rule for the number of cosine terms B (left14-dm) written out with
``statsmodels``: the order by AIC on the innovation variance of Burg's recursion
(``pacf_burg``), the coefficients from ``statsmodels``' ``burg``, the closed-form AR
spectrum ``1 / |1 - sum_k phi_k exp(-i w k)|^2`` at ``w = pi j / N``, its cumulative
mean ratio to ``f(0)``, and the delta-method standard error from a central
finite-difference gradient and ``sigma^2 Gamma_p^-1 / N`` (``acovf``; Brockwell &
Davis 1991, Thm 8.1.1). B is the largest j whose ratio less ``z`` standard errors is
at least 0.98. The series is chosen so that this lower bound sits just above 0.98 at
the B of ``z = norm.ppf(0.95)`` and just below it one term further, and a 10 % change
of ``z`` either way moves B (checked in the test, with a gap of > 1e-5 from 0.98 at
every term, far beyond the 1e-9 agreement of the two Burg recursions).
"""

import numpy as np
from scipy.signal import lfilter
from scipy.stats import norm
from statsmodels.regression.linear_model import burg
from statsmodels.tsa.stattools import acovf, pacf_burg

from modalinfo.forecast.evaluate import _dm_terms

Z95 = norm.ppf(0.95)


def _lower_bound_terms(d):
    """Terms j, the mean spectrum ratio over 1..j and its delta-method se (statsmodels)."""
    n = d.size
    p_max = max(1, min(20, n // 10))
    pacf = pacf_burg(d, p_max, demean=True)[0]
    innov = np.r_[np.var(d), np.var(d) * np.cumprod(1 - pacf[1:] ** 2)]
    order = int(np.argmin(n * np.log(innov) + 2 * np.arange(p_max + 1)))
    assert order >= 1
    phi = burg(d, order)[0]
    j = np.arange(1, int(np.floor(0.4 * n ** (2.0 / 3.0))) + 1)

    def mean_ratio(coef):
        def spectrum(w):
            return 1 / np.abs(1 - np.exp(-1j * np.outer(w, np.arange(1, coef.size + 1)))
                              @ coef) ** 2
        return np.cumsum(spectrum(np.pi * j / n)) / j / spectrum(np.zeros(1))

    share = mean_ratio(phi)
    step = 1e-6
    grad = np.array([(mean_ratio(phi + step * e) - mean_ratio(phi - step * e)) / (2 * step)
                     for e in np.eye(phi.size)])
    gamma = acovf(d, demean=True, fft=False, nlag=phi.size - 1)
    lag = np.abs(np.subtract.outer(np.arange(phi.size), np.arange(phi.size)))
    cov = innov[order] * np.linalg.inv(gamma[lag]) / n
    se = np.sqrt(np.einsum("ib,ij,jb->b", grad, cov, grad))
    return j, share, se


def _terms(j, share, se, z):
    ok = share - z * se >= 0.98
    return int(j[ok].max()) if ok.any() else int(share[0] >= 0.98)


def test_terms_sit_at_the_one_sided_95_percent_margin():
    rng = np.random.default_rng(5)
    d = lfilter([1.0], [1.0, -0.5], rng.standard_normal(1000))   # AR(1) 0.5 losses
    j, share, se = _lower_bound_terms(d)
    b = _terms(j, share, se, Z95)
    # the series sits at the margin's edge: 10 % less margin takes a term more, 10 %
    # more a term fewer; no term's bound within 1e-5 of 0.98 (no rounding luck)
    assert _terms(j, share, se, 0.9 * Z95) > b > _terms(j, share, se, 1.1 * Z95)
    for z in (0.9 * Z95, Z95, 1.1 * Z95):
        assert np.min(np.abs(share - z * se - 0.98)) > 1e-5
    assert share[b - 1] - Z95 * se[b - 1] >= 0.98 > share[b] - Z95 * se[b]
    assert _dm_terms(d)[0] == b
