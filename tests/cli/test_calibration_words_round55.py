"""``fitting-error`` and ``batch`` say the calibration event's advice in a command's words.

Round 55 PART b, C52 / C54 / C59 / C60: ``order_modes``' ``CalibrationEventWarning``
ended, on ``modalinfo fitting-error`` and ``modalinfo batch``, with the API's advice
"(log.select), or pass quality=False", which no command has; ``reorder`` said it in its
own words since fix53-d. The warning now carries a ``cli_text`` (what every command
prints, ``modalinfo.common.startup.command_line_text``); a Python caller keeps the API's.

Reference: a planted event (Z5 + 3 sd from frame 12,000 of a stationary AR(1) log drawn
with ``scipy.signal.lfilter``; fix53-d's case), named by mode.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.cli import main
from modalinfo.common.startup import command_line_text
from modalinfo.ordering.orderings import CALIBRATION_ADVICE
from modalinfo.telemetry import CalibrationEventWarning


@pytest.fixture(scope="module")
def stepped(tmp_path_factory):
    rng = np.random.default_rng(53)
    e = rng.standard_normal((22000, 8)) * np.sqrt(1.0 - 0.81)
    c = lfilter([1.0], [1.0, -0.9], e, axis=0)[2000:] * np.linspace(1.0, 0.3, 8)
    c[12000:, 3] += 3.0 * c[:, 3].std()      # Z5 (column 4 of Z2-Z9) + 3 sd
    path = tmp_path_factory.mktemp("cal") / "log.npy"
    np.save(path, c)
    return path


def _events(rec):
    return [w.message for w in rec if isinstance(w.message, CalibrationEventWarning)]


def test_fitting_error_prints_command_words(stepped):
    with pytest.warns(CalibrationEventWarning) as rec:
        code = main(["fitting-error", str(stepped), "--in-modes", "2-9", "--rate", "2000",
                     "--orderings", "zernike:variance", "--pupil-pixels", "16"])
    assert code == 0
    events = _events(rec)
    assert len(events) == 1
    printed = command_line_text(events[0])
    assert "Z5" in printed and "a log cut at the event" in printed
    assert "quality=False" not in printed and "log.select" not in printed
    assert "(assess_quality)" not in printed
    assert str(events[0]).endswith(CALIBRATION_ADVICE)  # the Python caller's words kept


def test_order_modes_keeps_api_words_for_python(stepped):
    from modalinfo.ordering import order_modes
    from modalinfo.ordering.compare import basis_for_log
    from modalinfo.telemetry import ModalLog

    log = ModalLog(np.load(stepped), rate=2000.0, modes=list(range(2, 10)))
    with pytest.warns(CalibrationEventWarning, match=r"pass quality=False"):
        order_modes(log, basis_for_log("zernike", log, n_pixels=16), "variance",
                    n_resamples=0)
