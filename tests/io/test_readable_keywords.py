"""The keywords and attributes our FITS and HDF5 files carry for people (and other tools).

``read_fits``/``read_hdf5`` take the JSON header as authoritative, so a wrong readable
keyword would not break our own round trips; these tests read the files with the
libraries another tool would use, without ``modalinfo.io``.

References (outside the code): ``astropy.io.fits`` and ``h5py`` reading the written files;
the log's own values (rate [Hz], wavelength [m], units, convention, labels, timestamps
[s]) as given to ``ModalLog`` in the test; the FITS standard's axis order (NAXIS1 is the
fastest axis: modes, NAXIS2 frames).
"""

import h5py
import numpy as np
import pytest
from astropy.io import fits

from modalinfo.io import save
from modalinfo.telemetry import ModalLog

RATE, WAVELENGTH = 1234.5, 633e-9


@pytest.fixture
def log():
    coeffs = np.random.default_rng(2).standard_normal((40, 3)) * 50.0
    times = np.arange(40) / RATE + 0.25
    return ModalLog(coeffs, timestamps=times, modes=[4, 5, 6], units="nm",
                    wavelength=WAVELENGTH, metadata={"telescope": "GREGOR"})


def test_fits_keywords_read_by_astropy(tmp_path, log):
    path = save(log, tmp_path / "log.fits")
    with fits.open(path) as hdul:
        head = hdul[0].header
        assert (head["NAXIS1"], head["NAXIS2"]) == (3, 40)  # modes fastest
        np.testing.assert_array_equal(hdul[0].data, log.coeffs)
        assert head["BUNIT"] == "nm"
        assert head["MI_CONV"] == "noll"
        assert head["MI_RATE"] == pytest.approx(RATE, rel=1e-12)
        assert head["MI_WAVE"] == pytest.approx(WAVELENGTH, rel=1e-12)
        assert head["TELESCOP"] == "GREGOR"
        times = hdul["TIMES"]
        assert times.header["BUNIT"] == "s"
        np.testing.assert_array_equal(times.data, np.arange(40) / RATE + 0.25)


def test_hdf5_attributes_read_by_h5py(tmp_path, log):
    path = save(log, tmp_path / "log.h5")
    with h5py.File(path, "r") as f:
        dset = f["coefficients"]
        np.testing.assert_array_equal(dset[()], log.coeffs)
        assert dset.attrs["units"] == b"nm"
        assert dset.attrs["convention"] == b"noll"
        assert [lab.decode() for lab in dset.attrs["labels"]] == ["Z4", "Z5", "Z6"]
        np.testing.assert_array_equal(f["timestamps"][()], np.arange(40) / RATE + 0.25)
