"""Configs that break the laws the simulator rests on are refused, naming field, rule, value.

References, written out here from the laws (not from the code under test):

- a Shack-Hartmann of ``n x n`` subapertures measures two slopes per valid subaperture;
  the valid ones are counted here on a numpy grid (subaperture centre on the annular
  pupil), and a least-squares reconstructor needs at least as many slopes as modes; a
  WFS at altitude h spans the meta-pupil ``D + 2 h tan(fov / 2)`` (geometry), over which
  the telescope's hole is a smaller fraction;
- r0 shrinks as ``sec(z)**(-3/5)`` (Roddier 1981): the pixel ``D / n_pixels`` must not
  exceed r0 at ``r0_wavelength`` (the simulator's phase);
- von Karman's outer scale must exceed the pupil (Kolmogorov's inertial range);
- frozen flow: a layer moving ``v T`` in a frame must not cross more than the pupil;
- the ground-based solar range of wavelengths, 300 nm to 28 um;
- the 180-degree field and other bounds of the issue 27 list.
"""

import math
import re

import numpy as np
import pytest

from closedloop import presets, simulate
from closedloop.config import SimulationConfig


def _with(name: str, **changes) -> SimulationConfig:
    """Return preset ``name`` with keys changed in its plain form (``layers__0__wind_speed``)."""
    d = presets.get(name).to_dict()
    for key, value in changes.items():
        *path, last = key.split("__")
        t = d
        for p in path:
            t = t[int(p)] if p.isdigit() else t[p]
        t[last] = value
    return SimulationConfig.from_dict(d)


def _valid_by_grid(n: int, obscuration: float) -> int:
    c = (np.arange(n) + 0.5) / n - 0.5
    yy, xx = np.meshgrid(c, c, indexing="ij")
    r = np.hypot(xx, yy)
    return int(((r <= 0.5) & (r >= obscuration / 2)).sum())


def test_two_by_two_subapertures_cannot_drive_184_modes():
    # the issue's case: table1's 119 + 65 modes, both WFSs of 2 x 2 subapertures (4 valid
    # each: 16 slopes for the joint reconstructor)
    with pytest.raises(ValueError, match=r"`dms\[\*\].n_modes` must be <= 16 in all, the "
                                         r"slopes all the WFSs measure \(8 \+ 8 .*ill-posed"
                                         r".*got 184"):
        _with("table1", wfss__0__n_subapertures=2, wfss__1__n_subapertures=2)
    # the joint count: 8 x 8 subapertures on both (52 valid each, by the grid count)
    # carry 119 + 65 = 184 <= 208 modes; 200 + 65 do not
    assert 4 * _valid_by_grid(8, 0.0) == 208
    eight = {"wfss__0__n_subapertures": 8, "wfss__1__n_subapertures": 8}
    _with("table1", **eight)
    with pytest.raises(ValueError, match=r"must be <= 208 in all.*got 265"):
        _with("table1", dms__0__n_modes=200, **eight)


@pytest.mark.parametrize("obscuration", [0.0, 0.4])
def test_modes_up_to_the_measured_slopes_are_accepted(obscuration):
    # kaos: one ground DM and WFS of 7 x 7 subapertures over the pupil
    limit = 2 * _valid_by_grid(7, obscuration)
    # as many modes as slopes pass this rule; a single Zernike DM of them reaches radial
    # order 11 > 0.9 x 7 subapertures across and is refused by the subaperture-order rule
    # (issue 29, test_dkist_scao.py), not by this one
    with pytest.raises(ValueError, match=r"`dms\[0\].n_modes` must be <= 27 \(Zernike "
                                         r"radial order <= 0.9 x the subapertures"):
        _with("kaos", telescope__obscuration=obscuration, dms__0__n_modes=limit)
    with pytest.raises(ValueError, match=rf"`dms\[0\].n_modes` must be <= {limit},.*got "
                                         rf"{limit + 1}\."):
        _with("kaos", telescope__obscuration=obscuration, dms__0__n_modes=limit + 1)


def test_the_obscuration_scales_to_the_meta_pupil_a_high_wfs_spans():
    # a WFS (and its DM) at h = 10 km with a 10" field spans the meta-pupil D + 2 h
    # tan(fov / 2) = 1.185 m (geometry, written out here); the telescope's 0.4 D hole is
    # 0.236 of that grid's span: 36 valid subapertures of 7 x 7, not the 32 of an
    # unscaled 0.4 hole (by the grid count)
    h, fov, diameter = 10_000.0, 10.0, 0.7
    meta = diameter + 2 * h * math.tan(math.radians(fov / 3600) / 2)
    scaled = 0.4 * diameter / meta
    assert (_valid_by_grid(7, scaled), _valid_by_grid(7, 0.4)) == (36, 32)
    limit = 2 * _valid_by_grid(7, scaled)
    high = {"telescope__obscuration": 0.4, "wfss__0__altitude": h, "dms__0__altitude": h,
            "wfss__0__field_of_view": fov}
    # at the slopes' count this rule passes; the subaperture-order rule (issue 29) refuses
    with pytest.raises(ValueError, match=r"must be <= 27 \(Zernike radial order"):
        _with("kaos", dms__0__n_modes=limit, **high)
    with pytest.raises(ValueError, match=rf"`dms\[0\].n_modes` must be <= {limit},.*got "
                                         rf"{limit + 1}\."):
        _with("kaos", dms__0__n_modes=limit + 1, **high)


def test_r0_must_be_sampled_by_the_pupil_grid():
    # the case: r0 of 0.4 mm (at 500 nm) on 62 mm pixels
    with pytest.raises(ValueError, match=r"`layers\[\*\].d_over_r0` must be such that r0 at "
                                         r"r0_wavelength .* one pupil pixel"):
        _with("table1", layers__0__d_over_r0=4.0 / 0.4e-3)
    # the bound, from r0's law: at r0_wavelength (500 nm) and 30 deg zenith, r0 = D /
    # (D/r0) x cos(30)^(3/5); the pixel is 4 m / 64
    z = 30.0
    factor = math.cos(math.radians(z)) ** 0.6
    limit = 4.0 / (4.0 / 64) * factor  # largest total D/r0 (one layer)
    base = {"telescope__zenith_angle": z, "layers__1__d_over_r0": 1e-9}
    _with("table1", layers__0__d_over_r0=limit * 0.99, **base)
    with pytest.raises(ValueError, match="d_over_r0"):
        _with("table1", layers__0__d_over_r0=limit * 1.01, **base)


@pytest.mark.parametrize("outer_scale", [0.01, 3.9, 4.0])
def test_outer_scale_below_the_pupil_is_refused(outer_scale):
    with pytest.raises(ValueError, match=r"`layers\[0\].outer_scale` must be > "
                                         r"telescope.diameter = 4 m .*inertial"):
        _with("table1", layers__0__outer_scale=outer_scale)
    assert _with("table1", layers__0__outer_scale=4.01).layers[0].outer_scale == 4.01


@pytest.mark.parametrize("outer_scale", [1e10, 1e300])
def test_an_outer_scale_past_kolmogorov_is_refused(outer_scale):
    # 1e300 m overflowed in the screen's spectrum (1 / L0**2); inf is Kolmogorov
    with pytest.raises(ValueError, match=r"outer_scale` must be <= 1e\+09 m or inf"):
        _with("kaos", layers__0__outer_scale=outer_scale)
    assert math.isinf(_with("kaos", layers__0__outer_scale=math.inf).layers[0].outer_scale)
    # the bound itself is finite and accepted (the rule: <= 1e9 m or inf)
    assert _with("kaos", layers__0__outer_scale=1e9).layers[0].outer_scale == 1e9


def test_a_zero_field_takes_one_direction_only():
    # field.size 0: every direction is the axis, so n_points must be 1 (the rule), and 1 is
    # the on-axis run, accepted
    assert _with("kaos", field__size=0.0, field__n_points=1).field.n_points == 1
    with pytest.raises(ValueError, match=r"n_points` must be 1 when field.size is 0"):
        _with("kaos", field__size=0.0, field__n_points=3)


def test_a_mirror_narrower_than_two_pixels_is_refused():
    with pytest.raises(ValueError, match=r"`dms\[0\].diameter` must be >= 2 pupil pixels"):
        _with("kaos", dms__0__diameter=1e-9)


def test_wind_direction_beyond_a_turn_is_refused():
    with pytest.raises(ValueError, match=r"`layers\[0\].wind_direction` must be <= 360"):
        _with("kaos", layers__0__wind_direction=1e308)
    assert _with("kaos", layers__0__wind_direction=-360.0).layers[0].wind_direction == -360.0


def test_wind_beyond_the_pupil_per_frame_is_refused():
    # the per-frame bound binds below the 100 m/s wind rule (left26-twins): a 62.5 ms
    # frame on the 4-m pupil, 4 / 0.0625 = 64 m/s exactly (binary fractions)
    slow = dict(loop__time_step=0.0625, loop__integration_time=0.0625, loop__delay=0.03125,
                layers__1__wind_speed=10.0)
    with pytest.raises(ValueError, match=r"`layers\[0\].wind_speed` must be <= "
                                         r"telescope.diameter / loop.time_step = 64 m/s"):
        _with("table1", layers__0__wind_speed=64.5, **slow)
    _with("table1", layers__0__wind_speed=64.0, **slow)  # 4 m per 62.5 ms frame: the bound


@pytest.mark.parametrize("key", ["wavelength", "r0_wavelength"])
@pytest.mark.parametrize("value", [1e-9, 299e-9, 29e-6, 1e-3])
def test_wavelengths_outside_the_solar_range_are_refused(key, value):
    with pytest.raises(ValueError, match=rf"`{key}` must be in \[300 nm, 28 um\]"):
        _with("kaos", **{key: value})


@pytest.mark.parametrize("value", [300e-9, 28e-6])
def test_wavelength_range_ends_are_accepted(value):
    assert _with("kaos", wavelength=value).wavelength == value


@pytest.mark.parametrize(("key", "value"), [("field__size", 648000.0),
                                            ("wfss__0__field_of_view", 648000.0),
                                            ("field__size", 3601.0)])
def test_fields_beyond_one_degree_are_refused(key, value):
    name = key.replace("__0__", "[0].").replace("__", ".")
    with pytest.raises(ValueError, match=rf"`{re.escape(name)}` must be <= 3600 arcsec"):
        _with("kaos", **{key: value})


def test_a_grid_of_coincident_directions_is_refused():
    with pytest.raises(ValueError, match=r"`field.n_points` must be 1 when field.size is 0"):
        _with("kaos", field__size=0.0, field__n_points=3)


def test_an_obscured_pupil_runs_and_reports_the_annulus():
    # the whole loop with a 30 % obscuration (Shack-Hartmann, Zernike DM, science path)
    # runs where it raised NotImplementedError; the annulus's own numbers are tested in
    # optics/test_obscured_pupil.py
    cfg = _with("kaos", telescope__obscuration=0.3, field__n_points=1)
    res = simulate(cfg, 0.02, progress=False)
    assert np.isfinite(res.strehl).all() and (res.strehl > 0).all()
    assert math.isnan(res.corrected_fov_diameter(0.3))  # one point: no area
    # a zonal mirror with an ideal sensor: the hole's pixels are not seen, measured as 0
    # (the identity reconstructor keeps one measurement per mirror pixel)
    zonal = _with("kaos", telescope__obscuration=0.4, field__n_points=1,
                  wfss__0__kind="ideal", dms__0__kind="ideal")
    res = simulate(zonal, 0.02, progress=False)
    assert np.isfinite(res.strehl).all() and res.strehl[-1, 0] > 0.5


def test_every_preset_still_validates():
    for name in presets.names():
        cfg = presets.get(name)
        assert SimulationConfig.from_dict(cfg.to_dict()) == cfg


def test_wind_moving_more_than_the_pupil_in_one_frame_is_refused():
    # frozen flow: v T <= D; kaos has D = 0.7 m, here with a 10 ms frame (its own 0.5 ms
    # gives 1400 m/s, beyond the 100 m/s wind rule that now refuses first: left26-twins),
    # so v <= 70 m/s
    slow = dict(loop__time_step=0.01, loop__integration_time=0.01, loop__delay=0.01)
    bound = 0.7 / 0.01
    assert _with("kaos", layers__0__wind_speed=0.99 * bound, **slow).layers[0].wind_speed \
        < bound
    with pytest.raises(ValueError, match=r"`layers\[0\].wind_speed` must be <= "
                                         r"telescope.diameter / loop.time_step = 70 m/s"):
        _with("kaos", layers__0__wind_speed=1.01 * bound, **slow)


def test_shack_hartmann_noise_bound_is_10_arcsec():
    # the rule: <= 10 arcsec RMS (a solar subaperture's field is 5-10"); 10 itself passes
    assert _with("kaos", wfss__0__noise=10.0).wfss[0].noise == 10.0
    with pytest.raises(ValueError, match=r"`wfss\[0\].noise` must be <= 10 arcsec RMS"):
        _with("kaos", wfss__0__noise=10.5)


def _von_karman_over_kolmogorov(r_over_l0: float) -> float:
    """Phase structure function of von Karman over Kolmogorov's at ``r`` (same r0).

    von Karman: ``0.17253 (L0/r0)**(5/3) [1 - 1.00563 x**(5/6) K_{5/6}(x)]``,
    ``x = 2 pi r / L0`` (Conan 2000, JOSA A 17, 1807 eq. 2); Kolmogorov
    ``6.88 (r/r0)**(5/3)``.
    """
    from scipy import special

    x = 2 * np.pi * r_over_l0
    vk = 0.17253 * (1 - 1.00563 * x ** (5 / 6) * special.kv(5 / 6, x))
    return vk / (6.88 * r_over_l0 ** (5 / 3))


@pytest.mark.parametrize("outer_scale", [0.01, 2.0, 4.0])
def test_synthetic_open_loop_refuses_the_outer_scales_the_config_refuses(outer_scale):
    """``synthetic.open_loop_log`` took L0 < D, which the config refuses (issue 27).

    The law: with L0 <= D the structure function across the pupil is a fraction of
    Kolmogorov's (2.5 % at r = L0), so r0 no longer describes the phase there.
    """
    from modalinfo.telemetry.synthetic import Layer, open_loop_log, open_loop_psd

    assert _von_karman_over_kolmogorov(1.0) < 0.05
    kw = dict(modes=[2, 3], rate=500.0, diameter=4.0, layers=Layer(0.1, 10.0))
    rule = r" = 4 m \(the pupil must lie in the turbulence's inertial range below L0"
    with pytest.raises(ValueError, match=r"^`outer_scale` must be > diameter" + rule) as lib:
        open_loop_log(n_frames=64, outer_scale=outer_scale, **kw)
    with pytest.raises(ValueError, match=r"`outer_scale` must be > diameter" + rule):
        open_loop_psd([1.0], outer_scale=outer_scale, **kw)
    with pytest.raises(ValueError, match=r"`layers\[0\].outer_scale` must be > "
                                         r"telescope.diameter" + rule) as sim:
        _with("table1", layers__0__outer_scale=outer_scale)
    # the same rule and value after the argument's name
    assert str(lib.value).split(" = 4 m ")[1] == str(sim.value).split(" = 4 m ")[1]
    log = open_loop_log(n_frames=64, outer_scale=4.01, seed=1, **kw)
    assert log.coeffs.shape == (64, 2)
