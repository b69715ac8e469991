"""The histogram CMI keeps its histogram when ANY column is discrete, not only the first.

Reference: the documented resolution rule (module notes of
``modalinfo.information.conditional``): the switch to the KSG CMI needs every column
continuous; a discrete column (at most n / 20 distinct values, the rule of the kde and
ksg engines) keeps the histogram. The data: the Gaussian triple of
tests/information/test_cmi_switch_ties_round16.py (partial correlation 0.8 given z)
with a second conditioning column of 3 levels, independent of the rest, so the exact
CMI stays ``-0.5 ln(1 - 0.64)`` = 0.511 nats; with the discrete column in either place
of z no switch is made, and with it replaced by a continuous column the switch is made
(the rule fails at d = 4, n = 2000). Planted bugs that judged only each group's first
column (R16-A3) or switched when any column was continuous escaped before this file.
"""

import warnings

import numpy as np
import pytest

from modalinfo.information import conditional_mutual_information


@pytest.fixture(scope="module")
def data():
    rng = np.random.default_rng(1616)
    n = 2000
    z, e1, e2 = rng.standard_normal((3, n))
    levels = rng.integers(0, 3, n).astype(float)
    other = rng.standard_normal(n)
    return z + e1, z + 0.8 * e1 + 0.6 * e2, z, levels, other


def _switched(x, y, z) -> bool:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        conditional_mutual_information(x, y, z, method="histogram")
    return any("KSG CMI instead" in str(w.message) for w in caught)


@pytest.mark.parametrize("where", ["second", "first"])
def test_a_discrete_conditioning_column_keeps_the_histogram(data, where):
    x, y, z, levels, _ = data
    zz = np.column_stack([z, levels] if where == "second" else [levels, z])
    assert not _switched(x, y, zz)


def test_all_continuous_columns_switch(data):
    x, y, z, _, other = data
    assert _switched(x, y, np.column_stack([z, other]))
