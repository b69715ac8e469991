"""Round 7 of issue 27's adversarial inputs (bases): failures, fixed.

The full list of inputs tried is in docs/ADVERSARIAL.md, section "Round 7, issue 27".

Reference: the documented contract (a ValueError naming the argument before any work);
the memory a theoretical K-L basis needs is at least its (n_z, M) float64 eigenvectors,
8 n_z M bytes: for M = 10^6 (3 x 10^6 Zernikes) 2.2 x 10^4 GiB, more than any machine.
"""

from __future__ import annotations

import pytest

from modalinfo.bases import KLBasis, Pupil


def test_kl_with_a_million_modes_is_refused_at_once():
    # b22: KLBasis.from_turbulence(Pupil(16), 10**6) ran > 150 s (a hang) before; now refused
    # before the covariance blocks are built
    with pytest.raises(ValueError, match=r"`n_modes`=1000000 K-L modes of \d+ Zernikes need"):
        KLBasis.from_turbulence(Pupil(16), 10**6)


def test_kl_with_a_huge_zernike_set_is_refused():
    with pytest.raises(ValueError, match=r"use fewer modes or `zernike_modes`"):
        KLBasis.from_turbulence(Pupil(16), 5, zernike_modes=10**8)
