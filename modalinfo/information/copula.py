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
           "spread_dependence_limit", "spread_stride", "margin_below", "rank_resolution_why",
           "cmi_rank_resolution_why", "RANK_RESOLUTION_MARGIN", "RANK_DISTINCT_SHARE",
           "CMI_RANK_RESOLUTION_MARGIN"]


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


#: Margin [nats] of the rank-resolution rule of a pair (:func:`rank_resolution_why`): on
#: normal scores the MI cannot be read above what the ranks of n samples resolve, ln n
#: (the entropy of a uniform rank); at MI = ln n - 2 the noise sd of y = x + s e,
#: s ~ exp(-MI) = e^2 / n, spans e^2 / 2.5 ~ 3 spacings of n normal samples (2.5 / n
#: at the centre), so above it the noise moves a sample past fewer than ~3 neighbours.
RANK_RESOLUTION_MARGIN = 2.0
#: Smallest share of distinct values (of n samples) at which a variable with repeated
#: values is still judged by the rank-resolution rule, with ln n replaced by ln of its
#: number of distinct values (tied values share one rank). Below it the levels, not the
#: ranks, bind: each level holds several samples, the MI of the pair saturates at the
#: levels' entropy, and the estimate follows the exact MI of the rounded pair there
#: (issue 27, left28-misc, measured).
RANK_DISTINCT_SHARE = 0.5
#: Margin [nats] below 0.5 ln n of the conditional rank-resolution rule
#: (:func:`cmi_rank_resolution_why`). The normal scores Phi^-1(F_n(x)) differ from the
#: Gaussian map of the values by the empirical CDF's error over the density, ~1 / sqrt(n)
#: and different for each column, so a relation through several columns (z = x + y +
#: s e given y) is read through a noise of relative variance ~1 / n: the CMI of rank-based
#: estimates saturates near 0.5 ln n - 0.9 (measured, 3 seeds, exact 6 nats: gaussian
#: 2.22 / 2.87 / 3.67 and ksg 2.27 / 3.03 / 3.86 at n = 500 / 2000 / 1e4; the KSG's
#: Frenzel-Pompe CMI saturates there even when z is not in the relation). From 0.5 ln n
#: - 1.5 on, estimates of exact 2 / 3 / 4 nats read 13-14 % low (round 55 PART a).
CMI_RANK_RESOLUTION_MARGIN = 1.5


def rank_resolution_why(value: float, x: np.ndarray, y: np.ndarray, estimator: str,
                        small_n_floor: bool = False) -> str | None:
    """Why the MI ``value`` (nats) of a rank-based estimate is capped by the ranks, or None.

    On normal scores (``copula=True``) an estimate reads the ranks only, and the ranks of
    n samples resolve at most ln n nats (the entropy of a uniform rank on n values).
    For a pair y = x + s e near |rho| = 1 the MI is about ln(1 / s) and the spacing of n
    normal samples about 2.5 / n at the centre, so within :data:`RANK_RESOLUTION_MARGIN`
    = 2 nats of ln n the noise scrambles the ranks of fewer than ~3 neighbours: the
    estimate is then neither close nor a bound (measured, Gaussian pairs, 10 seeds,
    kde, min-max [nats]: n = 2000, rho = 0.999999, exact 6.56, 6.17-7.06; n = 1e4, rho =
    1 - 1e-8, exact 8.86, 8.20-8.95; round 55 PART a, 5 seeds, n = 2000: ksg 6.07-6.12
    and gaussian 6.21-6.41 for 6.91, ksg 6.59-6.61 and gaussian 7.43-7.83 for 9.21,
    silent before), while ``copula=False`` follows the raw values. Never fires at rho
    <= 0.999 for n = 500 .. 1e4 (the kde's rates in
    :func:`~modalinfo.information.mutual_information`).

    Repeated values share one rank, so a variable with ``d`` distinct values resolves
    at most ln d: the line is ln d - 2 for the variable with fewer distinct values,
    while ``d`` is at least :data:`RANK_DISTINCT_SHARE` of n (a rounded continuum;
    review 21's K2). With more ties the levels bind instead and the pair is left to the
    other rules. With ``small_n_floor`` (the KSG and the Gaussian copula) the line is
    at least 0.5 ln n, which binds below n = e^4 ~ 55, so that the sampling noise of a
    small independent pair (gaussian 0.32 nats at n = 10, where ln n - 2 = 0.30) is not
    read as a cap; the kde keeps its measured line there (rho = 0.99 at n = 30, round
    39's class road). ``estimator`` names the estimator in the message.
    """
    n = x.shape[0]
    floor = 0.5 * math.log(n) if small_n_floor else -math.inf
    if not value > max(math.log(n) - RANK_RESOLUTION_MARGIN, floor):
        return None  # ln(distinct) <= ln n: nothing can fire
    distinct = {name: int(np.unique(a).size) for name, a in (("x", x), ("y", y))}
    name = min(distinct, key=distinct.get)
    d = distinct[name]
    if d < RANK_DISTINCT_SHARE * n:
        return None  # the levels bind, not the ranks (RANK_DISTINCT_SHARE)
    cap = math.log(d)
    if not value > cap - RANK_RESOLUTION_MARGIN:
        return None
    if d == n:
        return (f"the estimate {value:.3f} nats is within {RANK_RESOLUTION_MARGIN:g} "
                f"nats of ln n = {cap:.3f}, the most the ranks of n = {n} samples "
                f"resolve ({estimator} runs on normal scores): near |rho| = 1 it is "
                "neither close nor a bound; copula=False estimates it on the raw values")
    return (f"the estimate {value:.3f} nats is within {RANK_RESOLUTION_MARGIN:g} nats "
            f"of ln {d} = {cap:.3f}, the most the ranks of n = {n} samples resolve "
            f"when `{name}` takes {d} distinct values (tied values share one rank; "
            f"{estimator} runs on normal scores): near |rho| = 1 it is neither close nor "
            "a bound; copula=False estimates it on the raw values")


def cmi_rank_resolution_why(value: float, n: int, estimator: str) -> str | None:
    """Why a rank-based CMI ``value`` (nats) of n samples is capped by the ranks, or None.

    At or above ``0.5 ln n - CMI_RANK_RESOLUTION_MARGIN`` (2.30 nats at n = 2000, 3.11
    at 1e4): the normal scores of each column carry an error of ~1 / sqrt(n) of their
    own (:data:`CMI_RANK_RESOLUTION_MARGIN`), so a near-deterministic relation through
    the conditioning columns reads far low (round 55 PART a: z = x + y + 1e-3 e given
    y, exact 6.91 nats, n = 2000: ksg 3.02, kde 3.53, gaussian 2.94, silent before). A
    true CMI this large (a relation that leaves z out, e.g. y = x + s e given an
    unrelated z, is resolved by the gaussian and kde up to ~ln n) is warned too: the
    ranks cannot tell the two apart, and ``copula=False`` estimates it on the values.
    ``estimator`` names the estimator in the message.
    """
    line = 0.5 * math.log(n) - CMI_RANK_RESOLUTION_MARGIN
    if not value >= line:
        return None
    return (f"the estimate {value:.3f} nats is at or above 0.5 ln n - "
            f"{CMI_RANK_RESOLUTION_MARGIN:g} = {line:.3f}: the normal scores of n = {n} "
            f"samples ({estimator} runs on them) differ from the Gaussian map of the values "
            "by ~1 / sqrt(n), column by column, so a relation through several columns is "
            "resolved to about 0.5 ln n nats at most: the estimate is neither close nor a "
            "bound (a near-deterministic relation reads far low, a variable of few levels "
            "can read high); copula=False estimates it on the values")


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
