"""``common.chunked.blocks``: rows per block within the budget (review37, issue 27).

Reference (outside the code under test): the documented rule, counted by hand: a block
holds ``budget // cost_per_row`` rows (at least one), the last block the rest.
"""

from __future__ import annotations

from modalinfo.common.chunked import blocks


def test_blocks_hold_budget_over_cost_rows():
    assert [(s.start, s.stop) for s in blocks(10, 3, budget=9)] == [(0, 3), (3, 6), (6, 9),
                                                                   (9, 10)]
    assert [(s.start, s.stop) for s in blocks(3, 100, budget=9)] == [(0, 1), (1, 2), (2, 3)]
