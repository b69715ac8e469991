"""A FITS / AOT file cut inside its last HDU's padding is named as truncated (fix57-d).

fix54-d compared the file's length with each HDU's declared data bytes, not with those
bytes padded to whole 2880-byte blocks (FITS Standard 4.0, section 3.3.2: every HDU
fills whole blocks), so a file cut after its last data byte but before the end of the
padding passed the check and was read by the parsers, which said "Empty or corrupt FITS
file" (astropy, through our FITS reader) or "TypeError: buffer is too small" (aotpy):
fix56-c's Left. The reader now names the truncation, the HDU and the bytes.

Reference from outside the code: astropy's account of the intact file
(``HDUList.fileinfo``: where the last HDU's data start, ``datLoc``, and the bytes they
span with their padding, ``datSpan``) and the FITS size rule on the headers as astropy
parses them; astropy's and aotpy's own readers on the same cut file (astropy warns
"File may have been truncated", aotpy verifying checksums fails: the reader refused it
before too, in their words; its data may be whole, but a file cut there may have lost
HDUs after it, which nothing in it declares). The cuts (``os.truncate``): right after the
last data byte (no padding), in the middle of the padding, one byte short of the end.
"""

from __future__ import annotations

import gc
import math
import os
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from astropy.io import fits
from astropy.utils.exceptions import AstropyUserWarning

from modalinfo.io import load, save
from modalinfo.io.files import LogFormatError
from modalinfo.telemetry import ModalLog

ROOT = Path(__file__).resolve().parents[2]


def _log() -> ModalLog:
    # 301 x 3 float64 = 7224 bytes: 1416 bytes of padding after the data
    x = np.random.default_rng(57).standard_normal((301, 3))
    return ModalLog(x, rate=1000.0, modes=[2, 3, 4])


def _write(kind: str, folder: Path) -> Path:
    log = _log()
    if kind == "image":
        return save(log, folder / "log.fits")
    if kind == "aot":
        pytest.importorskip("aotpy")
        return save(log, folder / "log_aot.fits", fmt="aot")
    path = folder / "table.fits"  # a foreign binary table, one column per mode
    cols = [fits.Column(name=f"Z{j}", format="D", array=log.coeffs[:, k])
            for k, j in enumerate(log.modes)]
    fits.HDUList([fits.PrimaryHDU(), fits.BinTableHDU.from_columns(cols)]).writeto(path)
    return path


def _last(path: Path) -> tuple[int, int, int, int]:
    """``(index, data start, declared data bytes, padded span)`` of the last HDU, by astropy."""
    with fits.open(path) as hdul:
        k = len(hdul) - 1
        info, h = hdul.fileinfo(k), hdul[k].header
        axes = [h[f"NAXIS{i}"] for i in range(1, h["NAXIS"] + 1)]
        need = (abs(h["BITPIX"]) // 8 * h.get("GCOUNT", 1)
                * (h.get("PCOUNT", 0) + math.prod(axes))) if axes else 0
        return k, info["datLoc"], need, info["datSpan"]


KINDS = ["image", "table", "aot"]
CUTS = ["data_end", "middle", "one_short"]


def _cut(path: Path, where: str) -> tuple[int, int, int, int]:
    k, data, need, span = _last(path)
    assert span > need > 0 and data + span == path.stat().st_size  # padding to cut into
    cut = {"data_end": data + need, "middle": data + (need + span) // 2,
           "one_short": data + span - 1}[where]
    os.truncate(path, cut)
    return cut, k, data, need


@pytest.mark.parametrize("where", CUTS)
@pytest.mark.parametrize("kind", KINDS)
def test_cut_in_the_padding_is_named_truncated(tmp_path, kind, where):
    path = _write(kind, tmp_path)
    cut, k, data, need = _cut(path, where)
    with pytest.raises(LogFormatError) as info:
        load(path)
    text = str(info.value)
    assert "\n" not in text
    assert text.startswith(f"truncated {'AOT' if kind == 'aot' else 'FITS'} file ")
    assert f"HDU {k} " in text and f"declares {need} bytes of data" in text
    assert f"the file has {cut - data} of them ({cut} bytes in all" in text
    assert "its data are whole, the padding after them is cut" in text


@pytest.mark.parametrize("where", CUTS)
def test_astropy_and_aotpy_see_a_short_file(tmp_path, where):
    aotpy = pytest.importorskip("aotpy")
    path = _write("aot", tmp_path)
    _cut(path, where)
    # astropy: "File may have been truncated" (a warning; an error under this suite's
    # filterwarnings); aotpy with its checksums verified (as ``load(..., verify=True)``
    # reads): numpy's "buffer is too small", the words the reader gave before
    with pytest.warns(AstropyUserWarning, match="File may have been truncated"):
        fits.open(path, lazy_load_hdus=False).close()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AstropyUserWarning)
        warnings.simplefilter("ignore", ResourceWarning)  # aotpy leaves the file open then
        with pytest.raises(TypeError, match="buffer is too small"):
            aotpy.AOSystem.read_from_file(str(path), file_type="fits", checksum=True)
        gc.collect()  # its file closed here, under the filter


def test_cut_in_the_data_is_not_said_whole(tmp_path):
    path = _write("image", tmp_path)
    _, data, need, _ = _last(path)
    os.truncate(path, data + need - 8)
    with pytest.raises(LogFormatError, match="truncated FITS file") as info:
        load(path)
    assert "data are whole" not in str(info.value)


def test_intact_files_still_read(tmp_path):
    ref = _log().coeffs
    for kind in KINDS:
        assert np.array_equal(np.asarray(load(_write(kind, tmp_path)).coeffs), ref), kind


@pytest.mark.parametrize("kind", ["image", "aot"])
def test_cli_exits_2_in_one_line(tmp_path, kind):
    path = _write(kind, tmp_path)
    _cut(path, "middle")
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    res = subprocess.run([sys.executable, "-m", "modalinfo", "info", str(path)],
                         capture_output=True, text=True, env=env, timeout=300)
    assert res.returncode == 2, res.stderr
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in res.stderr
    assert "truncated" in lines[0] and path.name in lines[0]
