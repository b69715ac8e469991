"""The science wavelength: residual variance and Strehl ratio against the laws of r0(lambda).

References (independent of closedloop's code):
- r0 grows as lambda^(6/5), so the phase variance at the science wavelength is the
  variance at the wavelength of r0 times (lambda_r0 / lambda)^2, exactly: the same run
  (same seed, same loop) at two science wavelengths gives residual variances in the
  ratio (lambda_2 / lambda_1)^2 to float precision, and the Marechal Strehl
  exp(-sigma^2) at each;
- Noll (1976): the piston-removed variance of Kolmogorov turbulence over a disc is
  1.0324 (D / r0(lambda))^(5/3); for a finite outer scale the same variance by direct
  numerical integration of the von Karman spectrum against the disc's piston filter
  (the integral is checked against Noll's 1.0324 at L0 = inf). Checked on the open-loop
  frame (the first frame: no command has reached the mirror yet) over 81 pupils per
  screen, far apart on a high layer, and several independent screens.
"""

import dataclasses

import numpy as np
import pytest
from scipy import integrate, special

from closedloop.config import (
    DMConfig,
    FieldConfig,
    LayerConfig,
    LoopConfig,
    SimulationConfig,
    TelescopeConfig,
    WFSConfig,
)
from closedloop.simulation import LoopModel, simulate

NOLL_PISTON_REMOVED = 1.0324
ARCSEC = np.pi / 648000.0  # radians per arcsecond, written out here


def _config(wavelength, *, n_pixels=16, d_over_r0=10.0, altitude=0.0, field=None,
            r0_wavelength=500e-9, wind=5.0, direction=30.0, outer_scale=np.inf):
    field = FieldConfig(size=0.0, n_points=1) if field is None else field
    return SimulationConfig(
        name="wavelength",
        telescope=TelescopeConfig(diameter=4.0, n_pixels=n_pixels),
        layers=(LayerConfig(altitude=altitude, d_over_r0=d_over_r0, wind_speed=wind,
                            wind_direction=direction, outer_scale=outer_scale),),
        dms=(DMConfig(altitude=0.0, n_modes=9),),
        wfss=(WFSConfig(altitude=0.0, field_of_view=0.0, n_subapertures=6, noise=0.002,
                        field_samples=1),),
        loop=LoopConfig(time_step=1e-3, integration_time=1e-3, delay=0.5e-3, gain=0.4),
        field=field, wavelength=wavelength, r0_wavelength=r0_wavelength)


@pytest.mark.parametrize("r0_wavelength", [500e-9, 700e-9])
def test_one_run_at_two_science_wavelengths_scales_as_lambda_squared(r0_wavelength):
    # a closed loop with a noisy SH: the residual at the wavelength of r0 is the same
    # phase whatever the science wavelength, so the variances scale by (l_r0 / l)^2
    field = FieldConfig(size=20.0, n_points=3)
    runs = {}
    for wl in (r0_wavelength, 1.6e-6, 400e-9):
        cfg = _config(wl, altitude=3000.0, field=field, r0_wavelength=r0_wavelength)
        runs[wl] = simulate(cfg, 0.02, seed=3, progress=False)
    base = runs[r0_wavelength].residual_variance
    assert np.all(base > 0)
    for wl, res in runs.items():
        expected = base * (r0_wavelength / wl) ** 2
        np.testing.assert_allclose(res.residual_variance, expected, rtol=1e-12)
        np.testing.assert_allclose(res.strehl, np.exp(-expected), rtol=1e-12)
        # the logs stay in rad at the wavelength of r0, whatever the science wavelength
        np.testing.assert_array_equal(res.logs["dm0.commands"].coeffs,
                                      runs[r0_wavelength].logs["dm0.commands"].coeffs)
        assert res.logs["dm0.commands"].wavelength == r0_wavelength


def von_karman_piston_removed(d_over_r0, diameter, outer_scale):
    """Piston-removed phase variance over a disc [rad^2], by direct integration.

    ``int W(f) (1 - |2 J1(pi D f) / (pi D f)|^2) 2 pi f df`` with the von Karman
    spectrum ``W(f) = 0.0229 r0^(-5/3) (f^2 + L0^-2)^(-11/6)`` (the exact constant).
    """
    c = ((24.0 / 5.0 * special.gamma(6.0 / 5.0)) ** (5.0 / 6.0) * special.gamma(11.0 / 6.0) ** 2
         / (2.0 * np.pi ** (11.0 / 3.0)))
    r0 = diameter / d_over_r0
    inv_l0 = 0.0 if np.isinf(outer_scale) else 1.0 / outer_scale

    def integrand(f):
        x = np.pi * diameter * f
        return (c * r0 ** (-5.0 / 3.0) * (f * f + inv_l0 ** 2) ** (-11.0 / 6.0)
                * (1.0 - (2.0 * special.j1(x) / x) ** 2) * 2.0 * np.pi * f)

    knee = 50.0 / diameter
    return (integrate.quad(integrand, 0.0, knee, limit=1000)[0]
            + integrate.quad(integrand, knee, np.inf, limit=1000)[0])


def test_the_integral_is_nolls_constant_for_kolmogorov():
    assert von_karman_piston_removed(10.0, 4.0, np.inf) / 10.0 ** (5 / 3) == pytest.approx(
        NOLL_PISTON_REMOVED, rel=2e-4)


def _open_loop_ratios(wavelength, seeds, r0_wavelength=500e-9, outer_scale=8.0):
    """Per screen: mean open-loop variance over 81 pupils / the law at the science wavelength."""
    # 81 directions 200" apart on a layer at h = 10 m / 200": 40 whole pixels (2.5 D)
    # between neighbouring pupils, read without interpolation, nearly independent for
    # L0 = 2 D. The first frame is open loop: no command has reached the mirror yet.
    h = 10.0 / (200.0 * ARCSEC)
    cfg = _config(wavelength, altitude=h, field=FieldConfig(size=1600.0, n_points=9),
                  r0_wavelength=r0_wavelength, wind=0.0, outer_scale=outer_scale)
    # open loop (`loop.closed = false`): a one-frame run is then valid
    cfg = dataclasses.replace(cfg, loop=dataclasses.replace(cfg.loop, closed=False))
    model = LoopModel(cfg)
    # r0(lambda) = r0(lambda_r0) (lambda / lambda_r0)^(6/5); L0 does not depend on lambda
    d_over_r0_sci = 10.0 * (wavelength / r0_wavelength) ** (-6.0 / 5.0)
    law = von_karman_piston_removed(d_over_r0_sci, 4.0, outer_scale)
    return np.array([simulate(cfg, 1e-3, seed=s, model=model, progress=False)
                     .residual_variance[0].mean() / law for s in seeds])


def test_open_loop_variance_is_the_law_at_the_science_wavelength():
    # 3 screens x 81 pupils at 1.25 um. Measured: the per-screen means scatter by 4.7 %
    # (8 screens; one pupil by 50 %), their mean was 0.995 +- 0.017: the mean of 3 has a
    # s.e. of 2.7 %, and 10 % is 3.7 s.e. A wrong r0 exponent (lambda^1 instead of
    # lambda^(6/5)) moves the value by 35 %, a variance at the wavelength of r0 by 2.5^2.
    ratios = _open_loop_ratios(1.25e-6, range(3))
    assert ratios.mean() == pytest.approx(1.0, abs=0.10)


@pytest.mark.slow
def test_open_loop_variance_is_the_law_many_screens():
    # 16 screens at 2.2 um: s.e. ~1.2 %, 5 % is 4 s.e.
    ratios = _open_loop_ratios(2.2e-6, range(16))
    print(f"open loop / law at 2.2 um: {ratios.mean():.3f} +- "
          f"{ratios.std(ddof=1) / np.sqrt(ratios.size):.3f}")
    assert ratios.mean() == pytest.approx(1.0, abs=0.05)
