"""The theoretical K-L variances are decreasing at thousands of modes (round 48 PART a, K01-K03).

``KLBasis.from_turbulence`` promises "``M`` modes of decreasing variance". Its sort key
was rounded to 1e-10 of the *largest* variance, so beyond ~900 modes (variances ~5e-7 of
0.449) two variances 4e-5 apart were a tie ordered cos before sin, smaller first: 3
inversions at 1,000 modes, 37 at 2,000 (largest relative increase 2.2e-4).

References: the docstring's promise (``np.diff(variances) <= 0``) and numpy's own
descending sort of the same variances (``np.sort``), which the K-L order must equal;
the cos / sin twins of one block (bit-identical eigenvalues of one matrix) must stay in
the order cos, sin.
"""

import numpy as np

from modalinfo.bases import KLBasis, Pupil, noll_to_zernike


def test_kl_variances_of_1000_modes_are_decreasing():
    kl = KLBasis.from_turbulence(Pupil(100), 1000)
    v = kl.variances
    assert np.all(np.diff(v) <= 0.0), np.flatnonzero(np.diff(v) > 0)
    assert np.array_equal(v, np.sort(v)[::-1])


def test_close_variances_are_ordered_by_value_and_twins_cos_first():
    from modalinfo.bases.kl import _decreasing_order  # the one sort rule of both K-L paths

    # 5.00001e-7 (a sin mode) is larger than 5e-7 (a cos mode): value first, not kind
    values = np.array([0.449, 5.0e-7, 5.00001e-7, 0.02, 0.02])
    kinds = np.array([1, 1, 2, 2, 1])  # the twins 0.02 / 0.02: sin listed before cos
    order = _decreasing_order(values, kinds)
    assert order.tolist() == [0, 4, 3, 2, 1]
    assert np.array_equal(values[order], np.sort(values)[::-1])


def test_kl_ties_stay_in_the_order_m0_cos_sin():
    kl = KLBasis.from_turbulence(Pupil(32), 50)
    v = kl.variances
    assert np.all(np.diff(v) <= 0.0)
    # equal variances (cos / sin twins; also blocks of other |m| over the same radial
    # orders, Noll's covariance depending on n, n' only) keep the order m = 0, cos, sin
    dominant = kl.zernike_modes[np.argmax(np.abs(kl.zernike_from_kl), axis=0)]
    _, m = noll_to_zernike(dominant)
    kind = np.where(m == 0, 0, np.where(m > 0, 1, 2))
    ties = np.flatnonzero(np.diff(v) == 0)
    assert ties.size >= 10  # the twins are there
    for k in ties:
        assert kind[k] <= kind[k + 1], (k, dominant[k], dominant[k + 1])
