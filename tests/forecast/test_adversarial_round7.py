"""Round 7 of issue 27's adversarial inputs (forecast): failures, fixed.

The full list of inputs tried is in docs/ADVERSARIAL.md, section "Round 7, issue 27".

Reference: the causal MA(inf) weights of an AR(1), psi_j = phi^j (Brockwell & Davis
1991, eq. 3.1.7), and the documented contract (a ValueError naming the argument).
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.forecast import psi_weights


def test_psi_weights_of_zero_terms_is_refused():
    # c21: psi_weights(phi, theta, 0) stopped with IndexError (psi_0 written first)
    with pytest.raises(ValueError, match=r"`n` must be an int >= 1; got 0"):
        psi_weights(np.array([0.5]), np.array([]), 0)


def test_psi_weights_of_an_ar1_are_powers():
    assert psi_weights(np.array([0.5]), np.array([]), 4).tolist() == [1.0, 0.5, 0.25, 0.125]
