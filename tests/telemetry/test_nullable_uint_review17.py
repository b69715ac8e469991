"""A table of pandas' nullable unsigned integers is read as its numbers (review17, K1).

Reference: NumPy's own conversion of the same values (``to_numpy(dtype=float)``), as the
round 18 test does for Float64. Round 18 PART a accepted numeric extension columns of kind
float, signed or unsigned integer; planted bug K1 (review17: ``"fiu"`` -> ``"fi"``) refused
a ``UInt16`` table as ``dtype object`` with no test seeing it.
"""

import numpy as np
import pandas as pd

from modalinfo.telemetry import ModalLog


def test_nullable_uint16_and_int64_tables_are_read_exactly():
    values = np.arange(60, dtype=np.uint16).reshape(20, 3) * 7 % 13
    for dtype in ("UInt16", "Int64"):
        df = pd.DataFrame(values).astype(dtype)
        log = ModalLog(df, modes=[2, 3, 4])
        assert np.array_equal(log.coeffs, values.astype(float))
