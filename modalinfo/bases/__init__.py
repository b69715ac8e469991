"""Modal bases of the pupil: Zernike, K-L (theoretical, empirical, DM-space), actuator IFs."""

from modalinfo.bases.basis import ModalBasis
from modalinfo.bases.dm_kl import DMKLBasis, dm_kl_modes, von_karman_structure_function
from modalinfo.bases.identify import ZernikeIdentification, identify_zernike
from modalinfo.bases.image_basis import MaskedPupil, basis_from_images, pupil_from_mask
from modalinfo.bases.indexing import (
    ansi_to_noll,
    ansi_to_zernike,
    fringe_to_noll,
    fringe_to_zernike,
    noll_to_ansi,
    noll_to_fringe,
    noll_to_zernike,
    parse_modes,
    zernike_to_ansi,
    zernike_to_fringe,
    zernike_to_noll,
)
from modalinfo.bases.influence import InfluenceFunctions
from modalinfo.bases.kl import KLBasis, default_zernike_modes
from modalinfo.bases.pupil import Pupil
from modalinfo.bases.turbulence import (
    noll_residual_variance,
    zernike_covariance,
    zernike_variance,
)
from modalinfo.bases.zernike import (
    ZernikeBasis,
    zernike_matrix,
    zernike_polynomial,
    zernike_radial,
)

__all__ = [
    "Pupil",
    "ModalBasis",
    "MaskedPupil",
    "basis_from_images",
    "pupil_from_mask",
    "identify_zernike",
    "ZernikeIdentification",
    "ZernikeBasis",
    "KLBasis",
    "InfluenceFunctions",
    "DMKLBasis",
    "dm_kl_modes",
    "von_karman_structure_function",
    "default_zernike_modes",
    "zernike_radial",
    "zernike_polynomial",
    "zernike_matrix",
    "noll_to_zernike",
    "zernike_to_noll",
    "ansi_to_zernike",
    "zernike_to_ansi",
    "fringe_to_zernike",
    "zernike_to_fringe",
    "noll_to_ansi",
    "ansi_to_noll",
    "noll_to_fringe",
    "fringe_to_noll",
    "parse_modes",
    "zernike_covariance",
    "zernike_variance",
    "noll_residual_variance",
]
