"""Mutation round 36 (review36): ``outlier_columns`` / ``outlier_note`` (round 53 PART a).

Plants that escaped stop 60's tests (docs/MUTATION.md, "Round 36"): the short-series
guard, the few-level columns left out (``min_levels``, ``OUTLIER_MIN_LEVELS`` 32) and the
note's order (the worst column, relative to its threshold, first).

References (outside the code): the planted glitches (their columns, frames and sizes
known by construction) in seeded Gaussian AR(1) series (``scipy.signal.lfilter``); the
documented rules (fewer than ``4 p + 2 = 18`` rows: nothing judged; a column of fewer
than ``min_levels`` distinct values: not judged) counted with numpy.
"""

from __future__ import annotations

import numpy as np
from scipy.signal import lfilter

from modalinfo.information.resampling import outlier_columns, outlier_note


def _ar1(seed: int, n: int, m: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return lfilter([1.0], [1.0, -0.5], rng.standard_normal((n + 200, m)), axis=0)[200:]


def test_a_series_under_18_rows_is_not_judged():
    x = _ar1(1, 17, 3)
    x[10, 1] += 1e3
    assert outlier_columns(x) == []
    y = _ar1(1, 400, 3)
    y[200, 1] += 1e3
    assert [c for c, *_ in outlier_columns(y)] == [1]   # judged from 18 rows up


def test_few_level_columns_are_not_judged():
    # a column of 9 levels (integers -4..4) with one value 60: not judged at 32 levels,
    # judged (and flagged) when every column is
    rng = np.random.default_rng(2)
    x = _ar1(2, 2000, 3)
    x[:, 2] = rng.integers(-4, 5, 2000)
    x[700, 2] = 60
    assert np.unique(x[:, 2]).size == 10
    assert [c for c, *_ in outlier_columns(x)] == [2]
    assert outlier_columns(x, min_levels=32) == []
    assert outlier_note(x, ["a", "b", "c"], "f") is None


def test_the_note_names_the_worst_column_first():
    x = _ar1(3, 2000, 4)
    x[500, 1] += 15.0        # the smaller glitch
    x[900, 3] += 60.0        # the larger one, named first
    note = outlier_note(x, ["m0", "m1", "m2", "m3"], "select_inputs")
    assert note.startswith("select_inputs: 2 series hold outliers")
    assert note.index("m3 (") < note.index("m1 (")
    assert "m3 (" in note and "at frame 900)" in note


def test_columns_are_counted_past_a_constant_one():
    x = _ar1(4, 2000, 3)
    x[:, 0] = 1.5                   # constant: not judged, still column 0
    x[800, 2] += 60.0
    assert [(c, t) for c, t, *_ in outlier_columns(x)] == [(2, 800)]


def test_the_heavy_tail_words_give_the_worst_column():
    # x glitched by 60 innovation sds (AR(1) 0.5 of unit innovations), y by 15: the
    # interval's words give the larger reach
    import re

    from modalinfo.information.resampling import _heavy_tail_rule

    xy = _ar1(5, 2000, 2)
    xy[600, 0] += 60.0
    xy[1200, 1] += 15.0
    words = _heavy_tail_rule(xy[:, :1], xy[:, 1:], "mutual_information_ci")
    reach = float(re.search(r"innovations reach ([0-9.]+) robust sigmas", words)[1])
    assert 45.0 < reach < 75.0


def test_the_threshold_rises_with_the_columns_judged():
    # the false-alarm probability is over the columns: one glitched column judged among
    # 40 must reach further than judged alone
    x = _ar1(6, 2000, 40)
    x[700, 0] += 60.0
    alone = outlier_columns(x[:, :1])
    among = [f for f in outlier_columns(x) if f[0] == 0]
    assert alone and among and among[0][3] > alone[0][3] + 0.3
