"""Review 21: ``mode_span`` shortens more than four runs, counting the modes left out.

Reference: the documented rule (``telemetry.checks.mode_span``), applied by hand: each
run of consecutive integer modes is ``first .. last``; with more than four runs the
first two and the last are written, and between them the number of modes of the runs
left out (counted here by hand from the lists).
"""

from __future__ import annotations

import pytest

from modalinfo.telemetry.checks import mode_span


@pytest.mark.parametrize(("modes", "text"), [
    ([2, 4, 6, 8], "Z2, Z4, Z6, Z8"),  # four runs: all written
    ([2, 4, 6, 8, 10], "Z2, Z4, ... (2 more modes) ..., Z10"),  # five: Z6, Z8 left out
    ([2, 3, 5, 7, 8, 9, 11, 13, 14], "Z2 .. Z3, Z5, ... (4 more modes) ..., Z13 .. Z14"),
])
def test_mode_span_by_hand(modes, text):
    assert mode_span(modes, "noll") == text
