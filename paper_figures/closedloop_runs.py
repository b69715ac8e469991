"""The closed-loop runs that Figures 2, 3 and 4 share: one atmosphere, every predictor.

The paper (Section 3.4) runs its LOST MCAO simulation of Table 1 four times on the same
conditions: without prediction, with the linear predictor, the ARMA and the neural net.
:func:`run_all` does the same with ``closedloop`` (one :class:`closedloop.LoopModel`, one
seed, one duration for every run), plus the ``oracle`` (the true future POL: the bound
no predictor can beat) and our best own predictor that trains on one run (``arma-aic``,
ARMA with AIC-chosen orders per mode; the VAR(4) on all 184 modes would need 7364
training frames under modalinfo's minimum-samples rule). Predictors that need training
are fitted on the no-prediction run after its loop closure and after 15 ms, as the paper
did (:func:`closedloop.run_trained`).
The no-prediction run also estimates the error budget (``budget_every``).

:func:`summarize` reduces the :class:`closedloop.SimulationResult` of each run to the
numbers the figures draw (:class:`ClosedLoopRuns`); :func:`compute` does both.
``python -m paper_figures`` calls :func:`compute` once and hands the result to the three
figure modules.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = ["PAPER_PREDICTORS", "EXTRA_PREDICTORS", "LABELS", "STYLES", "PredictorRun",
           "ClosedLoopRuns", "default_config", "quick_config", "run_all", "summarize",
           "compute", "DEFAULT_DURATION", "QUICK_DURATION"]

#: the paper's four runs (Section 3.4) and our two extra lines
PAPER_PREDICTORS = ("none", "linear", "arma", "nn-paper")
EXTRA_PREDICTORS = ("oracle", "arma-aic")

#: simulated time of the default run [s]: 500 frames of table1 (the loop closes in
#: ~30 ms), about 4-6 minutes on an idle 2-core machine with the paper's NN
DEFAULT_DURATION = 0.5
#: ``--quick``: 200 frames on a 5x5 field grid (ARMA with AIC orders needs 160 training
#: frames after 15 ms)
QUICK_DURATION = 0.2
#: ``--quick`` trains the paper's NN with this many L-BFGS iterations (default 500)
QUICK_NN_MAX_ITER = 50
#: ``--quick``: ``arma-aic`` searches p, q <= this (default 5), so still the paper's (2, 3):
#: the AIC fit of 184 modes is 12 s of CPU instead of 59 s (16 orders, not 36, and no
#: large ones; measured on 185 frames of an ARMA(1,1) series)
QUICK_ARMA_MAX_ORDER = 3

LABELS = {
    "none": "no prediction",
    "linear": "linear (a=2, b=-1)",
    "arma": "ARMA(2,3)",
    "nn-paper": "NN (paper, 10 patterns)",
    "nn": "NN 10-10-1, 2000 patterns",
    "oracle": "oracle (true future)",
    "multivariate": "multivariate VAR(4)",
    "arma-aic": "ARMA (AIC order)",
}

#: the paper's line styles (Figs. 2-3 captions: black continuous none, red dots linear,
#: magenta dashed NN, blue dash-dotted ARMA) and ours for the extra lines
STYLES = {
    "none": {"color": "k", "linestyle": "-"},
    "linear": {"color": "r", "linestyle": "none", "marker": ".", "markersize": 3},
    "nn-paper": {"color": "m", "linestyle": "--"},
    "nn": {"color": "purple", "linestyle": "--"},
    "arma": {"color": "b", "linestyle": "-."},
    "oracle": {"color": "0.55", "linestyle": ":"},
    "multivariate": {"color": "g", "linestyle": "-", "linewidth": 0.8},
    "arma-aic": {"color": "c", "linestyle": "-.", "linewidth": 0.8},
}


@dataclass(frozen=True)
class PredictorRun:
    """The numbers of one run that Figures 2-4 use.

    Attributes
    ----------
    name : str
        Predictor name (:data:`closedloop.control.predictors.NAMES`).
    summary : dict
        :meth:`closedloop.SimulationResult.summary`.
    times : (T,) ndarray
        End of each frame [s].
    strehl_peak : (T,) ndarray
        Maximum Strehl over the field per frame.
    closure_index : int
        First frame of the detected closed-loop steady state
        (:attr:`closedloop.SimulationResult.closure_index`; no steady state if the loop
        did not close: see ``averaging_start``).
    spectrum_freqs, spectrum_psd : ndarray
        Welch PSD of the SR peak from ``averaging_start`` [Hz], [1/Hz].
    strehl_map : (n, n) ndarray
        Time-averaged SR from ``averaging_start`` on the field grid (y rows, x columns).
    fov_diameter : float
        Equivalent diameter of the field with SR > 0.3 [arcmin].
    train_seconds, run_seconds : float
        Wall time of the training and of the loop [s].
    averaging_start : int or None
        First frame of the run's averages
        (:attr:`closedloop.SimulationResult.averaging_start`: the closure if the loop
        closed, else the second half; the spectrum, the map and ``summary`` use it).
        None (a run built by hand) reads as ``closure_index``.
    """

    name: str
    summary: dict
    times: np.ndarray
    strehl_peak: np.ndarray
    closure_index: int
    spectrum_freqs: np.ndarray
    spectrum_psd: np.ndarray
    strehl_map: np.ndarray
    fov_diameter: float
    train_seconds: float = 0.0
    run_seconds: float = 0.0
    averaging_start: int | None = None

    @property
    def label(self) -> str:
        """Legend label of the predictor."""
        return LABELS.get(self.name, self.name)

    @property
    def window_start(self) -> int:
        """First frame of the run's averages (``averaging_start``; if None, ``closure_index``)."""
        return self.closure_index if self.averaging_start is None else self.averaging_start

    @property
    def loop_status(self) -> str:
        """Say whether the loop closed: ``summary["loop_status"]`` ("closed", "did not ...").

        A summary built by hand without it reads as "closed", as ``averaging_start`` None.
        """
        return str(self.summary.get("loop_status", "closed"))

    @property
    def closed(self) -> bool:
        """True if the loop closed: ``closure_index`` is then the start of its averages."""
        return self.loop_status == "closed"

    @property
    def peak_mean(self) -> float:
        """Mean SR peak after closure."""
        return float(self.summary["strehl_peak_mean"])


@dataclass(frozen=True)
class ClosedLoopRuns:
    """Every run of one atmosphere, reduced to numbers (see :func:`summarize`).

    Attributes
    ----------
    config_name : str
    seed : int
    duration : float
        [s].
    field_size : float
        Side of the square science field [arcsec].
    wavelength : float
        Science wavelength [m].
    runs : dict of str -> PredictorRun
        In the order they were run (``"none"`` first).
    budget : dict of str -> ndarray
        Error budget of the no-prediction run per direction [rad^2 at the science
        wavelength]: ``directions``, ``fitting``, ``aliasing``, ``temporal``, ``noise``,
        ``measured``.
    quick : bool
        Made with the reduced ``--quick`` settings.
    notes : dict
        Anything the report should state about the settings (e.g. the NN's iterations).
    """

    config_name: str
    seed: int
    duration: float
    field_size: float
    wavelength: float
    runs: dict
    budget: dict
    quick: bool = False
    notes: dict = field(default_factory=dict)

    def get(self, name: str) -> PredictorRun | None:
        """Return the run of predictor ``name`` (None if it was not run)."""
        return self.runs.get(name)

    @property
    def best_direction(self) -> int:
        """Index of the direction with the highest time-averaged SR without prediction."""
        return int(np.argmax(self.runs["none"].strehl_map.ravel()))


def default_config():
    """table1, the paper's Table 1 with closedloop's documented defaults."""
    from closedloop import presets

    return presets.get("table1")


def quick_config():
    """table1 on a 5x5 field grid (``--quick``)."""
    from closedloop.config import FieldConfig

    cfg = default_config()
    return cfg.replace(field=FieldConfig(size=cfg.field.size, n_points=5))


def _loop_predictor(name: str, nn_max_iter: int | None, arma_max_order: int | None = None):
    from closedloop.control.predictors import LoopPredictor

    p = LoopPredictor.from_name(name)
    # a fresh forecaster of this run's own: its settings can be changed in place
    if nn_max_iter is not None and name in ("nn", "nn-paper"):
        p.predictor.max_iter = int(nn_max_iter)
    if arma_max_order is not None and name == "arma-aic":
        p.predictor.max_order = int(arma_max_order)
    return p


def run_all(config, duration: float, *, seed: int = 0,
            names: tuple[str, ...] = PAPER_PREDICTORS + EXTRA_PREDICTORS,
            budget_every: int | None = 5, nn_max_iter: int | None = None,
            arma_max_order: int | None = None, progress: bool | None = False,
            log=print, model=None) -> tuple[dict, dict]:
    """Run every predictor of ``names`` on one atmosphere; return ``(results, timings)``.

    Parameters
    ----------
    config : closedloop.SimulationConfig
    duration : float
        Simulated time of every run [s].
    seed : int
        The one atmosphere (and WFS noise) of all runs.
    names : tuple of str
        Predictor names; ``"none"`` is always run first (the others train on it).
    budget_every : int or None
        Error budget of the no-prediction run every this many frames (None: none).
    nn_max_iter : int or None
        Override of the neural nets' training iterations (``--quick``).
    arma_max_order : int or None
        Override of the largest p and q ``arma-aic`` searches (``--quick``).
    progress : bool or None
        tqdm bars of the loops.
    log : callable
        Receives one progress line per run.
    model : closedloop.LoopModel, optional
        The config's model, if already built (else built here).

    Returns
    -------
    results : dict of str -> closedloop.SimulationResult
    timings : dict of str -> (train_seconds, run_seconds)
    """
    from closedloop.simulation import LoopModel
    from closedloop.training import run_trained

    names = ("none", *[n for n in names if n != "none"])
    model = LoopModel(config) if model is None else model
    results: dict = {}
    timings: dict = {}
    for name in names:
        t0 = time.perf_counter()
        predictor = _loop_predictor(name, nn_max_iter, arma_max_order)
        if predictor.needs_training:  # here, not in run_trained, to time it apart
            predictor = predictor.trained(results["none"])
        t1 = time.perf_counter()
        results[name] = run_trained(config, predictor, duration, seed=seed, model=model,
                                    progress=progress,
                                    budget_every=budget_every if name == "none" else None)
        t2 = time.perf_counter()
        timings[name] = (t1 - t0, t2 - t1)
        r, start = results[name], results["none"].averaging_start
        s = r.summary()
        # the report's window (Figure 2): every run from the no-prediction run's closure;
        # the FoV is the run's own window (its summary), as labelled
        log(f"[paper_figures]   {name}: SR peak {np.mean(r.strehl_peak[start:]):.3f} (mean "
            f"from {r.times[start] * 1e3:.0f} ms, the no-prediction run's closure), corrected "
            f"FoV d = {s['corrected_fov_diameter_arcmin']:.2f}' (from its own closure at "
            f"{r.times[r.averaging_start] * 1e3:.0f} ms) (train {t1 - t0:.1f} s, "
            f"loop {t2 - t1:.1f} s)")
    return results, timings


def summarize(results: dict, *, duration: float, timings: dict | None = None,
              quick: bool = False, notes: dict | None = None) -> ClosedLoopRuns:
    """Reduce the :class:`closedloop.SimulationResult` of each run to :class:`ClosedLoopRuns`."""
    timings = timings or {}
    runs = {}
    for name, r in results.items():
        freqs, psd = r.strehl_peak_spectrum()
        runs[name] = PredictorRun(
            name=name, summary=r.summary(), times=np.asarray(r.times),
            strehl_peak=np.asarray(r.strehl_peak), closure_index=int(r.closure_index),
            spectrum_freqs=np.asarray(freqs), spectrum_psd=np.asarray(psd),
            strehl_map=r.strehl_map(), fov_diameter=float(r.corrected_fov_diameter(0.3)),
            train_seconds=timings.get(name, (0.0, 0.0))[0],
            run_seconds=timings.get(name, (0.0, 0.0))[1],
            averaging_start=int(r.averaging_start))
    ref = results["none"]
    b = ref.budget
    budget: dict[str, Any] = {}
    if b is not None:
        budget = {k: np.asarray(getattr(b, k)) for k in
                  ("directions", "fitting", "aliasing", "temporal", "noise", "measured")}
    cfg = ref.config
    return ClosedLoopRuns(config_name=cfg.name, seed=ref.seed, duration=float(duration),
                          field_size=float(cfg.field.size), wavelength=float(cfg.wavelength),
                          runs=runs, budget=budget, quick=quick, notes=dict(notes or {}))


def compute(*, quick: bool = False, config=None, duration: float | None = None, seed: int = 0,
            names: tuple[str, ...] = PAPER_PREDICTORS + EXTRA_PREDICTORS,
            budget_every: int | None = 5, progress: bool | None = False,
            log=print) -> ClosedLoopRuns:
    """Run and summarise (defaults: table1 for 0.5 s; ``quick``: 5x5 field, 0.2 s).

    ``quick`` also trains the neural nets for ``QUICK_NN_MAX_ITER`` iterations and lets
    ``arma-aic`` search p, q <= ``QUICK_ARMA_MAX_ORDER``: a smoke run, numbers not the
    paper's.
    """
    if config is None:
        config = quick_config() if quick else default_config()
    if duration is None:
        duration = QUICK_DURATION if quick else DEFAULT_DURATION
    nn_max_iter = QUICK_NN_MAX_ITER if quick else None
    arma_max_order = QUICK_ARMA_MAX_ORDER if quick else None
    results, timings = run_all(config, duration, seed=seed, names=names,
                               budget_every=budget_every, nn_max_iter=nn_max_iter,
                               arma_max_order=arma_max_order, progress=progress, log=log)
    notes = {}
    if nn_max_iter is not None and any(n in ("nn", "nn-paper") for n in names):
        notes["nn_max_iter"] = nn_max_iter
    if arma_max_order is not None and "arma-aic" in names:
        notes["arma_max_order"] = arma_max_order
    return summarize(results, duration=duration, timings=timings, quick=quick, notes=notes)


def budget_sentence(runs: ClosedLoopRuns) -> tuple[str, dict]:
    """Say what the no-prediction error budget lets a predictor buy, in words and numbers.

    At the direction where the no-prediction SR map peaks, removing the whole temporal
    error (what a perfect predictor could at most do; noise and the other terms stay)
    would raise the Marechal SR from ``exp(-measured)`` to ``exp(-(measured - temporal))``.
    """
    b = runs.budget
    if not b:
        return ("(no error budget was estimated for this run)", {})
    dirs = b["directions"]
    none_map = runs.runs["none"].strehl_map.ravel()
    # the budget directions are the science grid's (closedloop.budget): pick the best one
    k = int(np.argmax(none_map)) if len(dirs) == none_map.size else 0
    nums = {
        "direction": tuple(float(v) for v in dirs[k]),
        "fitting": float(b["fitting"][k]), "aliasing": float(b["aliasing"][k]),
        "temporal": float(b["temporal"][k]), "noise": float(b["noise"][k]),
        "measured": float(b["measured"][k]),
        "temporal_mean": float(np.mean(b["temporal"])),
        "fit_alias_mean": float(np.mean(b["fitting"] + b["aliasing"])),
    }
    nums["sr_now"] = float(np.exp(-nums["measured"]))
    nums["sr_bound"] = float(np.exp(-(nums["measured"] - nums["temporal"])))
    nums["temporal_share"] = nums["temporal"] / nums["measured"]
    x, y = nums["direction"]
    text = (
        f"The no-prediction run's own error budget (rad^2 at "
        f"{runs.wavelength * 1e9:.0f} nm, after closure) at ({x:.0f}\", {y:.0f}\"), the "
        f"direction of its best SR: fitting {nums['fitting']:.3f}, aliasing "
        f"{nums['aliasing']:.3f}, temporal {nums['temporal']:.3f}, noise {nums['noise']:.3f} "
        f"(measured residual {nums['measured']:.3f}). The temporal term, the only one a "
        f"predictor acts on, is {nums['temporal_share']:.1%} of the residual there (field "
        f"mean {nums['temporal_mean']:.3f} against {nums['fit_alias_mean']:.3f} of fitting + "
        f"aliasing). Removing it entirely would raise the Marechal SR there from "
        f"{nums['sr_now']:.3f} to at most {nums['sr_bound']:.3f}.")
    return text, nums


def report_section(runs: ClosedLoopRuns, elapsed: float) -> str:
    """Return the report's paragraph on the shared runs (settings, timings)."""
    none = runs.runs["none"]
    rows = ["| predictor | training [s] | loop [s] | steps/s |", "|---|---|---|---|"]
    for r in runs.runs.values():
        rows.append(f"| {r.label} | {r.train_seconds:.1f} | {r.run_seconds:.1f} | "
                    f"{r.summary['steps_per_second']:.0f} |")
    quick = (" **Quick settings** (`--quick`): a 5x5 field grid and a short run"
             + (f"; the neural nets trained for {runs.notes['nn_max_iter']} iterations"
                if "nn_max_iter" in runs.notes else "")
             + (f"; ARMA with AIC orders searched p, q <= {runs.notes['arma_max_order']}"
                if "arma_max_order" in runs.notes else "")
             + ": the numbers below are not the full run's." if runs.quick else "")
    return f"""## Closed-loop runs of Figures 2-4

`closedloop` preset `{runs.config_name}` (the paper's Table 1 with the documented
defaults of `closedloop/presets.py`), seed {runs.seed}, {runs.duration:g} s
({none.times.size} frames) per run, one `LoopModel` and one atmosphere for every
predictor; ARMA and NN trained on the POL of the no-prediction run after its loop closure
and after 15 ms, as in the paper. The no-prediction run also estimates its error budget.
Total {elapsed:.0f} s.{quick}

{chr(10).join(rows)}
"""
