"""fix54-d (issue 27, round 53 PART b "Left"): a FITS / AOT / .fz file cut short is named so.

A truncated FITS or AOT file was reported in astropy's / aotpy's words ("Header missing
END card", numpy's "buffer is too small", "Missing mandatory table 'AOT_DETECTORS'").
Each reader now says which file, that it is truncated, in which HDU, and the bytes found
against the bytes the header declares.

Reference from outside the code: astropy's own account of the intact file
(``HDUList.fileinfo``: where each HDU's header and data start, and the data's span) and
the FITS Standard 4.0's size rule (``|BITPIX|/8 x GCOUNT x (PCOUNT + NAXIS1 x ... x
NAXISn)``, eq. 2), computed here from the intact file's headers as astropy parses them
(the compressed image's tile table read with ``disable_image_compression``); the cut is
``os.truncate`` at three points: inside the header of the HDU holding the data, in the
middle of its data, and one 2880-byte block short of the end.
"""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from astropy.io import fits

from modalinfo.io import load, save
from modalinfo.io.files import LogFormatError
from modalinfo.telemetry import ModalLog

ROOT = Path(__file__).resolve().parents[2]


def _log() -> ModalLog:
    x = np.random.default_rng(54).standard_normal((3000, 12))
    return ModalLog(x, rate=1000.0, modes=list(range(2, 14)))


def _write(kind: str, folder: Path) -> Path:
    """The intact file of ``kind``: our FITS image, a FITS table, our AOT, an fpack-style .fz."""
    log = _log()
    if kind == "image":
        return save(log, folder / "log.fits")
    if kind == "aot":
        pytest.importorskip("aotpy")
        return save(log, folder / "log_aot.fits", fmt="aot")
    path = folder / ("table.fits" if kind == "table" else "log.fits.fz")
    if kind == "table":  # a foreign binary table, one column per mode
        cols = [fits.Column(name=f"Z{j}", format="D", array=log.coeffs[:, k])
                for k, j in enumerate(log.modes)]
        hdu = fits.BinTableHDU.from_columns(cols)
    else:  # lossless tile compression (GZIP, no quantization)
        hdu = fits.CompImageHDU(log.coeffs, compression_type="GZIP_2", quantize_level=0)
    fits.HDUList([fits.PrimaryHDU(), hdu]).writeto(path)
    return path


def _layout(path: Path) -> list[tuple[int, int, int]]:
    """``(header start, data start, declared data bytes)`` of each HDU, by astropy."""
    out = []
    with fits.open(path, disable_image_compression=True) as hdul:
        for k, hdu in enumerate(hdul):
            info = hdul.fileinfo(k)
            h = hdu.header
            axes = [h[f"NAXIS{i}"] for i in range(1, h["NAXIS"] + 1)]
            need = (abs(h["BITPIX"]) // 8 * h.get("GCOUNT", 1)
                    * (h.get("PCOUNT", 0) + math.prod(axes))) if axes else 0
            out.append((info["hdrLoc"], info["datLoc"], need))
    return out


KINDS = ["image", "table", "aot", "fz"]
WHERE = ["header", "data", "block"]


def _cut(path: Path, where: str) -> tuple[int, int, tuple[int, int, int]]:
    """Truncate ``path``; return the cut, the HDU it falls in and that HDU's layout."""
    layout = _layout(path)
    size = path.stat().st_size
    # the HDU holding the log's data: the largest
    index = max(range(len(layout)), key=lambda k: layout[k][2])
    head, data, need = layout[index]
    cut = {"header": head + 1000, "data": data + need // 2, "block": size - 2880}[where]
    hdu = max(k for k, (h, _, _) in enumerate(layout) if h <= cut)
    os.truncate(path, cut)
    return cut, hdu, layout[hdu]


@pytest.mark.parametrize("where", WHERE)
@pytest.mark.parametrize("kind", KINDS)
def test_truncated_file_is_named_with_its_sizes(tmp_path, kind, where):
    path = _write(kind, tmp_path)
    cut, hdu, (head, data, need) = _cut(path, where)
    with pytest.raises(LogFormatError) as info:
        load(path)
    text = str(info.value)
    assert "\n" not in text
    assert text.startswith(f"truncated {'AOT' if kind == 'aot' else 'FITS'} file ")
    assert path.name in text
    assert f"ends at byte {cut}" in text or f"({cut} bytes in all" in text
    if cut < data:  # inside the header: no END card before the end of the file
        assert f"inside the header of HDU {hdu}" in text
    else:  # in the data: the header's size against the bytes present
        assert f"HDU {hdu} " in text
        assert f"declares {need} bytes of data" in text
        assert f"the file has {cut - data} of them" in text


def test_intact_files_still_read(tmp_path):
    """The check judges length only: every intact file reads, values bit for bit."""
    ref = _log().coeffs
    for kind in KINDS:
        got = np.asarray(load(_write(kind, tmp_path)).coeffs)
        assert np.array_equal(got, ref), kind


@pytest.mark.parametrize("kind", KINDS)
def test_cli_says_truncated_in_one_line_exit_2(tmp_path, kind):
    path = _write(kind, tmp_path)
    _cut(path, "data")
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    res = subprocess.run([sys.executable, "-m", "modalinfo", "info", str(path)],
                         capture_output=True, text=True, env=env, timeout=300)
    assert res.returncode == 2, res.stderr
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in res.stderr
    assert "truncated" in lines[0] and path.name in lines[0]
