"""Frame numbers of ``--split-gaps`` and ``--max-frames`` runs (adversarial round 48 PART b).

References: the file's own frame numbers (the log is built here with a gap after frame
1000 of 3000, so its longest contiguous segment is frames 1000..2999 by construction) and
the order ``reorder --frame K`` gives without ``--split-gaps`` (the same per-frame MI
ordering of the same frame, seed and budget: the same bits).

- T18: ``reorder --split-gaps --frame 5`` ordered frame 1005 (frame 5 of the segment) and
  printed / stored "frame 5"; now frame K is the file's: outside the segment it is refused,
  inside it orders that frame, and the JSON's ``frame`` is K.
- The same JSON key under ``--max-frames`` held the subsample's index (``--frame 4`` with
  every 2nd frame stored 2; found after the round's count).
- O65 / O66: forecast's and reorder's JSON did not say which frames ``--split-gaps`` kept
  (forecast's ``first_origin`` counts from the segment); now ``provenance.analysed_frames``.
- T19: the refusal of a ``--frame`` that ``--max-frames`` skips said "every 2th".
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from modalinfo.io import save
from modalinfo.telemetry import ModalLog

from .conftest import exit_code, write_small_log

ORDER = ["--resamples", "0", "--budget", "2000", "--pupil-pixels", "16"]


@pytest.fixture
def gapped(tmp_path):
    """3000 frames of Z2-Z5 at 1 kHz with a 50 ms gap after frame 1000 (segment 1000..2999)."""
    rng = np.random.default_rng(5)
    times = np.arange(3000) / 1000.0
    times[1000:] += 0.05
    coeffs = np.cumsum(rng.standard_normal((3000, 4)), axis=0) * 0.01
    return save(ModalLog(coeffs, timestamps=times, modes=[2, 3, 4, 5]), tmp_path / "gap.npz")


def _order(log, tmp_path, name, *extra):
    out = tmp_path / name
    assert exit_code(["reorder", log, *ORDER, "--out", out, *extra]) == 0
    return json.loads(out.read_text())


def test_split_gaps_frame_is_the_files_frame(gapped, tmp_path, capsys):
    reference = _order(gapped, tmp_path, "plain.json", "--frame", "1005")
    cut = _order(gapped, tmp_path, "cut.json", "--frame", "1005", "--split-gaps")
    assert cut["order"] == reference["order"]
    assert cut["frame"] == 1005
    assert "frame 1005" in capsys.readouterr().out


def test_split_gaps_frame_outside_the_segment_is_refused(gapped, tmp_path, capsys):
    out = tmp_path / "no.json"
    assert exit_code(["reorder", gapped, *ORDER, "--frame", "5", "--split-gaps",
                      "--out", out]) == 2
    err = capsys.readouterr().err
    assert "--frame 5" in err and "1000..2999" in err
    assert not out.exists()


def test_max_frames_json_frame_is_the_files_frame(tmp_path, capsys):
    log = write_small_log(tmp_path / "small.npz", 2000)
    got = _order(log, tmp_path, "sub.json", "--frame", "4", "--max-frames", "1000")
    assert got["frame"] == 4
    assert exit_code(["reorder", log, *ORDER, "--frame", "5", "--max-frames", "1000"]) == 2
    err = capsys.readouterr().err
    assert "every 2nd of 2000" in err and "2th" not in err


def test_outputs_record_the_segment(gapped, tmp_path):
    cut = _order(gapped, tmp_path, "pooled.json", "--split-gaps")
    expected = {"first": 1000, "last": 2999, "every": 1}
    record = cut["provenance"]["analysed_frames"]
    assert {k: record[k] for k in expected} == expected
    out = tmp_path / "fc"
    assert exit_code(["forecast", gapped, "--split-gaps", "--predictors", "linear",
                      "--horizon", "1", "--out", out, "--quiet"]) == 0
    forecast = json.loads((out / "forecast.json").read_text())
    record = forecast["provenance"]["analysed_frames"]
    assert {k: record[k] for k in expected} == expected
    # first_origin counts from the segment's first frame: training half of 2000 frames
    assert forecast["first_origin"] == 999


def test_variance_json_names_its_score_units(tmp_path):
    """O60: a variance order's scores are mean squares [rad^2] (numpy), the JSON said only nats."""
    log = write_small_log(tmp_path / "small.npz", 400)
    out = tmp_path / "var.json"
    assert exit_code(["reorder", log, "--method", "variance", "--resamples", "0",
                      "--out", out]) == 0
    got = json.loads(out.read_text())
    assert got["score_units"] == "rad^2"
    coeffs = np.load(log)["coefficients"]
    np.testing.assert_allclose(got["scores"], np.mean(coeffs ** 2, axis=0), rtol=1e-12)
    mi = _order(log, tmp_path, "mi.json", "--method", "mi_marginal")
    assert mi["score_units"] == "nats"


def test_closed_pipe_still_writes_the_out_file(tmp_path):
    """`reorder ... --out F.json | head -1` exited 0 without F.json (a BrokenPipeError mid-run).

    Reference: the README's promise, "a closed pipe (`| head -1`) is not an error"; the
    reader's end is closed before the command writes anything, so the first write fails.
    """
    import os
    import subprocess
    import sys

    log = write_small_log(tmp_path / "small.npz", 2000)
    out = tmp_path / "piped.json"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    proc = subprocess.Popen(
        [sys.executable, "-m", "modalinfo", "reorder", str(log), *ORDER, "--max-frames",
         "1000", "--frame", "4", "--out", str(out)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env)
    proc.stdout.close()  # the reader is gone before the first line
    _, err = proc.communicate(timeout=300)
    assert proc.returncode == 0, err
    assert json.loads(out.read_text())["frame"] == 4
