"""Round 39 PART a, Q06: frames swapped in pairs on a smooth (open-loop, 1 kHz) log.

``open_loop_log`` Z2..Z13 at 1 kHz, D = 8 m, wind 10 m/s (lag-1 autocorrelations
0.998-1.0), written in swapped pairs over the whole log or over rows 2000..3999: the
pair-order rule read lag-1 products, dominated by the slow level for modes this
persistent (p = 0.96 and 0.90), and the report was clean, while numpy's persistence RMSE
of the swapped log is 2.2x (1.5x) the true log's. Reference: the swap itself (the rows
written) and numpy's first differences; the unswapped log must stay clean.
"""

import warnings

import numpy as np
import pytest

from modalinfo.telemetry import ModalLog, assess_quality
from modalinfo.telemetry.synthetic import open_loop_log
from modalinfo.telemetry.synthetic.spectra import Layer


@pytest.fixture(scope="module")
def smooth():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        log = open_loop_log(list(range(2, 14)), n_frames=4000, rate=1000.0, diameter=8.0,
                            layers=[Layer(r0=0.15, wind_speed=10.0)], seed=7)
    return np.asarray(log.coeffs)


def _swapped(x, start):
    y = x.copy()
    y[start::2], y[start + 1::2] = x[start + 1::2], x[start::2]
    return y


def _report(x):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return assess_quality(ModalLog(x, rate=1000.0))


def _step_rms(x):
    return float(np.sqrt(np.mean(np.diff(x, axis=0) ** 2)))


def test_the_true_log_is_clean(smooth):
    report = _report(smooth)
    assert report.pair_order == () and report.clean


@pytest.mark.parametrize(("start", "rows"), [(0, ()), (2000, (2000, 4000))])
def test_swapped_pairs_of_a_smooth_log_are_found(smooth, start, rows):
    y = _swapped(smooth, start)
    assert _step_rms(y) > 1.4 * _step_rms(smooth)  # the swap matters (numpy)
    report = _report(y)
    assert report.pair_order and report.pair_order[2] <= 1e-4
    assert not report.clean
    assert report.pair_rows == rows
