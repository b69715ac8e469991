"""Round 31 PART b (issue 27): MATLAB MAT-files and Feather tables, read right or refused.

docs/ADVERSARIAL.md, "Round 31 PART b, issue 27": a MATLAB v5 / v4 MAT-file and a Feather
table were told "a CSV must be UTF-8: re-save it as UTF-8" (a01-a03, a11, a37); a
MATLAB v7.3 MAT-file (an HDF5 file behind a 512-byte user block) was "a corrupt CSV
file: UnicodeDecodeError" (a04, a24); and a v7.3 variable of 300 frames x 200 modes,
which MATLAB stores column-major so that it arrives as 200 x 300, was read as 200 frames
of 300 modes without a word (a23, a42).

References, all from outside the code: ``scipy.io.savemat`` writes the v5 and v4 files
and ``scipy.io.loadmat`` reads the v5 one back (the refusal's advice, followed word for
word, gives the matrix exactly); ``pandas.DataFrame.to_feather`` / ``read_feather`` the
Feather table; the v7.3 file is built as MATLAB documents its format (the text header
"MATLAB 7.3 MAT-file" in a 512-byte HDF5 user block, each variable a dataset with the
attribute ``MATLAB_class``, dimensions in reverse: a T x M matrix is an (M, T) dataset
to a row-major reader) with ``h5py``; the expected matrix is the array written.
"""

from __future__ import annotations

import h5py
import numpy as np
import pytest
import scipy.io

from modalinfo.io import detect_format, load
from modalinfo.io.files import LogFormatError

T, M = 300, 200  # near-square: the shape rule alone cannot tell the layout


def _log(n_frames=T, n_modes=M):
    return np.random.default_rng(31).normal(size=(n_frames, n_modes))


def _mat73(path, x, *, matlab=True):
    """Write ``x`` (T x M as MATLAB sees it) the way MATLAB's ``save -v7.3`` lays it out."""
    with h5py.File(path, "w", userblock_size=512) as f:
        dset = f.create_dataset("coefficients", data=x.T)  # column-major: (M, T) on disk
        if matlab:
            dset.attrs["MATLAB_class"] = np.bytes_("double")
    if matlab:
        with open(path, "r+b") as fh:
            fh.write(b"MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: Mon Nov 30 "
                     b"12:00:00 2026 HDF5 schema 1.00 .".ljust(116, b" ")
                     + b"\x00" * 8 + b"\x00\x02IM")


def test_mat73_is_read_as_hdf5_and_its_layout_is_asked_not_guessed(tmp_path):
    x = _log()
    _mat73(tmp_path / "tel.mat", x)
    assert detect_format(tmp_path / "tel.mat") == "hdf5"
    with pytest.raises(LogFormatError, match="MATLAB_class") as err:
        load(tmp_path / "tel.mat", rate=1000.0)
    assert "column-major" in str(err.value) and "--transpose" in str(err.value)
    log = load(tmp_path / "tel.mat", rate=1000.0, transpose=True)
    assert log.coeffs.shape == (T, M)
    np.testing.assert_array_equal(log.coeffs, x)


def test_mat73_variable_renamed_h5_is_asked_too(tmp_path):
    x = _log()
    _mat73(tmp_path / "tel.h5", x)
    with pytest.raises(LogFormatError, match="MATLAB_class"):
        load(tmp_path / "tel.h5", rate=1000.0)
    with pytest.raises(LogFormatError, match="MATLAB_class"):
        load(tmp_path / "tel.h5", rate=1000.0, dataset="coefficients")
    kept = load(tmp_path / "tel.h5", rate=1000.0, transpose=False)  # the caller's word
    np.testing.assert_array_equal(kept.coeffs, x.T)


def test_a_plain_hdf5_dataset_of_that_shape_is_still_read_as_stored(tmp_path):
    x = _log()
    _mat73(tmp_path / "plain.h5", x, matlab=False)
    np.testing.assert_array_equal(load(tmp_path / "plain.h5", rate=1000.0).coeffs, x.T)


def test_mat_v5_refusal_advice_followed_gives_the_matrix(tmp_path, monkeypatch):
    x = _log(400, 6)
    scipy.io.savemat(tmp_path / "tel.mat", {"coefficients": x})
    with pytest.raises(LogFormatError) as err:
        load(tmp_path / "tel.mat", rate=1000.0)
    text = str(err.value)
    assert "MATLAB v5 MAT-file" in text and "UTF-8" not in text and "\n" not in text
    advice = text.split("convert it in Python with `", 1)[1].split("`", 1)[0]
    monkeypatch.chdir(tmp_path)
    exec(advice.replace("PATH", "'tel.mat'").replace("VARIABLE", "coefficients"),
         {"numpy": np, "scipy": scipy})
    np.testing.assert_array_equal(load(tmp_path / "log.npy", rate=1000.0).coeffs, x)


def test_mat_v4_is_named_a_mat_file_and_a_text_mat_stays_a_csv(tmp_path):
    x = _log(400, 6)
    scipy.io.savemat(tmp_path / "tel4.mat", {"coefficients": x}, format="4")
    with pytest.raises(LogFormatError, match="MATLAB MAT-file") as err:
        load(tmp_path / "tel4.mat", rate=1000.0)
    assert "UTF-8" not in str(err.value)
    np.savetxt(tmp_path / "ascii.mat", x)  # MATLAB's `save -ascii` writes text
    np.testing.assert_allclose(load(tmp_path / "ascii.mat", rate=1000.0).coeffs, x,
                               rtol=1e-15)


def test_feather_refusal_advice_followed_gives_the_table(tmp_path, monkeypatch):
    pd = pytest.importorskip("pandas")
    pytest.importorskip("pyarrow")
    x = _log(400, 6)
    pd.DataFrame(x, columns=[f"Z{j}" for j in range(2, 8)]).to_feather(tmp_path / "t.feather")
    with pytest.raises(LogFormatError) as err:
        load(tmp_path / "t.feather", rate=1000.0)
    text = str(err.value)
    assert "Arrow (Feather)" in text and "UTF-8" not in text
    advice = text.split("convert it in Python with `", 1)[1].split("`", 1)[0]
    monkeypatch.chdir(tmp_path)
    exec(advice.replace("PATH", "'t.feather'"), {"pandas": pd})
    log = load(tmp_path / "log.csv", rate=1000.0)
    np.testing.assert_array_equal(log.coeffs, x)
    assert [f"Z{j}" for j in log.modes] == [f"Z{j}" for j in range(2, 8)]
