"""Piles of one value in continuous data: the pile rule and ksg (left27-piles, issue 27).

References from outside the code: the exact MI of a standard Gaussian pair with both
variables clipped to [a, b] (atoms at the clip levels beside the continuous density),
by Gauss-Legendre quadrature of the interior term, 1-D quadrature of the atom x
continuum terms and scipy.stats.multivariate_normal.cdf for the atom x atom cells
(checked here against -0.5 ln(1 - rho^2) with no clip, and against round 27's cell sums:
0.537 at rho 0.9, +-0.5 sigma); shared dropouts written as 0.0 with probability p:
H(p) + (1 - p) (-0.5 ln(1 - rho^2)) in closed form. Tolerance max(0.05 nats, 10 %)
(the project's; the rule's threshold is where kde / histogram / gaussian pass it,
discrete module notes "Piles").
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.special import xlogy
from scipy.stats import multivariate_normal, norm

from modalinfo.information import (
    BiasRuleWarning,
    conditional_mutual_information,
    mutual_information,
    mutual_information_ci,
    transfer_entropy,
)
from modalinfo.information.discrete import pile_of


def clipped_mi(rho: float, a: float, b: float, nodes: int = 300) -> float:
    """Exact I(clip(X, a, b); clip(Y, a, b)) of a standard Gaussian pair [nats]."""
    s = np.sqrt(1 - rho**2)
    lo, hi = (a if np.isfinite(a) else -12.0), (b if np.isfinite(b) else 12.0)
    t, w = np.polynomial.legendre.leggauss(nodes)
    u = 0.5 * (hi - lo) * t + 0.5 * (hi + lo)
    wu = 0.5 * (hi - lo) * w
    xx, yy = np.meshgrid(u, u, indexing="ij")
    q = (xx**2 - 2 * rho * xx * yy + yy**2) / (2 * s**2)
    dens = np.exp(-q) / (2 * np.pi * s)
    total = float(np.einsum("i,j,ij->", wu, wu, dens * (-np.log(s) - q + 0.5 * (xx**2 + yy**2))))
    atoms = []  # (probability, P(atom | other = v), interval)
    if np.isfinite(a):
        atoms.append((norm.cdf(a), lambda v: norm.cdf((a - rho * v) / s), (-40.0, a)))
    if np.isfinite(b):
        atoms.append((norm.sf(b), lambda v: norm.sf((b - rho * v) / s), (b, 40.0)))
    for pa, cond, _ in atoms:  # atom of x with continuous y, and the mirror term
        c = cond(u)
        total += 2 * float(np.sum(wu * norm.pdf(u) * xlogy(c, c / pa)))
    cdf = multivariate_normal(mean=[0, 0], cov=[[1, rho], [rho, 1]]).cdf
    for pa, _, (x0, x1) in atoms:
        for pb, _, (y0, y1) in atoms:
            pab = cdf([x1, y1]) - cdf([x0, y1]) - cdf([x1, y0]) + cdf([x0, y0])
            if pab > 0:
                total += pab * np.log(pab / (pa * pb))
    return total


def dropout_mi(rho: float, p: float) -> float:
    """Exact MI of a Gaussian pair whose frames drop out together (written 0.0) [nats]."""
    return -(p * np.log(p) + (1 - p) * np.log(1 - p)) - (1 - p) * 0.5 * np.log(1 - rho**2)


def pair(rho: float, n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    z = np.random.default_rng(seed).standard_normal((n, 2))
    return z[:, 0], rho * z[:, 0] + np.sqrt(1 - rho**2) * z[:, 1]


def piled(kind: str, rho: float, share: float, n: int, seed: int):
    """(x, y, exact MI) of a pair with a pile of the given kind and share."""
    x, y = pair(rho, n, seed)
    if kind == "clip":
        k = norm.isf(share / 2)
        return np.clip(x, -k, k), np.clip(y, -k, k), clipped_mi(rho, -k, k)
    if kind == "fullwell":
        c = norm.isf(share)
        return np.minimum(x, c), np.minimum(y, c), clipped_mi(rho, -np.inf, c)
    drop = np.random.default_rng(seed + 1).random(n) < share
    return np.where(drop, 0.0, x), np.where(drop, 0.0, y), dropout_mi(rho, share)


def tol(truth: float) -> float:
    return max(0.05, 0.1 * truth)


def test_exact_reference_against_closed_forms():
    # no clip within 8 sigma: the Gaussian MI; round 27's cell sum at +-0.5 sigma
    assert clipped_mi(0.9, -8, 8) == pytest.approx(-0.5 * np.log(1 - 0.81), abs=1e-9)
    assert clipped_mi(0.9, -0.5, 0.5) == pytest.approx(0.537, abs=1e-3)
    assert clipped_mi(0.9, -np.inf, 0.0) == pytest.approx(0.554, abs=1e-3)


@pytest.mark.parametrize("kind, share, rho", [("clip", 0.4, 0.9), ("fullwell", 0.4, 0.9),
                                              ("dropout", 0.2, 0.5), ("dropout", 0.05, 0.9)])
def test_ksg_within_tolerance_of_exact(kind, share, rho):
    # its tie-breaking noise keeps the default within max(0.05, 10 %) on every pile
    x, y, truth = piled(kind, rho, share, 4000, 27)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        value = mutual_information(x, y)  # ksg, the default: no warning
    assert abs(value - truth) <= tol(truth)


@pytest.mark.parametrize("method", ["kde", "histogram", "gaussian"])
@pytest.mark.parametrize("kind, share, rho", [("clip", 0.4, 0.9), ("fullwell", 0.4, 0.9),
                                              ("dropout", 0.2, 0.5)])
def test_blind_methods_warn_where_they_miss(method, kind, share, rho):
    x, y, truth = piled(kind, rho, share, 4000, 27)
    with pytest.warns(BiasRuleWarning, match=r"`x` (and `y` )?holds? .*method='ksg'") as rec:
        value = mutual_information(x, y, method=method)
    assert len(rec) == 1
    # the warning is there for the misses: at least one blind method misses each kind
    if method == "kde" and kind != "dropout" or method == "gaussian" and kind == "dropout":
        assert abs(value - truth) > tol(truth)


def test_small_piles_and_rounded_data_do_not_warn():
    x, y, _ = piled("clip", 0.9, 0.05, 4000, 3)  # 5 % at the ends: within tolerance
    xd, yd, _ = piled("dropout", 0.5, 0.002, 4000, 3)  # 0.2 % dropouts
    xr, yr = pair(0.75, 4000, 4)
    x1 = np.where(np.random.default_rng(5).random(4000) < 0.01, 0.0, xr)  # 1 %, x alone
    cases = [(x, y), (xd, yd), (x1, yr), (np.round(xr, 1), np.round(yr, 1)),  # 0.1 sigma
             (np.round(4 * xr), np.round(4 * yr)),  # integer codes
             (np.round(xr, 2), yr)]
    for method in ("kde", "histogram", "gaussian"):
        for a, b in cases:
            with warnings.catch_warnings():
                warnings.simplefilter("error")
                mutual_information(a, b, method=method)


def test_shared_dropouts_warn_above_half_a_percent():
    # 2 % of frames dropped in both (exact 0.239 at rho 0.5): kde -0.10 before, silent
    x, y, truth = piled("dropout", 0.5, 0.02, 4000, 6)
    with pytest.warns(BiasRuleWarning, match=r"`x` and `y` hold 2\.\d% .* at one value each"):
        value = mutual_information(x, y, method="kde")
    assert abs(value - truth) > tol(truth)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert abs(mutual_information(x, y) - truth) <= tol(truth)  # ksg


def test_pile_of_names_value_share_and_place():
    x, _, _ = piled("dropout", 0.5, 0.2, 4000, 5)
    value, share, where = pile_of(x)
    assert (value, where) == (0.0, "inside")
    # binomial(4000, 0.2): sd 0.0063
    assert abs(share - 0.2) < 4 * np.sqrt(0.2 * 0.8 / 4000)
    xc, _, _ = piled("fullwell", 0.5, 0.3, 4000, 5)
    assert pile_of(xc)[2] == "ends"
    assert pile_of(np.round(xc, 1)) is None  # rounded: no continuum beside the atom


def test_ci_cmi_and_te_warn_once_on_a_pile():
    x, y, _ = piled("clip", 0.9, 0.4, 2000, 8)
    z = np.random.default_rng(9).standard_normal(2000)
    with pytest.warns(BiasRuleWarning, match="method='ksg'") as rec:
        mutual_information_ci(x, y, method="kde", n_resamples=20, seed=0)
    assert sum("holds" in str(w.message) for w in rec) == 1
    # (the histogram CMI switches to ksg at this n by its resolution rule: not piled)
    for method in ("kde", "gaussian"):
        with pytest.warns(BiasRuleWarning, match="`x` holds") as rec:
            conditional_mutual_information(x, y, z, method=method)
        assert sum("holds" in str(w.message) for w in rec) == 1
    for method in ("histogram", "gaussian"):
        with pytest.warns(BiasRuleWarning, match="holds") as rec:
            transfer_entropy(x, y, method=method)
        assert sum("holds" in str(w.message) for w in rec) == 1
    with pytest.raises(ValueError, match="holds"):
        conditional_mutual_information(x, y, z, method="kde", fallback="raise")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        conditional_mutual_information(x, y, z)  # ksg: silent


def test_ordering_warns_once_per_call_on_dropped_frames():
    # 10 % of the frames written as all-zero coefficients (dropouts): the wavefront and
    # every mode's contribution hold 10 % at 0.0 (above the 3 % of one variable)
    from modalinfo.bases import Pupil, ZernikeBasis
    from modalinfo.ordering import order_modes

    basis = ZernikeBasis(Pupil(24), modes=range(2, 8))
    rng = np.random.default_rng(11)
    coeffs = rng.standard_normal((400, 6)) * np.linspace(1.0, 0.3, 6)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        order_modes(coeffs, basis, "mi_marginal", seed=0, sample_budget=20_000)
    coeffs[rng.random(400) < 0.1] = 0.0
    with pytest.warns(BiasRuleWarning, match=r"order_modes with estimator='histogram' "
                      r"\(and \d+ other variable\(s\)\): `the wavefront` hold") as rec:
        order_modes(coeffs, basis, "mi_marginal", seed=0, sample_budget=20_000)
    assert sum("hold" in str(w.message) for w in rec) == 1


def test_select_inputs_warns_once_per_call_on_dropped_frames():
    from modalinfo.information import select_inputs

    rng = np.random.default_rng(12)
    e = rng.standard_normal((600, 3))
    data = np.empty_like(e)
    data[0] = e[0]
    for t in range(1, 600):  # a VAR(1): each series driven by its past and the first's
        data[t] = 0.6 * data[t - 1] + 0.3 * data[t - 1, 0] + e[t]
    data[rng.random(600) < 0.05] = 0.0  # dropped frames written as zeros
    with pytest.warns(BiasRuleWarning, match=r"select_inputs with method='histogram': `m0` hold"
                      ) as rec:
        select_inputs(data, 1, max_lag=2, method="histogram", n_surrogates=19,
                      intervals=False, seed=0)
    assert sum("hold" in str(w.message) for w in rec) == 1
