"""A file whose content is another format than its name (or ``fmt``) says is named so.

Reference: the formats' own signatures, from their specifications -- a FITS file starts
with the card ``SIMPLE  =`` (FITS Standard 4.0, section 4.4.1.1), an HDF5 file with
``\\x89HDF\\r\\n\\x1a\\n`` (HDF5 File Format Specification, "Format Signature"), an NPZ with
the ZIP local-file header ``PK\\x03\\x04`` (APPNOTE.TXT 4.3.7) -- and the round trip: the
remedy the hint names, followed literally, loads a log bitwise equal to the one saved.
Adversarial round 18 PART b, row M02 (a CSV named ``.fits`` was "corrupt FITS" with no
word that it is a CSV).
"""

from __future__ import annotations

import shutil
import subprocess
import sys

import numpy as np
import pytest

from modalinfo.io import LogFormatError, load, save
from modalinfo.telemetry import ModalLog


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    root = tmp_path_factory.mktemp("hint")
    log = ModalLog(np.random.default_rng(1).standard_normal((30, 4)), rate=1000.0)
    return log, {fmt: save(log, root / f"log.{ext}")
                 for fmt, ext in (("csv", "csv"), ("fits", "fits"), ("hdf5", "h5"),
                                  ("npz", "npz"))}


@pytest.mark.parametrize("ext", [".fits", ".h5", ".npz"])
def test_csv_under_a_binary_extension_is_named_csv(saved, tmp_path, ext, assert_same_log):
    log, paths = saved
    wrong = tmp_path / f"log{ext}"
    shutil.copyfile(paths["csv"], wrong)
    with pytest.raises(LogFormatError) as err:
        load(wrong)
    message = str(err.value)
    assert str(wrong) in message
    assert "it looks like a CSV file: try --fmt csv" in message
    assert_same_log(log, load(wrong, fmt="csv"))  # the remedy, followed


@pytest.mark.parametrize(("content", "forced"), [
    ("hdf5", "fits"), ("fits", "npz"), ("npz", "csv"), ("csv", "hdf5"), ("fits", "hdf5"),
])
def test_forced_format_names_the_content(saved, content, forced, assert_same_log):
    log, paths = saved
    with pytest.raises(LogFormatError) as err:
        load(paths[content], fmt=forced)
    assert f"file: try --fmt {content} (Python: fmt='{content}')" in str(err.value)
    assert_same_log(log, load(paths[content], fmt=content))


def test_damaged_fits_header_gets_no_csv_hint(saved, tmp_path):
    # a FITS header is ASCII too (80-character cards, no line breaks): it is damaged
    # FITS, not a CSV, and must not be sent to the CSV reader
    data = bytearray(paths_bytes := saved[1]["fits"].read_bytes())
    assert paths_bytes.startswith(b"SIMPLE  =")
    data[:6] = b"SIMPLX"
    bad = tmp_path / "bad.fits"
    bad.write_bytes(bytes(data))
    with pytest.raises(LogFormatError) as err:
        load(bad)
    assert "try --fmt" not in str(err.value)


def test_cli_one_line_exit_2(saved, tmp_path):
    wrong = tmp_path / "night.fits"
    shutil.copyfile(saved[1]["csv"], wrong)
    run = subprocess.run([sys.executable, "-m", "modalinfo", "info", str(wrong)],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 2
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and "try --fmt csv" in lines[0], run.stderr
