"""Round 14 PART b's file fixes at the edges their tests left (review13, planted bugs R13-B2..B5).

References, all outside the code under test: pandas' own CSV reader (which columns hold
values; the numbers a spreadsheet's locale format stands for, read with the advice the
refusal gives), the Zstandard frame magic number 0xFD2FB528, little-endian (RFC 8878,
section 3.1.1), and h5py's virtual datasets with sources named relative to the file
(libhdf5 looks for them beside the file, whatever the working folder).
"""

from __future__ import annotations

import h5py
import numpy as np
import pandas as pd
import pytest

from modalinfo.io import load
from modalinfo.io.files import LogFormatError


def _coeffs(frames: int = 200, modes: int = 5) -> np.ndarray:
    return np.random.default_rng(14).standard_normal((frames, modes)) * 0.05


# ---------------------------------- R13-B2: a trailing unnamed column that holds a value
def test_a_trailing_unnamed_column_with_a_value_is_not_dropped(tmp_path):
    c = _coeffs(50, 2)
    rows = [f"{float(a)!r},{float(b)!r}," for a, b in c]
    rows[7] += "7.5"  # one value in the unnamed column: data, not spreadsheet padding
    path = tmp_path / "padded.csv"
    path.write_text("Z2,Z3,\n" + "\n".join(rows) + "\n")
    assert pd.read_csv(path).iloc[:, 2].notna().sum() == 1  # pandas sees the value
    with pytest.raises((LogFormatError, ValueError, TypeError), match="non-empty"):
        load(path, rate=1000.0)  # which mode is it? refused, not silently dropped


# ------------------------------------------------ R13-B3: a zstd-compressed log (RFC 8878)
def test_zstd_compressed_log_says_which_compressor(tmp_path):
    path = tmp_path / "log.zst"
    magic = (0xFD2FB528).to_bytes(4, "little")  # RFC 8878 3.1.1: the frame's magic number
    path.write_bytes(magic + bytes(range(64)))
    with pytest.raises(LogFormatError) as info:
        load(path, rate=1000.0)
    text = str(info.value)
    assert "zstd-compressed" in text and "unzstd" in text and "UTF-8" not in text


# ------------------------- R13-B4: virtual-dataset sources beside the file, run elsewhere
def test_virtual_sources_beside_the_file_are_found_from_another_folder(tmp_path,
                                                                       monkeypatch):
    c = _coeffs()
    data = tmp_path / "data"
    data.mkdir()
    with h5py.File(data / "src.h5", "w") as f:
        f["a"], f["b"] = c[:100], c[100:]
    layout = h5py.VirtualLayout(shape=c.shape, dtype="f8")
    layout[:100] = h5py.VirtualSource("src.h5", "a", shape=(100, 5))
    layout[100:] = h5py.VirtualSource("src.h5", "b", shape=(100, 5))
    with h5py.File(data / "vds.h5", "w") as f:
        f.create_virtual_dataset("coefficients", layout, fillvalue=np.nan)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    with h5py.File(data / "vds.h5") as f:  # libhdf5 itself finds them beside the file
        np.testing.assert_array_equal(f["coefficients"][()], c)
    np.testing.assert_array_equal(load(data / "vds.h5", rate=1000.0).coeffs, c)


# ---------------- R13-B5 (and the delimiter): the locale advice, followed, reads the file
_THOUSANDS_ROWS = [(1000.5 + k, k + 0.25) for k in range(50)]


@pytest.mark.parametrize("case", ["comma-delimited, point thousands",
                                  "semicolon-delimited, point thousands",
                                  "semicolon-delimited, comma thousands",
                                  "comma-delimited, decimal comma"])
def test_locale_advice_followed_reads_the_numbers(tmp_path, case):
    path = tmp_path / "locale.csv"
    if case == "comma-delimited, point thousands":
        body = [f'"1.{int(a) - 1000:03d},5","{int(b)},25"' for a, b in _THOUSANDS_ROWS]
        path.write_text("Z2,Z3\n" + "\n".join(body) + "\n")
        expected = np.array(_THOUSANDS_ROWS)
    elif case == "semicolon-delimited, point thousands":
        body = [f"1.{int(a) - 1000:03d},5;{int(b)},25" for a, b in _THOUSANDS_ROWS]
        path.write_text("Z2;Z3\n" + "\n".join(body) + "\n")
        expected = np.array(_THOUSANDS_ROWS)
    elif case == "semicolon-delimited, comma thousands":
        body = [f"1,{int(a) - 1000:03d}.5;{b}" for a, b in _THOUSANDS_ROWS]
        path.write_text("Z2;Z3\n" + "\n".join(body) + "\n")
        expected = np.array(_THOUSANDS_ROWS)
    else:
        expected = _coeffs(50, 2)
        pd.DataFrame(expected, columns=["Z2", "Z3"]).to_csv(path, index=False, decimal=",")
    with pytest.raises(LogFormatError) as info:
        load(path, rate=1000.0)
    text = str(info.value)
    assert "corrupt" not in text
    advice = text.split("pandas: ")[1][:-1]  # pd.read_csv(path, ...).to_csv(new, ...)
    fixed = tmp_path / "fixed.csv"
    eval(advice, {"pd": pd, "path": path, "new": fixed})  # noqa: S307 - our own message
    np.testing.assert_allclose(load(fixed, rate=1000.0).coeffs, expected, rtol=1e-15)
