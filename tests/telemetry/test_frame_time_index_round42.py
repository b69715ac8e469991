"""A DataFrame's DatetimeIndex against the log's time axis (adversarial round 42 PART a, M08-M10).

``ModalLog(df, rate=500)`` with a 1 ms DatetimeIndex kept 500 Hz, and rows shuffled or
reversed in time by their index were analysed in that order: the index was dropped.
Reference: pandas' own index (``Index.is_monotonic_increasing``, ``np.diff`` of
``total_seconds``) and the rule the log applies to ``rate`` against ``timestamps``
(median interval within 1e-3 of ``1 / rate``).
"""

import numpy as np
import pandas as pd
import pytest

from modalinfo.telemetry import ModalLog

RNG = np.random.default_rng(4242)
DATA = RNG.standard_normal((300, 4))
INDEX = pd.date_range("2026-06-01 12:00", periods=300, freq="1ms")


def test_rate_disagreeing_with_index_refused():
    frame = pd.DataFrame(DATA, index=INDEX)
    assert np.median(np.diff((frame.index - frame.index[0]).total_seconds())) == pytest.approx(1e-3)
    with pytest.raises(ValueError, match=r"`rate` \(500.0 Hz\) disagrees with the DatetimeIndex"):
        ModalLog(frame, rate=500.0)


@pytest.mark.parametrize("order", ["shuffled", "reversed", "repeated"])
def test_rows_out_of_time_order_refused(order):
    frame = pd.DataFrame(DATA, index=INDEX)
    if order == "shuffled":
        frame = frame.iloc[RNG.permutation(len(frame))]
    elif order == "reversed":
        frame = frame.sort_index(ascending=False)
    else:
        frame.index = INDEX.where(np.arange(300) != 7, INDEX[6])
    assert not frame.index.is_monotonic_increasing or not frame.index.is_unique
    with pytest.raises(ValueError, match="not strictly increasing"):
        ModalLog(frame, rate=1000.0)


@pytest.mark.parametrize("index", [INDEX, pd.to_timedelta(np.arange(300), unit="ms")])
def test_index_in_order_at_the_rate_accepted(index):
    log = ModalLog(pd.DataFrame(DATA, index=index), rate=1000.0)
    assert log.rate == 1000.0
    np.testing.assert_array_equal(log.coeffs, DATA)


def test_index_without_rate_accepted_as_before():
    log = ModalLog(pd.DataFrame(DATA, index=INDEX))
    assert log.rate is None
    np.testing.assert_array_equal(log.coeffs, DATA)
