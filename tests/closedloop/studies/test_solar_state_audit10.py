"""A SolarSensitivity with a NaN latency equals its pickle (audit 10-state).

Reference: round trips. An RTC whose loop is unstable is reported as ``(compute, nan)``
in ``latency`` (closedloop.studies.solar); NaN compared by identity made the pickled
study unequal to the original before the fix.
"""

import math
import pickle

from closedloop.studies import solar


def _study(delay: float) -> solar.SolarSensitivity:
    rows = (dict(knob="base", value="", predictor="none", delay=1e-3, strehl_peak=0.5,
                 fov_arcmin=math.nan),)
    return solar.SolarSensitivity("table1-solar", 3, 0.1, ("none",), rows,
                                  {"this-machine": (4e-3, math.nan), "fpga": (1e-4, delay)},
                                  12.4)


def test_round_trip_with_nan_latency():
    s = _study(5e-4)
    assert s == pickle.loads(pickle.dumps(s))
    assert s != _study(6e-4)
