"""Greedy MI orders that a CPU's last bits cannot move (golden40, issue 27).

Stop 49's golden run on an AMD EPYC moved Figure 1's K-L (theory) MI-order mode counts
on the simulated closed-loop log (18 -> 19, 16 -> 18, 9 -> 8) against the reference of
another x86_64 CPU. Measured (``NUMBA_CPU_NAME=generic OPENBLAS_CORETYPE=Sandybridge``
against the native build, docs/TESTING.md "Golden numbers"): the Zernike orders are bit
for bit the same, the K-L pixel matrix differs in the last bits (LAPACK's eigenvectors),
and the histogram MI of the K-L candidates moved by up to 6e-4 nats, one frame's order
at step 1 and its count 24 -> 13. Cause: K-L values at pixels mirrored by the pupil's
symmetries were equal only to the last bit (``cos(arctan2(y, -x))`` is not
``-cos(arctan2(y, x))`` bit for bit), so whether two such pixels tie, and so the
rank-based histogram's counts, depended on the eigenvectors' last bits.

References: the exact symmetries of ``cos(m theta)``, ``sin(m theta)`` under the
reflections ``x -> -x``, ``y -> -y`` and ``x <-> y`` (a K-L mode of one ``|m|`` and kind
is mapped to +-itself, an odd-``m`` cos mode to +-its sin twin); a K-L basis whose
eigenvectors carry one-ulp noise (what another LAPACK returns) must give the same MI,
bit for bit, along the greedy order; for the tie rule of the greedy search, scores
written by hand (exactly equal, and 1e-14 apart relative).
"""

import copy
from pathlib import Path

import numpy as np
import pytest

from modalinfo.bases import KLBasis, Pupil
from modalinfo.ordering import order_modes, orderings

pytestmark = pytest.mark.usefixtures("quiet_warnings")


class _Sum:
    """Score of a candidate: w . phi, with one unit row per mode (scores by hand)."""

    def __init__(self, w):
        self.w = np.asarray(w, dtype=float)

    def score(self, phi):
        return float(self.w @ phi)


def _greedy_first(w, search="exhaustive"):
    contrib = np.eye(len(w))
    order, *_ = orderings._greedy(_Sum(w), contrib, search=search)
    return order


@pytest.mark.parametrize("search", ["exhaustive", "screened"])
def test_exactly_equal_scores_pick_the_lower_index(search):
    assert _greedy_first([0.5, 1.0, 1.0, 0.25], search)[0] == 1


@pytest.mark.parametrize("search", ["exhaustive", "screened"])
def test_scores_within_float_error_pick_the_lower_index(search):
    # mode 2 beats mode 1 by 1e-14 relative (~45 ulp): a tie, the lower index wins
    # (before the rule, mode 2 won on those last bits)
    order = _greedy_first([0.5, 1.0, 1.0 + 1e-14, 0.25], search)
    assert order[0] == 1
    # the winner's score is its own (the MI along the order), not the best's
    assert orderings._lowest_tied(np.array([np.nan, 1.0, 1.0 + 1e-14]), 1.0 + 1e-14) == 1


def test_scores_beyond_float_error_are_not_a_tie():
    # 1e-9 relative is far above the 2^-40 tolerance: the higher score wins
    assert _greedy_first([0.5, 1.0, 1.0 + 1e-9, 0.25])[0] == 2
    assert orderings._lowest_tied(np.array([1.0, 1.0 + 1e-9]), 1.0 + 1e-9) == 1


def _mirror_exact(img, mask, other):
    return bool(np.all(np.abs(img[mask]) == np.abs(other[mask])))


def test_kl_values_at_mirror_pixels_tie_bit_for_bit():
    pupil = Pupil(32)
    kl = KLBasis.from_turbulence(pupil, 20)
    img = pupil.to_image(kl.matrix.T)
    mask = pupil.mask
    for k in range(20):
        assert _mirror_exact(img[k], mask, img[k][:, ::-1]), k  # x -> -x
        assert _mirror_exact(img[k], mask, img[k][::-1]), k  # y -> -y
    # x <-> y: the twins KL1/KL2 (tip/tilt-like, m = 1) map onto each other
    assert _mirror_exact(img[0], mask, img[1].T)


def _perturbed_kl(kl, seed):
    """The same K-L with one-ulp noise on its eigenvectors (another CPU's LAPACK).

    The noise is a function of the entry's bits and ``seed``: the cos and sin blocks of
    one ``|m|`` are one matrix decomposed once (``kl._eig_blocks``), so another LAPACK
    moves both twins alike.
    """
    change = np.array(kl.zernike_from_kl)
    bits = change.view(np.uint64)
    noise = ((bits * np.uint64(2654435761) + np.uint64(seed)) >> np.uint64(7)) % np.uint64(3)
    noise = noise.astype(np.int64) - 1
    change = np.where(noise > 0, np.nextafter(change, np.inf),
                      np.where(noise < 0, np.nextafter(change, -np.inf), change))
    change[kl.zernike_from_kl == 0] = 0.0  # the blocks' zeros stay zeros
    other = copy.copy(kl)
    other._setup(kl.pupil, kl.zernike_modes, change, np.array(kl.variances), None)
    return other


def test_kl_greedy_mi_is_unmoved_by_last_bit_eigenvectors(simulated_log_and_kl):
    log, kl = simulated_log_and_kl
    # frame 3999 of data/kaos_closedloop.npz: its K-L order changed at step 1 between
    # the native and the generic build before the fix (count 24 -> 13)
    base = order_modes(log, kl, "mi_greedy", frame=3999, seed=0, n_resamples=0)
    for seed in (1, 2):
        other = order_modes(log, _perturbed_kl(kl, seed), "mi_greedy", frame=3999, seed=0,
                            n_resamples=0)
        np.testing.assert_array_equal(other.order, base.order)
        np.testing.assert_array_equal(other.mi, base.mi)


@pytest.fixture(scope="module")
def simulated_log_and_kl():
    import warnings

    from modalinfo.io import load
    from modalinfo.ordering.compare import basis_for_log

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        log = load(Path(__file__).resolve().parents[2] / "data" / "kaos_closedloop.npz")
        return log, basis_for_log("kl-theory", log)


def test_a_continuous_modes_nodal_pixels_are_not_a_pile():
    # exact mirrors make a K-L mode odd under x <-> y exactly 0 on the diagonals (8 % of
    # a 32-pixel pupil's pixels, above the pile rule's 3 %): points of a nodal line, not
    # an atom of the continuous mode, no warning (Figure 1's and Figure 6's K-L orders
    # warned "KL4 holds 3.0 % of its samples at 0" without this); real zeros (mode 4
    # dropped in 10 % of the frames) still warn, and so do a bare matrix's zeros
    # (its own samples: test_crowded_mode_round27.py)
    import warnings

    from modalinfo.information.methods import BiasRuleWarning

    kl = KLBasis.from_turbulence(Pupil(32), 12)
    assert (kl.matrix == 0).mean(axis=0).max() > 0.03  # the case exists
    coeffs = np.random.default_rng(3).standard_normal((400, 12)) * np.sqrt(kl.variances)
    with warnings.catch_warnings():
        warnings.simplefilter("error", BiasRuleWarning)
        order_modes(coeffs, kl, "mi_greedy", seed=0, n_resamples=0, sample_budget=20_000)
    dropped = coeffs.copy()
    dropped[::10, 3] = 0.0
    with pytest.warns(BiasRuleWarning, match="KL4. holds"):
        order_modes(dropped, kl, "mi_greedy", seed=0, n_resamples=0, sample_budget=20_000)
