"""Figure 8 (an extension, not in the paper): information flow between modes.

Which modes inform which, at which lag: the transfer entropy
``TE[j -> i, l] = I(x_i[t]; x_j[t - l] | x_i[t - 1], x_i[t - 2])`` of every pair of
modes at log-spaced lags (:func:`modalinfo.information.transfer_entropy_map`, Gaussian
estimator, family-wise p-values from the step-down maximum statistic over the whole
map under time-shift surrogates of the sources), on three telemetry sets:

- the two shipped KAOS-like logs (``data/kaos_like_closed_loop.npz``, spectral, and
  ``data/kaos_closedloop.npz``, written by the ``closedloop`` simulator), their first
  :data:`N_MODES` modes;
- the POL telemetry of a no-prediction ``closedloop`` run of the preset
  ``table1-wind`` (two DMs, each with its own WFS): the first :data:`N_MODES_MCAO`
  modes of each DM's POL, so the map holds the transfer within each WFS's modes and
  between the two WFSs.

The paper has no such figure (its predictors are univariate and their inputs chosen
by assumption); issue 21 asks for it. The spectral log is a control with no frozen
flow: its modes have real cross-spectra (no lag structure) by construction, so any
transfer it shows comes from the zero-lag mixing of modes with different spectra.

Steps as :mod:`paper_figures.fig6_compression` (``NEEDS_LOG = False``: the figure
reads the shipped logs and runs its own loop): :func:`compute` (numbers, a
:class:`FigureFlow`), :func:`plot` (PNG, PDF, JSON), :func:`report` (Markdown),
:func:`table_rows` (rows of the report's comparison table), :func:`make`, :func:`main`.

Usage::

    python -m paper_figures.fig_information_flow [--out DIR] [--overwrite] [--quick]
"""

from __future__ import annotations

import json
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from modalinfo.common.cli import Parser

FIGURE_NAME = "fig8_information_flow.png"
PDF_NAME = "fig8_information_flow.pdf"
JSON_NAME = "fig8_information_flow.json"
NEEDS_RUNS = False
#: reads the shipped logs itself and runs its own loop (like Figure 6)
NEEDS_LOG = False

DATA = Path(__file__).resolve().parent.parent / "data"
#: (key, path, description) of the shipped logs
SHIPPED = (
    ("spectral", DATA / "kaos_like_closed_loop.npz", "spectral KAOS-like log"),
    ("simulated", DATA / "kaos_closedloop.npz", "simulated kaos closed-loop log"),
)
PRESET = "table1-wind"
N_MODES = 9             # Z2..Z10 of the shipped logs
N_MODES_MCAO = 5        # Z2..Z6 of each DM's POL
#: source lags [frames], log-spaced: frozen flow crosses a pupil in tens to hundreds
LAGS = (1, 2, 3, 5, 8, 13, 21, 34)
HISTORY = 2
N_SURROGATES = 99
ALPHA = 0.05
DURATION = 0.3          # s of table1-wind (loop closure ~7 ms)
QUICK_DURATION = 0.25   # --quick: rows enough for QUICK_SURROGATES lattice shifts
QUICK_FRAMES = 3000     # --quick: first frames of the shipped logs
QUICK_SURROGATES = 39
TOP_LINKS = 6           # links listed per data set in the report


@dataclass(frozen=True)
class FlowSet:
    """One data set's map.

    Attributes
    ----------
    key, description : str
        Short key and Markdown description of the telemetry.
    rate : float
        Frame rate [Hz].
    flow : modalinfo.information.TransferEntropyMap
        The map (TE in nats; lags in frames).
    seconds : float
        Time the map took [s].
    """

    key: str
    description: str
    rate: float
    flow: Any
    seconds: float


@dataclass(frozen=True)
class FigureFlow:
    """Figure 8's numbers.

    Attributes
    ----------
    sets : tuple of FlowSet
        One map per telemetry set.
    quick : bool
        Reduced settings.
    run_seconds : float
        Time of the table1-wind run (model and loop) [s]; 0 if none.
    elapsed : float
        Time :func:`compute` took [s].
    """

    sets: tuple[FlowSet, ...]
    quick: bool
    run_seconds: float
    elapsed: float


def _config(quick: bool):
    """table1-wind; ``quick``: on-axis SR only and 2 rings of field samples per WFS."""
    import dataclasses

    from closedloop import presets
    from closedloop.config import FieldConfig

    cfg = presets.get(PRESET)
    if not quick:
        return cfg
    return cfg.replace(field=FieldConfig(size=cfg.field.size, n_points=1),
                       wfss=tuple(dataclasses.replace(w, field_samples=2) for w in cfg.wfss))


def table1_wind_pol(config, duration: float, seed: int) -> tuple[Any, Any, int]:
    """POL logs of the two DMs of a no-prediction table1-wind run, after loop closure.

    The one place that runs the loop (closedloop's public API of today). Returns the
    two POL ``ModalLog``s (frames from the closure on) and the closure frame.
    """
    from closedloop.simulation import simulate

    result = simulate(config, duration, seed=seed)
    start = int(result.closure_index)
    return result.logs["dm0.pol"][start:], result.logs["dm1.pol"][start:], start


def _datasets(quick: bool, seed: int) -> tuple[list[tuple], float]:
    """``[(key, description, log, extra, modes, extra_modes)]`` and the run's time [s]."""
    from modalinfo.io import load

    sets = []
    for key, path, desc in SHIPPED:
        log = load(path)
        if quick:
            log = log[:QUICK_FRAMES]
        sets.append((key, f"{desc} (`{path.name}`)", log, None, list(range(N_MODES)), None))
    t0 = time.perf_counter()
    duration = QUICK_DURATION if quick else DURATION
    dm0, dm1, start = table1_wind_pol(_config(quick), duration, seed)
    run_s = time.perf_counter() - t0
    what = " (quick: WFS fields sampled by 2 rings)" if quick else ""
    sets.append(("table1-wind", f"POL of `{PRESET}`{what} ({duration:g} s, seed {seed}, no "
                 f"prediction, frames after the loop closure at frame {start}); DM 0 "
                 "(ground WFS) beside DM 1 (`extra:`, upper WFS)", dm0, dm1,
                 list(range(N_MODES_MCAO)), list(range(N_MODES_MCAO))))
    return sets, run_s


def compute(*, quick: bool = False, seed: int = 0, datasets: list[tuple] | None = None
            ) -> FigureFlow:
    """Transfer-entropy maps of every data set.

    Parameters
    ----------
    quick : bool
        Shorter logs and run, fewer surrogates.
    seed : int
        Atmosphere of the table1-wind run and the surrogates' seed.
    datasets : list of tuple, optional
        ``(key, description, log, extra, modes, extra_modes)`` to map instead of the
        shipped logs and the table1-wind run (for tests).
    """
    from modalinfo.information import transfer_entropy_map

    start = time.perf_counter()
    run_s = 0.0
    if datasets is None:
        datasets, run_s = _datasets(quick, seed)
    out = []
    for key, desc, log, extra, modes, extra_modes in datasets:
        t0 = time.perf_counter()
        n_frames = np.asarray(log.coeffs).shape[0]
        lags = [lag for lag in LAGS if lag + 40 <= n_frames // 2] or [1]
        flow = transfer_entropy_map(
            log, extra=extra, modes=modes, extra_modes=extra_modes, lags=lags,
            history=HISTORY, alpha=ALPHA,
            n_surrogates=QUICK_SURROGATES if quick else N_SURROGATES, seed=seed)
        out.append(FlowSet(key=key, description=desc, rate=float(log.rate or 1.0),
                           flow=flow, seconds=time.perf_counter() - t0))
    return FigureFlow(sets=tuple(out), quick=quick, run_seconds=run_s,
                      elapsed=time.perf_counter() - start)


def _short(label: str) -> str:
    return label.replace("extra:", "U:")


def plot(fig8: FigureFlow, out_dir: Path) -> list[Path]:
    """Draw the maps (PNG, PDF) and write their numbers (JSON) into ``out_dir``."""
    # a Figure of its own, no backend switch: the caller's backend stays as it was
    # (round 45 PART a, G15); Figure.savefig draws with Agg all the same
    from matplotlib.figure import Figure

    from paper_figures._common import save_png_pdf

    n = len(fig8.sets)
    fig = Figure(figsize=(10, 3.6 * n))
    axes = fig.subplots(n, 2, squeeze=False,
                        gridspec_kw={"wspace": 0.35, "hspace": 0.55})
    # fixed margins, not tight_layout: a layout pass redraws every tick label
    for row, fs in zip(axes, fig8.sets, strict=True):
        f = fs.flow
        labels = [_short(s) for s in f.labels]
        mx = f.max_te
        im = row[0].imshow(np.nan_to_num(mx.T, nan=0.0), cmap="viridis", origin="upper")
        best = f.best_lag
        sig = np.array([[f.significant[j, i].any() for i in range(len(labels))]
                        for j in range(len(labels))])
        for j, i in zip(*np.nonzero(sig), strict=True):
            row[0].text(j, i, str(int(best[j, i])), ha="center", va="center", fontsize=6,
                        color="w")
        row[0].set_xticks(range(len(labels)), labels, rotation=90, fontsize=6)
        row[0].set_yticks(range(len(labels)), labels, fontsize=6)
        row[0].set_xlabel("source")
        row[0].set_ylabel("target")
        row[0].set_title(f"{fs.key}: max TE over lags [nats]\n(number: best lag [frames], "
                         "significant pairs)", fontsize=8)
        fig.colorbar(im, ax=row[0], fraction=0.046)
        ms = 1e3 / fs.rate
        pos = np.arange(f.lags.size)  # lags are log-spaced: equal steps on the axis
        for s, t, _, _, _ in f.links()[:TOP_LINKS]:
            j, i = f.labels.index(s), f.labels.index(t)
            row[1].plot(pos, f.te[j, i], marker="o", ms=3, label=f"{_short(s)} -> {_short(t)}")
        row[1].axhline(np.quantile(f.null_max, 1 - f.alpha) if f.null_max.size else 0,
                       color="k", ls=":", lw=0.8,
                       label=f"single-step family-wise {f.alpha:g} threshold")
        row[1].set_xticks(pos, [f"{lag * ms:g}" for lag in f.lags], fontsize=7)
        row[1].set_xlabel("lag [ms]")
        row[1].set_ylabel("TE [nats]")
        row[1].set_title(f"{fs.key}: strongest links vs lag", fontsize=8)
        row[1].legend(fontsize=6)
    fig.suptitle("Figure 8 (extension, not in the paper): transfer entropy between modes",
                 fontsize=10)
    fig.subplots_adjust(left=0.08, right=0.97, top=0.93, bottom=0.08)
    paths = save_png_pdf(fig, out_dir, FIGURE_NAME, PDF_NAME)
    payload = {fs.key: {"labels": list(fs.flow.labels), "lags": fs.flow.lags.tolist(),
                        "rate": fs.rate, "n_samples": fs.flow.n_samples,
                        # undefined cells (a mode to itself...) as null: -1 read back as a
                        # TE of -1 nats and a p-value of -1 (audit 10, feedback, row
                        # pf-fig8-json-sentinel)
                        "te": _nulls(fs.flow.te), "pvalue": _nulls(fs.flow.pvalue),
                        "alpha": fs.flow.alpha, "n_surrogates": fs.flow.n_surrogates}
               for fs in fig8.sets}
    json_path = Path(out_dir) / JSON_NAME
    json_path.write_text(json.dumps(payload), encoding="utf-8")
    return [*paths, json_path]


def _nulls(arr) -> list:
    """``arr.tolist()`` with NaN as None (JSON null: the value is undefined)."""
    a = np.asarray(arr, dtype=np.float64)
    return np.where(np.isnan(a), None, a).tolist()


def _n_pairs(f) -> int:
    return len(f.labels) * (len(f.labels) - 1)


def _cross(f, s: str, t: str) -> bool:
    return s.startswith("extra:") != t.startswith("extra:")


def table_rows(fig8: FigureFlow) -> list[tuple[str, str, str, str]]:
    """``(quantity, paper, ours, why)`` rows: significant links per data set."""
    rows = []
    for fs in fig8.sets:
        links = fs.flow.links()
        top = links[0] if links else None
        ms = 1e3 / fs.rate
        ours = f"{len(links)} of {_n_pairs(fs.flow)} pairs"
        if top:
            ours += (f"; strongest {top[0]} -> {top[1]} at {top[2] * ms:g} ms "
                     f"({top[3]:.4f} nats)")
        if fs.key == "table1-wind":
            n_cross = sum(_cross(fs.flow, s, t) for s, t, *_ in links)
            ours += f"; {n_cross} between the two WFSs"
        rows.append((f"information flow, {fs.key}: significant links (family-wise "
                     f"{fs.flow.alpha:g})", "not in the paper", ours,
                     "extension (issue 21): the paper's predictors are univariate"))
    return rows


def report(fig8: FigureFlow) -> str:
    """Markdown section of Figure 8."""
    lines = [
        "## Figure 8: Information flow between modes (extension, not in the paper)\n",
        f"![Figure 8]({FIGURE_NAME})\n",
        "Transfer entropy `TE[j -> i, l] = I(x_i[t]; x_j[t-l] | x_i[t-1], x_i[t-2])` of every "
        f"pair of modes at lags {', '.join(map(str, LAGS))} frames "
        "(`modalinfo.information.transfer_entropy_map`, Gaussian estimator). A link is "
        "significant when its family-wise p-value is at most the level: step-down maxT "
        "(Westfall & Young) over the largest TE of the map under "
        f"{fig8.sets[0].flow.n_surrogates if fig8.sets else N_SURROGATES} circular "
        "time shifts of the sources, which holds the chance of any spurious link in a map "
        f"at {ALPHA:g} (measured within the Monte-Carlo error on maps of 2 to 100 cells: "
        "`modalinfo.information.flow`). Bivariate TE does not "
        "separate direct from indirect transfer (a common driver shows as a link). Numbers "
        f"in `{JSON_NAME}` (null where undefined).\n",
    ]
    for fs in fig8.sets:
        f = fs.flow
        ms = 1e3 / fs.rate
        links = f.links()
        lags = ("" if tuple(f.lags) == LAGS
                else f", lags {', '.join(map(str, f.lags))} (a short log)")
        lines.append(f"**{fs.key}**: {fs.description}; {len(f.labels)} series{lags}, n = "
                     f"{f.n_samples} rows, {len(links)} significant links of "
                     f"{_n_pairs(f)} pairs (map in {fs.seconds:.1f} s).\n")
        if links:
            lines += ["| source | target | lag [frames] | lag [ms] | TE [nats] | p (family-wise) |",
                      "|---|---|---|---|---|---|"]
            for s, t, lag, te, p in links[:TOP_LINKS]:
                lines.append(f"| {s} | {t} | {lag} | {lag * ms:g} | {te:.4f} | {p:.3f} |")
            lines.append("")
    lines.append(
        "Reading: a TE that peaks at one lag is transport (a layer carrying a pattern "
        "from one mode, or one WFS, to another); a TE flat over the lags is a slowly "
        "varying component two modes share, not transport. The spectral log has no "
        "frozen flow (its modes are mixtures of series with real cross-spectra), so a "
        "link there is the zero-lag mixing of modes with different temporal spectra "
        "(tilt and coma are one coupled family of the Zernike covariance). In the "
        "simulated logs the layers move across the pupil, and a mode's future is "
        "informed by other modes' past at lags up to the wind's crossing time (for "
        "table1-wind, the 70 m/s upper layer crosses the 4 m pupil in 57 ms, the 21 m/s "
        "ground layer in 190 ms). In the figure, `U:` marks the upper WFS (DM 1).")
    if fig8.run_seconds:
        lines.append(f"\nThe table1-wind run took {fig8.run_seconds:.1f} s.")
    return "\n".join(lines) + "\n"


def make(out_dir: Path, *, quick: bool = False, seed: int = 0) -> str:
    """Compute, draw and report Figure 8."""
    fig8 = compute(quick=quick, seed=seed)
    plot(fig8, out_dir)
    return report(fig8)


def main(argv: list[str] | None = None) -> int:
    """Command line: draw the figure and print the report section."""
    parser = Parser(prog="python -m paper_figures.fig_information_flow",
                                     description="Figure 8: information flow between modes.")
    parser.add_argument("--out", type=Path, default=Path("out"), help="output directory")
    parser.add_argument("--overwrite", action="store_true", help="replace an existing figure")
    parser.add_argument("--quick", action="store_true", help="shorter logs and run")
    args = parser.parse_args(argv)
    from paper_figures._common import write_figure

    # under the lock python -m paper_figures takes; staged, all or nothing (left13-cli)
    return write_figure(args.out, [FIGURE_NAME, PDF_NAME, JSON_NAME], args.overwrite,
                        lambda stage: make(stage, quick=args.quick), parser.prog)


if __name__ == "__main__":
    sys.exit(main())
