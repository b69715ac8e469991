"""``modalinfo convert IN IN --overwrite``: refused, IN unchanged byte for byte.

Round 44 PART b, d22: ``convert r1x.fits r1x.fits --overwrite --loop dm0`` on an AOT file
of ``closedloop export`` replaced the whole system (loops dm0 and dm0.pol, telescope, WFS,
DMs; 241,920 bytes) by a plain FITS of one loop (17,280 bytes) without a word. Reference:
the SHA-256 (hashlib) of IN before and after, and ``os.path.samefile``'s reading of "the
same file" (a hard link or a symbolic link to IN is IN).
"""
import hashlib
import os

import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.io import save
from modalinfo.telemetry import ModalLog


def _digest(path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.fixture
def log():
    rng = np.random.default_rng(1)
    return ModalLog(rng.standard_normal((64, 3)), rate=1000.0, units="rad", wavelength=5e-7)


@pytest.mark.parametrize("fmt, name", [("aot", "sys.fits"), ("npz", "log.npz")])
def test_output_equal_to_input_is_refused(tmp_path, capsys, log, fmt, name):
    path = save(log, tmp_path / name, fmt=fmt)
    before = _digest(path)
    assert main(["convert", str(path), str(path), "--overwrite", "--to-fmt", "fits"
                 if fmt == "aot" else "npz", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "is the input file IN" in err and err.count("\n") == 1
    assert _digest(path) == before


@pytest.mark.parametrize("link", ["hard", "symbolic"])
def test_output_linked_to_input_is_refused(tmp_path, capsys, log, link):
    path = save(log, tmp_path / "log.npz")
    other = tmp_path / "other.npz"
    (os.link if link == "hard" else os.symlink)(path, other)
    before = _digest(path)
    assert main(["convert", str(path), str(other), "--overwrite", "--units", "nm",
                 "--quiet"]) == 2
    assert "is the input file IN" in capsys.readouterr().err
    assert _digest(path) == before


def test_another_name_still_converts(tmp_path, log):
    path = save(log, tmp_path / "log.npz")
    assert main(["convert", str(path), str(tmp_path / "nm.npz"), "--units", "nm",
                 "--quiet"]) == 0
