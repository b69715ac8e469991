"""A FITS ``dataset`` written in superscript digits is an HDU name, never int()'s (review29).

Round 29 I6 (modalinfo/io/fits.py:211, fixes 45-c: ``isdigit`` became ``isdecimal``):
planted back, ``dataset="²"`` reached ``int("²")`` and its "invalid literal for int() with
base 10" in place of the refusal naming the HDUs; no test gave a FITS dataset in such
digits. References, outside the package: Python's ``str.isdigit`` / ``isdecimal`` and
``int`` ("²".isdigit() is true, int() refuses it; "２" is decimal and int() reads 2),
astropy writing the file.
"""

import numpy as np
import pytest

from modalinfo import io
from modalinfo.io.formats import LogFormatError


@pytest.fixture
def foreign(tmp_path):
    fits = pytest.importorskip("astropy.io.fits")
    path = tmp_path / "two.fits"
    data = np.random.default_rng(29).standard_normal((50, 3))
    fits.HDUList([fits.PrimaryHDU(), fits.ImageHDU(data, name="COEFFS"),
                  fits.ImageHDU(2 * data, name="OTHER")]).writeto(path)
    return path, data


def test_a_superscript_index_is_refused_naming_the_hdus(foreign):
    path, _ = foreign
    assert "²".isdigit() and not "²".isdecimal()
    with pytest.raises(ValueError, match="invalid literal"):
        int("²")
    with pytest.raises(LogFormatError, match=r"dataset='²' .* names no single HDU .* its "
                                             r"HDUs are 0 \(PRIMARY\), 1 \(COEFFS\), 2 \(OTHER\)"):
        io.load(path, dataset="²", units="rad", modes=[2, 3, 4])


def test_a_fullwidth_index_is_read_as_int_reads_it(foreign):
    path, data = foreign
    assert int("２") == 2
    back = io.load(path, dataset="２", units="rad", modes=[2, 3, 4])
    assert np.array_equal(back.coeffs, 2 * data)
