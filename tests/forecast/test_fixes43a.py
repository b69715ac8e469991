"""Fixes of round 43 PART a (issue 27): a model setting changed after ``fit``, and results.

References outside the package:

- S03 / S37 / S38 / S57: scikit-learn's convention that ``set_params`` leaves the fitted
  attributes as they were until ``fit``. Before the fix the package then forecast with the
  old model while ``get_params()`` reported the new one (ARMA fitted with order (2, 0),
  set to (1, 0): AR(2) forecasts, bit-equal to before; ``update`` carried on mid-pass; with
  ``refit_every`` the pass switched to AR(1) at its first refit). Now ``predict``,
  ``predict_interval``, ``reset`` and ``update`` refuse, naming the setting and "call
  fit()"; after ``fit`` the object forecasts as a fresh one built with the new setting
  (numpy's least squares for the fitted linear extrapolation).
- U11: ``to_json`` and ``summary()`` name the units; the CSV now does, in a last ``units``
  column read back by ``csv.DictReader`` (the other columns as before).
- C12 / C21: a ModalLog passed where an array is expected: the hint ``ModalLog(log)``
  itself gives, "(use log.coeffs)".
- C35: a test half stuck at one value has no scale-shift judgement (NaN, as documented);
  ``summary()`` names the modes not judged.
"""

from __future__ import annotations

import csv

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.forecast import (
    ARMAPredictor,
    LinearPredictor,
    MultivariatePredictor,
    evaluate,
    lag1_autocorrelations,
)
from modalinfo.telemetry import ModalLog


def _ar2(n=2400, seed=0, modes=1):
    """AR(2) x[t] = 0.5 x[t-1] + 0.2 x[t-2] + e[t] (scipy's lfilter), one column per mode."""
    x = lfilter([1.0], [1.0, -0.5, -0.2], np.random.default_rng(seed).standard_normal((n, modes)),
                axis=0)
    return x[:, 0] if modes == 1 else x


@pytest.mark.parametrize("make, change", [
    (lambda: ARMAPredictor(order=(2, 0)), {"order": (1, 0)}),          # S03
    (lambda: LinearPredictor(), {"fit_weights": True}),                  # S57
    (lambda: MultivariatePredictor(order=2), {"alpha": 0.5}),
])
def test_model_setting_changed_after_fit_is_refused_until_fit(make, change):
    x = _ar2(modes=2)
    p = make().fit(x[:1500])
    p.update(x[0])  # an online pass under way (S37)
    p.set_params(**change)
    name = next(iter(change))
    for call in (lambda: p.predict(x), lambda: p.update(x[1]), p.reset):
        with pytest.raises(ValueError, match=rf"`{name}` .* changed since fit\(\).*call fit\(\)"):
            call()
    p.fit(x[:1500])  # re-estimated: forecasts as a fresh object built with the setting
    fresh = make().set_params(**change).fit(x[:1500])
    np.testing.assert_array_equal(p.predict(x), fresh.predict(x))
    np.testing.assert_array_equal(p.update(x[0]), fresh.update(x[0]))


def test_refit_policy_does_not_switch_models_mid_pass():
    # S38: AR(2) forecasts until the first refit, then AR(1)'s, in one pass
    x = _ar2()
    p = ARMAPredictor(order=(2, 0), refit_every=500).fit(x[:1000])
    for v in x[1000:1100]:
        p.update(v)
    p.set_params(order=(1, 0))
    with pytest.raises(ValueError, match="`order` \\(2, 0\\) -> \\(1, 0\\)"):
        p.update(x[1100])
    with pytest.raises(ValueError, match="`order`"):
        p.predict_interval(x)


def test_setting_back_and_forecast_time_settings_are_accepted():
    x = _ar2()
    p = ARMAPredictor(order=(2, 0)).fit(x[:1500])
    before = p.predict(x)
    p.set_params(order=(1, 0)).set_params(order=(2, 0))
    np.testing.assert_array_equal(p.predict(x), before)
    p.update(x[0])
    p.set_params(level=0.5)  # read by predict_interval only: the pass goes on
    p.update(x[1])
    i50 = p.predict_interval(x, horizon=1)
    i95 = p.set_params(level=0.95).predict_interval(x, horizon=1)
    # normal quantiles: half-widths 0.674 and 1.960 standard deviations
    np.testing.assert_allclose((i50.upper - i50.lower) / (i95.upper - i95.lower),
                               0.6744897501960817 / 1.959963984540054, rtol=1e-9)


def _log(units="rad", n=1200):
    x = _ar2(n=n, modes=2) * 0.01
    return ModalLog(x, rate=1000.0, modes=[2, 3], units=units)


def test_forecast_csv_names_its_units(tmp_path):
    # U11
    log = _log()
    nm = log.to_units("nm", wavelength=500e-9) if log.wavelength is None else log.to_units("nm")
    ev = evaluate([LinearPredictor()], nm, train=600, horizons=[1, 2])
    path = ev.to_csv(tmp_path / "f.csv")
    with open(path, newline="") as fh:
        reader = csv.DictReader(fh)
        rows = list(reader)
    assert reader.fieldnames[:9] == ["predictor", "mode", "horizon", "rmse", "gain",
                                     "coverage", "dm_statistic", "p_value", "beats_baseline"]
    assert reader.fieldnames[-1] == "units"
    assert rows and {r["units"] for r in rows} == {"nm"}
    wf = [r for r in rows if r["predictor"] == "linear" and r["mode"] == "wavefront"]
    assert [float(r["rmse"]) for r in wf] == [float(v) for v in
                                               ev.rmse_wavefront[ev.index("linear")]]


def test_modal_log_where_an_array_is_expected_hints_coeffs():
    # C12 / C21; since fix54-b ``Predictor.fit`` takes a ModalLog (its coeffs, labels and
    # metadata): the same parameters as on ``log.coeffs``
    log = _log()
    a, b = LinearPredictor().fit(log), LinearPredictor().fit(np.asarray(log.coeffs))
    assert all(np.array_equal(a.params_[k], b.params_[k]) for k in a.params_)
    with pytest.raises(TypeError, match=r"\(use log\.coeffs\)"):
        lag1_autocorrelations(log)


def test_summary_names_modes_without_a_scale_shift_judgement():
    # C35: random-walk (open-loop-like) training frames, the test half stuck at one value:
    # too few effective training values to judge (documented NaN)
    x = np.random.default_rng(0).standard_normal((2000, 2)).cumsum(0) * 0.01
    x[1000:] = x[1000]
    log = ModalLog(x, rate=1000.0, modes=[2, 3], units="rad")
    ev = evaluate([LinearPredictor()], log, train=1000, horizons=[1])
    assert np.isnan(ev.scale_shift).all()
    assert "scale shift not judged for Z2, Z3" in ev.summary()
