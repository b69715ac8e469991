"""report.md's head line names the code that made it (round 43 PART b, R04).

The head gave ``modalinfo 0.1.0+src...`` only, a fingerprint of modalinfo and closedloop,
not of paper_figures (which makes the report). Reference: the record each figure's PNG
carries (``Description`` text chunk, read with PIL), whose ``git`` and ``source_sha256``
the adversary recomputed with ``find ... | sha256sum``.
"""

import json

import numpy as np
import pytest
from PIL import Image

from paper_figures.__main__ import main


@pytest.mark.slow  # Figure 1 on a 400-frame log: ~2 min on a loaded 2-core machine
def test_head_line_gives_git_and_source_sha256(tmp_path):
    from modalinfo.telemetry.synthetic import kaos_like

    log = kaos_like(n_frames=400, seed=0, modes=list(range(2, 29)))
    np.savetxt(tmp_path / "mine.csv", np.asarray(log.to_units("nm").coeffs), delimiter=",")
    assert main(["--out", str(tmp_path / "o"), "--only", "1", "--log",
                 str(tmp_path / "mine.csv"), "--rate", "2000", "--in-units", "nm",
                 "--wavelength", "5e-7", "--in-modes", "2-28", "--in-convention", "noll"]) == 0
    head = (tmp_path / "o" / "report.md").read_text().splitlines()[2]
    png = next((tmp_path / "o").glob("*.png"))
    record = json.loads(Image.open(png).text["Description"])
    assert record["source_sha256"] and f"source SHA-256 {record['source_sha256']}" in head
    assert f"git {record['git'] or 'unknown'}" in head
