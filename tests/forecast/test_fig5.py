"""Figure 5 script: runs on a log file and reports the right numbers.

References: the table of the report recomputed independently with numpy on the
coefficients written to the log: the whole-wavefront RMSE of persistence
(x[t+h] = x[t]), of the training mean and of the paper's linear extrapolation
(x[t+1] = 2 x[t] - x[t-1]) over the origins t = 6999 .. T - 11, and the gains
RMSE_persistence / RMSE; the paper's layout (three panels, ARMA fit window 0-6999,
NN training ending at 6980). The full run on ``kaos_like(seed=0)`` is marked slow.
"""

import json

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.io import save
from modalinfo.telemetry import ModalLog
from paper_figures import fig5_forecast


def test_fig5_on_a_log_file(tmp_path):
    rng = np.random.default_rng(0)
    coeffs = lfilter([1.0, -0.3], [1.0, -0.9], rng.standard_normal((7100, 2)), axis=0) * 0.01
    path = tmp_path / "log.npz"
    save(ModalLog(coeffs, rate=2000.0, modes=[2, 3], units="rad"), path)
    text = fig5_forecast.make(tmp_path / "out", path)
    assert (tmp_path / "out" / "fig5_forecast.png").stat().st_size > 10_000
    data = json.loads((tmp_path / "out" / "fig5_forecast.json").read_text())
    assert data["n_train"] == 7000 and data["labels"] == ["Z2", "Z3"]
    assert "**Z2**" in text and "fitted on frames\n  0-6999" in text
    # the table's numbers against a numpy recomputation (h = 1, 2, 3, 5, 10)
    hs = [1, 2, 3, 5, 10]
    origins = np.arange(6999, coeffs.shape[0] - 10)
    train_mean = coeffs[:7000].mean(axis=0)

    def rmse(pred, h):
        return np.sqrt(np.mean(np.sum((coeffs[origins + h] - pred) ** 2, axis=1)))

    pers = [rmse(coeffs[origins], h) for h in hs]
    want = {
        "persistence": pers,
        "mean": [rmse(train_mean, h) for h in hs],
    }
    lin1 = rmse(2 * coeffs[origins] - coeffs[origins - 1], 1)
    rows = {line.split("|")[1].strip(): line.split("|")[2:-1] for line in text.splitlines()
            if line.startswith("| ") and "(x" in line}
    for name, values in want.items():
        for cell, value, p in zip(rows[name], values, pers, strict=True):
            rmse_text, gain_text = cell.split()
            assert float(rmse_text) == pytest.approx(value, abs=6e-5), (name, cell)
            assert float(gain_text.strip("(x)")) == pytest.approx(p / value, abs=6e-3)
    lin_rmse, lin_gain = rows["linear (a=2, b=-1)"][0].split()
    assert float(lin_rmse) == pytest.approx(lin1, abs=6e-5)
    assert float(lin_gain.strip("(x)")) == pytest.approx(pers[0] / lin1, abs=6e-3)


@pytest.mark.slow
def test_fig5_default_kaos_like(tmp_path):
    text = fig5_forecast.make(tmp_path, None)
    assert "kaos_like(seed=0)" in text and "loses to persistence" in text
    data = json.loads((tmp_path / "fig5_forecast.json").read_text())
    gains = dict(zip(data["names"], (g[0] for g in data["gain_wavefront"]), strict=True))
    assert gains["ARMA(2,3)"] > 1.0 and gains["NN paper (10 patterns)"] < 1.0
