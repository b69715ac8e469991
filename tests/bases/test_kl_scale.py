"""The theoretical K-L at the scale of a 4-m telescope (issue 30, item 2).

References: (1) the former all-pairs construction of the Zernike covariance and the
former dense eigen-decomposition (``_dense_zernike_covariance``, ``_eig_by_symmetry`` +
``_fix_signs``, kept callable), which the block-by-block path must equal bit for bit;
(2) laws from outside the code: the trace of a covariance is invariant under the
orthogonal change to K-L modes, so the K-L variances of all ``n_z`` modes sum to the
Zernike variances (Noll 1976's ``Delta_1 - Delta_J``); the K-L modes are optimal
(Karhunen-Loeve theorem), so the variance left after the first ``n`` K-L modes is never
above Noll's Zernike residual ``Delta_{n+1}``; and the leading K-L variances converge as
the Zernike set grows (the small-size K-L of 500 modes is the reference for the first 500
of 3,000).
"""

import numpy as np
import pytest

from modalinfo.bases import noll_residual_variance
from modalinfo.bases import turbulence as tb
from modalinfo.bases.kl import _eig_blocks, _eig_by_symmetry, _fix_signs, default_zernike_modes


def _kl_from_blocks(n_modes, outer_scale=np.inf, modes=None):
    modes = default_zernike_modes(n_modes) if modes is None else modes
    return _eig_blocks(tb._covariance_blocks(modes, outer_scale, 4.0), modes, n_modes)


@pytest.mark.parametrize("outer_scale, modes", [
    (np.inf, default_zernike_modes(200)),    # 629 Zernikes, Noll closed form
    (20.0, np.arange(1, 67)),                # piston included, numerical von Karman integral
    (np.inf, np.random.default_rng(0).permutation(np.arange(2, 92))),  # any order of modes
])
def test_blocks_equal_dense_construction_bit_for_bit(outer_scale, modes):
    dense = tb._dense_zernike_covariance(modes, outer_scale, 4.0)
    blocked = tb.zernike_covariance(modes, outer_scale=outer_scale, diameter=4.0)
    assert np.array_equal(blocked, dense)
    n_keep = modes.size // 3
    values, vectors = _eig_by_symmetry(dense, modes)
    expected = np.ascontiguousarray(_fix_signs(vectors[:, :n_keep]))
    got_values, got_vectors = _kl_from_blocks(n_keep, outer_scale, modes)
    assert np.array_equal(got_values, values[:n_keep])
    assert np.array_equal(got_vectors, expected)


def test_kl_trace_equals_sum_of_zernike_variances():
    modes = default_zernike_modes(1000)  # 2..3003: 3,002 Zernikes, radial orders 1..76
    values, _ = _kl_from_blocks(modes.size, modes=modes)
    # decreasing (kl._decreasing_order: ties to 10 significant digits of each value;
    # round 48 PART a made this exact, test_kl_order_round48.py)
    assert values.shape == (modes.size,)
    assert np.all(np.diff(values) <= 1e-10 * values[0])
    # trace invariance: sum of K-L variances = sum of Zernike variances = Delta_1 - Delta_J
    zernike_sum = noll_residual_variance(1) - noll_residual_variance(int(modes[-1]))
    assert values.sum() == pytest.approx(zernike_sum, rel=1e-10)


def test_kl_3000_modes_optimality_and_convergence():
    values, vectors = _kl_from_blocks(3000)  # over 9,044 Zernikes, radial orders 1..133
    assert vectors.shape == (9044, 3000)
    assert np.all(np.diff(values) <= 1e-10 * values[0])
    # K-L optimality: residual after n K-L modes <= Noll's Zernike residual Delta_{n+1}
    n = np.arange(1, 3001)
    kl_residual = noll_residual_variance(1) - np.cumsum(values)
    assert np.all(kl_residual <= noll_residual_variance(n + 1) * (1 + 1e-9))
    # and strictly better once the Zernike radial orders mix (beyond tip/tilt)
    assert kl_residual[-1] < 0.99 * noll_residual_variance(3001)
    # convergence: the first 500 K-L variances of 3,000 vs the 500-mode default K-L
    small, _ = _kl_from_blocks(500)
    assert np.max(np.abs(values[:500] / small - 1)) < 1e-2
