"""The MAP reconstructor's prior: each layer's turbulence goes to the DM nearest to it.

References (computed in the test):
- Noll (1976): the variance of Zernike coefficient j (radial order n) of Kolmogorov
  turbulence over a disc of diameter D, by direct numerical integration of the
  Kolmogorov spectrum against the mode's Fourier transform, checked here against
  Noll's table (0.449 for each tilt, Delta_3 - Delta_4 = 0.023 for defocus,
  Delta_10 - Delta_11 = 0.0024, in units of (D/r0)^(5/3));
- each layer assigned to the DM whose altitude is nearest (along the line of sight),
  each DM's prior the sum of its layers' variances over the DM's disc (diameter
  D + 2 h tan(F/2), F its WFS's field), r0 along the line of sight r0 (sec z)^(-3/5);
- the assignment changes the result measurably: a tilt the WFSs see identically on
  every plane is split between the DMs by the MAP estimate in proportion to their
  priors, so moving the strong layer from one DM to the other moves the estimate.
"""

import functools
import math

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
from closedloop.simulation import LoopModel

ARCSEC = math.pi / 648000.0
FIELDS = (60.0, 20.0)
DM_ALTITUDES = (0.0, 8000.0)


@functools.cache
def _radial_order_variance(n):
    """Variance of one Zernike coefficient of radial order n for D/r0 = 1 [rad^2].

    Direct integral of the Kolmogorov spectrum ``0.0229 r0^(-5/3) f^(-11/3)`` against
    the mode's squared Fourier transform ``(n + 1) (2 J_{n+1}(pi D f) / (pi D f))^2``
    (Noll 1976, eq. 8): ``int W(f) |Q(f)|^2 2 pi f df``.
    """
    c = ((24.0 / 5.0 * special.gamma(6.0 / 5.0)) ** (5.0 / 6.0) * special.gamma(11.0 / 6.0) ** 2
         / (2.0 * math.pi ** (11.0 / 3.0)))

    def integrand(f):  # D = 1, r0 = 1
        x = math.pi * f
        return c * f ** (-11.0 / 3.0) * (n + 1) * (2.0 * special.jv(n + 1, x) / x) ** 2 \
            * 2.0 * math.pi * f

    return (integrate.quad(integrand, 0.0, 20.0, limit=2000)[0]
            + integrate.quad(integrand, 20.0, np.inf, limit=2000)[0])


def noll_variance(j, d_over_r0):
    """Variance of Noll Zernike j (j >= 2) of Kolmogorov turbulence [rad^2]."""
    n = math.ceil((math.sqrt(8 * j + 1) - 3) / 2)
    return _radial_order_variance(n) * d_over_r0 ** (5.0 / 3.0)


def test_noll_variance_against_nolls_table():
    assert noll_variance(2, 1.0) == pytest.approx(0.449, abs=5e-4)
    assert noll_variance(3, 1.0) == pytest.approx(0.449, abs=5e-4)
    assert noll_variance(4, 1.0) == pytest.approx(0.134 - 0.111, abs=5e-4)
    assert noll_variance(11, 1.0) == pytest.approx(0.0401 - 0.0377, abs=2e-4)


def _config(layers, zenith=0.0, fields=FIELDS, diameters=(None, None)):
    return SimulationConfig(
        name="prior",
        telescope=TelescopeConfig(diameter=4.0, n_pixels=32, zenith_angle=zenith),
        layers=tuple(LayerConfig(altitude=h, d_over_r0=s, wind_speed=5.0) for h, s in layers),
        dms=(DMConfig(altitude=DM_ALTITUDES[0], n_modes=20, diameter=diameters[0]),
             DMConfig(altitude=DM_ALTITUDES[1], n_modes=9, diameter=diameters[1])),
        wfss=tuple(WFSConfig(altitude=h, field_of_view=f, n_subapertures=8, noise=0.005,
                             field_samples=2, dm=i)
                   for i, (h, f) in enumerate(zip(DM_ALTITUDES, fields, strict=True))),
        loop=LoopConfig(), field=FieldConfig(size=30.0, n_points=3),
        wavelength=630e-9, r0_wavelength=500e-9)


def _expected_prior(layers, zenith, modes=(20, 9)):
    airmass = 1.0 / math.cos(math.radians(zenith))
    out = []
    for d, (h_dm, field) in enumerate(zip(DM_ALTITUDES, FIELDS, strict=True)):
        diameter = 4.0 + 2.0 * h_dm * airmass * math.tan(field / 2.0 * ARCSEC)
        var = np.zeros(modes[d])
        for h, d_over_r0 in layers:
            nearest = int(np.argmin([abs(h - a) for a in DM_ALTITUDES]))
            if nearest != d:
                continue
            r0 = 4.0 / d_over_r0 * airmass ** (-3.0 / 5.0)
            var += [noll_variance(j, diameter / r0) for j in range(2, modes[d] + 2)]
        out.append(var)
    return np.concatenate(out)


# (altitude, D/r0) of each layer: 3.5 km is nearer 0 than 8 km, 5 km nearer 8 km
CASES = [
    ([(3500.0, 12.0), (5000.0, 4.0)], 0.0),
    ([(3500.0, 4.0), (5000.0, 12.0)], 0.0),
    ([(0.0, 10.0), (9000.0, 3.0), (4500.0, 2.0)], 30.0),
]


@pytest.mark.parametrize("layers,zenith", CASES)
def test_each_layers_prior_goes_to_its_nearest_dm(layers, zenith):
    model = LoopModel(_config(layers, zenith))
    np.testing.assert_allclose(model.prior, _expected_prior(layers, zenith), rtol=2e-3)


def _tilt_share_on_dm0(model):
    """Share of a global x tilt (seen alike on every plane) that MAP puts on DM 0."""
    g = model.geometry
    slope = 1e-2  # rad/m
    maps = [np.zeros((p.n, p.n)) for p in g.planes]
    x = g.plane_coords(g.dm_plane[0])
    maps[g.dm_plane[0]] = np.tile(slope * x, (g.planes[g.dm_plane[0]].n, 1))
    est = model.sense(maps, None)
    # Z2 over a disc of diameter D_d has the slope 4 / D_d per unit coefficient
    physical = [est[model.mode_slices[d]][0] * 4.0 / model.dms[d].diameter for d in range(2)]
    return physical[0] / sum(physical), sum(physical) / slope


@pytest.mark.parametrize("case", [0, 1])
def test_a_tilt_seen_alike_by_every_beam_is_split_by_the_priors(case):
    # both DMs 6 m across and both WFS fields 20": every beam crosses both discs, so a
    # tilt on DM 0 and the same tilt on DM 1 give the same measurements, and the MAP
    # estimate of a global tilt splits it in the ratio of the DMs' tilt priors: with
    # equal discs, the ratio of the sums of (D/r0)^(5/3) of the layers nearest to each
    layers = CASES[case][0]
    model = LoopModel(_config(layers, fields=(20.0, 20.0), diameters=(6.0, 6.0)))
    share, total = _tilt_share_on_dm0(model)
    strength = [0.0, 0.0]
    for h, d_over_r0 in layers:
        strength[int(np.argmin([abs(h - a) for a in DM_ALTITUDES]))] += d_over_r0 ** (5 / 3)
    # (the tilt is not quite orthogonal to the other sampled modes: ~1 % leaks to them)
    assert total == pytest.approx(1.0, abs=0.03)
    assert share == pytest.approx(strength[0] / sum(strength), abs=1e-6)


def test_swapping_the_assignment_moves_the_estimate():
    # the same two layers with their strengths swapped: the split moves from ~0.86 to
    # ~0.14 of the tilt on the ground DM
    shares = [_tilt_share_on_dm0(LoopModel(_config(CASES[c][0], fields=(20.0, 20.0),
                                                    diameters=(6.0, 6.0))))[0]
              for c in (0, 1)]
    assert shares[0] > 0.8 and shares[1] < 0.2
