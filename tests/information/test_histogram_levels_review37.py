"""The histogram's merged-levels note names a merged z (review37, issue 27).

Reference (outside the code under test): the columns' distinct values (``numpy.unique``)
and the bias rule's arithmetic: 2,000 samples and 3 axes give 7 quantile bins per axis
(a 343-cell table). x's and y's levels have the budget max(343, 2000 // 4) = 500 cells,
so a 12-level x would need 7 * 7 * 12 = 588 cells and keeps the bins; z's levels are
coded first within Q47's max(343, 2000) cells (read56: a merged z level is a false link),
so a 12-level z (588 cells) keeps its levels and a 48-level z (2,352 cells) the bins.
Where levels merge, the note must say so whichever of x, y, z holds them."""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.information.histogram import merged_levels_why


def _columns(where: str, count: int):
    rng = np.random.default_rng(0)
    n = 2000
    levels = rng.integers(0, count, n).astype(float)
    assert np.unique(levels).size == count
    other = rng.standard_normal(n) + levels
    y = (rng.standard_normal(n) + levels)[:, None]
    x, z = (levels[:, None], other[:, None]) if where == "x" else (other[:, None], levels[:, None])
    return x, y, z


@pytest.mark.parametrize(("where", "count"), [("x", 12), ("z", 48)])
def test_a_merged_discrete_column_is_named_in_x_or_z(where, count):
    # read56: z was 12 levels here (merged by fix54-c's one budget of n / 4; now coded)
    why = merged_levels_why(*_columns(where, count))
    assert why is not None and f"`{where}` {count}" in why and "7 bins" in why


def test_a_twelve_level_z_keeps_its_levels():
    """read56: z's levels are coded first within n cells (588 here): nothing merged."""
    assert merged_levels_why(*_columns("z", 12)) is None


def test_bins_the_caller_chose_give_no_note():
    # documented: None for a number of bins the caller chose (theirs, as elsewhere)
    rng = np.random.default_rng(0)
    n = 2000
    levels = rng.integers(0, 12, n).astype(float)[:, None]
    noise = rng.standard_normal((n, 1))
    assert merged_levels_why(levels, noise + levels, noise, bins=7) is None


def test_two_discrete_z_columns_are_coded_as_their_pairs():
    # x = 3 z1 + z2 is a function of the pair (z1, z2): I(x; y | z) = 0 exactly, and the
    # plug-in (no bias correction) of a table that codes every pair apart is exactly 0
    from modalinfo.information.histogram import histogram_cmi

    rng = np.random.default_rng(0)
    n = 4000
    z = rng.integers(0, 3, (n, 2)).astype(float)
    x = (3 * z[:, 0] + z[:, 1])[:, None]
    y = x + rng.integers(0, 2, (n, 1))
    assert histogram_cmi(x, y, z, bias_correction="none") == pytest.approx(0.0, abs=1e-12)
