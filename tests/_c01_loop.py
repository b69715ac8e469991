"""Round 53 PART a's C01 loop: one copy of the small closed loop several tests simulate.

For tests/ordering/test_calibration_simulator_fix55b.py and
tests/closedloop/test_bare_predictor_scale_fix56b.py: a 0.7 m telescope, one Kolmogorov
layer at D/r0 7 in frozen flow (5 m/s), 27 modes, a 7 x 7 Shack-Hartmann, 2 kHz with one
frame of delay and gain 0.4664 (the integrator's margin).
"""

from __future__ import annotations

from closedloop import SimulationConfig
from closedloop.config import (
    DMConfig,
    FieldConfig,
    LayerConfig,
    LoopConfig,
    TelescopeConfig,
    WFSConfig,
)


def c01_config(seed: int, noise: float = 0.0, name: str = "c01") -> SimulationConfig:
    """The C01 loop at ``seed`` with WFS ``noise`` [arcsec]."""
    return SimulationConfig(
        telescope=TelescopeConfig(diameter=0.7, n_pixels=56, zenith_angle=0.0),
        layers=(LayerConfig(altitude=0.0, d_over_r0=7.0, wind_speed=5.0,
                            wind_direction=0.0),),
        dms=(DMConfig(altitude=0.0, n_modes=27),),
        wfss=(WFSConfig(altitude=0.0, field_of_view=10.0, n_subapertures=7, noise=noise,
                        field_samples=3),),
        loop=LoopConfig(time_step=5e-4, integration_time=5e-4, delay=5e-4, gain=0.4664),
        field=FieldConfig(size=10.0, n_points=1), seed=seed, name=name)
