"""Planted-bug review 26 (stop 50): the greedy tie rule below 1 nat.

The module notes of ``modalinfo.ordering.orderings`` (golden40): scores within
``_TIE_RTOL * max(1, |best|)`` nats of the step's best are a tie, won by the lower index:
the plug-in histogram MI's rounding error is at most ``K eps (MI + 2)``, an absolute
error that does not shrink with the MI, so a best of 1e-3 nats keeps the absolute
tolerance 2^-40 = 9.1e-13 nats. Reference: scores written by hand (1e-14 nats apart: a
tie; 1e-9 apart: not). Plant R26-C1 (``_TIE_RTOL * |best|``: scores below 1 nat tied
only when bit-equal) escaped tests/ordering/test_cross_cpu_ties_golden40.py, whose
scores were all near 1 nat.
"""

from types import SimpleNamespace

import numpy as np
import pytest

from modalinfo.ordering import orderings

pytestmark = pytest.mark.usefixtures("quiet_warnings")


def _by_hand(w):
    """A scorer whose score of a candidate phi (one unit row per mode) is w . phi."""
    w = np.asarray(w, dtype=float)
    return SimpleNamespace(score=lambda phi: float(w @ phi))


@pytest.mark.parametrize("search", ["exhaustive", "screened"])
@pytest.mark.parametrize("best", [1e-3, 0.2])
def test_small_scores_within_the_absolute_float_error_pick_the_lower_index(search, best):
    assert 1e-14 < 2.0**-40  # within the absolute tolerance of a score below 1 nat
    w = [best / 4, best, best + 1e-14, best / 8]
    order, *_ = orderings._greedy(_by_hand(w), np.eye(len(w)), search=search)
    assert order[0] == 1
    assert orderings._lowest_tied(np.array([best, best + 1e-14]), best + 1e-14) == 0


def test_small_scores_beyond_the_tolerance_are_not_a_tie():
    w = [2.5e-4, 1e-3, 1e-3 + 1e-9, 1.25e-4]  # 1e-9 nats: 1100 x 2^-40
    order, *_ = orderings._greedy(_by_hand(w), np.eye(len(w)))
    assert order[0] == 2


@pytest.mark.parametrize("n", [15, 16])
def test_direction_cosines_are_numpys_cos_and_sin_of_the_angles(n):
    # Pupil.direction_cosines: x / r and y / r, "the pixel at the centre (r = 0, odd N)
    # gets (1, 0), as arctan2(0, 0) = 0". Reference: numpy's cos, sin of theta_valid
    # (arctan2), within 4 ulp. Plant R26-C5 (the centre's cosine 0) escaped
    from modalinfo.bases import Pupil

    pupil = Pupil(n)
    c, s = pupil.direction_cosines()
    np.testing.assert_allclose(c, np.cos(pupil.theta_valid), rtol=0, atol=1e-15)
    np.testing.assert_allclose(s, np.sin(pupil.theta_valid), rtol=0, atol=1e-15)
    assert np.all(c**2 + s**2 == pytest.approx(1.0, abs=1e-15))
