"""``MultivariatePredictor(alpha="gcv")`` and the ``multivariate`` preset (fix48-d, issue 27).

Round 47 PART a / fix48-c: the preset's fixed relative ridge (alpha 1e-3) gained 0.30 over
persistence at h = 1 on a smooth open-loop log (Z2-Z7, 10 m/s, seed 2, train 1500) where
statsmodels' OLS VAR(4) gains 183 (benchmarks/bench_var_ridge_48c.py, RESULTS.md
"fix48-c"). The preset now chooses alpha by generalised cross-validation.

References: Golub, Heath & Wahba (1979)'s GCV, ``n ||(I - H) Y||_F^2 / (n - tr H)^2``,
computed here per grid value from its definitions with ``numpy.linalg.lstsq`` on the
augmented system ``[Z_s; sqrt(alpha) I] B = [Y; 0]`` (the ridge on unit-norm lags ``Z_s``,
the predictor's relative ridge): the residual from that solution, the hat matrix ``H`` as
the map from targets to fitted values (its columns: the fits of the unit vectors), its
trace summed from the diagonal; never the SVD formula the package uses. Persistence's
error on the scored frames for the gains (``evaluate``'s gain is pinned against NumPy in
tests/forecast/test_evaluate.py).
"""

import warnings

import numpy as np
import pytest

from modalinfo.forecast import MultivariatePredictor, RLSMultivariatePredictor, evaluate
from modalinfo.forecast.multivariate import GCV_GRID
from modalinfo.forecast.presets import PRESETS, make_predictor

from .conftest import noisy_var, smooth_log

ORDER = 4


def _reference_gcv(x, order):
    """GCV score per grid value, and the ridge weights (original units), by lstsq."""
    xc = x - x.mean(axis=0)
    n_rows = len(xc) - order
    Z = np.hstack([xc[order - i:len(xc) - i] for i in range(1, order + 1)])
    Y = xc[order:]
    norm = np.sqrt(np.sum(Z ** 2, axis=0))
    Zs = Z / norm
    k = Zs.shape[1]
    well_conditioned = np.linalg.cond(Zs) <= 1 / np.sqrt(np.finfo(float).eps)
    scores, weights = {}, {}
    for alpha in GCV_GRID:
        if alpha == 0.0 and not well_conditioned:
            continue
        A = np.vstack([Zs, np.sqrt(alpha) * np.eye(k)])
        B = np.linalg.lstsq(A, np.vstack([Y, np.zeros((k, Y.shape[1]))]), rcond=None)[0]
        # hat matrix: fitted values of each unit target vector
        E = np.vstack([np.eye(n_rows), np.zeros((k, n_rows))])
        H = Zs @ np.linalg.lstsq(A, E, rcond=None)[0]
        rss = np.sum((Y - Zs @ B) ** 2)
        scores[alpha] = n_rows * rss / (n_rows - np.trace(H)) ** 2
        weights[alpha] = (B / norm[:, None]).reshape(order, x.shape[1], x.shape[1])
    return scores, weights


def test_grid_is_zero_and_half_decades_to_one():
    assert GCV_GRID[0] == 0.0
    np.testing.assert_allclose(GCV_GRID[1:], 10.0 ** np.arange(-10, 0.25, 0.5), rtol=1e-15)


@pytest.mark.parametrize("make, order", [(lambda: noisy_var(160, 3), 4),
                                         (lambda: noisy_var(400, 1), 4),
                                         (lambda: smooth_log(600, 2), 2)])
def test_chosen_alpha_minimises_gcv_computed_from_its_definition(make, order):
    x = make()
    pred = MultivariatePredictor(order=order, alpha="gcv").fit(x)
    scores, weights = _reference_gcv(x, order)
    ranked = sorted(scores, key=scores.get)
    # the minimum is not a rounding tie: the runner-up's score is measurably larger
    assert scores[ranked[1]] > scores[ranked[0]] * (1 + 1e-9)
    assert pred.alpha_ == ranked[0]
    np.testing.assert_allclose(pred.coef_, weights[ranked[0]], rtol=1e-6,
                               atol=1e-9 * np.abs(weights[ranked[0]]).max())


def test_rank_deficient_lags_never_get_alpha_zero():
    """A duplicated mode: the scaled lags are singular (condition 5e20), alpha 0 is out."""
    x = smooth_log(600, 2)
    x = np.column_stack([x, x[:, 0]])
    scores, weights = _reference_gcv(x, 2)
    assert 0.0 not in scores
    best = min(scores, key=scores.get)
    pred = MultivariatePredictor(order=2, alpha="gcv").fit(x)
    assert pred.alpha_ == best > 0
    assert np.all(np.isfinite(pred.coef_))


def test_preset_beats_persistence_on_asmooth_log():
    """Before: gain 0.30 at h = 1 (alpha 1e-3); statsmodels' OLS VAR(4) gains 183."""
    x = smooth_log()
    ev = evaluate({"multivariate": make_predictor("multivariate")}, x, train=1500,
                  horizons=[1])
    assert ev.gain_wavefront[ev.index("multivariate"), 0] > 10


def test_preset_with_a_duplicated_mode_is_finite_and_beats_persistence():
    """Singular lags: GCV's 1e-10 ridge, gain 135 / 29 at h = 1 / 5 (before: 0.32 / 0.56)."""
    x = smooth_log()
    x = np.column_stack([x, x[:, 0]])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # evaluate's Diebold-Mariano notes, not the fit's
        ev = evaluate({"multivariate": make_predictor("multivariate")}, x, train=1500,
                      horizons=[1, 5])
    gain = ev.gain_wavefront[ev.index("multivariate")]
    assert np.all(np.isfinite(gain))
    assert np.all(gain > 10), gain


def test_refits_choose_again():
    """Fitted on a noisy VAR (GCV 10^-0.5), refitted online on a smooth log (GCV 0)."""
    noisy = noisy_var(400, 1)
    smooth = smooth_log(600, 2)[:, :3]
    pred = MultivariatePredictor(order=4, alpha="gcv", refit_every=500, window=500)
    pred.fit(noisy)
    fitted = pred.alpha_
    assert fitted == MultivariatePredictor(order=4, alpha="gcv").fit(noisy).alpha_
    for row in smooth[:500]:
        pred.update(row)
    again = MultivariatePredictor(order=4, alpha="gcv").fit(smooth[:500]).alpha_
    assert pred.alpha_ == again != fitted


def test_a_number_is_its_own_alpha_and_presets_say_which():
    x = noisy_var(400, 1)
    assert MultivariatePredictor(order=4, alpha=0.05).fit(x).alpha_ == 0.05
    assert make_predictor("multivariate").alpha == "gcv"
    assert make_predictor("rls").alpha == 1e-3
    assert PRESETS["multivariate"][0] == "multivariate VAR(4)"


@pytest.mark.parametrize("cls, alpha, match", [
    (MultivariatePredictor, "GCV", "`alpha` must be a number >= 0 or 'gcv'; got 'GCV'"),
    (RLSMultivariatePredictor, "gcv", "`alpha` must be a number >= 0 for "
                                      "RLSMultivariatePredictor"),
])
def test_bad_alpha_strings_are_refused(cls, alpha, match):
    with pytest.raises(ValueError, match=match):
        cls(order=2, alpha=alpha).fit(noisy_var(400, 1))


def test_chosen_alpha_at_few_rows_review31b():
    """Few regression rows (n - tr H small): the GCV denominator's exact degrees of freedom
    decide the choice. Review 31b planted ``dof = n - tr H + 1`` in ``_gcv_ridge``; the
    three logs above kept their choices under it. Reference: ``_reference_gcv`` (lstsq)."""
    checked = 0
    for seed in range(200):
        x = noisy_var(64, seed)
        scores, _ = _reference_gcv(x, 2)
        ranked = sorted(scores, key=scores.get)
        if scores[ranked[1]] <= scores[ranked[0]] * (1 + 1e-6):
            continue  # a near tie: either choice is GCV's
        checked += 1
        assert MultivariatePredictor(order=2, alpha="gcv").fit(x).alpha_ == ranked[0], seed
    assert checked >= 150
