"""Tests of unit conversions and the Fringe peak/RMS normalisation.

References: the definitions phase[rad] = 2 pi OPD / lambda and waves = OPD / lambda
(hand-computed: 500 nm of OPD at 500 nm is 1 wave = 2 pi rad); Noll (1976) eq. 4 for
the normalisation N_nm; the RMS over the unit disc of the peak-normalised Fringe
polynomials computed by numerical quadrature with scipy (e.g. defocus 2 rho^2 - 1
has RMS 1/sqrt(3)).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import integrate

from modalinfo.telemetry import ModalLog
from modalinfo.telemetry.units import (
    UNITS,
    check_wavelength,
    peak_normalized_from_rms,
    rms_from_peak_normalized,
    unit_scale,
    zernike_rms_normalization,
)


def test_hand_computed_values():
    # 500 nm of OPD at a 500 nm wavelength: 1 wave, 2 pi rad
    assert 500 * unit_scale("nm", "waves", 500e-9) == pytest.approx(1.0, rel=1e-15)
    assert 500 * unit_scale("nm", "rad", 500e-9) == pytest.approx(2 * math.pi, rel=1e-15)
    assert unit_scale("waves", "rad") == pytest.approx(2 * math.pi, rel=1e-15)
    assert unit_scale("um", "nm") == pytest.approx(1000.0, rel=1e-15)
    # 1 rad at 1.6 um is 1600 / (2 pi) nm = 254.648 nm
    assert unit_scale("rad", "nm", 1.6e-6) == pytest.approx(254.64790894703253, rel=1e-14)
    assert unit_scale("rad", "rad") == 1.0


def test_log_hand_value():
    log = ModalLog(np.array([[500.0]]), rate=1.0, units="nm")
    assert log.to_units("waves", wavelength=500e-9).coeffs[0, 0] == pytest.approx(1.0)
    assert log.to_units("rad", wavelength=500e-9).coeffs[0, 0] == pytest.approx(2 * math.pi)
    assert log.to_units("um").coeffs[0, 0] == pytest.approx(0.5)


@settings(max_examples=60, deadline=None)
@given(
    a=st.sampled_from(UNITS),
    b=st.sampled_from(UNITS),
    lam=st.floats(min_value=1e-7, max_value=2e-5),
)
def test_round_trip_scale(a, b, lam):
    assert unit_scale(a, b, lam) * unit_scale(b, a, lam) == pytest.approx(1.0, rel=1e-14)
    via = unit_scale(a, "nm", lam) * unit_scale("nm", b, lam)
    assert unit_scale(a, b, lam) == pytest.approx(via, rel=1e-14)


def test_errors():
    with pytest.raises(ValueError, match=r"`to_units` must be one of"):
        unit_scale("rad", "mm", 1e-6)
    with pytest.raises(TypeError, match=r"`from_units` must be a str"):
        unit_scale(1, "rad")
    with pytest.raises(ValueError, match=r"`wavelength` \(metres\) is required"):
        unit_scale("rad", "nm")
    with pytest.raises(ValueError, match=r"`wavelength` must be > 0.0"):
        unit_scale("rad", "nm", -1e-6)
    with pytest.raises(ValueError, match=r"`wavelength` must be in metres within 1e-07 - "
                                         r"0.0001 .*got 500 \(did you mean 500e-9 m\?\)"):
        unit_scale("rad", "nm", 500.0)
    assert check_wavelength(1e-4) == 1e-4
    with pytest.raises(ValueError, match=r"`lam` must be > 0.0; got 0.0"):
        check_wavelength(0.0, "lam")


def test_rms_normalization_values():
    assert zernike_rms_normalization(0, 0) == 1.0
    with pytest.raises(ValueError, match=r"`n` must be >= 0; got -2"):
        zernike_rms_normalization(-2, 0)  # was a silent NaN
    with pytest.raises(ValueError, match=r"`m` must satisfy \|m\| <= n with n - \|m\| even"):
        zernike_rms_normalization(2, 1)
    assert zernike_rms_normalization(1, 1) == pytest.approx(2.0)
    assert zernike_rms_normalization(2, 0) == pytest.approx(math.sqrt(3))
    np.testing.assert_allclose(
        zernike_rms_normalization([3, 4], [-1, 0]), [math.sqrt(8), math.sqrt(5)]
    )


def _peak_rms(radial, azimuthal_m):
    """RMS over the unit disc of R(rho) cos(m theta) by quadrature."""

    def integrand(rho, theta):
        return (radial(rho) * math.cos(azimuthal_m * theta)) ** 2 * rho

    val, _ = integrate.dblquad(integrand, 0, 2 * math.pi, 0, 1)
    return math.sqrt(val / math.pi)


@pytest.mark.parametrize(
    ("fringe", "radial", "m"),
    [
        (4, lambda r: 2 * r**2 - 1, 0),  # defocus
        (2, lambda r: r, 1),  # tilt x
        (5, lambda r: r**2, 2),  # astigmatism 0 deg
        (9, lambda r: 6 * r**4 - 6 * r**2 + 1, 0),  # primary spherical
    ],
)
def test_peak_to_rms_matches_quadrature(fringe, radial, m):
    # a_peak Z_peak has the RMS a_peak * rms(Z_peak); in unit-RMS terms that is a_rms.
    rms = _peak_rms(radial, m)
    a_rms = rms_from_peak_normalized(np.array([[1.0]]), [fringe])[0, 0]
    assert a_rms == pytest.approx(rms, rel=1e-7)
    back = peak_normalized_from_rms(np.array([[a_rms]]), [fringe])[0, 0]
    assert back == pytest.approx(1.0, rel=1e-14)


def test_peak_conversion_keeps_float32():
    x = np.ones((3, 2), dtype=np.float32)
    assert rms_from_peak_normalized(x, [2, 4]).dtype == np.float32
    with pytest.raises(ValueError, match=r"`modes` must be a 1-D list of Fringe indices"):
        rms_from_peak_normalized(x, [0, 4])


def test_a_wavelength_below_the_vacuum_uv_is_refused():
    # audit 9, centre: 1e-30 m was accepted (500 nm of OPD became 3e25 rad); the range is
    # now the command line's (100 nm - 100 um, one rule); 500 nm of OPD at 100 nm is
    # 5 waves, 10 pi rad (the definition of the units)
    with pytest.raises(ValueError, match=r"`wavelength` must be in metres within 1e-07 .*"
                                         r"got 1e-30\.$"):
        unit_scale("nm", "rad", 1e-30)
    with pytest.raises(ValueError, match=r"within 1e-07 - 0.0001"):
        check_wavelength(1e-12)  # 1 pm, accepted before
    assert unit_scale("nm", "rad", 1e-7) * 500.0 == pytest.approx(10 * np.pi, rel=1e-14)


@pytest.mark.parametrize("value, ok", [
    (1e-7, True), (0.999e-7, False), (3.934e-7, True),  # the edge; Ca II K (solar AO)
    (2.0e-5, True), (1e-4, True), (1.001e-4, False),     # METIS Q band; the edge
    (1e-3, False), (500.0, False), (1.6, False)])        # 1 mm; nm and um typed as m
def test_the_api_and_the_command_line_share_one_wavelength_range(value, ok):
    import argparse

    from modalinfo.cli.shared import wavelength_arg

    text = repr(value)
    if ok:
        assert check_wavelength(value) == value == wavelength_arg(text)
        return
    with pytest.raises(ValueError, match="100 nm - 100 um"):
        check_wavelength(value)
    with pytest.raises(argparse.ArgumentTypeError, match="100 nm - 100 um"):
        wavelength_arg(text)


def test_fringe_conversions_refuse_what_they_cannot_convert():
    """Audit 9: complex coefficients lost their imaginary part, an object array came
    back as objects, a Fringe index 4.5 was truncated to 4, a masked value was used.
    Reference: Noll's N_nm = sqrt(3) of defocus (n = 2, m = 0; Fringe 4)."""
    from modalinfo.telemetry import peak_normalized_from_rms

    assert rms_from_peak_normalized([math.sqrt(3.0)], [4])[0] == pytest.approx(1.0)
    series = np.arange(6.0)  # one mode's series (T,): the same numbers either way
    np.testing.assert_allclose(peak_normalized_from_rms(series, [4]), series * math.sqrt(3))
    with pytest.raises(TypeError, match="`coeffs` must be real"):
        rms_from_peak_normalized(np.ones((3, 2)) + 1j, [2, 4])
    with pytest.raises(TypeError, match="`coeffs` must be a numeric array"):
        rms_from_peak_normalized(np.ones((3, 2), dtype=object), [2, 4])
    with pytest.raises(TypeError, match="`modes` must be an int or an integer array"):
        rms_from_peak_normalized(np.ones((3, 2)), [2, 4.5])
    with pytest.raises(ValueError, match=r"`coeffs` must have shape \(T, 2\) or \(2,\)"):
        peak_normalized_from_rms(np.ones(6), [2, 4])
    with pytest.raises(ValueError, match="`coeffs` is a masked array"):
        rms_from_peak_normalized(np.ma.masked_array(np.ones(2), mask=[1, 0]), [2, 4])


def test_a_log_with_assumed_units_is_not_converted(tmp_path):
    """Audit 9 (files): a foreign file without units loads as rad "(assumed)"; to_units
    scaled it by a guess and kept ``assumed: rad`` beside units nm. Reference: the CLI's
    rule (``convert --units`` refuses without ``--in-units``) and the definition
    OPD[nm] = phase[rad] lambda / (2 pi) once the units are stated."""
    from modalinfo.io import load

    coeffs = np.random.default_rng(0).standard_normal((50, 3))
    np.save(tmp_path / "plain.npy", coeffs)
    log = load(tmp_path / "plain.npy", rate=1000.0)
    assert log.metadata["assumed"]["units"] == "rad"
    with pytest.raises(ValueError, match="`units`: this log's units \\(rad\\) were assumed"):
        log.to_units("nm", wavelength=500e-9)
    assert log.to_units("rad") is not None  # no conversion: nothing guessed
    stated = load(tmp_path / "plain.npy", rate=1000.0, units="rad")
    nm = stated.to_units("nm", wavelength=500e-9)
    np.testing.assert_allclose(nm.coeffs, coeffs * 500.0 / (2 * math.pi), rtol=1e-15)
