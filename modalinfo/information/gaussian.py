"""Gaussian (parametric) estimators: MI and entropy of a fitted normal distribution.

For a bivariate normal pair with correlation coefficient r,
``I(X; Y) = -0.5 ln(1 - r^2)`` (Cover & Thomas 2006, Example 8.5.1), and a normal
variable has ``H = 0.5 ln(2 pi e sigma^2)`` (ibid., Example 8.1.2). These are exact
for Gaussian data; for continuous data the Gaussian-copula MI (the default, on normal
scores) is a lower bound of the MI (Ince et al. 2017); they are blind to non-linear
dependence (y = x^2 gives about 0).

Discrete data: where both variables take so few values that their table holds at least
10 samples per cell, the MI is that of the table (Miller-Madow plug-in,
:mod:`modalinfo.information.discrete`), the rule of the kde and ksg engines. A normal
model of such a pair is not a bound of its MI: for a binary symmetric channel with
10 % errors (phi = 0.8) it gives 0.51 nats against the table's exact
ln 2 - H(0.1) = 0.368 (audit 9, row t14).
"""

from __future__ import annotations

import math

import numpy as np

from modalinfo.information import _kernels as kern
from modalinfo.information.copula import check_copula, copula_scores
from modalinfo.information.discrete import discrete_cmi, discrete_pair_mi, discrete_x_levels
from modalinfo.information.methods import MIMethod, register_method

__all__ = [
    "GaussianEngine",
    "fisher_z_from_mi",
    "gaussian_entropy",
    "gaussian_mi_from_correlation",
    "mi_from_fisher_z",
    "unit_scaled",
]

#: Floor of 1 - r^2, so that an exactly linear relation gives a large finite MI
#: (-0.5 ln 1e-15 = 17.3 nats) instead of infinity where a caller needs a number (kde's
#: Gaussian reference); :class:`GaussianEngine` refuses such a pair instead.
ONE_MINUS_R2_FLOOR = 1e-15


#: Below this 1 - r * r, :class:`GaussianEngine` recomputes 1 - r^2 as a residual to tell
#: |r| = 1 from a large finite MI (1e-6: an MI of 6.9 nats; above it the check is skipped).
_RESIDUAL_CHECK_BELOW = 1e-6


def gaussian_mi_from_correlation(r: float) -> float:
    """``-0.5 ln(1 - r^2)`` in nats, with 1 - r^2 floored at :data:`ONE_MINUS_R2_FLOOR`."""
    return -0.5 * math.log(max(1.0 - r * r, ONE_MINUS_R2_FLOOR))


def fisher_z_from_mi(mi: np.ndarray | float) -> np.ndarray:
    """Return Fisher's ``z = atanh |r|`` of the correlation whose Gaussian MI is ``mi``.

    ``I = -0.5 ln(1 - r^2) = ln cosh z``, so ``z = acosh(e^I) = I + ln(1 + sqrt(1 - e^-2I))``,
    written so that no step overflows or cancels (``atanh(sqrt(1 - e^-2I))`` rounds to
    infinity from I ~ 18 nats). Fisher (1921): ``z`` of a normal sample's correlation is
    nearly normal with a variance nearly free of the correlation, where ``I`` is skewed
    and its spread grows with it. ``mi`` >= 0, any shape; returns the same shape.
    """
    i = np.asarray(mi, dtype=float)
    return i + np.log1p(np.sqrt(-np.expm1(-2.0 * i)))


def mi_from_fisher_z(z: np.ndarray | float) -> np.ndarray:
    """Return ``ln cosh z`` in nats, the Gaussian MI of the correlation ``tanh z``.

    The inverse of :func:`fisher_z_from_mi` for z >= 0; even in z; no overflow.
    """
    a = np.abs(np.asarray(z, dtype=float))
    return a + np.log1p(np.exp(-2.0 * a)) - math.log(2.0)


def unit_scaled(a: np.ndarray) -> np.ndarray:
    """Return ``a / max |a|``, shape (n,), values in [-1, 1].

    Sums of squares of the result neither underflow (data ~1e-170 and below) nor
    overflow (~1e154 and above); correlations are unchanged. ``a`` not all zero.
    """
    return a / np.max(np.abs(a))


class GaussianEngine:
    """Gaussian MI from the Pearson correlation; caches the centred, normalised x.

    Scale invariant: both variables are divided by their largest magnitude first.

    Parameters
    ----------
    copula : bool
        Default True: the correlation of the normal scores Phi^-1(rank / (n + 1)) of
        each variable (Gaussian-copula MI, Ince et al., Hum. Brain Mapp. 38, 1541,
        2017): exact for any pair whose copula is Gaussian, whatever the marginals, up
        to the resolution of n normal scores (round 14 PART a: 5.93 nats at n = 2000 for
        a Gaussian pair with rho = 0.999999, exact 6.56, where ``copula=False`` gave
        6.54: the scores of nearby ranks cannot show a correlation that close to 1),
        a lower bound of the MI otherwise, and moved by one glitch by about its share
        of the sample. ``False``: the Pearson correlation of the values (the former
        behaviour), which one sample at 1e6 drives to 0.
    """

    def __init__(self, *, copula: bool = True):
        self.copula = check_copula(copula)

    def _prepare(self, a: np.ndarray) -> np.ndarray:
        if self.copula:
            return copula_scores(a)
        return a

    def fit(self, x: np.ndarray) -> GaussianEngine:
        """Cache ``(x - mean) / ||x - mean||`` (x validated, 1-D, not constant)."""
        xs = unit_scaled(self._prepare(x))
        xc = xs - xs.mean()
        self._xu = xc / math.sqrt(kern.dot(xc, xc))
        self._x_levels = discrete_x_levels(x)  # None unless x may be one side of a table
        return self

    def score(self, y: np.ndarray) -> float:
        """``-0.5 ln(1 - r^2)`` in nats (y validated, same length, not constant).

        Raises ValueError where ``1 - r^2 <=`` :data:`ONE_MINUS_R2_FLOOR` (``|r| = 1`` to
        within rounding, e.g. a discrete variable and its copy): the Gaussian MI is
        infinite there (Cover & Thomas 2006, Example 8.5.1), as for the continuous copies
        ``mutual_information`` refuses. Both variables discrete with at least 10 samples
        per cell of their table: the Miller-Madow plug-in MI of the table instead (module
        notes, "Discrete data").
        """
        table = discrete_pair_mi(self._x_levels, y)
        if table is not None:
            return table
        ys = unit_scaled(self._prepare(y))
        num, norm = kern.centred_dot_and_norm(self._xu, ys)
        if not norm > 0.0:  # y constant after rounding of its mean: no correlation
            return 0.0
        r = min(1.0, max(-1.0, num / norm))
        if 1.0 - r * r < _RESIDUAL_CHECK_BELOW:
            self._refuse_unit_correlation(ys)
        return gaussian_mi_from_correlation(r)

    def _refuse_unit_correlation(self, ys: np.ndarray) -> None:
        """Raise if ``1 - r^2 <= ONE_MINUS_R2_FLOOR``, computed as a residual.

        ``1 - r^2`` is the squared norm of ``yu - r xu`` (both centred, unit norm): that
        difference keeps the digits ``1 - r * r`` loses (for a binary copy of 2000 samples
        ``1 - r * r`` is ~1e-14 of rounding, the residual ~1e-30).
        """
        yc = ys - ys.mean()
        yu = yc / math.sqrt(kern.dot(yc, yc))
        e = yu - kern.dot(self._xu, yu) * self._xu
        one_minus = kern.dot(e, e)
        if one_minus <= ONE_MINUS_R2_FLOOR:
            # the model's MI is infinite here; a floored 17 nats would pass for an estimate
            # (a binary copy gave 16 nats where the other methods give its entropy)
            values = "normal scores (ranks)" if self.copula else "values"
            raise ValueError(
                f"`y` is an affine function of `x` in their {values}: their correlation is "
                f"+-1 to within rounding (1 - r^2 = {one_minus:.3g} <= "
                f"{ONE_MINUS_R2_FLOOR:g}), where the Gaussian MI -0.5 ln(1 - r^2) is "
                "infinite, which no estimator can return. A discrete variable and its copy "
                "have MI equal to its entropy: use method='histogram', 'kde' or 'ksg'; "
                "else drop one of the two variables.")


def gaussian_entropy(x: np.ndarray) -> float:
    """``0.5 ln(2 pi e s^2)`` in nats with s^2 the unbiased sample variance."""
    var = float(np.var(x, ddof=1))
    return 0.5 * math.log(2.0 * math.pi * math.e * var)


# ----------------------------------------------------------------------------- conditional MI
#: Floor of the eigenvalues of a correlation matrix (as ONE_MINUS_R2_FLOOR for MI).
_EIG_FLOOR = 1e-15


def _standardise_columns(a: np.ndarray, copula: bool = False) -> np.ndarray:
    """Columns standardised to mean 0, sd 1: of the values, or of their normal scores."""
    out = np.empty_like(a)
    for j in range(a.shape[1]):
        u = copula_scores(a[:, j]) if copula else unit_scaled(a[:, j])
        out[:, j] = (u - u.mean()) / u.std()
    return out


def _logdet(corr: np.ndarray) -> float:
    if corr.shape[0] == 0:
        return 0.0
    return float(np.sum(np.log(np.maximum(np.linalg.eigvalsh(corr), _EIG_FLOOR))))


def gaussian_cmi(x, y, z, *, copula: bool = True) -> float:
    """``0.5 ln(det S_xz det S_yz / (det S_z det S_xyz))`` [nats] (Cover & Thomas 2006, eq. 8.56).

    x, y, z of shapes (n, dx), (n, dy), (n, dz). With ``copula`` (default) S is the
    correlation of the columns' normal scores (the Gaussian-copula CMI of Ince et al.
    2017), else of the values; exact for jointly Gaussian data, blind to non-linear
    dependence.

    Raises ``ValueError`` if the n samples do not exceed the d columns: the sample
    correlation then has rank <= n - 1 < d, its determinants are those of the eigenvalue
    floor, and the estimate is arbitrary (20 samples over 102 columns gave -1.48 nats for
    an exact 0.22: adversarial round 8, row d15).
    """
    n, d = x.shape[0], x.shape[1] + y.shape[1] + z.shape[1]
    if n <= d:
        raise ValueError(
            f"the Gaussian CMI needs more samples than columns: `x`, `y` and `z` have "
            f"{d} columns together and n = {n} samples, so their correlation matrix has "
            f"rank <= n - 1 = {n - 1} and its determinants are arbitrary; give fewer "
            f"conditioning columns (`z`) or more samples.")
    table = discrete_cmi(x, y, z)
    if table is not None:  # every column discrete: the table's CMI (module notes)
        return table
    u = _standardise_columns(np.concatenate([x, y, z], axis=1), check_copula(copula))
    value = gaussian_cmi_from_covariance((u.T @ u) / u.shape[0], x.shape[1], y.shape[1])
    if x.shape[1] == 1 and value > -0.5 * math.log(_RESIDUAL_CHECK_BELOW):
        _refuse_unit_partial_correlation(u, y.shape[1], copula)
    return value


#: Tolerance of :func:`gaussian_scores_rule` (the issue's): max(0.05 nats, 10 %).
_SCORES_TOL_NATS, _SCORES_TOL_SHARE = 0.05, 0.10


def gaussian_scores_rule(x: np.ndarray, y: np.ndarray, z: np.ndarray,
                         value: float) -> str | None:
    """Why the Gaussian-copula CMI ``value`` (nats) lost the values' dependence, or None.

    Rule (Leftovers 11-resolve, issue 27): the Gaussian CMI of the values above that of
    the normal scores by more than max(0.05 nats, 10 %). On a law with a Gaussian copula
    the scores' value is the exact one and the values' cannot exceed it but by sampling
    noise: a monotone map of each variable can only lower a Gaussian pair's correlation
    (its maximal correlation is |rho|: Lancaster 1957), and heavy tails or a glitch lower
    the values' value. Above it, the ranks distort the dependence: the normal scores of a
    series with few effective samples are a lumpy map of it (the transfer entropy of a
    VAR(1) pair with a persistent target or source, a = 0.99: scores 0.27-0.36, values
    0.38-0.43, exact 0.398; audit 11-regime; measured silent, 5 seeds each, on AR(1)
    targets a = 0.5-0.999 with a white source, on a VAR(1) with a = 0.9 and a source of
    0.9, on Student-t innovations of 1-3 degrees of freedom). ``transfer_entropy``
    judges it and keeps the value (the scores make the estimate robust to glitches);
    the loops of estimates (maps, selections, predictors, resamples) do not, nor does
    ``conditional_mutual_information``, whose columns need not be series: the values'
    sample covariance of a multivariate Student-t (one common scale) puts their
    Gaussian MI far above the scores' by chance (Beyond-Normal student-2x2-df1, n = 1e4:
    0.39 against 0.001, 20 of 20 seeds).

    x, y, z: float arrays of shapes (n, dx), (n, dy), (n, dz), as :func:`gaussian_cmi`;
    every column discrete (the table's CMI, no scores): not judged.
    """
    if discrete_cmi(x, y, z) is not None:
        return None
    xyz = np.concatenate([x, y, z], axis=1)
    on_values = gaussian_cmi_from_covariance(
        np.cov(_standardise_columns(xyz, False), rowvar=False, bias=True),
        x.shape[1], y.shape[1])
    allowed = max(_SCORES_TOL_NATS, _SCORES_TOL_SHARE * on_values)
    if not on_values - value > allowed:
        return None
    return (f"the Gaussian-copula CMI (normal scores) is {value:.3f} nats and that of the "
            f"values {on_values:.3f}, more than max(0.05, 10 %) above it, which no Gaussian "
            "copula gives (a monotone map of each variable cannot raise a Gaussian pair's "
            "correlation): the ranks distort this dependence, as the normal scores of "
            "persistent series with few effective samples do, and the value is a lower "
            "bound (copula=False gives the values' Gaussian CMI; method='ksg' the KSG)")


def _refuse_unit_partial_correlation(u: np.ndarray, dy: int, copula: bool) -> None:
    """Raise if the partial correlation of ``u[:, 0]`` and the next dy columns is +-1.

    As :meth:`GaussianEngine._refuse_unit_correlation`, for the CMI: ``1 - rho^2`` is the
    ratio of the least-squares residuals of x on (y, z) and on z alone; at or below
    :data:`ONE_MINUS_R2_FLOOR` the Gaussian CMI is infinite (audit 9: a binary delayed
    copy's transfer entropy came out 16.9 nats, where the histogram gives its entropy).
    """
    def residual(a: np.ndarray) -> float:
        if a.shape[1] == 0:
            return float(u[:, 0] @ u[:, 0])
        e = u[:, 0] - a @ np.linalg.lstsq(a, u[:, 0], rcond=None)[0]
        return float(e @ e)

    given_z = residual(u[:, 1 + dy:])
    one_minus = residual(u[:, 1:]) / given_z if given_z > 0 else 1.0
    if given_z > ONE_MINUS_R2_FLOOR * u.shape[0] and one_minus <= ONE_MINUS_R2_FLOOR:
        values = "normal scores (ranks)" if copula else "values"
        raise ValueError(
            f"`x` is an affine function of `y` given `z` in their {values}: their partial "
            f"correlation is +-1 to within rounding (1 - r^2 = {one_minus:.3g} <= "
            f"{ONE_MINUS_R2_FLOOR:g}), where the Gaussian CMI is infinite, which no "
            "estimator can return. A discrete variable and its copy have a finite CMI: use "
            "method='histogram' or 'ksg'; else drop one of the two variables.")


def gaussian_cmi_from_covariance(c: np.ndarray, dx: int, dy: int) -> float:
    """Gaussian CMI (nats) of the blocks (x, y, z) = (first dx, next dy, rest) of ``c``.

    ``c`` is a covariance (or correlation) matrix, shape (d, d); it is scaled to a
    correlation matrix first, and eigenvalues are floored at 1e-15.
    """
    sd = np.sqrt(np.diag(c))
    c = c / np.outer(sd, sd)
    ix = np.arange(dx)
    iy = np.arange(dx, dx + dy)
    iz = np.arange(dx + dy, c.shape[0])

    def ld(idx):
        return _logdet(c[np.ix_(idx, idx)])

    return 0.5 * (ld(np.r_[ix, iz]) + ld(np.r_[iy, iz]) - ld(iz) - ld(np.arange(c.shape[0])))


#: The ``"gaussian"`` method (:mod:`modalinfo.information.methods`).
METHOD = register_method(MIMethod(
    name="gaussian", engine=GaussianEngine, entropy=gaussian_entropy, cmi=gaussian_cmi,
    gaussian_closed_form=True,
    summary="-0.5 ln(1 - r^2) of the normal scores (Gaussian copula)"))
