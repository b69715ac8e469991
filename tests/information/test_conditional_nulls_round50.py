"""The histogram conditional test's shuffle null on non-linear Markov chains (fix50-e,
issue 27; round 50 PART a O02 / O03).

References: the Markov property (X -> Z -> Y with independent noises: I(X; Y | Z) = 0
exactly, so a level-alpha test rejects in a binomial(draws, alpha) count); the generating
link sin 6Z (what a surrogate y must keep of z: its mean given z) and the noise's
variance; Runge (2018, AISTATS, Algorithm 1) for the local permutation. Seeds fixed; each
count's false-failure rate is stated where it is set.
"""

import warnings

import numpy as np

from modalinfo.information import (
    BiasRuleWarning,
    conditional_mutual_information_test,
    select_inputs,
)
from modalinfo.information.resampling import local_permutation


def _sine_chain(rng, n):
    """Z ~ U(0, 1), X = Z + U(0, .1), Y = sin 6Z + U(0, .1): CMI 0 (round 50 PART a O03)."""
    z = rng.random(n)
    return z + 0.1 * rng.random(n), np.sin(6 * z) + 0.1 * rng.random(n), z


def _square_chain(rng, n):
    """Z ~ N(0, 1), X = Z + N(0, .2^2), Y = Z^2 + N(0, .2^2): CMI 0 (O02)."""
    z = rng.standard_normal(n)
    return z + 0.2 * rng.standard_normal(n), z**2 + 0.2 * rng.standard_normal(n), z


def test_local_permutation_keeps_y_given_z():
    """y[perm] about sin 6z keeps the noise's spread: its mean square about the generating
    link is Var U(0, .1) + mean^2 = 1/1200 + 0.05^2 = 0.00333 plus what 5 neighbours'
    z-spread adds (sin' <= 6, neighbours ~ 2.5 / n apart: < 0.001); a plain permutation
    gives ~0.5. Most rows are distinct (Runge's draw repeats a row only where all 5
    neighbours are taken)."""
    rng = np.random.default_rng(1)
    _, y, z = _sine_chain(rng, 4000)
    perm = local_permutation(z[:, None], True, np.random.default_rng(2))
    assert perm.shape == (4000,) and np.unique(perm).size > 0.9 * 4000
    assert np.mean((y[perm] - np.sin(6 * z)) ** 2) < 0.00333 + 0.002
    assert not np.array_equal(perm, np.arange(4000))


def test_histogram_shuffle_test_keeps_its_level_on_non_linear_chains():
    """O02 / O03: rejected 26 / 40 and 40 / 40 at 5 % with the fit + shuffled residual
    surrogates. 15 draws of each chain at n = 2000: at most 4 of 30 rejections
    (binomial(30, 0.05): P(>= 5) = 1.6 %, the false-failure rate)."""
    rejected = 0
    for seed in range(15):
        for chain in (_sine_chain, _square_chain):
            x, y, z = chain(np.random.default_rng(8000 + seed), 2000)
            result = conditional_mutual_information_test(
                x, y, z, method="histogram", n_surrogates=39, surrogate="shuffle",
                seed=seed)
            rejected += result.pvalue <= 0.05
    assert rejected <= 4


def test_histogram_shuffle_test_keeps_its_power():
    """X = Z + .5 E, Y = Z^2 + .2 E + .3 N (E shared: CMI > 0): 10 draws at n = 2000 all
    rejected at 5 % (measured 40 / 40 before and after the local permutation)."""
    for seed in range(10):
        rng = np.random.default_rng(9000 + seed)
        z, e = rng.standard_normal((2, 2000))
        x = z + 0.5 * e
        y = z**2 + 0.2 * e + 0.3 * rng.standard_normal(2000)
        result = conditional_mutual_information_test(
            x, y, z, method="histogram", n_surrogates=39, surrogate="shuffle", seed=seed)
        assert result.pvalue <= 0.05


def _log_with_square(seed, n=2000):
    """Modes (x, z, y, w): x AR(1) drives z, y_t = sin 6 z_{t-1} + e, w_t = z_t^2 + e.

    y's Markov blanket among the lagged modes is {z_{t-1}}: w_{t-1} (a function of
    z_{t-1} plus independent noise) informs nothing beyond it.
    """
    rng = np.random.default_rng(seed)
    x, z, y = np.zeros((3, n))
    ex, ez, ey = rng.standard_normal((3, n))
    for t in range(1, n):
        x[t] = 0.6 * x[t - 1] + ex[t]
        z[t] = 0.4 * z[t - 1] + 0.7 * x[t - 1] + 0.6 * ez[t]
        y[t] = np.sin(6 * z[t - 1]) + 0.3 * ey[t]
    w = z**2 + 0.3 * rng.standard_normal(n)
    return np.column_stack([x, z, y, w])


def test_histogram_selection_names_an_input_that_only_follows_an_earlier_one():
    """The histogram search added w[t] after z[t] in 40 of 40 such logs (at 5 %, its
    rotation null lacking w's non-linear link to z), silently before fix50-e, which made
    it warn; since fix51-a its null keeps that link and w is added in 2 of 40
    (tests/information/test_nonlinear_nulls_fix51a.py). Here (3 seeds): the true input
    first, and a search that still adds w warns."""
    for seed in range(3):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result = select_inputs(_log_with_square(seed), 2, max_lag=3,
                                   method="histogram", n_surrogates=19, intervals=False,
                                   seed=seed)
        assert (result.inputs[0].source, result.inputs[0].lag) == (1, 0)
        if any(i.source == 3 for i in result.inputs):
            assert any(issubclass(w.category, BiasRuleWarning)
                       and "local permutations" in str(w.message) for w in caught)
