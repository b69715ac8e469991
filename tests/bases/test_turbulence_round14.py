"""Round 14 PART a: Noll's residual variance refuses a J it cannot hold in memory.

References (outside the code): Noll (1976), J. Opt. Soc. Am. 66, 207, Table IV
(Delta_10 = 0.0401, Delta_21 = 0.0208 in (D / r0)^(5/3) rad^2) and his large-J fit
``0.2944 J^(-sqrt(3)/2)``, whose decay the exact sum follows within a factor 1.5 at
J = 1e5 (the docstring's ``J**(-5/6)`` law is slower than the fit).
"""

import pytest

from modalinfo.bases import noll_residual_variance


@pytest.mark.parametrize("J", [2**40, 10**7 + 1])
def test_a_huge_J_is_refused_in_one_line_naming_it(J):
    # was MemoryError ("Unable to allocate 8.00 TiB") for 2**40
    with pytest.raises(ValueError, match=r"^`J` must be <= 10000000; got \d+\.$"):
        noll_residual_variance(J)


def test_table_values_and_a_large_J_still_answer():
    assert noll_residual_variance(10) == pytest.approx(0.0401, rel=0.01)
    assert noll_residual_variance(21) == pytest.approx(0.0208, rel=0.01)
    fit = 0.2944 * 1e5 ** (-(3**0.5) / 2)
    assert fit < noll_residual_variance(10**5) < 1.5 * fit
