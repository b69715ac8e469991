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
  4 a2 / d), summed over the layers, per slope over its subaperture's lit fraction
  (computed here on a fine grid against the pupil disc, ``tests/closedloop/_geometry``):
  a pupil-edge subaperture averages the small scales over less area.
"""

from __future__ import annotations

import numpy as np
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

from .._geometry import lit_fractions

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
    # each slope's own: a fully lit subaperture's the disc's tilt variance, a pupil-edge
    # one's that over its lit fraction f (the tilt averaged over f of the area)
    _, lit = lit_fractions(4.0, 0.0, 1.0, 2, 8, 2.0, 200)
    f = np.tile(lit[0][w.valid_subapertures], 2)
    got = np.broadcast_to(w.model_error_variance(r0s, 0.3), f.shape)
    assert (f == 1.0).sum() >= 8 and f.min() < 0.75
    np.testing.assert_allclose(got[f == 1.0], expected, rtol=1e-12)
    # the sensor's lit area is its pixel pairs', off the disc's by up to ~0.1 of a
    # subaperture (tests/closedloop/test_lit_share_left31.py): per slope 25 %, mean 10 %
    ratio = got[f < 1.0] * f[f < 1.0] / expected
    np.testing.assert_allclose(ratio, 1.0, rtol=0.25)
    assert abs(ratio.mean() - 1.0) < 0.1, ratio.mean()
    assert w.pitch == pytest.approx(d, rel=1e-15)
    assert np.all(np.asarray(w.model_error_variance(r0s, 0.0)) == 0.0)
