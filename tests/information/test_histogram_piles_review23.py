"""The kept-histogram CMI warning where only some columns are discrete (review23, issue 27).

docs/MUTATION.md, "Planted bugs, round 23", R23-X1: round 31 PART a's warning for a
histogram CMI that a discrete column keeps (no KSG switch) is judged "where a column of
x or y is continuous"; its tests had x and y wholly continuous, so a rule judging only
where *every* column of x and y is continuous (``all`` -> ``any`` discrete) escaped.

Reference (outside the code): the closed form of a Gaussian pair's MI,
``-0.5 log(1 - rho^2)``; x, y1 Gaussian with rho = 0.9 where a balanced binary z is 1 and
independent where it is 0, beside y2 an independent binary flag, so
``I(x; (y1, y2) | z) = 0.5 (-0.5 log(1 - 0.81)) = 0.415`` nats (y2 adds nothing).
"""

import numpy as np
import pytest

from modalinfo.information import BiasRuleWarning, conditional_mutual_information


@pytest.mark.parametrize("seed", [0, 1])
def test_a_discrete_column_beside_a_continuous_one_still_warns(seed):
    n = 2000
    rng = np.random.default_rng(seed)
    z = rng.integers(0, 2, n).astype(float)
    rho = np.where(z > 0, 0.9, 0.0)
    x = rng.standard_normal(n)
    y1 = rho * x + np.sqrt(1.0 - rho ** 2) * rng.standard_normal(n)
    y = np.column_stack([y1, rng.integers(0, 2, n).astype(float)])
    truth = 0.5 * (-0.5 * np.log(1.0 - 0.81))
    # 5 bins per axis over 4 columns (< 8): measured 0.324 / 0.313 (-22 to -25 %)
    with pytest.warns(BiasRuleWarning, match="a discrete column keeps the histogram"):
        value = conditional_mutual_information(x, y, z, method="histogram")
    assert truth - value > 0.05  # the loss the warning names


def test_the_entropy_of_a_sample_with_a_pile_keeps_the_plain_quantile_bins():
    """R23-B7: the entropy's widths are the unsplit edges', so its bins are the plain ones.

    Reference: numpy alone, ``np.quantile`` edges (linear interpolation, the module's
    edges), ``np.searchsorted(inner, x, "right")`` bins and the plug-in differential
    entropy ``-sum p log(p / w)`` plus Miller-Madow's ``(K - 1) / (2 n)`` (Cover & Thomas
    2006, Theorem 8.3.1). Splitting the pile's tied edges here put the pile in a bin of
    zero width: an entropy of -inf.
    """
    from modalinfo.information.histogram import histogram_entropy

    rng = np.random.default_rng(23)
    n, k = 3000, 10
    x = np.where(rng.random(n) < 0.3, 0.0, rng.standard_normal(n))  # a 30 % pile at 0
    edges = np.quantile(x, np.linspace(0.0, 1.0, k + 1))
    assert np.count_nonzero(edges == 0.0) >= 2  # tied edges: the case at hand
    counts = np.bincount(np.searchsorted(edges[1:-1], x, side="right"), minlength=k)
    occ = counts > 0
    p = counts[occ] / n
    expected = -np.sum(p * np.log(p / np.diff(edges)[occ])) + (occ.sum() - 1.0) / (2.0 * n)
    value = histogram_entropy(x, bins=k, binning="quantile")
    assert np.isfinite(value)
    assert value == pytest.approx(expected, rel=1e-12)
