"""Gaussian-copula normalisation: the rank transform every default MI estimator uses.

Mutual information is unchanged by a strictly monotone map of each variable
separately (Kraskov, Stoegbauer & Grassberger, Phys. Rev. E 69, 066138, 2004, eq. 2
and sec. II), so an estimator may replace each variable by any monotone function of
it without changing its target. Replacing a sample by its normal scores

    u_i = Phi^-1(rank_i / (n + 1))

(the empirical Gaussian-copula transform; Ince et al., Hum. Brain Mapp. 38, 1541,
2017) makes every marginal a standard normal, whatever the data's units, scale or
tails: a glitch at 1e6 becomes the largest score, Phi^-1(n / (n + 1)) ~ 3.5 sigma at
n = 4000, and moves every other sample's score by at most one rank. An estimate
computed on normal scores therefore depends on the ranks only, so one corrupted
sample changes it by about its share 1/n of the sample, never by the size of the
corruption.

Ties (rounded, integer or boolean data) get the average of their ranks (scipy's
``rankdata(method="average")``), so tied values keep equal scores and the result is
a deterministic function of the data (no random tie breaking here; the KSG engine
adds its own seeded noise to tied scores, see :mod:`modalinfo.information.ksg`).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.special import ndtri
from scipy.stats import rankdata

from modalinfo.common.validation import as_float_array

__all__ = ["copula_scores", "copula_scores_ties", "check_copula", "normal_score_correlation",
           "small_sample_rule", "SMALL_SAMPLE_RULE_MAX", "spread_dependence",
           "spread_dependence_limit", "spread_stride", "margin_below"]


def copula_scores(x: np.ndarray) -> np.ndarray:
    """Return the normal scores ``Phi^-1(rank / (n + 1))`` of a 1-D sample, shape (n,).

    Parameters
    ----------
    x : numpy.ndarray, shape (n,)
        Finite samples, any units.

    Returns
    -------
    numpy.ndarray, shape (n,)
        Dimensionless scores in about [-Phi^-1(n / (n + 1)), +Phi^-1(n / (n + 1))];
        tied values share the score of their average rank.

    Raises
    ------
    TypeError, ValueError
        If ``x`` is not a finite, real, 1-D array (a 2-D array was ranked flattened
        against its row count, giving NaN scores; a list raised AttributeError).
    """
    x = as_float_array(x, "x", ndim=1)
    n = x.shape[0]
    return ndtri(rankdata(x) / (n + 1.0))


def copula_scores_ties(x: np.ndarray) -> tuple[np.ndarray, bool]:
    """Return the normal scores of :func:`copula_scores` and whether x has tied values.

    The tie test is O(n) on the ranks: without ties they are 1 .. n; tied values
    share their average rank, an integer or a half-integer, so twice the ranks are
    integers that repeat exactly when values do.
    """
    n = x.shape[0]
    ranks = rankdata(x)
    ties = bool(np.bincount((2.0 * ranks).astype(np.int64)).max() > 1)
    return ndtri(ranks / (n + 1.0)), ties


def check_copula(copula: object) -> bool:
    """Validate a ``copula`` option (a bool) and return it as a Python bool."""
    if not isinstance(copula, bool | np.bool_):
        raise TypeError(f"`copula` must be a bool; got {copula!r}.")
    return bool(copula)


def normal_score_correlation(x: np.ndarray, y: np.ndarray) -> float:
    """Pearson correlation of the normal scores of x and y, clipped inside (-1, 1).

    Its Gaussian MI ``-0.5 ln(1 - r^2)`` is the pair's Gaussian-copula MI, a lower bound
    of the MI of a continuous pair (Ince et al. 2017).
    """
    r = float(np.corrcoef(copula_scores(x), copula_scores(y))[0, 1])
    return max(min(r, 1.0 - 1e-12), -1.0 + 1e-12)


def margin_below(value: float, reference: float) -> float | None:
    """Return the tolerance ``max(0.05 nats, 10 %)`` if ``value`` is below ``reference`` by more.

    One copy of the rule the bin-rule warnings and the spread rule use to call an
    estimate biased low against a finer grid, a tail-resolving grid or the KSG
    estimate; ``None`` when the estimate is within it.
    """
    tol = max(0.05, 0.1 * reference)
    return tol if reference > value + tol else None


#: Most pairs of the systematic subsample (every ceil(n / 8192)-th) of
#: :func:`spread_dependence` and of the histogram's rank correlation.
SPREAD_SAMPLES = 8192
#: Gate of the spread-dependence rule: ``D > SPREAD_BASE + SPREAD_SDS / sqrt(m)``
#: (:func:`spread_dependence_limit`).
SPREAD_BASE = 0.1
SPREAD_SDS = 4.0


#: Most pairs of the spread rule's KSG reference (``ksg.spread_rule_why``; every
#: ceil(n / 32768)-th): on the gate's 8192 KSG's own noise decided near the tolerance
#: (fix50-c).
SPREAD_REFERENCE_SAMPLES = 32768


def spread_stride(n: int, most: int = SPREAD_SAMPLES) -> int:
    """Stride ceil(n / most) of a systematic subsample of at most ``most`` of n pairs.

    With the default 8192, :func:`spread_dependence`'s and the histogram's
    rank-correlation subsample (its bin rule's), one rule for both; with
    :data:`SPREAD_REFERENCE_SAMPLES`, the spread rule's KSG reference.
    """
    return -(-n // most)


def spread_dependence(x: np.ndarray, y: np.ndarray) -> tuple[float, int, bool]:
    """Dependence of the normal scores beyond their correlation: ``(D, m, ties)``.

    On the normal scores a, b (unit variance) of a systematic subsample of m <=
    :data:`SPREAD_SAMPLES` pairs, with r their correlation and a2, b2 the standardised
    squares,

        D = max(|corr(a2, b2) - r^2|, |corr(a2, b)|, |corr(a, b2)|,
                |eta2(b | a) - r^2|, |eta2(a | b) - r^2|),

    eta2 the neighbour estimate of the correlation ratio (:func:`_neighbour_share`).
    For a Gaussian pair each of the five is 0 in expectation (Isserlis: corr(a^2, b^2)
    = r^2, odd moments vanish; a linear regression explains r^2), with sampling sd about
    1 / sqrt(m); a pair whose spread depends on the other variable (y = x e: corr(a2,
    b2) ~ 0.58 while r ~ 0), that follows a parabola (y = x^2 + e: corr(a2, b) ~ 0.69)
    or an oscillation (y = sin(2 pi x) + e: eta2 ~ 0.33, the moment terms ~0.02;
    fix50-c) reads far above. ``ties``:
    whether either subsample has repeated values (the rules skip such pairs).
    Adversarial round 48 PART a, N14 / N15 (fix49-a).
    """
    stride = spread_stride(x.shape[0])
    a, tx = copula_scores_ties(np.ascontiguousarray(x[::stride]))
    b, ty = copula_scores_ties(np.ascontiguousarray(y[::stride]))
    m = a.shape[0]

    def unit(v: np.ndarray) -> np.ndarray:
        v = v - v.mean()
        sd = math.sqrt(float(np.dot(v, v)) / m)
        return v / sd if sd > 0 else v

    a, b = unit(a), unit(b)
    a2, b2 = unit(a * a), unit(b * b)
    r = float(np.dot(a, b)) / m
    d = max(abs(float(np.dot(a2, b2)) / m - r * r), abs(float(np.dot(a2, b)) / m),
            abs(float(np.dot(a, b2)) / m), abs(_neighbour_share(a, b) - r * r),
            abs(_neighbour_share(b, a) - r * r))
    return d, m, tx or ty


def _neighbour_share(a: np.ndarray, b: np.ndarray) -> float:
    """Share of ``b``'s variance its regression on ``a`` explains, from neighbours in ``a``.

    ``a``, ``b``: unit-variance, zero-mean scores of shape (m,). Consecutive pairs in the
    order of ``a`` share ``E[b | a]`` where it is smooth, so the lag-1 correlation of
    ``b`` in that order estimates the correlation ratio ``Var E[b | a] / Var b``: ``r^2``
    for a Gaussian pair, above it for any curve, monotone or not (y = sin(2 pi x) + e,
    x normal: ~0.3 for r ~ 0, which the moment terms of :func:`spread_dependence` read
    as ~0.02; fix50-c). Sampling sd ~1 / sqrt(m).
    """
    bs = b[np.argsort(a, kind="stable")]
    return float(np.dot(bs[:-1], bs[1:])) / (bs.shape[0] - 1)


def spread_dependence_limit(m: int) -> float:
    """Return the gate ``SPREAD_BASE + SPREAD_SDS / sqrt(m)`` of :func:`spread_dependence`'s D.

    4 sampling sds (1 / sqrt(m)) above the Gaussian value plus 0.1: measured on
    Gaussian pairs (rho 0, 0.3, 0.6, 0.9, 0.95; n = 200, 1e3, 1e4, 1e5; 200 seeds
    each) the largest D was 0.27 at n = 200 (gate 0.38) and 0.05 at n >= 1e4 (gate
    0.15): 0 of 4000 fired. A Student-t pair (a common scale: 3 degrees of freedom,
    rho = 0.5) reads 0.26 and passes the gate from n ~ 1e3, which is why the rule
    asks the KSG estimate next (``ksg.spread_rule_why``).
    """
    return SPREAD_BASE + SPREAD_SDS / math.sqrt(m)


#: Largest n :func:`small_sample_rule` judges: its tables were measured up to n = 400
#: (docs/ADVERSARIAL.md, "Fixes 38-a"); beyond, only a near copy would reach it.
SMALL_SAMPLE_RULE_MAX = 1000


def small_sample_rule(x: np.ndarray, y: np.ndarray, reach: tuple[tuple[float, int], ...],
                      what: str) -> str | None:
    """Why an estimator is biased low at this n for the pair's dependence, or None.

    ``reach``: points (g, n_max), g increasing, from simulation of Gaussian pairs: up to
    n_max samples the mean estimate of a pair whose normal-score MI reads g is below
    the MI by more than ``max(0.05, 10 %)`` (the package's tolerance). The pair's
    ``g = -0.5 ln(1 - r^2)`` (:func:`normal_score_correlation`; it reads the MI low at
    small n, so the rule errs towards silence) is interpolated linearly between the
    points; below the first none, beyond the last ``n_max`` grows as ``e^g / g``
    (a k-NN or kernel estimate needs ~e^MI samples: Gao, Ver Steeg & Galstyan 2015).
    Continuous pairs only (a tie marks discrete or rounded data, whose table is its law),
    n <= :data:`SMALL_SAMPLE_RULE_MAX`. Round 37 PART a, S13-S15.
    """
    n = x.shape[0]
    if n > SMALL_SAMPLE_RULE_MAX or any(np.unique(a).size < n for a in (x, y)):
        return None
    r = normal_score_correlation(x, y)
    g = -0.5 * math.log(1.0 - r * r)
    gs = [p[0] for p in reach]
    if g < gs[0]:
        return None
    if g <= gs[-1]:
        n_max = float(np.interp(g, gs, [p[1] for p in reach]))
    else:
        n_max = reach[-1][1] * (math.exp(g - gs[-1]) * gs[-1] / g)
    if n > n_max:
        return None
    return (f"{what} at n = {n} on a pair whose normal scores carry {g:.3f} nats "
            f"(correlation {r:.4g}): up to n ~ {n_max:.0f} a Gaussian pair of this "
            "dependence reads biased low by more than max(0.05, 10 %) on average (the "
            "small-sample bias grows with the MI), so the value is likely a lower bound")
