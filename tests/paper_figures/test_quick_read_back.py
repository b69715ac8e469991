"""The quick run's figures read back, and its report's sentences recomputed from its JSON.

References, all outside the figure and report code:
- units and ticks: the documented conventions (DESIGN.md: fitting error in waves^2,
  time in ms, angles on the sky in arcsec / arcmin; ``closedloop.presets``: table1's
  science wavelength 630 nm, 1 ms frames; ``paper_figures.closedloop_runs``: the quick
  runs are 0.2 s of table1 on a 5x5 grid over 120"), checked against the axes of the
  matplotlib Figures the run saved (recorded by ``conftest.py``'s ``quick_run``);
- input series: Figure 2's "none" line against a separate ``closedloop.simulate`` of
  the run its docstring names (table1, 5x5 field, 0.2 s, seed 0), its SR peak taken
  here as ``max over directions of exp(-residual variance)`` (Marechal); Figure 1's
  panel (a) against the shipped logs: the frame its title names has the median total
  variance (the docstring's "typical frame"), and its standard-order curve is the
  Parseval tail sum of that frame's coefficients in waves^2 (to the pupil's sampling);
- sentences: Figure 7's and Figure 8's report sentences recomputed with this test's own
  arithmetic from the JSON files the run wrote (``fig7_solar.json``,
  ``fig8_information_flow.json``).
"""

import json
import re
from pathlib import Path

import numpy as np
import pytest

DATA = Path(__file__).resolve().parents[2] / "data"


def _section(out, start):
    text = (out / "report.md").read_text()
    parts = re.split(r"^(## .*)$", text, flags=re.M)
    found = [parts[i + 1] for i in range(1, len(parts) - 1, 2) if parts[i].startswith(start)]
    assert len(found) == 1, start
    return " ".join(found[0].split())


def _ticks_inside(ax, axis="x"):
    lo, hi = sorted(ax.get_xlim() if axis == "x" else ax.get_ylim())
    ticks = ax.get_xticks() if axis == "x" else ax.get_yticks()
    return [t for t in ticks if lo - 1e-9 * abs(hi - lo) <= t <= hi + 1e-9 * abs(hi - lo)]


# ------------------------------------------------------------------ axes: units and ticks
def test_figure2_axes_are_ms_and_strehl_at_630_nm(quick_run):
    ax = quick_run.figures["fig2_sr_peak.png"].axes[0]
    assert ax.get_xlabel() == "time [ms]"
    assert ax.get_ylabel() == "SR peak over the field (630 nm)"
    assert ax.get_ylim() == (0.0, 1.0)
    # 0.2 s of 1-ms frames: the data run from the first frame's end (1 ms) to 200 ms,
    # and the visible ticks are milliseconds (a time axis in s would end at 0.2)
    for line in ax.get_lines():
        x = np.asarray(line.get_xdata(), dtype=float)
        if x.size > 2:
            assert x[0] == pytest.approx(1.0) and x[-1] == pytest.approx(200.0)
            assert np.allclose(np.diff(x), 1.0)
    ticks = _ticks_inside(ax)
    assert min(ticks) >= 0 and max(ticks) >= 150 and max(ticks) <= 220
    assert all(0.0 <= t <= 1.0 for t in _ticks_inside(ax, "y"))


def test_figure3_axes_are_hz_up_to_nyquist(quick_run):
    ax = quick_run.figures["fig3_sr_spectrum.png"].axes[0]
    assert ax.get_xlabel() == "frequency [Hz]"
    assert ax.get_ylabel() == "PSD of the SR peak [1/Hz]"
    assert ax.get_xscale() == "log" and ax.get_yscale() == "log"
    for line in ax.get_lines():
        x = np.asarray(line.get_xdata(), dtype=float)
        if x.size > 2:
            # Welch at 1 kHz on the ~190 frames after closure: bins k fs / nperseg from
            # the first non-zero one up to the 500 Hz Nyquist frequency (an odd segment
            # length ends half a bin below it)
            df = x[0]
            assert 1000 / 256 - 1e-9 <= df <= 1000 / 100 and np.allclose(np.diff(x), df)
            assert 500.0 - df / 2 - 1e-9 <= x.max() <= 500.0 + 1e-9


def test_figure4_maps_span_the_120_arcsec_field(quick_run):
    fig = quick_run.figures["fig4_sr_maps.png"]
    maps = [ax for ax in fig.axes if ax.get_images()]
    assert len(maps) >= 4
    for ax in maps:
        assert ax.get_xlabel() == "x [arcsec]"
        image = ax.get_images()[0]
        assert image.get_extent() == pytest.approx([-60.0, 60.0, -60.0, 60.0])
        assert image.get_array().shape == (5, 5)   # the quick 5x5 grid
        assert image.get_clim() == (0.0, 1.0)
        assert all(-60 <= t <= 60 for t in _ticks_inside(ax))
    assert any(ax.get_ylabel() == "y [arcsec]" for ax in maps)
    bars = [ax for ax in fig.axes if ax.get_ylabel().startswith("SR after closure")]
    assert len(bars) == 1 and bars[0].get_ylabel() == "SR after closure (630 nm)"


def test_figure1_axes_are_modes_and_waves2(quick_run):
    for name in ("fig1_fitting_error.png", "fig1_fitting_error_closedloop.png"):
        axes = quick_run.figures[name].axes
        assert len(axes) == 3
        for ax in axes:
            assert ax.get_xlabel() == "number of modes n"
            assert ax.get_ylabel() == "fitting error $\\Delta\\Phi(n)$ [waves$^2$]"
            assert ax.get_yscale() == "log"
            ticks = _ticks_inside(ax)
            assert min(ticks) >= 0 and max(ticks) <= 28   # 27 modes (Z2-Z28)


def test_figure5_time_axes_are_ms_at_2_khz(quick_run):
    for name in ("fig5_forecast.png", "fig5_forecast_closedloop.png"):
        axes = quick_run.figures[name].axes
        for ax in axes[:3]:
            assert ax.get_xlabel() == "time [ms]"
            # the first logged mode, Z2, in the log's units (rad)
            assert ax.get_ylabel() == "Z2 [rad]"
            x = np.concatenate([np.asarray(ln.get_xdata(), float) for ln in ax.get_lines()
                                if len(ln.get_xdata()) > 2])
            steps = np.diff(np.unique(x))
            assert steps.min() == pytest.approx(0.5)   # 2 kHz frames


# ------------------------------------------------------------------ input series
@pytest.fixture(scope="module")
def none_run():
    """The run Figure 2's docstring names, simulated here: table1, 5x5 field, 0.2 s, seed 0."""
    from closedloop import presets, simulate
    from closedloop.config import FieldConfig

    cfg = presets.get("table1")
    cfg = cfg.replace(field=FieldConfig(size=cfg.field.size, n_points=5))
    return simulate(cfg, 0.2, seed=0, progress=False)


def test_figure2_draws_the_sr_peak_of_the_run_it_names(quick_run, none_run):
    ax = quick_run.figures["fig2_sr_peak.png"].axes[0]
    lines = {ln.get_label().rsplit(" (", 1)[0]: ln for ln in ax.get_lines()
             if not ln.get_label().startswith("_")}
    line = lines["no prediction"]
    peak = np.exp(-np.asarray(none_run.residual_variance)).max(axis=1)
    np.testing.assert_allclose(np.asarray(line.get_ydata(), float), peak, rtol=1e-9)
    # the legend's mean is the mean of the drawn line after the closure line
    t_close = [ln for ln in ax.get_lines() if ln.get_label().startswith("_")
               and np.ptp(np.asarray(ln.get_xdata(), float)) == 0][0].get_xdata()[0]
    x = np.asarray(line.get_xdata(), float)
    mean = float(np.asarray(line.get_ydata(), float)[x >= t_close].mean())
    assert line.get_label() == f"no prediction ({mean:.3f})"


def test_figure1_panel_a_is_the_typical_frame_of_the_shipped_logs(quick_run):
    from modalinfo.io import load

    for name, fig in (("kaos_like_closed_loop.npz", "fig1_fitting_error.png"),
                      ("kaos_closedloop.npz", "fig1_fitting_error_closedloop.png")):
        a = np.asarray(load(DATA / name).to_units("waves").coeffs, dtype=float)
        total = np.sum(a ** 2, axis=1)
        ax = quick_run.figures[fig].axes[0]
        title = re.match(r"\(a\) typical frame (\d+) ", ax.get_title())
        assert title, ax.get_title()
        frame = int(title.group(1))
        # the frame of median total variance (the figure ranks the pupil-sampled totals,
        # equal to these Parseval sums to the sampling error: a rank within 2 % of the
        # median, where a frame taken at random is further with probability 0.96)
        rank = int(np.sum(total < total[frame]))
        assert abs(rank - total.size / 2) <= 0.02 * total.size, (name, frame, rank)
        # standard order: dPhi(n) = sum_{k > n} a_k^2 by Parseval (unit-RMS modes), to the
        # pupil's sampling error
        line = [ln for ln in ax.get_lines() if ln.get_label() == "zernike:standard"][0]
        n = np.asarray(line.get_xdata(), float).astype(int)
        tail = np.array([np.sum(a[frame, k:] ** 2) for k in n])
        np.testing.assert_allclose(np.asarray(line.get_ydata(), float)[n < a.shape[1]],
                                   tail[n < a.shape[1]], rtol=0.1)


# ------------------------------------------------------------------ sentences from JSON
def test_figure7_sentences_recomputed_from_its_json(quick_run):
    num = json.loads((quick_run.out / "fig7_solar.json").read_text())
    body = _section(quick_run.out, "## Figure 7")
    sol, t1 = num["solar"], num["table1"]
    assert (f"the delay is {num['delay_ms']['solar']:g} ms against table1's "
            f"{num['delay_ms']['table1']:g} ms), seed {num['seed']}, "
            f"{num['duration']:g} s per run") in body
    assert (f"({sol['closure_ms']:.0f} ms; table1 {t1['closure_ms']:.0f} ms)") in body
    for p, v in sol["peak_mean"].items():
        if p == "none" or p not in t1["peak_mean"]:
            continue
        d_sol = v - sol["peak_mean"]["none"]
        d_t1 = t1["peak_mean"][p] - t1["peak_mean"]["none"]
        assert f"{d_sol:+.3f} (table1 {d_t1:+.3f})" in body, p
    sb, tb = sol["budget"], t1["budget"]
    assert (f"the temporal term is {sb['temporal']:.3f} rad^2 of a {sb['measured']:.3f} "
            f"rad^2 residual with solar sensing ({100 * sb['temporal'] / sb['measured']:.1f}%)"
            ) in body
    assert (f"against {tb['temporal']:.3f} of {tb['measured']:.3f} "
            f"({100 * tb['temporal'] / tb['measured']:.1f}%)") in body
    assert f"the noise term is {sb['noise']:.4f} against {tb['noise']:.4f}" in body
    # Marechal: removing the temporal term multiplies the SR by exp(+temporal)
    assert f"from {sb['sr_now']:.3f} to at most {sb['sr_bound']:.3f}" in body
    assert sb["sr_bound"] == pytest.approx(sb["sr_now"] * np.exp(sb["temporal"]), rel=1e-6)
    best = max((p for p in sol["peak_mean"] if p != "none"), key=sol["peak_mean"].get)
    gain = sol["peak_mean"][best] - sol["peak_mean"]["none"]
    assert f"{gain:+.3f} in SR peak" in body


def test_figure8_sentences_and_link_tables_recomputed_from_its_json(quick_run):
    # a link: a (source j, target i) pair, j != i, whose family-wise p-value at its best
    # lag (the largest TE over lags) is at most the level; listed strongest first
    payload = json.loads((quick_run.out / "fig8_information_flow.json").read_text())
    body = _section(quick_run.out, "## Figure 8")
    assert payload
    for key, s in payload.items():
        te, pv = np.asarray(s["te"], float), np.asarray(s["pvalue"], float)
        labels, lags, ms = s["labels"], s["lags"], 1e3 / s["rate"]
        n = len(labels)
        links = []
        for j in range(n):
            for i in range(n):
                if i == j:
                    continue
                a = int(np.argmax(te[j, i]))
                if 0.0 <= pv[j, i, a] <= s["alpha"]:   # -1: NaN in the file
                    links.append((labels[j], labels[i], lags[a], te[j, i, a], pv[j, i, a]))
        links.sort(key=lambda r: -r[3])
        head = re.search(rf"\*\*{re.escape(key)}\*\*: [^*]*?; (\d+) series[^*]*?n = (\d+) "
                         rf"rows, (\d+) significant links of (\d+) pairs", body)
        assert head, key
        assert head.groups() == (str(n), str(s["n_samples"]), str(len(links)),
                                 str(n * (n - 1)))
        part = body.split(f"**{key}**", 1)[1].split("**", 1)[0] if links else ""
        for src, tgt, lag, v, p in links[:6]:
            assert (f"| {src} | {tgt} | {lag} | {lag * ms:g} | {v:.4f} | {p:.3f} |"
                    in part), (key, src, tgt)
