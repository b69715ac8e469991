"""A range written between labels ('Z2-Z4') is refused saying how ranges are written.

Adversarial round 41 PART b, issue 27 (row F08): `modalinfo forecast --modes Z2-Z4` on a
log of Z2..Z11 was refused with "'Z2-Z4' is not a mode of this log; its modes are
Z2..Z11" - untrue of Z2, Z3 and Z4. Reference, outside the code: the log's own modes
(Noll 2..11, given to the constructor) and the help's documented forms ('2-10',
'2,3,4' or labels); a range past the log's modes keeps the "not a mode" refusal.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.telemetry import ModalLog


def _log() -> ModalLog:
    return ModalLog(np.random.default_rng(41).standard_normal((50, 10)), rate=1000.0,
                    modes=list(range(2, 12)))


def test_a_label_range_says_how_ranges_are_written():
    with pytest.raises(ValueError, match=r"range is read between mode indices") as err:
        _log().select(modes=["Z2-Z4"])
    assert "is not a mode of this log" not in str(err.value)


def test_the_index_range_and_the_listed_labels_select_the_same_modes():
    log = _log()
    assert log.select(modes=[2, 3, 4]).modes == log.select(modes=["Z2", "Z3", "Z4"]).modes
    with pytest.raises(ValueError, match="is not a mode of this log"):
        log.select(modes=["Z2-Z40"])
