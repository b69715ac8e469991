"""A field too wide for its sensor's altitude is refused naming the meta-pupil law (round 31 a).

Reference, from outside the code: the meta-pupil diameter of a sensor conjugated to
altitude h over a field theta, ``D + 2 h tan(theta / 2)`` (Ragazzoni, Farinato &
Marchetti 2000), computed here with ``math``. A 600" field at 20 km makes a 62.2-m
meta-pupil: 8 subapertures of 7.8 m, none half lit by a 4-m pupil from any direction.
Before: the refusal named only ``telescope.obscuration = 0`` (wrong form).
"""

import dataclasses
import math

import pytest

from closedloop.config import (
    DMConfig,
    FieldConfig,
    LayerConfig,
    LoopConfig,
    SimulationConfig,
    TelescopeConfig,
    WFSConfig,
)
from closedloop.simulation import LoopModel

ARCSEC = math.pi / 180.0 / 3600.0


def _config(altitude: float, field: float, n_modes: int = 20) -> SimulationConfig:
    return SimulationConfig(
        name="metapupil",
        telescope=TelescopeConfig(diameter=4.0, n_pixels=64),
        layers=(LayerConfig(altitude=0.0, d_over_r0=10.0, wind_speed=0.0),),
        dms=(DMConfig(altitude=altitude, n_modes=n_modes, kind="zernike"),),
        wfss=(WFSConfig(altitude=altitude, field_of_view=field, kind="shack_hartmann",
                        noise=0.0, n_subapertures=8, field_samples=3),),
        loop=LoopConfig(time_step=1e-3, integration_time=1e-3, delay=0.0, gain=0.5),
        field=FieldConfig(size=0.0, n_points=1), wavelength=500e-9, r0_wavelength=500e-9,
    )


def test_a_field_too_wide_for_its_altitude_names_the_meta_pupil():
    d_wfs = 4.0 + 2.0 * 20e3 * math.tan(300.0 * ARCSEC)  # 62.18 m
    with pytest.raises(ValueError) as err:
        LoopModel(_config(20e3, 600.0))
    text = str(err.value)
    assert f"meta-pupil of {d_wfs:.4g} m" in text
    assert f"a pitch of {d_wfs / 8:.4g} m" in text
    assert "field_of_view = 600 arcsec" in text and "altitude = 20000 m" in text
    assert "a smaller field or a lower altitude" in text
    assert "\n" not in text


def test_the_obscuration_reading_is_unchanged_on_the_pupil():
    cfg = _config(0.0, 0.0, n_modes=2)
    cfg = dataclasses.replace(cfg, telescope=dataclasses.replace(cfg.telescope,
                                                                   obscuration=0.95))
    with pytest.raises(ValueError, match=r"obscuration = 0.95\): the sensor would measure "
                                         r"nothing; use more subapertures, a smaller "
                                         r"obscuration$"):
        LoopModel(cfg)
