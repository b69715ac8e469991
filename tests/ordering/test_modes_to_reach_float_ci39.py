"""``modes_to_reach`` counts a target within the curve's float error as reached.

Reference: exact arithmetic. dPhi(n) is a sum of up to M squares, exact only to ~M eps
dPhi(0); two orders that keep the same first n modes (in another sequence) give the same
dPhi(n) to that error only. Figure 1's "the error the standard order reaches with 20
modes" was reached by the a_k^2 order keeping the same 20 modes at 20 on one CPU and at 21
on another (stop 49's CI on an AMD EPYC against the golden run): a bare ``<=`` on the
float curve. A target one ulp below dPhi(20) must read 20 modes (fails before the fix), a
target below by far more than the float error 21.
"""

import numpy as np

from modalinfo.ordering import fitting_error

from .test_fitting_error import orthonormal_modes


def _result():
    z = orthonormal_modes(200, 30, seed=2)
    a = np.random.default_rng(8).standard_normal((1, 30)) * np.geomspace(3.0, 1e-3, 30)
    return fitting_error(a, z, per_frame=True)


def test_a_target_one_ulp_below_the_curve_is_reached():
    res = _result()
    curve = res.curve(frame=0, include_zero=True)
    for n in (5, 20, 29):
        assert res.modes_to_reach(np.nextafter(curve[n], 0.0), frame=0) == n
        assert res.modes_to_reach(curve[n] * (1 - 4 * np.finfo(float).eps), frame=0) == n


def test_a_target_below_by_more_than_the_float_error_is_not_reached():
    res = _result()
    curve = res.curve(frame=0, include_zero=True)
    # one part in 1e9 of the total below dPhi(20): far above M eps, so 21 modes are needed
    assert res.modes_to_reach(curve[20] - 1e-9 * curve[0], frame=0) == 21
    assert res.modes_to_reach(curve[20], frame=0) == 20
