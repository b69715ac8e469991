"""``compare_orderings``'s ``specs`` as a list of strings, and refusals naming ``specs``.

Round 40 PART a, G04, G06, G09, G10. The docstring's promise ("basis:method,..." or a
list) and the orders' definitions as references: "standard" is the log's column order,
"variance" the columns by decreasing mean square (numpy on the coefficients). Before: a
list of "basis:method" strings was unpacked character-wise (ValueError: too many values
to unpack (expected 2)), and the refusals of a bad string named `orderings`, the
command line's option, not the argument.
"""

import warnings

import numpy as np
import pytest

from modalinfo.ordering.compare import compare_orderings
from modalinfo.telemetry import ModalLog


def _log():
    rng = np.random.default_rng(3)
    coeffs = rng.standard_normal((600, 6)) * np.array([0.3, 1.0, 0.5, 0.2, 0.8, 0.1])
    return ModalLog(coeffs, rate=1000.0, modes=list(range(2, 8)))


def test_a_list_of_spec_strings_is_read_as_the_string():
    log = _log()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = compare_orderings(log, ["zernike:standard", " zernike:variance"], n_pixels=16)
    got = {(e.basis, e.method): list(e.ordering.order) for e in result.entries}
    ms = np.mean(np.asarray(log.coeffs) ** 2, axis=0)
    assert got == {("zernike", "standard"): list(range(6)),
                   ("zernike", "variance"): list(np.argsort(-ms, kind="stable"))}


@pytest.mark.parametrize("specs, error", [
    (["zernike"], ValueError),
    ("standard,variance", ValueError),
    ("", ValueError),
    ([("zernike", "standard", "x")], ValueError),
    (5, TypeError),
])
def test_bad_specs_are_refused_naming_specs(specs, error):
    with pytest.raises(error, match="`specs"):
        compare_orderings(_log(), specs, n_pixels=16)
