r"""More readers' refusals quote the file in its shown form (review 31, round 31 mutation).

``tests/io/test_shown_paths_fix48a.py`` reaches each reader through one corrupt content;
a raw ``'{path}'`` planted back in another refusal of the same reader (a modalinfo CSV
cut after its header line, a FITS primary HDU without data, an HDF5 log without its
coefficients, a missing NPZ array, an empty file, an unknown extension to ``save``, an
AOT file without a control loop) passed every test. References, outside the package:
the file's bytes (``os.fsencode``) and ``codecs.escape_decode`` of the quoted name in the
message (``ls -b``'s escapes back to bytes); a shown message is printable UTF-8.
"""

from __future__ import annotations

import codecs
import os
import re
import warnings

import numpy as np
import pytest

SLASH = b"a\\xe9"  # a literal backslash, then x, e, 9
BYTE = b"b\xe9"  # the byte 0xE9: not UTF-8
STEMS = pytest.mark.parametrize("stem", [SLASH, BYTE], ids=["backslash", "byte"])


def _names_file(message: str, path: bytes) -> bool:
    """Whether a quoted name in ``message`` gives the bytes ``path`` back (ls -b escapes)."""
    message.encode("utf-8")  # printable: no lone surrogate (a raw undecodable byte)
    quoted = re.findall(r"'([^']*)'", message)
    return any(codecs.escape_decode(q.encode("utf-8"))[0] == path for q in quoted)


def _log():
    from modalinfo.telemetry import ModalLog

    return ModalLog(np.random.default_rng(0).normal(size=(20, 3)), rate=100.0, modes=[2, 3, 4])


def _path(tmp_path, stem: bytes, suffix: str) -> bytes:
    return os.path.join(os.fsencode(tmp_path), stem + suffix.encode())


def _refusal(path: bytes, **hints) -> str:
    from modalinfo.io import load

    with warnings.catch_warnings(), pytest.raises(Exception) as caught:  # noqa: B017
        warnings.simplefilter("ignore")
        load(os.fsdecode(path), **hints)
    return str(caught.value)


@STEMS
def test_a_modalinfo_csv_cut_after_its_header_line(tmp_path, stem):
    from modalinfo.io import save

    good = save(_log(), tmp_path / "good.csv")
    path = _path(tmp_path, stem, ".csv")
    with open(path, "wb") as fh:
        fh.write(good.read_bytes().splitlines(keepends=True)[0])  # the '# modalinfo:' line
    message = _refusal(path)
    assert "header row missing" in message and _names_file(message, path), ascii(message)


@STEMS
def test_a_modalinfo_fits_without_primary_data(tmp_path, stem):
    fits = pytest.importorskip("astropy.io.fits")
    from modalinfo.io import save

    good = save(_log(), tmp_path / "good.fits")
    with fits.open(good) as hdul:
        header = hdul[0].header.copy()
    for key in ("CHECKSUM", "DATASUM"):
        header.remove(key, ignore_missing=True)
    path = _path(tmp_path, stem, ".fits")
    fits.HDUList([fits.PrimaryHDU(header=header)]).writeto(os.fsdecode(path))
    message = _refusal(path)
    assert "primary HDU has no data" in message and _names_file(message, path), ascii(message)


@STEMS
def test_a_modalinfo_hdf5_without_coefficients(tmp_path, stem):
    h5py = pytest.importorskip("h5py")
    from modalinfo.io import save

    path = _path(tmp_path, stem, ".h5")
    save(_log(), tmp_path / "good.h5")
    os.rename(tmp_path / "good.h5", path)
    with h5py.File(path, "a") as f:
        del f["coefficients"]
    message = _refusal(path)
    assert "no coefficients dataset" in message and _names_file(message, path), ascii(message)


@STEMS
def test_a_missing_npz_array(tmp_path, stem):
    path = _path(tmp_path, stem, ".npz")
    with open(path, "wb") as fh:
        np.savez(fh, a=np.zeros((10, 3)))
    message = _refusal(path, dataset="nope", rate=10.0)
    assert "no array 'nope'" in message and _names_file(message, path), ascii(message)


@STEMS
def test_an_empty_file(tmp_path, stem):
    path = _path(tmp_path, stem, ".csv")
    open(path, "wb").close()
    message = _refusal(path)
    assert "is empty" in message and _names_file(message, path), ascii(message)


@STEMS
def test_save_to_an_unknown_extension(tmp_path, stem):
    from modalinfo.io import save

    path = _path(tmp_path, stem, ".xyz")
    with pytest.raises(ValueError) as caught:
        save(_log(), os.fsdecode(path))
    message = str(caught.value)
    assert "cannot tell the format" in message and _names_file(message, path), ascii(message)


@STEMS
def test_an_aot_file_without_a_control_loop(tmp_path, stem):
    aotpy = pytest.importorskip("aotpy")

    path = _path(tmp_path, stem, ".fits")
    system = aotpy.AOSystem(ao_mode="SCAO", main_telescope=aotpy.MainTelescope(uid="TEL"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        system.write_to_file(os.fsdecode(path))
    message = _refusal(path)
    assert "has no control loop" in message and _names_file(message, path), ascii(message)


def _every_quote_names_file(message: str, path: bytes) -> bool:
    """Whether every quoted name in ``message`` gives the bytes ``path`` back."""
    message.encode("utf-8")
    quoted = re.findall(r"'([^']*)'", message)
    return bool(quoted) and all(codecs.escape_decode(q.encode("utf-8"))[0] == path for q in quoted)


@STEMS
def test_a_readers_oserror_names_the_file_shown_twice(tmp_path, stem):
    """An ``OSError`` in Python's format (a read error, EIO) inside a reader: both names shown."""
    import errno
    from pathlib import Path

    from modalinfo.io import LogFormatError
    from modalinfo.io._common import reading

    path = _path(tmp_path, stem, ".csv")
    with pytest.raises(LogFormatError) as caught, reading("CSV", Path(os.fsdecode(path))):
        raise OSError(errno.EIO, "Input/output error", os.fsdecode(path))
    message = str(caught.value)
    assert message.count("'") == 4 and _every_quote_names_file(message, path), ascii(message)


@STEMS
def test_a_member_crc_mismatch_found_at_the_end(tmp_path, stem):
    """A memory-mapped NPZ whose member fails its CRC-32, checked from the file (no pass)."""
    from modalinfo.io import LogFormatError, integrity_check, load
    from tests.io.test_integrity import X, _flip

    plain = tmp_path / "f.npz"
    np.savez(plain, a=X)
    _flip(plain, "foreign")
    path = _path(tmp_path, stem, ".npz")
    os.rename(plain, path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        log = load(os.fsdecode(path), mmap=True, rate=100.0)
    check = integrity_check(os.fsdecode(path), log, mmap=True)
    with pytest.raises(LogFormatError) as caught:
        check.finish()
    message = str(caught.value)
    assert "CRC" in message and _names_file(message, path), ascii(message)


@STEMS
def test_a_column_that_is_not_a_mode_beside_mode_columns(tmp_path, stem):
    path = _path(tmp_path, stem, ".csv")
    with open(path, "wb") as fh:
        fh.write(b"Z2,Z3,Z4,flag\n" + b"".join(b"%d,1,2,0\n" % i for i in range(20)))
    message = _refusal(path, rate=100.0)
    assert "are not modes" in message and _names_file(message, path), ascii(message)


@STEMS
def test_a_closedloop_result_read_as_a_log(tmp_path, stem):
    h5py = pytest.importorskip("h5py")

    path = _path(tmp_path, stem, ".h5")
    with h5py.File(path, "w") as f:
        f.attrs["format"] = "closedloop-result"  # what marks a result (closedloop/result.py)
    message = _refusal(path)
    assert "closedloop result, not a log" in message and _names_file(message, path), \
        ascii(message)
