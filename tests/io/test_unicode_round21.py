"""Round 21 PART b: Unicode in unit words, mode labels and AOT text.

References, all outside the code: the Unicode standard's normalisation forms as Python's
``unicodedata`` implements them (NFKC maps the micro sign U+00B5 to Greek mu U+03BC and
full-width letters to ASCII; NFC composes 'e' + U+0301 into U+00E9); the FITS standard
(4.0, section 4.2: header text is printable ASCII, 0x20-0x7E) as ``str.isascii``; values
written with numpy / h5py and compared with ``numpy.array_equal``.
"""

import unicodedata

import h5py
import numpy as np
import pytest

from modalinfo.io import LogFormatError, load, save
from modalinfo.telemetry import ModalLog

NFD = unicodedata.normalize("NFD", "mode_\u00e9")


def _series(n=300, m=4, seed=3):
    return np.random.default_rng(seed).standard_normal((n, m)).cumsum(0) * 0.01


def test_reference_forms():
    assert unicodedata.normalize("NFKC", "\u00b5m") == "\u03bcm"
    assert unicodedata.normalize("NFKC", "\uff4e\uff4d") == "nm"
    assert NFD != "mode_\u00e9" and unicodedata.normalize("NFC", NFD) == "mode_\u00e9"


@pytest.mark.parametrize("unit", ["\u03bcm", "\u00b5m", "\uff55\uff4d"])
def test_hdf5_units_attribute_in_micrometres(tmp_path, unit):
    # before: the Greek mu and the full-width letters were "not a unit of optical path"
    a = _series()
    path = tmp_path / "u.h5"
    with h5py.File(path, "w") as f:
        d = f.create_dataset("coefficients", data=a)
        d.attrs["units"] = unit
        d.attrs["rate"] = 1000.0
    log = load(path, wavelength=5e-7)
    assert log.units == "um"
    assert np.array_equal(np.asarray(log.coeffs), a)


def test_csv_header_in_greek_mu_micrometres(tmp_path):
    # before: 'Z2 [\u03bcm]' was read as rad "(assumed)", the note saying the file
    # "does not record its units"
    a = _series()
    path = tmp_path / "mu.csv"
    header = ",".join(f"Z{j} [\u03bcm]" for j in range(2, 6))
    np.savetxt(path, a, delimiter=",", header=header, comments="", fmt="%.17g",
               encoding="utf-8")
    log = load(path, rate=1000.0, wavelength=5e-7)
    assert log.units == "um"
    assert log.labels == ["Z2", "Z3", "Z4", "Z5"]
    assert np.array_equal(np.asarray(log.coeffs), a)


def _csv(path, labels, a):
    t = np.arange(a.shape[0]) / 1000.0
    np.savetxt(path, np.column_stack([t, a]), delimiter=",",
               header="time," + ",".join(labels), comments="", fmt="%.17g", encoding="utf-8")


def test_labels_equal_under_nfc_are_one_label(tmp_path):
    # before: 'mode_e\u0301' and 'mode_\u00e9' were two modes printed alike
    path = tmp_path / "twin.csv"
    _csv(path, ["m1", NFD, "mode_\u00e9", "m4"], _series())
    with pytest.raises(ValueError, match="two Unicode spellings"):
        load(path)


# a random-walk / smooth test log: its lagged MI holds < 20 effective samples, which
# select_inputs warns since fixes 40-a (the effective-sample rule); not this test's point
@pytest.mark.filterwarnings("ignore::modalinfo.information.methods.BiasRuleWarning")
def test_a_composed_label_finds_the_decomposed_column(tmp_path):
    # before: `modes` / `target` 'mode_\u00e9' was "not a mode" of a file spelling it NFD
    from modalinfo.information.selection import select_inputs

    a = _series(n=400)
    path = tmp_path / "nfd.csv"
    _csv(path, ["m1", NFD, "m3", "m4"], a)
    log = load(path)
    assert log.labels[1] == NFD  # the file's spelling is kept
    sub = log.select(modes=["mode_\u00e9"])
    assert np.array_equal(np.asarray(sub.coeffs)[:, 0], a[:, 1])
    res = select_inputs(log, "mode_\u00e9", max_lag=2, n_surrogates=19, intervals=False,
                        seed=0)
    ref = select_inputs(log, 1, max_lag=2, n_surrogates=19, intervals=False, seed=0)
    assert res.target == ref.target == NFD
    assert res.inputs == ref.inputs and res.information == ref.information


def test_aot_refusal_names_the_field(tmp_path):
    # before: the telescope metadata was named by its value only; a closedloop config's
    # name failed in astropy naming no field
    log = ModalLog(_series(), rate=1000.0, modes=[2, 3, 4, 5], units="rad",
                   wavelength=5e-7, metadata={"telescope": "T\u00e9lescope \U0001f52d"})
    with pytest.raises(ValueError) as exc:
        save(log, tmp_path / "x.fits", fmt="aot")
    message = str(exc.value)
    assert "main_telescope" in message and "ASCII" in message
    assert "T\u00e9lescope" in message and "\n" not in message
    assert not (tmp_path / "x.fits").exists()
    save(log, tmp_path / "x.h5")  # HDF5 keeps it
    assert load(tmp_path / "x.h5").metadata["telescope"] == "T\u00e9lescope \U0001f52d"


def test_unicode_labels_survive_every_writer(tmp_path):
    labels = ["\u03962", "mode_\u00e9", "\U0001f642", "Z5"]
    a = _series()
    log = ModalLog(a, rate=1000.0, modes=labels, convention="labels", units="rad")
    for name, fmt in [("l.npz", None), ("l.h5", None), ("l.fits", None), ("l.csv", None),
                      ("l_aot.fits", "aot")]:
        save(log, tmp_path / name, fmt=fmt)
        back = load(tmp_path / name)
        assert back.labels == labels, name
        assert np.array_equal(np.asarray(back.coeffs), a), name


def test_log_format_error_is_a_value_error():
    assert issubclass(LogFormatError, ValueError)
