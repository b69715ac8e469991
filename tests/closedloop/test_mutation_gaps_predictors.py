"""closedloop.control.predictors: names, sentinels, the training window and the fit, no loop.

Gaps found by mutation testing (docs/MUTATION.md, "kinds.py, resources.py, predictors.py,
training.py"). No loop runs: the reference run is a stand-in holding what a
``SimulationResult`` gives the training (``predictor``, ``config.dms``, the ``dmK.pol``
logs' ``coeffs``, ``times``, ``averaging_start``, ``diverged``), written in the test;
for the runs that did not close or diverged, real ``SimulationResult``s built from the
residual histories of tests/closedloop/test_result_window.py, whose status and window
are known by construction. References, from outside the code:

- the paper's training window: after the loop closure and from t > 15 ms (module
  docstring), picked here by hand from times written as decimals; the closure is the
  run's one averaging window (docs/CLOSEDLOOP.md, "One averaging window per run": the
  second half ``T // 2`` of a run that did not close), and a diverged run is refused;
- an analytic law: a series that is an exact AR(2), ``x_k = 1.5 x_{k-1} - 0.7 x_{k-2}``
  (noise-free after its two first values), is fitted by the least-squares linear predictor
  (``linear-ls``) to ``(a, b) = (1.5, -0.7)`` to rounding, and a noisy one within its
  sampling error; ``statsmodels``' ``AutoReg(trend="c")`` gives the same weights and
  intercept on the window (``trend="n"`` before fix 41-a added the intercept);
- the names: ``modalinfo.forecast.presets.PRESETS`` (the one list) plus the three
  sentinels; every refusal's whole message as the docstrings state it.
"""

from __future__ import annotations

import re
import warnings
from types import SimpleNamespace

import numpy as np
import pytest

from closedloop.control import predictors as predictors_module
from closedloop.control.predictors import (
    NAMES,
    NO_PREDICTION,
    ORACLE,
    REFERENCE_POL,
    LoopPredictor,
    loop_predictor,
    training_data,
    training_start,
)
from modalinfo.forecast import LinearPredictor
from modalinfo.forecast.presets import PRESETS


def _ar2(n: int, modes: int, *, noise: float = 0.0, seed: int = 0) -> np.ndarray:
    """``(n, modes)`` AR(2) series ``x_k = 1.5 x_{k-1} - 0.7 x_{k-2} + noise e_k``."""
    rng = np.random.default_rng(seed)
    x = np.zeros((n, modes))
    x[0], x[1] = rng.normal(size=modes), rng.normal(size=modes)
    for k in range(2, n):
        x[k] = 1.5 * x[k - 1] - 0.7 * x[k - 2] + noise * rng.normal(size=modes)
    return x


def _reference(pols, *, closure: int = 0, predictor: str = "none", dt_ms: int = 1):
    """A no-prediction run's stand-in: POL logs per DM, times ``k dt`` written as decimals.

    A loop that closed at frame ``closure`` (its averaging window starts there).
    """
    n = pols[0].shape[0]
    return SimpleNamespace(
        predictor=predictor,
        config=SimpleNamespace(dms=tuple(range(len(pols)))),
        logs={f"dm{i}.pol": SimpleNamespace(coeffs=p) for i, p in enumerate(pols)},
        times=np.array([k * dt_ms / 1000 for k in range(n)]),
        closure_index=closure, averaging_start=closure, diverged=False,
        loop_status="closed")


# ---------------------------------------------------------------- the training window
def test_training_starts_after_15_ms_and_after_the_closure():
    pol = np.zeros((100, 1))
    # 1-ms frames: t = 15 ms is frame 15; the paper trains from t > 15 ms: frame 16
    assert training_start(_reference([pol], closure=0)) == 16
    assert training_start(_reference([pol], closure=16)) == 16
    assert training_start(_reference([pol], closure=40)) == 40
    # 0.5-ms frames: 15 ms is frame 30 -> 31; 2-ms frames: 14 ms, 16 ms -> frame 8
    half = _reference([pol], closure=3)
    half.times = np.array([k / 2000 for k in range(100)])
    assert training_start(half) == 31
    assert training_start(_reference([pol], closure=0, dt_ms=2)) == 8
    assert isinstance(training_start(_reference([pol])), int)


def test_a_run_that_did_not_close_trains_on_its_second_half():
    from modalinfo.telemetry import ModalLog

    from .test_result_views import _result
    from .test_result_window import N, _never_rose

    # an SR peak that never rose: "closure" frame 0 (the open-loop start), window N // 2;
    # 1-ms frames, so t > 15 ms alone would start at frame 15 (times (k + 1) ms)
    pol = np.arange(N * 2.0).reshape(N, 2)
    r = _result(_never_rose(), logs={"dm0.pol": ModalLog(pol, rate=1e3, modes=[2, 3])})
    assert r.loop_status.startswith("did not close") and r.closure_index == 0
    assert training_start(r) == N // 2 == 50
    np.testing.assert_array_equal(training_data(r), pol[50:])
    # a diverged run (closes at frame 1, then grows to 9 times its lowest level): refused
    grown = _result(np.concatenate([[2.0], np.full(20, 0.1), np.full(N - 21, 0.9)]))
    assert grown.diverged and grown.closure_index == 1
    msg = ("the reference run diverged: the residual grew to 9.0 times its lowest 5-ms mean "
           "(0.9 against 0.1 rad^2, field mean); a predictor cannot be trained on its POL "
           "(fix the loop first: a lower gain, a shorter delay).")
    with pytest.raises(ValueError, match="^" + re.escape(msg) + "$"):
        training_start(grown)


def test_training_data_is_every_dm_s_pol_side_by_side_from_the_start():
    a = np.arange(200.0).reshape(50, 4)
    b = -np.arange(100.0).reshape(50, 2)
    data = training_data(_reference([a, b], closure=20))
    np.testing.assert_array_equal(data, np.hstack([a[20:], b[20:]]))
    one = training_data(_reference([a], closure=0))
    np.testing.assert_array_equal(one, a[16:])


def test_training_needs_20_frames_after_the_start():
    ok = _reference([np.ones((36, 2))])  # frames 16..35: 20
    assert training_data(ok).shape == (20, 2)
    short = _reference([np.ones((35, 2))])
    msg = ("the reference run has 19 frames after its loop closure; run it longer to "
           "train a predictor.")
    with pytest.raises(ValueError, match="^" + re.escape(msg) + "$"):
        training_data(short)


def test_training_refuses_a_run_with_a_predictor():
    msg = ("training needs the no-prediction run; got a run with predictor "
           "'linear-ls'.")
    with pytest.raises(ValueError, match="^" + re.escape(msg) + "$"):
        training_data(_reference([np.ones((60, 2))], predictor="linear-ls"))


# ---------------------------------------------------------------- names and sentinels
def test_the_names_are_the_presets_and_the_three_sentinels():
    assert NAMES == ("none", "persistence", "oracle", *PRESETS)
    assert REFERENCE_POL == "reference-pol" and predictors_module._PAPER_TRAINING_START == 15e-3
    assert NO_PREDICTION == LoopPredictor(name="none")
    assert (ORACLE.name, ORACLE.predictor, ORACLE.training, ORACLE.oracle) == (
        "oracle", None, None, True)
    assert (NO_PREDICTION.predictor, NO_PREDICTION.training, NO_PREDICTION.oracle) == (
        None, None, False)
    assert NO_PREDICTION.is_none and not ORACLE.is_none
    assert not NO_PREDICTION.needs_training and not ORACLE.needs_training


@pytest.mark.parametrize("name", [n for n in NAMES if n not in ("none", "oracle",
                                                                  "persistence")])
def test_each_name_gives_a_fresh_untrained_forecaster_of_its_preset(name):
    spec = LoopPredictor.from_name(name)
    assert type(spec.predictor) is type(PRESETS[name][1]())
    assert (spec.name, spec.training, spec.oracle) == (name, REFERENCE_POL, False)
    assert spec.needs_training and not spec.is_none
    assert repr(spec) == f"LoopPredictor({name!r}, untrained)"
    assert LoopPredictor.from_name(name).predictor is not spec.predictor


def test_the_sentinel_names_give_the_sentinels():
    assert LoopPredictor.from_name("none") is NO_PREDICTION
    assert LoopPredictor.from_name("oracle") is ORACLE
    assert repr(ORACLE) == "LoopPredictor('oracle')"


@pytest.mark.parametrize("name", ["kalman", "ARMA", "", None, 3, ("none",)])
def test_an_unknown_name_is_refused_listing_the_names(name):
    msg = f"`predictor` must be one of {', '.join(NAMES)}; got {name!r}."
    with pytest.raises(ValueError, match="^" + re.escape(msg) + "$"):
        LoopPredictor.from_name(name)


def test_a_fitted_forecaster_is_wrapped_ready_and_named_by_its_class():
    fitted = LinearPredictor().fit(_ar2(40, 2))
    spec = LoopPredictor.from_fitted(fitted)
    assert (spec.name, spec.predictor, spec.training, spec.oracle) == (
        "LinearPredictor", fitted, None, False)
    assert not spec.needs_training and not spec.is_none
    assert repr(spec) == "LoopPredictor('LinearPredictor')"
    assert LoopPredictor.from_fitted(fitted, name="mine").name == "mine"


@pytest.mark.parametrize("thing", [object(), SimpleNamespace(update=len),
                                   SimpleNamespace(reset=len)])
def test_a_forecaster_without_reset_and_update_is_refused(thing):
    msg = ("`predictor` must have reset() and update(x) (a modalinfo.forecast Predictor); "
           f"got {type(thing).__name__}.")
    with pytest.raises(TypeError, match="^" + re.escape(msg) + "$"):
        LoopPredictor.from_fitted(thing)


# ---------------------------------------------------------------- the fit
def test_trained_fits_the_window_to_the_ar2_law_and_leaves_the_spec_alone():
    pols = [_ar2(120, 2, seed=1), _ar2(120, 1, seed=2)]
    # garbage before the window: a fit that used it would not find the law
    for p in pols:
        p[:30] = np.random.default_rng(9).normal(size=(30, p.shape[1])) * 50
    reference = _reference(pols, closure=30)
    spec = LoopPredictor.from_name("linear-ls")
    trained = spec.trained(reference)
    np.testing.assert_allclose(trained.predictor.coef_, np.tile([1.5, -0.7], (3, 1)),
                               atol=1e-8)
    assert (trained.name, trained.training, trained.oracle) == ("linear-ls", None, False)
    assert not trained.needs_training and repr(trained) == "LoopPredictor('linear-ls')"
    # the spec's forecaster is untouched (copied before the fit)
    assert spec.needs_training and not hasattr(spec.predictor, "params_")
    assert trained.predictor is not spec.predictor


def test_trained_on_a_noisy_series_is_statsmodels_autoreg():
    from statsmodels.tsa.ar_model import AutoReg

    pol = _ar2(400, 1, noise=1.0, seed=4)
    trained = LoopPredictor.from_name("linear-ls").trained(_reference([pol], closure=0))
    fit = AutoReg(pol[16:, 0], lags=2, trend="c").fit()  # linear-ls has an intercept
    np.testing.assert_allclose(trained.predictor.coef_[0], fit.params[1:], rtol=1e-8)
    np.testing.assert_allclose(trained.predictor.intercept_[0], fit.params[0], rtol=1e-6,
                               atol=1e-10 * np.abs(pol).max())
    np.testing.assert_allclose(fit.params[1:], [1.5, -0.7], atol=0.1)


def test_trained_with_a_basis_fits_the_projected_pol():
    pols = [_ar2(120, 3, seed=5)]
    basis = np.array([[1.0, 0.0], [1.0, 1.0], [0.0, 2.0]])
    spec = LoopPredictor.from_name("linear-ls")
    projected = spec.trained(_reference(pols), basis=basis)
    # a linear combination of the same AR(2) law is that law
    assert projected.predictor.coef_.shape == (2, 2)
    np.testing.assert_allclose(projected.predictor.coef_, np.tile([1.5, -0.7], (2, 1)),
                               atol=1e-8)
    hand = LinearPredictor(fit_weights=True).fit(pols[0][16:] @ basis)
    np.testing.assert_array_equal(projected.predictor.coef_, hand.coef_)


def test_trained_leaves_a_forecaster_with_mutable_state_untouched():
    class Recording:
        """A forecaster whose fit writes into a list it holds (in place)."""

        def __init__(self):
            self.seen = []

        def fit(self, data):
            self.seen.append(data.shape)
            return self

    spec = LoopPredictor(name="mine", predictor=Recording(), training=REFERENCE_POL)
    trained = spec.trained(_reference([np.ones((60, 3))]))
    assert trained.predictor.seen == [(44, 3)]
    assert spec.predictor.seen == []  # "self is unchanged": a deep copy was fitted


def test_nothing_to_train_returns_the_same_spec():
    reference = _reference([np.ones((60, 1))], predictor="arma")  # never read
    assert ORACLE.trained(reference) is ORACLE
    assert NO_PREDICTION.trained(reference) is NO_PREDICTION
    ready = LoopPredictor.from_fitted(LinearPredictor().fit(_ar2(40, 1)))
    assert ready.trained(reference) is ready


# ---------------------------------------------------------------- simulate's argument
def test_loop_predictor_reads_each_kind_of_argument():
    spec = LoopPredictor.from_name("arma")
    assert loop_predictor(spec) is spec and loop_predictor(ORACLE) is ORACLE
    assert loop_predictor(None) is NO_PREDICTION
    fitted = LinearPredictor().fit(_ar2(40, 1))
    wrapped = loop_predictor(fitted)
    assert wrapped.predictor is fitted and wrapped.name == "LinearPredictor"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert loop_predictor("oracle") is ORACLE
    assert [w.category for w in caught] == [DeprecationWarning]
    assert str(caught[0].message) == ("simulate(predictor='oracle') is deprecated; pass "
                                      "closedloop.ORACLE.")


@pytest.mark.parametrize("name", ["arma", "none", "ORACLE"])
def test_loop_predictor_refuses_other_names_pointing_to_the_training(name):
    msg = (f"`predictor` must be a LoopPredictor, a fitted Predictor or None; got the name "
           f"{name!r} (a name is trained first: closedloop.run_trained(config, name, ...) or "
           f"LoopPredictor.from_name(name).trained(reference)).")
    with pytest.raises(ValueError, match="^" + re.escape(msg) + "$"):
        loop_predictor(name)


def test_loop_predictor_refuses_what_is_no_predictor():
    with pytest.raises(TypeError, match=r"^`predictor` must have reset\(\) and update\(x\) "
                                        r"\(a modalinfo.forecast Predictor\); got int\.$"):
        loop_predictor(3)
