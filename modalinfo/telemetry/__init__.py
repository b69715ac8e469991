"""Telemetry logs of modal coefficients: ``ModalLog``, units and one-pass summaries.

``modalinfo.telemetry.synthetic`` holds the synthetic open/closed-loop logs
(``open_loop_log``, ``closed_loop_log``, ``kaos_like``).
"""

from modalinfo.telemetry import synthetic  # imports telemetry.log itself: order-free
from modalinfo.telemetry.log import (
    CONVENTIONS,
    NONFINITE_POLICIES,
    LogSummary,
    ModalLog,
    summarize,
)
from modalinfo.telemetry.units import (
    UNITS,
    peak_normalized_from_rms,
    rms_from_peak_normalized,
    unit_scale,
    zernike_rms_normalization,
)

__all__ = [
    "CONVENTIONS",
    "NONFINITE_POLICIES",
    "UNITS",
    "LogSummary",
    "ModalLog",
    "summarize",
    "synthetic",
    "unit_scale",
    "zernike_rms_normalization",
    "rms_from_peak_normalized",
    "peak_normalized_from_rms",
]
