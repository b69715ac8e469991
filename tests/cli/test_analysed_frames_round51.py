"""reorder's header and every command's JSON say which frames were analysed (round 51 PART b).

O14: ``reorder --max-frames 600`` on 2000 frames ordered every 4th frame (500) and printed
"pooled over all frames"; its ``--out`` JSON recorded the command line only, so the default
``--max-frames`` (50000, never typed) left no trace at all. O15: ``reorder --split-gaps``
printed "pooled over all frames" of the longest segment. The stderr note was the only word.
References: the scores of ``--method variance`` recomputed with numpy on the frames the
header names (``coeffs[::4]``: mean square of each mode), and the log's gap built here
(frames 800..1999 are the longest contiguous segment by construction).
"""

from __future__ import annotations

import json

import numpy as np

from modalinfo.io import save
from modalinfo.telemetry import ModalLog

from .conftest import exit_code


def _log(tmp_path, gap: bool = False):
    rng = np.random.default_rng(51)
    times = np.arange(2000) / 1000.0
    if gap:
        times[800:] += 0.05  # a 50 ms gap after frame 799
    coeffs = rng.standard_normal((2000, 4)) * np.array([1.0, 2.0, 0.5, 1.5])
    return coeffs, save(ModalLog(coeffs, timestamps=times, modes=[2, 3, 4, 5], units="rad"),
                        tmp_path / "log.npz")


def test_max_frames_is_in_the_header_and_the_json(tmp_path, capsys):
    coeffs, path = _log(tmp_path)
    out = tmp_path / "o.json"
    assert exit_code(["reorder", path, "--method", "variance", "--pupil-pixels", "16",
                      "--max-frames", "600", "--out", out]) == 0
    header = capsys.readouterr().out.splitlines()[0]
    assert "pooled over every 4th frame, 500 of 2000" in header, header
    result = json.loads(out.read_text())
    record = result["provenance"]["analysed_frames"]
    assert (record["first"], record["last"], record["every"]) == (0, 1996, 4)
    # the header names what was computed: numpy's mean squares of every 4th frame
    expected = np.mean(coeffs[::4] ** 2, axis=0)
    np.testing.assert_allclose(np.asarray(result["scores"]), expected, rtol=1e-12)


def test_all_frames_are_all_frames(tmp_path, capsys):
    _, path = _log(tmp_path)
    out = tmp_path / "o.json"
    assert exit_code(["reorder", path, "--method", "variance", "--pupil-pixels", "16",
                      "--out", out]) == 0
    assert "pooled over all frames" in capsys.readouterr().out.splitlines()[0]
    assert "analysed_frames" not in json.loads(out.read_text())["provenance"]


def test_split_gaps_segment_is_in_the_header(tmp_path, capsys):
    _, path = _log(tmp_path, gap=True)
    assert exit_code(["reorder", path, "--pupil-pixels", "16", "--budget", "2000",
                      "--resamples", "3", "--split-gaps"]) == 0
    header = capsys.readouterr().out.splitlines()[0]
    assert "pooled over frames 800..1999 of the file" in header, header
