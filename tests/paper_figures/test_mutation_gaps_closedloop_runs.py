"""The shared closed-loop runs of Figures 2-4, with the loops replaced by recorders.

Written for mutation testing (issue 26 item 3, docs/MUTATION.md). References, all
outside the module:

- the module docstring's contract: one ``LoopModel`` and one seed for every run, "none"
  first and the others trained on it, the error budget on the no-prediction run only
  (every 5 frames by default), ``--quick`` = a 5 x 5 field grid, 0.2 s, the NNs trained
  for 50 iterations and ARMA-AIC searching p, q <= 3 (each noted in the report), the
  SR > 0.3 corrected field of the paper (Sect. 3.4);
- the paper's line styles (Figs. 2-3 captions: black continuous none, red dots linear,
  magenta dashed NN, blue dash-dotted ARMA);
- hand-made stand-ins of ``SimulationResult`` whose numbers are written here, a clock
  whose readings are written here (so every timing is exact), and the log lines and the
  report's paragraph written out word for word.
No loop runs: ~1 s.
"""

from __future__ import annotations

import types

import numpy as np
import pytest

import closedloop.simulation
import closedloop.training
from closedloop import presets
from closedloop.config import FieldConfig
from paper_figures import closedloop_runs as cr


def test_constants():
    assert cr.PAPER_PREDICTORS == ("none", "linear", "arma", "nn-paper")
    assert cr.EXTRA_PREDICTORS == ("oracle", "arma-aic")
    assert (cr.DEFAULT_DURATION, cr.QUICK_DURATION) == (0.5, 0.2)
    assert (cr.QUICK_NN_MAX_ITER, cr.QUICK_ARMA_MAX_ORDER) == (50, 3)
    assert cr.LABELS["none"] == "no prediction" and cr.LABELS["arma"] == "ARMA(2,3)"
    assert cr.LABELS["linear"] == "linear (a=2, b=-1)"
    assert cr.LABELS["nn-paper"] == "NN (paper, 10 patterns)"
    # the paper's styles (Figs. 2-3 captions)
    assert cr.STYLES["none"] == {"color": "k", "linestyle": "-"}
    assert cr.STYLES["linear"] == {"color": "r", "linestyle": "none", "marker": ".",
                                   "markersize": 3}
    assert cr.STYLES["nn-paper"] == {"color": "m", "linestyle": "--"}
    assert cr.STYLES["arma"] == {"color": "b", "linestyle": "-."}


def _prun(name, smap=((0.1, 0.2), (0.4, 0.3)), summary=None):
    return cr.PredictorRun(name=name, summary=summary or {"strehl_peak_mean": 0.375},
                           times=np.arange(1, 5) * 1e-3, strehl_peak=np.zeros(4),
                           closure_index=1, spectrum_freqs=np.zeros(1),
                           spectrum_psd=np.zeros(1), strehl_map=np.array(smap),
                           fov_diameter=0.5)


def test_run_record_helpers():
    r = _prun("arma")
    assert r.label == "ARMA(2,3)" and _prun("my-own").label == "my-own"
    assert r.peak_mean == 0.375 and type(_prun("x", summary={"strehl_peak_mean": 1}).peak_mean) \
        is float
    assert (r.train_seconds, r.run_seconds) == (0.0, 0.0)
    runs = cr.ClosedLoopRuns(config_name="c", seed=1, duration=0.1, field_size=60.0,
                             wavelength=5e-7, runs={"none": r, "arma": _prun("arma")},
                             budget={})
    assert runs.get("arma") is runs.runs["arma"] and runs.get("nn") is None
    assert runs.notes == {} and runs.quick is False
    # the best direction: the largest SR of the no-prediction map, row-major index
    assert runs.best_direction == 2 and type(runs.best_direction) is int


def test_configs(monkeypatch):
    assert cr.default_config() == presets.get("table1")
    q = cr.quick_config()
    assert q.field.n_points == 5 and q.field.size == presets.get("table1").field.size
    assert q.replace(field=presets.get("table1").field) == presets.get("table1")
    # another field size is kept
    cfg = presets.get("table1")
    other = cfg.replace(field=FieldConfig(size=50.0, n_points=9))
    monkeypatch.setattr(presets, "get", lambda name: other if name == "table1" else None)
    assert cr.quick_config().field.size == 50.0
    assert cr.quick_config().field.n_points == 5


def test_loop_predictor_overrides():
    assert cr._loop_predictor("nn-paper", 7).predictor.max_iter == 7
    assert cr._loop_predictor("nn", 7.0).predictor.max_iter == 7
    assert type(cr._loop_predictor("nn", 7.0).predictor.max_iter) is int
    assert cr._loop_predictor("nn", None).predictor.max_iter == 100   # the forecaster's own
    assert cr._loop_predictor("arma-aic", 7, 2).predictor.max_order == 2
    assert type(cr._loop_predictor("arma-aic", None, 2.0).predictor.max_order) is int
    assert cr._loop_predictor("arma-aic", None, None).predictor.max_order == 5
    assert not hasattr(cr._loop_predictor("linear", 7, 2).predictor, "max_iter")
    assert not hasattr(cr._loop_predictor("nn", 7, 2).predictor, "max_order")
    assert not hasattr(cr._loop_predictor("arma-aic", 7, None).predictor, "max_iter")
    assert cr._loop_predictor("arma", None).name == "arma"


class _Result:
    """A SimulationResult's face: the numbers the shared runs keep, written here."""

    def __init__(self, name, peak, d, budget=None, seed=4):
        self.name, self.peak, self.d = name, peak, d
        self.times = [0.001, 0.002, 0.003]
        self.strehl_peak = [0.25, peak, peak]
        self.closure_index = np.int64(1)
        self.averaging_start = np.int64(2)   # not the closure: a run that did not close
        self.budget = budget
        self.seed = seed
        self.config = types.SimpleNamespace(name="table1", field=types.SimpleNamespace(size=60),
                                            wavelength=5e-7)
        self.thresholds = []

    def summary(self):
        return {"strehl_peak_mean": self.peak, "corrected_fov_diameter_arcmin": self.d,
                "steps_per_second": 250.0}

    def strehl_peak_spectrum(self):
        return [0.0, 500.0], [1.0, 2.0]

    def strehl_map(self):
        return np.array([[self.peak]])

    def corrected_fov_diameter(self, threshold):
        self.thresholds.append(threshold)
        return self.d


class _Pred:
    def __init__(self, name, needs):
        self.name, self.needs_training, self.trained_on = name, needs, None

    def trained(self, reference):
        out = _Pred(self.name, False)
        out.trained_on = reference
        return out


def test_run_all_none_first_trained_on_it_timed(monkeypatch):
    made, runs, lines = [], [], []
    models = []

    def loop_model(config):
        models.append(config)
        return "model"

    def loop_predictor(name, nn_max_iter, arma_max_order=None):
        made.append((name, nn_max_iter, arma_max_order))
        return _Pred(name, name != "none")

    peaks = {"none": 0.5, "arma": 0.625, "nn": 0.25}

    def run_trained(config, predictor, duration, **kw):
        runs.append((config, predictor, duration, kw))
        return _Result(predictor.name, peaks[predictor.name], 0.875)

    clock = iter([0.0, 1.0, 3.5, 10.0, 10.25, 11.0, 20.0, 22.0, 22.5])
    monkeypatch.setattr(cr, "time", types.SimpleNamespace(perf_counter=lambda: next(clock)))
    monkeypatch.setattr(closedloop.simulation, "LoopModel", loop_model)
    monkeypatch.setattr(closedloop.training, "run_trained", run_trained)
    monkeypatch.setattr(cr, "_loop_predictor", loop_predictor)
    results, timings = cr.run_all("cfg", 0.25, seed=9, names=("arma", "none", "nn"),
                                  budget_every=7, nn_max_iter=11, arma_max_order=2,
                                  progress=True, log=lines.append)
    assert list(results) == ["none", "arma", "nn"] and models == ["cfg"]
    assert made == [("none", 11, 2), ("arma", 11, 2), ("nn", 11, 2)]
    assert [r[0] for r in runs] == ["cfg"] * 3 and [r[2] for r in runs] == [0.25] * 3
    assert [r[3] for r in runs] == [
        {"seed": 9, "model": "model", "progress": True, "budget_every": 7},
        {"seed": 9, "model": "model", "progress": True, "budget_every": None},
        {"seed": 9, "model": "model", "progress": True, "budget_every": None}]
    assert runs[0][1].trained_on is None
    assert runs[1][1].trained_on is results["none"] and runs[2][1].trained_on is results["none"]
    assert timings == {"none": (1.0, 2.5), "arma": (0.25, 0.75), "nn": (2.0, 0.5)}
    assert lines == [
        "[paper_figures]   none: SR peak 0.500 (mean from 3 ms, the no-prediction run's "
        "closure), corrected FoV d = 0.88' (from its own closure at 3 ms) "
        "(train 1.0 s, loop 2.5 s)",
        "[paper_figures]   arma: SR peak 0.625 (mean from 3 ms, the no-prediction run's "
        "closure), corrected FoV d = 0.88' (from its own closure at 3 ms) "
        "(train 0.2 s, loop 0.8 s)",
        "[paper_figures]   nn: SR peak 0.250 (mean from 3 ms, the no-prediction run's "
        "closure), corrected FoV d = 0.88' (from its own closure at 3 ms) "
        "(train 2.0 s, loop 0.5 s)"]


def test_run_all_defaults(monkeypatch, capsys):
    runs, built = [], []
    monkeypatch.setattr(closedloop.simulation, "LoopModel", lambda c: built.append(c) or "m")
    monkeypatch.setattr(closedloop.training, "run_trained",
                        lambda c, p, d, **kw: runs.append((p.name, kw)) or _Result(p.name, 0.5,
                                                                                  0.5))
    monkeypatch.setattr(cr, "_loop_predictor",
                        lambda n, i, o=None: runs.append(("made", n, i, o)) or _Pred(n, False))
    results, _ = cr.run_all("cfg", 0.1)
    printed = capsys.readouterr().out.splitlines()
    assert list(results) == ["none", "linear", "arma", "nn-paper", "oracle", "arma-aic"]
    assert runs[0] == ("made", "none", None, None)
    assert runs[1] == ("none", {"seed": 0, "model": "m", "progress": False, "budget_every": 5})
    assert len(printed) == 6 and built == ["cfg"]
    assert printed[0].startswith("[paper_figures]   none: SR peak 0.500")
    # a model given is used, none built
    runs.clear()
    built.clear()
    cr.run_all("cfg", 0.1, names=("none",), model="given", log=lambda s: None)
    assert built == [] and runs[1][1]["model"] == "given"


def _budget():
    return types.SimpleNamespace(directions=[[0.0, 0.0]], fitting=[0.25], aliasing=[0.125],
                                 temporal=[0.0625], noise=[0.03125], measured=[0.5])


def test_summarize():
    results = {"none": _Result("none", 0.5, 0.75, budget=_budget()),
               "arma": _Result("arma", 0.625, 0.875)}
    runs = cr.summarize(results, duration=1, timings={"arma": (1.5, 2.5)}, quick=True,
                        notes={"k": 1})
    assert (runs.config_name, runs.seed, runs.duration, runs.field_size, runs.wavelength) == (
        "table1", 4, 1.0, 60.0, 5e-7)
    assert type(runs.duration) is float and type(runs.field_size) is float
    assert runs.quick is True and runs.notes == {"k": 1}
    assert list(runs.budget) == ["directions", "fitting", "aliasing", "temporal", "noise",
                                 "measured"]
    assert runs.budget["temporal"].tolist() == [0.0625]
    assert isinstance(runs.budget["fitting"], np.ndarray)
    a = runs.runs["arma"]
    assert (a.name, a.summary["strehl_peak_mean"], a.closure_index, a.fov_diameter) == (
        "arma", 0.625, 1, 0.875)
    assert type(a.closure_index) is int and type(a.fov_diameter) is float
    # the one averaging window of the result, kept as an int beside the closure
    assert a.averaging_start == 2 and type(a.averaging_start) is int and a.window_start == 2
    assert results["arma"].thresholds == [0.3]            # the paper's SR > 0.3
    assert a.times.tolist() == [0.001, 0.002, 0.003] and isinstance(a.times, np.ndarray)
    assert a.strehl_peak.tolist() == [0.25, 0.625, 0.625]
    assert isinstance(a.strehl_peak, np.ndarray)
    assert a.spectrum_freqs.tolist() == [0.0, 500.0] and a.spectrum_psd.tolist() == [1.0, 2.0]
    assert isinstance(a.spectrum_freqs, np.ndarray) and isinstance(a.spectrum_psd, np.ndarray)
    assert a.strehl_map.tolist() == [[0.625]]
    assert (a.train_seconds, a.run_seconds) == (1.5, 2.5)
    assert (runs.runs["none"].train_seconds, runs.runs["none"].run_seconds) == (0.0, 0.0)
    # without a budget or timings
    results["none"].budget = None
    runs = cr.summarize(results, duration=0.5)
    assert runs.budget == {} and runs.quick is False and runs.notes == {}
    assert runs.runs["arma"].run_seconds == 0.0


@pytest.mark.parametrize(("quick", "names", "notes"), [
    (False, cr.PAPER_PREDICTORS + cr.EXTRA_PREDICTORS, {}),
    (True, cr.PAPER_PREDICTORS + cr.EXTRA_PREDICTORS, {"nn_max_iter": 50,
                                                        "arma_max_order": 3}),
    (True, ("none", "nn"), {"nn_max_iter": 50}),
    (True, ("none", "arma-aic"), {"arma_max_order": 3}),
    (True, ("none", "arma"), {}),
])
def test_compute_settings(monkeypatch, quick, names, notes):
    calls = []
    monkeypatch.setattr(cr, "default_config", lambda: "full")
    monkeypatch.setattr(cr, "quick_config", lambda: "quick")
    monkeypatch.setattr(cr, "run_all", lambda *a, **k: calls.append((a, k)) or ("R", "T"))
    monkeypatch.setattr(cr, "summarize", lambda *a, **k: calls.append((a, k)) or "S")
    assert cr.compute(quick=quick, names=names, seed=6, budget_every=9, progress=None,
                      log="L") == "S"
    (args, kw), (sargs, skw) = calls
    assert args == ("quick" if quick else "full", 0.2 if quick else 0.5)
    assert kw == {"seed": 6, "names": names, "budget_every": 9,
                  "nn_max_iter": 50 if quick else None,
                  "arma_max_order": 3 if quick else None, "progress": None, "log": "L"}
    assert sargs == ("R",)
    assert skw == {"duration": 0.2 if quick else 0.5, "timings": "T", "quick": quick,
                   "notes": notes}


def test_compute_defaults_and_given_config(monkeypatch):
    calls = []
    monkeypatch.setattr(cr, "run_all", lambda *a, **k: calls.append((a, k)) or ({}, {}))
    monkeypatch.setattr(cr, "summarize", lambda *a, **k: calls.append((a, k)))
    cr.compute(config="mine", duration=0.125)
    (args, kw), (_, skw) = calls
    assert args == ("mine", 0.125)
    assert kw == {"seed": 0, "names": cr.PAPER_PREDICTORS + cr.EXTRA_PREDICTORS,
                  "budget_every": 5, "nn_max_iter": None, "arma_max_order": None,
                  "progress": False, "log": print}
    assert skw["duration"] == 0.125 and skw["quick"] is False


def _section_runs(quick, notes):
    none = cr.PredictorRun(name="none", summary={"strehl_peak_mean": 0.5,
                                                 "steps_per_second": 250.4},
                           times=np.arange(1, 101) * 1e-3, strehl_peak=np.zeros(100),
                           closure_index=1, spectrum_freqs=np.zeros(1),
                           spectrum_psd=np.zeros(1), strehl_map=np.zeros((1, 1)),
                           fov_diameter=0.5, train_seconds=0.0, run_seconds=12.25)
    arma = cr.PredictorRun(name="arma", summary={"strehl_peak_mean": 0.5,
                                                 "steps_per_second": 99.6},
                           times=np.arange(1, 101) * 1e-3, strehl_peak=np.zeros(100),
                           closure_index=1, spectrum_freqs=np.zeros(1),
                           spectrum_psd=np.zeros(1), strehl_map=np.zeros((1, 1)),
                           fov_diameter=0.5, train_seconds=1.5, run_seconds=30.0)
    return cr.ClosedLoopRuns(config_name="table1", seed=7, duration=0.1, field_size=60.0,
                             wavelength=5e-7, runs={"none": none, "arma": arma}, budget={},
                             quick=quick, notes=notes)


SECTION = """## Closed-loop runs of Figures 2-4

`closedloop` preset `table1` (the paper's Table 1 with the documented
defaults of `closedloop/presets.py`), seed 7, 0.1 s
(100 frames) per run, one `LoopModel` and one atmosphere for every
predictor; ARMA and NN trained on the POL of the no-prediction run after its loop closure
and after 15 ms, as in the paper. The no-prediction run also estimates its error budget.
Total 43 s.{quick}

| predictor | training [s] | loop [s] | steps/s |
|---|---|---|---|
| no prediction | 0.0 | 12.2 | 250 |
| ARMA(2,3) | 1.5 | 30.0 | 100 |
"""


@pytest.mark.parametrize(("quick", "notes", "text"), [
    (False, {"nn_max_iter": 50}, ""),
    (True, {}, " **Quick settings** (`--quick`): a 5x5 field grid and a short run: the "
               "numbers below are not the full run's."),
    (True, {"nn_max_iter": 50, "arma_max_order": 3},
     " **Quick settings** (`--quick`): a 5x5 field grid and a short run; the neural nets "
     "trained for 50 iterations; ARMA with AIC orders searched p, q <= 3: the numbers below "
     "are not the full run's."),
    (True, {"arma_max_order": 2},
     " **Quick settings** (`--quick`): a 5x5 field grid and a short run; ARMA with AIC "
     "orders searched p, q <= 2: the numbers below are not the full run's."),
])
def test_report_section_word_for_word(quick, notes, text):
    assert cr.report_section(_section_runs(quick, notes), 42.6) == SECTION.format(quick=text)


def test_budget_sentence_without_a_budget_or_a_matching_grid():
    runs = _section_runs(False, {})
    assert cr.budget_sentence(runs) == ("(no error budget was estimated for this run)", {})
    # budget directions that are not the science grid's (3 against a 2 x 2 map): the
    # first direction, not the map's best cell
    smap = np.array([[0.1, 0.2], [0.4, 0.3]])
    none = cr.PredictorRun(**{**runs.runs["none"].__dict__, "strehl_map": smap})
    b = {"directions": np.array([[-5.0, 0.0], [0.0, 0.0], [5.0, 0.0]]),
         "fitting": np.array([0.25, 0.5, 0.5]), "aliasing": np.array([0.125, 0.5, 0.5]),
         "temporal": np.array([0.125, 0.5, 0.5]), "noise": np.array([0.0, 0.5, 0.5]),
         "measured": np.array([0.5, 1.0, 1.0])}
    other = cr.ClosedLoopRuns(**{**runs.__dict__, "runs": {"none": none}, "budget": b})
    _, nums = cr.budget_sentence(other)
    assert nums["direction"] == (-5.0, 0.0) and nums["temporal"] == 0.125
    # the science grid's 4 directions: the map's best cell (index 2)
    b4 = {k: np.append(v, v[-1:], axis=0) for k, v in b.items()}
    b4["temporal"] = np.array([0.125, 0.5, 0.25, 0.5])
    grid = cr.ClosedLoopRuns(**{**runs.__dict__, "runs": {"none": none}, "budget": b4})
    assert cr.budget_sentence(grid)[1]["temporal"] == 0.25
