"""Ties between adjacent ranks and the explanation of the ordering table.

References: symmetry and exact construction. Noll tip and tilt are 2x and 2y, so on a
pupil grid symmetric under x <-> y, with every (frame, pixel) pair used and identical
tip and tilt coefficients (defocus and Z5 ~ xy are symmetric under the swap), the pairs
(Phi_ref, a_2 Z_2) and (Phi_ref, a_3 Z_3) are the same multiset: the MI of either choice
at step 1 is the same number, so the margin is exactly 0 and its bootstrap interval,
symmetric about 0 in distribution, reaches 0 (a tie). A mode with four times the
variance of the next wins by a margin many bootstrap spreads wide (no tie). The
footnote test builds a result whose gain lies outside its interval by hand. The slow
test checks the rate of ties over data seeds for independent equal-variance modes (a
coin-flip order by construction) against a binomial bound.
"""

import numpy as np
import pytest

from modalinfo.ordering import OrderingResult, order_modes
from modalinfo.ordering.compare import basis_for_log
from modalinfo.telemetry import ModalLog


@pytest.fixture(scope="module")
def tip_equals_tilt():
    rng = np.random.default_rng(0)
    a = rng.standard_normal((200, 4)) * [1.0, 1.0, 0.5, 0.25]
    a[:, 1] = a[:, 0]
    log = ModalLog(a, rate=1000.0, modes=[2, 3, 4, 5])
    basis = basis_for_log("zernike", log, n_pixels=16)
    return log, basis


@pytest.mark.parametrize("method", ["mi_greedy", "mi_marginal"])
def test_equal_modes_are_tied_distinct_ones_are_not(tip_equals_tilt, method):
    log, basis = tip_equals_tilt
    # equal-width bins: the x <-> y symmetry of the Zernike values holds to rounding only
    # (1e-16), and the default equiprobable bins can split a group of such near-tied
    # pixel values at an edge differently for Z2 and Z3 (measured margin 2.4e-5); the
    # Hacine-Gharbi bin number, as the same near-tie sits on an edge of the default
    # bins="auto" (70 equal-width bins here: measured margin 3.5e-5)
    res = order_modes(log, basis, method, sample_budget=10**6, seed=1, n_resamples=20,
                      estimator_options={"binning": "uniform", "bins": "hacine-gharbi"})
    assert res.n_samples == 200 * basis.matrix.shape[0]  # every pair: the symmetry holds
    assert set(res.labels[:2]) == {"Z2", "Z3"}
    assert res.margin[0] == pytest.approx(0.0, abs=1e-12)
    assert res.margin_low[0] <= 0.0 <= res.margin_high[0]
    # Z4 (variance 0.25) after Z2 + Z3, Z5 (0.0625) last: clear wins, no tie
    assert res.labels[2:] == ("Z4", "Z5")
    assert res.margin_low[1] > 0.0
    np.testing.assert_array_equal(res.tied_with_previous, [False, True, False, False])
    table = res.table().splitlines()
    assert table[2].startswith("~") and not table[3].startswith("~")
    assert any(n.startswith("~ 1 rank(s)") for n in res.notes())


def test_no_bootstrap_no_ties(tip_equals_tilt):
    log, basis = tip_equals_tilt
    res = order_modes(log, basis, "mi_greedy", sample_budget=10**6, seed=1, n_resamples=0)
    assert res.tied_with_previous is None and res.gain_outside_interval is None
    assert "~" not in res.table()
    # no tie can be marked: said once, not a legend promising '~' (round 33 PART b, B46)
    (note,) = res.notes()
    assert note.startswith("Noise not assessed (n_resamples 0: no bootstrap)")
    assert "gain CI" not in res.legend() and "score: I(Phi_ref" in res.legend()


def test_margin_round_trips_through_json(tip_equals_tilt, tmp_path):
    log, basis = tip_equals_tilt
    res = order_modes(log, basis, "mi_greedy", sample_budget=5000, seed=2, n_resamples=3)
    back = OrderingResult.from_json(res.to_json(tmp_path / "o.json"))
    np.testing.assert_array_equal(back.margin_low, res.margin_low)
    np.testing.assert_array_equal(back.tied_with_previous, res.tied_with_previous)


def test_gain_outside_its_interval_is_marked_and_explained():
    res = OrderingResult(
        order=np.arange(3), labels=("Z2", "Z3", "Z4"), basis_labels=("Z2", "Z3", "Z4"),
        method="mi_greedy", mi=np.array([0.5, 0.8, np.nan]), gain=np.array([0.5, 0.3, np.nan]),
        gain_low=np.array([0.40, 0.31, np.nan]), gain_high=np.array([0.6, 0.35, np.nan]),
        scores=np.array([0.5, 0.4, 0.1]), n_resamples=20,
        margin=np.array([0.2, 0.1, np.nan]), margin_low=np.array([0.1, 0.05, np.nan]),
        margin_high=np.array([0.3, 0.15, np.nan]),
    )
    np.testing.assert_array_equal(res.gain_outside_interval, [False, True, False])
    rows = res.table().splitlines()
    assert not rows[1].endswith("*") and rows[2].endswith("*") and not rows[3].endswith("*")
    (note,) = res.notes()
    assert note.startswith("* step(s) 2: the gain lies outside its percentile interval")
    assert "'*'" in res.legend()


@pytest.mark.slow
def test_independent_equal_variance_modes_mostly_tied():
    # statistical check: tip and tilt independent with equal variance (their order is
    # a coin flip) are marked tied on most data seeds (17 of 20 when written; the
    # bound 12 fails with probability < 1% if the rate is 0.85); modes with 4x and 16x
    # less variance are never tied with the rank above (0 of 20 when written)
    ties = separated = 0
    for seed in range(20):
        rng = np.random.default_rng(seed)
        a = rng.standard_normal((400, 4)) * [1.0, 1.0, 0.5, 0.25]
        log = ModalLog(a, rate=1000.0, modes=[2, 3, 4, 5])
        basis = basis_for_log("zernike", log, n_pixels=16)
        res = order_modes(log, basis, "mi_greedy", sample_budget=20000, seed=seed,
                          n_resamples=20)
        ties += bool(res.tied_with_previous[1])
        separated += bool(res.tied_with_previous[2] or res.tied_with_previous[3])
    assert ties >= 12
    assert separated <= 2
