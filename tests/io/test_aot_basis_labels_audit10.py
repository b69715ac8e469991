"""K-L mode images written to an AOT file keep their names (audit 10, feedback, row
aotb-kl).

Reference: the round trip (labels and mode images as written) and the K-L modes'
Zernike content, measured here by least squares (numpy) of the images on the Zernike
basis: the third K-L mode of Z2..Z11 is 0.98 Z4 - 0.18 Z11, not Z4. Before, the images
passing the 0.95 correlation rule were read back as ``Z2, Z3, Z4, Z6...`` and the
file's own names (card ``MI_MODES``) were ignored.
"""

import numpy as np
import pytest

pytest.importorskip("aotpy")

from modalinfo.bases import KLBasis, Pupil, ZernikeBasis  # noqa: E402
from modalinfo.io.aot import read_aot, read_aot_basis, write_aot  # noqa: E402
from modalinfo.telemetry import ModalLog  # noqa: E402


def test_kl_images_keep_their_labels(tmp_path):
    pupil = Pupil(32, diameter=0.7)
    zb = ZernikeBasis(pupil, modes=range(2, 12))
    kb = KLBasis.from_turbulence(pupil, 10, zernike_modes=range(2, 12))
    content = np.linalg.lstsq(zb.matrix, kb.matrix, rcond=None)[0]
    assert abs(content[9, 2]) > 0.1  # KL3 holds Z11: not a Zernike
    log = ModalLog(np.random.default_rng(1).standard_normal((50, 10)), rate=1e3,
                   modes=list(kb.labels), convention="labels")
    path = write_aot(log, tmp_path / "kl.fits", basis=kb)
    basis, _ = read_aot_basis(path)
    assert list(basis.labels) == list(kb.labels)
    np.testing.assert_array_equal(basis.matrix, kb.matrix)
    assert read_aot(path) == log


def test_zernike_images_still_named_by_identification(tmp_path):
    zb = ZernikeBasis(Pupil(24), modes=range(2, 8))
    log = ModalLog(np.random.default_rng(2).standard_normal((40, 6)), rate=1e3)
    basis, ident = read_aot_basis(write_aot(log, tmp_path / "z.fits", basis=zb))
    assert list(basis.labels) == list(zb.labels) and ident.all_zernike
