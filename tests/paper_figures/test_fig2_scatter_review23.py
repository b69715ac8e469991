"""Figure 2's ranking-scatter sentence clips a negative lag-1 autocorrelation (review23).

docs/MUTATION.md, "Planted bugs, round 23", R23-B3: left30-twins routed the sentence's
lag-1 autocorrelation through ``lag1_autocorrelations``; the module docstring clips it to
[0, 1) (a negative r would claim more effective frames than frames). The hand example of
``test_mutation_gaps_fig2_sr_peak.py`` (r = -0.79) reads "within" either way, so a clip
at -1 escaped.

Reference: hand numbers (dyadic series, every value exact). Over frames 2..5,
linear - arma = d = [0.625, -0.125, 0.625, -0.125]: mean 0.25 (the spread of the two
means), sd (ddof 1) 0.375 sqrt(4 / 3) = 0.4330, lag-1 autocorrelation -0.75 (Brockwell
& Davis eq. 1.4.4: 3 x (-0.140625) / (4 x 0.140625)). Clipped to 0: n_eff = 4,
2 se = 0.4330 > 0.25, within the scatter; unclipped, n_eff = 4 x 1.75 / 0.25 = 28 and
2 se = 0.1637 < 0.25 would say the ranking holds.
"""

from __future__ import annotations

from paper_figures import fig2_sr_peak as fig2

from .test_mutation_gaps_fig2_sr_peak import SERIES, _runs


def test_a_negative_lag1_autocorrelation_is_clipped_to_zero():
    series = dict(SERIES, **{"linear": ([0.0, 0.0, 0.875, 0.5, 0.875, 0.5], 3),
                             "arma": ([0.0, 0.0, 0.25, 0.625, 0.25, 0.625], 4)})
    r = fig2.compute(_runs(("none", "linear", "arma"), series=series))
    assert (r.peak_mean["linear"], r.peak_mean["arma"]) == (0.6875, 0.4375)
    last = fig2.table_rows(r)[3][3]
    assert last.endswith("; within twice the standard error of the frame-by-frame "
                         "difference: the ranking is within the run's scatter"), last
