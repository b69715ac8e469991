"""The white share of a target at ~4x white noise is measured (round 49 PART a N13, fix50-c).

x drives y (VAR(1): x' = 0.9 x + e, y' = 0.5 y + 0.4 x + f, unit innovations) and x is
observed with white noise of variance 20 (its signal's is 1 / (1 - 0.81) = 5.26: WFS noise
of ~4x the signal). Reference: the closed form of the white share of x's variance,
N / (S + N) = 20 / 25.26 = 0.792 (S from scipy's ``solve_discrete_lyapunov``). Its
autocorrelation at lags 1-3 is 0.188 / 0.169 / 0.152, steps of ~0.02 against a sampling s.d.
of ~0.02 at 4,000 frames: before the fix ``white_share`` required rho_1 > rho_2 > rho_3 and
returned None on 6 of 20 seeds (seeds 3 and 9 of these), and the map's y -> x link (no
coupling makes it) went unwarned.
"""

import warnings

import numpy as np
import pytest
from scipy.linalg import solve_discrete_lyapunov

from modalinfo.information import transfer_entropy_map
from modalinfo.information.flow import white_share

from .test_flow_noisy_target_round49 import A, _pair

NOISE_VAR = 20.0


@pytest.mark.parametrize("seed", [3, 9])
def test_white_share_at_four_times_the_signal(seed):
    exact = NOISE_VAR / (solve_discrete_lyapunov(A, np.eye(2))[0, 0] + NOISE_VAR)
    # s.e. of the lag-0 extrapolation ~0.04 here (Bartlett): 0.15 is > 3 s.e.
    assert white_share(_pair(seed, NOISE_VAR)[:, 0]) == pytest.approx(exact, abs=0.15)


def test_map_names_the_noisy_driver_at_four_times_the_signal():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        tmap = transfer_entropy_map(_pair(3, NOISE_VAR), lags=3, seed=0)
    assert tmap.significant[1, 0].any()  # the y -> x link the noise makes
    noisy = [w for w in caught if "white share" in str(w.message)]
    assert len(noisy) == 1
    assert "m0 (" in str(noisy[0].message)


def test_persistent_mode_under_noise_reads_a_level_line():
    # A persistent mode (AR(1) 0.99, variance 1 / (1 - 0.99^2) = 50.25) under white noise
    # of variance 200 (~4x): rho_k = 0.2 x 0.99^k is flat at ~0.2, so the sampled rho_3
    # may exceed rho_1 (before the fix: None on 159 of 200 seeds). Closed form 200 / 250.25.
    rng = np.random.default_rng(0)
    n = 4000
    e = rng.standard_normal(n + 2000)
    z = np.zeros(n + 2000)
    for t in range(1, z.size):
        z[t] = 0.99 * z[t - 1] + e[t]
    x = z[2000:] + np.sqrt(200.0) * rng.standard_normal(n)
    assert white_share(x) == pytest.approx(200.0 / (200.0 + 1.0 / (1.0 - 0.99**2)), abs=0.15)
