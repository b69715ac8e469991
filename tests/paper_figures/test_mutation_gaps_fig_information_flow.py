"""Figure 8 (information flow) on hand-made maps: every number, row, sentence and axis.

Written for mutation testing (issue 26 item 3, docs/MUTATION.md). References, all
outside the module:

- the maps are written in this file: ``TransferEntropyMap`` records whose TE and
  p-values are dyadic arrays chosen by hand, so the links, the best lags, the maxima
  over the lags, the cross-sensor count and the threshold (``numpy.quantile``'s linear
  rule worked out by hand: 0.385 for 0.1 .. 0.4 at 0.95) are known in advance, and the
  lags in ms are ``lag * 1000 / rate`` done by hand (500 Hz: 2 ms per frame);
- the heavy parts are recorders: ``transfer_entropy_map``, ``modalinfo.io.load``, the
  closed-loop ``simulate`` and the table1-wind run, so ``compute``'s contract (module
  docstring: the shipped logs' first 9 modes, 3000 frames in ``--quick``, the first 5
  modes of each DM's POL after the closure, history 2, the family-wise 0.05, 99 or 39
  surrogates, lags that fit in half the log with 40 rows to spare) is checked on what
  is passed;
- the figure is read back from the ``Figure`` handed to ``savefig`` and the files saved
  (axes, units, ticks, the series drawn, annotations, the PNG's size at 110 dpi, the
  strict JSON), and the report, the table rows and the command line's messages are
  written out here word for word.
No transfer entropy is estimated and no loop runs: ~3 s.
"""

from __future__ import annotations

import dataclasses
import json
import types
from pathlib import Path

import matplotlib.image
import numpy as np
import pytest

import closedloop.simulation
import modalinfo.information
import modalinfo.io
from closedloop import presets
from modalinfo.information import TransferEntropyMap
from modalinfo.telemetry import ModalLog
from paper_figures import fig_information_flow as fig8

from .conftest import saved_figures

LAGS = (1, 2, 3, 5, 8, 13, 21, 34)


def _map(labels, lags, te, p, null_max, n_surrogates, n_samples=1000):
    return TransferEntropyMap(
        labels=tuple(labels), group=np.array([int(s.startswith("extra:")) for s in labels]),
        lags=np.array(lags), te=te, pvalue=p, null_max=np.array(null_max, dtype=float),
        history=2, n_samples=n_samples, method="gaussian", units="nats", alpha=0.05,
        n_surrogates=n_surrogates, min_shift=10, estimated_seconds=0.0)


def _blank(s, n_lags, value):
    te = np.full((s, s, n_lags), value)
    p = np.ones((s, s, n_lags))
    for k in range(s):
        te[k, k] = np.nan
        p[k, k] = np.nan
    return te, p


def map_a():
    """table1-wind-like: Z2, Z3, extra:Z2 at the eight lags (500 Hz: 2 ms per frame)."""
    te, p = _blank(3, 8, 0.0625)
    te[0, 2, 3], p[0, 2, 3] = 0.5, 0.01       # Z2 -> extra:Z2 at lag 5: a link, cross
    te[1, 0, 5], p[1, 0, 5] = 0.25, 0.05      # Z3 -> Z2 at lag 13: p == alpha, a link
    te[2, 1, 0], p[2, 1, 0] = 0.125, 0.2      # extra:Z2 -> Z3: best lag 1 not significant,
    p[2, 1, 2] = 0.01                         # lag 3 is: annotated, but no link
    te[1, 2], p[1, 2] = np.nan, np.nan        # a cell outside the map's candidates
    te[2, 0, 7], p[2, 0, 7] = 0.1875, 0.5     # extra:Z2 -> Z2 peaks at lag 34, not significant
    return _map(("Z2", "Z3", "extra:Z2"), LAGS, te, p, [0.4, 0.1, 0.3, 0.2], 39, 900)


# map B: Z2..Z5 at lags 1, 2 (a short log), 250 Hz (4 ms per frame): seven links
B_LINKS = [  # (j, i, lag index, te, p), strongest first
    (0, 1, 1, 0.875, 0.01), (1, 2, 0, 0.75, 0.01), (2, 3, 1, 0.625, 0.02),
    (3, 0, 0, 0.5, 0.02), (0, 2, 1, 0.375, 0.03), (1, 3, 0, 0.25, 0.04),
    (2, 0, 1, 0.125, 0.05)]


def map_b():
    te, p = _blank(4, 2, 0.03125)
    for j, i, a, v, pv in B_LINKS:
        te[j, i, a], p[j, i, a] = v, pv
    return _map(("Z2", "Z3", "Z4", "Z5"), (1, 2), te, p, [0.5, 0.25], 99, 700)


def map_c():
    """No link, no surrogate maximum (threshold drawn at 0)."""
    te, p = _blank(2, 8, 0.0625)
    return _map(("Z2", "Z3"), LAGS, te, p, [], 0, 500)


def _figure(run_seconds=12.34):
    sets = (fig8.FlowSet("table1-wind", "POL of a hand-made run", 500.0, map_a(), 3.0),
            fig8.FlowSet("spectral", "spectral log", 250.0, map_b(), 0.5),
            fig8.FlowSet("simulated", "simulated log", 1000.0, map_c(), 12.0))
    return fig8.FigureFlow(sets=sets, quick=False, run_seconds=run_seconds, elapsed=20.0)


# ---- constants (module docstring and the report's formula) -----------------------------

def test_constants_of_the_docstring():
    assert (fig8.FIGURE_NAME, fig8.PDF_NAME, fig8.JSON_NAME) == (
        "fig8_information_flow.png", "fig8_information_flow.pdf", "fig8_information_flow.json")
    assert fig8.NEEDS_RUNS is False and fig8.NEEDS_LOG is False
    assert [(k, p.name) for k, p, _ in fig8.SHIPPED] == [
        ("spectral", "kaos_like_closed_loop.npz"), ("simulated", "kaos_closedloop.npz")]
    assert all(p.is_file() for _, p, _ in fig8.SHIPPED)
    assert [d for *_, d in fig8.SHIPPED] == ["spectral KAOS-like log",
                                              "simulated kaos closed-loop log"]
    assert fig8.PRESET == "table1-wind"
    assert (fig8.N_MODES, fig8.N_MODES_MCAO) == (9, 5)        # Z2..Z10, Z2..Z6
    assert fig8.LAGS == LAGS and fig8.HISTORY == 2          # x_i[t-1], x_i[t-2]
    assert (fig8.N_SURROGATES, fig8.QUICK_SURROGATES, fig8.ALPHA) == (99, 39, 0.05)
    assert (fig8.DURATION, fig8.QUICK_DURATION, fig8.QUICK_FRAMES) == (0.3, 0.25, 3000)
    assert fig8.TOP_LINKS == 6


# ---- compute ---------------------------------------------------------------------------

class _Recorder:
    def __init__(self, result=None):
        self.calls = []
        self.result = result

    def __call__(self, *args, **kwargs):
        self.calls.append((args, kwargs))
        return self.result() if callable(self.result) else self.result


def _log(n, m=10, rate=500.0):
    x = np.arange(n * m, dtype=float).reshape(n, m) % 7.0
    return ModalLog(x, rate=rate)


@pytest.mark.parametrize(("n_frames", "lags"), [
    (148, list(LAGS)),        # 148 // 2 = 74 = 34 + 40: every lag fits
    (147, list(LAGS[:-1])),   # 73: 34 does not
    (80, [1]),                # 40: no lag fits -> lag 1 alone
])
def test_compute_passes_the_lags_that_fit(monkeypatch, n_frames, lags):
    rec = _Recorder(map_c)
    monkeypatch.setattr(modalinfo.information, "transfer_entropy_map", rec)
    log, other = _log(n_frames), _log(n_frames, 3)
    r = fig8.compute(seed=5, datasets=[("k", "d", log, other, [0, 1], [2])])
    ((args, kw),) = rec.calls
    assert args == (log,)
    assert kw == {"extra": other, "modes": [0, 1], "extra_modes": [2], "lags": lags,
                  "history": 2, "alpha": 0.05, "n_surrogates": 99, "seed": 5}
    (fs,) = r.sets
    assert (fs.key, fs.description, fs.rate) == ("k", "d", 500.0)
    assert type(fs.rate) is float


def test_compute_quick_surrogates_rate_and_times(monkeypatch):
    rec = _Recorder(map_c)
    monkeypatch.setattr(modalinfo.information, "transfer_entropy_map", rec)
    no_rate = ModalLog(np.ones((200, 2)) * np.arange(200)[:, None] % 3, rate=None)
    import time
    t0 = time.perf_counter()
    r = fig8.compute(quick=True, datasets=[("a", "A", _log(200), None, None, None),
                                           ("b", "B", no_rate, None, None, None)])
    wall = time.perf_counter() - t0
    assert [c[1]["n_surrogates"] for c in rec.calls] == [39, 39]
    assert [c[1]["seed"] for c in rec.calls] == [0, 0]
    assert [fs.rate for fs in r.sets] == [500.0, 1.0]      # no rate: frames
    assert r.quick is True and r.run_seconds == 0.0
    assert all(0.0 <= fs.seconds <= r.elapsed for fs in r.sets)
    assert 0.0 <= r.elapsed <= wall
    assert all(isinstance(fs.flow, TransferEntropyMap) for fs in r.sets)


def test_compute_without_datasets_maps_the_shipped_logs_and_the_run(monkeypatch):
    loaded = []

    def load(path):
        loaded.append(Path(path))
        return _log(4000, 12, 1000.0)

    dm0, dm1 = _log(300, 6, 2000.0), _log(300, 6, 2000.0)
    run = _Recorder((dm0, dm1, 14))
    tem = _Recorder(map_c)
    monkeypatch.setattr(modalinfo.io, "load", load)
    monkeypatch.setattr(fig8, "table1_wind_pol", run)
    monkeypatch.setattr(modalinfo.information, "transfer_entropy_map", tem)
    for quick in (False, True):
        loaded.clear()
        run.calls.clear()
        tem.calls.clear()
        r = fig8.compute(quick=quick, seed=3)
        assert loaded == [p for _, p, _ in fig8.SHIPPED]
        ((cfg, duration, seed), kw), = run.calls
        assert kw == {} and seed == 3 and duration == (0.25 if quick else 0.3)
        assert cfg.field.n_points == (1 if quick else presets.get("table1-wind").field.n_points)
        assert 0.0 <= r.run_seconds <= r.elapsed
        assert [fs.key for fs in r.sets] == ["spectral", "simulated", "table1-wind"]
        assert [fs.rate for fs in r.sets] == [1000.0, 1000.0, 2000.0]
        frames = [np.asarray(a[0].coeffs).shape[0] for a, _ in tem.calls]
        assert frames == ([3000, 3000, 300] if quick else [4000, 4000, 300])
        assert [kw["modes"] for _, kw in tem.calls] == [list(range(9))] * 2 + [list(range(5))]
        assert [kw["extra_modes"] for _, kw in tem.calls] == [None, None, list(range(5))]
        assert tem.calls[2][1]["extra"] is dm1 and tem.calls[2][0][0] is dm0
        assert [kw["extra"] for _, kw in tem.calls[:2]] == [None, None]
        assert [kw["seed"] for _, kw in tem.calls] == [3, 3, 3]
        what = " (quick: WFS fields sampled by 2 rings)" if quick else ""
        d = "0.25" if quick else "0.3"
        assert [fs.description for fs in r.sets] == [
            "spectral KAOS-like log (`kaos_like_closed_loop.npz`)",
            "simulated kaos closed-loop log (`kaos_closedloop.npz`)",
            f"POL of `table1-wind`{what} ({d} s, seed 3, no prediction, frames after the "
            "loop closure at frame 14); DM 0 (ground WFS) beside DM 1 (`extra:`, upper WFS)"]


def test_config_quick_samples_the_field_sparsely():
    full = fig8._config(False)
    assert full == presets.get("table1-wind")
    quick = fig8._config(True)
    assert quick.field.n_points == 1 and quick.field.size == full.field.size
    assert [w.field_samples for w in quick.wfss] == [2] * len(full.wfss)
    assert len(full.wfss) == 2
    # everything else of the WFSs is table1-wind's
    assert [dataclasses.replace(w, field_samples=0) for w in quick.wfss] == [
        dataclasses.replace(w, field_samples=0) for w in full.wfss]


def test_config_quick_keeps_the_presets_field_size(monkeypatch):
    # table1-wind's field is FieldConfig's default 120"; a preset with another size keeps it
    from closedloop.config import FieldConfig

    cfg = presets.get("table1-wind")
    other = cfg.replace(field=FieldConfig(size=60.0, n_points=cfg.field.n_points))
    monkeypatch.setattr(presets, "get", lambda name: other if name == "table1-wind" else None)
    assert fig8._config(True).field.size == 60.0
    assert fig8._config(False) is other


def test_table1_wind_pol_cuts_both_logs_at_the_closure(monkeypatch):
    dm0 = _log(20, 5)
    dm1 = ModalLog(np.asarray(dm0.coeffs) + 100.0, rate=500.0)
    rec = _Recorder(types.SimpleNamespace(closure_index=np.int64(6),
                                          logs={"dm0.pol": dm0, "dm1.pol": dm1,
                                                "dm0.cmd": _log(20, 5)}))
    monkeypatch.setattr(closedloop.simulation, "simulate", rec)
    a, b, start = fig8.table1_wind_pol("cfg", 0.125, 9)
    assert rec.calls == [(("cfg", 0.125), {"seed": 9})]
    assert start == 6 and type(start) is int
    np.testing.assert_array_equal(a.coeffs, np.asarray(dm0.coeffs)[6:])
    np.testing.assert_array_equal(b.coeffs, np.asarray(dm1.coeffs)[6:])


# ---- plot: read back -------------------------------------------------------------------

@pytest.fixture(scope="module")
def drawn(tmp_path_factory):
    out = tmp_path_factory.mktemp("fig8")
    with saved_figures() as figures:
        paths = fig8.plot(_figure(), out)
    return out, paths, figures


def test_plot_files_and_layout(drawn):
    # one test reads everything back: mutmut runs a plot mutant only with the tests that
    # called plot (the fixture's first user), see docs/MUTATION.md
    out, paths, figures = drawn
    assert paths == [out / "fig8_information_flow.png", out / "fig8_information_flow.pdf",
                     out / "fig8_information_flow.json"]
    fig = figures["fig8_information_flow.png"]
    assert figures["fig8_information_flow.pdf"] is fig
    # 3 data sets: 10 x 10.8 inches at 110 dpi
    assert tuple(fig.get_size_inches()) == pytest.approx((10.0, 10.8))
    assert matplotlib.image.imread(paths[0]).shape[:2] == (1188, 1100)
    assert paths[1].read_bytes()[:5] == b"%PDF-"
    sp = fig.subplotpars
    assert (sp.left, sp.right, sp.top, sp.bottom) == pytest.approx((0.08, 0.97, 0.93, 0.08))
    assert fig._suptitle.get_text() == ("Figure 8 (extension, not in the paper): transfer "
                                        "entropy between modes")
    assert fig._suptitle.get_fontsize() == 10
    # 3 rows x (map, lines) + one colour bar per map
    assert len(fig.axes) == 9
    grid = fig.axes[:6]
    gs = grid[0].get_subplotspec().get_topmost_subplotspec().get_gridspec()
    assert (gs.nrows, gs.ncols, gs.wspace, gs.hspace) == (3, 2, 0.35, 0.55)
    rows = sorted({round(ax.get_position().y0, 6) for ax in grid}, reverse=True)
    assert len(rows) == 3
    for k, ax in enumerate(grid):
        assert round(ax.get_position().y0, 6) == rows[k // 2]
    assert all(grid[2 * r].get_position().x0 < grid[2 * r + 1].get_position().x0
               for r in range(3))
    cbars = fig.axes[6:]
    for r, cb in enumerate(cbars):
        # a colour bar of the map's image, cut from the map's cell (fraction 0.046 of it),
        # between the map and the lines panel
        assert cb._colorbar.mappable is grid[2 * r].images[0]
        spec = cb.get_subplotspec()
        assert spec.get_topmost_subplotspec() == grid[2 * r].get_subplotspec(
        ).get_topmost_subplotspec()
        assert spec.get_gridspec().get_width_ratios()[-1] == pytest.approx(0.046)
        m = grid[2 * r].get_position()
        assert m.x1 < cb.get_position().x0 < grid[2 * r + 1].get_position().x0

    # ---- row 0 (map A, 500 Hz): the map panel
    ax = grid[0]
    (im,) = ax.images
    np.testing.assert_array_equal(np.asarray(im.get_array()), [  # [target, source]
        [0.0, 0.25, 0.1875], [0.0625, 0.0, 0.125], [0.5, 0.0, 0.0]])
    assert im.get_cmap().name == "viridis" and im.origin == "upper"
    texts = [(t.get_position(), t.get_text()) for t in ax.texts]
    assert texts == [((0, 2), "5"), ((1, 0), "13"), ((2, 1), "1")]  # (source, target)
    for t in ax.texts:
        assert (t.get_ha(), t.get_va(), t.get_fontsize(), t.get_color()) == (
            "center", "center", 6, "w")
    assert [t.get_text() for t in ax.get_xticklabels()] == ["Z2", "Z3", "U:Z2"]
    assert [t.get_text() for t in ax.get_yticklabels()] == ["Z2", "Z3", "U:Z2"]
    assert list(ax.get_xticks()) == [0, 1, 2] and list(ax.get_yticks()) == [0, 1, 2]
    assert [t.get_rotation() for t in ax.get_xticklabels()] == [90.0] * 3
    assert [t.get_rotation() for t in ax.get_yticklabels()] == [0.0] * 3
    assert {t.get_fontsize() for t in ax.get_xticklabels() + ax.get_yticklabels()} == {6}
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("source", "target")
    assert ax.get_title() == ("table1-wind: max TE over lags [nats]\n(number: best lag "
                              "[frames], significant pairs)")
    assert ax.title.get_fontsize() == 8
    # ---- row 0: the lines panel, lags in ms (2 ms per frame), log-spaced at equal steps
    ax = grid[1]
    lines = ax.get_lines()
    assert [ln.get_label() for ln in lines] == [
        "Z2 -> U:Z2", "Z3 -> Z2", "single-step family-wise 0.05 threshold"]
    a = map_a()
    np.testing.assert_array_equal(lines[0].get_xdata(), np.arange(8))
    np.testing.assert_array_equal(lines[0].get_ydata(), a.te[0, 2])
    np.testing.assert_array_equal(lines[1].get_xdata(), np.arange(8))
    np.testing.assert_array_equal(lines[1].get_ydata(), a.te[1, 0])
    for ln in lines[:2]:
        assert (ln.get_marker(), ln.get_markersize()) == ("o", 3)
    thr = lines[2]
    np.testing.assert_allclose(thr.get_ydata(), [0.385, 0.385], rtol=1e-12)
    assert (thr.get_color(), thr.get_linestyle(), thr.get_linewidth()) == ("k", ":", 0.8)
    assert [t.get_text() for t in ax.get_xticklabels()] == [
        "2", "4", "6", "10", "16", "26", "42", "68"]
    assert list(ax.get_xticks()) == list(range(8))
    assert {t.get_fontsize() for t in ax.get_xticklabels()} == {7}
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("lag [ms]", "TE [nats]")
    assert ax.get_title() == "table1-wind: strongest links vs lag"
    assert ax.title.get_fontsize() == 8
    leg = ax.get_legend()
    assert [t.get_text() for t in leg.get_texts()] == [ln.get_label() for ln in lines]
    assert {t.get_fontsize() for t in leg.get_texts()} == {6}

    # ---- row 1 (map B, 250 Hz, lags 1, 2): six lines of seven links, strongest first
    ax = grid[3]
    labels = [ln.get_label() for ln in ax.get_lines()]
    assert labels == ["Z2 -> Z3", "Z3 -> Z4", "Z4 -> Z5", "Z5 -> Z2", "Z2 -> Z4", "Z3 -> Z5",
                      "single-step family-wise 0.05 threshold"]
    np.testing.assert_allclose(ax.get_lines()[-1].get_ydata(), [0.4875] * 2, rtol=1e-12)
    assert [t.get_text() for t in ax.get_xticklabels()] == ["4", "8"]
    assert ax.get_title() == "spectral: strongest links vs lag"
    assert grid[2].get_title().startswith("spectral: max TE")
    assert len(grid[2].texts) == 7
    # ---- row 2 (map C, no link, no surrogates): threshold at 0, lags in ms at 1 kHz
    ax = grid[5]
    (thr,) = ax.get_lines()
    np.testing.assert_array_equal(thr.get_ydata(), [0.0, 0.0])
    assert [t.get_text() for t in ax.get_xticklabels()] == [str(v) for v in LAGS]
    assert len(grid[4].texts) == 0
    np.testing.assert_array_equal(np.asarray(grid[4].images[0].get_array()),
                                  [[0.0, 0.0625], [0.0625, 0.0]])

    # ---- the JSON: strict (NaN written as null: audit 10), every set's numbers
    data = json.loads(paths[2].read_text(encoding="utf-8"),
                      parse_constant=lambda c: pytest.fail(f"non-strict JSON {c}"))
    assert list(data) == ["table1-wind", "spectral", "simulated"]
    d = data["table1-wind"]
    assert d["labels"] == ["Z2", "Z3", "extra:Z2"] and d["lags"] == list(LAGS)
    assert (d["rate"], d["n_samples"], d["alpha"], d["n_surrogates"]) == (500.0, 900, 0.05,
                                                                          39)
    te, p = np.array(d["te"]), np.array(d["pvalue"])
    assert te.shape == p.shape == (3, 3, 8)
    np.testing.assert_array_equal(te[1, 2], [None] * 8)
    np.testing.assert_array_equal(te[0, 0], [None] * 8)
    np.testing.assert_array_equal(p[1, 2], [None] * 8)
    np.testing.assert_array_equal(te[0, 2], a.te[0, 2])
    np.testing.assert_array_equal(p[1, 0], a.pvalue[1, 0])
    assert data["spectral"]["lags"] == [1, 2] and data["spectral"]["rate"] == 250.0
    assert data["simulated"]["n_surrogates"] == 0


# ---- report and table ------------------------------------------------------------------

INTRO = (
    "## Figure 8: Information flow between modes (extension, not in the paper)\n\n"
    "![Figure 8](fig8_information_flow.png)\n\n"
    "Transfer entropy `TE[j -> i, l] = I(x_i[t]; x_j[t-l] | x_i[t-1], x_i[t-2])` of every "
    "pair of modes at lags 1, 2, 3, 5, 8, 13, 21, 34 frames "
    "(`modalinfo.information.transfer_entropy_map`, Gaussian estimator). A link is "
    "significant when its family-wise p-value is at most the level: step-down maxT "
    "(Westfall & Young) over the largest TE of the map under "
    "{n} circular time shifts of the sources, which holds the chance of any spurious link "
    "in a map at 0.05 (measured within the Monte-Carlo error on maps of 2 to 100 cells: "
    "`modalinfo.information.flow`). Bivariate TE does not separate direct from indirect "
    "transfer (a common driver shows as a link). Numbers in `fig8_information_flow.json` "
    "(null where undefined).\n")
READING = (
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
HEAD = ("| source | target | lag [frames] | lag [ms] | TE [nats] | p (family-wise) |\n"
        "|---|---|---|---|---|---|\n")


def test_report_word_for_word():
    text = fig8.report(_figure())
    expected = (
        INTRO.format(n=39) + "\n"
        "**table1-wind**: POL of a hand-made run; 3 series, n = 900 rows, 2 significant "
        "links of 6 pairs (map in 3.0 s).\n\n" + HEAD
        + "| Z2 | extra:Z2 | 5 | 10 | 0.5000 | 0.010 |\n"
        "| Z3 | Z2 | 13 | 26 | 0.2500 | 0.050 |\n\n"
        "**spectral**: spectral log; 4 series, lags 1, 2 (a short log), n = 700 rows, 7 "
        "significant links of 12 pairs (map in 0.5 s).\n\n" + HEAD
        + "| Z2 | Z3 | 2 | 8 | 0.8750 | 0.010 |\n"
        "| Z3 | Z4 | 1 | 4 | 0.7500 | 0.010 |\n"
        "| Z4 | Z5 | 2 | 8 | 0.6250 | 0.020 |\n"
        "| Z5 | Z2 | 1 | 4 | 0.5000 | 0.020 |\n"
        "| Z2 | Z4 | 2 | 8 | 0.3750 | 0.030 |\n"
        "| Z3 | Z5 | 1 | 4 | 0.2500 | 0.040 |\n\n"
        "**simulated**: simulated log; 2 series, n = 500 rows, 0 significant links of 2 "
        "pairs (map in 12.0 s).\n\n" + READING + "\n\n"
        "The table1-wind run took 12.3 s.\n")
    assert text == expected


def test_report_without_a_run_or_sets():
    text = fig8.report(_figure(run_seconds=0.0))
    assert text.endswith(READING + "\n") and "run took" not in text
    # no data set: the surrogates named are the module's 99
    assert fig8.report(fig8.FigureFlow((), False, 0.0, 0.0)) == (
        INTRO.format(n=99) + "\n" + READING + "\n")


def test_table_rows_word_for_word():
    rows = fig8.table_rows(_figure())
    why = "extension (issue 21): the paper's predictors are univariate"
    assert rows == [
        ("information flow, table1-wind: significant links (family-wise 0.05)",
         "not in the paper", "2 of 6 pairs; strongest Z2 -> extra:Z2 at 10 ms (0.5000 "
         "nats); 1 between the two WFSs", why),
        ("information flow, spectral: significant links (family-wise 0.05)",
         "not in the paper", "7 of 12 pairs; strongest Z2 -> Z3 at 8 ms (0.8750 nats)", why),
        ("information flow, simulated: significant links (family-wise 0.05)",
         "not in the paper", "0 of 2 pairs", why)]


def test_cross_sensor_count_counts_both_directions():
    # extra:Z2 -> Z2 (upper to ground) and Z2 -> extra:Z3 (ground to upper) cross, Z2 -> Z3
    # does not: 2 of 3 (a count of the links within one WFS would give 1, a count of
    # the links into the upper WFS 1)
    te, p = _blank(4, 1, 0.0625)
    labels = ("Z2", "Z3", "extra:Z2", "extra:Z3")
    for j, i, v in ((2, 0, 0.5), (0, 1, 0.25), (0, 3, 0.125)):
        te[j, i, 0], p[j, i, 0] = v, 0.01
    fs = fig8.FlowSet("table1-wind", "d", 100.0, _map(labels, (1,), te, p, [0.1], 9), 1.0)
    (row,) = fig8.table_rows(fig8.FigureFlow((fs,), False, 0.0, 0.0))
    assert row[2] == ("3 of 12 pairs; strongest extra:Z2 -> Z2 at 10 ms (0.5000 nats); "
                      "2 between the two WFSs")
    # the count is for the table1-wind set only
    fs2 = fig8.FlowSet("other", "d", 100.0, fs.flow, 1.0)
    assert fig8.table_rows(fig8.FigureFlow((fs2,), False, 0.0, 0.0))[0][2] == (
        "3 of 12 pairs; strongest extra:Z2 -> Z2 at 10 ms (0.5000 nats)")


# ---- make and the command line ---------------------------------------------------------

def _small():
    # one row of two series: a quick drawing for the command-line tests
    return fig8.FigureFlow((fig8.FlowSet("simulated", "simulated log", 1000.0, map_c(), 1.0),),
                           False, 0.0, 1.0)


@pytest.fixture
def fake_compute(monkeypatch):
    rec = _Recorder(_small)
    monkeypatch.setattr(fig8, "compute", rec)
    return rec


def test_make_draws_and_reports(tmp_path, fake_compute):
    text = fig8.make(tmp_path, quick=True, seed=4)
    assert fake_compute.calls == [((), {"quick": True, "seed": 4})]
    assert text == fig8.report(_small())
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        [fig8.FIGURE_NAME, fig8.PDF_NAME, fig8.JSON_NAME])
    fake_compute.calls.clear()
    fig8.make(tmp_path)
    assert fake_compute.calls == [((), {"quick": False, "seed": 0})]


def test_main_writes_prints_and_refuses(tmp_path, monkeypatch, capsys, fake_compute):
    out = tmp_path / "a" / "b"
    assert fig8.main(["--out", str(out), "--quick"]) == 0
    assert fake_compute.calls == [((), {"quick": True, "seed": 0})]
    assert capsys.readouterr().out == fig8.report(_small()) + "\n"
    assert sorted(p.name for p in out.iterdir()) == sorted(
        [fig8.FIGURE_NAME, fig8.PDF_NAME, fig8.JSON_NAME])
    # each of the three files alone blocks a second run without --overwrite
    for name in (fig8.FIGURE_NAME, fig8.PDF_NAME, fig8.JSON_NAME):
        d = tmp_path / name.replace(".", "_")
        d.mkdir()
        (d / name).write_bytes(b"x")
        assert fig8.main(["--out", str(d)]) == 2
        err = capsys.readouterr().err
        assert err == (f"python -m paper_figures.fig_information_flow: error: "
                       f"'{d / name}' exists; pass --overwrite\n")
        assert (d / name).read_bytes() == b"x" and len(list(d.iterdir())) == 1
        assert fig8.main(["--out", str(d), "--overwrite"]) == 0
        assert (d / name).read_bytes() != b"x"
    assert [c[1]["quick"] for c in fake_compute.calls] == [True, False, False, False]
    # the default folder: ./out
    monkeypatch.chdir(tmp_path)
    assert fig8.main([]) == 0
    assert (tmp_path / "out" / fig8.JSON_NAME).is_file()


def test_main_help(capsys):
    with pytest.raises(SystemExit) as exc:
        fig8.main(["--help"])
    assert exc.value.code == 0
    out = " ".join(capsys.readouterr().out.split())
    assert out.startswith("usage: python -m paper_figures.fig_information_flow [-h] "
                          "[--out OUT] [--overwrite] [--quick]")
    assert "[--quick] Figure 8: information flow between modes. options:" in out
    for text in ("--out OUT output directory", "--overwrite replace an existing figure",
                 "--quick shorter logs and run"):
        assert text in out
