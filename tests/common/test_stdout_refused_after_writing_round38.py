"""A stdout that refuses the summary of files already written: named, status 1.

Adversarial round 38 PART b, rows P49, P56-P59 (cause W3): ``modalinfo convert small.npz
c.npz > /dev/full`` (and ``synth``, ``batch``, ``closedloop run --out``, ``closedloop
export``) wrote the file completely, then said "error: [Errno 28] No space left on
device" with status 2, the README's status of "a usage or input error" (for batch: "an
input error found before any work"), naming neither standard output nor the file.
References: /dev/full's contract (every write fails with ENOSPC; the file system the
file went to is not full), the file read back by numpy / h5py, and the package's own
status for a stdout that refuses the help (``--help > /dev/full``: "could not write the
output", status 1, Audit 10-env).
"""

import os
import subprocess
import sys

import numpy as np
import pytest

from modalinfo.cli import main as modalinfo_main


class _Full:
    """A stream like /dev/full."""

    def write(self, text):
        raise OSError(28, "No space left on device")

    def flush(self):
        raise OSError(28, "No space left on device")


_SAID = ("could not write standard output (No space left on device); the files written "
         "before it are complete")


def _one_line(capsys, prog):
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert err.startswith(f"{prog}: error: {_SAID}"), err


def test_synth_then_convert_to_a_full_stdout(tmp_path, monkeypatch, capsys):
    log, copy = tmp_path / "s.npz", tmp_path / "c.npz"
    monkeypatch.setattr("sys.stdout", _Full())
    assert modalinfo_main(["synth", str(log), "--frames", "200"]) == 1
    _one_line(capsys, "modalinfo synth")
    assert np.load(log)["coefficients"].shape == (200, 27)
    assert modalinfo_main(["convert", str(log), str(copy)]) == 1
    _one_line(capsys, "modalinfo convert")
    np.testing.assert_array_equal(np.load(copy)["coefficients"],
                                  np.load(log)["coefficients"])


def test_closedloop_run_out_and_export_to_a_full_stdout(tmp_path, monkeypatch, capsys):
    import h5py

    from closedloop.cli import main as closedloop_main

    run, fits = tmp_path / "r.h5", tmp_path / "r.fits"
    monkeypatch.setattr("sys.stdout", _Full())
    assert closedloop_main(["run", "--preset", "kaos", "--duration", "0.01", "--quiet",
                            "--out", str(run)]) == 1
    _one_line(capsys, "closedloop run")
    with h5py.File(run, "r") as f:  # complete: it opens and holds the run's datasets
        assert len(f.keys()) > 0
    assert closedloop_main(["export", str(run), str(fits), "--no-mode-images"]) == 1
    _one_line(capsys, "closedloop export")
    assert fits.stat().st_size > 0


@pytest.mark.slow
@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full")
def test_batch_to_a_full_stdout_keeps_its_table_and_says_so(tmp_path):
    # a real /dev/full in a subprocess: a fake sys.stdout stops Dask's worker start-up
    log, out = tmp_path / "a.npz", tmp_path / "out"
    assert modalinfo_main(["synth", str(log), "--frames", "200", "--quiet"]) == 0
    with open("/dev/full", "w") as full:
        done = subprocess.run([sys.executable, "-m", "modalinfo", "batch", str(log), "--out",
                               str(out), "--workers", "1", "--no-plots"], stdout=full,
                              stderr=subprocess.PIPE, text=True, timeout=600, check=False)
    assert done.returncode == 1, done.stderr
    assert f"modalinfo batch: error: {_SAID}" in done.stderr
    assert "Traceback" not in done.stderr
    assert (out / "batch.csv").is_file()
