"""Planted-bug review 24 (issue 27): Figure 1's Targets paragraph on a user's log.

Reference: the counts of a ``Figure1`` written by hand (``_figure`` of
``test_mutation_gaps_fig1_fitting_error``): on the typical frame the five orderings need
0, 0, 2, 0, 3 modes to reach 0.4 waves^2, so "reached with 0 modes by every ordering"
is false there and the paragraph gives the range 0-3 (table (a)); with 0 everywhere
it says every ordering reaches it with 0 modes.
"""

from __future__ import annotations

import dataclasses

from paper_figures import fig1_fitting_error as fig1

from .test_mutation_gaps_fig1_fitting_error import NAMES, _figure


def _with_paper_counts(counts):
    f = _figure()
    typical = dataclasses.replace(f.typical,
                                  modes_at_paper_target=dict(zip(NAMES, counts, strict=True)))
    return dataclasses.replace(f, typical=typical)


def test_some_orderings_need_modes_for_the_paper_target():
    text = fig1.report(_with_paper_counts((0, 0, 2, 0, 3)))
    assert "the orderings need 0-3 modes to reach 0.4 waves^2 on the typical frame" in text
    assert "with 0 modes by every ordering" not in text


def test_every_ordering_at_zero_says_so():
    text = fig1.report(_with_paper_counts((0, 0, 0, 0, 0)))
    assert "\"reached\" with 0 modes by every ordering on the typical frame" in text
