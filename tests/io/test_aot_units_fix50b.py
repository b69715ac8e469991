"""AOT files carry a FITS-standard BUNIT, or none for waves, and read back in their units (fix50-b).

Stop 56 left (fix49-c, which settled it for plain FITS files): ``modalinfo convert LOG
OUT.aot.fits --to-fmt aot`` (``write_aot`` through aotpy) wrote the coefficient image's
``BUNIT = 'waves'`` for a log in waves, not a unit of the FITS standard (4.0, section
4.3, tables 3-5: ``rad`` and ``m`` with the prefixes ``n`` and ``u`` are; a count of
wavelengths is not). AOT's own unit strings (aotpy's ``m``, ``s``, ``rad``, ``deg``...)
are the standard's (its table columns' ``TUNITn`` are aotpy's, e.g.
``electron*s^-1*pix^-1``, which FITS 4.0 does not spell: not ours to change). References:
``astropy.units.Unit(card, format="fits")`` (astropy's FITS-standard unit parser) on
every image's ``BUNIT``, ``verify``,
aotpy's own reader (the image unit another AOT reader sees), and ``numpy.array_equal``
of the read coefficients with the written ones. Every unit of ``ModalLog`` reads back
as written, from the file as written and with its ``MI_JSON`` header stripped (what
``MI_UNITS`` alone says); another writer's ``BUNIT = 'waves'`` still reads in waves.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.io import load, save
from modalinfo.telemetry import ModalLog
from modalinfo.telemetry.units import UNITS

fits = pytest.importorskip("astropy.io.fits")
units = pytest.importorskip("astropy.units")
aotpy = pytest.importorskip("aotpy")


def _log(unit: str) -> ModalLog:
    coeffs = np.random.default_rng(4).standard_normal((64, 3)) * 0.1
    return ModalLog(coeffs, rate=1000.0, modes=[2, 3, 4], units=unit, wavelength=1.65e-6)


def _unit_cards(path) -> list[str]:
    """Every image's ``BUNIT`` (the file verified first)."""
    with fits.open(path) as hdul:
        hdul.verify("exception")
        return [str(h.header["BUNIT"]) for h in hdul
                if str(h.header.get("BUNIT", "")).strip()]


def _coefficient_image(path):
    system = aotpy.AOSystem.read_from_file(str(path))
    return system.loops[0].modal_coefficients


def _stripped(path, out):
    """The file without its ``MI_JSON`` card (checksums renewed)."""
    with fits.open(path) as hdul:
        for hdu in hdul:
            hdu.header.pop("MI_JSON", None)
        hdul.writeto(out, checksum=True)
    return out


@pytest.mark.parametrize("unit", UNITS)
def test_every_unit_is_fits_standard_and_reads_back(tmp_path, unit):
    log = _log(unit)
    path = save(log, tmp_path / f"{unit}.aot.fits", fmt="aot")
    for card in _unit_cards(path):
        units.Unit(card, format="fits")  # raises for a unit FITS does not spell
    image = _coefficient_image(path)
    assert image.unit == (None if unit == "waves" else unit)
    for read in (load(path), load(_stripped(path, tmp_path / "stripped.aot.fits"))):
        assert read.units == unit
        assert "units" not in read.metadata.get("assumed", {})
        assert np.array_equal(read.coeffs, log.coeffs)


def test_convert_to_aot_in_waves(tmp_path, capsys):
    source = save(_log("rad"), tmp_path / "in.npz")
    out = tmp_path / "out.aot.fits"
    assert main(["convert", str(source), str(out), "--to-fmt", "aot", "--units", "waves"]) == 0
    capsys.readouterr()
    for card in _unit_cards(out):
        units.Unit(card, format="fits")
    assert load(out).units == "waves"


def test_another_writers_bunit_waves_still_reads_in_waves(tmp_path):
    """A foreign AOT file that says ``BUNIT = 'waves'`` (and no MI_UNITS) is read in waves."""
    path = save(_log("rad"), tmp_path / "r.aot.fits", fmt="aot")
    with fits.open(path) as hdul:
        for hdu in hdul:
            hdu.header.pop("MI_JSON", None)
            hdu.header.pop("MI_UNITS", None)
            if hdu.header.get("BUNIT") == "rad":
                hdu.header["BUNIT"] = "waves"
        hdul.writeto(tmp_path / "foreign.aot.fits", checksum=True)
    assert load(tmp_path / "foreign.aot.fits").units == "waves"
