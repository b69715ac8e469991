"""Planted-bug review 18 (issue 27): a damaged FITS header holding a comma is not a CSV.

Leftovers 18-forms' format hint (row M02) tells a CSV from damaged FITS by lines: a
FITS header is 80-character ASCII cards with no line breaks, and its first card reads
``KEYWORD = value`` with the ``=`` in column 9 and a space in column 10 (FITS Standard
4.0, section 4.1.2.2). The existing test's header held no comma, so the card-layout
check was never reached. Reference from outside the code: a FITS file written by
``astropy.io.fits`` whose sixth card is ``OBSERVER= 'Smith, J.'`` (a comma within the
first 512 bytes), its ``SIMPLE`` keyword then damaged byte-wise.
"""

from __future__ import annotations

import numpy as np
import pytest
from astropy.io import fits

from modalinfo.io import LogFormatError, load
from modalinfo.io.formats import sniff_format


@pytest.fixture
def damaged(tmp_path):
    hdu = fits.PrimaryHDU(np.random.default_rng(41).standard_normal((30, 4)))
    hdu.header["OBSERVER"] = "Smith, J."
    good = tmp_path / "good.fits"
    hdu.writeto(good)
    data = bytearray(good.read_bytes())
    assert data.startswith(b"SIMPLE  =") and b"Smith, J." in data[:512]
    assert b"\n" not in data[:2880]
    data[:6] = b"SIMPLX"
    bad = tmp_path / "bad.fits"
    bad.write_bytes(bytes(data))
    return bad


def test_damaged_fits_with_a_comma_is_not_sniffed_as_csv(damaged):
    assert sniff_format(damaged) != "csv"


def test_damaged_fits_with_a_comma_gets_no_csv_hint(damaged):
    with pytest.raises(LogFormatError) as err:
        load(damaged)
    assert "try --fmt csv" not in str(err.value)
