"""Adversarial round 14, PART b (files written by other tools, byte-reproducibility): the fixes.

References, all outside the code under test: h5py's own virtual datasets, soft and
external links (``h5py.VirtualLayout``, ``h5py.SoftLink``, ``h5py.ExternalLink``);
astropy's checksum verification (``fits.open(..., checksum=True)`` with warnings as
errors) and its FITS output of the same HDUs; the bytes of a file written twice (a
byte-for-byte ``==``); pandas' CSV writer in a spreadsheet's locale (``sep=';'``,
``decimal=','``) and with trailing empty columns; the magic numbers of bzip2 / xz
(Python's :mod:`bz2` and :mod:`lzma`); the file-name limit of the folder
(``os.pathconf(..., "PC_NAME_MAX")``). Rows of docs/ADVERSARIAL.md "Round 14 PART b".
Each test fails on the code before its fix.
"""

from __future__ import annotations

import bz2
import lzma
import os
import time
import warnings

import h5py
import numpy as np
import pandas as pd
import pytest
from astropy.io import fits

from modalinfo.common.files import atomic_write
from modalinfo.io import load, save
from modalinfo.io.files import LogFormatError
from modalinfo.telemetry import ModalLog


def _coeffs(frames: int = 200, modes: int = 5) -> np.ndarray:
    return np.random.default_rng(14).standard_normal((frames, modes)) * 0.05


def _log() -> ModalLog:
    return ModalLog(_coeffs(), rate=1000.0, modes=list(range(2, 7)), units="rad",
                    wavelength=5e-7)


# ------------------------------------------------ H04: a virtual dataset, source gone
def test_virtual_dataset_with_a_missing_source_is_refused(tmp_path):
    c = _coeffs()
    layout = h5py.VirtualLayout(shape=c.shape, dtype="f8")
    layout[:100] = h5py.VirtualSource(str(tmp_path / "gone.h5"), "a", shape=(100, 5))
    path = tmp_path / "vds.h5"
    with h5py.File(path, "w") as f:
        f.create_virtual_dataset("coefficients", layout, fillvalue=0.0)
    with h5py.File(path) as f:  # what libhdf5 gives: the fill value, no error
        assert not np.any(f["coefficients"][()])
    with pytest.raises(LogFormatError, match="virtual .*'.*gone.h5' are missing"):
        load(path, rate=1000.0)


def test_virtual_dataset_with_its_sources_reads_them(tmp_path):
    c = _coeffs()
    with h5py.File(tmp_path / "src.h5", "w") as f:
        f["a"], f["b"] = c[:100], c[100:]
    layout = h5py.VirtualLayout(shape=c.shape, dtype="f8")
    layout[:100] = h5py.VirtualSource("src.h5", "a", shape=(100, 5))
    layout[100:] = h5py.VirtualSource("src.h5", "b", shape=(100, 5))
    with h5py.File(tmp_path / "vds.h5", "w") as f:
        f.create_virtual_dataset("coefficients", layout, fillvalue=np.nan)
    cwd = os.getcwd()
    os.chdir(tmp_path)  # libhdf5 finds a relative source from the working folder
    try:
        np.testing.assert_array_equal(load(tmp_path / "vds.h5", rate=1000.0).coeffs, c)
    finally:
        os.chdir(cwd)


# ------------------------------------- H01-H03: links only, no --dataset: name the links
@pytest.mark.parametrize("kind", ["external", "soft-dangling"])
def test_file_of_links_only_names_them_instead_of_pick_one_of_none(tmp_path, kind):
    path = tmp_path / "links.h5"
    with h5py.File(tmp_path / "target.h5", "w") as f:
        f["coefficients"] = _coeffs()
    with h5py.File(path, "w") as f:
        f["coefficients"] = (h5py.ExternalLink("target.h5", "/coefficients")
                             if kind == "external" else h5py.SoftLink("/nowhere"))
    with pytest.raises(LogFormatError) as info:
        load(path, rate=1000.0)
    text = str(info.value)
    assert "pick one" not in text and "links: 'coefficients'" in text
    assert ("target.h5" if kind == "external" else "'/nowhere'") in text


# --------------------------------------- R03/R11: FITS and AOT bytes hold no clock time
@pytest.mark.parametrize("fmt", ["fits", "aot"])
def test_fits_and_aot_writes_are_byte_identical_and_verify(tmp_path, fmt, monkeypatch):
    log = _log()
    first = save(log, tmp_path / "a.fits", fmt=fmt)
    time.sleep(1.1)  # astropy's default comment holds the time to the second
    monkeypatch.setenv("TZ", "Asia/Kolkata")
    time.tzset()
    try:
        second = save(log, tmp_path / "b.fits", fmt=fmt)
    finally:
        monkeypatch.delenv("TZ")
        time.tzset()
    assert first.read_bytes() == second.read_bytes()
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # astropy warns on a checksum that fails
        with fits.open(first, checksum=True) as hdul:
            assert all("CHECKSUM" in hdu.header and "DATASUM" in hdu.header for hdu in hdul)
            for hdu in hdul:
                _ = hdu.data
    np.testing.assert_array_equal(load(first).coeffs, log.coeffs)


# ----------------------------------------- F18/F27/F30: a spreadsheet's number format
def test_decimal_comma_csv_is_named_and_the_advice_works(tmp_path):
    c = _coeffs()
    frame = pd.DataFrame(c, columns=[f"Z{j}" for j in range(2, 7)])
    german = tmp_path / "excel.csv"
    frame.to_csv(german, index=False, sep=";", decimal=",", encoding="utf-8-sig")
    with pytest.raises(LogFormatError) as info:
        load(german, rate=1000.0)
    text = str(info.value)
    assert "corrupt" not in text and "decimal comma" in text
    advice = text.split("pandas: ")[1][:-1]  # pd.read_csv(path, ...).to_csv(new, ...)
    fixed = tmp_path / "fixed.csv"
    eval(advice, {"pd": pd, "path": german, "new": fixed})  # noqa: S307 - our own message
    np.testing.assert_allclose(load(fixed, rate=1000.0).coeffs, c, rtol=1e-15)


def test_thousands_separator_csv_is_named(tmp_path):
    path = tmp_path / "th.csv"
    path.write_text("Z2,Z3\n" + "\n".join(f'"1,{k:03d}.5",{k}.25' for k in range(50)) + "\n")
    with pytest.raises(LogFormatError, match="thousands separators.*thousands=','"):
        load(path, rate=1000.0)


# ---------------------------------------------- F19/F20: trailing empty columns (Excel)
@pytest.mark.parametrize("extra", [",", ",,"])
def test_trailing_empty_columns_are_not_modes(tmp_path, extra):
    c = _coeffs()
    plain = tmp_path / "plain.csv"
    pd.DataFrame(c, columns=[f"Z{j}" for j in range(2, 7)]).to_csv(plain, index=False)
    padded = tmp_path / "padded.csv"
    padded.write_text("".join(line + extra + "\n" for line in plain.read_text().splitlines()))
    log = load(padded, rate=1000.0)
    np.testing.assert_array_equal(log.coeffs, load(plain, rate=1000.0).coeffs)
    assert log.modes == load(plain, rate=1000.0).modes


def test_an_empty_column_in_the_middle_is_still_refused(tmp_path):
    path = tmp_path / "mid.csv"
    path.write_text("Z2,,Z4\n" + "\n".join(f"{k}.5,,{k}.25" for k in range(50)) + "\n")
    with pytest.raises((LogFormatError, ValueError, TypeError), match="non-empty"):
        load(path, rate=1000.0)  # a missing name inside the header: which mode is it?


# ------------------------------------------------ F28/F29: bzip2 / xz compressed logs
@pytest.mark.parametrize(("module", "word", "tool"), [(bz2, "bzip2", "bunzip2 -k"),
                                                      (lzma, "xz", "unxz -k")])
def test_compressed_log_says_which_compressor(tmp_path, module, word, tool):
    plain = save(_log(), tmp_path / "log.npz")
    packed = tmp_path / "log.npz.z"
    packed.write_bytes(module.compress(plain.read_bytes()))
    with pytest.raises(LogFormatError) as info:
        load(packed)
    text = str(info.value)
    assert f"{word}-compressed" in text and tool in text and "UTF-8" not in text


# --------------------------------------------------- S01: a 255-byte output file name
def test_atomic_write_takes_a_name_at_the_folders_limit(tmp_path):
    limit = os.pathconf(tmp_path, "PC_NAME_MAX")
    for name in ("a" * (limit - 4) + ".npz", "é" * ((limit - 4) // 2) + ".npz"):
        target = tmp_path / name
        assert len(os.fsencode(target.name)) <= limit
        atomic_write(target, lambda fh: fh.write(b"x"), overwrite=False)
        assert target.read_bytes() == b"x"
        atomic_write(target, lambda fh: fh.write(b"y"), overwrite=True)
        assert target.read_bytes() == b"y"
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        ["a" * (limit - 4) + ".npz", "é" * ((limit - 4) // 2) + ".npz"])
