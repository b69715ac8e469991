"""``selection.search_bytes``: the candidate search's memory estimate (review37, issue 27).

Reference (outside the code under test): the estimate's documented count (fix54-d,
docs/ADVERSARIAL.md and ``search_bytes``' docstring): 6 float64 copies of the
candidates plus 4 column blocks, a block ``min(2^20, 2 x candidates)`` values (the
whole candidates at twice the values when they are fewer than a block), 8 bytes each:
``48 v + 32 min(2^20, 2 v)`` bytes for ``v`` candidate values, counted by hand.
"""

from __future__ import annotations

import pytest

from modalinfo.information.selection import search_bytes


@pytest.mark.parametrize(("values", "want"), [
    (1000, 48 * 1000 + 32 * 2000),                       # small: blocks of 2 v
    (2 ** 19, 48 * 2 ** 19 + 32 * 2 ** 20),              # 2 v = one block exactly
    (3000 * 10 * 2000, 48 * 60_000_000 + 32 * 2 ** 20),  # 3,000 modes x 10 lags x 2,000
])
def test_search_bytes_counts_six_copies_and_four_blocks(values, want):
    assert search_bytes(values) == want
