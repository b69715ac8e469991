"""Layer wind directions in the AOT export follow the AOT standard's convention.

References: the AOT definition as ``aotpy`` documents it
(``AtmosphericParameters.layers_wind_direction``: "0 deg being North, increasing
eastward"), read as the meteorological from-direction, with the simulator's grid taken
as a map seen from above (+x = East, +y = North); hand-computed cases (wind to +x, i.e.
to the East, blows from the West: 270 deg) and a second implementation written here (the
bearing ``atan2(east, north)`` of the from-vector ``-(cos a, sin a)``); the round trip
through a FITS file read back by ``aotpy.AOSystem.read_from_file``.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

aotpy = pytest.importorskip("aotpy")

from closedloop.aot import (  # noqa: E402
    CLOSEDLOOP_KEY,
    aot_wind_direction,
    export_aot,
    wind_direction_from_aot,
)
from closedloop.config import (  # noqa: E402
    DMConfig,
    FieldConfig,
    LayerConfig,
    LoopConfig,
    SimulationConfig,
    TelescopeConfig,
    WFSConfig,
)
from closedloop.simulation import simulate  # noqa: E402
from modalinfo.io import load  # noqa: E402


def _bearing_from(direction_deg) -> np.ndarray:
    """AOT azimuth [deg] the wind comes from, for motion at ``a`` deg from +x (East) to +y."""
    a = np.radians(np.asarray(direction_deg, dtype=float))
    east, north = -np.cos(a), -np.sin(a)  # the from-vector
    return np.degrees(np.arctan2(east, north)) % 360.0


def _angle_gap(x, y) -> np.ndarray:
    """Smallest absolute difference of two angles [deg] (so 359.999... and 0 agree)."""
    d = (np.asarray(x) - np.asarray(y)) % 360.0
    return np.minimum(d, 360.0 - d)


@pytest.mark.parametrize("ours,aot", [
    (0.0, 270.0),     # blows to +x = East: from the West
    (90.0, 180.0),    # to +y = North: from the South
    (180.0, 90.0),    # to the West: from the East
    (270.0, 0.0),     # to the South: from the North
    (45.0, 225.0),    # to the North-East: from the South-West
    (-90.0, 0.0),     # any real angle: -90 is 270
    (360.0, 270.0),
    (720.0 + 30.0, 240.0),
])
def test_hand_computed_cases(ours, aot):
    assert float(aot_wind_direction(ours)) == pytest.approx(aot, abs=1e-12)
    assert float(wind_direction_from_aot(aot)) == pytest.approx(ours % 360.0, abs=1e-12)


def test_conversion_matches_the_bearing_of_the_from_vector_and_inverts():
    a = np.random.default_rng(0).uniform(-720.0, 720.0, 500)
    b = aot_wind_direction(a)
    assert np.all((b >= 0.0) & (b < 360.0))
    assert _angle_gap(b, _bearing_from(a)).max() < 1e-9
    assert _angle_gap(wind_direction_from_aot(b), a).max() < 1e-9
    back = wind_direction_from_aot(b)
    assert np.all((back >= 0.0) & (back < 360.0))


def test_the_floats_next_to_270_stay_below_360():
    # np.mod(x, 360) rounds up to 360 for x within half an ulp of 360 (2.8e-14) below a
    # multiple of 360; 270 - a for the float64 a nearest 270 + 360 k is 0 or one ulp of a
    # away (5.7e-14 and more), never there. (270 + 1e-14 is 270.0 itself in float64.)
    assert 270.0 + 1e-14 == 270.0
    for k in (-3, -1, 0, 1, 2, 10):
        centre = 270.0 + 360.0 * k
        for a in (np.nextafter(centre, -np.inf), centre, np.nextafter(centre, np.inf)):
            for convert in (aot_wind_direction, wind_direction_from_aot):
                assert 0.0 <= float(convert(a)) < 360.0, (convert.__name__, repr(a))
    # just past 270 (to the South, a hair East of it): from the North, one ulp of 270
    # short of 360, the float64 below 360, not 360 and not 0
    up = np.nextafter(270.0, np.inf)
    assert float(aot_wind_direction(up)) == np.nextafter(360.0, 0.0) == 360.0 - (up - 270.0)
    assert float(wind_direction_from_aot(up)) == np.nextafter(360.0, 0.0)


@pytest.mark.parametrize("bad", [np.nan, np.inf, [0.0, np.nan]])
def test_non_finite_directions_are_refused(bad):
    with pytest.raises(ValueError, match="`direction` must be finite"):
        aot_wind_direction(bad)
    with pytest.raises(ValueError, match="`aot_direction` must be finite"):
        wind_direction_from_aot(bad)


def test_round_trip_through_aotpy(tmp_path):
    # a small zonal system (ideal sensor, ideal DM) with three layers blowing in different
    # directions; the export's identity reconstructor is not written
    directions = (0.0, 117.0, 250.0)
    cfg = SimulationConfig(
        name="wind",
        telescope=TelescopeConfig(diameter=4.0, n_pixels=16),
        layers=tuple(LayerConfig(altitude=h, d_over_r0=5.0, wind_speed=8.0, wind_direction=d)
                     for h, d in zip((0.0, 3000.0, 8000.0), directions, strict=True)),
        dms=(DMConfig(altitude=0.0, kind="ideal"),),
        wfss=(WFSConfig(altitude=0.0, field_of_view=0.0, kind="ideal", field_samples=1),),
        loop=LoopConfig(time_step=1e-3, integration_time=1e-3, delay=0.0, gain=0.5),
        field=FieldConfig(size=0.0, n_points=1))
    run = simulate(cfg, 0.005, seed=2, progress=False)
    path = export_aot(run, tmp_path / "wind.fits")
    system = aotpy.AOSystem.read_from_file(path)
    (atm,) = system.atmosphere_params
    written = np.asarray(atm.layers_wind_direction.data, dtype=float).ravel()
    np.testing.assert_allclose(written, [270.0, 153.0, 20.0], rtol=0, atol=1e-12)
    assert _angle_gap(written, _bearing_from(directions)).max() < 1e-9
    np.testing.assert_allclose(wind_direction_from_aot(written), directions, rtol=0, atol=1e-12)
    (loop,) = [lp for lp in system.loops if lp.uid == "dm0"]
    assert loop.measurements_to_modes is None  # the identity of a zonal loop, not written
    np.testing.assert_array_equal(load(path, loop="dm0").coeffs, run.logs["dm0.residual"].coeffs)
    card = next(m.value for m in system.metadata if m.key == CLOSEDLOOP_KEY)
    notes = json.loads(card)
    assert notes["wind_direction"].startswith("AOT LAYERS_WIND_DIRECTION: deg, 0 = North")
