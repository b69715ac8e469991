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
from dataclasses import dataclass

from closedloop.config import WAVELENGTH_RANGE
from modalinfo.common.validation import check_real

__all__ = ["PhotonBudget", "solar_spectral_radiance"]

_H = 6.62607015e-34   # Planck [J s]
_C = 2.99792458e8     # speed of light [m/s]
_K = 1.380649e-23     # Boltzmann [J/K]
_ARCSEC = math.pi / (180.0 * 3600.0)

def _check_wavelength(wavelength) -> float:
    """Refuse a wavelength outside the ground-based solar range (config.WAVELENGTH_RANGE).

    500 (nanometres meant, metres read) gave a radiance 2e-35 of the true one, and a
    PhotonBudget of a few electrons, without a word (audit 9).
    """
    low, high = WAVELENGTH_RANGE
    wavelength = check_real(wavelength, "wavelength")  # type and finiteness: the one copy
    if not low <= wavelength <= high:
        raise ValueError(f"`wavelength` must be in [{low * 1e9:g} nm, {high * 1e6:g} um] "
                         f"(in metres: the ground-based solar range); got {wavelength!r}.")
    return wavelength


def solar_spectral_radiance(wavelength: float, brightness_temperature: float = 6300.0) -> float:
    """Return the disc-centre continuum radiance as a blackbody [W m^-2 sr^-1 m^-1].

    Parameters
    ----------
    wavelength : float
        [m], in ``closedloop.config.WAVELENGTH_RANGE`` (300 nm - 28 um).
    brightness_temperature : float
        [K], > 0.
    """
    # validation.check_real: a 0-d array is its number; bool, complex, inf, nan refused
    wavelength = _check_wavelength(wavelength)
    brightness_temperature = check_real(brightness_temperature, "brightness_temperature",
                                        minimum=0.0, strict_min=True)
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
        # validation.check_real (the one copy): a 0-d array or NumPy scalar is its number,
        # bool / complex / str refused (TypeError), nan / inf and <= 0 refused (ValueError);
        # it returns Python floats, kept in the frozen fields (records, JSON compare them)
        for name in ("wavelength", "bandwidth", "exposure", "throughput",
                     "quantum_efficiency", "full_well", "fill", "brightness_temperature"):
            object.__setattr__(self, name, check_real(getattr(self, name), name,
                                                      minimum=0.0, strict_min=True))
        _check_wavelength(self.wavelength)
        for name in ("throughput", "quantum_efficiency", "fill"):
            if getattr(self, name) > 1.0:
                raise ValueError(f"`{name}` must be <= 1; got {getattr(self, name)!r}.")
        object.__setattr__(self, "read_noise",
                           check_real(self.read_noise, "read_noise", minimum=0.0))

    def unattenuated_electrons(self, subaperture_area: float, pixel_scale_arcsec: float) -> float:
        """Mean photo-electrons per pixel without attenuation.

        Parameters
        ----------
        subaperture_area : float
            [m^2].
        pixel_scale_arcsec : float
            [arcsec].
        """
        subaperture_area = check_real(subaperture_area, "subaperture_area", minimum=0.0,
                                      strict_min=True)
        pixel_scale_arcsec = check_real(pixel_scale_arcsec, "pixel_scale_arcsec", minimum=0.0,
                                        strict_min=True)
        radiance = solar_spectral_radiance(self.wavelength, self.brightness_temperature)
        photon_radiance = radiance * self.wavelength / (_H * _C)  # photons s^-1 m^-2 sr^-1 m^-1
        omega = (pixel_scale_arcsec * _ARCSEC) ** 2
        return (photon_radiance * self.bandwidth * self.exposure * subaperture_area * omega
                * self.throughput * self.quantum_efficiency)

    def electrons(self, subaperture_area: float, pixel_scale_arcsec: float) -> float:
        """Mean photo-electrons per pixel: unattenuated, capped at ``fill * full_well``."""
        return min(self.unattenuated_electrons(subaperture_area, pixel_scale_arcsec),
                   self.fill * self.full_well)
