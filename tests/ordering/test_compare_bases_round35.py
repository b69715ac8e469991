"""Round 35 PART a (issue 27, S4, S5, W1): one ``bases`` dict handed to ``compare_orderings``
for several logs.

Reference: the same question asked by another road, ``compare_orderings`` on the second
log with no ``bases`` (every basis built from that log). A basis the dict holds from a
call on another log must not stand in for it: before the fix the data K-L of log A was
used for log B (residual after 4 modes 0.040 against B's own 0.034 waves^2, labelled
"kl-data"), a theoretical K-L for an outer scale of 10 m served a log recording 50 m,
and a Zernike basis of 9 modes met a 6-mode log with an error naming ``log_or_coeffs``.
The same log twice still reuses the dict (the Figure 1 path) and matches a fresh call.
"""


import numpy as np
import pytest

from modalinfo.ordering.compare import compare_orderings
from modalinfo.telemetry import ModalLog

MODES = list(range(2, 11))


def _logs():
    rng = np.random.default_rng(0)
    a = rng.standard_normal((2000, 9)) * np.linspace(1.0, 0.2, 9)
    mix = np.eye(9)
    mix[1, 0], mix[4, 3] = 0.95, -0.9
    b = (rng.standard_normal((2000, 9)) @ mix.T) * np.linspace(0.3, 1.0, 9)
    return (ModalLog(a, rate=1000.0, modes=MODES, units="rad"),
            ModalLog(b, rate=1000.0, modes=MODES, units="rad"))


def _mean(comp):
    return np.asarray(comp.entries[0].error.mean)


pytestmark = pytest.mark.usefixtures("quiet_warnings")


def test_data_kl_of_another_log_is_refused():
    la, lb = _logs()
    shared = {}
    compare_orderings(la, "kl-data:variance", bases=shared, n_pixels=32)
    with pytest.raises(ValueError, match=r"bases\['kl-data'\].*other coefficients"):
        compare_orderings(lb, "kl-data:variance", bases=shared, n_pixels=32)


def test_theory_kl_of_another_outer_scale_is_refused():
    la, lb = _logs()
    la = la.with_metadata(outer_scale=10.0, diameter=4.0)
    lb = lb.with_metadata(outer_scale=50.0, diameter=4.0)
    shared = {}
    compare_orderings(la, "kl-theory:variance", bases=shared, n_pixels=32)
    with pytest.raises(ValueError, match=r"bases\['kl-theory'\].*outer scale"):
        compare_orderings(lb, "kl-theory:variance", bases=shared, n_pixels=32)


def test_zernike_basis_of_other_modes_is_refused_naming_bases():
    la, lb = _logs()
    shared = {}
    compare_orderings(la, "zernike:variance", bases=shared, n_pixels=32)
    fewer = lb.select(modes=MODES[:6])
    with pytest.raises(ValueError, match=r"bases\['zernike'\].*other modes"):
        compare_orderings(fewer, "zernike:variance,kl-data:variance", bases=shared,
                          n_pixels=32)


def test_same_log_reuses_and_matches_a_fresh_call():
    _, lb = _logs()
    shared = {}
    first = compare_orderings(lb, "kl-data:variance", bases=shared, n_pixels=32)
    built = shared["kl-data"]
    again = compare_orderings(lb, "kl-data:variance", bases=shared, n_pixels=32)
    assert shared["kl-data"] is built
    fresh = compare_orderings(lb, "kl-data:variance", n_pixels=32)
    np.testing.assert_allclose(_mean(again), _mean(fresh), rtol=1e-12)
    np.testing.assert_allclose(_mean(first), _mean(fresh), rtol=1e-12)
