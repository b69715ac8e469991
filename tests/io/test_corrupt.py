"""Damaged and malformed files fail loudly, with the documented exceptions only.

Reference: the documented contract of ``modalinfo.io`` -- a truncated or altered
file either raises ``LogFormatError`` (a ``ValueError``) naming the file, or, when
the damage hit bytes that carry no information (padding, free space, a comment),
loads a log identical to the original; it never returns different data. Malformed
CSV text and NPZ content (hypothesis fuzzing) raise only ``ValueError`` /
``TypeError`` / ``OSError``.
"""

from __future__ import annotations

import io
import tempfile
import zipfile
import zlib
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from modalinfo.io import LogFormatError, load, save
from modalinfo.telemetry import ModalLog

EXTENSIONS = (".npz", ".csv", ".fits", ".h5")


@pytest.fixture(scope="module")
def originals(tmp_path_factory):
    root = tmp_path_factory.mktemp("orig")
    rng = np.random.default_rng(0)
    out = {}
    for dtype in (np.float32, np.float64):
        log = ModalLog(
            rng.standard_normal((40, 5)).astype(dtype),
            timestamps=np.cumsum(rng.uniform(0.5, 1.5, 40)) * 1e-3,
            units="nm",
            wavelength=5e-7,
            metadata={"telescope": "LOST", "loop": "closed", "values": [1, 2.5, "x"]},
        )
        for ext in EXTENSIONS:
            path = save(log, root / f"{np.dtype(dtype).name}{ext}")
            out[(np.dtype(dtype).name, ext)] = (log, path.read_bytes())
    return out


def _outcome(log, data: bytes, ext: str, assert_same_log):
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f"bad{ext}"
        path.write_bytes(data)
        try:
            back = load(path)
        except LogFormatError as exc:
            assert str(path) in str(exc)
            return "error"
        assert_same_log(log, back)  # harmless damage only
        return "same"


@pytest.mark.parametrize("dtype", ["float32", "float64"])
@pytest.mark.parametrize("ext", EXTENSIONS)
def test_truncation_always_detected(originals, ext, dtype, assert_same_log):
    log, raw = originals[(dtype, ext)]
    # (a CSV cut just before its final newline loses nothing: the last cut keeps 2 bytes off)
    cuts = sorted({1, 8, 100, len(raw) // 3, len(raw) // 2, len(raw) - 200, len(raw) - 2})
    for cut in cuts:
        assert _outcome(log, raw[:cut], ext, assert_same_log) == "error", cut


@pytest.mark.parametrize("dtype", ["float32", "float64"])
@pytest.mark.parametrize("ext", EXTENSIONS)
def test_bit_flips_never_give_wrong_data(originals, ext, dtype, assert_same_log):
    log, raw = originals[(dtype, ext)]
    # a seed stable across processes (``hash`` of a str is salted per process)
    rng = np.random.default_rng(zlib.crc32(f"{ext}-{dtype}".encode()))
    outcomes = []
    for _ in range(60):
        data = bytearray(raw)
        i = int(rng.integers(0, len(raw)))
        data[i] ^= 1 << int(rng.integers(0, 8))
        outcomes.append(_outcome(log, bytes(data), ext, assert_same_log))
    # How many flips land in padding or free space depends on the writing library's
    # layout (astropy, h5py), so no count is asserted beyond "the damage was seen";
    # flips inside the coefficients are always caught (next test).
    assert "error" in outcomes


@pytest.mark.parametrize("ext", EXTENSIONS)
def test_flip_in_coefficients_detected(originals, ext, assert_same_log):
    """A flipped bit inside a stored coefficient is always caught (checksums)."""
    log, raw = originals[("float64", ext)]
    value = np.float64(log.coeffs[17, 3])
    if ext == ".csv":
        needle = repr(float(value)).encode()
    elif ext == ".fits":
        needle = np.array([value], dtype=">f8").tobytes()
    else:
        needle = np.array([value], dtype="<f8").tobytes()
    i = raw.find(needle)
    assert i > 0
    data = bytearray(raw)
    data[i + len(needle) - 2] ^= 0x01  # a low-order digit / mantissa bit
    assert _outcome(log, bytes(data), ext, assert_same_log) == "error"


def test_truncated_npy_memmap_detected(tmp_path):
    x = np.random.default_rng(1).standard_normal((1000, 3))
    np.save(tmp_path / "x.npy", x)
    raw = (tmp_path / "x.npy").read_bytes()
    (tmp_path / "t.npy").write_bytes(raw[:-8])
    for mmap in (True, False):
        with pytest.raises(LogFormatError, match=r"corrupt NPY file .*t\.npy.*truncated"):
            load(tmp_path / "t.npy", mmap=mmap, rate=1.0)


def test_truncated_hdf5_memmap_detected(tmp_path):
    log = ModalLog(np.random.default_rng(2).standard_normal((5000, 3)), rate=1.0)
    raw = save(log, tmp_path / "x.h5").read_bytes()
    (tmp_path / "t.h5").write_bytes(raw[: len(raw) - 1000])
    with pytest.raises(LogFormatError, match=r"corrupt HDF5 file .*t\.h5"):
        load(tmp_path / "t.h5", mmap=True)


def test_empty_and_garbage_files(tmp_path):
    (tmp_path / "empty.npz").write_bytes(b"")
    with pytest.raises(LogFormatError, match=r"empty"):
        load(tmp_path / "empty.npz")
    (tmp_path / "garbage.xyz").write_bytes(bytes(range(256)) * 4)
    with pytest.raises(LogFormatError, match=r"neither UTF-8 text \(CSV\) nor"):
        load(tmp_path / "garbage.xyz")
    # named like a raw dump, the same bytes are one (fix56-c)
    (tmp_path / "garbage.bin").write_bytes(bytes(range(256)) * 4)
    with pytest.raises(LogFormatError, match=r"headerless binary dump \(1,024 bytes"):
        load(tmp_path / "garbage.bin")
    (tmp_path / "garbage.fits").write_bytes(b"\x00\x01" * 1000)
    with pytest.raises(LogFormatError, match=r"corrupt FITS file"):
        load(tmp_path / "garbage.fits")


def test_pickled_npz_member_refused(tmp_path):
    buf = io.BytesIO()
    np.save(buf, np.array([{"a": 1}], dtype=object), allow_pickle=True)
    with zipfile.ZipFile(tmp_path / "p.npz", "w") as zf:
        zf.writestr("coeffs.npy", buf.getvalue())
    with pytest.raises(LogFormatError, match=r"Python objects \(pickles are never loaded\)"):
        load(tmp_path / "p.npz")


# ----------------------------------------------------------------- fuzzing
_ALLOWED = (ValueError, TypeError, OSError)

csv_text = st.one_of(
    st.text(max_size=300),
    st.lists(
        st.lists(
            st.one_of(
                st.floats().map(repr),
                st.sampled_from(["", "nan", "inf", "x", "Z4", "time", "#", '"', "1e999", "--"]),
                st.integers().map(str),
            ),
            max_size=5,
        ),
        max_size=6,
    ).map(lambda rows: "\n".join(",".join(r) for r in rows)),
    st.builds(
        lambda body, junk: '# modalinfo: {"modalinfo":1,"shape":[2,1],' + junk + "\n" + body,
        st.text(max_size=40),
        st.text(max_size=60),
    ),
)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(text=csv_text, hint=st.sampled_from([{}, {"rate": 10.0}, {"nonfinite": "drop"}]))
def test_fuzz_csv_only_documented_errors(text, hint):
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "f.csv"
        path.write_text(text, encoding="utf-8", errors="surrogatepass")
        try:
            log = load(path, **hint)
        except _ALLOWED:
            return
        assert isinstance(log, ModalLog)
        assert np.all(np.isfinite(log.coeffs))


def _npz_bytes(members: dict) -> bytes:
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as zf:
        for name, payload in members.items():
            zf.writestr(name, payload)
    return buf.getvalue()


def _npy(arr) -> bytes:
    b = io.BytesIO()
    np.save(b, arr)
    return b.getvalue()


npz_member = st.one_of(
    st.binary(max_size=200),
    st.builds(lambda a: _npy(np.asarray(a)), st.lists(st.floats(), max_size=6)),
    st.builds(
        lambda a, k: _npy(np.asarray(a).reshape(-1, 1))[: max(0, len(_npy(np.asarray(a))) - k)],
        st.lists(st.floats(), min_size=1, max_size=6),
        st.integers(0, 30),
    ),
    st.just(_npy(np.array('{"modalinfo":1}'))),
    st.just(_npy(np.array("not json"))),
    st.just(_npy(np.zeros((3, 2)))),
    st.just(_npy(np.zeros((0, 2)))),
)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    members=st.dictionaries(
        st.sampled_from(["coefficients.npy", "header.npy", "timestamps.npy", "x.npy", "y"]),
        npz_member,
        max_size=3,
    ),
    cut=st.integers(0, 50),
)
def test_fuzz_npz_only_documented_errors(members, cut):
    data = _npz_bytes(members)
    if cut:
        data = data[: max(0, len(data) - cut)]
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "f.npz"
        path.write_bytes(data)
        try:
            log = load(path, rate=5.0)
        except _ALLOWED:
            return
        assert isinstance(log, ModalLog)


@pytest.mark.parametrize("mmap", [False, True])
def test_hdf5_byte_order_flag_damage_detected(tmp_path, mmap):
    """Same bytes, other byte order: every value changes, so it must not load."""
    import h5py

    log = ModalLog(np.random.default_rng(3).standard_normal((30, 3)), rate=10.0)
    path = save(log, tmp_path / "x.h5")
    with h5py.File(path, "r+") as f:
        del f["coefficients"]
        f.create_dataset("coefficients", data=np.asarray(log.coeffs).view(">f8"))
    with pytest.raises(LogFormatError, match=r"corrupt HDF5 file .*>f8 disagree"):
        load(path, mmap=mmap)


@pytest.mark.parametrize("mmap", [False, True])
def test_npz_byte_order_flag_damage_detected(tmp_path, mmap):
    """An NPZ whose valid (CRC-correct) member has the other byte order must not load."""
    log = ModalLog(np.random.default_rng(5).standard_normal((30, 3)), rate=10.0)
    path = save(log, tmp_path / "x.npz")
    with np.load(path) as z:
        header = z["header"]
    np.savez(tmp_path / "y.npz", coefficients=np.asarray(log.coeffs).view(">f8"), header=header)
    with pytest.raises(LogFormatError, match=r"corrupt NPZ file .*>f8 disagree with the header"):
        load(tmp_path / "y.npz", mmap=mmap)


def test_hdf5_checksum_covers_values(tmp_path):
    import h5py

    log = ModalLog(np.random.default_rng(4).standard_normal((30, 3)), rate=10.0)
    path = save(log, tmp_path / "y.h5")
    with h5py.File(path, "r+") as f:
        f["coefficients"][5, 1] = 0.0
    with pytest.raises(LogFormatError, match=r"coefficients do not match their SHA-256"):
        load(path)
    assert load(path, verify=False).coeffs[5, 1] == 0.0


def test_csv_blank_lines_after_the_end_marker_are_no_damage(tmp_path, assert_same_log):
    # an editor or a transfer appending blank lines leaves every value in place: the log
    # is identical; a line of data appended after the marker is refused by name
    log = ModalLog(np.random.default_rng(5).standard_normal((20, 3)), rate=100.0)
    path = save(log, tmp_path / "a.csv")
    text = path.read_text()
    (tmp_path / "blank.csv").write_text(text + "\n  \n\n")
    assert_same_log(load(tmp_path / "blank.csv"), log)
    (tmp_path / "more.csv").write_text(text + "1,2,3\n")
    with pytest.raises(LogFormatError, match=r"more\.csv.*1 line\(s\) after the end marker"):
        load(tmp_path / "more.csv")
