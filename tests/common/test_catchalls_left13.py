"""The catch-all ``except Exception`` of the packages does not re-label a lack of memory.

Issue 27, left13-cli item 6 (the review of every ``except Exception`` is recorded in
docs/ADVERSARIAL.md, "Leftovers 13-cli"). ``as_float_array`` turned any failure of
``np.asarray`` into ``TypeError: `x` must be a numeric array``, a ``MemoryError`` included:
a value too big for memory was called the wrong type. Reference, outside the code: Python's
exception hierarchy (``MemoryError`` and ``TypeError`` are distinct built-ins; a
``KeyboardInterrupt`` is no ``Exception``), and numpy's ``__array__`` protocol, through
which the value raises.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.common.validation import as_float_array


class _Raises:
    def __init__(self, error: BaseException) -> None:
        self.error = error

    def __array__(self, dtype=None, copy=None):
        raise self.error


def test_a_memory_error_stays_a_memory_error():
    with pytest.raises(MemoryError, match="Unable to allocate"):
        as_float_array(_Raises(MemoryError("Unable to allocate 8.00 TiB")), "x")


def test_ctrl_c_passes_and_a_ragged_list_is_a_type_error():
    with pytest.raises(KeyboardInterrupt):
        as_float_array(_Raises(KeyboardInterrupt()), "x")
    with pytest.raises(TypeError, match="`x` must be a numeric array"):
        as_float_array([[1.0, 2.0], [3.0]], "x")
    np.testing.assert_array_equal(as_float_array([1, 2], "x"), [1.0, 2.0])
