"""Mutual-information and entropy estimators for continuous 1-D samples.

Estimators: ``"kde"`` (Gaussian kernel following the data covariance, FFT on a
grid), ``"histogram"`` (plug-in with Miller-Madow), ``"ksg"`` (Kraskov et al. 2004)
and ``"gaussian"`` (-0.5 ln(1 - r^2)), all behind :func:`mutual_information`,
:func:`entropy` and the reusable :class:`MutualInformation`; bootstrap confidence
intervals and permutation tests for autocorrelated telemetry in
``modalinfo.information.uncertainty``.
"""

from modalinfo.information.api import (
    METHODS,
    UNITS,
    MutualInformation,
    entropy,
    mutual_information,
)
from modalinfo.information.uncertainty import (
    MIConfidenceResult,
    MIPermutationResult,
    mutual_information_ci,
    mutual_information_permutation_test,
    optimal_block_length,
)

__all__ = [
    "METHODS",
    "UNITS",
    "MIConfidenceResult",
    "MIPermutationResult",
    "MutualInformation",
    "entropy",
    "mutual_information",
    "mutual_information_ci",
    "mutual_information_permutation_test",
    "optimal_block_length",
]
