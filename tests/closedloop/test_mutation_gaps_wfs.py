"""closedloop.optics.wfs: the sensors' AOT records, cost estimates, model errors and refusals.

Gaps found by mutation testing (docs/MUTATION.md, "closedloop/optics/wfs.py"). References,
from outside the module under test:

- the AOT records as ``closedloop/aot.py``'s docstring defines them: a Shack-Hartmann is
  ``"shack-hartmann"`` with its ``(n_sub, n_sub)`` mask (``-1`` outside, else the valid
  subaperture's index, rows are y), slopes [rad/m] reshaped ``(T, 2, s_v)`` x then y;
  an ideal sensor a one-value-per-subaperture ``"pyramid"`` whose subapertures are the
  measured pixels of its DM's disc on the DM's plane grid, values [rad], ``(T, 1, n)``;
  ``MI_GEOM`` extras: the DM driven, the line-of-sight altitude ``h sec z``, the field
  samples, the configured noise [arcsec], the pitch ``(D + 2 h sec z tan(F/2)) / n_sub``;
- Noll (1976)'s table of ``Delta_J`` (``Delta_10 = 0.0401``) for an ideal sensor's model
  error ``Delta_J (D_dm / r0)^(5/3)`` summed over the layers, and the Z-tilt variance
  ``16 * 0.449 (d / r0)^(5/3) / d^2`` of a subaperture for a Shack-Hartmann's;
- the resource estimate's counts from their definitions: a disc of ``a`` pixels across
  holds ``pi a^2 / 4`` pixels (checked against the built sensors' measurement counts),
  two axes x 8 entries (two bilinear reads) per pixel pair and per direction and plane
  for a SH, 4 per pixel and per direction and plane for an ideal sensor;
- the project's rule for bad input: the message names the argument, the rule, the value.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from closedloop.config import (
    DMConfig,
    WFSConfig,
)
from closedloop.kinds import sensor_kind
from closedloop.model import LoopModel
from closedloop.optics import wfs as wfs_module

from .conftest import GAP_DIAMETER, gap_config, gap_sensor

ARCSEC = math.pi / 648000.0
D = GAP_DIAMETER


def _config(kind="shack_hartmann", zenith=0.0, noise=0.05, altitude=0.0, field=30.0,
            obscuration=0.0, n_modes=9, n_pixels=32):
    sensor = gap_sensor(altitude, field, noise if kind == "shack_hartmann" else 0.0, 0, kind)
    return gap_config("wfs-gaps", ((0.0, 8.0, 5.0), (5000.0, 4.0, 10.0)),
                      (DMConfig(altitude=altitude, n_modes=n_modes),), (sensor,),
                      n_pixels=n_pixels, zenith_angle=zenith, obscuration=obscuration)


@pytest.fixture(scope="module")
def sh():
    """A SH at 3 km seen at 30 deg from the zenith."""
    cfg = _config(zenith=30.0, altitude=3000.0)
    return cfg, LoopModel(cfg)


@pytest.fixture(scope="module")
def ideal():
    cfg = _config(kind="ideal", obscuration=0.3)
    return cfg, LoopModel(cfg)


def test_shack_hartmann_aot_record(sh):
    cfg, model = sh
    w = model.wfss[0]
    wcfg = cfg.wfss[0]
    meas = np.arange(6.0 * w.n_measurements).reshape(6, w.n_measurements)
    layout = wfs_module.slopes_aot_layout(w, meas)
    # x slopes then y slopes: (T, 2 s_v) -> (T, 2, s_v)
    n = w.n_valid_subapertures
    assert layout.shape == (6, 2, n)
    np.testing.assert_array_equal(layout[:, 0], meas[:, :n])
    np.testing.assert_array_equal(layout[:, 1], meas[:, n:])
    spec = wfs_module.slopes_aot_record(model, 0, wcfg, layout, extra={"own": 1}, n_extra=2)
    assert (spec.uid, spec.source, spec.kind, spec.units) == ("wfs0", "sun", "shack-hartmann",
                                                             "rad/m")
    assert spec.n_valid_subapertures == n + 2
    assert spec.measurements is layout
    assert spec.field_of_view == 30.0 and spec.altitude == 3000.0  # as configured
    mask = spec.subaperture_mask
    assert mask.shape == (8, 8) and mask.dtype == np.int32
    for k, sub in enumerate(w.valid_subapertures):
        assert mask[sub // 8, sub % 8] == k  # rows are y
    assert (mask == -1).sum() == 64 - n
    sec = 1.0 / math.cos(math.radians(30.0))
    pitch = (D + 2.0 * 3000.0 * sec * math.tan(15.0 * ARCSEC)) / 8
    assert spec.extra == {
        "drives": "dm0", "line_of_sight_altitude": pytest.approx(3000.0 * sec, rel=1e-12),
        "field_samples": 7, "noise_arcsec": 0.05,
        "subaperture_pitch": pytest.approx(pitch, rel=1e-12), "n_subapertures": 8,
        "order": "d = 0: x slopes, d = 1: y slopes; mask rows are y", "own": 1}
    assert isinstance(spec.extra["field_samples"], int)
    # without a kind's extra entries: the valid subapertures only
    assert wfs_module.slopes_aot_record(model, 0, wcfg, layout).n_valid_subapertures == n


def test_index_grid_marks_the_listed_cells():
    grid = wfs_module.index_grid(3, np.array([7, 0, 5]))
    np.testing.assert_array_equal(grid, [[1, -1, -1], [-1, -1, 2], [-1, 0, -1]])
    assert grid.dtype == np.int32


def test_ideal_sensor_aot_record_is_a_one_value_pyramid_on_the_lit_disc(ideal):
    cfg, model = ideal
    w = model.wfss[0]
    kind = sensor_kind("ideal")
    meas = np.arange(3.0 * w.n_measurements).reshape(3, w.n_measurements)
    layout = kind.aot_layout(w, meas)
    assert layout.shape == (3, 1, w.n_measurements)
    np.testing.assert_array_equal(layout[:, 0], meas)
    spec = kind.aot_record(model, 0, cfg.wfss[0], layout)
    assert (spec.uid, spec.source, spec.kind, spec.units, spec.dimensions) == (
        "wfs0", "sun", "pyramid", "rad", 1)
    assert spec.n_valid_subapertures == w.n_measurements
    # the measured pixels: the DM disc's pixels outside the central obscuration
    g = model.geometry
    n_p = g.planes[w.dm.plane].n
    x = g.plane_coords(w.dm.plane)
    xx, yy = np.meshgrid(x, x)  # rows are y
    r = np.hypot(xx, yy).ravel()[w.dm.pixels] / (D / 2.0)
    lit = w.dm.pixels[r >= 0.3]
    assert 0 < lit.size < w.dm.pixels.size  # the obscuration removes some
    mask = spec.subaperture_mask
    assert mask.shape == (n_p, n_p)
    np.testing.assert_array_equal(mask.ravel()[lit], np.arange(lit.size))
    assert (mask == -1).sum() == n_p * n_p - lit.size
    assert spec.extra["kind"] == "ideal" and spec.extra["drives"] == "dm0"
    assert spec.extra["note"] == (
        "AOT has no ideal (phase) sensor type: written as a Pyramid record with one value "
        "per subaperture; its subapertures are the measured pixels of its DM's disc (mask "
        "on the DM plane grid), its measurements their field-averaged phase [rad] as the "
        "simulator's sensor gives them")
    assert spec.measurements is layout
    assert spec.field_of_view == 30.0 and spec.altitude == 0.0
    assert spec.extra["noise_arcsec"] == 0.0 and spec.extra["line_of_sight_altitude"] == 0.0


def test_ideal_record_refuses_pixels_that_are_not_the_measurements(ideal):
    _, model = ideal
    w = model.wfss[0]
    rows = w.measured_pixels
    try:
        w.measured_pixels = rows[:-1]
        with pytest.raises(ValueError) as err:
            wfs_module._sensed_pixels(w)
    finally:
        w.measured_pixels = rows
    assert str(err.value) == (f"ideal sensor 0: {rows.size - 1} pixels for {rows.size} "
                              "measurements (internal geometry error).")


def test_ideal_sensor_model_error_is_nolls_residual():
    model = LoopModel(_config(kind="ideal"))  # 9 modes: Z2..Z10, Delta_10
    w = model.wfss[0]
    r0s = [0.5, 1.0]
    expected = 0.0401 * sum((w.dm.diameter / r0) ** (5.0 / 3.0) for r0 in r0s)
    assert w.model_error_variance(r0s, 0.7) == pytest.approx(expected, rel=0.01)


def test_shack_hartmann_model_error_is_the_subaperture_z_tilt(sh):
    cfg, model = sh
    w = model.wfss[0]
    sec = 1.0 / math.cos(math.radians(30.0))
    d = (D + 2.0 * 3000.0 * sec * math.tan(15.0 * ARCSEC)) / 8
    r0s = [0.5, 1.0]
    expected = 0.3 * 16.0 * 0.449 * sum((d / r0) ** (5.0 / 3.0) for r0 in r0s) / d ** 2
    # at 3 km the metapupil's ring is lit by part of the field: each measurement's model
    # error and noise variance grow as 1 / its field share (issue 27, left28-field)
    share = w.field_share
    assert share.max() == 1.0 and share.min() < 1.0
    me = np.asarray(w.model_error_variance(r0s, 0.3))
    np.testing.assert_allclose(me * share, expected, rtol=1e-12)
    # the configured 0.05" as a phase gradient at r0_wavelength [rad/m]
    sigma = 2.0 * math.pi * 0.05 * ARCSEC / 500e-9
    np.testing.assert_allclose(np.asarray(w.noise_rms) ** 2 * share, sigma ** 2, rtol=1e-12)


@pytest.mark.parametrize("field", [60.0, 0.0])
@pytest.mark.parametrize("kind", ["shack_hartmann", "ideal"])
def test_resource_estimate_counts(kind, field):
    cfg = _config(kind=kind, altitude=3000.0, field=field)
    model = LoopModel(cfg)
    g = model.geometry
    w = model.wfss[0]
    n_planes = len(g.planes)
    est = sensor_kind(kind).estimate(cfg, 0, n_planes, g.dx)
    samples = len(w.samples)
    assert samples == (7 if field else 1)
    if kind == "shack_hartmann":
        across = (D + 2.0 * 3000.0 * math.tan(field / 2.0 * ARCSEC)) / g.dx
        assert est.n_measurements == pytest.approx(2.0 * math.pi / 4.0 * 8 ** 2, rel=1e-12)
        assert est.build_entries == pytest.approx(
            2 * samples * n_planes * math.pi / 4.0 * across ** 2 * 8, rel=1e-12)
    else:
        disc = w.dm.diameter / g.dx
        assert est.n_measurements == pytest.approx(math.pi / 4.0 * disc ** 2, rel=1e-12)
        assert est.build_entries == pytest.approx(samples * n_planes * est.n_measurements * 4,
                                                  rel=1e-12)
        # the count is the built sensor's, to the disc's pixelisation
        assert est.n_measurements == pytest.approx(w.n_measurements, rel=0.05)


def test_shack_hartmann_estimate_counts_the_built_slopes():
    # on the ground the meta-pupil is the pupil: 2 (pi / 4) n_sub^2 slopes, to the
    # pupil's pixelisation (104 built for 100.5)
    cfg = _config()
    model = LoopModel(cfg)
    est = sensor_kind("shack_hartmann").estimate(cfg, 0, len(model.geometry.planes),
                                                 model.geometry.dx)
    assert est.n_measurements == pytest.approx(model.wfss[0].n_measurements, rel=0.05)


def test_ideal_sensor_sees_its_own_plane_sharply_less_the_mean():
    # an ideal sensor at 3 km with a 60" field: every direction sees a phase on its own
    # plane at the same pixel, so the field average is that pixel's phase; piston is not
    # sensed (the module docstring), so the measurement is the phase less its mean
    cfg = _config(kind="ideal", altitude=3000.0, field=60.0)
    model = LoopModel(cfg)
    w = model.wfss[0]
    g = model.geometry
    rng = np.random.default_rng(2)
    maps = [np.zeros((p.n, p.n)) for p in g.planes]
    maps[w.dm.plane] = rng.standard_normal(maps[w.dm.plane].shape) + 5.0
    phase = maps[w.dm.plane].ravel()[w.dm.pixels[w.measured_pixels]]
    assert w.n_measurements == phase.size and w.n_valid_subapertures == 0
    np.testing.assert_allclose(w.forward(maps), phase - phase.mean(), atol=1e-12)
    # the disc's edge pixels are reached by some of the 7 directions only, and a few by
    # none (not measured)
    x = g.plane_coords(w.dm.plane)
    n = g.planes[w.dm.plane].n
    points = np.column_stack([x[w.dm.pixels % n], x[w.dm.pixels // n]])
    count = np.sum([w._illuminated(points, t) for t in w.samples], axis=0)
    assert np.any((count > 0) & (count < 7))
    np.testing.assert_array_equal(w.measured_pixels, np.flatnonzero(count > 0))


def test_an_ideal_sensor_on_a_zonal_mirror_has_no_model_error():
    cfg = _config(kind="ideal").replace(dms=(DMConfig(altitude=0.0, kind="ideal"),))
    model = LoopModel(cfg)
    assert model.wfss[0].model_error_variance([0.5, 1.0], 0.3) == 0.0
    assert model.wfss[0].reconstructor is None


def test_has_noise_of_floats_and_arrays():
    assert wfs_module.has_noise(0.1) and not wfs_module.has_noise(0.0)
    assert wfs_module.has_noise(np.array([0.0, 0.2]))
    assert not wfs_module.has_noise(np.zeros(3))
    assert wfs_module.has_noise(np.float32(0.5))  # not a Python float: the array path


def test_refusals_name_the_rule_and_the_value(sh):
    cfg, model = sh
    w = model.wfss[0]
    maps = [np.zeros((p.n, p.n)) for p in model.geometry.planes]
    with pytest.raises(ValueError) as err:
        w.forward(maps[:-1])
    assert str(err.value) == f"`plane_maps` must hold {len(maps)} maps; got {len(maps) - 1}."
    bad = list(maps)
    bad[1] = np.zeros((3, 3))
    n1 = model.geometry.planes[1].n ** 2
    with pytest.raises(ValueError) as err:
        w.forward(bad)
    assert str(err.value) == f"`plane_maps[1]` must have {n1} pixels; got 9."
    with pytest.raises(ValueError) as err:
        wfs_module.IdealSensor(model.geometry, 0, model.dms[0])
    assert str(err.value) == (
        "`geometry.config.wfss[0].kind` must be 'ideal' for IdealSensor; got "
        "'shack_hartmann' (build it through closedloop.kinds.sensor_kind(kind).build).")
    with pytest.raises(ValueError) as err:
        wfs_module.bilinear_matrix(np.array([-0.5]), np.array([1.0]), 4)
    assert str(err.value) == "a beam leaves its plane's grid (internal geometry error)."


def test_a_new_kind_without_its_parts_says_what_is_missing(sh):
    _, model = sh

    class Bare(wfs_module.WavefrontSensor):
        kind = "shack_hartmann"

    with pytest.raises(NotImplementedError) as err:
        Bare(model.geometry, 0, model.dms[0])
    assert str(err.value) == "Bare must implement _build"
    with pytest.raises(NotImplementedError) as err:
        wfs_module.WavefrontSensor.model_error_variance(model.wfss[0], [1.0], 0.3)
    assert str(err.value) == "ShackHartmann must implement model_error_variance"


def test_subaperture_sampling_message():
    cfg = _config(n_pixels=16).replace(
        wfss=(WFSConfig(altitude=0.0, field_of_view=30.0, n_subapertures=8, noise=0.05,
                        field_samples=2, dm=0),))
    # a 16-pixel pupil: 8 subapertures of 2 pixels are allowed, 9 are not
    wfs_module.check_subaperture_sampling(cfg, 0)
    big = cfg.wfss[0].__class__(**{**vars(cfg.wfss[0]), "n_subapertures": 9})
    with pytest.raises(ValueError) as err:
        wfs_module.check_subaperture_sampling(cfg.replace(wfss=(big,)), 0)
    assert str(err.value) == (
        "`wfss[0].n_subapertures` must be <= 8 (at least 2 pixels per subaperture across the "
        "16-pixel meta-pupil at telescope.n_pixels = 16); got 9.")


def test_forward_adds_the_draws_scaled_by_noise_rms(sh):
    # forward's contract: the draws given are standard normal, scaled by noise_rms and
    # added to the noise-free measurement (a flat residual measures 0)
    _, model = sh
    w = model.wfss[0]
    maps = [np.zeros((p.n, p.n)) for p in model.geometry.planes]
    draws = np.random.default_rng(4).standard_normal(w.n_measurements)
    np.testing.assert_array_equal(w.forward(maps, draws), w.noise_rms * draws)
    np.testing.assert_array_equal(w.forward(maps), np.zeros(w.n_measurements))


@pytest.mark.parametrize("axis", [0, 1])
@pytest.mark.parametrize("n_sub", [7, 8, 14])
def test_window_weights_partition_each_subaperture_and_each_cell(axis, n_sub):
    # a pair's dx x dx cell ([x, x + dx] along the axis, [y - dx/2, y + dx/2] across)
    # tiles the plane with the other pairs' cells: the weights (area inside S / dx^2)
    # sum to (pitch / dx)^2 over each subaperture S and to 1 over each cell inside the
    # square; 7 or 14 subapertures over 32 pixels put edges inside pixels (14: a pitch
    # of 2.3 pixels, near the 2-pixel limit of the config)
    dx, d_wfs, n = 0.125, 4.0, 40
    x = (np.arange(n) - (n - 1) / 2.0) * dx + 0.03  # the grid off the square's centre
    xx, yy = np.meshgrid(x[:-1], x)
    start = np.column_stack([xx.ravel(), yy.ravel()])
    if axis == 1:
        start = start[:, ::-1]
    pair, sub, weight = wfs_module._window_entries(start, axis, dx, d_wfs, n_sub)
    assert np.all(weight > 0) and np.all((sub >= 0) & (sub < n_sub ** 2))
    per_sub = np.bincount(sub, weights=weight, minlength=n_sub ** 2)
    np.testing.assert_allclose(per_sub, (d_wfs / n_sub / dx) ** 2, rtol=1e-12)
    per_pair = np.bincount(pair, weights=weight, minlength=start.shape[0])
    s, y = start[:, axis], start[:, 1 - axis]
    inside = (s >= -2.0) & (s + dx <= 2.0) & (y - dx / 2 >= -2.0) & (y + dx / 2 <= 2.0)
    outside = (s >= 2.0) | (s + dx <= -2.0) | (y - dx / 2 >= 2.0) | (y + dx / 2 <= -2.0)
    assert inside.sum() > 900
    np.testing.assert_allclose(per_pair[inside], 1.0, rtol=1e-12)
    assert np.all(per_pair[outside] == 0.0)


def test_bilinear_matrix_is_scipys_linear_interpolation_up_to_the_last_pixel():
    # reference: scipy.interpolate.RegularGridInterpolator (linear) on the same grid,
    # points anywhere in [0, n - 1] including the edges (the last cell's clamp) and
    # the first cell
    from scipy.interpolate import RegularGridInterpolator

    n = 6
    values = np.random.default_rng(1).standard_normal((n, n))  # rows, columns
    rng = np.random.default_rng(2)
    cols = np.concatenate([rng.uniform(0, n - 1, 50), [0.0, n - 1.0, n - 1.0, 0.5, 4.7]])
    rows = np.concatenate([rng.uniform(0, n - 1, 50), [n - 1.0, 0.0, n - 1.0, 0.2, n - 1.0]])
    m = wfs_module.bilinear_matrix(cols, rows, n)
    ref = RegularGridInterpolator((np.arange(n), np.arange(n)), values)(
        np.column_stack([rows, cols]))
    np.testing.assert_allclose(m @ values.ravel(), ref, rtol=0, atol=1e-13)
    # a point off the grid on one axis only is refused
    for c, r in ((-0.5, 2.0), (2.0, -0.5)):
        with pytest.raises(ValueError):
            wfs_module.bilinear_matrix(np.array([c]), np.array([r]), n)


def test_a_shack_hartmann_on_a_zonal_mirror_gets_a_pseudo_inverse():
    # the zonal DM's interaction is sparse; the reconstructor is its Moore-Penrose
    # pseudo-inverse (R G R = R, R G symmetric), one row per disc pixel
    cfg = _config().replace(dms=(DMConfig(altitude=0.0, kind="ideal"),))
    w = LoopModel(cfg).wfss[0]
    g = w.interaction.toarray()
    r = w.reconstructor
    assert r.shape == (w.dm.pixels.size, w.n_measurements)
    np.testing.assert_allclose(r @ g @ r, r, atol=1e-10 * np.abs(r).max())
    np.testing.assert_allclose(r @ g, (r @ g).T, atol=1e-10)


def test_an_ideal_sensor_is_noise_free_and_reads_back_its_mirrors_modes():
    # an ideal sensor at the DM's altitude sees each DM mode's own shape and its
    # least-squares fit on the DM's modes is that mode (piston removed from both sides)
    cfg = _config(kind="ideal", altitude=3000.0, field=60.0)
    model = LoopModel(cfg)
    w = model.wfss[0]
    assert w.noise_rms == 0.0
    g = model.geometry
    maps = [np.zeros((p.n, p.n)) for p in g.planes]
    for k in (0, 3, 8):
        flat = np.zeros(g.planes[w.dm.plane].n ** 2)
        flat[w.dm.pixels] = w.dm.shapes[:, k]
        maps[w.dm.plane] = flat.reshape(maps[w.dm.plane].shape)
        np.testing.assert_allclose(model.sense(maps, np.random.default_rng(0)),
                                   np.eye(w.dm.n_modes)[k], atol=1e-10)
