"""``order_modes`` on a log that must raise no calibration event, and numpy's variance order.

One copy for the calibration-event tests (fix53-a's AR(1) logs, fix55-b's simulator
POLs). Reference: numpy's mean squares of the coefficients, ranked largest first with a
stable sort, for the ``"variance"`` order (the pooled numbers are those of the log).
"""

from __future__ import annotations

import warnings

import numpy as np

from modalinfo.ordering import order_modes
from modalinfo.telemetry import CalibrationEventWarning


def silent_order(log, basis, method: str = "variance"):
    """``order_modes(log, basis, method)`` with a ``CalibrationEventWarning`` an error."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", CalibrationEventWarning)
        return order_modes(log, basis, method)


def mean_square_order(c: np.ndarray, modes: list[int]) -> list[str]:
    """Labels ``Z<j>`` of the columns of ``c`` (T, M), largest numpy mean square first."""
    ms = np.mean(c * c, axis=0)
    return [f"Z{modes[i]}" for i in np.argsort(-ms, kind="stable")]
