"""psi_weights under np.seterr(all="raise") (round 9, row se-psi-long).

Reference: the MA(inf) weights of an AR(1), psi_j = phi^j (Brockwell & Davis eq. 3.1.7),
which underflow to 0 after ~1075 terms at phi = 0.5; the underflow raised
FloatingPointError under ``np.seterr(all="raise")``. The weights must equal 0.5^j (0 once
it underflows) whatever the error state.
"""

import numpy as np

from modalinfo.forecast import psi_weights


def test_psi_weights_underflow_is_not_an_error():
    old = np.seterr(all="raise")
    try:
        psi = psi_weights([0.5], [], 2000)
    finally:
        np.seterr(**old)
    j = np.arange(2000)
    with np.errstate(under="ignore"):
        assert np.array_equal(psi, 0.5 ** j)
