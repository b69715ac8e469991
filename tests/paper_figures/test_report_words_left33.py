"""Figure 5's words on the increments follow the correlation printed beside them.

Issue 27, leftovers 33-report item 1. Reference, outside the code: the lag-1
correlation of the increments of a series written here, computed with numpy
(``np.corrcoef`` of consecutive differences) on the ARMA fit window (frames 0-6999),
and its sign and size against 0.5, the threshold of the linear extrapolation
x[n+1] = 2 x[n] - x[n-1] (its one-step error Delta x[n+1] - Delta x[n] has variance
2 (1 - rho) Var(Delta x), persistence's Var(Delta x)). The report is built from the
hand-made ``Figure5`` of the mutation-gap tests (``_figure``, whose linear gain is x0.75,
or x1.10 with a replaced evaluation), its increment correlations replaced by those
measured here: "rough, anti-correlated" was printed whenever the extrapolation lost to
persistence, also beside a mean correlation of 0.30.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.signal import lfilter

from paper_figures import fig5_forecast as fig5

from .test_mutation_gaps_fig5_forecast import GAINS, FakeEvaluation, _figure


def _integrated_ar1(phi: float, n_modes: int = 6, seed: int = 0) -> np.ndarray:
    """7100 frames whose increments are an AR(1) of coefficient ``phi``, the series their sum."""
    e = np.random.default_rng(seed).standard_normal((7100, n_modes))
    return np.cumsum(lfilter([1.0], [1.0, -phi], e, axis=0), axis=0)


def _numpy_rho(x: np.ndarray) -> np.ndarray:
    d = np.diff(x[:7000], axis=0)
    return np.array([np.corrcoef(d[1:, m], d[:-1, m])[0, 1] for m in range(d.shape[1])])


def _lines(rho: np.ndarray, gains=GAINS) -> str:
    f = dataclasses.replace(_figure(evaluation=FakeEvaluation(gains=gains)),
                            increment_correlation=rho)
    text = fig5.report(f)
    start = text.index("- The paper's linear extrapolation")
    return " ".join(text[start:text.index("- ARMA(2,3), as in the paper")].split())


@pytest.mark.parametrize("phi, words", [
    (0.3, "has weakly correlated increments (positively, but below the 0.5 the "
          "extrapolation needs)."),
    (-0.3, "has rough, anti-correlated increments."),
    (0.0, None),  # the sign of the printed mean decides: numpy's value says which
])
def test_the_words_follow_the_measured_correlation(phi, words):
    x = _integrated_ar1(phi)
    rho = _numpy_rho(x)
    mean = f"{np.mean(rho):.2f}"
    text = _lines(rho)
    assert "**loses to persistence**" in text  # the hand-made gain x0.75
    assert f"the increments is {mean} on average over the modes" in text
    if words is None:  # phi = 0: the measured mean is within sampling noise of 0
        words = ("has rough, anti-correlated increments." if float(mean) < 0 else
                 "has rough, uncorrelated increments (those of a random walk)."
                 if float(mean) == 0 else "has weakly correlated increments")
    assert f"your log `my.npz` {words}" in text
    if float(mean) >= 0:
        assert "anti-correlated" not in text


def test_a_printed_zero_is_not_anti_correlated():
    text = _lines(np.array([-0.004, 0.0, 0.001, -0.002, 0.0, 0.0]))  # mean -0.0008
    assert "on average over the modes (-0.00 to 0.00)" in text
    assert "has rough, uncorrelated increments (those of a random walk)." in text


def test_a_mean_above_half_with_a_losing_wavefront_says_why():
    # mean 0.6 (numpy) while the extrapolation loses on the wavefront: the gain weighs
    # the modes by their increment variance, on other frames
    rho = _numpy_rho(_integrated_ar1(0.6))
    assert np.mean(rho) > 0.5
    text = _lines(rho)
    assert "has increments correlated at 0.5 or more on average, yet the extrapolation" in text
    assert "weighs each mode by its increment variance and is measured on the frames " \
           "after 6999, the mean weighs the modes equally on frames 0-6999." in text
    assert "anti-correlated" not in text


def test_a_winning_extrapolation_states_the_comparison_the_number_supports():
    gains = GAINS.copy()
    gains[1] = 1.1  # the linear extrapolation beats persistence
    high = _numpy_rho(_integrated_ar1(0.7))
    text = _lines(high, gains)
    assert (f"gains x1.10 over persistence at h = 1 (mean lag-1 increment correlation "
            f"{np.mean(high):.2f} > 0.5).") in text
    low = _numpy_rho(_integrated_ar1(0.3))
    text = _lines(low, gains)
    assert f"(mean lag-1 increment correlation {np.mean(low):.2f}, not above 0.5: " in text
    assert "> 0.5)" not in text
