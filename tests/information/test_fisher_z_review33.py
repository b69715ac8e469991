"""``gaussian.mi_from_fisher_z`` / ``fisher_z_from_mi`` (review33, mutation round 33).

References: ``numpy.log(numpy.cosh(z))`` (moderate z) and the asymptote ``|z| - ln 2``
(``ln cosh z = |z| - ln 2 + ln(1 + e^(-2|z|))``, exact to double precision beyond
|z| = 20); ``numpy.arctanh`` of ``sqrt(1 - e^(-2I))`` for the inverse. The docstring says
``mi_from_fisher_z`` is even in z (a plant dropping its ``abs`` gave -z - ln 2 + ... < 0
for negative z, which fix50-a's file never passed).
"""

import math

import numpy as np
import pytest

from modalinfo.information.gaussian import fisher_z_from_mi, mi_from_fisher_z


@pytest.mark.parametrize("z", [0.0, 0.3, 1.7, 6.0])
def test_ln_cosh_is_even(z):
    ref = float(np.log(np.cosh(z)))
    assert float(mi_from_fisher_z(z)) == pytest.approx(ref, abs=1e-12)
    assert float(mi_from_fisher_z(-z)) == pytest.approx(ref, abs=1e-12)


def test_large_z_does_not_overflow():
    z = np.array([-800.0, 800.0])
    np.testing.assert_allclose(mi_from_fisher_z(z), 800.0 - math.log(2.0), rtol=1e-15)


@pytest.mark.parametrize("mi", [1e-6, 0.05, 0.7, 5.0])
def test_fisher_z_is_atanh_of_r(mi):
    r = math.sqrt(-math.expm1(-2.0 * mi))
    assert float(fisher_z_from_mi(mi)) == pytest.approx(math.atanh(r), rel=1e-10)
    assert float(mi_from_fisher_z(fisher_z_from_mi(mi))) == pytest.approx(mi, rel=1e-9)
