"""Round 19 PART b: HDF5 attributes that contradict the header; non-ASCII text in AOT.

References from outside the code: the file's own attributes read back with ``h5py``
(what another tool, HDFView or h5py, shows the user) and ``str.isascii`` (FITS tables
hold ASCII text, FITS standard 4.0 section 7.3.3). Before the fix an HDF5 log whose
``units`` attribute was edited to 'nm' (or whose ``labels`` were relabelled) was read
as the header said without a word, and a log with a telescope named 'T\u00e9ide' failed
to convert to AOT with "'ascii' codec can't encode character", naming neither the text
nor a way out.
"""

import h5py
import numpy as np
import pytest

from modalinfo.io import load, save
from modalinfo.io.files import LogFormatError
from modalinfo.telemetry import ModalLog


def _log(**metadata):
    x = np.random.default_rng(0).normal(size=(40, 3)) * 0.1
    return ModalLog(x, rate=1000.0, modes=[2, 3, 4], units="rad", wavelength=5e-7,
                    metadata=metadata)


@pytest.mark.parametrize(("key", "value", "match"), [
    ("units", np.bytes_(b"nm"), "units='nm'"),
    ("convention", np.bytes_(b"ansi"), "convention='ansi'"),
    ("labels", np.array([b"Z3", b"Z4", b"Z5"]), "labels"),
])
def test_edited_hdf5_attribute_is_refused(tmp_path, key, value, match):
    path = tmp_path / "log.h5"
    save(_log(), path)
    assert load(path).units == "rad"
    with h5py.File(path, "a") as f:
        f["coefficients"].attrs[key] = value
    with h5py.File(path, "r") as f:  # what another tool shows: the edited value
        assert np.array_equal(f["coefficients"].attrs[key], value)
    with pytest.raises(LogFormatError, match=match):
        load(path)


def test_untouched_hdf5_attributes_read(tmp_path):
    path = tmp_path / "log.h5"
    log = _log()
    save(log, path)
    back = load(path)
    assert np.array_equal(back.coeffs, log.coeffs) and back.labels == ["Z2", "Z3", "Z4"]


def test_aot_refuses_non_ascii_text_by_name(tmp_path):
    name = "T\u00e9ide"
    assert not name.isascii()
    path = tmp_path / "log.aot"
    with pytest.raises(ValueError, match=f"'{name}'.*ASCII|ASCII.*'{name}'"):
        save(_log(telescope=name), path, fmt="aot")
    assert list(tmp_path.iterdir()) == []  # nothing half-written
    save(_log(telescope="Teide"), path, fmt="aot")  # the advice: rename it
    assert load(path, fmt="aot").coeffs.shape == (40, 3)
