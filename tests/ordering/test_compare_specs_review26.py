"""Planted-bug review 26 (stop 50): a bad basis and a bad method are told apart in ``specs``.

Round 40 PART a (G04-G10) made ``compare_orderings``' refusals name ``specs``; each part
of a ``basis:method`` entry is checked against its own list (the documented bases and
methods, ``modalinfo.ordering.compare.BASES`` / ``METHODS``). Reference: those lists.
Plant R26-D3 (the method refused as ``specs basis``) escaped
tests/ordering/test_compare_specs_round40.py, which matched "`specs" only.
"""

import numpy as np
import pytest

from modalinfo.ordering.compare import BASES, METHODS, compare_orderings
from modalinfo.telemetry import ModalLog


def _log():
    coeffs = np.random.default_rng(3).standard_normal((600, 6))
    return ModalLog(coeffs, rate=1000.0, modes=list(range(2, 8)))


@pytest.mark.parametrize("specs, part, listed", [
    (["zernike:nope"], "method", METHODS),
    ([("nope", "standard")], "basis", BASES),
    ("zernike:standard,nope:variance", "basis", BASES),
])
def test_the_refusal_names_the_part_that_is_wrong_and_its_choices(specs, part, listed):
    with pytest.raises(ValueError) as err:
        compare_orderings(_log(), specs, n_pixels=16)
    text = str(err.value)
    assert text.startswith(f"`specs {part}` must be one of "), text
    assert all(repr(v) in text for v in listed) and text.endswith("got 'nope'."), text
