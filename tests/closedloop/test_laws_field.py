"""A WFS's field: its samples cover the field's disc, and a layer at altitude h is blurred.

References (computed in the test):
- geometry of the field samples: a hexagonal set whose outer ring touches the field's
  edge (every sample within F/2, the farthest at F/2), every point of the field's disc
  within one sample spacing of a sample, equal nearest-neighbour spacing (uniform
  density), centred, ``1 + 3 r (r - 1)`` samples for r rings;
- the blur: a WFS conjugated to 0 co-adding the field's directions theta_s sees a layer
  at altitude h read at u + h theta_s, so a sinusoidal layer cos(2 pi f x) is measured
  as T(f) cos(2 pi f x) with T(f) = mean_s cos(2 pi f h theta_s,x) (a second
  implementation of the hexagonal set, written here); for a uniform disc of diameter
  d = h F this is the Airy-like 2 J1(pi f d) / (pi f d), which the hexagonal set
  approximates (within 0.03 for f d <= 0.5 with four rings, computed here). The sample
  spacing is chosen so that every x-shift is a whole number of pixels, and the layer
  varies along x only: no interpolation enters.
"""

import math

import numpy as np
import pytest
from scipy import special

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

ARCSEC = math.pi / 648000.0
N_PIXELS = 32
DX = 4.0 / N_PIXELS
H = 10_000.0
RINGS = 4
# sample spacing a with a h = 2 dx: x-shifts (q + r/2) a h are whole pixels
SPACING = 2.0 * DX / H / ARCSEC
FIELD = 2.0 * (RINGS - 1) * SPACING  # arcsec, 30.9"


def hexagonal_set(field, rings):
    """The test's own hexagonal field samples [arcsec]: corners on the field's edge."""
    pts = []
    for q in range(-(rings - 1), rings):
        for r in range(-(rings - 1), rings):
            if max(abs(q), abs(r), abs(q + r)) <= rings - 1:
                pts.append((q + 0.5 * r, r * math.sqrt(3.0) / 2.0))
    return np.array(pts) * (field / 2.0) / (rings - 1)


def _config(kind, *, field=FIELD, rings=RINGS):
    dm = (DMConfig(altitude=0.0, kind="ideal") if kind == "ideal"
          else DMConfig(altitude=0.0, n_modes=14))
    return SimulationConfig(
        name="field",
        telescope=TelescopeConfig(diameter=4.0, n_pixels=N_PIXELS),
        layers=(LayerConfig(altitude=0.0, d_over_r0=10.0, wind_speed=0.0),
                LayerConfig(altitude=H, d_over_r0=3.0, wind_speed=0.0)),
        dms=(dm,),
        wfss=(WFSConfig(altitude=0.0, field_of_view=field, kind=kind, n_subapertures=8,
                        field_samples=rings),),
        loop=LoopConfig(), field=FieldConfig(size=0.0, n_points=1),
        wavelength=500e-9, r0_wavelength=500e-9)


def _sinusoid_maps(model, plane, frequency):
    g = model.geometry
    maps = [np.zeros((p.n, p.n)) for p in g.planes]
    x = g.plane_coords(plane)
    maps[plane] = np.tile(np.cos(2.0 * math.pi * frequency * x), (g.planes[plane].n, 1))
    return maps


@pytest.mark.parametrize("field,rings", [(FIELD, RINGS), (60.0, 3), (20.0, 5), (10.0, 2)])
def test_field_samples_cover_the_field_disc_uniformly(field, rings):
    model = LoopModel(_config("ideal", field=field, rings=rings))
    samples = np.asarray(model.wfss[0].samples)
    assert samples.shape == (1 + 3 * rings * (rings - 1), 2)
    radius = np.hypot(samples[:, 0], samples[:, 1])
    spacing = field / 2.0 / (rings - 1)
    assert radius.max() == pytest.approx(field / 2.0, rel=1e-12)  # reaches the edge
    np.testing.assert_allclose(samples.mean(axis=0), 0.0, atol=1e-12 * field)
    # uniform density: every sample's nearest neighbour at the same spacing
    d = np.hypot(*(samples[:, None, :] - samples[None, :, :]).transpose(2, 0, 1))
    np.fill_diagonal(d, np.inf)
    np.testing.assert_allclose(d.min(axis=1), spacing, rtol=1e-9)
    # coverage: every point of the field's disc within one spacing of a sample
    rng = np.random.default_rng(0)
    r = field / 2.0 * np.sqrt(rng.uniform(size=4000))
    t = rng.uniform(0, 2 * math.pi, size=4000)
    pts = np.column_stack([r * np.cos(t), r * np.sin(t)])
    gap = np.min(np.hypot(*(pts[:, None, :] - samples[None, :, :]).transpose(2, 0, 1)), axis=1)
    assert gap.max() <= spacing
    # the same set as the test's own construction (up to order)
    mine = hexagonal_set(field, rings)
    key = lambda p: np.lexsort((np.round(p[:, 0], 9), np.round(p[:, 1], 9)))  # noqa: E731
    np.testing.assert_allclose(samples[key(samples)], mine[key(mine)], atol=1e-12 * field)


def _transfer(frequency):
    theta_x = hexagonal_set(FIELD, RINGS)[:, 0] * ARCSEC
    return float(np.mean(np.cos(2.0 * math.pi * frequency * H * theta_x)))


def _airy(frequency):
    x = math.pi * frequency * H * FIELD * ARCSEC
    return 2.0 * special.j1(x) / x


@pytest.mark.parametrize("period_px,check_disc", [(48, True), (24, True), (12, False)])
def test_ideal_wfs_sees_a_high_layer_through_its_field_footprint(period_px, check_disc):
    model = LoopModel(_config("ideal"))
    g = model.geometry
    high = g.layer_plane[1]
    f = 1.0 / (period_px * DX)
    wfs = model.wfss[0]
    measured = wfs.forward(_sinusoid_maps(model, high, f))
    dm = model.dms[0]
    n = g.planes[dm.plane].n
    x_pix = g.plane_coords(dm.plane)[dm.pixels % n][wfs.measured_pixels]
    transfer = _transfer(f)
    np.testing.assert_allclose(measured, transfer * np.cos(2 * math.pi * f * x_pix),
                               atol=1e-12)
    # the same layer on the WFS's own plane is seen sharply
    sharp = wfs.forward(_sinusoid_maps(model, g.layer_plane[0], f))
    np.testing.assert_allclose(sharp, np.cos(2 * math.pi * f * x_pix), atol=1e-12)
    if check_disc:  # a disc of diameter h F, to the hexagon's approximation of it
        assert transfer == pytest.approx(_airy(f), abs=0.03)


@pytest.mark.parametrize("period_px", [48, 24, 16])
def test_shack_hartmann_slopes_of_a_high_layer_are_blurred_by_the_same_footprint(period_px):
    # the SH is linear: a high layer's slopes are T(f) times the same layer's at 0 km,
    # whatever the subaperture window
    model = LoopModel(_config("shack_hartmann"))
    g = model.geometry
    f = 1.0 / (period_px * DX)
    wfs = model.wfss[0]
    high = wfs.forward(_sinusoid_maps(model, g.layer_plane[1], f))
    ground = wfs.forward(_sinusoid_maps(model, g.layer_plane[0], f))
    assert np.abs(ground).max() > 0.1 * 2 * math.pi * f  # the sinusoid is seen
    np.testing.assert_allclose(high, _transfer(f) * ground, atol=1e-12 * np.abs(ground).max())
