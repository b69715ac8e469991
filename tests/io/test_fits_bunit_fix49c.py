"""FITS logs carry a standard BUNIT, or none for waves (fix49-c, round 48 PART b, O56).

``modalinfo convert s.npz w.fits --units waves`` wrote ``BUNIT = 'waves'``, which is
not a unit of the FITS standard (4.0, section 4.3, tables 3-5: ``rad``, ``m`` with the
prefixes ``n`` and ``u`` are; a count of wavelengths is not), so astropy refused it.
References: ``astropy.units.Unit(BUNIT, format="fits")`` (astropy's FITS-standard unit
parser), ``fits.open(...).verify("exception")``, and ``numpy.array_equal`` of the read
coefficients with the written ones (bit-exact). A FITS file of another writer with
``BUNIT = 'waves'`` and one of ours whose ``MI_JSON`` was stripped still read in waves.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.io import load, save
from modalinfo.telemetry import ModalLog

fits = pytest.importorskip("astropy.io.fits")
units = pytest.importorskip("astropy.units")

WAVELENGTH = 1.65e-6


def _log(unit: str) -> ModalLog:
    coeffs = np.random.default_rng(4).standard_normal((64, 3)) * 0.1
    return ModalLog(coeffs, rate=1000.0, modes=[2, 3, 4], units=unit, wavelength=WAVELENGTH)


@pytest.mark.parametrize("unit", ["rad", "nm", "um", "waves"])
def test_written_bunit_is_fits_standard_and_reads_back(tmp_path, unit):
    log = _log(unit)
    path = save(log, tmp_path / f"{unit}.fits")
    with fits.open(path, checksum=True) as hdul:
        hdul.verify("exception")
        header = hdul[0].header
        assert header["MI_UNITS"] == unit
        if unit == "waves":
            assert "BUNIT" not in header
        else:
            assert units.Unit(header["BUNIT"], format="fits") == units.Unit(unit)
    back = load(path)
    assert back.units == unit and back.wavelength == WAVELENGTH
    assert back.coeffs.dtype == log.coeffs.dtype and np.array_equal(back.coeffs, log.coeffs)


def test_convert_units_waves_writes_no_bunit(tmp_path):
    from modalinfo.cli import main

    src = save(_log("rad"), tmp_path / "s.npz")
    assert main(["convert", str(src), str(tmp_path / "w.fits"), "--units", "waves"]) == 0
    with fits.open(tmp_path / "w.fits") as hdul:
        hdul.verify("exception")
        assert "BUNIT" not in hdul[0].header and hdul[0].header["MI_UNITS"] == "waves"
    back = load(tmp_path / "w.fits")
    assert back.units == "waves"
    assert np.allclose(back.coeffs * 2 * np.pi, _log("rad").coeffs, rtol=1e-15, atol=0)


@pytest.mark.parametrize("card", ["BUNIT", "MI_UNITS"])
def test_a_foreign_or_stripped_file_in_waves_reads_in_waves(tmp_path, card):
    data = _log("rad").coeffs
    hdu = fits.PrimaryHDU(data)
    hdu.header[card] = "waves"
    hdu.header["CTYPE1"], hdu.header["CTYPE2"] = "MODE", "TIME"
    hdu.writeto(tmp_path / "old.fits")
    back = load(tmp_path / "old.fits", rate=1000.0, wavelength=WAVELENGTH)
    assert back.units == "waves"
    assert np.array_equal(back.coeffs, data)
