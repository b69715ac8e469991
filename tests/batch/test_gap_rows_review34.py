"""A batch ordering row on a gapped log at the edges of its refusal rule (review34, round 34).

``batch.analyses._require_contiguous_for_ordering`` (round 51 PART b, C105) refuses the
stability windows on a log with a gap from ``windows`` >= 2 (two windows are already a
stability: ``ordering_stability`` splits the log in time), before the ordering's work.
Reference: the gap is the test's own (frames 200..219 removed from a 1 kHz log's
timestamps, as ``test_gap_rows_round51.py``), and the same row on the same frames with no
gap (timestamps equally spaced) is ``ok``, so the refusal is the gap's, not the size's.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.io import save
from modalinfo.telemetry import ModalLog

from .test_gap_rows_round51 import _row

_ORDERING = {"estimator": "gaussian", "budget": 2000, "pupil_pixels": 16}


def _log(tmp_path, gap: bool) -> str:
    rng = np.random.default_rng(34)
    n = 600
    x = np.zeros((n, 3))
    e = rng.normal(size=(n, 3))
    for t in range(1, n):  # AR(1), phi 0.8
        x[t] = 0.8 * x[t - 1] + e[t]
    frames = np.r_[0:200, 220:n + 20] if gap else np.arange(n)
    log = ModalLog(x, timestamps=frames / 1000.0, modes=[2, 3, 4], units="rad",
                   wavelength=5e-7)
    path = tmp_path / f"{'gapped' if gap else 'whole'}.npz"
    save(log, path)
    return str(path)


@pytest.mark.parametrize("windows", [2, 3])
def test_two_windows_on_a_gapped_log_are_refused(tmp_path, windows):
    row = _row(_log(tmp_path, gap=True), "ordering", windows=windows, **_ORDERING)
    assert row["status"] == "error"
    assert f"ordering.windows {windows}" in row["error_message"]
    assert "--set ordering.windows=0" in row["error_message"]
    whole = _row(_log(tmp_path, gap=False), "ordering", windows=windows, **_ORDERING)
    assert whole["status"] == "ok", whole.get("error_message")
    assert np.isfinite(whole["window_spearman"])
