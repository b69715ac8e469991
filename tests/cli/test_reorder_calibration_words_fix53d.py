"""``modalinfo reorder``'s calibration-event warning in the command's words (fix53-d).

fix53-a's ``CalibrationEventWarning`` of ``order_modes`` ends with API advice ("log.select",
"quality=False"), which the command line has no spelling of; the command now says it in
its own words (a log cut at the event, ``--stability FRAMES``).

Reference: a planted event (Z5 + 3 sd from frame 12,000 of a stationary AR(1) log drawn
with ``scipy.signal.lfilter``; fix53-a's L04 case), named by mode and frame.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.cli import main
from modalinfo.telemetry import CalibrationEventWarning


def test_reorder_names_its_own_options_for_a_calibration_event(tmp_path):
    rng = np.random.default_rng(53)
    e = rng.standard_normal((22000, 8)) * np.sqrt(1.0 - 0.81)
    c = lfilter([1.0], [1.0, -0.9], e, axis=0)[2000:] * np.linspace(1.0, 0.3, 8)
    c[12000:, 3] += 3.0 * c[:, 3].std()      # Z5 (column 4 of Z2-Z9) + 3 sd
    path = tmp_path / "log.npy"
    np.save(path, c)
    with pytest.warns(CalibrationEventWarning) as rec:
        code = main(["reorder", str(path), "--in-modes", "2-9", "--rate", "2000",
                     "--method", "variance", "--pupil-pixels", "16"])
    assert code == 0
    msgs = [str(w.message) for w in rec if isinstance(w.message, CalibrationEventWarning)]
    assert len(msgs) == 1, msgs
    assert "Z5" in msgs[0] and "--stability FRAMES" in msgs[0]
    assert "quality=False" not in msgs[0] and "log.select" not in msgs[0]


def test_reorder_runs_the_quality_pass_once(tmp_path, monkeypatch):
    # --outliers' pass and order_modes' were two full passes over the log (fix53-d): the
    # command's report is handed to order_modes where the coefficients are the log's
    import modalinfo.telemetry.quality as quality

    calls = []
    real = quality.assess_quality
    monkeypatch.setattr(quality, "assess_quality",
                        lambda *a, **k: calls.append(1) or real(*a, **k))
    rng = np.random.default_rng(7)
    c = lfilter([1.0], [1.0, -0.9], rng.standard_normal((4000, 4)), axis=0)
    path = tmp_path / "clean.npy"
    np.save(path, c)
    assert main(["reorder", str(path), "--in-modes", "4-7", "--rate", "1000",
                 "--method", "variance", "--pupil-pixels", "16"]) == 0
    assert len(calls) == 1
