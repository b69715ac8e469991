"""Forecasts scored on frames unlike their training frames (Leftovers 28-shift, issue 27).

Round 28 PART b, N07: ``modalinfo forecast`` of a log whose loop opens half-way trained
on the closed half and scored on the open half (10x the rms) without a word; its 95 %
intervals covered 0.55-0.16. ``evaluate`` now compares, per mode, the test frames'
mean square innovation of an AR(4) model fitted on the training frames with the
training one (``ForecastEvaluation.scale_shift``) and warns once.

References (outside the code): the AR(1) law - a model ``x_t = 0.9 x_(t-1) + e`` frozen
on frames whose law is ``x_t = 0.999 x_(t-1) + u`` (rms 0.5) leaves innovations of mean
square ``(0.999 - 0.9)^2 0.25 + 0.25 (1 - 0.999^2) = 2.95e-3`` against the training
``0.05^2 (1 - 0.81) = 4.75e-4`` (x6.2; rms x2.5); stationary AR(1) logs simulated with
``scipy.signal.lfilter``; the false-alarm count against the 1 % family-wise level
(binomial: at most 2 of 200 is the brief's ">= 99 % silent"); the one-sided F law
(``scipy.stats.f``) for the ratio's spread on a stationary log.
"""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest
from scipy import stats
from scipy.signal import lfilter

from modalinfo.forecast import evaluate


def _ar1(rng, n, phi, rms, m):
    e = rng.standard_normal((n, m)) * rms * np.sqrt(1.0 - phi**2)
    e[0] = rng.standard_normal(m) * rms                   # a stationary start
    return lfilter([1.0], [1.0, -phi], e, axis=0)


def _loop_opens(seed=1):
    rng = np.random.default_rng(seed)
    return np.vstack([_ar1(rng, 4000, 0.9, 0.05, 2), _ar1(rng, 4000, 0.999, 0.5, 2)])


def test_loop_opening_is_named(tmp_path):
    log = _loop_opens()
    with pytest.warns(UserWarning, match="differ in scale from the training frames") as rec:
        ev = evaluate({}, log, train=0.5, horizons=(1, 10))
    assert sum("differ in scale" in str(w.message) for w in rec) == 1     # once
    assert ev.shifted_modes == ev.labels
    # frozen-model innovations x6.2 in mean square by the AR(1) law (a 4000-frame
    # segment of AR(1) 0.999 holds ~2 correlation times, so its own variance wanders)
    assert np.all(ev.scale_shift > 2.0)
    text = ev.summary()
    lines = [ln for ln in text.splitlines() if ln.startswith("Train/test scale shift")]
    assert len(lines) == 1 and "retrain" in lines[0]
    ev.to_json(tmp_path / "f.json")
    data = json.loads((tmp_path / "f.json").read_text())
    assert data["shifted_modes"] == list(ev.labels)
    np.testing.assert_allclose(data["scale_shift"], np.sqrt(ev.scale_shift))


def test_calmer_test_frames_are_named_too():
    # seeing improves x2.5 in rms at the split: the intervals are too wide there
    rng = np.random.default_rng(3)
    log = np.vstack([_ar1(rng, 3000, 0.9, 1.0, 3), _ar1(rng, 3000, 0.9, 0.4, 3)])
    with pytest.warns(UserWarning, match="differ in scale"):
        ev = evaluate({}, log, train=0.5, horizons=1)
    np.testing.assert_allclose(np.sqrt(ev.scale_shift), 0.4, rtol=0.1)
    assert len(ev.shifted_modes) == 3


def test_stationary_logs_stay_silent():
    # 200 seeds of a stationary AR(1) 0.9 log (6 modes x 2000 frames, half trained):
    # the rule is 1 % family-wise, so >= 99 % of the logs must be silent (measured: 0)
    from modalinfo._stats import SHIFT_ALPHA
    from modalinfo.forecast.evaluate import _scale_shift

    warned = 0
    ratios = []
    for seed in range(200):
        x = _ar1(np.random.default_rng(seed), 2000, 0.9, 1.0, 6)
        ratio, _, shifted = _scale_shift(x, x[:1000], 1000, 8192, SHIFT_ALPHA)
        warned += bool(shifted.any())
        ratios.append(ratio)
    assert warned <= 2
    ratios = np.concatenate(ratios)
    # the per-mode ratio follows F(1000, 991) to within sampling: its 1 % / 99 %
    # quantiles 0.86 / 1.16; 1200 ratios put ~12 outside each, binomial sd 3.5
    lo, hi = stats.f.ppf([0.01, 0.99], 1000, 991)
    assert np.sum(ratios < lo) <= 12 + 4 * 3.5 and np.sum(ratios > hi) <= 12 + 4 * 3.5


def test_stationary_evaluate_is_silent():
    x = _ar1(np.random.default_rng(7), 4000, 0.95, 0.1, 4)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ev = evaluate({}, x, train=0.5, horizons=(1, 5))
    assert ev.shifted_modes == ()
    assert np.all(np.abs(np.sqrt(ev.scale_shift) - 1.0) < 0.1)


def test_cli_prints_it_in_one_line(tmp_path, capsys):
    from modalinfo.cli import main
    from modalinfo.io import save
    from modalinfo.telemetry import ModalLog

    path = tmp_path / "loopopen.npz"
    save(ModalLog(_loop_opens(), rate=2000.0, modes=[2, 3], units="rad"), path)
    with pytest.warns(UserWarning, match="differ in scale") as rec:
        assert main(["forecast", str(path), "--predictors", "linear", "--horizon", "2"]) == 0
    assert sum("differ in scale" in str(w.message) for w in rec) == 1
    shown = [ln for ln in capsys.readouterr().out.splitlines() if "scale shift" in ln]
    assert len(shown) == 1 and shown[0].startswith("Train/test scale shift: Z2 x")
    assert "Z3 x" in shown[0] and "retrain" in shown[0]


def test_batch_row_carries_it():
    # a batch worker's warning reaches no one: the row says it (no warning raised here)
    from modalinfo.batch.analyses import _forecast, resolve_params
    from modalinfo.telemetry import ModalLog

    log = ModalLog(_loop_opens(), rate=2000.0, modes=[2, 3], units="rad")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        row = _forecast(log, resolve_params("forecast", {"predictors": "linear",
                                                         "horizon": 2}))
    assert row["shifted_modes"] == "Z2,Z3"
    assert row["scale_shift_max"] > 2.0 ** 0.5          # rms ratio; AR(1) law x2.5


@pytest.mark.parametrize("scale", [1e-100, 1e150])
def test_scale_free(scale):
    # the ratio is scale-free: the same log at 1e-100 / 1e150 (squares representable; fourth
    # powers of the raw innovations would not be) gives the same ratios, no warning but
    # the shift's own
    log = _loop_opens()
    with pytest.warns(UserWarning, match="differ in scale") as rec:
        ev = evaluate({}, log * scale, train=0.5, horizons=1)
    assert len(rec) == 1
    with pytest.warns(UserWarning, match="differ in scale"):
        ref = evaluate({}, log, train=0.5, horizons=1)
    np.testing.assert_allclose(ev.scale_shift, ref.scale_shift, rtol=1e-9)
