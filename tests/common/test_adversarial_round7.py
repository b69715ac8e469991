"""Round 7 of issue 27's adversarial inputs (validation): integers float64 rounds together.

The full list of inputs tried is in docs/ADVERSARIAL.md, section "Round 7, issue 27".

Reference: IEEE 754 binary64 holds every integer up to 2^53 exactly and, between 2^62
and 2^63, only multiples of 2^10 (binary32: integers up to 2^24); the MI of a sample
and that of its ranks shifted by an offset are equal (MI is invariant under monotone
maps, Kraskov et al. 2004).
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.common.validation import as_float_array
from modalinfo.information import mutual_information
from modalinfo.telemetry import ModalLog


def _ranks(n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    x = rng.standard_normal(n)
    return np.argsort(np.argsort(x)).astype(np.int64), 0.6 * x + 0.8 * rng.standard_normal(n)


def test_integers_near_2_63_that_float64_merges_are_refused():
    # a31, a32: ranks + (2^63 - 10^4) became 5 distinct floats: MI 0.14 for 0.23, silently
    r, y = _ranks(2000, 7)
    with pytest.raises(ValueError, match=r"`x` holds integers beyond 2\^53 .*\(2000 distinct "
                                         r"values become \d+\); subtract an offset"):
        mutual_information(r + (2**63 - 10_000), y, method="ksg")
    with pytest.raises(ValueError, match=r"`x` holds integers beyond 2\^53"):
        mutual_information(r.astype(np.uint64) + np.uint64(2**64 - 5000), y, method="ksg")


def test_large_integers_float64_holds_exactly_are_kept():
    # multiples of 2^10 near 2^62 are exact in float64: same MI as the ranks themselves
    r, y = _ranks(2000, 8)
    big = r * 1024 + 2**62
    assert mutual_information(big, y, method="ksg") == mutual_information(r, y, method="ksg")


def test_the_float32_limit_is_2_24():
    a = np.array([2**24, 2**24 + 1, 2**24 + 2], dtype=np.int64)  # 2^24 + 1 rounds to 2^24
    with pytest.raises(ValueError, match=r"`a` holds integers beyond 2\^24"):
        as_float_array(a, "a", dtype=np.float32)
    assert as_float_array(a, "a").tolist() == [2**24, 2**24 + 1, 2**24 + 2]


def test_a_log_of_integers_float64_merges_is_refused():
    # f14: ModalLog of int64 coefficients near 2^63 kept 2 distinct values of 800
    c = np.arange(800, dtype=np.int64).reshape(400, 2) + (2**63 - 1000)
    with pytest.raises(ValueError, match=r"`coeffs` holds integers beyond 2\^53"):
        ModalLog(c, rate=1e3, modes=[2, 3])
