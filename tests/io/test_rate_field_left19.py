"""A foreign file's rate field that disagrees with its timestamps is said, once.

Reference outside the code: the timestamps' median interval (``numpy.median`` of
``numpy.diff``) of files written directly with numpy (NPZ members), h5py (an HDF5
dataset with a ``rate`` attribute) and astropy (a FITS table with a ``TIME`` column and a
``RATE`` keyword). Round 19 PART b, B10, B12, B17: such files were read at the
timestamps' rate without a word about the field; now ``metadata["rate_field"]`` and one
note of ``modalinfo info`` say it, naming the field and both rates. A field that agrees
within the timestamps' jitter (2 % timing noise), a ``--rate`` given, or a converted
copy give no note.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.io import load, save

FRAMES = 400


def _data(jitter: float = 0.0):
    rng = np.random.default_rng(4)
    coeffs = rng.standard_normal((FRAMES, 3))
    times = np.arange(FRAMES) / 1000.0  # 1000 Hz
    if jitter:
        times = times + rng.uniform(-jitter, jitter, FRAMES) / 1000.0
    return coeffs, times


def _npz(path: Path, rate: float, jitter: float = 0.0) -> Path:
    coeffs, times = _data(jitter)
    np.savez(path, coefficients=coeffs, timestamps=times, rate=np.float64(rate))
    return path


def _h5(path: Path, rate: float) -> Path:
    h5py = pytest.importorskip("h5py")
    coeffs, times = _data()
    with h5py.File(path, "w") as f:
        f.create_dataset("coefficients", data=coeffs).attrs["rate"] = rate
        f.create_dataset("timestamps", data=times)
    return path


def _fits(path: Path, rate: float) -> Path:
    fits = pytest.importorskip("astropy.io.fits")
    coeffs, times = _data()
    cols = [fits.Column(name="TIME", format="D", array=times)]
    cols += [fits.Column(name=f"Z{j}", format="D", array=coeffs[:, k])
             for k, j in enumerate((2, 3, 4))]
    table = fits.BinTableHDU.from_columns(cols)
    table.header["RATE"] = rate
    fits.HDUList([fits.PrimaryHDU(), table]).writeto(path)
    return path


WRITERS = {"npz": (_npz, "member 'rate'"), "h5": (_h5, "attribute of 'coefficients', 'rate'"),
           "fits": (_fits, "keyword of HDU 1 'RATE'")}


def _info(capsys, argv) -> tuple[int, str, str]:
    code = main(["info", *map(str, argv)])
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.mark.parametrize("fmt", sorted(WRITERS))
def test_disagreeing_rate_field_is_said_once(fmt, tmp_path, capsys):
    write, where = WRITERS[fmt]
    path = write(tmp_path / f"log.{fmt}", 500.0)
    reference = 1.0 / float(np.median(np.diff(_data()[1])))  # 1000 Hz
    log = load(path)
    assert log.rate == pytest.approx(reference, rel=1e-9)  # the timestamps are used
    note = log.metadata["rate_field"]
    assert f"({where})" in note and "says 500 Hz" in note
    assert f"timestamps {reference:.6g} Hz" in note
    code, out, err = _info(capsys, [path])
    assert code == 0
    assert "(timestamps)" in out
    lines = [ln for ln in out.splitlines() if "rate field" in ln]
    assert lines == [f"rate note   {note}"], out  # once, in full
    # a command reading the log says it once on stderr
    code = main(["convert", str(path), str(tmp_path / "copy.npz")])
    err = capsys.readouterr().err
    assert code == 0
    lines = [ln for ln in err.splitlines() if "rate field" in ln]
    assert len(lines) == 1, err
    assert lines[0].startswith(f"modalinfo convert: note: 'log.{fmt}': the file's rate field")
    assert "--rate" in lines[0]


@pytest.mark.parametrize("fmt", sorted(WRITERS))
def test_agreeing_rate_field_is_not_said(fmt, tmp_path, capsys):
    write, _ = WRITERS[fmt]
    log = load(write(tmp_path / f"log.{fmt}", 1000.0))
    assert "rate_field" not in log.metadata


def test_field_within_the_timestamps_jitter_is_not_said(tmp_path):
    # +-2 % of an interval of timing noise: the median interval is off by less than
    # that (1000 Hz within the jitter); a field 5 % away is said
    assert "rate_field" not in load(_npz(tmp_path / "a.npz", 1000.0, 0.02)).metadata
    assert "rate_field" in load(_npz(tmp_path / "b.npz", 1050.0, 0.02)).metadata


def test_no_note_with_a_rate_given_or_on_a_converted_copy(tmp_path, capsys):
    path = _npz(tmp_path / "log.npz", 500.0)
    assert "rate_field" not in load(path, rate=500.0).metadata
    code, _, err = _info(capsys, [path, "--rate", "500"])
    assert code == 0 and "rate field" not in err
    copy = save(load(path), tmp_path / "copy.npz")  # its metadata keeps the record
    code, out, err = _info(capsys, [copy])
    assert code == 0 and "rate field" not in err and "rate note" not in out, out
