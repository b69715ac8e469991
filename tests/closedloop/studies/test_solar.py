"""closedloop.studies.solar: the correlation's latency and the solar sensitivity study.

References, from outside the code under test:
- the latency law written here: ``delay = readout + compute / rtc_speed`` rounded to
  ``time_step / 8`` (Figure 6's latency model, restated by hand), and the loop's stability
  limit from :func:`modalinfo.servo.max_stable_gain` (an independent root-locus);
- the cost law of the square-difference search: one frame's work is proportional to
  ``n_subapertures x window^2 x (2 max_shift + 3)^2`` (counted here on the arrays the
  measurement receives, with a deterministic clock: no wall-time assertion);
- the image size of a correlating WFS: its field of view over its pixel scale (the
  contract: 60" and 20" at 0.5" for table1's fields);
- physics: with fewer photons or a lower granulation contrast the correlation noise
  grows (Michau et al. 1992: variance ~ 1 / (photons x contrast^2)), so the budget's
  noise term must grow, never shrink.
"""

import math

import numpy as np
import pytest

from closedloop import presets
from closedloop.studies import solar


# ------------------------------------------------------------------ RTC presets
def test_rtc_presets_are_documented_and_valid():
    for name, rtc in solar.RTC_PRESETS.items():
        assert rtc.name == name and rtc.readout >= 0 and rtc.rtc_speed > 0 and rtc.source


@pytest.mark.parametrize("kw", [{"readout": -1e-3}, {"rtc_speed": 0.0}, {"rtc_speed": True},
                                {"readout": float("nan")}])
def test_rtc_refuses_bad_values(kw):
    args = {"name": "x", "readout": 0.5e-3, "rtc_speed": 2.0} | kw
    with pytest.raises(ValueError, match=next(iter(kw))):
        solar.SolarRTC(**args)


# ------------------------------------------------------------------ compute time
class _CountingClock:
    """A clock that advances by the square-difference work of each measurement call."""

    def __init__(self):
        self.now = 0.0

    def __call__(self):
        return self.now


def _patch_work(monkeypatch, clock):
    import closedloop.optics.shifts as shifts

    real = shifts.measure_shifts
    calls = []

    def counted(reference, images, **kw):
        images = np.asarray(images)
        n, h, w = images.shape if images.ndim == 3 else (1, *images.shape)
        lag = kw.get("max_shift", 3) + 1
        window = min(h, w) - 2 * lag
        calls.append((n, h, w))
        clock.now += n * window ** 2 * (2 * lag + 1) ** 2 * 1e-9  # 1 ns per difference
        return real(reference, images, **kw)

    monkeypatch.setattr(shifts, "measure_shifts", counted)
    return calls


def test_compute_time_covers_the_whole_batch(monkeypatch):
    clock = _CountingClock()
    calls = _patch_work(monkeypatch, clock)
    times = {n: solar.correlation_compute_time(n, 24, repeats=3, clock=clock)
             for n in (3, 6, 12)}
    # every call measured all n images of 24x24 pixels
    assert {c[1:] for c in calls} == {(24, 24)}
    assert sorted({c[0] for c in calls}) == [3, 6, 12]
    for n, t in times.items():
        assert t == pytest.approx(n * (24 - 8) ** 2 * 9 ** 2 * 1e-9, rel=1e-12)
    # so the measured compute scales with the subaperture count
    assert times[12] / times[3] == pytest.approx(4.0, rel=1e-12)


def test_compute_time_is_a_real_measurement():
    t = solar.correlation_compute_time(4, 16, repeats=2)
    assert math.isfinite(t) and t > 0


@pytest.mark.parametrize("kw, name", [({"n_subapertures": 0}, "n_subapertures"),
                                      ({"image_pixels": 10}, "image_pixels"),
                                      ({"repeats": 0}, "repeats"),
                                      ({"max_shift": 0}, "max_shift")])
def test_compute_time_refusals(kw, name):
    args = {"n_subapertures": 2, "image_pixels": 16} | kw
    with pytest.raises(ValueError, match=name):
        solar.correlation_compute_time(**args)


# ------------------------------------------------------------------ latency
def test_latency_refuses_a_config_without_correlating_wfs():
    with pytest.raises(ValueError, match="correlating"):
        solar.solar_latency(presets.get("table1"), timer=lambda n, p: 0.0)
