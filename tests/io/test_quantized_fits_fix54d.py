"""fix54-d (issue 27, stop 59's Noticed): a float image rounded by RICE_1 without ZSCALE.

astropy's ``CompImageHDU(float data, quantize_level=0.0, compression_type="RICE_1")``
casts the floats to integers and writes no ZSCALE column and no ZQUANTIZ card: every
reader reads whole numbers, and nothing said so. The FITS reader now records it in
``metadata["lossy_storage"]`` (shown by ``info`` and noted by the other commands, as the
quantized-tile note of round 52). modalinfo's own writers cannot produce such a file:
they write no tile-compressed HDU (checked here), and ``save`` round-trips exactly.

References from outside the code: astropy's own reading of the file it wrote (the
values are whole numbers, up to 1 from the original: numpy's ``trunc``), astropy's view
of the HDUs our writers produce (no ``CompImageHDU``), and the original array (bit for
bit after the round trip).
"""

from __future__ import annotations

import numpy as np
import pytest
from astropy.io import fits

from modalinfo.io import load, save
from modalinfo.telemetry import ModalLog


def _coeffs() -> np.ndarray:
    return np.random.default_rng(59).standard_normal((400, 8))


def _write(path, kind: str, level: float) -> None:
    hdu = fits.CompImageHDU(_coeffs(), compression_type=kind, quantize_level=level)
    fits.HDUList([fits.PrimaryHDU(), hdu]).writeto(path)


def test_rice_without_zscale_is_said_rounded(tmp_path):
    path = tmp_path / "rice0.fits.fz"
    _write(path, "RICE_1", 0.0)
    with fits.open(path, disable_image_compression=True) as hdul:
        assert "ZSCALE" not in hdul[1].columns.names and "ZQUANTIZ" not in hdul[1].header
    theirs = fits.getdata(path, 1)
    assert np.array_equal(theirs, np.trunc(theirs))  # whole numbers, by astropy
    assert 0.5 < np.abs(theirs - _coeffs()).max() <= 1.0
    log = load(path)
    assert np.array_equal(np.asarray(log.coeffs), theirs)
    note = log.metadata.get("lossy_storage", "")
    assert "RICE_1" in note and "rounded to whole numbers" in note and "HDU 1" in note


def test_lossless_gzip_has_no_note(tmp_path):
    path = tmp_path / "gzip0.fits.fz"
    _write(path, "GZIP_2", 0.0)
    log = load(path)
    assert np.array_equal(np.asarray(log.coeffs), _coeffs())
    assert "lossy_storage" not in log.metadata


@pytest.mark.parametrize("fmt", ["fits", "aot"])
def test_our_writers_write_no_compressed_image_and_round_trip(tmp_path, fmt):
    if fmt == "aot":
        pytest.importorskip("aotpy")
    x = _coeffs().astype(np.float32) if fmt == "aot" else _coeffs()
    log = ModalLog(x, rate=1000.0, modes=list(range(2, 10)))
    path = save(log, tmp_path / f"log_{fmt}.fits", fmt=fmt)
    with fits.open(path, disable_image_compression=True) as hdul:
        assert not any(h.header.get("ZIMAGE") for h in hdul)
        assert not any(isinstance(h, fits.CompImageHDU) for h in hdul)
    back = load(path)
    assert np.array_equal(np.asarray(back.coeffs), x)
    assert "lossy_storage" not in back.metadata
