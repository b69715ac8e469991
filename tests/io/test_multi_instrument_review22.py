"""Two key columns beside four Zernike columns are still a minority: refused (review 22).

Issue 27, review22 (docs/MUTATION.md, "Planted bugs, round 22", M1: the key-column rule
"a minority of names that are not modes" narrowed to under a third passed
test_multi_instrument_round29, whose one key beside four or five mode columns is a fifth
or less). Reference, outside the code: the rows written with numpy's ``repr`` of ``A``
and ``B = 3 A + 1``, two WFSs interleaved and keyed by two columns (``wfs``, ``night``:
2 of 6 names, a minority), and the documented rule of ``modalinfo.io._columns.mode_columns``
(adversarial round 29 PART b, M23): refused naming both columns.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.io import LogFormatError, load

RNG = np.random.default_rng(29)
A = RNG.standard_normal((300, 4)) * 0.1
B = 3 * A + 1


def test_two_key_columns_beside_four_zernike_columns_are_refused(tmp_path):
    path = tmp_path / "keys.csv"
    names = [f"Z{j}" for j in range(2, 6)]
    rows = [",".join([*names, "wfs", "night"])]
    for a, b in zip(A, B, strict=True):
        rows.append(",".join([*map(repr, a.tolist()), "1", "7"]))
        rows.append(",".join([*map(repr, b.tolist()), "2", "7"]))
    path.write_text("\n".join(rows) + "\n")
    with pytest.raises(LogFormatError, match=r"column\(s\) 'wfs', 'night' are not modes "
                                             r"beside 4 noll mode columns"):
        load(path, rate=1000.0)
