"""A saved result's arrays name their units for h5py (adversarial round 48 PART b, O52).

Reference: SimulationResult's and ErrorBudget's documented units (times [s], directions
[arcsec], residual variance and budget terms [rad^2 at the science wavelength],
snapshots [rad at it], slopes [rad/m] at r0_wavelength, as the AOT export's MI_CLOOP card
states) read back with h5py, not with ``SimulationResult.load``. Before, only the logs
carried a ``units`` attribute: ``residual_variance`` (rad^2 at 630 nm for kaos) sat
beside logs in rad at 500 nm with nothing to tell them apart.
"""

from __future__ import annotations

import h5py
import pytest

from closedloop.result import SimulationResult

from .test_result_views import _full_result


def test_every_array_names_its_units(tmp_path):
    r = _full_result()
    path = r.save(tmp_path / "run.h5")
    science, r0_wavelength = r.config.wavelength, r.config.r0_wavelength
    expected = {
        "times": ("s", None), "directions": ("arcsec", None),
        "residual_variance": ("rad^2", science), "snapshots": ("rad", science),
        "snapshot_directions": ("arcsec", None), "measurements/wfs0": ("rad/m", r0_wavelength),
        "budget/fitting": ("rad^2", science), "budget/measured": ("rad^2", science),
        "budget/directions": ("arcsec", None), "budget/frames": ("frame", None),
    }
    with h5py.File(path, "r") as f:
        for name, (units, wavelength) in expected.items():
            attrs = f[name].attrs
            assert attrs["units"] == units, name
            assert attrs.get("wavelength_m") == (None if wavelength is None
                                                 else pytest.approx(wavelength, rel=0)), name
    back = SimulationResult.load(path)  # the checksum still verifies
    assert back == r
