"""Round 36 PART b, O17: a refit that reads the training frames again is not a refit.

Reference: the refit schedule's arithmetic (refits after ``n`` frames on the ``window``
frames before, ``n`` a multiple of ``refit_every``) and NumPy: with 300 training frames and
``refit_every=300`` (window = the training length) the only refit in range comes after 300
frames, on frames 0..299 - the training frames - so the sliding mean equals the training
mean at every origin (checked with NumPy below), while the settings recorded the refits.
Before the fix the schedule was accepted; with ``window=299`` the same refit reads other
frames and is kept.
"""

import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.forecast import MeanPredictor, evaluate
from modalinfo.io import save
from modalinfo.telemetry import ModalLog


def _x(n=600, m=2):
    return np.random.default_rng(36).standard_normal((n, m))


def test_a_refit_on_the_training_frames_is_refused_by_evaluate():
    x = _x()  # origins 299..598; refits after 300 (the training frames) and 600 (none)
    with pytest.raises(ValueError, match=r"never refit a forecast: the first refit comes "
                       r"after 600 frames \(the one after 300 frames refits the 300 "
                       r"training frames themselves\) and the last forecast origin is "
                       r"frame 598"):
        evaluate({"m": MeanPredictor()}, x, train=300, horizons=[1], refit_every=300)


def test_the_same_refit_on_another_window_is_the_numpy_sliding_mean():
    # window 299: the refit after 300 frames reads x[1:300], used from origin 300 on
    x = _x()
    ev = evaluate({"m": MeanPredictor()}, x, train=300, horizons=[1], refit_every=300,
                  window=299)
    origins = np.arange(299, 599)
    fc = np.tile(x[:300].mean(axis=0), (origins.size, 1))
    fc[1:] = x[1:300].mean(axis=0)
    want = np.sqrt(((x[origins + 1] - fc) ** 2).sum(axis=1).mean())
    assert ev.rmse_wavefront[ev.index("m"), 0] == pytest.approx(want, rel=1e-12)


def test_forecast_refuses_it_in_one_line(tmp_path, capsys):
    path = tmp_path / "log.npz"
    save(ModalLog(_x(2000, 3), rate=2000.0, modes=[2, 3, 4], units="rad"), path)
    code = main(["forecast", str(path), "--predictors", "linear", "--horizon", "1",
                 "--refit-every", "1000", "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err, err
    assert "refits the 1000 training frames themselves" in err
    assert not (tmp_path / "out").exists()
