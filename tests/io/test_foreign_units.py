"""What a foreign file states about its units, its integer columns and its header row.

References: files written directly with NumPy, plain text, astropy and h5py whose unit
words (FITS ``BUNIT`` / ``TUNITn``, an HDF5 ``units`` attribute, an NPZ ``units``
member, a CSV ``# units:`` comment or ``[nm]`` column suffix) have a known meaning: the
log must carry that unit (metres as nm, the values times 10^9 exactly as NumPy
computes them), a word that is no unit of phase or optical path must be refused
unless the caller states the units (never silently read as rad), and the values must
come back as written. Integers beyond 2^53 are checked against Python's exact int
arithmetic (``float(2**62 + k)`` is the same float for every small k).
"""

from __future__ import annotations

import warnings

import h5py
import numpy as np
import pytest
from astropy.io import fits

from modalinfo.io import LogFormatError, load

rng = np.random.default_rng(9)
X = rng.standard_normal((30, 3))
ROWS = "\n".join(",".join(repr(float(v)) for v in row) for row in X) + "\n"


def _csv(path, text):
    path.write_text(text)
    return path


@pytest.mark.parametrize("header", [
    "# units: nm\nZ2,Z3,Z4\n",
    "# Unit : nm\nZ2,Z3,Z4\n",
    "Z2 [nm],Z3 [nm],Z4 [nm]\n",
    "Z2 (nm),Z3 (nm),Z4 (nm)\n",
    "Z2_nm,Z3_nm,Z4_nm\n",
])
def test_csv_states_nm(tmp_path, header):
    log = load(_csv(tmp_path / "a.csv", header + ROWS))
    assert log.units == "nm" and log.modes == [2, 3, 4] and log.convention == "noll"
    np.testing.assert_array_equal(log.coeffs, X)
    assert "units" not in log.metadata.get("assumed", {})


def test_csv_unknown_or_mixed_units_refused(tmp_path):
    with pytest.raises(LogFormatError, match=r"'furlong'.*--in-units"):
        load(_csv(tmp_path / "f.csv", "# units: furlong\nZ2,Z3,Z4\n" + ROWS))
    # the caller's statement wins over a word the reader cannot know, which is kept
    log = load(tmp_path / "f.csv", units="nm")
    assert log.units == "nm" and "furlong" in log.metadata["file_unit"]
    with pytest.raises(LogFormatError, match="different units"):
        load(_csv(tmp_path / "m.csv", "Z2 [nm],Z3 [rad],Z4 [nm]\n" + ROWS))
    with pytest.raises(LogFormatError, match="one log holds one unit"):
        load(_csv(tmp_path / "c.csv", "# units: rad\nZ2 [nm],Z3 [nm],Z4 [nm]\n" + ROWS))
    # a file stating nm contradicted by the caller: refused, as for any stored value
    with pytest.raises(ValueError, match="contradicts"):
        load(_csv(tmp_path / "n.csv", "# units: nm\nZ2,Z3,Z4\n" + ROWS), units="rad")


def test_fits_bunit_and_tunit(tmp_path):
    fits.PrimaryHDU(X).writeto(tmp_path / "m.fits")
    with fits.open(tmp_path / "m.fits", mode="update") as hdul:
        hdul[0].header["BUNIT"] = "m"
    log = load(tmp_path / "m.fits")
    assert log.units == "nm" and "converted to nm" in log.metadata["unit_conversion"]
    np.testing.assert_array_equal(log.coeffs, X * 1e9)
    fits.PrimaryHDU(X).writeto(tmp_path / "adu.fits")
    with fits.open(tmp_path / "adu.fits", mode="update") as hdul:
        hdul[0].header["BUNIT"] = "ADU"
    with pytest.raises(LogFormatError, match=r"BUNIT.*'ADU'"):
        load(tmp_path / "adu.fits")
    cols = [fits.Column(name=f"Z{j}", format="D", unit="um", array=X[:, k])
            for k, j in enumerate((2, 3, 4))]
    fits.BinTableHDU.from_columns(cols).writeto(tmp_path / "t.fits")
    log = load(tmp_path / "t.fits")
    assert log.units == "um" and log.modes == [2, 3, 4]
    np.testing.assert_array_equal(log.coeffs, X)
    cols[1] = fits.Column(name="Z3", format="D", unit="nm", array=X[:, 1])
    fits.BinTableHDU.from_columns(cols).writeto(tmp_path / "t2.fits")
    with pytest.raises(LogFormatError, match="TUNITn keywords disagree"):
        load(tmp_path / "t2.fits")
    fits.BinTableHDU.from_columns([
        fits.Column(name=f"Z{j} [nm]", format="D", unit="rad", array=X[:, k])
        for k, j in enumerate((2, 3, 4))]).writeto(tmp_path / "t3.fits")
    with pytest.raises(LogFormatError, match="TUNITn keywords say 'rad' but the column names"):
        load(tmp_path / "t3.fits")


def test_hdf5_units_attribute_and_npz_member(tmp_path):
    with h5py.File(tmp_path / "a.h5", "w") as f:
        f.create_dataset("coeffs", data=X).attrs["units"] = "nm"
    log = load(tmp_path / "a.h5")
    assert log.units == "nm"
    np.testing.assert_array_equal(log.coeffs, X)
    with h5py.File(tmp_path / "b.h5", "w") as f:
        f.create_dataset("coeffs", data=X).attrs["units"] = "rad/s"
    with pytest.raises(LogFormatError, match="'rad/s'"):
        load(tmp_path / "b.h5")
    np.savez(tmp_path / "c.npz", coefficients=X, units=np.array("waves"))
    assert load(tmp_path / "c.npz").units == "waves"


@pytest.mark.parametrize("fmt", ["npz", "hdf5", "fits"])
def test_integer_columns_beyond_2_53_refused(tmp_path, fmt):
    big = np.int64(2**62) + np.arange(30, dtype=np.int64)
    path = tmp_path / {"npz": "a.npz", "hdf5": "a.h5", "fits": "a.fits"}[fmt]
    assert len({float(int(v)) for v in big}) == 1  # float64 cannot tell them apart
    if fmt == "npz":
        np.savez(path, z2=big, z3=np.arange(30))
    elif fmt == "hdf5":
        with h5py.File(path, "w") as f:
            f["z2"], f["z3"] = big, np.arange(30)
    else:
        fits.BinTableHDU.from_columns([
            fits.Column(name="Z2", format="K", array=big),
            fits.Column(name="Z3", format="K", array=np.arange(30)),
        ]).writeto(path)
    with pytest.raises(LogFormatError, match=r"2\^53.*30 distinct values become 1"):
        load(path)


def test_csv_header_of_mode_indices(tmp_path):
    log = load(_csv(tmp_path / "i.csv", "2,3,4\n" + ROWS))
    assert log.n_frames == 30 and log.modes == [2, 3, 4]
    np.testing.assert_array_equal(log.coeffs, X)
    assert "mode indices" in log.metadata["header_row"]
    # integer data stays data, as does a first row that is no run of indices
    ints = load(_csv(tmp_path / "n.csv", "2,3,4\n5,6,7\n"))
    np.testing.assert_array_equal(ints.coeffs, [[2, 3, 4], [5, 6, 7]])
    other = load(_csv(tmp_path / "o.csv", "2,4,5\n" + ROWS))
    assert other.n_frames == 31 and list(other.coeffs[0]) == [2.0, 4.0, 5.0]


@pytest.mark.parametrize("name, scale", [
    ("t [s]", 1.0), ("Timestamp (ms)", 1e-3), ("time_sec", 1.0), ("time/\u00b5s", 1e-6),
    ("time [us]", 1e-6), ("TIME (ns)", 1e-9), ("time [h]", 3600.0), ("t_min", 60.0),
])
def test_csv_time_column_spellings(tmp_path, name, scale):
    # each was read as a mode before (a 'labels' log whose first "mode" was the clock)
    t = np.arange(30) * 5.0  # 5 units apart
    text = f"{name},Z2 [nm],Z3 [nm],Z4 [nm]\n" + "\n".join(
        ",".join(repr(float(v)) for v in (t[k], *X[k])) for k in range(30)) + "\n"
    with warnings.catch_warnings():
        # 5 s, 5 us or 5 min apart are outside the wavefront sensors' 1 Hz - 100 kHz and
        # warned on (Leftovers 26-rate); the spelling of the unit is what is tested here
        warnings.filterwarnings("ignore", "`timestamps` give a frame rate of", UserWarning)
        log = load(_csv(tmp_path / "t.csv", text))
    assert log.modes == [2, 3, 4] and log.units == "nm"
    np.testing.assert_allclose(log.timestamps, t * scale, rtol=1e-15)
    np.testing.assert_array_equal(log.coeffs, X)


def test_fits_table_tnull_is_a_missing_value(tmp_path):
    # the FITS standard (4.0, sect. 7.3.2): TNULLn is the value of an undefined integer
    # cell; it was read as the number -32768 before
    z2 = np.array([1, 2, -32768, 4, 5], dtype=np.int16)
    fits.BinTableHDU.from_columns([
        fits.Column(name="Z2", format="I", null=-32768, array=z2),
        fits.Column(name="Z3", format="I", array=np.arange(5, dtype=np.int16)),
    ]).writeto(tmp_path / "n.fits")
    with pytest.raises(ValueError, match="must be finite.*frame 2, column 0"):
        load(tmp_path / "n.fits")
    log = load(tmp_path / "n.fits", nonfinite="interpolate")
    np.testing.assert_array_equal(log.coeffs[:, 0], [1, 2, 3, 4, 5])


@pytest.mark.parametrize("per_mode", [False, True])
def test_hdf5_cf_fill_value_is_a_missing_value(tmp_path, per_mode):
    # CF conventions (1.11, sect. 2.5.1): cells equal to _FillValue / missing_value are
    # undefined; netCDF-4 files are HDF5 and were read with -9999 as a coefficient
    x = X.copy()
    x[4, 1] = -9999.0
    with h5py.File(tmp_path / "f.h5", "w") as f:
        if per_mode:
            for k in range(3):
                f[f"z{k + 2}"] = x[:, k]
            f["z3"].attrs["missing_value"] = -9999.0
        else:
            f.create_dataset("coeffs", data=x).attrs["_FillValue"] = -9999.0
    with pytest.raises(ValueError, match="must be finite.*frame 4, column 1"):
        load(tmp_path / "f.h5")
    log = load(tmp_path / "f.h5", nonfinite="drop")
    np.testing.assert_array_equal(log.coeffs, np.delete(X, 4, axis=0))


def test_csv_quoted_numbers_are_numbers(tmp_path):
    # RFC 4180 lets any field be quoted (pandas QUOTE_ALL, spreadsheets): refused before
    text = '"Z2","Z3","Z4"\n' + "\n".join(
        ",".join(f'"{float(v)!r}"' for v in row) for row in X) + "\n"
    log = load(_csv(tmp_path / "q.csv", text))
    assert log.modes == [2, 3, 4]
    np.testing.assert_array_equal(log.coeffs, X)
    with pytest.raises(LogFormatError, match="'1,5'"):  # a decimal comma stays refused
        load(_csv(tmp_path / "c.csv", 'Z2,Z3\n"1,5",2\n'))
