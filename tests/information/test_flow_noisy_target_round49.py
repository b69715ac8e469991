"""The map names the targets of its links whose variance is part white (round 49 PART a N12).

x drives y (VAR(1): x' = 0.9 x + e, y' = 0.5 y + 0.4 x + f, unit innovations) and x is
observed with white noise of variance 5 (its signal's is 1 / (1 - 0.81) = 5.26: WFS noise of
~1x the signal). Reference: the exact Gaussian TE of the observed series from their
autocovariances (A^k Sigma + R delta_k, Sigma from scipy's ``solve_discrete_lyapunov``):
0.047 nats y -> x, with no coupling from y to x (Smirnov 2013, Phys. Rev. E 87, 042917),
and the white share of x's variance, N / (S + N) = 0.487. Before the fix the map showed the
y -> x link in 20 of 20 seeds with no warning; the clean pair (same seeds) shows no link
into x and must not be warned.
"""

import warnings

import numpy as np
import pytest
from scipy.linalg import solve_discrete_lyapunov

from modalinfo.information import transfer_entropy_map

A = np.array([[0.9, 0.0], [0.4, 0.5]])
N_FRAMES = 4000
NOISE_VAR = 5.0


def _pair(seed, noise_var):
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((N_FRAMES + 500, 2))
    z = np.zeros_like(e)
    for t in range(1, z.shape[0]):
        z[t] = A @ z[t - 1] + e[t]
    z = z[500:]
    z[:, 0] += np.sqrt(noise_var) * rng.standard_normal(N_FRAMES)
    return z


def _noisy_warnings(data):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        tmap = transfer_entropy_map(data, lags=3, seed=0)
    return tmap, [w for w in caught if "white share" in str(w.message)]


def test_white_share_matches_the_closed_form():
    from modalinfo.information.flow import white_share  # new with the fix

    sigma = solve_discrete_lyapunov(A, np.eye(2))
    exact = NOISE_VAR / (sigma[0, 0] + NOISE_VAR)
    # s.e. of the lag-0 extrapolation at 4000 frames ~0.05: 3 s.e.
    assert white_share(_pair(1, NOISE_VAR)[:, 0]) == pytest.approx(exact, abs=0.15)
    assert white_share(_pair(1, 0.0)[:, 0]) is None


@pytest.mark.parametrize("seed", [3, 11])
def test_link_into_a_noisy_driver_is_warned(seed):
    tmap, caught = _noisy_warnings(_pair(seed, NOISE_VAR))
    assert tmap.significant[1, 0].any()  # the y -> x link the noise makes
    assert len(caught) == 1
    assert "m0 (" in str(caught[0].message)


@pytest.mark.parametrize("seed", [3, 11])
def test_clean_pair_is_not_warned(seed):
    tmap, caught = _noisy_warnings(_pair(seed, 0.0))
    assert not tmap.significant[1, 0].any()
    assert tmap.significant[0, 1].any()
    assert caught == []
