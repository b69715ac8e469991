"""closedloop.optics.photon_budget: the Sun's radiance, the electrons per pixel, the rules.

Gaps found by mutation testing (docs/MUTATION.md, "closedloop/optics/photon_budget.py").
References, from outside the code under test:

- Planck's law ``B = 2 h c^2 / lambda^5 / (exp(h c / (lambda k T)) - 1)`` written here
  with the constants of ``scipy.constants`` (CODATA), at wavelengths and temperatures
  away from the defaults (the default temperature, 6300 K, from the module docstring);
- the photon count of a pixel from its definition: photon radiance ``B lambda / (h c)``
  times bandwidth, exposure, area, the pixel's solid angle ``(p pi / 648000)^2``,
  throughput and QE, every factor set to a value other than its default;
- the cap ``fill * full_well`` and the defaults as the class docstring lists them, and
  the module docstring's numbers (~7e7 e- unattenuated through a 25 cm subaperture and
  0.5" pixels in 1 ms; ~2e6 e- through AO76's 7.5 cm subapertures in 0.4 ms; 15 000 e-
  after the cap, whose photon noise, 122 e-, is 60 times the 2 e- read noise);
- the validation rules and messages as ``__post_init__``'s contract states them
  (finite numbers > 0, fractions <= 1, a read noise >= 0), each at its boundary, in the
  words of ``modalinfo.common.validation.check_real``'s contract (TypeError for what is
  not a real number, "must be finite", "must be > 0.0"; left26-twins).
"""

import math

import pytest
from scipy import constants

from closedloop.optics.photon_budget import PhotonBudget, solar_spectral_radiance

ARCSEC = math.pi / 648_000.0


def _planck(lam, temperature):
    h, c, k = constants.h, constants.c, constants.k
    return 2 * h * c ** 2 / lam ** 5 / (math.exp(h * c / (lam * k * temperature)) - 1.0)


@pytest.mark.parametrize(("lam", "temperature"), [(500e-9, 6300.0), (854e-9, 5800.0),
                                                  (393e-9, 4500.0), (1.56e-6, 7000.0)])
def test_radiance_is_planck(lam, temperature):
    got = solar_spectral_radiance(lam, temperature)
    assert got == pytest.approx(_planck(lam, temperature), rel=1e-12)


def test_radiance_default_temperature_is_6300_k():
    assert solar_spectral_radiance(630e-9) == pytest.approx(_planck(630e-9, 6300.0), rel=1e-12)
    assert PhotonBudget().brightness_temperature == 6300.0


def test_defaults_are_the_documented_ones():
    b = PhotonBudget()
    assert (b.wavelength, b.bandwidth, b.exposure, b.throughput, b.quantum_efficiency,
            b.read_noise, b.full_well, b.fill) == (500e-9, 10e-9, 1e-3, 0.3, 0.6, 2.0,
                                                   30_000.0, 0.5)


def _electrons(lam, band, exposure, area, pixel, throughput, qe, temperature):
    photons = _planck(lam, temperature) * lam / (constants.h * constants.c)
    return photons * band * exposure * area * (pixel * ARCSEC) ** 2 * throughput * qe


def test_unattenuated_electrons_from_the_definition():
    # every factor away from its default, so that each one is seen
    b = PhotonBudget(wavelength=656e-9, bandwidth=0.3e-9, exposure=2.5e-5, throughput=0.45,
                     quantum_efficiency=0.8, read_noise=1.0, full_well=1e9, fill=0.9,
                     brightness_temperature=5900.0)
    want = _electrons(656e-9, 0.3e-9, 2.5e-5, 0.01, 0.37, 0.45, 0.8, 5900.0)
    assert b.unattenuated_electrons(0.01, 0.37) == pytest.approx(want, rel=1e-12)
    # below the cap, the pixel gets all of it
    assert want < 0.9 * 1e9
    assert b.electrons(0.01, 0.37) == pytest.approx(want, rel=1e-12)
    # area linear, pixel scale squared (the solid angle)
    assert b.unattenuated_electrons(0.03, 0.37) == pytest.approx(3 * want, rel=1e-12)
    assert b.unattenuated_electrons(0.01, 0.74) == pytest.approx(4 * want, rel=1e-12)


def test_electrons_are_capped_at_fill_times_full_well():
    b = PhotonBudget(full_well=40_000.0, fill=0.25)
    assert b.unattenuated_electrons(0.0625, 0.5) > 10_000.0
    assert b.electrons(0.0625, 0.5) == 10_000.0
    # exactly at the cap (the unattenuated count itself as the well): the same number
    n = PhotonBudget(exposure=1e-9).unattenuated_electrons(0.0625, 0.5)
    assert PhotonBudget(exposure=1e-9, full_well=n, fill=1.0).electrons(0.0625, 0.5) == n


def test_module_docstring_numbers():
    # ~7e7 e- through a 25 cm subaperture (0.0625 m^2), 0.5" pixels, 1 ms, defaults
    n = PhotonBudget().unattenuated_electrons(0.25 ** 2, 0.5)
    assert 6.5e7 < n < 7.5e7
    # AO76: 7.5 cm subapertures, 0.4 ms: "still ~2e6" (one significant figure)
    n76 = PhotonBudget(exposure=0.4e-3).unattenuated_electrons(0.075 ** 2, 0.5)
    assert 1.5e6 < n76 < 2.5e6
    # capped at 0.5 x 30 000 = 15 000 e-: photon noise 122 e-, 60 times the read noise
    b = PhotonBudget()
    assert b.electrons(0.25 ** 2, 0.5) == 15_000.0
    assert round(math.sqrt(b.electrons(0.25 ** 2, 0.5))) == 122
    assert round(math.sqrt(b.electrons(0.25 ** 2, 0.5)) / b.read_noise) == 61


POSITIVE = ("wavelength", "bandwidth", "exposure", "throughput", "quantum_efficiency",
            "full_well", "fill", "brightness_temperature")


def _refusal(name: str, bad, rule: str) -> tuple[type, str]:
    """The exception and message of ``validation.check_real``'s contract (left26-twins).

    Not a real number (bool, str, None): TypeError; nan / inf: "must be finite";
    out of range: the rule and the value as a float.
    """
    if isinstance(bad, bool) or not isinstance(bad, int | float):
        return TypeError, f"`{name}` must be a real number; got {bad!r}."
    if not math.isfinite(bad):
        return ValueError, f"`{name}` must be finite; got {bad}."
    return ValueError, f"`{name}` must be {rule}; got {float(bad)}."


@pytest.mark.parametrize("name", POSITIVE)
@pytest.mark.parametrize("bad", [0.0, -1.0, 0, float("nan"), float("inf"), True, "1", None])
def test_positive_finite_rule(name, bad):
    kind, message = _refusal(name, bad, "> 0.0")
    with pytest.raises(kind) as exc:
        PhotonBudget(**{name: bad})
    assert str(exc.value) == message


@pytest.mark.parametrize("name", [n for n in POSITIVE if n != "wavelength"])
def test_small_positive_values_and_ints_are_accepted(name):
    assert getattr(PhotonBudget(**{name: 1e-300}), name) == 1e-300
    assert getattr(PhotonBudget(**{name: 1}), name) == 1


@pytest.mark.parametrize("name", ("throughput", "quantum_efficiency", "fill"))
def test_fractions_are_at_most_one(name):
    assert getattr(PhotonBudget(**{name: 1.0}), name) == 1.0
    with pytest.raises(ValueError) as exc:
        PhotonBudget(**{name: 1.0000001})
    assert str(exc.value) == f"`{name}` must be <= 1; got 1.0000001."


@pytest.mark.parametrize("name", ("bandwidth", "exposure", "full_well",
                                  "brightness_temperature"))
def test_other_quantities_may_exceed_one(name):
    assert getattr(PhotonBudget(**{name: 2.5}), name) == 2.5


@pytest.mark.parametrize("bad", [500, 2.5, 1e-300, 299e-9, 29e-6])
def test_wavelength_is_metres_in_the_solar_range(bad):
    # 500 (nm meant) was read as 500 m: a radiance 2e-35 of the true one, no error (audit 9)
    assert PhotonBudget(wavelength=300e-9).wavelength == 300e-9
    assert PhotonBudget(wavelength=28e-6).wavelength == 28e-6
    match = r"`wavelength` must be in \[300 nm, 28 um\] \(in metres"
    with pytest.raises(ValueError, match=match):
        PhotonBudget(wavelength=bad)
    with pytest.raises(ValueError, match=match):
        solar_spectral_radiance(bad)


@pytest.mark.parametrize("bad", [0.0, -5800.0, float("inf"), float("nan"), "5800"])
def test_radiance_needs_a_positive_temperature(bad):
    # 0 K was a ZeroDivisionError, -5800 K a negative radiance
    kind, message = _refusal("brightness_temperature", bad, "> 0.0")
    with pytest.raises(kind) as exc:
        solar_spectral_radiance(630e-9, bad)
    assert str(exc.value) == message


@pytest.mark.parametrize(("area", "pixel"), [(-0.01, 0.5), (0.01, 0.0), (float("nan"), 0.5)])
def test_electrons_need_a_positive_area_and_pixel(area, pixel):
    # a negative area gave negative electrons
    name, bad = ("pixel_scale_arcsec", pixel) if area == 0.01 else ("subaperture_area", area)
    with pytest.raises(ValueError) as exc:
        PhotonBudget().unattenuated_electrons(area, pixel)
    assert str(exc.value) == _refusal(name, bad, "> 0.0")[1]


def test_read_noise_rule():
    assert PhotonBudget(read_noise=0.0).read_noise == 0.0
    assert PhotonBudget(read_noise=3).read_noise == 3
    # a bool is not a noise (True was used as 1 e-), nor is an infinite one
    for bad in (-1e-9, float("nan"), float("inf"), True, "2", None):
        kind, message = _refusal("read_noise", bad, ">= 0.0")
        with pytest.raises(kind) as exc:
            PhotonBudget(read_noise=bad)
        assert str(exc.value) == message
