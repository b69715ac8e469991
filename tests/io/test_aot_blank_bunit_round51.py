"""Stop 57, fix51-c item 6 (review33's uncovered plant R33-A4): a blank BUNIT defers to MI_UNITS.

``io/aot.py``'s reader takes the coefficient image's unit from its ``BUNIT``, and from
write_aot's ``MI_UNITS`` card when the ``BUNIT`` is missing or blank (a log in waves:
no FITS-standard unit spells waves, so write_aot writes none). review33's plant
``if not isinstance(unit, str)`` (a blank ``BUNIT``, a ``str``, no longer read as
missing) escaped every test: write_aot never writes a blank ``BUNIT``. Another writer
(or an edit) may: here astropy writes ``BUNIT = ' '`` into the file write_aot made.

Reference: the log as written (its units, ``numpy.array_equal`` of the coefficients),
read back from the file with its ``MI_JSON`` card stripped (so that ``MI_UNITS`` and
``BUNIT`` alone say the unit, as tests/io/test_aot_units_fix50b.py reads it).
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.io import load, save
from modalinfo.telemetry import ModalLog

fits = pytest.importorskip("astropy.io.fits")
pytest.importorskip("aotpy")


@pytest.mark.parametrize("blank", [" ", ""])
def test_blank_bunit_reads_the_mi_units_card(tmp_path, blank):
    log = ModalLog(np.random.default_rng(33).standard_normal((64, 3)) * 0.1, rate=1000.0,
                   modes=[2, 3, 4], units="waves", wavelength=1.65e-6)
    path = save(log, tmp_path / "w.aot.fits", fmt="aot")
    edited = tmp_path / "blank.aot.fits"
    with fits.open(path) as hdul:
        images = [h for h in hdul if "MI_UNITS" in h.header]
        assert len(images) == 1 and "BUNIT" not in images[0].header
        for hdu in hdul:
            hdu.header.pop("MI_JSON", None)
        images[0].header["BUNIT"] = blank
        hdul.writeto(edited, checksum=True)
    read = load(edited)
    assert read.units == "waves"
    assert "units" not in read.metadata.get("assumed", {})
    assert np.array_equal(read.coeffs, log.coeffs)
