"""Ordering of modal bases by mutual information, and fitting-error curves.

The paper's Section 2 (Stangalini et al., LOST MCAO): reorder a Zernike or K-L basis
by the information each mode adds about the full reconstruction, and compare orderings
by their fitting error dPhi(n) against the standard, variance and data-PCA orders.
"""

from modalinfo.ordering.fitting_error import FittingErrorResult, fitting_error
from modalinfo.ordering.orderings import (
    METHODS,
    SpatialEnvelopeWarning,
    envelope_information,
    mi_along_order,
    order_modes,
    sample_contributions,
)
from modalinfo.ordering.result import OrderingResult
from modalinfo.ordering.stability import StabilityResult, ordering_stability, rank_agreement

__all__ = [
    "METHODS",
    "FittingErrorResult",
    "OrderingResult",
    "SpatialEnvelopeWarning",
    "StabilityResult",
    "envelope_information",
    "fitting_error",
    "mi_along_order",
    "order_modes",
    "ordering_stability",
    "rank_agreement",
    "sample_contributions",
]
