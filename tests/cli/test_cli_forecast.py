"""Tests of ``modalinfo forecast``.

Reference: the same numbers from :func:`modalinfo.forecast.evaluate` called directly on
the log loaded with ``modalinfo.io.load`` (JSON output compared value by value), and
the dispatcher's documented exit status 2 with a one-line error on bad input.
"""

import json

import numpy as np

from modalinfo.cli import main
from modalinfo.forecast import ARMAPredictor, LinearPredictor, evaluate
from modalinfo.io import load, save
from modalinfo.telemetry import ModalLog


def _log(tmp_path):
    rng = np.random.default_rng(0)
    coeffs = np.cumsum(rng.standard_normal((800, 4)), axis=0) * 0.01
    path = tmp_path / "log.npz"
    save(ModalLog(coeffs, rate=2000.0, modes=[2, 3, 4, 5], units="rad"), path)
    return path


def test_forecast_writes_outputs_matching_library(tmp_path, capsys):
    path = _log(tmp_path)
    out = tmp_path / "res"
    code = main(["forecast", str(path), "--predictors", "linear,arma", "--modes", "2-4",
                 "--horizon", "3", "--train", "400", "--out", str(out)])
    assert code == 0
    text = capsys.readouterr().out
    assert "Whole-wavefront RMSE" in text and "| arma |" in text and "Z2" in text
    data = json.loads((out / "forecast.json").read_text())
    log = load(path).select(modes=[2, 3, 4])
    ev = evaluate({"linear": LinearPredictor(), "arma": ARMAPredictor(order=(2, 3))}, log,
                  train=400, horizons=range(1, 4))
    np.testing.assert_allclose(data["rmse_wavefront"], ev.rmse_wavefront, rtol=1e-12)
    assert data["labels"] == ["Z2", "Z3", "Z4"]
    for name in ("forecast.csv", "forecast_series.png", "forecast_rmse.png"):
        assert (out / name).stat().st_size > 100
    # refuses to overwrite, then accepts with --overwrite; --quiet prints nothing
    assert main(["forecast", str(path), "--predictors", "linear", "--out", str(out),
                 "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "--overwrite" in err and len(err.strip().splitlines()) == 1
    assert main(["forecast", str(path), "--predictors", "linear", "--out", str(out),
                 "--overwrite", "--quiet", "--train", "0.6"]) == 0
    assert capsys.readouterr().out == ""


def test_forecast_bad_input_exit_2(tmp_path, capsys):
    path = _log(tmp_path)
    cases = [
        (["--predictors", "linear,oracle"], "unknown predictor 'oracle'"),
        (["--horizon", "0"], "--horizon must be an int >= 1; got 0"),
        (["--train", "abc"], "--train must be a fraction"),
        (["--train", "795"], "--train must leave at least --horizon + 1 = 11"),
        (["--modes", "40-41"], "modes"),
    ]
    for extra, message in cases:
        assert main(["forecast", str(path), "--quiet", *extra]) == 2
        err = capsys.readouterr().err
        assert message in err, (extra, err)
        assert len(err.strip().splitlines()) == 1
    assert main(["forecast", str(tmp_path / "missing.npz")]) == 2
    assert "does not exist" in capsys.readouterr().err
