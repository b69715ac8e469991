"""``--plot x.pgf`` without the TeX engine is refused before any work (round 54 PART b, O27, O37).

Reference: matplotlib's PGF backend, which runs ``rcParams['pgf.texsystem']`` (xelatex by
default) to measure its text and raises ``RuntimeError: 'xelatex' not found`` without it.
Before the fix, ``fitting-error --plot fe.pgf`` printed its table and then that
traceback (exit 1). ``PATH`` is set here to an empty folder, so no TeX engine is found
whatever this machine installed; a PNG is still drawn as before.
"""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.telemetry import ModalLog


@pytest.fixture
def small_log(tmp_path):
    path = tmp_path / "small.npz"
    x = np.random.default_rng(54).normal(size=(300, 5))
    from modalinfo.io import save

    save(ModalLog(x, rate=1000.0, units="rad", wavelength=5e-7), path)
    return path


@pytest.mark.parametrize("name", ["fe.pgf", "fe.PGF"])
def test_pgf_without_engine_refused_before_work(tmp_path, capsys, monkeypatch, small_log,
                                                 name):
    empty = tmp_path / "bin"
    empty.mkdir()
    monkeypatch.setenv("PATH", str(empty))  # no TeX engine on it
    out = tmp_path / name
    code = main(["fitting-error", str(small_log), "--orderings", "zernike:standard",
                 "--pupil-pixels", "16", "--plot", str(out), "--quiet"])
    captured = capsys.readouterr()
    assert code == 2
    assert captured.out == ""  # before the work: no table was printed
    assert "--plot" in captured.err and str(matplotlib.rcParams["pgf.texsystem"]) in captured.err
    assert "Traceback" not in captured.err
    assert not out.exists()


def test_png_still_drawn(tmp_path, capsys, small_log):
    out = tmp_path / "fe.png"
    assert main(["fitting-error", str(small_log), "--orderings", "zernike:standard",
                 "--pupil-pixels", "16", "--plot", str(out), "--quiet"]) == 0
    assert out.read_bytes()[:4] == b"\x89PNG"
