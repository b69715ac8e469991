"""Stability of orderings across time windows and seeds.

References: ``scipy.stats.spearmanr`` / ``kendalltau`` definitions checked by hand
(identical orders give 1, reversed give -1, one adjacent swap of M items gives
Kendall tau = 1 - 4 / (M (M - 1)) and Spearman rho = 1 - 12 / (M (M^2 - 1))); a synthetic
log whose dominant mode changes halfway must show a drop of the window agreement.
"""

import numpy as np
import pytest

from modalinfo.ordering import ordering_stability, rank_agreement


def orthonormal_modes(n_pix, n_modes, seed=0):
    q, _ = np.linalg.qr(np.random.default_rng(seed).standard_normal((n_pix, n_modes)))
    return q * np.sqrt(n_pix)


def test_rank_agreement_hand_values():
    m = 6
    ident = np.arange(m)
    assert rank_agreement(ident, ident) == pytest.approx((1.0, 1.0))
    assert rank_agreement(ident, ident[::-1]) == pytest.approx((-1.0, -1.0))
    swap = ident.copy()
    swap[[2, 3]] = swap[[3, 2]]
    rho, tau = rank_agreement(ident, swap)
    assert tau == pytest.approx(1 - 4 / (m * (m - 1)))
    assert rho == pytest.approx(1 - 12 / (m * (m * m - 1)))
    with pytest.raises(ValueError, match="must be permutations of the same modes"):
        rank_agreement([0, 1, 2], [0, 1, 1])


def test_stationary_variance_order_is_stable_and_change_is_detected():
    rng = np.random.default_rng(0)
    sig = np.array([3.0, 2.0, 1.5, 1.0, 0.5, 0.2])
    z = orthonormal_modes(100, 6)
    a = rng.standard_normal((2000, 6)) * sig
    res = ordering_stability(a, z, "variance", window=400, seeds=())
    assert res.window_orders.shape == (5, 6)
    np.testing.assert_allclose(res.window_spearman, 1.0)
    np.testing.assert_allclose(res.window_top_overlap, 1.0)
    # reverse the variances in the second half: the window straddling nothing (800..1200
    # is all first half) agrees, the pair across the change disagrees
    b = a.copy()
    b[1000:] = rng.standard_normal((1000, 6)) * sig[::-1]
    res2 = ordering_stability(b, z, "variance", window=500, seeds=(), n_top=2)
    np.testing.assert_allclose(res2.window_spearman, [1.0, -1.0, 1.0])
    np.testing.assert_allclose(res2.window_top_overlap, [1.0, 0.0, 1.0])
    assert "median Spearman" in res2.summary()


def test_seed_stability_of_mi_greedy():
    rng = np.random.default_rng(1)
    sig = np.array([3.0, 1.0, 0.3, 0.1])
    a = rng.standard_normal((400, 4)) * sig
    z = orthonormal_modes(64, 4)
    res = ordering_stability(a, z, "mi_greedy", window=200, seeds=(0, 1, 2),
                             sample_budget=5000)
    assert res.seed_orders.shape == (3, 4) and res.seed_spearman.shape == (3,)
    # the leading mode carries 90% of the variance: every seed and window puts it first
    assert np.all(res.seed_orders[:, 0] == 0) and np.all(res.window_orders[:, 0] == 0)


def test_bad_inputs():
    a = np.ones((100, 3))
    z = orthonormal_modes(30, 3)
    with pytest.raises(ValueError, match="`window` must be an int <= 50"):
        ordering_stability(a, z, "variance", window=80)
    with pytest.raises(ValueError, match="`seeds` must hold at least 2 seeds"):
        ordering_stability(a, z, "variance", seeds=(1,))
    with pytest.raises(ValueError, match="`n_top` must be an int <= 3"):
        ordering_stability(a, z, "variance", n_top=4)


def test_rank_agreement_refuses_orders_that_are_not_ints():
    """Audit 9: float orders indexed the ranks (IndexError), a masked index was used.
    Reference: identical orderings agree exactly (rho = tau = 1)."""
    assert rank_agreement(np.array([2, 0, 1], dtype=np.uint8), [2, 0, 1]) == pytest.approx(
        (1.0, 1.0))
    with pytest.raises(TypeError, match="`order_a` must be a 1-D sequence of ints"):
        rank_agreement(np.array([1.0, 0.0, 2.0]), [1, 0, 2])
    with pytest.raises(TypeError, match="`order_b` must be a 1-D sequence of ints"):
        rank_agreement([1, 0, 2], np.array([1.0, 0.0, 2.0]))
    with pytest.raises(ValueError, match="`order_a` is a masked array"):
        rank_agreement(np.ma.masked_array([1, 0, 2], mask=[0, 1, 0]), [1, 0, 2])


def test_windows_of_a_log_with_a_gap_refused():
    # Reference: the time axis by construction (two nights of 1000 frames at 2 kHz, 8 h
    # apart): a 400-frame window lasts 0.2 s, while window / mean rate gave 2880 s
    from modalinfo.telemetry import ModalLog

    rng = np.random.default_rng(0)
    a = rng.standard_normal((2000, 4)) * np.array([3.0, 2.0, 1.0, 0.5])
    t = np.r_[np.arange(1000), np.arange(1000)] / 2000.0
    t[1000:] += 8 * 3600.0
    z = orthonormal_modes(64, 4)
    log = ModalLog(a, timestamps=t)
    with pytest.raises(ValueError, match=r"time windows assumes equally spaced.*gap"):
        ordering_stability(log, z, "variance", window=400, seeds=())
    res = ordering_stability(log.longest_segment(), z, "variance", window=400, seeds=())
    assert res.window_duration == pytest.approx(0.2)
