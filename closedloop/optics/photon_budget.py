"""The photon budget of a solar wavefront sensor's pixel: the Sun's radiance, the detector.

The disc-centre continuum is taken as a blackbody at the brightness
temperature ``T_b`` (default 6300 K; the visible disc-centre continuum of Neckel & Labs
1984 has ``T_b`` ~ 6200-6400 K). Through a 25 cm subaperture (table1's ground WFS), 0.5"
pixels, 10 nm, 1 ms, throughput 0.3 and QE 0.6 that is ~7e7 photo-electrons per pixel, and
through the 7.5 cm subapertures of the DST's AO76 at its 2500 frames/s (0.4 ms) still
~2e6: far more than a detector well holds. Solar WFSs attenuate (neutral density, a
beam-splitter fraction: DKIST feeds its WFSs with 4 %) to run near full well, so their
noise is the photon noise of the well, not of the Sun ("photon noise dominates, detector
noise is not an issue; CCDs with large wells are preferred", NSO's ATST AO design), and
the slope noise is set by the contrast of the subaperture image, 1-3 % on granulation
(Rimmele & Marino 2011, Living Rev. Sol. Phys. 8, 2, Sect. 2.3; Michau et al. 1992). The
budget therefore caps the mean signal at ``fill * full_well`` (defaults 0.5 x 30 000 e-;
read noise 2 e-) and records the attenuation it needed: at 15 000 e- the photon noise
(122 e-) is 60 times the read noise, so the well and the fill set the noise and the read-noise
default hardly matters. The 0.5" pixel is the sampling of AO76's correlating SH (20x20
pixels over a 10"x10" field per subaperture; Rimmele & Marino 2011, Sect. 4-5), whose
field is the usual 10-12" of solar SHs (Berkefeld et al. on GREGOR's 9.2 cm subapertures).
The 1 ms exposure is table1's frame time; the 2-2.5 kHz systems (AO76, SST, DKIST) expose
at most 0.4-0.5 ms, which changes nothing once the signal is capped. Not taken from a
design (no published figure was reachable here): the 10 nm bandwidth, the throughput, the
QE, the 30 000 e- well and the 2 e- read noise. The designs and their sources:
``docs/CLOSEDLOOP.md``, "Solar WFS designs behind the photon budget".
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

from closedloop.config import WAVELENGTH_RANGE
from modalinfo.common.validation import as_scalar

__all__ = ["PhotonBudget", "solar_spectral_radiance"]

_H = 6.62607015e-34   # Planck [J s]
_C = 2.99792458e8     # speed of light [m/s]
_K = 1.380649e-23     # Boltzmann [J/K]
_ARCSEC = math.pi / (180.0 * 3600.0)

def _check_wavelength(wavelength) -> None:
    """Refuse a wavelength outside the ground-based solar range (config.WAVELENGTH_RANGE).

    500 (nanometres meant, metres read) gave a radiance 2e-35 of the true one, and a
    PhotonBudget of a few electrons, without a word (audit 9).
    """
    low, high = WAVELENGTH_RANGE
    if isinstance(wavelength, bool) or not isinstance(wavelength, numbers.Real) \
            or not low <= wavelength <= high:
        raise ValueError(f"`wavelength` must be in [{low * 1e9:g} nm, {high * 1e6:g} um] "
                         f"(in metres: the ground-based solar range); got {wavelength!r}.")


def solar_spectral_radiance(wavelength: float, brightness_temperature: float = 6300.0) -> float:
    """Return the disc-centre continuum radiance as a blackbody [W m^-2 sr^-1 m^-1].

    Parameters
    ----------
    wavelength : float
        [m], in ``closedloop.config.WAVELENGTH_RANGE`` (300 nm - 28 um).
    brightness_temperature : float
        [K], > 0.
    """
    # a 0-d array is its number (validation.as_scalar; left25-api)
    wavelength, brightness_temperature = as_scalar(wavelength), as_scalar(brightness_temperature)
    _check_wavelength(wavelength)
    if isinstance(brightness_temperature, bool) or not isinstance(
            brightness_temperature, numbers.Real) or not 0 < brightness_temperature < math.inf:
        raise ValueError(f"`brightness_temperature` must be a finite number of kelvin > 0; "
                         f"got {brightness_temperature!r}.")
    x = _H * _C / (wavelength * _K * brightness_temperature)
    return 2.0 * _H * _C ** 2 / wavelength ** 5 / math.expm1(x)


@dataclass(frozen=True)
class PhotonBudget:
    """Photons reaching one WFS pixel per exposure, and the detector's noise.

    Attributes
    ----------
    wavelength : float
        Centre of the WFS band [m] (default 500 nm).
    bandwidth : float
        Filter width [m] (default 10 nm).
    exposure : float
        Exposure [s] (default 1 ms, table1's integration time).
    throughput : float
        Telescope, relay and WFS optics to the detector, before any attenuation (0.3).
    quantum_efficiency : float
        Detector QE (0.6).
    read_noise : float
        [e- rms per pixel] (2).
    full_well : float
        [e-] (30 000).
    fill : float
        Mean signal as a fraction of the full well the attenuation aims at (0.5).
    brightness_temperature : float
        Disc-centre continuum brightness temperature [K] (6300).
    """

    wavelength: float = 500e-9
    bandwidth: float = 10e-9
    exposure: float = 1e-3
    throughput: float = 0.3
    quantum_efficiency: float = 0.6
    read_noise: float = 2.0
    full_well: float = 30_000.0
    fill: float = 0.5
    brightness_temperature: float = 6300.0

    def __post_init__(self):
        for name in ("wavelength", "bandwidth", "exposure", "throughput",
                     "quantum_efficiency", "full_well", "fill", "brightness_temperature"):
            v = as_scalar(getattr(self, name))  # a 0-d array is its number
            if not isinstance(v, numbers.Real) or isinstance(v, bool) or not v > 0 \
                    or not math.isfinite(v):
                raise ValueError(f"`{name}` must be a finite number > 0; got {v!r}.")
            # Python floats in the frozen fields: records and metadata hold plain numbers
            object.__setattr__(self, name, float(v))
        _check_wavelength(self.wavelength)
        for name in ("throughput", "quantum_efficiency", "fill"):
            if getattr(self, name) > 1.0:
                raise ValueError(f"`{name}` must be <= 1; got {getattr(self, name)!r}.")
        v = as_scalar(self.read_noise)
        if not isinstance(v, numbers.Real) or isinstance(v, bool) or not v >= 0 \
                or not math.isfinite(v):
            raise ValueError(f"`read_noise` must be a finite number >= 0; got {v!r}.")
        object.__setattr__(self, "read_noise", float(v))

    def unattenuated_electrons(self, subaperture_area: float, pixel_scale_arcsec: float) -> float:
        """Mean photo-electrons per pixel without attenuation.

        Parameters
        ----------
        subaperture_area : float
            [m^2].
        pixel_scale_arcsec : float
            [arcsec].
        """
        subaperture_area, pixel_scale_arcsec = as_scalar(subaperture_area), as_scalar(
            pixel_scale_arcsec)  # a 0-d array is its number (left25-api)
        for name, v in (("subaperture_area", subaperture_area),
                        ("pixel_scale_arcsec", pixel_scale_arcsec)):
            if isinstance(v, bool) or not isinstance(v, numbers.Real) or not 0 < v < math.inf:
                raise ValueError(f"`{name}` must be a finite number > 0; got {v!r}.")
        radiance = solar_spectral_radiance(self.wavelength, self.brightness_temperature)
        photon_radiance = radiance * self.wavelength / (_H * _C)  # photons s^-1 m^-2 sr^-1 m^-1
        omega = (pixel_scale_arcsec * _ARCSEC) ** 2
        return (photon_radiance * self.bandwidth * self.exposure * subaperture_area * omega
                * self.throughput * self.quantum_efficiency)

    def electrons(self, subaperture_area: float, pixel_scale_arcsec: float) -> float:
        """Mean photo-electrons per pixel: unattenuated, capped at ``fill * full_well``."""
        return min(self.unattenuated_electrons(subaperture_area, pixel_scale_arcsec),
                   self.fill * self.full_well)
