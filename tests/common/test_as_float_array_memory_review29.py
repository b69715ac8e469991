"""``as_float_array`` checks the memory of every copy it makes, a strided one too (review29).

Round 29 V2 (modalinfo/common/validation.py:441, round 46 PART a A11): the check runs
when "a copy is made": a copy asked, another dtype, or an array that is not C-contiguous
(``np.asarray(order="C")`` copies it). Planted without the contiguity clause, it passed
every test, whose large arrays were int or float32. Reference, outside the package: the
arithmetic of the copy, 2^25 float64 values x 8 bytes = 0.25 GiB, against an available
memory set here (``modalinfo.common.memory.available_memory_bytes`` replaced, as in
test_check_memory.py); numpy's ``flags`` (the view is not C-contiguous, holds no memory).
"""

import numpy as np
import pytest

from modalinfo.common import memory
from modalinfo.common.validation import as_float_array


def test_a_copy_of_a_strided_float64_array_is_checked(monkeypatch):
    monkeypatch.setattr(memory, "available_memory_bytes", lambda: float(100 * 2**20))
    view = np.broadcast_to(np.zeros(1), (2**25,))  # 0.25 GiB as a copy, 8 bytes as a view
    assert view.dtype == np.float64 and not view.flags.c_contiguous
    with pytest.raises(ValueError, match=r"^`data` needs about 0\.25 GiB for a float64 copy "
                                         r"of its \(33554432,\) values and 0\.0977 GiB"):
        as_float_array(view, "data")
    small = np.broadcast_to(np.zeros(1), (1000,))  # below 128 MiB: copied, not refused
    assert as_float_array(small, "data").flags.c_contiguous
