"""A failed NN training is said, not swallowed (adversarial round 45 PART a, N45 / N32).

Reference: scikit-learn itself. ``MLPRegressor`` built by hand on the same 10-lag
windows and seed raises its own ``ConvergenceWarning`` ("lbfgs failed to converge after
25 iteration(s) (status=2): ABNORMAL") and reports ``n_iter_`` = 25 < ``max_iter`` =
100: the line search failed, the network did not train. ``NeuralNetPredictor`` recorded
that in ``converged_`` and said nothing. With ``standardize=False`` on a log in nm
(root mean square ~2000) the hidden tanh units saturate (tanh(5) = 0.9999) and the
forecasts were nearly constant, again without a word.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from sklearn.exceptions import ConvergenceWarning
from sklearn.neural_network import MLPRegressor

from modalinfo.forecast import NeuralNetPredictor


def _ar2(n, seed):
    rng = np.random.default_rng(seed)
    e = rng.standard_normal(n + 200)
    x = np.zeros(n + 200)
    for t in range(2, n + 200):
        x[t] = 1.6 * x[t - 1] - 0.7 * x[t - 2] + e[t]
    return x[200:]


def _hand(x, k=10):
    """scikit-learn by hand: the predictor's network on raw (unstandardised) windows."""
    inputs = np.stack([x[t - k:t] for t in range(k, len(x))])
    model = MLPRegressor(hidden_layer_sizes=(10,), activation="tanh", solver="lbfgs",
                         alpha=1.0, max_iter=100, random_state=0, tol=1e-6)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model.fit(inputs, x[k:])
    return model, [w for w in caught if issubclass(w.category, ConvergenceWarning)]


def test_abnormal_lbfgs_stop_warns_naming_column_and_iterations():
    x = _ar2(400, 9) * 1e4 + 1e5
    model, hand_warnings = _hand(x)
    assert hand_warnings and model.n_iter_ < 100  # scikit-learn: a failed line search
    with pytest.warns(ConvergenceWarning) as record:
        p = NeuralNetPredictor(standardize=False).fit(x[:, None])
    ours = [w for w in record if "NeuralNetPredictor.fit" in str(w.message)]
    assert len(ours) == 1
    text = str(ours[0].message)
    assert f"column 0 after {model.n_iter_}" in text
    assert "max_iter = 100" in text and "standardize=True" in text
    assert ours[0].filename == __file__  # names the caller's line
    assert p.models_[0].n_iter_ == model.n_iter_
    assert not p.converged_[0]


def test_standardize_false_far_from_unit_scale_warns():
    # N45: AR(2) in nm (x 500 / 2 pi) with a 2000 nm static offset
    x = _ar2(2000, 9) * 500 / (2 * np.pi) + 2000.0
    with pytest.warns(ConvergenceWarning,
                      match=r"standardize=False and the root mean square of 1 training "
                            r"column\(s\) exceeds 5 \(column 0: 2\.0\de\+03\)"):
        NeuralNetPredictor(standardize=False, max_iter=20).fit(x[:, None])


def test_no_warning_when_training_is_fine():
    x = _ar2(2000, 9)  # rad, root mean square ~4.3 < 5
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        NeuralNetPredictor(standardize=False, max_iter=20).fit(x[:, None])
        NeuralNetPredictor(max_iter=20).fit((x * 500 / (2 * np.pi) + 2000.0)[:, None])
