"""Round 35 PART b, Q00 / Q01: a refit schedule no scored forecast uses is refused.

Reference: the refit schedule's arithmetic (refits after ``n`` frames, ``n`` a multiple of
``refit_every`` and at least ``window``; the forecast at origin ``t`` uses the refits with
``n <= t``) and NumPy: the training mean refitted on a sliding window, computed by hand
over the forecast origins. Before the fix ``--refit-every 5000`` or ``--window 5000`` on a
2000-frame log ran, recorded the refits in forecast.json, and every number was that of
the parameters fitted once.
"""

import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.forecast import LinearPredictor, MeanPredictor, evaluate
from modalinfo.io import save
from modalinfo.telemetry import ModalLog


def _x(n=600, m=2):
    return np.cumsum(np.random.default_rng(35).standard_normal((n, m)), axis=0) * 0.01


@pytest.mark.parametrize(("refit", "window"), [(5000, None), (100, 5000), (598, None)])
def test_evaluate_refuses_refits_after_the_last_origin(refit, window):
    # 600 frames, train 300, horizon 1: origins 299..598; refit 598 with the default
    # window 300 comes after 598 frames: used from origin 598 (accepted, below); 5000 and
    # a 5000-frame window never
    x = _x()
    if refit == 598:
        evaluate({"ls": LinearPredictor(fit_weights=True)}, x, train=300, horizons=[1],
                 refit_every=refit, window=window)
        return
    with pytest.raises(ValueError, match=r"`refit_every` = \d+ with `window` = \d+.* would "
                       r"never refit a forecast: the first refit comes after 5000 frames "
                       r"and the last forecast origin is frame 598 of the log's 600"):
        evaluate({"ls": LinearPredictor(fit_weights=True)}, x, train=300, horizons=[1],
                 refit_every=refit, window=window)


def test_a_refit_at_the_last_origin_is_the_numpy_sliding_mean():
    # the accepted edge: one refit after 598 frames on the 300 before, used by the forecast
    # at origin 598 only (NumPy: the mean of x[298:598])
    x = np.random.default_rng(35).standard_normal((600, 2))  # white: an honest DM test
    ev = evaluate({"m": MeanPredictor()}, x, train=300, horizons=[1], refit_every=598)
    origins = np.arange(299, 599)
    fc = np.tile(x[:300].mean(axis=0), (origins.size, 1))
    fc[-1] = x[298:598].mean(axis=0)
    want = np.sqrt(((x[origins + 1] - fc) ** 2).sum(axis=1).mean())
    assert ev.rmse_wavefront[ev.index("m"), 0] == pytest.approx(want, rel=1e-12)


def test_forecast_refuses_idle_refits_in_one_line(tmp_path, capsys):
    path = tmp_path / "log.npz"
    save(ModalLog(_x(2000, 3), rate=2000.0, modes=[2, 3, 4], units="rad"), path)
    for extra in (["--refit-every", "5000"], ["--refit-every", "100", "--window", "5000"]):
        code = main(["forecast", str(path), "--predictors", "linear-ls", "--horizon", "2",
                     *extra])
        err = capsys.readouterr().err
        assert code == 2 and err.count("\n") == 1 and "Traceback" not in err
        assert "--refit-every" in err and "--window" in err and "never refit" in err
