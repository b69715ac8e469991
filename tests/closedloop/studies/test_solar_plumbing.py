"""closedloop.studies.solar: the study's bookkeeping, on runs whose numbers are set here.

Gaps found by mutation testing (docs/MUTATION.md, "closedloop/studies/solar.py"). No closed
loop is run: ``run_trained`` and ``LoopModel`` are replaced by recorders that return runs
whose residual variances and budget are written in the test. References, from outside
the code under test:

- the documented contract (the module's and functions' docstrings): which runs are made,
  with which config, seed, duration, model, training reference and budget; what a row,
  a log line, the Markdown table and the command line's first line hold;
- the row numbers computed here by hand from the variances set in the test: SR =
  exp(-variance) (Marechal), the peak over directions averaged over the frames after
  closure, and the budget term of the direction nearest the axis;
- the latency law ``delay = readout + compute / rtc_speed`` rounded to ``time_step / n``
  with ``n = max(8, loop.oversampling)`` (written out by hand for each case), and the
  loop's stability limit from :func:`modalinfo.servo.max_stable_gain`;
- the RTC presets' numbers as the module docstring states them (readout 0.5 ms; speeds
  32, 256 and 1).
"""

import dataclasses
import math
from types import SimpleNamespace

import numpy as np
import pytest

from closedloop import presets
from closedloop.studies import solar
from modalinfo.servo import max_stable_gain


def _solar(**wfs):
    cfg = presets.get("table1-solar")
    if wfs:
        cfg = cfg.replace(wfss=tuple(dataclasses.replace(w, **wfs) for w in cfg.wfss))
    return cfg


class _Sensor:
    def __init__(self, n):
        self.n_valid_subapertures = n


class _Model:
    """Stands for a LoopModel: only the valid subaperture counts are read."""

    def __init__(self, *counts):
        self.wfss = [_Sensor(n) for n in counts]


# ------------------------------------------------------------------ RTC presets
def test_rtc_presets_hold_the_documented_numbers():
    # module docstring: readout 0.5 ms for all three; speeds 32, 256 and 1
    got = {k: (r.name, r.readout, r.rtc_speed) for k, r in solar.RTC_PRESETS.items()}
    assert got == {"workstation": ("workstation", 0.5e-3, 32.0),
                   "fpga": ("fpga", 0.5e-3, 256.0),
                   "this-machine": ("this-machine", 0.5e-3, 1.0)}
    assert "Scharmer" in solar.RTC_PRESETS["workstation"].source
    assert "Rimmele" in solar.RTC_PRESETS["fpga"].source


def test_rtc_latency_model_carries_readout_speed_and_oversampling():
    rtc = solar.SolarRTC("x", 2e-3, 4.0)
    for over, model in ((8, rtc.latency_model()), (16, rtc.latency_model(16))):
        assert (model.readout, model.rtc_speed, model.oversampling) == (2e-3, 4.0, over)
        # delay = readout + compute / speed on the grid time_step / oversampling
        assert model.delay(1e-3, 1e-3) == pytest.approx(2.25e-3, abs=1e-15)  # 2 + 1 / 4 ms


def test_rtc_accepts_zero_readout_and_names_the_rule():
    assert solar.SolarRTC("x", 0, 1).readout == 0
    with pytest.raises(ValueError) as exc:
        solar.SolarRTC("x", -1e-3, 1.0)
    # validation.check_real's words (left26-twins): the field named with its class
    assert str(exc.value) == "`SolarRTC.readout` must be >= 0.0; got -0.001."
    with pytest.raises(ValueError) as exc:
        solar.SolarRTC("x", 0.0, 0.0)
    assert str(exc.value) == "`SolarRTC.rtc_speed` must be > 0.0; got 0.0."
    for bad, kind in (("1", TypeError), (float("inf"), ValueError), (None, TypeError)):
        with pytest.raises(kind, match="`SolarRTC.rtc_speed`"):
            solar.SolarRTC("x", 0.0, bad)
    assert solar.SolarRTC("x", 0.0, 3).rtc_speed == 3  # an int is a number


def test_unknown_rtc_message_lists_the_presets():
    with pytest.raises(ValueError) as exc:
        solar.solar_latency(_solar(), rtc="nope", compute_time=0.0)
    assert str(exc.value) == ("`rtc` must be a SolarRTC or one of ['fpga', 'this-machine', "
                              "'workstation']; got 'nope'.")


# ------------------------------------------------------------------ compute time
def test_positive_int_rule_and_message():
    with pytest.raises(ValueError) as exc:
        solar.correlation_compute_time(2, 16, repeats=0)
    assert str(exc.value) == "`repeats` must be an int >= 1; got 0."
    with pytest.raises(ValueError) as exc:
        solar.correlation_compute_time(2, 10)  # 2 max_shift + 5 = 11 at the default 3
    assert str(exc.value) == "`image_pixels` must be an int >= 11; got 10."
    with pytest.raises(ValueError, match="n_subapertures"):
        solar.correlation_compute_time(True, 16)
    with pytest.raises(ValueError, match="image_pixels"):
        solar.correlation_compute_time(2, 16.0)


def test_compute_time_runs_at_the_size_boundary_with_numpy_ints():
    clock = iter(np.arange(0.0, 100.0, 1.0))
    # a clock advancing 1 s per reading: each timed batch costs exactly 1 s
    t = solar.correlation_compute_time(np.int64(2), 11, repeats=np.int64(2),
                                       clock=lambda: float(next(clock)))
    assert t == 1.0


def test_compute_time_passes_repeats_and_seed_to_the_measurement(monkeypatch):
    calls = []

    def fake(n, pixels, **kw):
        calls.append((n, pixels, kw))
        return 1e-3 * n

    monkeypatch.setattr(solar, "correlation_compute_time", fake)
    t = solar.correlating_compute_time(_solar(), _Model(204, 120), repeats=2, seed=7)
    assert calls == [(205, 120, {"repeats": 2, "seed": 7}), (121, 40, {"repeats": 2, "seed": 7})]
    assert t == pytest.approx(1e-3 * (205 + 121), rel=1e-12)
    calls.clear()
    solar.correlating_compute_time(_solar(), _Model(204, 120))
    assert [c[2] for c in calls] == [{"repeats": 5, "seed": 0}] * 2  # documented defaults


def test_image_size_is_rounded_and_floored_at_the_search_window():
    # 20" / 0.3" = 66.7 -> 67 pixels (rounded, not truncated); 60" / 0.3" = 200
    assert solar.correlating_wfs_sizes(_solar(pixel_scale=0.3), _Model(3, 4)) == [
        (0, 3, 200), (1, 4, 67)]
    # 20" / 2.5" = 8 pixels, below 2 max_shift + 5 = 11: the image is 11 pixels
    assert solar.correlating_wfs_sizes(_solar(pixel_scale=2.5), _Model(3, 4)) == [
        (0, 3, 24), (1, 4, 11)]


def test_sizes_of_a_mixed_config_skip_the_geometric_wfs():
    cfg = _solar()
    geometric = dataclasses.replace(cfg.wfss[1], kind="shack_hartmann")
    cfg = cfg.replace(wfss=(cfg.wfss[0], geometric))
    assert solar.correlating_wfs_sizes(cfg, _Model(204, 120)) == [(0, 204, 120)]


def test_no_correlating_wfs_message_names_the_config_and_kinds():
    with pytest.raises(ValueError) as exc:
        solar.correlating_wfs_sizes(presets.get("table1"), _Model(1, 1))
    assert str(exc.value) == ("`config` ('table1') has no WFS of kind 'correlating' (kinds: "
                              "['shack_hartmann', 'shack_hartmann']); there is no "
                              "correlation to time.")


# ------------------------------------------------------------------ latency
@pytest.mark.parametrize("compute, expected", [
    (0.0, 0.5e-3),          # 0.5 ms = 4 steps of 0.125 ms
    (4e-3, 0.625e-3),       # 0.5 + 4 / 32 = 0.625 ms = 5 steps
    (2.4e-3, 0.625e-3),     # 0.575 ms = 4.6 steps -> 5 steps
    (0.8e-3, 0.5e-3),       # 0.525 ms = 4.2 steps -> 4 steps
])
def test_delay_by_hand_on_the_eighth_frame_grid(compute, expected):
    c, delay = solar.solar_latency(_solar(), rtc="workstation", compute_time=compute)
    assert c == compute and isinstance(c, float)
    assert delay == pytest.approx(expected, abs=1e-15)


def test_delay_grid_follows_a_finer_loop_oversampling():
    cfg = _solar()
    # delay 1.0625 frames: the loop steps in 1/16 frame, so the latency grid is 1/16 ms
    cfg = cfg.replace(loop=dataclasses.replace(cfg.loop, delay=1.0625e-3))
    assert cfg.loop.oversampling == 16
    # 0.5 + 2 / 32 = 0.5625 ms = 9 steps of 1/16 ms (on the 1/8 grid it would be 0.5 ms)
    _, delay = solar.solar_latency(cfg, rtc="workstation", compute_time=2e-3)
    assert delay == pytest.approx(0.5625e-3, abs=1e-15)


def test_latency_measures_with_the_given_model_and_timer():
    seen = []

    def timer(n, pixels):
        seen.append((n, pixels))
        return 1e-6 * n * pixels

    c, delay = solar.solar_latency(_solar(), rtc="fpga", model=_Model(204, 120), timer=timer)
    assert seen == [(205, 120), (121, 40)]
    assert c == pytest.approx(1e-6 * (205 * 120 + 121 * 40), rel=1e-12)
    assert delay == pytest.approx(0.625e-3, abs=1e-15)  # 0.5 + 29.44 ms / 256 -> 4.9 steps


def test_compute_time_argument_rule_and_message():
    # validation.check_real's words and types (left26-twins)
    for bad, kind, message in (
            (True, TypeError, "must be a real number; got True."),
            (float("nan"), ValueError, "must be finite; got nan."),
            (float("inf"), ValueError, "must be finite; got inf."),
            (-1e-9, ValueError, "must be >= 0.0; got -1e-09."),
            ("1", TypeError, "must be a real number; got '1'.")):
        with pytest.raises(kind) as exc:
            solar.solar_latency(_solar(), compute_time=bad)
        assert str(exc.value) == f"`compute_time` {message}"
    assert solar.solar_latency(_solar(), compute_time=0)[0] == 0.0


def test_unstable_message_names_rtc_delay_compute_and_limit():
    cfg = _solar()
    with pytest.raises(ValueError) as exc:
        solar.solar_latency(cfg, rtc="this-machine", compute_time=4e-3)
    limit = max_stable_gain(4.5, 1.0)  # 0.5 + 4 ms = 4.5 frames, one-frame exposure
    assert limit < cfg.loop.gain
    assert str(exc.value) == (
        "`rtc` 'this-machine' (readout 0.5 ms, rtc_speed 1) gives a delay of 4.500 ms "
        "(4.00 ms of correlation on this machine): the loop gain 0.5 is beyond the largest "
        f"stable gain {limit:.3f} there; use a faster RTC or a lower gain.")


def test_a_gain_just_below_the_limit_is_accepted():
    cfg = _solar()
    limit = max_stable_gain(4.5, 1.0)
    low = cfg.replace(loop=dataclasses.replace(cfg.loop, gain=0.99 * limit))
    assert solar.solar_latency(low, rtc="this-machine", compute_time=4e-3)[1] == \
        pytest.approx(4.5e-3, abs=1e-15)


# ------------------------------------------------------------------ variations
def test_variations_change_one_knob_on_every_wfs(monkeypatch):
    monkeypatch.setattr(solar, "correlating_compute_time",
                        lambda *a, **k: pytest.fail("no rtc knob: nothing to time"))
    base = _solar()
    out, lat = solar.solar_variations(base, {"signal": (150.0,), "contrast": (0.03,),
                                             "n_subapertures": (8,)})
    assert lat == {}
    assert [(k, label) for k, label, _ in out] == [("signal", "150 e-"), ("contrast", "0.03"),
                                                   ("n_subapertures", "8")]
    for (knob, _, change), v in zip(out, (150.0, 0.03, 8), strict=True):
        cfg = change(base)
        assert cfg.wfss == tuple(dataclasses.replace(w, **{knob: v}) for w in base.wfss)
        assert cfg.loop == base.loop and cfg.dms == base.dms


def test_variations_time_once_for_every_rtc_and_drop_an_unstable_one(monkeypatch):
    calls = []

    def timed(config, model=None, **kw):
        calls.append((config, model))
        return 4e-3

    monkeypatch.setattr(solar, "correlating_compute_time", timed)
    base, model = _solar(), object()
    out, lat = solar.solar_variations(base, {"rtc": ("workstation", "this-machine", "fpga")},
                                      model=model)
    assert calls == [(base, model)]  # one measurement serves every RTC
    assert lat["workstation"] == (4e-3, pytest.approx(0.625e-3, abs=1e-15))
    assert lat["fpga"] == (4e-3, pytest.approx(0.5e-3, abs=1e-15))  # 0.516 ms -> 4 steps
    c, d = lat["this-machine"]
    assert c == 4e-3 and math.isnan(d)  # 4.5 ms is beyond the stable gain (test above)
    assert [(k, label) for k, label, _ in out] == [("rtc", "workstation: 0.625 ms"),
                                                   ("rtc", "fpga: 0.500 ms")]
    cfg = out[0][2](base)
    assert cfg.loop == dataclasses.replace(base.loop, delay=0.625e-3)
    assert cfg.wfss == base.wfss


def test_variations_reuse_a_stored_latency_and_its_measurement(monkeypatch):
    monkeypatch.setattr(solar, "correlating_compute_time",
                        lambda *a, **k: pytest.fail("a stored measurement serves"))
    stored = {"workstation": (8e-3, 0.75e-3)}
    out, lat = solar.solar_variations(_solar(), {"rtc": ("workstation", "fpga")},
                                      latency=stored)
    assert stored == {"workstation": (8e-3, 0.75e-3)}  # the caller's dict is not changed
    assert lat["workstation"] == (8e-3, 0.75e-3)       # used as given
    # fpga from the stored 8 ms: 0.5 + 8 / 256 = 0.531 ms -> 4 steps = 0.5 ms
    assert lat["fpga"] == (8e-3, pytest.approx(0.5e-3, abs=1e-15))
    assert [label for _, label, _ in out] == ["workstation: 0.750 ms", "fpga: 0.500 ms"]


def test_an_unstable_stored_latency_does_not_serve_as_measurement(monkeypatch):
    monkeypatch.setattr(solar, "correlating_compute_time", lambda *a, **k: 3e-3)
    out, lat = solar.solar_variations(_solar(), {"rtc": ("workstation",)},
                                      latency={"x": (float("nan"), float("nan"))})
    # measured here: 0.5 + 3 / 32 = 0.594 ms = 4.75 steps -> 5 steps
    assert lat["workstation"] == (3e-3, pytest.approx(0.625e-3, abs=1e-15))


def test_values_messages():
    with pytest.raises(TypeError) as exc:
        solar.solar_variations(_solar(), [("signal", (1.0,))])
    assert str(exc.value) == "`values` must be a dict knob -> values; got [('signal', (1.0,))]."
    with pytest.raises(ValueError) as exc:
        solar.solar_variations(_solar(), {"wind": (1,), "seeing": (2,)})
    assert str(exc.value) == ("`values` keys must be among ['contrast', 'n_subapertures', "
                              "'rtc', 'signal']; got ['seeing', 'wind'].")
    for bad in ("abc", 3.0):
        with pytest.raises(TypeError) as exc:
            solar.solar_variations(_solar(), {"signal": bad})
        assert str(exc.value) == f"`values['signal']` must be a tuple of values; got {bad!r}."


# ------------------------------------------------------------------ the study
class _Run:
    """A finished run: 3 frames x 2 directions (closure at frame 1), a 3-direction budget."""

    def __init__(self, config, seed, duration, k):
        step = config.loop.time_step
        self.config, self.seed = config, seed
        self.times = np.arange(1, round(duration / step) + 1) * step
        self.closure_index = self.averaging_start = 1  # closed: averages from the closure
        self.residual_variance = np.array([[9.0, 9.0], [0.1 * k, 0.2 * k], [0.3 * k, 0.1 * k]])
        self.fov = 0.5 * k
        # the direction nearest the axis is the second one (0.1" off axis)
        self.budget = SimpleNamespace(directions=np.array([[30.0, 0.0], [0.0, 0.1], [5.0, 5.0]]),
                                      **{t: np.array([9.0, 0.01 * k + i, 9.0]) for i, t in
                                         enumerate(("fitting", "aliasing", "temporal", "noise",
                                                    "measured"))})

    def corrected_fov_diameter(self, threshold):
        assert threshold == 0.3
        return self.fov


@pytest.fixture
def recorder(monkeypatch):
    import closedloop.simulation as sim
    import closedloop.training as training

    calls, models = [], []

    class FakeModel:
        def __init__(self, config):
            self.config = config
            models.append(config)

    def run_trained(cfg, name, duration, *, seed, model, reference, progress, budget_every):
        calls.append(dict(cfg=cfg, name=name, duration=duration, seed=seed, model=model,
                          reference=reference, progress=progress, budget_every=budget_every))
        run = _Run(cfg, seed, duration, len(calls))
        if budget_every is None:  # as simulate: no budget asked, none made
            run.budget = None
        calls[-1]["run"] = run
        return run

    monkeypatch.setattr(sim, "LoopModel", FakeModel)
    monkeypatch.setattr(training, "run_trained", run_trained)
    return SimpleNamespace(calls=calls, models=models)


def test_study_runs_each_variation_for_each_predictor(recorder):
    base, model, lines = _solar(), object(), []
    values = {"signal": (150.0,), "n_subapertures": (8,), "rtc": ("workstation",)}
    study = solar.solar_sensitivity(base, values=values, predictors=("arma", "none", "arma"),
                                    duration=0.003, seed=4, budget_every=7,
                                    max_runs=8,  # (3 variations + base) x 2: the boundary
                                    latency={"workstation": (4e-3, 0.625e-3)}, model=model,
                                    progress=True, log=lines.append)
    calls = recorder.calls
    assert [(c["name"]) for c in calls] == ["none", "arma"] * 4
    expected_cfgs = [base, base.replace(wfss=tuple(dataclasses.replace(w, signal=150.0)
                                                   for w in base.wfss)),
                     base.replace(wfss=tuple(dataclasses.replace(w, n_subapertures=8)
                                             for w in base.wfss)),
                     base.replace(loop=dataclasses.replace(base.loop, delay=0.625e-3))]
    assert [c["cfg"] for c in calls[::2]] == expected_cfgs
    assert [c["cfg"] for c in calls[1::2]] == expected_cfgs
    # one model per variation, shared by its two runs; the given one for the base
    assert recorder.models == expected_cfgs[1:]
    assert calls[0]["model"] is model and calls[1]["model"] is model
    for j in range(1, 4):
        assert calls[2 * j]["model"] is calls[2 * j + 1]["model"]
        assert calls[2 * j]["model"].config == expected_cfgs[j]
    for c in calls:
        assert (c["duration"], c["seed"], c["progress"]) == (0.003, 4, True)
        # the budget is the no-prediction run's; the predictor trains on that run
        assert c["budget_every"] == (7 if c["name"] == "none" else None)
    for j in range(4):
        assert calls[2 * j]["reference"] is None
        assert calls[2 * j + 1]["reference"] is calls[2 * j]["run"]

    assert (study.config_name, study.seed, study.duration, study.predictors) == (
        "table1-solar", 4, 0.003, ("none", "arma"))
    assert isinstance(study.seed, int) and isinstance(study.duration, float)
    assert study.latency == {"workstation": (4e-3, 0.625e-3)}
    assert study.elapsed >= 0
    keys = [(r["knob"], r["value"], r["predictor"]) for r in study.rows]
    assert keys == [(k, v, p) for k, v in (("base", ""), ("signal", "150 e-"),
                                           ("n_subapertures", "8"),
                                           ("rtc", "workstation: 0.625 ms"))
                    for p in ("none", "arma")]
    for i, r in enumerate(study.rows):
        k = i + 1  # the k-th run's variances (frames after closure: rows 1 and 2)
        peak = 0.5 * (math.exp(-0.1 * k) + math.exp(-0.1 * k))
        field = 0.25 * (math.exp(-0.1 * k) + math.exp(-0.2 * k) + math.exp(-0.3 * k)
                        + math.exp(-0.1 * k))
        assert r["strehl_peak"] == pytest.approx(peak, rel=1e-12)
        assert r["strehl_field"] == pytest.approx(field, rel=1e-12)
        assert r["fov_arcmin"] == 0.5 * k
        assert r["parameter"] == r["knob"]  # the sensitivity study's own key, the same
        assert r["delay"] == (0.625e-3 if r["knob"] == "rtc" else base.loop.delay)
        terms = ("fitting", "aliasing", "temporal", "noise", "measured")
        if r["predictor"] == "none":
            assert [r[t] for t in terms] == pytest.approx([0.01 * k + i for i in range(5)])
        else:
            assert not set(terms) & set(r)
    assert lines[0] == "[solar] base (base) none: SR peak 0.905, FoV 0.50', noise 3.0100"
    assert lines[1] == "[solar] base (base) arma: SR peak 0.819, FoV 1.00'"
    assert lines[2] == "[solar] signal 150 e- none: SR peak 0.741, FoV 1.50', noise 3.0300"
    assert len(lines) == 8


def test_row_lookup_and_its_key_error(recorder):
    study = solar.solar_sensitivity(_solar(), values={"contrast": (0.03,)}, predictors=("none",),
                                    duration=0.002, model=object())
    assert study.row("contrast", "0.03") is study.rows[1]
    assert study.row("base", "", "none") is study.rows[0]
    with pytest.raises(KeyError) as exc:
        study.row("contrast", "0.03", "arma")
    assert exc.value.args[0] == "no run 'contrast' = '0.03' with 'arma'"
    # defaults: duration 0.3 s is not used here; budget every 5 frames, no progress bars
    assert [c["budget_every"] for c in recorder.calls] == [5, 5]
    assert [c["progress"] for c in recorder.calls] == [False, False]
    assert [c["seed"] for c in recorder.calls] == [0, 0]


def test_study_defaults_to_table1_solar_and_builds_its_model(recorder):
    solar.solar_sensitivity(values={"signal": (150.0,)}, predictors=("none",), duration=0.002)
    base = presets.get("table1-solar")
    assert recorder.calls[0]["cfg"] == base
    assert recorder.models[0] == base  # the base model, built since none was given
    assert recorder.calls[0]["model"].config == base


def test_given_base_runs_are_reused_and_checked(recorder):
    base = _solar()
    given = _Run(base, 3, 0.004, 7)
    study = solar.solar_sensitivity(base, values={"signal": (150.0,)}, predictors=("none",
                                                                                     "arma"),
                                    duration=0.004, seed=3, model=object(),
                                    base_results={"none": given})
    assert [c["name"] for c in recorder.calls] == ["arma", "none", "arma"]
    assert recorder.calls[0]["reference"] is given and recorder.calls[0]["cfg"] == base
    assert study.rows[0]["fov_arcmin"] == 3.5  # the given run's numbers (k = 7)
    # a duration off by less than half a frame is the same run; by more, another
    near = _Run(base, 3, 0.004, 1)
    near.times = near.times + 0.4e-3
    solar.solar_sensitivity(base, values={"signal": (150.0,)}, predictors=("none",),
                            duration=0.004, seed=3, model=object(), base_results={"none": near})
    for bad in (_Run(base, 4, 0.004, 1), _Run(base, 3, 0.005, 1),
                _Run(_solar(signal=150.0), 3, 0.004, 1)):
        with pytest.raises(ValueError) as exc:
            solar.solar_sensitivity(base, values={"signal": (150.0,)}, predictors=("none",),
                                    duration=0.004, seed=3, model=object(),
                                    base_results={"none": bad})
        assert str(exc.value) == ("`base_results['none']` is not a run of the base config "
                                  "with seed 3 and duration 0.004 s.")
    far = _Run(base, 3, 0.004, 1)
    far.times = far.times + 0.6e-3
    with pytest.raises(ValueError, match="base_results"):
        solar.solar_sensitivity(base, values={"signal": (150.0,)}, predictors=("none",),
                                duration=0.004, seed=3, model=object(),
                                base_results={"none": far})


def test_study_refusal_messages(monkeypatch):
    with pytest.raises(ValueError) as exc:
        solar.solar_sensitivity(_solar(), predictors=("none",), max_runs=8)
    # 2 + 2 + 2 + 2 variations + base = 9 runs of one predictor
    assert str(exc.value) == ("`max_runs` = 8 is below the 9 runs asked ((8 variations + base) "
                              "x 1 predictors); give fewer values or predictors, or raise "
                              "max_runs.")
    with pytest.raises(TypeError) as exc:
        solar.solar_sensitivity(_solar(), predictors="arma")
    assert str(exc.value) == "`predictors` must be a tuple of names; got the string 'arma'."
    with pytest.raises(ValueError) as exc:
        solar.solar_sensitivity(_solar(), predictors=("none", "x", "y"))
    assert str(exc.value).endswith("; got ['x', 'y'].")
    assert str(exc.value).startswith("`predictors` must be names of ['arma', ")


# ------------------------------------------------------------------ Markdown and CLI
def _study():
    rows = []
    for knob, value, delay in (("base", "", 1e-3), ("signal", "150 e-", 1e-3),
                               ("rtc", "fpga: 0.500 ms", 0.5e-3)):
        for p, sr, fov in (("none", 0.5, 1.0), ("arma", 0.625, 1.5)):
            row = dict(knob=knob, value=value, predictor=p, delay=delay, strehl_peak=sr,
                       fov_arcmin=fov)
            if p == "none":
                row.update(fitting=0.1, aliasing=0.02, temporal=0.3, noise=0.04, measured=0.5)
            rows.append(row)
    return solar.SolarSensitivity("table1-solar", 3, 0.1, ("none", "arma"), tuple(rows),
                                  {"workstation": (0.1, 0.625e-3),
                                   "this-machine": (4e-3, float("nan"))}, 12.4)


_TABLE = """\
| knob | value | delay [ms] | SR peak none | SR peak arma | FoV d none ['] | FoV d arma ['] \
| fitting | aliasing | temporal | noise | measured (on axis, rad^2) |
|---|---|---|---|---|---|---|---|---|---|---|---|
| (base) |  | 1.000 | 0.500 | 0.625 | 1.00 | 1.50 | 0.1000 | 0.0200 | 0.3000 | 0.0400 | 0.5000 |
| photon flux (signal, e-/px/frame) | 150 e- | 1.000 | 0.500 | 0.625 | 1.00 | 1.50 | 0.1000 \
| 0.0200 | 0.3000 | 0.0400 | 0.5000 |
| compute latency (loop.delay) | fpga: 0.500 ms | 0.500 | 0.500 | 0.625 | 1.00 | 1.50 \
| 0.1000 | 0.0200 | 0.3000 | 0.0400 | 0.5000 |"""


def test_markdown_table_written_by_hand():
    assert solar.markdown(_study()) == _TABLE


def test_markdown_leaves_missing_terms_empty():
    study = _study()
    rows = [dict(r) for r in study.rows]
    del rows[0]["aliasing"]
    text = solar.markdown(dataclasses.replace(study, rows=tuple(rows)))
    assert "| 0.1000 |  | 0.3000 |" in text.splitlines()[2]


def test_command_line_passes_its_options_and_prints_the_study(monkeypatch, capsys):
    seen = {}

    def fake(**kw):
        seen.update(kw)
        kw["log"]("[solar] a line")
        return _study()

    monkeypatch.setattr(solar, "solar_sensitivity", fake)
    assert solar.main(["--quick", "--knobs", " rtc, signal,", "--duration", "0.1",
                       "--seed", "3"]) == 0
    assert seen["values"] == {"rtc": ("workstation",), "signal": (150.0,)}
    assert (seen["duration"], seen["seed"]) == (0.1, 3)
    out = capsys.readouterr()
    assert out.err == "[solar] a line\n"
    head, table = out.out.split("\n\n")
    assert head.startswith(
        "table1-solar sensitivity: seed 3, 0.1 s per run, one knob changed at a time (12 s). "
        "Latency: workstation: correlation 100.00 ms on this machine -> delay 0.625 ms; "
        "this-machine: correlation 4.00 ms on this machine -> ")
    # an unstable RTC reads "-> unstable loop" (it read "-> delay unstable loop" before)
    assert head.endswith("this machine -> unstable loop.")
    assert table == _TABLE + "\n"
    seen.clear()
    assert solar.main([]) == 0
    assert seen["values"] == solar.FULL_VALUES
    assert (seen["duration"], seen["seed"]) == (0.3, 0)


def test_command_line_errors_are_one_line(monkeypatch, capsys):
    def fake(**kw):
        raise ValueError("first line\nsecond line")

    monkeypatch.setattr(solar, "solar_sensitivity", fake)
    assert solar.main(["--quick"]) == 2
    assert capsys.readouterr().err == "solar: error: first line\n"
    assert solar.main(["--knobs", " , "]) == 2
    assert capsys.readouterr().err == ("solar: error: --knobs must be a comma list of "
                                       "signal,contrast,n_subapertures,rtc; got ' , '\n")


def test_documented_knob_values():
    # the module's table: the base's own value is not repeated; quick is one value each
    assert solar.FULL_VALUES == {"signal": (1500.0, 150.0), "contrast": (0.06, 0.03),
                                 "n_subapertures": (8, 24), "rtc": ("fpga", "workstation")}
    assert solar.QUICK_VALUES == {"signal": (150.0,), "contrast": (0.03,),
                                  "n_subapertures": (8,), "rtc": ("workstation",)}
    assert solar.MAX_RUNS == 60 and solar.DEFAULT_PIXEL_SCALE == 0.5


def test_command_line_help_names_the_program_and_its_options(capsys):
    with pytest.raises(SystemExit) as exc:
        solar.main(["--help"])
    assert exc.value.code == 0
    raw = capsys.readouterr().out
    assert "\n\nSensitivity of table1-solar to the solar knobs.\n\n" in raw
    text = " ".join(raw.split())
    assert text.startswith("usage: python -m closedloop.studies.solar ")
    assert "--quick one value per knob" in text
    assert ("--knobs KNOBS comma list of knobs to vary (default all: "
            "signal,contrast,n_subapertures,rtc)") in text


def test_markdown_labels_an_unlisted_knob_by_its_name():
    study = _study()
    rows = tuple(dict(r, knob="wind") if r["knob"] == "signal" else r for r in study.rows)
    text = solar.markdown(dataclasses.replace(study, rows=rows))
    assert text.splitlines()[3].startswith("| wind | 150 e- | 1.000 |")


def test_latency_without_a_timer_measures_with_repeats_and_seed(monkeypatch):
    calls = []

    def measured(n, pixels, **kw):
        calls.append((n, pixels, kw))
        return 0.0

    monkeypatch.setattr(solar, "correlation_compute_time", measured)
    solar.solar_latency(_solar(), model=_Model(204, 120))
    assert calls == [(205, 120, {"repeats": 5, "seed": 0}), (121, 40, {"repeats": 5, "seed": 0})]
    calls.clear()
    solar.solar_latency(_solar(), model=_Model(204, 120), repeats=2, seed=9)
    assert [c[2] for c in calls] == [{"repeats": 2, "seed": 9}] * 2


def test_sizes_build_the_loop_model_when_none_is_given(monkeypatch):
    import closedloop.simulation as sim

    built = []

    def fake_model(config):
        built.append(config)
        return _Model(11, 12)

    monkeypatch.setattr(sim, "LoopModel", fake_model)
    cfg = _solar()
    assert solar.correlating_wfs_sizes(cfg) == [(0, 11, 120), (1, 12, 40)]
    assert built == [cfg]
    solar.correlating_wfs_sizes(cfg, _Model(1, 2))
    assert built == [cfg]  # a given model is used as it is


def test_stability_limit_uses_the_exposure_and_the_boundary_is_refused():
    cfg = _solar()
    half = cfg.replace(loop=dataclasses.replace(cfg.loop, integration_time=0.5e-3))
    limit = max_stable_gain(10.5, 0.5)  # 0.5 + 10 ms, half-frame exposure
    assert f"{limit:.3f}" != f"{max_stable_gain(10.5, 1.0):.3f}"
    with pytest.raises(ValueError) as exc:
        solar.solar_latency(half, rtc="this-machine", compute_time=0.01)
    assert str(exc.value) == (
        "`rtc` 'this-machine' (readout 0.5 ms, rtc_speed 1) gives a delay of 10.500 ms "
        "(10.00 ms of correlation on this machine): the loop gain 0.5 is beyond the largest "
        f"stable gain {limit:.3f} there; use a faster RTC or a lower gain.")
    # a gain exactly at the limit is not stable (the limit is where a pole reaches |z| = 1)
    limit = max_stable_gain(4.5, 1.0)
    at = cfg.replace(loop=dataclasses.replace(cfg.loop, gain=limit))
    with pytest.raises(ValueError, match="beyond the largest stable gain"):
        solar.solar_latency(at, rtc="this-machine", compute_time=4e-3)


def test_study_defaults_and_its_own_base(recorder, monkeypatch):
    timed = []
    monkeypatch.setattr(solar, "correlating_compute_time",
                        lambda config, model=None, **kw: timed.append((config, model)) or 4e-3)
    ticks = iter([10.0, 12.5, 20.0])
    monkeypatch.setattr(solar, "time", SimpleNamespace(perf_counter=lambda: next(ticks)))
    base, model = _solar(signal=3000.0), object()
    study = solar.solar_sensitivity(base, values={"rtc": ("workstation",)},
                                    predictors=("none",), model=model)
    # the base given, not the preset; the RTC's correlations timed on that base and model
    assert recorder.calls[0]["cfg"] == base and timed == [(base, model)]
    assert study.elapsed == 2.5  # wall time from start to end of the study
    assert recorder.calls[1]["cfg"] == base.replace(
        loop=dataclasses.replace(base.loop, delay=0.625e-3))
    assert [c["duration"] for c in recorder.calls] == [0.3, 0.3]  # the documented default
    assert study.duration == 0.3 and study.config_name == "table1-solar"
    with pytest.raises(ValueError) as exc:
        solar.solar_sensitivity(base, max_runs=0)
    assert str(exc.value) == "`max_runs` must be an int >= 1; got 0."


def test_given_run_of_another_predictor_refused(recorder):
    # audit 10, feedback: the no-prediction run given as the 'arma' row was shown as arma's
    base = _solar()
    other = _Run(base, 3, 0.004, 7)
    other.predictor = "none"
    with pytest.raises(ValueError, match=r"`base_results\['arma'\]` is a run of predictor "
                                         r"'none', not 'arma'"):
        solar.solar_sensitivity(base, values={"signal": (150.0,)}, predictors=("none", "arma"),
                                duration=0.004, seed=3, model=object(),
                                base_results={"arma": other})


def test_predictor_rows_average_from_the_no_prediction_closure(recorder, monkeypatch):
    """Round 43 PART b, R33: Figure 7's "(base)" ARMA row (0.379) averaged from ARMA's own
    closure, its main table (0.354) from the no-prediction run's: the sign of ARMA's effect
    flipped between two tables of one section. Reference: Marechal by hand on the variances
    set here, from the no-prediction run's closure (frame 1), not ARMA's (frame 2); the FoV
    stays the run's own (Figure 4's rule)."""
    import closedloop.training as training

    inner = training.run_trained

    def later_closure(cfg, name, *args, **kwargs):
        run = inner(cfg, name, *args, **kwargs)
        if name != "none":
            run.closure_index = run.averaging_start = 2  # a predictor settles later
        return run

    monkeypatch.setattr(training, "run_trained", later_closure)
    study = solar.solar_sensitivity(_solar(), values={"signal": (150.0,)},
                                    predictors=("none", "arma"), duration=0.003, seed=0,
                                    max_runs=4, latency={"workstation": (4e-3, 0.625e-3)},
                                    model=object())
    for knob, value in (("base", ""), ("signal", "150 e-")):
        row = study.row(knob, value, "arma")
        run = next(c["run"] for c in recorder.calls if c["name"] == "arma"
                   and c["run"].config == (_solar() if knob == "base" else _solar(signal=150.0)))
        want = np.mean(np.exp(-run.residual_variance[1:]).max(axis=1))  # from frame 1
        assert row["strehl_peak"] == pytest.approx(want, rel=1e-12)
        assert row["strehl_field"] == pytest.approx(np.exp(-run.residual_variance[1:]).mean(),
                                                    rel=1e-12)
        assert row["fov_arcmin"] == run.fov
