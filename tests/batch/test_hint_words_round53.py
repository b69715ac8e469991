"""A batch error row names a reader hint as the batch user gave it (round 53 PART b, M09-M38).

Reference: the command line's options (``modalinfo batch --help``: --rate, --in-units,
--in-modes, --transpose, --loop) and the manifest's columns (``modalinfo.batch.manifest``);
``modalinfo info`` says "hint --rate 2000.0 contradicts ..." of the same file. The file is
written by ``modalinfo.io.save`` at 1000 Hz, 3 modes, in rad.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.batch.analyses import resolve_params, run_log_task
from modalinfo.io import save
from modalinfo.telemetry import ModalLog


@pytest.fixture
def log_file(tmp_path):
    path = tmp_path / "a.npz"
    save(ModalLog(np.random.default_rng(0).standard_normal((50, 3)), rate=1000.0), path)
    return str(path)


@pytest.mark.parametrize(("hints", "named"), [
    ({"rate": 2000.0}, "hint rate (--rate or column 'rate') = 2000.0 contradicts"),
    ({"units": "nm", "wavelength": 5e-7}, "hint units (--in-units or column 'in_units')"),
    ({"modes": [2, 3]}, "hint modes (--in-modes or column 'in_modes')"),
    ({"transpose": True}, "hint transpose (--transpose or column 'transpose') = True"),
    ({"loop": "0"}, "loop (--loop or column 'loop') selects a control loop"),
])
def test_hint_named_by_option_and_column(log_file, hints, named):
    payload = {"path": log_file, "fmt": None, "hints": hints, "analysis": "summary",
               "params": resolve_params("summary")}
    with pytest.raises(ValueError) as caught:  # the runner makes it the error row
        run_log_task(payload)
    assert named in str(caught.value)
    assert "`" not in str(caught.value)  # the reader's "hint `rate`=" was the row's text
