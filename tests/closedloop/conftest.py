"""Fixtures shared by the closedloop tests (reference: none; configs only)."""

import dataclasses

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
from closedloop.optics.actuator_dm import valid_actuators


@pytest.fixture(scope="module")
def tiny_actuator_loop() -> SimulationConfig:
    """table1 scaled down: one ground layer, 8 x 8 subapertures, 9 x 9 actuators, all modes."""
    cfg = SimulationConfig(
        name="tiny-actuators",
        telescope=TelescopeConfig(diameter=4.0, n_pixels=32),
        layers=(LayerConfig(altitude=0.0, d_over_r0=16.0, wind_speed=10.0),),
        dms=(DMConfig(altitude=0.0, n_modes=10, kind="actuators"),),
        wfss=(WFSConfig(altitude=0.0, field_of_view=0.0, n_subapertures=8, noise=0.0, dm=0),),
        loop=LoopConfig(time_step=1e-3, integration_time=1e-3, delay=0.5e-3, gain=0.5),
        field=FieldConfig(size=0.0, n_points=1),
        wavelength=500e-9, r0_wavelength=500e-9, seed=0)
    return cfg.replace(dms=(dataclasses.replace(cfg.dms[0],
                                                n_modes=valid_actuators(cfg, 0) - 1),))
