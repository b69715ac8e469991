"""Tests of ``modalinfo forecast``.

Reference: the same numbers from :func:`modalinfo.forecast.evaluate` called directly on
the log loaded with ``modalinfo.io.load`` (JSON output compared value by value), and
the dispatcher's documented exit status 2 with a one-line error on bad input. The
printed table's baselines are recomputed with NumPy from the file (persistence
``x[t + h] - x[t]`` and the training mean, over the forecast origins written out), and
each gain is the ratio of printed RMSEs.
"""

import json

import numpy as np
import pytest

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


def test_printed_baselines_are_the_errors_of_the_file(tmp_path, capsys):
    # whole-wavefront RMSE sqrt(mean over origins of sum over modes e^2); origins t = 399
    # .. 796 (the last training frame to the last with all 3 horizons ahead: 398), the
    # forecast of x[t + h] being x[t] (persistence) or the mean of the 400 training
    # frames. The table prints 4 significant digits (<= 3e-4 relative), gains 2 decimals.
    path = _log(tmp_path)
    assert main(["forecast", str(path), "--predictors", "linear", "--modes", "2-4",
                 "--horizon", "3", "--train", "400"]) == 0
    out = capsys.readouterr().out
    assert "398 origins after 400 training frames" in out
    rows = {}
    for line in out.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if cells[0] in ("persistence", "mean", "linear"):
            rows[cells[0]] = [(float(c.split()[0]), float(c.split("(x")[1].rstrip(")")))
                              for c in cells[1:]]
    x = load(path).coeffs[:, :3]
    t = np.arange(399, 797)
    mean = x[:400].mean(axis=0)
    for h in (1, 2, 3):
        persistence = np.sqrt(np.mean(np.sum((x[t + h] - x[t]) ** 2, axis=1)))
        climatology = np.sqrt(np.mean(np.sum((x[t + h] - mean) ** 2, axis=1)))
        assert rows["persistence"][h - 1] == pytest.approx((persistence, 1.0), rel=1e-3)
        assert rows["mean"][h - 1][0] == pytest.approx(climatology, rel=1e-3)
        for name in ("mean", "linear"):
            rmse, gain = rows[name][h - 1]
            assert gain == pytest.approx(rows["persistence"][h - 1][0] / rmse, abs=0.006)


def test_quiet_without_out_is_refused_before_the_work(tmp_path, capsys, monkeypatch):
    # audit 9 (issue 27): `forecast --quiet` without --out printed nothing and wrote
    # nothing, exit 0: the whole run was thrown away. It is refused in one line (exit 2)
    # before any predictor is fitted; with --out the same run succeeds silently.
    import modalinfo.forecast as forecast

    path = _log(tmp_path)
    called = []
    monkeypatch.setattr(forecast, "evaluate", lambda *a, **k: called.append(1))
    assert main(["forecast", str(path), "--predictors", "linear", "--quiet"]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and called == []
    assert captured.err.count("\n") == 1 and "--quiet without --out" in captured.err
    monkeypatch.undo()
    assert main(["forecast", str(path), "--predictors", "linear", "--horizon", "2",
                 "--quiet", "--out", str(tmp_path / "res")]) == 0
    assert capsys.readouterr().out == ""
    assert (tmp_path / "res" / "forecast.json").is_file()


@pytest.mark.parametrize("kind", ["loop", "dangling"])
def test_out_a_symlink_to_nothing_is_refused_before_the_work(tmp_path, capsys, monkeypatch,
                                                            kind):
    # audit 10-env: `--out` a symlink loop (or a dangling link) passed every check
    # (Path.exists is False for both), the whole evaluation ran, then mkdir failed:
    # "[Errno 17] File exists". Reference: POSIX symlink(7), stat(2) ELOOP / ENOENT.
    import modalinfo.forecast as forecast

    path = _log(tmp_path)
    out = tmp_path / "res"
    if kind == "loop":
        (tmp_path / "other").symlink_to(out)
        out.symlink_to(tmp_path / "other")
    else:
        out.symlink_to(tmp_path / "missing")
    called = []
    monkeypatch.setattr(forecast, "evaluate", lambda *a, **k: called.append(1))
    assert main(["forecast", str(path), "--predictors", "linear", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert called == [] and err.count("\n") == 1 and "symbolic link" in err
