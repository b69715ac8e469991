"""Figure 7 (an extension, not in the paper): the comparison of Figures 2-4 with solar sensing.

The paper's premise is solar: on granulation "wavefront sensing requires real-time
correlation techniques which, in addition to the larger integration time needed,
increase the time delay" (Stangalini et al., Introduction and Conclusions), and that is
why prediction should pay. Figures 2-4 answer the question with a geometric
Shack-Hartmann (``table1``); this figure asks it again with the correlating
Shack-Hartmann on granulation (``closedloop`` preset ``table1-solar``: table1 with both
WFSs ``kind = "correlating"``, noise from the photon budget and the scene's contrast, the
delay of a solar real-time computer): SR peak vs time, corrected field of view and the
error budget (with its noise term) for none / linear / ARMA / NN / oracle, beside
table1's numbers from the same run of ``python -m paper_figures``, and a sensitivity
panel (photon flux, granulation contrast, subaperture size, compute latency;
:mod:`closedloop.studies.solar`).

The runs reuse :func:`paper_figures.closedloop_runs.run_all` (one atmosphere, the same
seed, duration, field grid and NN iterations as the table1 runs; predictors trained on
the no-prediction run as in the paper) and the numbers of Figures 2 and 4
(:func:`paper_figures.fig2_sr_peak.compute`, :func:`paper_figures.fig4_sr_maps.compute`,
:func:`paper_figures.closedloop_runs.budget_sentence`). ``NEEDS_RUNS = True``: the
figure receives the table1 runs of Figures 2-4 and compares with them.

Steps: :func:`compute` (a :class:`Figure7`), :func:`plot` (PNG, PDF, JSON),
:func:`report`, :func:`table_rows`, :func:`make`, :func:`main`.

Usage::

    python -m paper_figures --only 7 [--quick]
    python -m paper_figures.fig7_solar [--out DIR] [--overwrite] [--quick]
"""

from __future__ import annotations

import json
import math
import os
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from modalinfo.common.cli import Parser
from modalinfo.common.files import quoted
from paper_figures._common import markdown_table, save_png_pdf, write_figure
from paper_figures.closedloop_runs import LABELS, STYLES, ClosedLoopRuns

FIGURE_NAME = "fig7_solar.png"
PDF_NAME = "fig7_solar.pdf"
JSON_NAME = "fig7_solar.json"
NEEDS_RUNS = True
PRESET = "table1-solar"
#: the paper's four runs and the oracle (the bound of a perfect forecast)
PREDICTORS = ("none", "linear", "arma", "nn-paper", "oracle")
#: ``--quick``: without the paper's NN, whose training is most of the quick figure's time
#: (117 of 210 s measured at a load average of 10)
QUICK_PREDICTORS = ("none", "linear", "arma", "oracle")
#: predictors of the sensitivity panel
SENSITIVITY_PREDICTORS = ("none", "arma")
#: one value of the photon, contrast and latency knobs (each costs a model and two runs;
#: the full table, with the subaperture size: ``python -m closedloop.studies.solar``)
SENSITIVITY_VALUES = {"signal": (150.0,), "contrast": (0.03,), "rtc": ("workstation",)}
#: ``--quick``: the photon flux only (each knob value costs a model and two runs)
QUICK_SENSITIVITY_VALUES = {"signal": (150.0,)}
#: error budget of the sensitivity runs every this many frames (its noise term does not
#: depend on it; the comparison runs probe every 5 frames like the table1 runs)
SENSITIVITY_BUDGET_EVERY = 25
#: the RTC presets whose latency the report states
REPORT_RTCS = ("fpga", "workstation")


@dataclass(frozen=True)
class Figure7:
    """Figure 7's numbers.

    Attributes
    ----------
    solar : ClosedLoopRuns
        The ``table1-solar`` runs (every predictor of :data:`PREDICTORS`).
    table1 : ClosedLoopRuns
        The table1 runs of Figures 2-4 (same seed, duration, field grid).
    numbers : dict
        Everything the report and the comparison table quote (the JSON's content):
        ``peak_mean``, ``fov``, ``budget`` per set (``"solar"``, ``"table1"``),
        ``latency`` per RTC, ``sensitivity`` rows.
    sensitivity : closedloop.studies.solar.SolarSensitivity
    quick : bool
    elapsed : float
        Time :func:`compute` took [s].
    """

    solar: ClosedLoopRuns
    table1: ClosedLoopRuns
    numbers: dict
    sensitivity: Any
    quick: bool
    elapsed: float


def solar_config(table1_runs: ClosedLoopRuns | None = None):
    """``table1-solar`` on the field grid of the table1 runs (5x5 with ``--quick``)."""
    from closedloop import presets
    from closedloop.config import FieldConfig

    cfg = presets.get(PRESET)
    if table1_runs is not None:
        n = table1_runs.runs["none"].strehl_map.shape[0]
        cfg = cfg.replace(field=FieldConfig(size=cfg.field.size, n_points=n))
    return cfg


def _set_numbers(runs: ClosedLoopRuns) -> dict:
    """SR peak (Figure 2's window), corrected FoV (Figure 4) and budget of one set of runs."""
    from paper_figures import fig2_sr_peak, fig4_sr_maps
    from paper_figures.closedloop_runs import budget_sentence

    fig2 = fig2_sr_peak.compute(runs)
    fig4 = fig4_sr_maps.compute(runs)
    _, budget = budget_sentence(runs)
    none = runs.runs["none"]
    return {
        "config": runs.config_name,
        "peak_mean": {k: v for k, v in fig2.peak_mean.items() if k in PREDICTORS},
        "fov": {k: v for k, v in fig4.diameter.items() if k in PREDICTORS},
        "closure_ms": float(none.times[none.closure_index] * 1e3),
        "budget": budget,
    }


def compute(runs: ClosedLoopRuns, *, config=None, sensitivity_values: dict | None = None,
            predictors: tuple[str, ...] | None = None,
            sensitivity_predictors: tuple[str, ...] = SENSITIVITY_PREDICTORS,
            log=print) -> Figure7:
    """Run ``table1-solar`` like the table1 runs, its sensitivity panel, and the numbers.

    Parameters
    ----------
    runs : ClosedLoopRuns
        The table1 runs of Figures 2-4 (their seed, duration, grid and ``quick`` are used).
    config : SimulationConfig, optional
        The solar config (default :func:`solar_config`).
    sensitivity_values : dict, optional
        Knob -> values of the sensitivity panel (default :data:`SENSITIVITY_VALUES`,
        quick :data:`QUICK_SENSITIVITY_VALUES`).
    predictors, sensitivity_predictors : tuple of str
        Predictors of the comparison (default :data:`PREDICTORS`, quick
        :data:`QUICK_PREDICTORS`) and of the sensitivity panel (default
        :data:`SENSITIVITY_PREDICTORS`, a subset of ``predictors``).
    log : callable
        Progress lines.
    """
    from closedloop.simulation import LoopModel
    from closedloop.studies.solar import (
        KNOB_LABELS,
        correlating_compute_time,
        solar_latency,
        solar_sensitivity,
    )
    from paper_figures.closedloop_runs import QUICK_NN_MAX_ITER, run_all, summarize

    start = time.perf_counter()
    cfg = solar_config(runs) if config is None else config
    if predictors is None:
        predictors = QUICK_PREDICTORS if runs.quick else PREDICTORS
    missing = [p for p in sensitivity_predictors if p not in predictors]
    if missing:
        raise ValueError(f"`sensitivity_predictors` must be among `predictors` "
                         f"{tuple(predictors)}; got {missing}.")
    nn_iter = QUICK_NN_MAX_ITER if runs.quick else None
    model = LoopModel(cfg)
    results, timings = run_all(cfg, runs.duration, seed=runs.seed, names=tuple(predictors),
                               budget_every=5, nn_max_iter=nn_iter, log=log, model=model)
    notes = {"nn_max_iter": nn_iter} if nn_iter is not None else {}
    solar = summarize(results, duration=runs.duration, timings=timings, quick=runs.quick,
                      notes=notes)
    compute_time = correlating_compute_time(cfg, model)  # timed once, for every RTC
    load = os.getloadavg()[0]  # the timing grows with the machine's load: record it
    latency = {}
    for rtc in REPORT_RTCS:
        try:
            latency[rtc] = solar_latency(cfg, rtc=rtc, compute_time=compute_time)
        except ValueError:  # unstable at the config's gain: reported as such
            latency[rtc] = (compute_time, float("nan"))
    if sensitivity_values is None:
        sensitivity_values = QUICK_SENSITIVITY_VALUES if runs.quick else SENSITIVITY_VALUES
    study = solar_sensitivity(cfg, values=sensitivity_values,
                              predictors=tuple(sensitivity_predictors),
                              duration=runs.duration, seed=runs.seed, model=model,
                              latency=latency, budget_every=SENSITIVITY_BUDGET_EVERY,
                              base_results={k: results[k] for k in sensitivity_predictors},
                              log=log)
    numbers = {
        "seed": runs.seed, "duration": runs.duration, "quick": runs.quick,
        "wavelength": solar.wavelength,
        "solar": _set_numbers(solar), "table1": _set_numbers(runs),
        "delay_ms": {"solar": float(cfg.loop.delay * 1e3),
                     "table1": float(_preset_delay(runs) * 1e3)},
        "latency": {k: {"compute_ms": c * 1e3, "delay_ms": d * 1e3}
                    for k, (c, d) in study.latency.items()},
        "load_average": float(load),
        "sensitivity": [dict(r) for r in study.rows],
        "knob_labels": dict(KNOB_LABELS),
    }
    elapsed = time.perf_counter() - start
    numbers["elapsed_s"] = elapsed  # the figure's own cost (not the table1 runs')
    return Figure7(solar=solar, table1=runs, numbers=numbers, sensitivity=study,
                   quick=runs.quick, elapsed=elapsed)


def _preset_delay(runs: ClosedLoopRuns) -> float:
    """Loop delay of the table1 runs [s] (the preset's, as :mod:`closedloop_runs` runs it)."""
    from paper_figures.closedloop_runs import default_config

    return float(default_config().loop.delay)


def _json_safe(obj):
    """NaN -> None, recursively (JSON has no NaN)."""
    if isinstance(obj, dict):
        return {str(k): _json_safe(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_json_safe(v) for v in obj]
    if isinstance(obj, (float, np.floating)):
        return float(obj) if math.isfinite(obj) else None
    if isinstance(obj, np.integer):
        return int(obj)
    return obj


def _sens_pairs(numbers: dict) -> list[tuple[str, str]]:
    """``(knob, value)`` of the sensitivity runs in their order (base first)."""
    seen: list[tuple[str, str]] = []
    for r in numbers["sensitivity"]:
        key = (r["knob"], r["value"])
        if key not in seen:
            seen.append(key)
    return seen


def _sens(numbers: dict, knob: str, value: str, predictor: str) -> dict:
    return next(r for r in numbers["sensitivity"] if r["knob"] == knob
                and r["value"] == value and r["predictor"] == predictor)


def plot(fig7: Figure7, out_dir: Path) -> list[Path]:
    """Draw Figure 7 (PNG, PDF) and write its numbers (JSON) into ``out_dir``."""
    # a Figure of its own, no backend switch: the caller's backend stays as it was
    # (round 45 PART a, G15); Figure.savefig draws with Agg all the same
    from matplotlib.figure import Figure

    num = fig7.numbers
    sol, t1 = num["solar"], num["table1"]
    fig = Figure(figsize=(13, 9))
    axes = fig.subplots(2, 2)
    # (a) SR peak vs time, solar, with table1's no-prediction line for reference
    ax = axes[0, 0]
    for name, r in fig7.solar.runs.items():
        ax.plot(r.times * 1e3, r.strehl_peak, label=f"{r.label} ({sol['peak_mean'][name]:.3f})",
                **STYLES.get(name, {}))
    ref = fig7.table1.runs["none"]
    ax.plot(ref.times * 1e3, ref.strehl_peak, color="0.7", lw=0.8,
            label=f"table1 (geometric SH), no prediction ({t1['peak_mean']['none']:.3f})")
    ax.axvline(sol["closure_ms"], color="0.4", lw=0.8)
    ax.set_xlabel("time [ms]")
    ax.set_ylabel(f"SR peak over the field ({fig7.solar.wavelength * 1e9:.0f} nm)")
    ax.set_ylim(0, 1)
    ax.set_title(f"(a) {fig7.solar.config_name}: SR peak vs time (mean after closure)",
                 fontsize=9)
    ax.legend(fontsize=6)
    # (b) corrected FoV, solar beside table1
    ax = axes[0, 1]
    names = [n for n in PREDICTORS if n in sol["fov"]]
    x = np.arange(len(names))
    ax.bar(x - 0.2, [t1["fov"].get(n, np.nan) for n in names], 0.4, color="0.7",
           label="table1 (geometric SH)")
    ax.bar(x + 0.2, [sol["fov"][n] for n in names], 0.4, color="tab:orange",
           label=f"{fig7.solar.config_name} (correlating SH)")
    from paper_figures.fig4_sr_maps import PAPER_DIAMETER

    paper = [PAPER_DIAMETER.get(n, np.nan) for n in names]
    ax.plot(x, paper, "k*", ms=9, label="paper (Fig. 4)")
    ax.set_xticks(x, [LABELS.get(n, n) for n in names], rotation=20, fontsize=7)
    ax.set_ylabel("corrected FoV diameter d (SR > 0.3) [arcmin]")
    ax.set_title("(b) corrected field of view", fontsize=9)
    ax.legend(fontsize=7)
    # (c) error budget at each set's best direction (no prediction)
    ax = axes[1, 0]
    terms = ("fitting", "aliasing", "temporal", "noise")
    colors = ("tab:blue", "tab:green", "tab:red", "tab:purple")
    for i, b in enumerate((t1["budget"], sol["budget"])):
        bottom = 0.0
        for term, color in zip(terms, colors, strict=True):
            v = b.get(term, 0.0) if b else 0.0
            ax.bar(i, v, 0.5, bottom=bottom, color=color, label=term if i == 0 else None)
            bottom += v
        if b:
            ax.plot([i - 0.3, i + 0.3], [b["measured"]] * 2, "k-", lw=2,
                    label="measured residual" if i == 0 else None)
    ax.set_xticks([0, 1], [t1["config"], sol["config"]])
    ax.set_ylabel(f"rad^2 at {fig7.solar.wavelength * 1e9:.0f} nm (best direction, no "
                  "prediction)")
    ax.set_title("(c) error budget: what a predictor can act on (temporal)", fontsize=9)
    ax.legend(fontsize=7)
    # (d) sensitivity: SR peak per knob value, none and ARMA; noise on a twin axis
    ax = axes[1, 1]
    pairs = _sens_pairs(num)
    x = np.arange(len(pairs))
    for k, name in enumerate(fig7.sensitivity.predictors):
        ax.plot(x + 0.1 * k, [_sens(num, kn, v, name)["strehl_peak"] for kn, v in pairs],
                "o" if name == "none" else "x", color=STYLES.get(name, {}).get("color", "k"),
                label=f"SR peak, {LABELS.get(name, name)}")
    ax.set_xticks(x, ["base" if kn == "base" else f"{kn}\n{v}" for kn, v in pairs], fontsize=6)
    ax.set_ylabel("SR peak after closure")
    ax.set_ylim(0, None)
    ax.set_xlim(-0.5, len(pairs) - 0.5)
    tw = ax.twinx()
    tw.plot(x, [_sens(num, kn, v, "none").get("noise", np.nan) for kn, v in pairs], "s",
            color="tab:purple", ms=4, label="noise term (no prediction)")
    tw.set_ylabel("on-axis noise term [rad^2]", color="tab:purple")
    ax.legend(fontsize=7, loc="upper left")
    tw.legend(fontsize=7, loc="upper right")
    ax.set_title("(d) sensitivity, one knob at a time", fontsize=9)
    fig.suptitle(f"Figure 7 (extension, not in the paper): solar correlating sensing, "
                 f"seed {num['seed']}, {num['duration']:g} s"
                 + (" (quick)" if num["quick"] else ""), fontsize=10)
    fig.tight_layout()
    out_dir = Path(out_dir)
    paths = save_png_pdf(fig, out_dir, FIGURE_NAME, PDF_NAME)
    json_path = out_dir / JSON_NAME
    json_path.write_text(json.dumps(_json_safe(num), indent=1), encoding="utf-8")
    return [*paths, json_path]


def _f(v, fmt: str) -> str:
    return "n/a" if v is None or (isinstance(v, float) and not math.isfinite(v)) else \
        format(v, fmt)


def table_rows(fig7: Figure7 | dict) -> list[tuple[str, str, str, str]]:
    """``(quantity, paper, ours, why)`` rows, from the figure's numbers (or its JSON dict)."""
    from paper_figures.fig2_sr_peak import PAPER_SR_NONE, PAPER_SR_PREDICTED_MIN
    from paper_figures.fig4_sr_maps import PAPER_DIAMETER

    num = fig7.numbers if isinstance(fig7, Figure7) else fig7
    sol, t1 = num["solar"], num["table1"]
    name = sol["config"]
    sb, tb = sol["budget"] or {}, t1["budget"] or {}
    rows = []
    for p in PREDICTORS:
        if p not in sol["peak_mean"]:
            continue
        v, t = sol["peak_mean"][p], t1["peak_mean"].get(p)
        paper = (f"{PAPER_SR_NONE:g}" if p == "none" else
                 f"> {PAPER_SR_PREDICTED_MIN:g}" if p != "oracle" else "-")
        ratio = v / sol["peak_mean"]["none"]
        why = (f"x{ratio:.3f} over no prediction (table1 "
               f"x{t / t1['peak_mean']['none']:.3f})" if p != "none" and t is not None else
               f"noise term {_f(sb.get('noise'), '.4f')} rad^2 against table1's "
               f"{_f(tb.get('noise'), '.4f')}")
        rows.append((f"SR peak, {LABELS.get(p, p)}, {name} (extension)", paper,
                     f"{v:.3f} (table1 {_f(t, '.3f')})", why))
    for p in ("none", "arma"):
        if p in sol["fov"]:
            rows.append((f"corrected FoV d, {LABELS.get(p, p)}, {name} (extension)",
                         f"{PAPER_DIAMETER[p]:g}'", f"{sol['fov'][p]:.2f}' (table1 "
                         f"{_f(t1['fov'].get(p), '.2f')}')",
                         "d = 2 sqrt(A/pi) of the field with SR > 0.3 (Figure 4's definition)"))
    if sb:
        rows.append((f"error budget at the best direction, {name} (extension)",
                     "not published",
                     f"fitting {sb['fitting']:.3f} + aliasing {sb['aliasing']:.3f} + temporal "
                     f"{sb['temporal']:.3f} + noise {sb['noise']:.4f} rad^2 (measured "
                     f"{sb['measured']:.3f})",
                     f"table1: temporal {_f(tb.get('temporal'), '.3f')}, noise "
                     f"{_f(tb.get('noise'), '.4f')}; a predictor acts on the temporal term only"))
    for rtc, lat in num["latency"].items():
        c, d = lat["compute_ms"], lat["delay_ms"]
        rows.append((f"correlation latency, {rtc} RTC (extension)",
                     "\"increase the time delay\" (not quantified)",
                     f"{_f(c, '.2f')} ms of correlation on this machine -> delay "
                     + (f"{d:.3f} ms" if d is not None and math.isfinite(d) else
                        "beyond the stable loop"),
                     f"{name}'s preset delay is {num['delay_ms']['solar']:g} ms (table1 "
                     f"{num['delay_ms']['table1']:g} ms)"))
    return rows


def report(fig7: Figure7) -> str:
    """Figure 7's section of the report (Markdown)."""
    from closedloop.studies.solar import markdown

    num = fig7.numbers
    sol, t1 = num["solar"], num["table1"]
    sb, tb = sol["budget"] or {}, t1["budget"] or {}
    gains = ", ".join(f"{LABELS.get(p, p)} {sol['peak_mean'][p] - sol['peak_mean']['none']:+.3f}"
                      f" (table1 {t1['peak_mean'][p] - t1['peak_mean']['none']:+.3f})"
                      for p in PREDICTORS if p != "none" and p in sol["peak_mean"]
                      and p in t1["peak_mean"])
    room = ""
    if sb and tb:
        room = (f" At the best direction the temporal term is {sb['temporal']:.3f} rad^2 of a "
                f"{sb['measured']:.3f} rad^2 residual with solar sensing "
                f"({sb['temporal'] / sb['measured']:.1%}), against {tb['temporal']:.3f} of "
                f"{tb['measured']:.3f} ({tb['temporal'] / tb['measured']:.1%}) with table1's "
                f"geometric sensor; the noise term is {sb['noise']:.4f} against "
                f"{tb['noise']:.4f}. Removing the whole temporal term would raise the "
                f"Marechal SR there from {sb['sr_now']:.3f} to at most {sb['sr_bound']:.3f}.")
    best = max((p for p in sol["peak_mean"] if p != "none"),
               key=lambda p: sol["peak_mean"][p], default="none")
    gain = sol["peak_mean"][best] - sol["peak_mean"]["none"]
    verdict = (f"Prediction buys little with solar sensing too (best: {LABELS.get(best, best)}, "
               f"{gain:+.3f} in SR peak): the residual stays dominated by the terms no "
               "predictor touches."
               if gain < 0.05 else
               f"With solar sensing prediction has room: {LABELS.get(best, best)} gains "
               f"{gain:+.3f} in SR peak.")
    lat = "; ".join(f"{k}: {_f(v['compute_ms'], '.2f')} ms of correlation on this machine "
                    "-> delay " + (f"{v['delay_ms']:.3f} ms" if v["delay_ms"] is not None
                                   and math.isfinite(v["delay_ms"]) else "unstable")
                    for k, v in num["latency"].items())
    quick = (" **Quick settings** (`--quick`): short runs on a 5x5 grid, no NN, one "
             "sensitivity knob; the numbers are not the full run's." if fig7.quick else "")
    lat += (f" (1-minute load average {num['load_average']:.1f} on this machine's "
            f"{os.cpu_count()} cores when timed: the time grows with the load)")
    return f"""## Figure 7: Solar correlating sensing (extension, not in the paper)

![Figure 7]({FIGURE_NAME})

The comparison of Figures 2-4 on `{sol['config']}` (table1 with both WFSs a correlating
Shack-Hartmann on granulation: slopes are contrast-weighted Z-tilts, the noise follows
from the photon budget and the scene's contrast, the delay is
{num['delay_ms']['solar']:g} ms against table1's {num['delay_ms']['table1']:g} ms), seed
{num['seed']}, {num['duration']:g} s per run, the same field grid and training as the
table1 runs of Figures 2-4; means after the no-prediction run's closure
({sol['closure_ms']:.0f} ms; table1 {t1['closure_ms']:.0f} ms). Numbers in
`{JSON_NAME}`.{quick}

{markdown_table(table_rows(fig7))}

SR peak gained over no prediction: {gains}.{room} {verdict}

**Latency** (`closedloop.studies.solar.solar_latency`: the correlations of one frame
timed on this machine with the sensor's kernels, then `LatencyModel`'s readout +
compute / rtc_speed on the simulator's grid): {lat}.

**Sensitivity** (one knob at a time, no prediction and ARMA; SR means after each knob
value's no-prediction run's closure, the main table's window, so its "(base)" row is the
table's; FoV from each run's own closure, as the table's FoV column; on-axis budget
of the no-prediction run; `python -m closedloop.studies.solar` makes the full table):

{markdown(fig7.sensitivity)}
"""


def make(out_dir: Path, runs: ClosedLoopRuns) -> str:
    """Compute, draw and report Figure 7 from the table1 runs of Figures 2-4."""
    fig7 = compute(runs)
    plot(fig7, out_dir)
    return report(fig7)


def main(argv: list[str] | None = None) -> int:
    """Command line: the table1 runs, Figure 7, and its report section printed."""
    parser = Parser(prog="python -m paper_figures.fig7_solar",
                                     description="Figure 7: the comparison of Figures 2-4 "
                                                 "with solar correlating sensing.")
    parser.add_argument("--out", type=Path, default=Path("out"), help="output directory")
    parser.add_argument("--overwrite", action="store_true", help="replace an existing figure")
    parser.add_argument("--quick", action="store_true", help="short runs, 5x5 field grid")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    for name in (FIGURE_NAME, PDF_NAME, JSON_NAME):
        if (args.out / name).exists() and not args.overwrite:
            sys.stderr.write(f"{parser.prog}: error: {quoted(args.out / name)} exists; pass "
                             "--overwrite\n")
            return 2
    from paper_figures import closedloop_runs

    runs = closedloop_runs.compute(quick=args.quick, seed=args.seed,
                                   names=PREDICTORS)
    # under the lock python -m paper_figures takes; staged, all or nothing (left13-cli)
    return write_figure(args.out, [FIGURE_NAME, PDF_NAME, JSON_NAME], args.overwrite,
                        lambda stage: make(stage, runs), parser.prog)


if __name__ == "__main__":
    sys.exit(main())
