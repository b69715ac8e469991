"""Transfer entropy's variables do not alias the caller's series (adversarial round 25).

Reference: numpy.shares_memory and a copy of the input taken before the call (the input
must read the same after the returned arrays are written), and the lagged columns
built by hand with numpy slicing.
"""

import numpy as np

from modalinfo.information import transfer_entropy_variables


def test_returned_columns_are_new_arrays():
    rng = np.random.default_rng(0)
    src, tgt = rng.standard_normal(200), rng.standard_normal(200)
    keep_src, keep_tgt = src.copy(), tgt.copy()
    for lag, history in [(0, 0), (1, 1), (3, 2)]:
        x, y, z = transfer_entropy_variables(src, tgt, lag=lag, history=history)
        t0 = max(lag, history)
        np.testing.assert_array_equal(x[:, 0], tgt[t0:])
        np.testing.assert_array_equal(y[:, 0], src[t0 - lag: 200 - lag])
        for a in (x, y, z):
            assert not np.shares_memory(a, src) and not np.shares_memory(a, tgt)
            assert a.flags.c_contiguous
            a -= 1.0  # standardising in place must not edit the caller's series
        np.testing.assert_array_equal(src, keep_src)
        np.testing.assert_array_equal(tgt, keep_tgt)
