"""A disk that fills mid-write: the error names the user's target, nothing is left behind.

Issue 27, left13-cli item 5: ``modalinfo forecast --out DIR`` on a disk that filled while it
wrote said ``No space left on device writing 'DIR/.forecast.2861-h7_ovg1_.tmp/
forecast_series.png'`` (its staging folder, a name the user never gave); a stand-alone
figure script said only ``[Errno 28]`` (matplotlib names no file); astropy's FITS writer
passed on numpy's short write (``540000 requested and 7832 written``, no errno) as it
was. All three were seen on a 64 kB tmpfs whose free space the pre-checks were told was
large. Reference, outside the code: the kernel's ``ENOSPC`` (``errno``), raised here where
a real file system raises it (``fsync`` of delayed allocation; matplotlib's ``savefig``;
numpy's ``tofile`` wording), and the folder's listing after the failure.
"""

from __future__ import annotations

import errno
import os

import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.common import files
from modalinfo.io import save
from modalinfo.telemetry.log import ModalLog
from paper_figures import fig6_compression


def _enospc(*args, **kwargs):
    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


def test_forecast_names_its_out_folder(tmp_path, monkeypatch, capsys):
    coeffs = np.cumsum(np.random.default_rng(5).standard_normal((600, 3)), axis=0)
    source = save(ModalLog(coeffs, rate=100.0, units="rad"), tmp_path / "in.npz")
    out = tmp_path / "fc"
    monkeypatch.setattr(files.os, "fsync", _enospc)  # the first staged file hits the limit
    code = main(["forecast", str(source), "--predictors", "linear", "--horizon", "2",
                 "--out", str(out), "--quiet"])
    err = capsys.readouterr().err.strip()
    assert code != 0 and len(err.splitlines()) == 1
    assert "No space left on device" in err and f"'{out}" in err
    assert ".forecast." not in err and ".tmp" not in err
    assert sorted(os.listdir(tmp_path)) == ["in.npz"]  # the new folder removed again


def test_figure_script_names_its_out_folder(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(fig6_compression, "make", _enospc)  # matplotlib's savefig, full
    out = tmp_path / "figs"
    assert fig6_compression.main(["--out", str(out), "--quick"]) != 0
    err = capsys.readouterr().err.strip()
    assert err == (f"python -m paper_figures.fig6_compression: error: "
                   f"No space left on device writing '{out}' (nothing was "
                   "written); free space or write elsewhere")
    assert os.listdir(tmp_path) == []


def test_numpy_short_write_is_a_full_disk(tmp_path):
    def write(fh):
        fh.write(b"x" * 10)
        raise OSError("540000 requested and 7832 written")  # ndarray.tofile's words

    with pytest.raises(OSError, match=r"No space left on device writing '.*a\.fits' "
                                      r"\(nothing was written\)") as info:
        files.atomic_write(tmp_path / "a.fits", write, overwrite=False)
    assert info.value.errno == errno.ENOSPC
    assert os.listdir(tmp_path) == []
