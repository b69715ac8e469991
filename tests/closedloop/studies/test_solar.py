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
from modalinfo.servo import max_stable_gain


# ------------------------------------------------------------------ RTC presets
def test_rtc_presets_are_documented_and_valid():
    for name, rtc in solar.RTC_PRESETS.items():
        assert rtc.name == name and rtc.readout >= 0 and rtc.rtc_speed > 0 and rtc.source


@pytest.mark.parametrize("kw", [{"readout": -1e-3}, {"rtc_speed": 0.0}, {"rtc_speed": True},
                                {"readout": float("nan")}])
def test_rtc_refuses_bad_values(kw):
    args = {"name": "x", "readout": 0.5e-3, "rtc_speed": 2.0} | kw
    # a bool is not a number: check_real's TypeError (left26-twins)
    kind = TypeError if isinstance(next(iter(kw.values())), bool) else ValueError
    with pytest.raises(kind, match=f"`SolarRTC.{next(iter(kw))}`"):
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


class _Sensor:
    def __init__(self, n):
        self.n_valid_subapertures = n


class _Model:
    """Stands for a LoopModel: only the valid subaperture counts are read."""

    def __init__(self, *counts):
        self.wfss = [_Sensor(n) for n in counts]


def _solar(**wfs):
    import dataclasses

    cfg = presets.get("table1-solar")
    if wfs:
        cfg = cfg.replace(wfss=tuple(dataclasses.replace(w, **wfs) for w in cfg.wfss))
    return cfg


def test_image_sizes_are_field_over_pixel_scale():
    assert solar.correlating_wfs_sizes(_solar(), _Model(204, 120)) == [(0, 204, 120),
                                                                       (1, 120, 40)]
    assert solar.correlating_wfs_sizes(_solar(pixel_scale=1.0), _Model(204, 120)) == [
        (0, 204, 60), (1, 120, 20)]


def test_compute_time_adds_every_wfs_and_its_tracker():
    calls = []

    def timer(n, pixels):
        calls.append((n, pixels))
        return 1e-6 * n * pixels ** 2

    t = solar.correlating_compute_time(_solar(), _Model(204, 120), timer=timer)
    assert calls == [(205, 120), (121, 40)]  # the subapertures and one tracker image
    assert t == pytest.approx(1e-6 * (205 * 120 ** 2 + 121 * 40 ** 2), rel=1e-12)


@pytest.mark.parametrize("compute", [0.0, 0.3e-3, 7.7e-3, 20e-3])
def test_delay_is_readout_plus_compute_over_speed_on_the_grid(compute):
    cfg = _solar()
    rtc = solar.SolarRTC("x", 0.5e-3, 32.0)
    c, delay = solar.solar_latency(cfg, rtc=rtc, compute_time=compute)
    step = cfg.loop.time_step / 8
    raw = 0.5e-3 + compute / 32.0
    assert c == compute
    assert delay / step == pytest.approx(round(delay / step), abs=1e-9)  # on the grid
    assert abs(delay - raw) <= step / 2 + 1e-15                        # the nearest point
    # the delay is a valid loop delay of the config (its validation accepts it)
    import dataclasses

    assert cfg.replace(loop=dataclasses.replace(cfg.loop, delay=delay)).loop.delay == delay


def test_unstable_delay_is_refused_naming_the_rtc():
    cfg = _solar()
    with pytest.raises(ValueError, match="`rtc` 'this-machine'"):
        solar.solar_latency(cfg, rtc="this-machine", compute_time=0.1)
    # the same delay by an independent stability analysis: beyond the loop's limit
    delay = 0.5e-3 + 0.1
    frames = round(delay / (cfg.loop.time_step / 8)) / 8
    assert max_stable_gain(frames, cfg.loop.integration_frames) < cfg.loop.gain
    with pytest.raises(ValueError, match="rtc"):
        solar.solar_latency(cfg, rtc="nope", compute_time=0.0)
    with pytest.raises(ValueError, match="compute_time"):
        solar.solar_latency(cfg, compute_time=-1.0)


# ------------------------------------------------------------------ sensitivity guards
@pytest.fixture
def no_model(monkeypatch):
    import closedloop.simulation as sim

    def boom(*a, **k):
        raise AssertionError("a model was built before the refusal")

    monkeypatch.setattr(sim, "LoopModel", boom)


def test_too_many_runs_are_refused_before_any_work(no_model):
    with pytest.raises(ValueError, match="max_runs"):
        # (2 + 2 + 2 + 2 variations + base) x 2 predictors = 18 runs
        solar.solar_sensitivity(_solar(), predictors=("none", "arma"), max_runs=17)


@pytest.mark.parametrize("kw, exc, name", [
    ({"values": {"wind": (1.0,)}}, ValueError, "values"),
    ({"values": {"signal": 150.0}}, TypeError, "values"),
    ({"values": {"rtc": ("nope",)}}, ValueError, "rtc"),
    ({"predictors": "arma"}, TypeError, "predictors"),
    ({"predictors": ("none", "nope")}, ValueError, "predictors"),
    ({"max_runs": 0}, ValueError, "max_runs"),
])
def test_sensitivity_refusals(no_model, kw, exc, name):
    with pytest.raises(exc, match=name):
        solar.solar_sensitivity(_solar(), **kw)


# ------------------------------------------------------------------ physics
def _small_solar():
    """table1-solar shrunk for speed: 32 pupil pixels, 8 subapertures, few modes, on axis."""
    import dataclasses

    from closedloop.config import FieldConfig

    cfg = _solar(n_subapertures=8, field_samples=2)
    return cfg.replace(telescope=dataclasses.replace(cfg.telescope, n_pixels=32),
                       dms=tuple(dataclasses.replace(d, n_modes=m)
                                 for d, m in zip(cfg.dms, (20, 9), strict=True)),
                       field=FieldConfig(size=cfg.field.size, n_points=1))


def test_less_signal_or_contrast_means_more_noise_in_the_budget():
    study = solar.solar_sensitivity(_small_solar(), values={"signal": (1500.0, 150.0),
                                                            "contrast": (0.06, 0.03)},
                                    predictors=("none",), duration=0.04, budget_every=5)
    noise = {(r["knob"], r["value"]): r["noise"] for r in study.rows}
    base = noise[("base", "")]
    assert base > 0
    # monotone: each step down in photons or contrast raises the noise term
    assert base < noise[("signal", "1500 e-")] < noise[("signal", "150 e-")]
    assert base < noise[("contrast", "0.06")] < noise[("contrast", "0.03")]


def test_command_line_refuses_an_unknown_knob_in_one_line(capsys, no_model):
    assert solar.main(["--knobs", "signal,wind"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--knobs" in err and "wind" in err
