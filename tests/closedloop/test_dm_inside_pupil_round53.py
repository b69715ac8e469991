"""A DM disc smaller than the pupil is named when the config is built (round 53 PART a).

Reference: geometry. Every direction's beam has the telescope's diameter on a mirror at
any altitude and the mirror is flat outside its disc (``DMConfig.diameter``), so a disc of
0.665 m under a 0.7 m pupil leaves the outer 2.5 % of the radius uncorrected: measured
before round 53, a 0.3 s SCAO run at D/r0 7 ran "closed" at a residual of 6.5 rad^2
against 0.34 rad^2 with the disc matched, without a word. A disc equal to or larger than
the pupil, or sized by the WFS (None), is not warned.
"""

import warnings

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


def _config(dm_diameter):
    return SimulationConfig(
        telescope=TelescopeConfig(diameter=0.7, n_pixels=56),
        layers=(LayerConfig(altitude=0.0, d_over_r0=7.0, wind_speed=5.0),),
        dms=(DMConfig(altitude=0.0, n_modes=20, diameter=dm_diameter),),
        wfss=(WFSConfig(altitude=0.0, field_of_view=10.0, n_subapertures=7),),
        loop=LoopConfig(time_step=5e-4, integration_time=5e-4, delay=5e-4, gain=0.4664),
        field=FieldConfig(size=10.0, n_points=1))


def test_dm_disc_inside_the_pupil_warns():
    with pytest.warns(UserWarning, match=r"`dms\[0\].diameter` = 0.665 m is smaller than "
                      r"telescope.diameter = 0.7 m.*outer 2.5 % of radius"):
        _config(0.665)


@pytest.mark.parametrize("diameter", [None, 0.7, 0.735])
def test_dm_disc_covering_the_pupil_is_quiet(diameter):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _config(diameter)
