"""Mutual-information and entropy estimators for continuous 1-D samples.

Estimators: ``"kde"`` (Gaussian kernel following the data covariance, FFT on a
grid), ``"histogram"`` (plug-in with Miller-Madow), ``"ksg"`` (Kraskov et al. 2004)
and ``"gaussian"`` (-0.5 ln(1 - r^2)), each rank-based by default (normal scores or
equiprobable bins, :func:`copula_scores`), all behind :func:`mutual_information`,
:func:`entropy` and the reusable :class:`MutualInformation`; bootstrap confidence
intervals and permutation tests for autocorrelated telemetry in
``modalinfo.information.uncertainty``. Conditional MI and transfer entropy of
multivariate samples (same four methods, surrogate tests and block-bootstrap
intervals) in ``modalinfo.information.conditional``; greedy selection of a
forecast's inputs in ``modalinfo.information.selection``; the map of transfer entropy
between every pair of modes at every lag in ``modalinfo.information.flow``.
"""

from modalinfo.information.api import (
    METHODS,
    UNITS,
    MutualInformation,
    entropy,
    mutual_information,
)
from modalinfo.information.conditional import (
    CMI_METHODS,
    BiasRuleWarning,
    bias_rule,
    conditional_mutual_information,
    conditional_mutual_information_ci,
    conditional_mutual_information_test,
    transfer_entropy,
    transfer_entropy_variables,
)
from modalinfo.information.copula import copula_scores
from modalinfo.information.flow import TransferEntropyMap, transfer_entropy_map
from modalinfo.information.resampling import optimal_block_length
from modalinfo.information.selection import InputSelection, SelectedInput, select_inputs
from modalinfo.information.uncertainty import (
    MIConfidenceResult,
    MIPermutationResult,
    mutual_information_ci,
    mutual_information_permutation_test,
)

__all__ = [
    "BiasRuleWarning",
    "CMI_METHODS",
    "METHODS",
    "InputSelection",
    "SelectedInput",
    "TransferEntropyMap",
    "UNITS",
    "MIConfidenceResult",
    "MIPermutationResult",
    "MutualInformation",
    "bias_rule",
    "conditional_mutual_information",
    "conditional_mutual_information_ci",
    "conditional_mutual_information_test",
    "copula_scores",
    "entropy",
    "mutual_information",
    "mutual_information_ci",
    "mutual_information_permutation_test",
    "optimal_block_length",
    "select_inputs",
    "transfer_entropy",
    "transfer_entropy_map",
    "transfer_entropy_variables",
]
