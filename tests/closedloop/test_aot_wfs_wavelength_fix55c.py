"""The AOT export fills each wavefront sensor's wavelength (fix55-c).

The export left AOT's ``WavefrontSensor.wavelength`` empty: only the loops' ``MI_WAVEL``
card said the wavelength of the phase. Reference: the file read back with aotpy (the
standard's reader), against the config: a geometric sensor measures the phase in rad
at ``r0_wavelength`` (not the science ``wavelength``, set apart here), a correlating one
forms images at its photon budget's wavelength
(``closedloop.optics.photon_budget.PhotonBudget().wavelength``, the documented default).
"""

import dataclasses

import pytest

from closedloop import simulate
from closedloop.aot import export_aot
from closedloop.optics.photon_budget import PhotonBudget

from .conftest import correlating_config, correlating_sensor, tiny_actuator_config

aotpy = pytest.importorskip("aotpy")


def _sensors(path):
    return {w.uid: w for w in aotpy.AOSystem.read_from_file(str(path)).wavefront_sensors}


def test_a_geometric_sensor_says_r0_wavelength(tmp_path):
    cfg = dataclasses.replace(tiny_actuator_config(), wavelength=630e-9)
    out = export_aot(simulate(cfg, 0.004, seed=0), tmp_path / "geo.fits")
    sensors = _sensors(out)
    assert set(sensors) == {"wfs0"}
    assert sensors["wfs0"].wavelength == pytest.approx(cfg.r0_wavelength, rel=1e-15)


def test_a_correlating_sensor_says_its_imaging_wavelength(tmp_path):
    cfg = correlating_config("corr", [(0.0, 4.0)], [(0.0, 20)],
                             [correlating_sensor(0.0, 10.0, n_sub=4)])
    out = export_aot(simulate(cfg, 0.003, seed=0), tmp_path / "corr.fits")
    assert _sensors(out)["wfs0"].wavelength == pytest.approx(PhotonBudget().wavelength,
                                                             rel=1e-15)
