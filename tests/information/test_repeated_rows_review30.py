"""The edges of ``repeated_rows_why``'s rule, as its docstring states them (review30, round 30).

Round 47 PART a (fixes 47-a) judges ksg on rows repeated in every column at once: "the
columns tying nowhere else (each column has exactly as many distinct values as there are
distinct rows) and fewer than DISCRETE_MIN_PER_CELL rows per distinct row, each repeated
row held fewer times than that (a row held more often is an atom)". Planted slips at
each edge passed tests/information/test_repeated_rows_round47.py: ``counts <=`` (an
atom held exactly DISCRETE_MIN_PER_CELL times counted as repeats: I2), the first
column's ``first != distinct`` dropped (I3), ``n > DISCRETE_MIN_PER_CELL * distinct``
(I4), and ``mutual_information`` judging x alone (I5: a mode repeated where the other
is not). Reference: the docstring's rules, with the counts of rows, distinct rows and
repeats made here by construction (numpy) and counted by hand.
"""

from __future__ import annotations

import warnings

import numpy as np

from modalinfo.information import mutual_information
from modalinfo.information.discrete import DISCRETE_MIN_PER_CELL, repeated_rows_why

K = DISCRETE_MIN_PER_CELL  # 10


def _distinct(n, seed=3):
    rng = np.random.default_rng(seed)
    return rng.standard_normal(n), rng.standard_normal(n)


def test_an_atom_held_exactly_the_cell_minimum_is_not_a_repeat():
    # 3000 distinct rows, 40 of them held K times: atoms (no repeats counted); 3360 rows
    x, y = _distinct(3000)
    idx = np.r_[np.arange(3000), np.repeat(np.arange(40), K - 1)]
    assert repeated_rows_why({"x": x[idx], "y": y[idx]}, "ksg") is None
    # held K - 1 times: 40 x (K - 2) = 320 repeats of 3320 rows (9.6 %): judged
    idx = np.r_[np.arange(3000), np.repeat(np.arange(40), K - 2)]
    why = repeated_rows_why({"x": x[idx], "y": y[idx]}, "ksg")
    assert why is not None and why.startswith(f"{40 * (K - 2)} of the 3320 rows")


def test_a_first_column_that_ties_across_rows_is_not_judged():
    # x rounded (ties across different rows), y distinct, 300 of 3000 rows repeated
    x, y = _distinct(3000)
    x = np.round(x, 1)
    idx = np.r_[np.arange(3000), np.arange(300)]
    assert np.unique(x).size < 3000 == np.unique(y).size
    assert repeated_rows_why({"x": x[idx], "y": y[idx]}, "ksg") is None
    assert repeated_rows_why({"y": y[idx], "x": x[idx]}, "ksg") is None


def test_exactly_the_cell_minimum_rows_per_distinct_row_is_not_judged():
    # 1000 distinct rows: 500 held twice, 500 held 2 K - 2 times: 5000 rows = K x 1000
    x, y = _distinct(1000)
    idx = np.r_[np.repeat(np.arange(500), 2), np.repeat(np.arange(500, 1000), 2 * K - 2)]
    assert idx.size == K * 1000
    assert repeated_rows_why({"x": x[idx], "y": y[idx]}, "ksg") is None
    # one row fewer: below K per distinct row, 500 repeats (the pairs held twice) judged
    why = repeated_rows_why({"x": x[idx[1:]], "y": y[idx[1:]]}, "ksg")
    assert why is not None and why.startswith(f"499 of the {K * 1000 - 1} rows")


def test_one_variable_repeated_alone_is_not_a_repeated_row():
    # x holds 300 repeated values at rows where y is fresh: no row repeats in both
    rng = np.random.default_rng(8)
    x = rng.standard_normal(3000)
    x = x[np.r_[np.arange(3000), np.arange(300)]]
    y = 0.6 * x + 0.8 * rng.standard_normal(x.size)
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        mutual_information(x, y, method="ksg")
    assert not [w for w in rec if "repeat an earlier row" in str(w.message)]
