"""Figure 7 (solar correlating sensing) on hand-made runs and stand-in simulations.

Written for mutation testing (issue 26 item 3, docs/MUTATION.md). References, all outside
the module:
- the runs (``ClosedLoopRuns`` of dyadic SR series) and the figure's numbers are written
  in this file; every number the table, the report and the JSON carry is worked out by
  hand from the definitions of the module docstring and of Figures 2 and 4 (mean SR peak
  from the no-prediction closure frame, gain = difference to no prediction, the ratio to
  no prediction, the Marechal bound ``exp(-(measured - temporal))``);
- ``compute`` runs no loop: ``run_all``, ``summarize``, ``LoopModel`` and the solar
  study's timing, latency and sensitivity are replaced by recorders, so the test checks
  what the docstring says is passed to each (the table1 runs' seed, duration, field
  grid and quick settings, ``budget_every`` 5 and 25, the base runs reused, one timing
  for every RTC, an unstable RTC reported as NaN) and what comes back into the numbers;
- the JSON is read back from the file (strict JSON: NaN written as null) and the figure
  from the ``Figure`` handed to ``savefig`` (titles, axis labels and units, tick labels,
  the bars' heights, the series drawn) and the PNG's size at 110 dpi;
- the preset's own loop delays (``closedloop.presets``: table1-solar 1 ms, table1 0.5 ms).
No closed loop runs: ~2 s.
"""

from __future__ import annotations

import json
import math
import os

import numpy as np
import pytest

from closedloop.studies.solar import SolarSensitivity
from paper_figures import fig7_solar as fig7
from paper_figures.closedloop_runs import ClosedLoopRuns, PredictorRun

from .conftest import saved_figures

TIMES = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0]) * 1e-3
NAN = float("nan")


def _run(name, series, closure, fov, best=4):
    smap = np.full((3, 3), 0.1)
    smap.flat[best] = 0.4
    return PredictorRun(
        name=name, summary={"strehl_peak_mean": 0.0, "steps_per_second": 1.0},
        times=TIMES.copy(), strehl_peak=np.array(series, dtype=float), closure_index=closure,
        spectrum_freqs=np.zeros(1), spectrum_psd=np.zeros(1), strehl_map=smap,
        fov_diameter=fov)


def _budget(k, fitting, aliasing, temporal, noise, measured):
    """A 9-direction budget whose direction ``k`` holds the given terms (others 1.0)."""
    b = {"directions": np.array([[x, y] for y in (-30.0, 0.0, 30.0) for x in (-30.0, 0.0, 30.0)])}
    for key, v in (("fitting", fitting), ("aliasing", aliasing), ("temporal", temporal),
                   ("noise", noise), ("measured", measured)):
        b[key] = np.full(9, 1.0)
        b[key][k] = v
    return b


# table1: SR means over frames 2..5 (none closes at frame 2): none 0.5, linear 0.625,
# arma 0.75, oracle 0.875, arma-aic 0.25 (not one of Figure 7's predictors)
TABLE1 = ClosedLoopRuns(
    config_name="table1", seed=7, duration=0.006, field_size=120.0, wavelength=630e-9,
    runs={"none": _run("none", [0, 0, 0.5, 0.5, 0.5, 0.5], 2, 1.0),
          "linear": _run("linear", [0, 0, 0.625, 0.625, 0.625, 0.625], 3, 1.25),
          "arma": _run("arma", [0, 0, 0.75, 0.75, 0.75, 0.75], 3, 1.75),
          "oracle": _run("oracle", [0, 0, 0.875, 0.875, 0.875, 0.875], 4, 2.0),
          "arma-aic": _run("arma-aic", [0, 0, 0.25, 0.25, 0.25, 0.25], 2, 0.5)},
    budget=_budget(4, 0.2, 0.06, 0.03, 0.01, 0.3))
# solar: none closes at frame 3 (4 ms): means over frames 3..5
SOLAR = ClosedLoopRuns(
    config_name="table1-solar", seed=7, duration=0.006, field_size=120.0, wavelength=630e-9,
    runs={"none": _run("none", [0.9, 0.9, 0.9, 0.25, 0.25, 0.25], 3, 0.5, best=2),
          "linear": _run("linear", [0.9, 0.9, 0.9, 0.375, 0.375, 0.375], 4, 0.75),
          "arma": _run("arma", [0.9, 0.9, 0.9, 0.5, 0.5, 0.5], 4, 1.25),
          "oracle": _run("oracle", [0.9, 0.9, 0.9, 0.625, 0.625, 0.625], 5, 1.5)},
    budget=_budget(2, 0.21, 0.12, 0.07, 0.02, 0.45))

STUDY_ROWS = (
    {"knob": "base", "value": "", "predictor": "none", "delay": 1e-3, "strehl_peak": 0.25,
     "strehl_field": 0.2, "fov_arcmin": 0.5, "fitting": 0.21, "aliasing": 0.12,
     "temporal": 0.07, "noise": 0.02, "measured": 0.45},
    {"knob": "base", "value": "", "predictor": "arma", "delay": 1e-3, "strehl_peak": 0.5,
     "strehl_field": 0.3, "fov_arcmin": 1.25},
    {"knob": "signal", "value": "150 e-", "predictor": "none", "delay": 1e-3,
     "strehl_peak": 0.125, "strehl_field": 0.1, "fov_arcmin": 0.25, "fitting": 0.21,
     "aliasing": 0.12, "temporal": 0.07, "noise": 0.5, "measured": 0.9},
    {"knob": "signal", "value": "150 e-", "predictor": "arma", "delay": 1e-3,
     "strehl_peak": 0.375, "strehl_field": 0.2, "fov_arcmin": 0.75},
)
LATENCY = {"fpga": (2e-3, 1.5e-3), "workstation": (2.5e-3, NAN)}


def _study(latency=LATENCY):
    return SolarSensitivity(config_name="table1-solar", seed=7, duration=0.006,
                            predictors=("none", "arma"), rows=STUDY_ROWS, latency=latency)


# ---------------------------------------------------------------------------------------
# compute, with every simulation replaced by a recorder

class _Clock:
    """perf_counter stepping 1, 2, 3, ... s (one step per call)."""

    def __init__(self):
        self.t = 100.0

    def perf_counter(self):
        self.t += 1.0
        return self.t


@pytest.fixture
def stand_ins(monkeypatch):
    import closedloop.simulation
    import closedloop.studies.solar as solar
    from paper_figures import closedloop_runs

    calls = {}

    def loop_model(cfg):
        calls.setdefault("model", []).append(cfg)
        return ("model", cfg.name)

    def run_all(cfg, duration, **kw):
        calls["run_all"] = (cfg, duration, kw)
        names = kw["names"]
        return {n: f"result {n}" for n in names}, {n: (1.0, 2.0) for n in names}

    def summarize(results, **kw):
        calls["summarize"] = (results, kw)
        return SOLAR

    def compute_time(cfg, model):
        calls["compute_time"] = (cfg, model)
        return 2e-3

    def latency(cfg, *, rtc, compute_time):
        calls.setdefault("latency", []).append((cfg.name, rtc, compute_time))
        if rtc == "workstation":
            raise ValueError("unstable")
        return (compute_time, 1.5e-3)

    def sensitivity(cfg, **kw):
        calls["sensitivity"] = (cfg, kw)
        return _study(kw["latency"])

    monkeypatch.setattr(closedloop.simulation, "LoopModel", loop_model)
    monkeypatch.setattr(closedloop_runs, "run_all", run_all)
    monkeypatch.setattr(closedloop_runs, "summarize", summarize)
    monkeypatch.setattr(solar, "correlating_compute_time", compute_time)
    monkeypatch.setattr(solar, "solar_latency", latency)
    monkeypatch.setattr(solar, "solar_sensitivity", sensitivity)
    monkeypatch.setattr(os, "getloadavg", lambda: (1.5, 9.0, 9.0))
    monkeypatch.setattr(fig7, "time", _Clock())
    return calls


def test_compute_passes_the_table1_settings_and_collects_the_numbers(stand_ins):
    from closedloop import presets

    log = []
    out = fig7.compute(TABLE1, log=log.append)
    calls = stand_ins
    cfg, duration, kw = calls["run_all"]
    # the preset on the table1 runs' 3x3 grid (same field size)
    assert cfg.name == "table1-solar"
    assert cfg.field.n_points == 3 and cfg.field.size == presets.get("table1-solar").field.size
    assert cfg.replace(field=presets.get("table1-solar").field) == presets.get("table1-solar")
    assert duration == 0.006
    assert kw == {"seed": 7, "names": ("none", "linear", "arma", "nn-paper", "oracle"),
                  "budget_every": 5, "nn_max_iter": None, "log": log.append,
                  "model": ("model", "table1-solar")}
    assert calls["model"] == [cfg]
    results, skw = calls["summarize"]
    assert results == {n: f"result {n}" for n in kw["names"]}
    assert skw == {"duration": 0.006, "timings": {n: (1.0, 2.0) for n in kw["names"]},
                   "quick": False, "notes": {}}
    # one timing, every RTC of the report
    assert calls["compute_time"] == (cfg, ("model", "table1-solar"))
    assert calls["latency"] == [("table1-solar", "fpga", 2e-3),
                                ("table1-solar", "workstation", 2e-3)]
    scfg, sk = calls["sensitivity"]
    assert scfg is cfg
    lat = sk.pop("latency")
    assert lat["fpga"] == (2e-3, 1.5e-3)
    assert lat["workstation"][0] == 2e-3 and math.isnan(lat["workstation"][1])
    assert sk == {"values": {"signal": (150.0,), "contrast": (0.03,), "rtc": ("workstation",)},
                  "predictors": ("none", "arma"), "duration": 0.006, "seed": 7,
                  "model": ("model", "table1-solar"), "budget_every": 25,
                  "base_results": {"none": "result none", "arma": "result arma"},
                  "log": log.append}
    assert out.solar is SOLAR and out.table1 is TABLE1 and out.quick is False
    assert out.sensitivity.rows == STUDY_ROWS
    # the clock: start at 101, end at 102
    assert out.elapsed == 1.0
    num = out.numbers
    assert num["elapsed_s"] == 1.0
    assert (num["seed"], num["duration"], num["quick"], num["wavelength"]) == (
        7, 0.006, False, 630e-9)
    # the presets' delays: table1-solar 1 ms, table1 0.5 ms
    assert num["delay_ms"] == {"solar": 1.0, "table1": 0.5}
    assert num["latency"]["fpga"] == {"compute_ms": 2.0, "delay_ms": 1.5}
    assert num["latency"]["workstation"]["compute_ms"] == 2.0
    assert math.isnan(num["latency"]["workstation"]["delay_ms"])
    assert list(num["latency"]) == ["fpga", "workstation"]
    assert num["load_average"] == 1.5 and type(num["load_average"]) is float
    assert num["sensitivity"] == list(STUDY_ROWS)
    assert all(type(r) is dict for r in num["sensitivity"])
    assert num["knob_labels"] == {"signal": "photon flux (signal, e-/px/frame)",
                                  "contrast": "granulation contrast",
                                  "n_subapertures": "subapertures across (size)",
                                  "rtc": "compute latency (loop.delay)"}
    # each set: Figure 2's window means, Figure 4's diameters, the closure in ms
    sol, t1 = num["solar"], num["table1"]
    assert sol["config"] == "table1-solar" and t1["config"] == "table1"
    assert sol["peak_mean"] == {"none": 0.25, "linear": 0.375, "arma": 0.5, "oracle": 0.625}
    assert t1["peak_mean"] == {"none": 0.5, "linear": 0.625, "arma": 0.75, "oracle": 0.875}
    assert sol["fov"] == {"none": 0.5, "linear": 0.75, "arma": 1.25, "oracle": 1.5}
    assert t1["fov"] == {"none": 1.0, "linear": 1.25, "arma": 1.75, "oracle": 2.0}
    assert sol["closure_ms"] == pytest.approx(4.0, rel=1e-12)
    assert t1["closure_ms"] == pytest.approx(3.0, rel=1e-12)
    assert type(sol["closure_ms"]) is float
    # the budget at the best direction of each set (solar cell 2, table1 cell 4)
    assert sol["budget"]["direction"] == (30.0, -30.0)
    assert t1["budget"]["direction"] == (0.0, 0.0)
    assert sol["budget"]["temporal"] == 0.07 and t1["budget"]["temporal"] == 0.03
    assert sol["budget"]["sr_bound"] == pytest.approx(math.exp(-0.38), rel=1e-12)


def test_compute_quick_settings(stand_ins):
    quick = ClosedLoopRuns(**{**TABLE1.__dict__, "quick": True})
    out = fig7.compute(quick, log=None)
    _, _, kw = stand_ins["run_all"]
    assert kw["names"] == ("none", "linear", "arma", "oracle")
    assert kw["nn_max_iter"] == 50
    assert stand_ins["summarize"][1]["quick"] is True
    assert stand_ins["summarize"][1]["notes"] == {"nn_max_iter": 50}
    assert stand_ins["sensitivity"][1]["values"] == {"signal": (150.0,)}
    assert out.quick is True and out.numbers["quick"] is True


def test_compute_given_config_predictors_and_values(stand_ins):
    from closedloop import presets

    cfg = presets.get("table1-solar")
    fig7.compute(TABLE1, config=cfg, predictors=("none", "arma"),
                 sensitivity_values={"contrast": (0.02,)}, sensitivity_predictors=("arma",))
    assert stand_ins["run_all"][0] is cfg
    assert stand_ins["run_all"][2]["names"] == ("none", "arma")
    assert stand_ins["sensitivity"][1]["values"] == {"contrast": (0.02,)}
    assert stand_ins["sensitivity"][1]["predictors"] == ("arma",)
    assert stand_ins["sensitivity"][1]["base_results"] == {"arma": "result arma"}


def test_sensitivity_predictors_must_be_run(stand_ins):
    with pytest.raises(ValueError) as err:
        fig7.compute(TABLE1, predictors=("none", "linear"))
    assert str(err.value) == ("`sensitivity_predictors` must be among `predictors` "
                              "('none', 'linear'); got ['arma'].")
    assert "run_all" not in stand_ins


def test_solar_config_follows_the_grid():
    from closedloop import presets

    assert fig7.solar_config() == presets.get("table1-solar")
    cfg = fig7.solar_config(TABLE1)
    assert cfg.field.n_points == 3
    assert cfg.field.size == presets.get("table1-solar").field.size == 120.0


# ---------------------------------------------------------------------------------------
# the figure's numbers as compute makes them (written by hand), its table and report

def _set(config, peak, fov, closure, budget):
    return {"config": config, "peak_mean": peak, "fov": fov, "closure_ms": closure,
            "budget": budget}


SOL_B = {"direction": (30.0, -30.0), "fitting": 0.21, "aliasing": 0.12, "temporal": 0.07,
         "noise": 0.02, "measured": 0.45, "sr_now": math.exp(-0.45),
         "sr_bound": math.exp(-0.38)}
T1_B = {"direction": (0.0, 0.0), "fitting": 0.2, "aliasing": 0.06, "temporal": 0.03,
        "noise": 0.01, "measured": 0.3, "sr_now": math.exp(-0.3), "sr_bound": math.exp(-0.27)}


def _numbers(quick=False, solar_peak=None, budget=True):
    return {
        "seed": 7, "duration": 0.006, "quick": quick, "wavelength": 630e-9,
        "solar": _set("table1-solar",
                      solar_peak or {"none": 0.25, "linear": 0.375, "arma": 0.5,
                                     "oracle": 0.625},
                      {"none": 0.5, "linear": 0.75, "arma": 1.25, "oracle": 1.5}, 4.0,
                      SOL_B if budget else {}),
        "table1": _set("table1", {"none": 0.5, "linear": 0.7, "arma": 0.8},
                       {"none": 1.0, "linear": 1.25, "arma": 1.75}, 3.0,
                       T1_B if budget else {}),
        "delay_ms": {"solar": 1.0, "table1": 0.5},
        "latency": {"fpga": {"compute_ms": 2.0, "delay_ms": 1.5},
                    "workstation": {"compute_ms": 2.5, "delay_ms": NAN}},
        "load_average": 1.5,
        "sensitivity": [dict(r) for r in STUDY_ROWS],
        "knob_labels": {"signal": "photon flux (signal, e-/px/frame)"},
        "elapsed_s": 3.0,
    }


def _fig(numbers=None, quick=False):
    return fig7.Figure7(solar=SOLAR, table1=TABLE1, numbers=numbers or _numbers(quick),
                        sensitivity=_study(), quick=quick, elapsed=3.0)


ROWS = [
    # ratios: solar 0.375 / 0.25 = 1.5, 0.5 / 0.25 = 2; table1 0.7 / 0.5, 0.8 / 0.5
    ("SR peak, no prediction, table1-solar (extension)", "0.4", "0.250 (table1 0.500)",
     "noise term 0.0200 rad^2 against table1's 0.0100"),
    ("SR peak, linear (a=2, b=-1), table1-solar (extension)", "> 0.6",
     "0.375 (table1 0.700)", "x1.500 over no prediction (table1 x1.400)"),
    ("SR peak, ARMA(2,3), table1-solar (extension)", "> 0.6", "0.500 (table1 0.800)",
     "x2.000 over no prediction (table1 x1.600)"),
    # no table1 oracle: the noise sentence, and "n/a"
    ("SR peak, oracle (true future), table1-solar (extension)", "-", "0.625 (table1 n/a)",
     "noise term 0.0200 rad^2 against table1's 0.0100"),
    ("corrected FoV d, no prediction, table1-solar (extension)", "0.9'",
     "0.50' (table1 1.00')",
     "d = 2 sqrt(A/pi) of the field with SR > 0.3 (Figure 4's definition)"),
    ("corrected FoV d, ARMA(2,3), table1-solar (extension)", "1.6'", "1.25' (table1 1.75')",
     "d = 2 sqrt(A/pi) of the field with SR > 0.3 (Figure 4's definition)"),
    ("error budget at the best direction, table1-solar (extension)", "not published",
     "fitting 0.210 + aliasing 0.120 + temporal 0.070 + noise 0.0200 rad^2 (measured 0.450)",
     "table1: temporal 0.030, noise 0.0100; a predictor acts on the temporal term only"),
    ("correlation latency, fpga RTC (extension)",
     "\"increase the time delay\" (not quantified)",
     "2.00 ms of correlation on this machine -> delay 1.500 ms",
     "table1-solar's preset delay is 1 ms (table1 0.5 ms)"),
    ("correlation latency, workstation RTC (extension)",
     "\"increase the time delay\" (not quantified)",
     "2.50 ms of correlation on this machine -> delay beyond the stable loop",
     "table1-solar's preset delay is 1 ms (table1 0.5 ms)"),
]


def test_table_rows_word_for_word():
    assert fig7.table_rows(_fig()) == ROWS
    # from the JSON dict (NaN written as None) the same rows
    assert fig7.table_rows(json.loads(json.dumps(fig7._json_safe(_numbers())))) == ROWS


def test_table_rows_without_budget_or_timing():
    num = _numbers(budget=False)
    num["latency"] = {"fpga": {"compute_ms": None, "delay_ms": None}}
    rows = fig7.table_rows(num)
    assert rows[0][3] == "noise term n/a rad^2 against table1's n/a"
    assert not any(r[0].startswith("error budget") for r in rows)
    assert rows[-1][2] == "n/a ms of correlation on this machine -> delay beyond the stable loop"


def _sensitivity_table():
    return "\n".join([
        "| knob | value | delay [ms] | SR peak none | SR peak arma | FoV d none ['] | "
        "FoV d arma ['] | fitting | aliasing | temporal | noise | measured (on axis, rad^2) |",
        "|" + "---|" * 12,
        "| (base) |  | 1.000 | 0.250 | 0.500 | 0.50 | 1.25 | 0.2100 | 0.1200 | 0.0700 | "
        "0.0200 | 0.4500 |",
        "| photon flux (signal, e-/px/frame) | 150 e- | 1.000 | 0.125 | 0.375 | 0.25 | 0.75 | "
        "0.2100 | 0.1200 | 0.0700 | 0.5000 | 0.9000 |"])


def _table(rows):
    return "\n".join(["| quantity | paper | ours | why they differ |", "|---|---|---|---|"]
                     + [f"| {a} | {b} | {c} | {d} |" for a, b, c, d in rows])


def test_report_word_for_word():
    # gains: solar linear +0.125, arma +0.250 (table1 +0.200, +0.300); the oracle has no
    # table1 run, so no gain; best solar predictor the oracle, +0.375 > 0.05
    # temporal shares 0.07 / 0.45 = 15.6 %, 0.03 / 0.3 = 10.0 %; SR exp(-0.45) = 0.638 ->
    # exp(-0.38) = 0.684
    expected = f"""## Figure 7: Solar correlating sensing (extension, not in the paper)

![Figure 7](fig7_solar.png)

The comparison of Figures 2-4 on `table1-solar` (table1 with both WFSs a correlating
Shack-Hartmann on granulation: slopes are contrast-weighted Z-tilts, the noise follows
from the photon budget and the scene's contrast, the delay is
1 ms against table1's 0.5 ms), seed
7, 0.006 s per run, the same field grid and training as the
table1 runs of Figures 2-4; means after the no-prediction run's closure
(4 ms; table1 3 ms). Numbers in
`fig7_solar.json`.

{_table(ROWS)}

SR peak gained over no prediction: linear (a=2, b=-1) +0.125 (table1 +0.200), ARMA(2,3) \
+0.250 (table1 +0.300). At the best direction the temporal term is 0.070 rad^2 of a 0.450 \
rad^2 residual with solar sensing (15.6%), against 0.030 of 0.300 (10.0%) with table1's \
geometric sensor; the noise term is 0.0200 against 0.0100. Removing the whole temporal \
term would raise the Marechal SR there from 0.638 to at most 0.684. With solar sensing \
prediction has room: oracle (true future) gains +0.375 in SR peak.

**Latency** (`closedloop.studies.solar.solar_latency`: the correlations of one frame
timed on this machine with the sensor's kernels, then `LatencyModel`'s readout +
compute / rtc_speed on the simulator's grid): fpga: 2.00 ms of correlation on this \
machine -> delay 1.500 ms; workstation: 2.50 ms of correlation on this machine -> delay \
unstable (1-minute load average 1.5 on this machine's {os.cpu_count()} cores when timed: \
the time grows with the load).

**Sensitivity** (one knob at a time, no prediction and ARMA; SR means after each knob
value's no-prediction run's closure, the main table's window, so its "(base)" row is the
table's; FoV from each run's own closure, as the table's FoV column; on-axis budget
of the no-prediction run; `python -m closedloop.studies.solar` makes the full table):

{_sensitivity_table()}
"""
    assert fig7.report(_fig()) == expected


def test_report_quick_little_gain_and_no_budget():
    num = _numbers(quick=True, solar_peak={"none": 0.25, "linear": 0.265625}, budget=False)
    text = fig7.report(_fig(num, quick=True))
    assert ("`fig7_solar.json`. **Quick settings** (`--quick`): short runs on a 5x5 grid, "
            "no NN, one sensitivity knob; the numbers are not the full run's.\n") in text
    # linear +0.015625 < 0.05; no budget: no temporal sentence
    assert ("SR peak gained over no prediction: linear (a=2, b=-1) +0.016 (table1 +0.200). "
            "Prediction buys little with solar sensing too (best: linear (a=2, b=-1), +0.016 "
            "in SR peak): the residual stays dominated by the terms no predictor "
            "touches.\n") in text
    # only no prediction: best is "none"
    num = _numbers(solar_peak={"none": 0.25})
    text = fig7.report(_fig(num))
    assert ("Prediction buys little with solar sensing too (best: no prediction, +0.000 in "
            "SR peak)") in text


# ---------------------------------------------------------------------------------------
# plot: the JSON and the drawn figure read back

@pytest.fixture(scope="module")
def drawn(tmp_path_factory):
    out = tmp_path_factory.mktemp("fig7")
    with saved_figures() as figures:
        paths = fig7.plot(_fig(), out)
    return out, paths, figures


def test_plot_writes_png_pdf_and_strict_json(drawn):
    # every read-back in one test: the module fixture draws once, in the first
    # test's setup, and mutmut runs a mutant of `plot` only with the tests that called it
    import matplotlib.colors as mcolors
    import matplotlib.image

    out, paths, figures = drawn
    assert paths == [out / "fig7_solar.png", out / "fig7_solar.pdf", out / "fig7_solar.json"]
    assert matplotlib.image.imread(paths[0]).shape[:2] == (990, 1430)  # 13 x 9 in, 110 dpi
    assert paths[1].read_bytes()[:5] == b"%PDF-"
    text = paths[2].read_text(encoding="utf-8")
    data = json.loads(text, parse_constant=lambda c: pytest.fail(f"non-JSON {c}"))
    expected = _numbers()
    expected["latency"]["workstation"]["delay_ms"] = None
    expected["solar"]["budget"] = dict(SOL_B, direction=[30.0, -30.0])
    expected["table1"]["budget"] = dict(T1_B, direction=[0.0, 0.0])
    assert data == expected
    assert text == json.dumps(expected, indent=1)
    fig = figures["fig7_solar.png"]
    assert tuple(fig.get_size_inches()) == (13.0, 9.0)
    assert fig._suptitle.get_text() == ("Figure 7 (extension, not in the paper): solar "
                                        "correlating sensing, seed 7, 0.006 s")
    assert fig._suptitle.get_fontsize() == 10
    a, b, c, d, twin = fig.axes
    # (a) the solar runs, table1's no-prediction line, the closure at 4 ms
    assert a.get_title() == "(a) table1-solar: SR peak vs time (mean after closure)"
    assert a.title.get_fontsize() == 9
    assert a.get_xlabel() == "time [ms]"
    assert a.get_ylabel() == "SR peak over the field (630 nm)"
    assert a.get_ylim() == (0.0, 1.0)
    lines = [ln for ln in a.get_lines() if ln.get_label()[0] != "_"]
    assert [ln.get_label() for ln in lines] == [
        "no prediction (0.250)", "linear (a=2, b=-1) (0.375)", "ARMA(2,3) (0.500)",
        "oracle (true future) (0.625)", "table1 (geometric SH), no prediction (0.500)"]
    for ln, run in zip(lines, [*SOLAR.runs.values(), TABLE1.runs["none"]], strict=True):
        np.testing.assert_allclose(ln.get_xdata(), [1, 2, 3, 4, 5, 6], rtol=1e-12)
        np.testing.assert_array_equal(ln.get_ydata(), run.strehl_peak)
    assert mcolors.to_hex(lines[0].get_color()) == "#000000"
    assert mcolors.to_hex(lines[2].get_color()) == "#0000ff"
    assert mcolors.to_hex(lines[-1].get_color()) == mcolors.to_hex("0.7")
    assert lines[-1].get_linewidth() == 0.8
    (vline,) = [ln for ln in a.get_lines() if ln.get_label()[0] == "_"]
    np.testing.assert_array_equal(vline.get_xdata(), [4.0, 4.0])
    assert mcolors.to_hex(vline.get_color()) == mcolors.to_hex("0.4")
    assert vline.get_linewidth() == 0.8
    assert a.get_legend().get_texts()[0].get_fontsize() == 6
    # (b) corrected FoV: table1 left, solar right, the paper's stars
    assert b.get_title() == "(b) corrected field of view"
    assert b.title.get_fontsize() == 9
    assert b.get_legend().get_texts()[0].get_fontsize() == 7
    assert b.get_ylabel() == "corrected FoV diameter d (SR > 0.3) [arcmin]"
    assert [t.get_text() for t in b.get_xticklabels()] == [
        "no prediction", "linear (a=2, b=-1)", "ARMA(2,3)", "oracle (true future)"]
    assert b.get_xticklabels()[0].get_rotation() == 20
    assert b.get_xticklabels()[0].get_fontsize() == 7
    bars = b.patches
    np.testing.assert_allclose([p.get_x() + p.get_width() / 2 for p in bars],
                               [-0.2, 0.8, 1.8, 2.8, 0.2, 1.2, 2.2, 3.2], atol=1e-12)
    np.testing.assert_allclose([p.get_width() for p in bars], [0.4] * 8, rtol=1e-12)
    np.testing.assert_array_equal([p.get_height() for p in bars],
                                  [1.0, 1.25, 1.75, NAN, 0.5, 0.75, 1.25, 1.5])
    assert mcolors.to_hex(bars[0].get_facecolor()) == mcolors.to_hex("0.7")
    assert mcolors.to_hex(bars[4].get_facecolor()) == mcolors.to_hex("tab:orange")
    (stars,) = b.get_lines()
    np.testing.assert_array_equal(stars.get_ydata(), [0.9, 1.25, 1.6, NAN])
    assert stars.get_marker() == "*" and stars.get_markersize() == 9
    assert [t.get_text() for t in b.get_legend().get_texts()] == [
        "paper (Fig. 4)", "table1 (geometric SH)", "table1-solar (correlating SH)"]
    # (c) the stacked budget terms, table1 then solar, and the measured residual
    assert c.get_title() == "(c) error budget: what a predictor can act on (temporal)"
    assert c.get_ylabel() == "rad^2 at 630 nm (best direction, no prediction)"
    assert [t.get_text() for t in c.get_xticklabels()] == ["table1", "table1-solar"]
    heights = [(p.get_x() + p.get_width() / 2, p.get_y(), p.get_height()) for p in c.patches]
    np.testing.assert_allclose(heights, [
        (0, 0, 0.2), (0, 0.2, 0.06), (0, 0.26, 0.03), (0, 0.29, 0.01),
        (1, 0, 0.21), (1, 0.21, 0.12), (1, 0.33, 0.07), (1, 0.4, 0.02)], atol=1e-12)
    assert [mcolors.to_hex(p.get_facecolor()) for p in c.patches[:4]] == [
        mcolors.to_hex(x) for x in ("tab:blue", "tab:green", "tab:red", "tab:purple")]
    assert c.patches[0].get_width() == 0.5
    # the legend's entries come from the first set's artists (each term named once)
    assert [b.get_label() for b in c.containers[:4]] == ["fitting", "aliasing", "temporal",
                                                         "noise"]
    assert len(c.containers) == 8
    assert all(b.get_label().startswith("_") for b in c.containers[4:])
    assert list(c.get_xticks()) == [0, 1]
    assert c.title.get_fontsize() == 9
    assert c.get_legend().get_texts()[0].get_fontsize() == 7
    measured = c.get_lines()
    np.testing.assert_allclose([ln.get_xdata() for ln in measured],
                               [[-0.3, 0.3], [0.7, 1.3]], atol=1e-12)
    assert [list(ln.get_ydata()) for ln in measured] == [[0.3, 0.3], [0.45, 0.45]]
    assert measured[0].get_linewidth() == 2
    assert [mcolors.to_hex(ln.get_color()) for ln in measured] == ["#000000"] * 2
    assert [ln.get_linestyle() for ln in measured] == ["-"] * 2
    assert measured[0].get_label() == "measured residual"
    assert measured[1].get_label().startswith("_")
    assert [t.get_text() for t in c.get_legend().get_texts()] == [
        "measured residual", "fitting", "aliasing", "temporal", "noise"]
    # (d) sensitivity: SR peak per knob value (none o, ARMA x shifted by 0.1), noise twin
    assert d.get_title() == "(d) sensitivity, one knob at a time"
    assert d.title.get_fontsize() == 9
    # the SR legend upper left, the noise legend upper right (matplotlib's codes 2 and 1)
    assert (d.get_legend()._loc, twin.get_legend()._loc) == (2, 1)
    assert {t.get_fontsize() for ax in (d, twin) for t in ax.get_legend().get_texts()} == {7}
    assert d.get_ylabel() == "SR peak after closure"
    assert [t.get_text() for t in d.get_xticklabels()] == ["base", "signal\n150 e-"]
    assert d.get_xticklabels()[0].get_fontsize() == 6
    assert d.get_xlim() == (-0.5, 1.5) and d.get_ylim()[0] == 0.0
    none, arma = d.get_lines()
    np.testing.assert_allclose(none.get_xdata(), [0.0, 1.0])
    np.testing.assert_allclose(arma.get_xdata(), [0.1, 1.1])
    assert list(none.get_ydata()) == [0.25, 0.125] and list(arma.get_ydata()) == [0.5, 0.375]
    assert (none.get_marker(), arma.get_marker()) == ("o", "x")
    assert mcolors.to_hex(arma.get_color()) == "#0000ff"
    assert [t.get_text() for t in d.get_legend().get_texts()] == [
        "SR peak, no prediction", "SR peak, ARMA(2,3)"]
    (noise,) = twin.get_lines()
    assert list(noise.get_ydata()) == [0.02, 0.5]
    assert noise.get_marker() == "s" and noise.get_markersize() == 4
    assert mcolors.to_hex(noise.get_color()) == mcolors.to_hex("tab:purple")
    assert twin.get_ylabel() == "on-axis noise term [rad^2]"
    assert mcolors.to_hex(twin.yaxis.label.get_color()) == mcolors.to_hex("tab:purple")
    assert [t.get_text() for t in twin.get_legend().get_texts()] == [
        "noise term (no prediction)"]


def test_json_safe():
    got = fig7._json_safe({1: (np.float64(NAN), np.int64(3), float("inf")),
                           "a": [np.float32(0.5), {"b": -math.inf}], "c": "x", "d": None})
    assert got == {"1": [None, 3, None], "a": [0.5, {"b": None}], "c": "x", "d": None}
    assert type(got["1"][1]) is int and type(got["a"][0]) is float


def test_plot_suptitle_quick(tmp_path, monkeypatch):
    # the figure as handed to the saver (not saved: the fixture reads the files back)
    import matplotlib.pyplot as plt

    saved = []
    monkeypatch.setattr(fig7, "save_png_pdf", lambda f, out, png, pdf: saved.append(
        (f, out, png, pdf)) or [out / png, out / pdf])
    paths = fig7.plot(_fig(_numbers(quick=True), quick=True), tmp_path)
    ((f, out, png, pdf),) = saved
    plt.close(f)
    assert (out, png, pdf) == (tmp_path, "fig7_solar.png", "fig7_solar.pdf")
    assert paths == [tmp_path / png, tmp_path / pdf, tmp_path / "fig7_solar.json"]
    assert f._suptitle.get_text().endswith(", seed 7, 0.006 s (quick)")


def test_plot_without_budgets_draws_no_budget_bars(tmp_path, monkeypatch):
    # no error budget estimated ({}, as budget_sentence returns): panel (c) is empty
    import matplotlib.pyplot as plt

    saved = []
    monkeypatch.setattr(fig7, "save_png_pdf", lambda f, out, png, pdf: saved.append(f)
                        or [out / png, out / pdf])
    fig7.plot(_fig(_numbers(budget=False)), tmp_path)
    (f,) = saved
    c = f.axes[2]
    plt.close(f)
    assert c.get_title().startswith("(c) error budget")
    assert [p.get_height() for p in c.patches] == [0.0] * 8
    assert c.get_lines() == []


# ---------------------------------------------------------------------------------------
# make and the command line

def test_make_and_main(tmp_path, monkeypatch, capsys):
    from paper_figures import closedloop_runs

    made, drawn = [], []
    fig = _fig()
    monkeypatch.setattr(fig7, "compute", lambda runs: made.append(runs) or fig)
    monkeypatch.setattr(fig7, "plot", lambda f, out: drawn.append((f, out)))
    text = fig7.make(tmp_path, TABLE1)
    assert made == [TABLE1] and drawn == [(fig, tmp_path)] and text == fig7.report(fig)

    calls = []

    def runs(**kw):
        calls.append(kw)
        return TABLE1

    monkeypatch.setattr(closedloop_runs, "compute", runs)
    monkeypatch.setattr(fig7, "make", lambda out, r: f"made {out} {r.config_name}")
    out = tmp_path / "new" / "deeper"
    assert fig7.main(["--out", str(out), "--quick", "--seed", "5"]) == 0
    assert calls == [{"quick": True, "seed": 5,
                      "names": ("none", "linear", "arma", "nn-paper", "oracle")}]
    # drawn in a staging folder under the folder's lock (left13-cli); the stand-in drew
    # nothing, so the new folder is left out again and the lock released
    assert not (out / ".lock").exists()
    assert capsys.readouterr().out.startswith(f"made {out / '.deeper.partial-'}")
    # defaults: out/, not quick, seed 0; the existing files refused, each by name
    monkeypatch.chdir(tmp_path)
    assert fig7.main([]) == 0
    assert calls[-1] == {"quick": False, "seed": 0,
                         "names": ("none", "linear", "arma", "nn-paper", "oracle")}
    assert not (tmp_path / "out" / ".lock").exists()
    capsys.readouterr()
    for name in ("fig7_solar.png", "fig7_solar.pdf", "fig7_solar.json"):
        d = tmp_path / name.replace(".", "_")
        d.mkdir()
        (d / name).write_text("mine")
        assert fig7.main(["--out", str(d)]) == 2
        assert capsys.readouterr().err == (
            f"python -m paper_figures.fig7_solar: error: '{d / name}' exists; pass --overwrite\n")
        assert fig7.main(["--out", str(d), "--overwrite"]) == 0
        assert (d / name).read_text() == "mine"  # make is the stand-in: nothing drawn


def test_main_help(capsys):
    with pytest.raises(SystemExit) as exc:
        fig7.main(["--help"])
    assert exc.value.code == 0
    out = " ".join(capsys.readouterr().out.split())
    assert out.startswith("usage: python -m paper_figures.fig7_solar ")
    assert ("Figure 7: the comparison of Figures 2-4 with solar correlating sensing." in out)
    for text in ("--out OUT output directory", "--overwrite replace an existing figure",
                 "--quick short runs, 5x5 field grid", "--seed SEED"):
        assert text in out


def test_constants_documented_in_the_module():
    assert (fig7.FIGURE_NAME, fig7.PDF_NAME, fig7.JSON_NAME) == (
        "fig7_solar.png", "fig7_solar.pdf", "fig7_solar.json")
    assert fig7.NEEDS_RUNS is True and fig7.PRESET == "table1-solar"
    assert fig7.REPORT_RTCS == ("fpga", "workstation")


def test_sens_pairs_in_order_base_first():
    assert fig7._sens_pairs({"sensitivity": list(STUDY_ROWS)}) == [
        ("base", ""), ("signal", "150 e-")]
    assert fig7._sens({"sensitivity": list(STUDY_ROWS)}, "signal", "150 e-", "arma") is \
        STUDY_ROWS[3]


# ---------------------------------------------------------------------------------------
# boundaries found by the mutation run of 2026-11-28 19:00 (docs/MUTATION.md)

def test_report_best_predictor_by_sr_not_by_name():
    # ARMA best (+0.250); "oracle" would win by name
    num = _numbers(solar_peak={"none": 0.25, "linear": 0.375, "arma": 0.5, "oracle": 0.3125})
    text = fig7.report(_fig(num))
    assert "With solar sensing prediction has room: ARMA(2,3) gains +0.250 in SR peak." in text


def test_report_no_prediction_is_never_the_best_predictor():
    # every predictor below no prediction: the best of them, with its negative gain
    num = _numbers(solar_peak={"none": 0.5, "linear": 0.25})
    assert ("Prediction buys little with solar sensing too (best: linear (a=2, b=-1), -0.250 "
            "in SR peak)") in fig7.report(_fig(num))


def test_report_a_gain_of_exactly_005_has_room():
    # 0.1125 - 0.0625 is 0.05 exactly in binary64: the verdict's bound is "< 0.05 buys
    # little"
    assert 0.1125 - 0.0625 == 0.05
    num = _numbers(solar_peak={"none": 0.0625, "linear": 0.1125})
    assert ("With solar sensing prediction has room: linear (a=2, b=-1) gains +0.050 in SR "
            "peak.") in fig7.report(_fig(num))


def test_report_needs_both_budgets_for_the_temporal_sentence():
    num = _numbers()
    num["table1"]["budget"] = {}
    text = fig7.report(_fig(num))
    assert "At the best direction" not in text
    assert "SR peak gained over no prediction: linear (a=2, b=-1) +0.125 (table1 +0.200), " \
           "ARMA(2,3) +0.250 (table1 +0.300). With solar sensing" in text
