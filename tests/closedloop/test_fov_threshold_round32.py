"""Round 32 (issue 27): a field whose Strehl ratio sits exactly at the threshold.

Reference: DESIGN.md's rule, the corrected field is where the time-averaged SR is
*above* the threshold (SR > 0.3), so a field at exactly the threshold has area 0 and a
field a hair above it is the whole square (d = 2 sqrt(A / pi)). Before the fix the
bilinear interpolation of a constant map at the threshold rounded up at some points
and reported 0.785' for 60" x 60" at SR = threshold.
"""

import math

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
from closedloop.result import SimulationResult


def _result(variance: float, n_points: int = 9) -> SimulationResult:
    config = SimulationConfig(
        telescope=TelescopeConfig(diameter=1.0, n_pixels=8),
        layers=(LayerConfig(altitude=0.0, d_over_r0=5.0, wind_speed=10.0),),
        dms=(DMConfig(altitude=0.0, n_modes=2),),
        wfss=(WFSConfig(altitude=0.0, field_of_view=0.0, n_subapertures=2, field_samples=1),),
        loop=LoopConfig(time_step=1e-3, integration_time=1e-3, delay=5e-4),
        field=FieldConfig(size=60.0, n_points=n_points))
    n_dir = n_points ** 2
    return SimulationResult(config=config, seed=0, predictor="none",
                            times=(np.arange(12) + 1) * 1e-3, directions=np.zeros((n_dir, 2)),
                            residual_variance=np.full((12, n_dir), variance), elapsed=0.1,
                            version="test")


@pytest.mark.parametrize("n_points", [3, 9, 17])
def test_a_field_exactly_at_the_threshold_has_no_corrected_area(n_points):
    r = _result(1.2, n_points)
    level = float(r.strehl_map(start=0)[0, 0])  # the SR every direction holds
    assert r.corrected_fov_diameter(level, start=0) == 0.0
    below = float(np.nextafter(level, 0.0))
    assert r.corrected_fov_diameter(below, start=0) == pytest.approx(
        2 * math.sqrt(60.0 ** 2 / math.pi) / 60.0, rel=1e-12)
