"""A serialised ordering's bootstrap bounds must be real (round 37 PART a, S11 / M4).

Reference: construction. An ordering written with ``n_resamples=40`` carries finite
bootstrap bounds of the margins between ranks; the same file with ``margin_low`` set to
all null (a file edited or written by another tool) holds no bound at all, so the order's
noise was not assessed and the result must say so (``noise_assessed`` False, the
"noise not assessed" note), not read as determined. A file claiming ``n_resamples`` 0
(no bootstrap) yet carrying bootstrap bounds contradicts itself and is refused, naming
the field.
"""

import numpy as np
import pytest

from modalinfo.ordering import OrderingResult, order_modes
from modalinfo.ordering.compare import basis_for_log
from modalinfo.telemetry import ModalLog


@pytest.fixture(scope="module")
def record():
    a = np.random.default_rng(3).standard_normal((300, 3)) * [1.0, 0.7, 0.3]
    log = ModalLog(a, rate=1000.0, modes=[2, 3, 4])
    basis = basis_for_log("zernike", log, n_pixels=16)
    res = order_modes(log, basis, "mi_greedy", sample_budget=20_000, seed=0, n_resamples=40)
    assert res.noise_assessed is True
    return res.to_dict()


def test_all_null_margins_are_not_an_assessment(record):
    data = dict(record, margin_low=[None] * len(record["margin_low"]))
    back = OrderingResult.from_dict(data)
    assert back.noise_assessed is False
    assert back.to_dict()["noise_assessed"] is False
    assert sum("not assessed" in n for n in back.notes()) == 1
    assert "not assessed" in back.legend()


@pytest.mark.parametrize("field", ["margin_low", "gain_low", "mi_high"])
def test_zero_resamples_with_bounds_refused(record, field):
    data = {k: v for k, v in record.items()
            if k not in ("mi_low", "mi_high", "gain_low", "gain_high", "margin_low",
                         "margin_high") or k == field}
    data["n_resamples"] = 0
    with pytest.raises(ValueError, match=r"`data\['n_resamples'\]` is 0.*" + field):
        OrderingResult.from_dict(data)
    data.pop(field)  # without the bounds the file is consistent
    assert OrderingResult.from_dict(data).noise_assessed is False
