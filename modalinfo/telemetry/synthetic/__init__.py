"""Synthetic open-loop and closed-loop Zernike telemetry with known statistics.

The test and demonstration data of the package, in three modules:

- ``spectra``: seeded open-loop series whose
  zero-lag covariance and temporal spectra follow turbulence theory (``Layer``,
  ``open_loop_log``, ``open_loop_psd``; what is exact and what approximate is
  documented there);
- ``closed_loop``: the residuals of a modal
  integrator loop run on them (``closed_loop_log``, ``closed_loop_simulation``); its
  servo model (rejection transfer function, bandwidths, stability) is
  :mod:`modalinfo.servo`;
- ``presets``: ``kaos_like``, a KAOS-like log.
"""

from modalinfo.telemetry.synthetic.closed_loop import (
    ClosedLoopResult,
    closed_loop_log,
    closed_loop_simulation,
)
from modalinfo.telemetry.synthetic.presets import KAOS_LIKE_DEFAULTS, kaos_like
from modalinfo.telemetry.synthetic.spectra import Layer, open_loop_log, open_loop_psd

__all__ = [
    "Layer",
    "ClosedLoopResult",
    "open_loop_log",
    "open_loop_psd",
    "closed_loop_log",
    "closed_loop_simulation",
    "kaos_like",
    "KAOS_LIKE_DEFAULTS",
]
