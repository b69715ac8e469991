"""The FITS unit cards' comment and provenance (review32, round 32).

Planted-bug review of fix49-c (``io/fits.py``'s ``BUNIT`` / ``MI_UNITS``): the comment
of ``MI_UNITS`` written for a log in waves (R32-I4: swapped condition) and the card
named in the metadata's ``file_unit`` when the units came from ``MI_UNITS`` (R32-I3:
``BUNIT`` named for a file without one) were read by no test. Reference: astropy's
reading of the written header (``fits.open``: the cards present, their comments).
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.io import load, save
from modalinfo.telemetry import ModalLog

fits = pytest.importorskip("astropy.io.fits")


def _log(unit: str) -> ModalLog:
    coeffs = np.random.default_rng(5).standard_normal((32, 3)) * 0.1
    return ModalLog(coeffs, rate=1000.0, modes=[2, 3, 4], units=unit, wavelength=1.65e-6)


@pytest.mark.parametrize("unit", ["rad", "waves"])
def test_mi_units_comment_says_what_bunit_does_not(tmp_path, unit):
    save(_log(unit), tmp_path / "a.fits")
    with fits.open(tmp_path / "a.fits") as hdul:
        header = hdul[0].header
        comment = header.comments["MI_UNITS"]
        has_bunit = "BUNIT" in header
    assert has_bunit == (unit == "rad")
    if unit == "waves":
        assert "wavelengths" in comment and "no BUNIT" in comment, comment
    else:
        assert comment == "units of the modal coefficients", comment


@pytest.mark.parametrize("card", ["BUNIT", "MI_UNITS"])
def test_the_unit_read_names_the_card_it_came_from(tmp_path, card):
    hdu = fits.PrimaryHDU(_log("rad").coeffs)
    hdu.header[card] = "waves"
    hdu.header["CTYPE1"], hdu.header["CTYPE2"] = "MODE", "TIME"
    hdu.writeto(tmp_path / "f.fits")
    back = load(tmp_path / "f.fits", rate=1000.0, wavelength=1.65e-6)
    assert back.units == "waves"
    assert f"keyword {card} of HDU 0" in back.metadata["file_unit"], back.metadata["file_unit"]
