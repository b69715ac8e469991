"""The closed-loop trainer records, without a warning, the ARMA modes held at root_margin.

Reference (fix57-a; round 55 PART a's "Left"): the least-squares AR(2) of each trained
POL mode, by ``numpy.linalg.lstsq`` on its lagged values (no intercept, the series
centred), and its inverse-root moduli by ``numpy.roots``. The loop tests' 0.15 s
no-prediction run has smooth modes whose least-squares AR(2) roots are at or beyond
the default limit ``1 / (1 + 1e-3)``; the ARMA(2, 3) fit holds its roots there on many
of them (a true statement). ``LoopPredictor.trained`` fits without warning (the loop
uses point forecasts a delay ahead and states no interval) and the trained forecaster's
``roots_held_`` names those modes; ``forecast_std`` of it still says so.
"""

import warnings

import numpy as np
import pytest

from closedloop.control.predictors import LoopPredictor, training_data
from modalinfo.forecast.arma import RootLimitWarning

from . import test_loop

cfg, model, reference = test_loop.cfg, test_loop.model, test_loop.reference

LIMIT = 1.0 / (1.0 + 1e-3)


def _ls_ar2_radius(x: np.ndarray) -> float:
    xc = (x - x.mean()) / x.std()
    design = np.column_stack([xc[1:-1], xc[:-2]])
    a = np.linalg.lstsq(design, xc[2:], rcond=None)[0]
    return float(np.max(np.abs(np.roots([1.0, -a[0], -a[1]]))))


def test_trained_arma_records_held_modes_silently(reference):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no warning from the trainer's fit
        trained = LoopPredictor.from_name("arma").trained(reference)
    fit = trained.predictor
    held = fit.roots_held_
    assert held.shape == (fit.ar_coef_.shape[0],) and held.dtype == bool
    assert held.any()
    data = training_data(reference)
    ls = np.array([_ls_ar2_radius(data[:, m]) for m in range(data.shape[1])])
    # a held mode's series asks for a root at or beyond the limit (the reference's own
    # least-squares AR(2), to the rounding of another solver), and sits at the limit
    assert np.all(ls[held] >= LIMIT * (1 - 1e-6))
    np.testing.assert_allclose(fit.ar_radius_[held], LIMIT, atol=1e-9)
    with pytest.warns(RootLimitWarning, match=f"{int(held.sum())} mode\\(s\\)"):
        fit.forecast_std(2)
