"""Mutual-information and entropy estimators for continuous 1-D samples.

Estimators: ``"kde"`` (Gaussian kernel following the data covariance, FFT on a
grid), ``"histogram"`` (plug-in with Miller-Madow), ``"ksg"`` (Kraskov et al. 2004)
and ``"gaussian"`` (-0.5 ln(1 - r^2)), each rank-based by default (normal scores or
equiprobable bins, :func:`copula_scores`), all behind :func:`mutual_information`,
:func:`entropy` and the reusable :class:`MutualInformation`. The default ``method=`` of
the MI, the conditional MI and the transfer entropy is ``"ksg"``
(``api.DEFAULT_METHOD``: the one estimator within 0.05 nats
or 10 % of the truth on every "Beyond Normal" task of at most 2 x 2 dimensions at
n = 1e4; benchmarks/RESULTS.md, "The KSG defaults"); the intervals and the
significance tests, which run the estimator once per resample, keep ``"histogram"``
(``api.RESAMPLING_METHOD``); the paper's orderings and
figures name theirs. Bootstrap confidence intervals and permutation tests for
autocorrelated telemetry in ``modalinfo.information.uncertainty``. Conditional MI of
multivariate samples (same four methods) in ``modalinfo.information.conditional``, transfer
entropy in ``modalinfo.information.transfer_entropy``, their surrogate tests and block-bootstrap
intervals in ``modalinfo.information.conditional_uncertainty``; greedy selection of a
forecast's inputs in ``modalinfo.information.selection``; the map of transfer entropy
between every pair of modes at every lag in ``modalinfo.information.flow``.

Each method is one :class:`MIMethod` record in one registry
(``modalinfo.information.methods``), registered by its own module; a new method is a
module that calls :func:`register_method` (docs/ARCHITECTURE.md).
"""

# the built-in methods, each registered by its own module on import
from modalinfo.information import gaussian, histogram, kde, ksg  # noqa: F401
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
)
from modalinfo.information.conditional_uncertainty import (
    conditional_mutual_information_ci,
    conditional_mutual_information_test,
)
from modalinfo.information.copula import copula_scores
from modalinfo.information.flow import TransferEntropyMap, transfer_entropy_map
from modalinfo.information.methods import MIMethod, register_method, unregister_method
from modalinfo.information.resampling import optimal_block_length
from modalinfo.information.selection import InputSelection, SelectedInput, select_inputs
from modalinfo.information.transfer_entropy import transfer_entropy, transfer_entropy_variables
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
    "MIMethod",
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
    "register_method",
    "select_inputs",
    "transfer_entropy",
    "transfer_entropy_map",
    "transfer_entropy_variables",
    "unregister_method",
]
