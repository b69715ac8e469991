"""A bare predictor fitted on an array is checked against the loop's POL (fix56-b).

References: the units' factors, exact by definition (a POL in rad at 500 nm is 79.577
nm per rad, 7.96e-8 m per rad, ``lambda / 2 pi``), and the run itself: the check's own
sensings draw no value from the run's noise generator, so a noisy run with the checked
predictor equals, bit for bit, the same run with the same forecaster wrapped as trained
on this config (``trained_on`` set: not sampled). Round 53 PART a C22 / fix54-b's Left:
a predictor fitted on ``np.asarray(result.logs["dm0.pol"].coeffs)`` (no conditions) ran
unchecked, whatever its training data's units; on c423e5eb the unit tests run without
a word (they fail) and the logs carry no ``predictor_check``.
"""

import warnings

import numpy as np
import pytest

from closedloop import SimulationConfig, simulate
from closedloop.control.predictors import LoopPredictor, training_conditions
from modalinfo.forecast import LinearPredictor

from .._c01_loop import c01_config

NM_PER_RAD = 500.0 / (2 * np.pi)  # phase at r0_wavelength 500 nm


def _config(seed: int, noise: float = 0.0) -> SimulationConfig:
    # round 53's C01 loop (fix55-b's generator), 2 kHz
    return c01_config(seed, noise, name="fix56b")


@pytest.fixture(scope="module")
def pol() -> np.ndarray:
    ref = simulate(_config(0), 0.3, progress=False)
    assert ref.config.r0_wavelength == 500e-9
    return np.asarray(ref.logs["dm0.pol"].coeffs)[ref.averaging_start:]


def _fit(x: np.ndarray) -> LinearPredictor:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a short history: the fit's own notes
        return LinearPredictor(fit_weights=True).fit(x)


@pytest.mark.parametrize("factor", [NM_PER_RAD, NM_PER_RAD * 1e-9, 1.0 / NM_PER_RAD])
def test_a_predictor_trained_in_other_units_is_refused(pol, factor):
    with pytest.raises(ValueError, match=r"`predictor` 'LinearPredictor': the loop's POL "
                       r"\[rad at r0_wavelength\] has .* times the rms of the data"):
        simulate(_config(1), 0.01, predictor=_fit(pol * factor), progress=False)


def test_one_in_the_loops_units_runs_and_the_result_says_what_was_checked(pol):
    r = simulate(_config(1), 0.02, predictor=_fit(pol), progress=False)
    note = r.logs["dm0.pol"].metadata["predictor_check"]
    assert "training conditions were not checked" in note
    assert "its mode count" in note and "scale x" in note
    none = simulate(_config(1), 0.02, progress=False)
    assert "predictor_check" not in none.logs["dm0.pol"].metadata


def test_the_check_leaves_the_runs_noise_draws_alone(pol):
    config = _config(2, noise=0.05)
    p = _fit(pol)
    checked = simulate(config, 0.02, predictor=p, progress=False)
    known = LoopPredictor(name="LinearPredictor", predictor=p,
                          trained_on=training_conditions(config))
    unsampled = simulate(config, 0.02, predictor=known, progress=False)
    for name in ("dm0.pol", "dm0.residual", "dm0.commands"):
        np.testing.assert_array_equal(checked.logs[name].coeffs, unsampled.logs[name].coeffs)
    assert "checked" in unsampled.logs["dm0.pol"].metadata["predictor_check"]
