"""The kde tie rule's edge against the plug-in table's (review34, mutation round 34).

``discrete.tied_table_why`` (round 51 PART a, Q54) speaks where every column is discrete
but the joint table is too sparse for the plug-in of ``discrete_cmi``, and is silent where
that table applies. Reference: the count of the cells, by hand: x and y of 10 levels each
and z of 2 give 200 cells, so n = 2,000 holds exactly ``DISCRETE_MIN_PER_CELL`` (10)
samples per cell (the plug-in's case, inclusive: ``discrete_cmi`` returns its table's
value there) and n = 1,990 holds fewer (the kernel's case, warned). Deterministic data; a
continuous column (normal draws, seed 34) is no discrete one.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.information.discrete import (
    DISCRETE_MIN_PER_CELL,
    discrete_cmi,
    tied_table_why,
)


def _columns(n: int) -> dict[str, np.ndarray]:
    i = np.arange(n)
    return {"x": (i % 10).astype(float), "y": ((i // 10) % 10).astype(float),
            "z": ((i // 100) % 2).astype(float)}


@pytest.mark.parametrize("n, plug_in", [(2000, True), (1990, False)])
def test_the_rule_is_silent_exactly_where_the_table_applies(n, plug_in):
    assert DISCRETE_MIN_PER_CELL == 10  # the 2,000 below is 10 x 200 cells
    cols = _columns(n)
    table = discrete_cmi(*(cols[k][:, None] for k in ("x", "y", "z")))
    assert (table is not None) == plug_in
    why = tied_table_why(cols, "kde")
    if plug_in:
        assert why is None
    else:
        assert why is not None and "200 cells" in why and f"n = {n}" in why


def test_one_continuous_column_is_no_tied_table():
    # the rule is for every column discrete: with a continuous z (no value repeated) it
    # is silent, though x's 30 levels and y's 10 alone would be a sparse table (300
    # cells for 1,990 rows), and speaks once z is discrete again
    n = 1990
    i = np.arange(n)
    cols = {"x": (i % 30).astype(float), "y": ((i // 30) % 10).astype(float),
            "z": np.random.default_rng(34).normal(size=n)}
    assert discrete_cmi(*(cols[k][:, None] for k in ("x", "y", "z"))) is None
    assert tied_table_why(cols, "kde") is None
    cols["z"] = (i % 2).astype(float)
    assert "600 cells" in tied_table_why(cols, "kde")
