"""AOT: a file's own mode names (card MI_MODES) win even when its images are Zernikes.

Round 9 of planted bugs (review9, bug F5): ``read_aot`` on a file without our own
header (``MI_JSON``: a foreign file, or closedloop's export) let the 0.95-correlation
identification rename modes whose images are exact Noll Zernikes although the file
names them (card ``MI_MODES``); the existing test wrote K-L images, which fail the
identification, and kept ``MI_JSON``, so that branch was never reached. Reference: the
names written in the file (``MI_MODES``, read back here with astropy), which
``read_aot_basis`` already honours, and the values as written.
"""

import json

import numpy as np
import pytest

pytest.importorskip("aotpy")
fits = pytest.importorskip("astropy.io.fits")

from modalinfo.bases import ModalBasis, Pupil, ZernikeBasis  # noqa: E402
from modalinfo.io.aot import read_aot, read_aot_basis, write_aot  # noqa: E402
from modalinfo.telemetry import ModalLog  # noqa: E402

NAMES = ["tip", "tilt", "focus", "astig45", "astig0"]


def test_zernike_images_under_the_files_own_names_keep_them(tmp_path):
    zb = ZernikeBasis(Pupil(24), modes=range(2, 7))
    named = ModalBasis(zb.matrix, zb.pupil, labels=NAMES)
    coeffs = np.random.default_rng(3).standard_normal((40, 5))
    log = ModalLog(coeffs, rate=1e3, modes=NAMES, convention="labels")
    path = write_aot(log, tmp_path / "named.fits", basis=named)
    with fits.open(path, mode="update") as hdus:  # a file without our own header
        found = [h for h in hdus if "MI_JSON" in h.header]
        assert found
        for h in found:
            assert json.loads(h.header["MI_MODES"]) == NAMES
            del h.header["MI_JSON"]
    basis, ident = read_aot_basis(path)
    assert ident.all_zernike and bool(np.all(ident.sign > 0))  # the identification's branch
    assert list(basis.labels) == NAMES
    back = read_aot(path)
    assert list(back.labels) == NAMES
    np.testing.assert_array_equal(back.coeffs, coeffs)
