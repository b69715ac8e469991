"""Figure 5 script (paper_figures.fig5_forecast): compute / plot / report / table rows.

References: the table of the report recomputed independently with numpy on the
coefficients written to the log: the whole-wavefront RMSE of persistence
(x[t+h] = x[t]), of the training mean and of the paper's linear extrapolation
(x[t+1] = 2 x[t] - x[t-1]) over the origins t = 6999 .. T - 11, and the gains
RMSE_persistence / RMSE; the lag-1 correlation of the increments and the ARMA panel's
error and interval count recomputed from the series; the paper's layout (three panels,
ARMA fit window 0-6999, NN training ending at 6980) and its numbers (ARMA(2,3), an
accurate forecast over 2-3 ms; Stangalini et al., Section 4). Log: 7100 frames x 2
modes of an ARMA(1,1) process, computed once per module; the full run on
``kaos_like(seed=0)`` is marked slow.
"""

import dataclasses
import json
from collections import Counter

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.io import load, save
from modalinfo.telemetry import ModalLog
from paper_figures import fig5_forecast

HS = [1, 2, 3, 5, 10]


@pytest.fixture(scope="module")
def log_file(tmp_path_factory):
    rng = np.random.default_rng(0)
    coeffs = lfilter([1.0, -0.3], [1.0, -0.9], rng.standard_normal((7100, 2)), axis=0) * 0.01
    path = tmp_path_factory.mktemp("fig5") / "log.npz"
    save(ModalLog(coeffs, rate=2000.0, modes=[2, 3], units="rad"), path)
    return path, coeffs


@pytest.fixture(scope="module")
def result(log_file):
    path, _ = log_file
    return fig5_forecast.compute(load(path), source="an ARMA(1,1) log")


def _rows(text):
    return {line.split("|")[1].strip(): line.split("|")[2:-1] for line in text.splitlines()
            if line.startswith("| ") and "(x" in line}


def test_make_writes_the_figure_and_json(log_file, result, tmp_path, monkeypatch):
    # make = load + compute + plot + report. Its compute is this module's ``result`` (the
    # same function on the same file, which the other tests check), given make's source
    # text: one fit of every predictor per module instead of two.
    path, coeffs = log_file
    calls = []

    def computed_once(log, *, source):
        calls.append(source)
        np.testing.assert_array_equal(np.asarray(log.coeffs), coeffs)  # make read the file
        return dataclasses.replace(result, source=source)

    monkeypatch.setattr(fig5_forecast, "compute", computed_once)
    text = fig5_forecast.make(tmp_path / "out", path)
    assert len(calls) == 1
    assert (tmp_path / "out" / "fig5_forecast.png").stat().st_size > 10_000
    assert (tmp_path / "out" / "fig5_forecast.pdf").read_bytes()[:4] == b"%PDF"
    data = json.loads((tmp_path / "out" / "fig5_forecast.json").read_text())
    assert data["n_train"] == 7000 and data["labels"] == ["Z2", "Z3"]
    assert "**`Z2`**" in text and "fitted on frames\n  0-6999" in text
    assert f"Input: `{path}`" in text


def test_report_table_against_numpy(result, log_file):
    _, coeffs = log_file
    text = fig5_forecast.report(result)
    origins = np.arange(6999, coeffs.shape[0] - 10)
    train_mean = coeffs[:7000].mean(axis=0)

    def rmse(pred, h):
        return np.sqrt(np.mean(np.sum((coeffs[origins + h] - pred) ** 2, axis=1)))

    pers = [rmse(coeffs[origins], h) for h in HS]
    want = {"persistence": pers, "mean": [rmse(train_mean, h) for h in HS]}
    lin1 = rmse(2 * coeffs[origins] - coeffs[origins - 1], 1)
    rows = _rows(text)
    for name, values in want.items():
        for cell, value, p in zip(rows[name], values, pers, strict=True):
            rmse_text, gain_text = cell.split()
            assert float(rmse_text) == pytest.approx(value, abs=6e-5), (name, cell)
            assert float(gain_text.strip("(x)")) == pytest.approx(p / value, abs=6e-3)
    lin_rmse, lin_gain = rows["linear (a=2, b=-1)"][0].split()
    assert float(lin_rmse) == pytest.approx(lin1, abs=6e-5)
    assert float(lin_gain.strip("(x)")) == pytest.approx(pers[0] / lin1, abs=6e-3)
    assert result.gain("linear (a=2, b=-1)") == pytest.approx(pers[0] / lin1, rel=1e-9)


def test_result_fields_and_report_numbers(result, log_file):
    _, coeffs = log_file
    assert isinstance(result, fig5_forecast.Figure5)
    assert (result.n_frames, result.n_modes, result.label) == (7100, 2, "Z2")
    assert result.frame_ms == 0.5 and result.t_unit == "ms"
    np.testing.assert_array_equal(result.x, coeffs[:, 0])
    # the lag-1 correlation of the increments on the training frames
    d = np.diff(coeffs[:7000], axis=0)
    d -= d.mean(axis=0)
    rho = [np.dot(d[1:, m], d[:-1, m]) / np.dot(d[:, m], d[:, m]) for m in range(2)]
    np.testing.assert_allclose(result.increment_correlation, rho, rtol=1e-12)
    # panel (b): largest error and values inside the interval, from the series
    y = coeffs[7000:7010, 0]
    err = np.max(np.abs(y - result.arma_interval_mean))
    inside = np.sum((result.arma_interval_lower <= y) & (y <= result.arma_interval_upper))
    assert result.arma_forecast_max_error == err and result.arma_forecast_inside == inside
    text = fig5_forecast.report(result)
    assert f"{inside}/10 measured\n  values inside, largest error {err:.3g} rad" in text
    assert "an ARMA(1,1) log, 7100 frames x 2 modes at 2000 Hz" in text
    ev = result.evaluation
    for name in ev.names:
        cells = _rows(text)[name]
        for cell, h in zip(cells, HS, strict=True):
            j = list(ev.horizons).index(h)
            assert cell.strip() == (f"{ev.rmse_wavefront[ev.index(name), j]:.4f} "
                                    f"(x{ev.gain_wavefront[ev.index(name), j]:.2f})")
    g = {name: ev.gain_wavefront[ev.index(name), 0] for name in ev.names}
    assert f"ARMA(2,3), as in the paper, gains x{g['ARMA(2,3)']:.2f} at h = 1" in text
    assert f"mode gives x{g['ARMA (AIC)']:.2f}" in text
    assert (f"x{min(result.paper_nn_gains):.2f} and x{max(result.paper_nn_gains):.2f}"
            in text)
    assert f"Best at h = 1: **{max(g, key=g.get)}**" in text
    if result.gain("linear (a=2, b=-1)") < 1:
        assert f"increments is {np.mean(rho):.2f} on average" in text
    else:
        assert f"mean lag-1 increment correlation {np.mean(rho):.2f}" in text
    p, q = result.aic_orders[0]
    assert f"picks ({p},{q}) for `Z2`" in text
    assert f"_(computed in {result.elapsed:.1f} s)_" in text


def _accurate(gains):
    """Longest h such that every gain at horizons 1..h is > 1 (horizons 1..10)."""
    h = 0
    for g in gains:
        if not g > 1:
            break
        h += 1
    return h


def test_table_rows_come_from_the_result(result):
    rows = fig5_forecast.table_rows(result)
    assert [r[:2] for r in rows] == [("best ARMA order (p,q)", "(2,3)"),
                                     ("forecast horizon that stays accurate", "2-3 ms")]
    assert all(len(r) == 4 for r in rows)
    counts = Counter(map(tuple, result.aic_orders.tolist()))
    top = max(counts.values())
    (p, q) = min(o for o, c in counts.items() if c == top)  # ties: smallest (p, q)
    assert rows[0][2] == f"({p},{q}) ({top}/2 modes)"
    ev = result.evaluation
    g_arma = ev.gain_wavefront[ev.index("ARMA(2,3)")]
    g_aic = ev.gain_wavefront[ev.index("ARMA (AIC)")]
    assert f"picks ({p},{q}) for {top} of 2 modes" in rows[0][3]
    assert f"and (2,3) for {counts.get((2, 3), 0)}" in rows[0][3]
    assert f"x{g_arma[0]:.2f}" in rows[0][3] and f"x{g_aic[0]:.2f}" in rows[0][3]
    best = ev.names[int(np.argmax(ev.gain_wavefront[:, 0]))]
    g_best = ev.gain_wavefront[ev.index(best)]

    def cell(gains):
        h = _accurate(gains)
        return f"{'>= ' if h == 10 else ''}{h * 0.5:g} ms ({h} frames)"

    assert rows[1][2] == f"ARMA(2,3): {cell(g_arma)}; {best}: {cell(g_best)}"
    assert result.accurate_horizon("ARMA(2,3)") == _accurate(g_arma)
    assert result.accurate_horizon("linear (a=2, b=-1)") == _accurate(
        ev.gain_wavefront[ev.index("linear (a=2, b=-1)")])
    assert "longest horizon up to which the predictor beats persistence" in rows[1][3]
    assert f"{ev.origins.size} origins" in rows[1][3]
    assert f"x{g_arma[-1]:.2f} at h = 10" in rows[1][3]


def test_plot_and_report_take_a_suffix(result, tmp_path):
    paths = fig5_forecast.plot(result, tmp_path, suffix="_kaos")
    assert [p.name for p in paths] == fig5_forecast.output_names("_kaos") == [
        "fig5_forecast_kaos.png", "fig5_forecast_kaos.pdf", "fig5_forecast_kaos.json"]
    assert paths[0].stat().st_size > 10_000 and paths[1].read_bytes()[:4] == b"%PDF"
    assert json.loads(paths[2].read_text())["names"] == list(result.evaluation.names)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(paths[i].name
                                                                for i in range(3))
    assert "![Figure 5](fig5_forecast_kaos.png)" in fig5_forecast.report(result,
                                                                          suffix="_kaos")


def test_compute_refuses_a_short_log():
    log = ModalLog(np.zeros((7040, 2)), rate=2000.0, modes=[2, 3], units="rad")
    with pytest.raises(ValueError, match="at least 7041 frames"):
        fig5_forecast.compute(log)


def test_main_refuses_to_overwrite_the_json(tmp_path, capsys):
    (tmp_path / "fig5_forecast_a.json").write_text("mine")
    assert fig5_forecast.main(["--out", str(tmp_path), "--suffix", "_a"]) == 2
    assert "fig5_forecast_a.json" in capsys.readouterr().err
    assert (tmp_path / "fig5_forecast_a.json").read_text() == "mine"


@pytest.mark.slow
def test_fig5_default_kaos_like(tmp_path):
    text = fig5_forecast.make(tmp_path, None)
    assert "kaos_like(seed=0)" in text and "loses to persistence" in text
    data = json.loads((tmp_path / "fig5_forecast.json").read_text())
    gains = dict(zip(data["names"], (g[0] for g in data["gain_wavefront"]), strict=True))
    assert gains["ARMA(2,3)"] > 1.0 and gains["NN paper (10 patterns)"] < 1.0


def test_quick_is_the_full_computation_on_the_first_modes(log_file, result, monkeypatch):
    # quick evaluates the first QUICK_MODES modes (1 here, of the log's 2) and the paper's
    # NN over QUICK_PAPER_SEEDS. Reference: the full computation (``result``) on the same
    # log: every predictor that fits one model per mode from that mode's own column
    # gives the same numbers on the first mode (to the rounding of sums over a
    # different number of columns: 1e-12 relative), the AIC order of that mode is the
    # same, the paper's NN gains are the full run's for those seeds. (The NNs
    # standardise with a mean over all columns and train by L-BFGS, which can amplify a
    # last-bit difference; the multivariate and info predictors use the other modes.)
    path, coeffs = log_file
    monkeypatch.setattr(fig5_forecast, "QUICK_MODES", 1)
    quick = fig5_forecast.compute(load(path), source="an ARMA(1,1) log", quick=True)
    assert quick.quick and not result.quick
    ev, full = quick.evaluation, result.evaluation
    assert ev.labels == ("Z2",) and full.labels == ("Z2", "Z3")
    assert ev.names == full.names
    np.testing.assert_array_equal(ev.origins, full.origins)
    for name in ("persistence", "mean", "linear (a=2, b=-1)", "linear (LS a, b)",
                 "ARMA(2,3)", "ARMA (AIC)"):
        i = ev.index(name)
        np.testing.assert_allclose(ev.rmse[i, :, 0], full.rmse[full.index(name), :, 0],
                                   rtol=1e-12, err_msg=name)
    np.testing.assert_array_equal(quick.aic_orders, result.aic_orders[:1])
    assert quick.paper_nn_seeds == fig5_forecast.QUICK_PAPER_SEEDS == (0, 1)
    assert quick.paper_nn_gains == result.paper_nn_gains[:2]
    # the panels and the per-mode statistics of the log are the full run's
    for name in ("x", "linear_one_step", "arma_interval_mean", "nn_one_step",
                 "nn_paper_one_step", "increment_correlation"):
        np.testing.assert_array_equal(getattr(quick, name), getattr(result, name))
    # the report says it is a smoke run, and counts the modes it evaluated
    text = " ".join(fig5_forecast.report(quick).split())
    assert ("**Quick settings** (`--quick`): a smoke run, numbers not the paper's: the "
            "evaluation and the AIC orders on the first 1 of the 2 modes, the paper's NN "
            "over 2 seeds.") in text
    assert "over seeds 0-1" in text and "over the 1 modes" in text
    assert "Quick settings" not in fig5_forecast.report(result)
    assert fig5_forecast.table_rows(quick)[0][2].endswith("(1/1 modes)")
