"""A user's own predictors through evaluate (adversarial round 44 PART a, E02 - E07, E09).

References: numpy (the log is compared with its copy, byte for byte), the error classes
and messages the package states for plug-ins (docs/ARCHITECTURE.md, `modalinfo.forecast`),
and the forecasts of an AR(1) recursion computed by hand (0.5^h x[t]). Before the fixes a
subclass overriding the public predict / update was scored as its parent (E02), one with
only the public methods reached AttributeError (E03), NaN parameters gave a NaN table (E04),
parameters of one mode on a 3-mode log made the kernel write past its arrays (SIGABRT,
E05), a `_fit_params` / `_filter` writing into its samples wrote into the user's log (E06,
E07), and an `__init__` that did not store its argument reached AttributeError (E09).
"""
import subprocess
import sys

import numpy as np
import pytest

from modalinfo.forecast import LinearPredictor, PersistencePredictor, evaluate
from modalinfo.forecast.base import Predictor


def _log(n=600, m=3, seed=0):
    r = np.random.default_rng(seed)
    x = np.zeros((n, m))
    for t in range(2, n):
        x[t] = 1.6 * x[t - 1] - 0.7 * x[t - 2] + r.standard_normal(m)
    return x


class Damped(PersistencePredictor):
    """AR(1) with phi = 0.5 about 0: forecasts 0.5^h x[t]."""

    def _fit_params(self, X, previous, name):
        p = super()._fit_params(X, previous, name)
        p["phi"] = 0.5 * np.ones((X.shape[1], 1))
        return p


def test_a_users_recursion_is_scored_as_computed_by_hand():
    x = _log()
    ev = evaluate({"damped": Damped()}, x, train=300, horizons=[1, 3])
    o = ev.origins
    for j, h in enumerate([1, 3]):
        hand = np.sqrt(np.mean((x[o + h] - 0.5 ** h * x[o]) ** 2, axis=0))
        np.testing.assert_allclose(ev.rmse[ev.index("damped"), j], hand, rtol=1e-12)


class Biased(LinearPredictor):
    def predict(self, history, horizon=None):
        return super().predict(history, horizon) + 100.0

    def update(self, x_t):
        return super().update(x_t) + 100.0


class OnlyPublic(Predictor):
    def __init__(self, *, horizon=10, refit_every=None, window=None):
        super().__init__(horizon=horizon, refit_every=refit_every, window=window)

    def fit(self, history):
        return self

    def predict(self, history, horizon=None):
        return np.repeat(np.asarray(history)[-1:], horizon or self.horizon, axis=0)

    def update(self, x_t):
        return np.repeat(np.asarray(x_t)[None], self.horizon, axis=0)


@pytest.mark.parametrize("cls", [Biased, OnlyPublic])
def test_public_overrides_evaluate_would_not_call_are_refused(cls):
    with pytest.raises(TypeError, match=rf"\({cls.__name__}\) defines its own predict and "
                                        "update, which evaluate does not call"):
        evaluate({"mine": cls()}, _log(), train=300, horizons=[1])


class NaNParams(PersistencePredictor):
    def _fit_params(self, X, previous, name):
        p = super()._fit_params(X, previous, name)
        p["phi"] = np.full((X.shape[1], 1), np.nan)
        return p


def test_non_finite_parameters_are_refused_naming_the_class():
    with pytest.raises(ValueError, match=r"NaNParams._fit_params returned a non-finite "
                                         r"value in parameter 'phi'"):
        evaluate({"nan": NaNParams()}, _log(), train=300, horizons=[1])


class OneMode(PersistencePredictor):
    def _fit_params(self, X, previous, name):
        return {"mu": np.zeros(1), "phi": np.ones((1, 1)), "theta": np.zeros((1, 0))}


def test_parameters_of_the_wrong_shape_are_refused():
    # in process: the refusal comes before the kernel (which wrote past its arrays)
    with pytest.raises(ValueError, match=r"OneMode._fit_params returned 'mu' of shape "
                                         r"\(1,\); the recursion reads \(M,\) with M = 3"):
        OneMode().fit(_log())


def test_parameters_of_the_wrong_shape_do_not_crash_evaluate():
    # a subprocess: before the fix the interpreter aborted (SIGABRT, heap corruption)
    code = (
        "import numpy as np\n"
        "from modalinfo.forecast import PersistencePredictor, evaluate\n"
        "class OneMode(PersistencePredictor):\n"
        "    def _fit_params(self, X, previous, name):\n"
        "        return {'mu': np.zeros(1), 'phi': np.ones((1, 1)), "
        "'theta': np.zeros((1, 0))}\n"
        "x = np.random.default_rng(0).standard_normal((600, 3)).cumsum(0)\n"
        "try:\n"
        "    evaluate({'w': OneMode()}, x, train=300, horizons=[1])\n"
        "except ValueError as e:\n"
        "    print('REFUSED', e)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=300)
    assert out.returncode == 0, out.stderr[-500:]
    assert "REFUSED OneMode._fit_params returned 'mu'" in out.stdout


class WritesHistory(PersistencePredictor):
    def _fit_params(self, X, previous, name):
        X[:] = 0.0
        return super()._fit_params(X, previous, name)


class WritesBlock(PersistencePredictor):
    def _filter(self, params, state, X, out, status):
        super()._filter(params, state, X, out, status)
        X[...] = 1e6


@pytest.mark.parametrize("cls", [WritesHistory, WritesBlock])
def test_a_users_hooks_cannot_write_into_the_log(cls):
    x = _log()
    keep = x.copy()
    with pytest.raises(ValueError, match="read-only"):
        evaluate({"w": cls()}, x, train=300, horizons=[1])
    assert np.array_equal(x, keep)


class NoStore(LinearPredictor):
    def __init__(self, gain=2.0, **kw):
        super().__init__(**kw)
        self._g = gain


def test_an_init_argument_not_stored_is_named():
    with pytest.raises(TypeError, match=r"NoStore.__init__ takes `gain` but the object "
                                        "has no attribute of that name"):
        evaluate({"ns": NoStore(gain=3.0)}, _log(), train=300, horizons=[1])
