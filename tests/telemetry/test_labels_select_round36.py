"""A labels-convention log says it takes labels, not indices (round 36 PART a, W1).

Reference: the log's own labels (``ModalLog.labels``) and the contract of the common
brief (a refusal says what was wrong). Before the fix ``select(modes=[0])`` said
"`modes` entries must be mode indices or labels; got 0" - 0 is a mode index.
"""

import numpy as np
import pytest

from modalinfo.telemetry import ModalLog


def _log() -> ModalLog:
    return ModalLog(np.arange(50.0).reshape(10, 5), rate=10.0,
                    modes=["a", "b", "c", "d", "e"], convention="labels")


@pytest.mark.parametrize("call", [lambda g: g.select(modes=[0]), lambda g: g.drop_modes(3)])
def test_index_on_labels_log_refused_saying_labels(call):
    with pytest.raises(TypeError, match="convention='labels' must be its labels"):
        call(_log())


def test_labels_still_select():
    g = _log().select(modes=["d", "b"])
    assert g.modes == ["d", "b"]
    np.testing.assert_array_equal(g.coeffs, np.arange(50.0).reshape(10, 5)[:, [3, 1]])
