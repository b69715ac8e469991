"""0-d NumPy arrays as the solar optics' numbers (left25-api, issue 27).

Reference, from outside the code: a 0-d array holds one number (NumPy's
``np.array(x)[()]`` is ``x``), so each call with ``np.array(x)`` must give what the call
with the Python float ``x`` gives, and a 0-d bool array is refused as ``True`` is.
Before, ``solar_spectral_radiance``, ``PhotonBudget.unattenuated_electrons`` and
``granulation_contrast`` refused ``np.array(6e-7)`` as "not in range" while
``modalinfo``'s own checks take it (``validation.as_scalar``). Since left26-twins these
numbers pass ``validation.check_real``, whose refusal of a non-real is a TypeError.
"""

import numpy as np
import pytest

from closedloop.optics.granulation import granulation_contrast
from closedloop.optics.photon_budget import PhotonBudget, solar_spectral_radiance


def test_radiance_takes_0d_arrays():
    assert solar_spectral_radiance(np.array(6e-7)) == solar_spectral_radiance(6e-7)
    assert solar_spectral_radiance(6e-7, np.array(5800.0)) == solar_spectral_radiance(
        6e-7, 5800.0)
    with pytest.raises(TypeError, match="`wavelength` must be a real number"):
        solar_spectral_radiance(np.array(True))
    with pytest.raises(TypeError, match="`brightness_temperature` must be a real number"):
        solar_spectral_radiance(6e-7, np.array(5800 + 0j))


def test_photon_budget_takes_0d_arrays():
    budget = PhotonBudget()
    assert budget.unattenuated_electrons(np.array(0.04), np.array(0.5)) == \
        budget.unattenuated_electrons(0.04, 0.5)
    with pytest.raises(TypeError, match="`pixel_scale_arcsec` must be a real number"):
        budget.unattenuated_electrons(0.04, np.array(True))


def test_granulation_contrast_takes_0d_arrays():
    assert granulation_contrast(np.array(5e-7)) == granulation_contrast(5e-7)
    with pytest.raises(ValueError, match="`wavelength`"):
        granulation_contrast(np.array("5e-7"))
