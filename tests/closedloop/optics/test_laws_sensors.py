"""The sensors' model-error variances (the MAP reconstructor's N) against Noll's tables.

References (typed from Noll 1976, JOSA 66, 207, not computed by the code under test):
- the ideal sensor: the phase beyond the DM's Zernikes Z2..Z_J is Noll's residual
  Delta_J (D / r0)^(5/3); Table IV gives Delta_21 = 0.0208 and Delta_10 = 0.0401, summed
  over the layers. Noll's printed values sit 0.2-0.3 % below the exact integrals (his
  Delta_1 = 1.0299 against the exact 1.0324) and have three significant figures: the
  tolerance is 0.5 %;
- the geometric Shack-Hartmann: ``model_error`` times the slope variance of a disc of
  the pitch d, ``16 * 0.449 (d / r0)^(5/3) / d^2`` (Noll's tilt variance 0.449
  (d/r0)^(5/3) rad^2 per tilt coefficient; Z2 = 2 (r / R) cos t, so the slope is
  4 a2 / d), summed over the layers.
"""

from __future__ import annotations

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
from closedloop.model import LoopModel

NOLL_DELTA = {10: 0.0401, 21: 0.0208}
NOLL_TILT = 0.449


def _config(kind, n_modes):
    return SimulationConfig(
        name="sensors",
        telescope=TelescopeConfig(diameter=4.0, n_pixels=32),
        layers=(LayerConfig(altitude=0.0, d_over_r0=10.0, wind_speed=0.0),
                LayerConfig(altitude=0.0, d_over_r0=5.0, wind_speed=0.0)),
        dms=(DMConfig(altitude=0.0, n_modes=n_modes),),
        wfss=(WFSConfig(altitude=0.0, field_of_view=0.0, kind=kind, n_subapertures=8,
                        noise=0.0, field_samples=1),),
        loop=LoopConfig(time_step=1e-3, integration_time=1e-3, delay=0.0, gain=0.5),
        field=FieldConfig(size=0.0, n_points=1))


@pytest.mark.parametrize("n_modes", [9, 20])
def test_ideal_sensor_model_error_is_nolls_residual(n_modes):
    cfg = _config("ideal", n_modes)
    w = LoopModel(cfg).wfss[0]
    j_max = n_modes + 1  # Z2 .. Z_{n_modes + 1}
    r0s = [4.0 / 10.0, 4.0 / 5.0]
    expected = NOLL_DELTA[j_max] * sum((4.0 / r0) ** (5 / 3) for r0 in r0s)
    assert w.model_error_variance(r0s, 0.3) == pytest.approx(expected, rel=5e-3)


def test_shack_hartmann_model_error_is_the_subaperture_tilt_variance():
    cfg = _config("shack_hartmann", 20)
    w = LoopModel(cfg).wfss[0]
    d = 4.0 / 8
    r0s = [0.4, 0.8]
    expected = 0.3 * 16 * NOLL_TILT * sum((d / r0) ** (5 / 3) for r0 in r0s) / d ** 2
    assert w.model_error_variance(r0s, 0.3) == pytest.approx(expected, rel=1e-12)
    assert w.pitch == pytest.approx(d, rel=1e-15)
    assert math.isfinite(w.model_error_variance(r0s, 0.0)) and (
        w.model_error_variance(r0s, 0.0) == 0.0)
