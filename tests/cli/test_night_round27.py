"""Round 27 PART b of issue 27: a heterogeneous night of logs, the fixes.

The full list of inputs (input | expected | before | after) is in docs/ADVERSARIAL.md,
"Round 27 PART b, issue 27".

References: the mode numbers written into the log file by the test itself (Noll 2-11
and 15-21: Z12-Z14 absent), so a text naming the modes must not span Z11 to Z15; the
file-size limit the test sets with ``resource.setrlimit(RLIMIT_FSIZE)`` in the child
process, which the one-line error must state (POSIX: a write past it fails with EFBIG).
"""

from __future__ import annotations

import os
import resource
import subprocess
import sys

import numpy as np
import pytest

from modalinfo import io
from modalinfo.telemetry import ModalLog

from .conftest import exit_code

GAP_MODES = list(range(2, 12)) + list(range(15, 22))  # 17 modes, Z12-Z14 absent


@pytest.fixture
def gap_log(tmp_path):
    rng = np.random.default_rng(27)
    log = ModalLog(rng.standard_normal((300, len(GAP_MODES))), rate=2000.0, modes=GAP_MODES,
                   units="rad", wavelength=5e-7)
    return io.save(log, tmp_path / "gap.npz")


def test_info_names_the_gap_in_the_modes(gap_log, capsys):
    # Before: "modes       Z2 .. Z21 (noll)" for a log holding 17 of those 20 modes.
    assert exit_code(["info", str(gap_log), "--quiet"]) == 0
    line = next(ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("modes"))
    assert "Z2 .. Z11, Z15 .. Z21" in line, line


def test_not_a_mode_error_names_the_gap(gap_log, capsys):
    # Before: "entry 13 is not a mode of this log; its modes are Z2..Z21 (noll)."
    assert exit_code(["forecast", str(gap_log), "--modes", "13", "--quiet", "--out",
                      str(gap_log.parent / "fc")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Z2..Z11, Z15..Z21" in err, err


@pytest.mark.parametrize(("modes", "text"), [
    ([2, 3, 4], "Z2 .. Z4"),
    ([7], "Z7"),
    ([2, 3, 5, 6], "Z2 .. Z3, Z5 .. Z6"),
    ([2, 3, 4, 9, 10, 11], "Z2 .. Z4, Z9 .. Z11"),
    ([11, 10, 9], "Z11, Z10, Z9"),  # descending columns: no run is claimed
    ([2, 4, 6, 8, 10, 12], "Z2, Z4, ... (3 more modes) ..., Z12"),
])
def test_mode_span_runs_match_the_modes(modes, text):
    from modalinfo.telemetry.checks import mode_span

    assert mode_span(modes, "noll") == text
    # every mode the text names as a run endpoint or single is one of the modes given
    named = [int(t.strip(" .,Z")) for t in text.replace("..", ",").split(",")
             if t.strip(" .,Z").isdigit()]
    assert set(named) <= set(modes)


def _limited(limit_bytes: int):
    def pre():  # the child alone: a file-size limit in pytest's process would bind the suite
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit_bytes, resource.RLIM_INFINITY))
    return pre


def test_file_size_limit_is_named(tmp_path):
    # Before: "modalinfo synth: error: [Errno 27] File too large" (no limit named).
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in sys.path if p)}
    proc = subprocess.run(
        [sys.executable, "-m", "modalinfo", "synth", "s.npz", "--frames", "20000", "--quiet"],
        cwd=tmp_path, env=env, capture_output=True, text=True, timeout=120,
        preexec_fn=_limited(100 * 1024), check=False)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr, proc.stderr
    assert "ulimit -f" in proc.stderr and "100.00 kiB" in proc.stderr, proc.stderr
    assert list(tmp_path.iterdir()) == []  # nothing half-written
