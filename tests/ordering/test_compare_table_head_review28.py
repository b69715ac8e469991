"""``Comparison.table``'s head promises target columns only when they follow (review28).

Round 43 PART b, d14: "last columns: modes to reach each target" headed a table of
``n=`` columns alone. Planted bug R28-O3 (the promise kept for ``fractions`` alone
forgotten, ``if targets``) escaped ``tests/cli/test_wordings_round43.py``. Reference: the
table's own head row, read back here (the ``<=`` columns it has or has not).
"""

import numpy as np
import pytest

from modalinfo.ordering.compare import compare_orderings
from modalinfo.telemetry import ModalLog


@pytest.fixture(scope="module")
def comparison():
    coeffs = np.random.default_rng(0).standard_normal((400, 9)) * np.linspace(2, 0.5, 9)
    log = ModalLog(coeffs, rate=1000.0, modes=list(range(2, 11)), units="rad")
    return compare_orderings(log, "zernike:variance", units="rad2", n_pixels=80)


@pytest.mark.parametrize("targets, fractions", [(None, None), ([0.5], None), (None, [0.1]),
                                                ([0.5], [0.1])])
def test_the_promise_follows_the_columns(comparison, targets, fractions):
    title, head = comparison.table(targets=targets, fractions=fractions).splitlines()[:2]
    has_columns = "<=" in head
    assert has_columns == bool(targets or fractions)
    assert ("last columns: modes to reach each target" in title) == has_columns
