"""Telemetry logs of modal coefficients: ``ModalLog``, units and one-pass summaries.

``modalinfo.telemetry.synthetic`` (synthetic open/closed-loop logs) is written
separately; it is imported below only when present.
"""

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
    "unit_scale",
    "zernike_rms_normalization",
    "rms_from_peak_normalized",
    "peak_normalized_from_rms",
]
