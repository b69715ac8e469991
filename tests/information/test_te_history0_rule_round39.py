"""Round 39 PART a, W27: ``transfer_entropy(history=0)`` warns as the lagged MI does.

With ``history=0`` the TE is the MI of the target and the lagged source (its
docstring), but the CMI road it takes had no effective-sample rule: AR(1) lag pairs,
rho = 0.99, n = 400 (exact MI -0.5 ln(1 - rho^2) = 1.959 nats, mean estimate 1.59 over
20 seeds) were warned by ``mutual_information`` 20 times in 20 and by the TE never.
Reference: the exact Gaussian MI and ``mutual_information``'s warning on the same pair.
"""

import warnings

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.information import BiasRuleWarning, mutual_information, transfer_entropy


def _ar1(n, rho, seed):
    e = np.random.default_rng(seed).normal(size=n + 500)
    return lfilter([np.sqrt(1.0 - rho * rho)], [1.0, -rho], e)[500:]


def _bias(f):
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        value = f()
    return value, [str(m.message) for m in w if issubclass(m.category, BiasRuleWarning)]


@pytest.mark.parametrize("seed", [300, 301, 302])
def test_persistent_self_lag_warned_like_the_mi(seed):
    x = _ar1(400, 0.99, seed)
    te, te_msgs = _bias(lambda: transfer_entropy(x, x, lag=1, history=0, method="ksg"))
    mi, mi_msgs = _bias(lambda: mutual_information(x[:-1], x[1:], method="ksg"))
    assert len(mi_msgs) == 1 and "effective samples" in mi_msgs[0]
    assert len(te_msgs) == 1 and "effective samples" in te_msgs[0]
    assert "history=0" in te_msgs[0]
    assert te == pytest.approx(mi, rel=1e-9)  # the value is the MI's, unchanged
    assert te < -0.5 * np.log(1 - 0.99 ** 2) - 0.1


def test_weakly_persistent_and_history_one_stay_quiet():
    x = _ar1(400, 0.5, 7)
    assert _bias(lambda: transfer_entropy(x, x, lag=1, history=0, method="ksg"))[1] == []
    y = _ar1(2000, 0.99, 8)
    z = np.roll(y, 1) + np.random.default_rng(9).normal(size=2000)
    assert _bias(lambda: transfer_entropy(y, z, lag=1, history=1, method="gaussian"))[1] == []
