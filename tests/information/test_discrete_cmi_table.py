"""The CMI of all-discrete columns whose conditioning and target take different numbers
of values: the table's Miller-Madow plug-in, ``I(x; (y, z)) - I(x; z)``.

References (outside the code):
- scikit-learn's ``mutual_info_score`` (the plug-in MI of a contingency table) of x and
  the joint label of (y, z) (``numpy.unique(..., axis=0)``) less that of x and z, each
  plus Miller's (1955) term ``(K_x + K_y - K_xy - 1) / (2 n)`` (K: occupied values);
- the law of the channel: with y uniform on ``m_y`` values, z uniform on ``m_z``,
  ``x = ((y + z) mod 2) xor B``, ``B ~ Bernoulli(q)``, ``I(x; y | z) = mean_z
  H_b(P(x = 1 | z)) - H_b(q)`` (Cover & Thomas 2006, eq. 2.60 and sec. 7.1.4).

Planted bug R8-25 (docs/MUTATION.md, round 8): the joint code of (y, z) written
``c_y m_y + c_z`` for ``c_y m_z + c_z`` merged cells whenever ``m_y < m_z`` (and broke
the table where ``m_y > m_z``); every test before had binary y and z, where the two are
the same number.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from sklearn.metrics import mutual_info_score

from modalinfo.information import conditional_mutual_information


def _hb(p: float) -> float:
    return 0.0 if p in (0.0, 1.0) else -(p * math.log(p) + (1 - p) * math.log(1 - p))


def _mm_mi(a: np.ndarray, b: np.ndarray) -> float:
    k_ab = np.unique(np.c_[a, b], axis=0).shape[0]
    k_a, k_b = np.unique(a).size, np.unique(b).size
    return mutual_info_score(a, b) + (k_a + k_b - k_ab - 1) / (2 * a.size)


@pytest.mark.parametrize("method", ["gaussian", "kde"])
@pytest.mark.parametrize(("m_y", "m_z"), [(2, 3), (3, 2), (2, 4)])
def test_discrete_cmi_is_the_tables_with_unequal_levels(method, m_y, m_z):
    n, q = 6000, 0.2
    rng = np.random.default_rng(11)
    y = rng.integers(0, m_y, n)
    z = rng.integers(0, m_z, n)
    x = ((y + z) % 2) ^ (rng.random(n) < q)
    yz = np.unique(np.c_[y, z], axis=0, return_inverse=True)[1].ravel()
    reference = _mm_mi(x, yz) - _mm_mi(x, z)
    got = conditional_mutual_information(x.astype(float), y.astype(float), z.astype(float),
                                         method=method)
    assert got == pytest.approx(reference, rel=1e-9)
    # the law: P(parity 1 | z) is the share of y values of the other parity than z
    law = np.mean([_hb(q + (1 - 2 * q) * np.mean((np.arange(m_y) + c) % 2))
                   for c in range(m_z)]) - _hb(q)
    assert got == pytest.approx(law, abs=0.02)  # sd of the estimate ~0.006 at n = 6000


def test_ksg_cmi_of_discrete_columns_is_the_table():
    """The KSG CMI follows the table rule of the other methods (stop 37: it gave 0.3727
    for the binary channel's 0.3677 table CMI at n = 2e4). Reference: the chain rule
    I(x; y | z) = I(x; (y, z)) - I(x; z) on scikit-learn's table MI plus Miller-Madow,
    and the channel law ln 2 - H(0.1) with z independent."""
    import math

    from sklearn.metrics import mutual_info_score

    from modalinfo.information import conditional_mutual_information

    rng = np.random.default_rng(7)
    n = 20_000
    x = rng.integers(0, 2, n).astype(float)
    y = np.abs(x - (rng.random(n) < 0.1))
    z = rng.integers(0, 2, n).astype(float)

    def mm(a, b):
        k_ab = np.unique(np.column_stack([a, b]), axis=0).shape[0]
        return mutual_info_score(a, b) + (np.unique(a).size + np.unique(b).size - k_ab - 1) / (
            2 * a.size)

    yz = 2 * y + z
    want = mm(x, yz) - mm(x, z)
    got = conditional_mutual_information(x, y, z[:, None], method="ksg")
    assert got == pytest.approx(want, rel=1e-9)
    assert got == pytest.approx(math.log(2) + 0.1 * math.log(0.1) + 0.9 * math.log(0.9),
                                abs=0.01)
