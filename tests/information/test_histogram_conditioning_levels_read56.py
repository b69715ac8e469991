"""The histogram CMI codes a discrete conditioning z by its levels first (read56, issue 27).

fix54-c coded discrete x, y and z columns alike, the fewest levels first, within one
budget of ``n / 4`` cells (``histogram.discrete_column_levels``); Q47's rule (round 51
PART a) had coded a discrete z by its levels within ``n`` cells. Where z has too many
levels for ``n / 4`` (and x and y as many), z went back to the quantile bins, which merge
its levels, and x and y, which both follow z inside a merged bin, share a CMI that z
does not leave them: a false link. Measured (10 seeds, n = 3,000, 7 bins per axis):
z ~ Poisson(10) (~23 levels), x, y = z + independent Bernoulli(1/2), 0.0626 (s.e. 0.0025)
where 784a057f (Q47's rule) read -0.0001; x, y = z + N(0, 0.5^2), 0.060 for 0.0025.
Now z's columns are coded first within Q47's budget, then x's and y's within fix54-c's.

References: the exact CMI, 0 (x and y are independent given z by construction); the
mean of 10 seeds must be under 0.01 nats, 25 s.e. below the value of before and 10 s.e.
above the value after (false-failure rate negligible; seeds fixed, 1000 - 1009).
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.information import conditional_mutual_information
from modalinfo.information.methods import BiasRuleWarning

from ._levels_table import plugin_cmi_mm as _plugin_cmi_mm


def _triple(seed: int, noise: float | None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """z ~ Poisson(10), n = 3,000; x, y = z + Bernoulli(1/2) (None) or + N(0, noise^2)."""
    rng = np.random.default_rng(1000 + seed)
    n = 3000
    z = rng.poisson(10, n).astype(float)
    if noise is None:
        x, y = z + rng.integers(0, 2, n), z + rng.integers(0, 2, n)
    else:
        x, y = z + noise * rng.standard_normal(n), z + noise * rng.standard_normal(n)
    return x.astype(float), y.astype(float), z


def test_integer_copies_of_a_poisson_z_hold_no_cmi_given_it():
    values = [conditional_mutual_information(*_triple(s, None), method="histogram")
              for s in range(10)]  # no warning either (the suite makes one an error)
    assert np.mean(values) < 0.01  # exact 0; before 0.0626 (z merged into 7 bins)


def test_noisy_copies_of_a_poisson_z_hold_no_cmi_given_it():
    values = []
    for s in range(10):
        # the 7 bins of x and y are below the resolution rule's 8, warned as before
        with pytest.warns(BiasRuleWarning, match="resolution rule"):
            values.append(conditional_mutual_information(*_triple(s, 0.5),
                                                         method="histogram"))
    assert np.mean(values) < 0.01  # exact 0; before 0.060


def test_a_few_level_x_keeps_its_levels_beside_a_many_level_z():
    """z Poisson(30) (~37 levels) first, then a 4-level x of shares 0.05 / 0.45 / 0.45 / 0.05.

    Every column is coded by its levels, so the value is the levels' table's (numpy's
    Miller-Madow plug-in, to 1e-9). c423e5eb merged z (over n / 4 cells with x's and y's
    levels); z coded first without the rule that a column of at most k levels is always
    kept binned x into 7 quantile bins, which put its last two levels in one.
    """
    rng = np.random.default_rng(56)
    n = 3000
    z = rng.poisson(30, n)
    x = rng.choice(4, n, p=[0.05, 0.45, 0.45, 0.05])
    y = x + rng.integers(0, 2, n) + (z > 30)
    got = conditional_mutual_information(*(a.astype(float) for a in (x, y, z)),
                                         method="histogram")
    assert got == pytest.approx(_plugin_cmi_mm(x, y, z), abs=1e-9)
