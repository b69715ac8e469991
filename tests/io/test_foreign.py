"""Reading files written by other software, hints, format detection and safe saving.

References: arrays written directly with NumPy (``np.save``/``np.savez``), plain
text, astropy (image and binary table) and h5py, whose values must come back
unchanged; the documented rules for hints (fill what is missing, refuse
contradictions), overwrite protection and atomic writes.
"""

from __future__ import annotations

import os

import numpy as np
import pytest
from astropy.io import fits

from modalinfo.io import LogFormatError, detect_format, load, save
from modalinfo.telemetry import ModalLog

rng = np.random.default_rng(42)
X = rng.standard_normal((50, 4))


def test_plain_npy_with_hints(tmp_path):
    np.save(tmp_path / "a.npy", X.astype(np.float32))
    log = load(tmp_path / "a.npy", rate=500.0, units="nm", modes=[4, 5, 6, 7], wavelength=5e-7)
    np.testing.assert_array_equal(log.coeffs, X.astype(np.float32))
    assert log.dtype == np.float32 and log.rate == 500.0 and log.modes == [4, 5, 6, 7]
    # integer modes without a convention: Noll indexing is assumed, and said so
    assert log.metadata == {
        "source_file": "a.npy", "source_format": "npy", "assumed": {"convention": "noll"}
    }
    mm = load(tmp_path / "a.npy", mmap=True)
    assert isinstance(mm.coeffs, np.memmap) and mm.rate is None


def test_npy_fortran_order_and_wrong_ndim(tmp_path):
    np.save(tmp_path / "f.npy", np.asfortranarray(X))
    np.testing.assert_array_equal(load(tmp_path / "f.npy").coeffs, X)
    np.testing.assert_array_equal(load(tmp_path / "f.npy", mmap=True).coeffs, X)
    np.save(tmp_path / "v.npy", X[:, 0])
    with pytest.raises(ValueError, match=r"v\.npy'.*`coeffs` must be 2-D"):
        load(tmp_path / "v.npy")


def test_foreign_npz(tmp_path):
    t = np.arange(50) / 200.0
    np.savez(tmp_path / "a.npz", zernike=X, t=t)
    log = load(tmp_path / "a.npz")
    np.testing.assert_array_equal(log.coeffs, X)
    np.testing.assert_array_equal(log.times, t)
    assert log.rate == pytest.approx(200.0)
    np.savez_compressed(tmp_path / "c.npz", whatever=X)
    np.testing.assert_array_equal(load(tmp_path / "c.npz", mmap=True).coeffs, X)
    np.savez(tmp_path / "two.npz", a=X, b=X)
    with pytest.raises(LogFormatError, match=r"2 2-D numeric arrays \(a, b\)"):
        load(tmp_path / "two.npz")


def test_foreign_csv_variants(tmp_path):
    body = "\n".join(",".join(repr(float(v)) for v in row) for row in X)
    (tmp_path / "plain.csv").write_text(body + "\n")
    log = load(tmp_path / "plain.csv", rate=100.0)
    np.testing.assert_array_equal(log.coeffs, X)
    assert log.modes == [2, 3, 4, 5]

    lines = ["# telescope: LOST", "# loop: closed", "time;Z4;Z5;Z6;Z7"]
    lines += [";".join(repr(float(v)) for v in (i / 50.0, *row)) for i, row in enumerate(X)]
    (tmp_path / "hdr.txt").write_text("\n".join(lines) + "\n")
    log = load(tmp_path / "hdr.txt")
    np.testing.assert_array_equal(log.coeffs, X)
    assert log.modes == [4, 5, 6, 7] and log.convention == "noll"
    assert log.rate == pytest.approx(50.0)
    assert log.metadata["telescope"] == "LOST" and log.metadata["loop"] == "closed"

    ws = "\n".join("  ".join(f"{v:.6f}" for v in row) for row in X[:, :2])
    (tmp_path / "ws.dat").write_text("KL1 KL2\n" + ws + "\n")
    log = load(tmp_path / "ws.dat", rate=1.0)
    assert log.convention == "labels" and log.labels == ["KL1", "KL2"]
    np.testing.assert_allclose(log.coeffs, X[:, :2], atol=1e-6)


def test_foreign_csv_errors(tmp_path):
    (tmp_path / "ragged.csv").write_text("1,2,3\n4,5\n")
    with pytest.raises(LogFormatError, match=r"corrupt CSV file .*ragged\.csv"):
        load(tmp_path / "ragged.csv")
    (tmp_path / "words.csv").write_text("a,b\nc,d\n")
    with pytest.raises(LogFormatError, match=r"words\.csv"):
        load(tmp_path / "words.csv")
    (tmp_path / "nan.csv").write_text("1,2\nnan,3\n4,5\n")
    with pytest.raises(ValueError, match=r"nan\.csv'.*must be finite"):
        load(tmp_path / "nan.csv", rate=1.0)
    log = load(tmp_path / "nan.csv", rate=1.0, nonfinite="interpolate")
    assert log.coeffs[1, 0] == 2.5 and len(log.repairs) == 1


def test_foreign_fits_image_and_table(tmp_path):
    hdu = fits.PrimaryHDU(X.astype(">f4"))
    hdu.header["BUNIT"] = "nm"
    hdu.writeto(tmp_path / "img.fits")
    log = load(tmp_path / "img.fits", rate=1000.0)
    np.testing.assert_array_equal(log.coeffs, X.astype(np.float32))
    assert log.coeffs.dtype == np.float32 and log.coeffs.dtype.isnative and log.units == "nm"

    cols = [fits.Column(name="TIME", format="D", array=np.arange(50) / 10.0)]
    cols += [
        fits.Column(name=f"Z{j}", format="D", array=X[:, k]) for k, j in enumerate([2, 3, 4, 5])
    ]
    fits.HDUList([fits.PrimaryHDU(), fits.BinTableHDU.from_columns(cols)]).writeto(
        tmp_path / "t.fits"
    )
    log = load(tmp_path / "t.fits")
    np.testing.assert_array_equal(log.coeffs, X)
    assert log.modes == [2, 3, 4, 5] and log.rate == pytest.approx(10.0)


def test_foreign_hdf5(tmp_path):
    import h5py

    with h5py.File(tmp_path / "a.h5", "w") as f:
        f.create_dataset("loop/modes", data=X)
        f.create_dataset("loop/time", data=np.arange(50) * 1e-3)
    log = load(tmp_path / "a.h5")
    np.testing.assert_array_equal(log.coeffs, X)
    assert log.rate == pytest.approx(1000.0)
    mm = load(tmp_path / "a.h5", mmap=True)
    assert isinstance(mm.coeffs, np.memmap)
    np.testing.assert_array_equal(mm.coeffs, X)
    with h5py.File(tmp_path / "chunked.h5", "w") as f:
        f.create_dataset("data", data=X, chunks=(10, 4), compression="gzip")
    got = load(tmp_path / "chunked.h5", mmap=True, rate=1.0)
    assert not isinstance(got.coeffs, np.memmap)  # compressed: read in full
    np.testing.assert_array_equal(got.coeffs, X)


def test_hints_fill_but_never_contradict(tmp_path):
    log = ModalLog(X, rate=100.0, units="nm", metadata={"telescope": "LOST"})
    path = save(log, tmp_path / "a.npz")
    assert load(path, rate=100.0).rate == 100.0  # agreeing hint is fine
    assert load(path, wavelength=5e-7).wavelength == 5e-7  # missing: filled
    assert load(path, metadata={"site": "x"}).metadata == {"telescope": "LOST", "site": "x"}
    with pytest.raises(ValueError, match=r"hint `rate`=200.0 contradicts the value 100.0"):
        load(path, rate=200.0)
    with pytest.raises(ValueError, match=r"hint `units`='rad' contradicts"):
        load(path, units="rad")
    with pytest.raises(ValueError, match=r"hint metadata\['telescope'\]='VLT' contradicts"):
        load(path, metadata={"telescope": "VLT"})
    with pytest.raises(TypeError, match=r"unknown hint `speed`"):
        load(path, speed=3)


def test_detect_format(tmp_path):
    log = ModalLog(X, rate=1.0)
    for fmt, name in (("npz", "a.dat"), ("fits", "b.csv"), ("hdf5", "c.npz"), ("csv", "d.bin")):
        path = save(log, tmp_path / name, fmt=fmt)
        assert detect_format(path) == fmt  # content beats the extension
    np.save(tmp_path / "e.xyz", X)
    assert detect_format(tmp_path / "e.xyz.npy") == "npy"


def test_path_errors(tmp_path):
    with pytest.raises(FileNotFoundError, match=r"no such file: '.*nope\.npz'"):
        load(tmp_path / "nope.npz")
    with pytest.raises(IsADirectoryError, match="is a directory"):
        load(tmp_path)
    with pytest.raises(TypeError, match=r"`path` must be a str or os.PathLike"):
        load(3)
    with pytest.raises(ValueError, match=r"`fmt` must be one of npz, npy, csv, fits, hdf5"):
        load(tmp_path / "x", fmt="xls")


@pytest.mark.parametrize("fmt", ["npz", "npy", "csv", "fits", "hdf5"])
def test_format_functions_name_a_bad_path(fmt):
    import modalinfo.io as mio

    with pytest.raises(TypeError, match=r"`path` must be a str or os.PathLike; got int"):
        getattr(mio, f"read_{fmt}")(3)
    if fmt != "npy":
        with pytest.raises(TypeError, match=r"`path` must be a str or os.PathLike; got int"):
            getattr(mio, f"write_{fmt}")(ModalLog(X, rate=1.0), 3)


def test_save_never_overwrites_and_is_atomic(tmp_path):
    log = ModalLog(X, rate=1.0)
    path = save(log, tmp_path / "a.npz")
    before = path.read_bytes()
    other = ModalLog(X + 1, rate=1.0)
    with pytest.raises(FileExistsError, match=r"a\.npz' exists; pass overwrite=True"):
        save(other, path)
    assert path.read_bytes() == before
    save(other, path, overwrite=True)
    np.testing.assert_array_equal(load(path).coeffs, X + 1)
    # no temporary file is left behind, even after a failing write
    with pytest.raises(ValueError, match="cannot tell the format"):
        save(log, tmp_path / "a.xyz")
    with pytest.raises(FileNotFoundError, match="does not exist"):
        save(log, tmp_path / "missing" / "a.npz")
    with pytest.raises(TypeError, match="`log` must be a ModalLog"):
        save(X, tmp_path / "b.npz")
    assert sorted(os.listdir(tmp_path)) == ["a.npz"]


def test_crash_during_write_leaves_no_file(tmp_path, monkeypatch):
    import modalinfo.io.npz as npz_mod

    def boom(*args, **kwargs):
        raise RuntimeError("disk full")

    monkeypatch.setattr(npz_mod.np, "savez", boom)
    with pytest.raises(RuntimeError, match="disk full"):
        save(ModalLog(X, rate=1.0), tmp_path / "a.npz")
    assert os.listdir(tmp_path) == []


def test_edited_csv_needs_verify_false(tmp_path):
    log = ModalLog(X[:5, :2], rate=10.0, metadata={"loop": "open"})
    path = save(log, tmp_path / "e.csv")
    lines = path.read_text().splitlines()
    lines[2] = "0.5,0.25"  # a person edits the first data row
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(LogFormatError, match=r"coefficients do not match their SHA-256"):
        load(path)
    edited = load(path, verify=False)
    np.testing.assert_array_equal(edited.coeffs[0], [0.5, 0.25])
    np.testing.assert_array_equal(edited.coeffs[1:], X[1:5, :2])
    assert edited.metadata == {"loop": "open"}


def test_a_rate_replacing_nanosecond_timestamps_starts_at_zero(tmp_path):
    """Unix nanoseconds read as seconds (1.76e18) cannot be a start time at 2 kHz: float64
    near them steps by 256 s (IEEE spacing, numpy.spacing). With rate= replacing them the
    axis starts at 0 and the first timestamp is kept, exact, in the metadata (stop 37: the
    round-9 start-time rule had made `--rate` refuse these files)."""
    from modalinfo.io import load

    ns = [1_764_380_000_000_000_000 + k * 500_000 for k in range(50)]
    d = np.random.default_rng(1).standard_normal((50, 2))
    path = tmp_path / "ns.csv"
    rows = (f"{t},{float(a)!r},{float(b)!r}\n" for t, (a, b) in zip(ns, d, strict=True))
    path.write_text("time,Z2,Z3\n" + "".join(rows))
    log = load(path, rate=2000.0)
    assert log.start_time == 0.0
    assert log.metadata["file_start_time"] == float(ns[0])
    assert np.spacing(float(ns[0])) == 256.0
    np.testing.assert_array_equal(log.coeffs, d)


def test_rate_hint_keeps_jittered_timestamps_and_their_gap(tmp_path):
    # Reference: the time axis by construction: 2 kHz with 5 % timing noise and 100
    # frames missing after frame 1499. The caller's true rate agrees with the
    # timestamps, so they (and the gap) are kept; the median interval was 0.2 % off on
    # this seed and the timestamps, gap included, were replaced by a uniform axis.
    rng = np.random.default_rng(4)
    t = np.sort(np.arange(3100) / 2000.0 + rng.normal(0, 0.05 / 2000, 3100))
    keep = np.r_[0:1500, 1600:3100]
    path = tmp_path / "jitter_gap.csv"
    np.savetxt(path, np.c_[t[keep], rng.standard_normal((3000, 2))], delimiter=",",
               header="time,Z2,Z3", comments="", fmt="%.17g")
    assert abs(np.median(np.diff(t[keep])) * 2000 - 1) > 1e-3  # the premise
    log = load(path, rate=2000.0, units="rad")
    np.testing.assert_array_equal(log.timestamps, t[keep])
    assert log.sampling().n_gaps == 1
