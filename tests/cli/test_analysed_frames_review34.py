"""reorder's header on a thinned and split log (review34, mutation round 34).

Round 51 PART b (O14 / O15): ``reorder`` names the frames it pooled. With ``--max-frames``
keeping every 2nd frame and ``--split-gaps`` keeping the longest contiguous segment of
those, the header names the segment in the file's frame numbers and the stride. Reference:
the log's gap is built here (a 50 ms jump after frame 799 of 2,000, so the thinned log's
segment is file frames 800..1998, every 2nd), and the scores of ``--method variance``
recomputed with numpy on exactly those frames (``coeffs[800::2]``: mean square of each
mode), and the provenance's ``analysed_frames`` against the same numbers (and its rule
against ``--max-frames 600`` on 2,000 frames by hand: every 4th, 500 of them).
"""

from __future__ import annotations

import json

import numpy as np

from modalinfo.io import save
from modalinfo.telemetry import ModalLog

from .conftest import exit_code


def test_a_thinned_segment_names_its_file_frames_and_stride(tmp_path, capsys):
    rng = np.random.default_rng(34)
    times = np.arange(2000) / 1000.0
    times[800:] += 0.05  # a 50 ms gap after frame 799
    coeffs = rng.standard_normal((2000, 4)) * np.array([1.0, 2.0, 0.5, 1.5])
    path = save(ModalLog(coeffs, timestamps=times, modes=[2, 3, 4, 5], units="rad"),
                tmp_path / "log.npz")
    out = tmp_path / "o.json"
    assert exit_code(["reorder", path, "--method", "variance", "--pupil-pixels", "16",
                      "--max-frames", "1000", "--split-gaps", "--out", out]) == 0
    header = capsys.readouterr().out.splitlines()[0]
    assert ("pooled over frames 800..1998 of the file, its longest contiguous segment, "
            "every 2nd frame") in header, header
    result = json.loads(out.read_text())
    np.testing.assert_allclose(np.asarray(result["scores"]),
                               np.mean(coeffs[800::2] ** 2, axis=0), rtol=1e-12)
    record = result["provenance"]["analysed_frames"]
    assert (record["first"], record["last"], record["every"]) == (800, 1998, 2)


def test_the_json_rule_names_the_limit_and_what_it_kept(tmp_path):
    # 2,000 frames under --max-frames 600: every 4th (ceil(2000 / 600)), 500 of them
    coeffs = np.random.default_rng(34).standard_normal((2000, 4))
    path = save(ModalLog(coeffs, timestamps=np.arange(2000) / 1000.0, modes=[2, 3, 4, 5],
                         units="rad"), tmp_path / "log.npz")
    out = tmp_path / "o.json"
    assert exit_code(["reorder", path, "--method", "variance", "--pupil-pixels", "16",
                      "--max-frames", "600", "--out", out]) == 0
    record = json.loads(out.read_text())["provenance"]["analysed_frames"]
    assert record["rule"] == "--max-frames 600: every 4th frame (500 of 2000)"
