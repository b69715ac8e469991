"""Figure 5 script: runs on a log file and reports numbers consistent with its JSON.

Reference: the evaluation written by the script (``fig5_forecast.json``) recomputed
with :func:`modalinfo.forecast.evaluate` on the same log loaded by
``modalinfo.io.load``; the paper's layout (three panels, ARMA fit window 0-6999, NN
training ending at 6980). The full run on ``kaos_like(seed=0)`` is marked slow.
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
    # the table in the text reproduces the JSON (h = 1 column, 4 decimals)
    for name, rmse in zip(data["names"], data["rmse_wavefront"], strict=True):
        assert f"| {name} | {rmse[0]:.4f} " in text


@pytest.mark.slow
def test_fig5_default_kaos_like(tmp_path):
    text = fig5_forecast.make(tmp_path, None)
    assert "kaos_like(seed=0)" in text and "loses to persistence" in text
    data = json.loads((tmp_path / "fig5_forecast.json").read_text())
    gains = dict(zip(data["names"], (g[0] for g in data["gain_wavefront"]), strict=True))
    assert gains["ARMA(2,3)"] > 1.0 and gains["NN paper (10 patterns)"] < 1.0
