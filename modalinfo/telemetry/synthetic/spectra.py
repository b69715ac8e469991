"""Open-loop turbulence telemetry: temporal spectra of Zernike modes and their synthesis.

Seeded time series of Noll-indexed Zernike coefficients whose zero-lag covariance and
temporal spectra follow turbulence theory (:func:`open_loop_log`, :func:`open_loop_psd`).
The closed loop run on them is ``modalinfo.telemetry.synthetic.closed_loop``.

What is exact and what is approximate
-------------------------------------
*Exact (in expectation, for every seed and record length)*

- Zero-lag covariance of :func:`open_loop_log`: ``sum_l (D/r0_l)**(5/3) C`` where ``C`` is
  :func:`modalinfo.bases.zernike_covariance` (Noll 1976 / von Karman, units
  ``(D/r0)**(5/3) rad^2``) and ``r0_l`` is the Fried parameter of layer ``l`` at the log's
  wavelength. Each unit series is normalised from its *discrete* spectrum, so
  ``E[x_t x_t^T]`` equals the target to rounding, not only asymptotically.
- Gaussian statistics (a linear filter of Gaussian white noise).

*Approximate (by construction; documented so that nobody mistakes it for frozen flow)*

- Temporal spectra. Each layer drives, for each mode, an independent unit-variance
  series whose power spectral density (PSD) is the two-power-law asymptote of Conan,
  Rousset & Madec (1995, JOSA A 12, 1559) for the mode's radial order ``n``: with the
  cutoff ``f_c = 0.3 (n + 1) v / D``,

  - ``n = 1`` (tip/tilt): ``PSD ~ f**(-2/3)`` for ``f < f_c``;
  - ``n >= 2``: ``PSD`` flat for ``f < f_c``;
  - all orders: ``PSD ~ f**(-17/3)`` for ``f > f_c``;

  continuous at ``f_c`` (a sharp corner, where the real spectra have a smooth knee and,
  for ``n >= 2``, a bump). With a finite outer scale ``L0`` the tip/tilt spectrum is made
  flat below ``f_0 = v / L0`` (a heuristic for the von Karman low-frequency saturation;
  the constant is not from the paper). The true frozen-flow spectra depend on the wind
  direction (tilt along the wind differs from tilt across it) and modes are
  cross-correlated at non-zero lags; here the two tilts have the same spectrum, there is
  no wind direction, and the cross-spectra of modes are real (no lag structure).
- Spatial mixing. The zero-lag covariance is imposed with the lower Cholesky factor
  ``L`` of ``C`` computed with the modes sorted by Noll index: ``x = L e``. ``C`` only
  couples modes with equal signed ``m`` (e.g. Z2-Z8-Z16, Z4-Z11-Z22), so the lowest mode
  of each coupled family keeps the pure spectrum of its radial order, and a higher mode
  ``j`` gets the mixture ``PSD_j(f) = sum_k L[j, k]**2 S_{n_k}(f)``: e.g. Z8 (coma)
  carries ``rho**2 = 0.072`` of its variance with the tip/tilt spectrum shape
  (``rho = -0.27`` for Kolmogorov turbulence) and the rest with the ``n = 3`` shape.
- Spectral resolution. Series are made by FFT filtering of white noise over twice the
  record (then cropped, so that the record is not periodic). Power below the lowest
  resolved frequency ``1 / (2 T)`` is not represented: the normalisation puts the whole
  variance on the resolved band ``(0, rate/2]`` (the zero-frequency bin is zero), so for
  a short record the tip/tilt spectrum is raised compared with the continuous model
  (:func:`open_loop_psd` gives both). For the 4.1 s of :func:`kaos_like` the factor is
  1.04 / 1.02 for its 5 / 10 m/s layers with L0 = 20 m, but 1.30 / 1.23 with
  ``L0 = inf`` (the Kolmogorov tip/tilt spectrum ``f**(-2/3)`` converges slowly); for
  ``n >= 2`` it is below 1.01. No power above the Nyquist frequency is generated (no
  aliasing).

References
----------
Noll, R. J. 1976, JOSA 66, 207. Conan, J.-M., Rousset, G. & Madec, P.-Y. 1995, JOSA A 12,
1559. Madec, P.-Y. 1999, in Adaptive Optics in Astronomy (Roddier ed.), ch. 6.
"""

from __future__ import annotations

import dataclasses
import numbers
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy import fft as sfft

from modalinfo.bases import noll_to_zernike, zernike_covariance
from modalinfo.bases.turbulence import check_outer_scale
from modalinfo.common.validation import (
    check_int,
    check_memory,
    check_r0,
    check_rate,
    check_real,
    check_rng,
    check_telescope_diameter,
    check_wind_speed,
    seed_record,
)
from modalinfo.telemetry.log import ModalLog
from modalinfo.telemetry.units import check_wavelength

#: Bytes held per sample and mode while the open-loop series are synthesised (white
#: noise, its half spectrum and the filtered series on the 2T FFT grid, float64)
FFT_BYTES_PER_SAMPLE = 64

__all__ = ["Layer", "open_loop_log", "open_loop_psd"]

#: Reference wavelength of ``Layer.r0`` by default (m).
_R0_WAVELENGTH = 500e-9
_CUTOFF_FACTOR = 0.3  # f_c = 0.3 (n + 1) v / D (Conan et al. 1995)
_LOW_SLOPE_TILT = -2.0 / 3.0
_HIGH_SLOPE = -17.0 / 3.0


# ---------------------------------------------------------------------------- layers
@dataclass(frozen=True)
class Layer:
    """One frozen-flow turbulent layer: its strength and wind speed.

    Give the strength as ``r0`` (metres) or as ``d_over_r0`` (``D / r0``, dimensionless,
    for the telescope diameter passed to the generator); both are quoted at
    ``r0_wavelength`` and scaled as ``lambda**(6/5)`` to the wavelength of the log.

    Parameters
    ----------
    r0 : float or None
        Fried parameter of this layer alone [m] at ``r0_wavelength``. Several layers
        combine as ``r0**(-5/3) = sum_l r0_l**(-5/3)``. Scaled to 500 nm it must be
        >= 1 mm (seeing of 100"); above 1 m (more than any site: 2-20 cm typical,
        0.3 m exceptional) a ``UserWarning`` asks whether centimetres were typed as
        metres, since a weak layer of a many-layer profile may have such an r0.
    wind_speed : float
        Wind speed [m/s], in (0, 100]: jet-stream cores blow at 30-70 m/s, rarely 100;
        a faster value is km/h or mph typed as m/s. Sets the temporal cutoffs
        ``0.3 (n + 1) v / D``.
    d_over_r0 : float or None
        ``D / r0`` of this layer at ``r0_wavelength`` (instead of ``r0``).
    r0_wavelength : float
        Wavelength [m] at which ``r0`` / ``d_over_r0`` are quoted. Default 500 nm.
    """

    r0: float | None
    wind_speed: float
    d_over_r0: float | None = None
    r0_wavelength: float = _R0_WAVELENGTH

    def __post_init__(self) -> None:
        if (self.r0 is None) == (self.d_over_r0 is None):
            raise ValueError(
                "Layer needs exactly one of `r0` (m) and `d_over_r0`; got "
                f"r0={self.r0!r}, d_over_r0={self.d_over_r0!r}."
            )
        object.__setattr__(
            self,
            "r0_wavelength",
            check_wavelength(self.r0_wavelength, "r0_wavelength"),
        )
        if self.r0 is not None:  # r0 scaled to 500 nm within 1 mm - 1 m (beyond: warned)
            object.__setattr__(self, "r0", check_r0(self.r0, "r0", self.r0_wavelength))
        else:
            object.__setattr__(
                self,
                "d_over_r0",
                check_real(self.d_over_r0, "d_over_r0", minimum=0.0, strict_min=True),
            )
        object.__setattr__(self, "wind_speed", check_wind_speed(self.wind_speed))

    def d_over_r0_at(self, diameter: float, wavelength: float) -> float:
        """Return ``D / r0`` of this layer at ``wavelength`` [m] for a ``diameter`` [m] pupil.

        Both are checked as everywhere in this module (``check_telescope_diameter``,
        ``check_wavelength``): 500 for 500 nm gave 1.3e-9, -8 m a negative ``D / r0``
        (round 41 PART a).
        """
        diameter = check_telescope_diameter(diameter)
        wavelength = check_wavelength(wavelength)
        scale = (wavelength / self.r0_wavelength) ** (6.0 / 5.0)
        if self.r0 is not None:
            return diameter / (self.r0 * scale)
        return self.d_over_r0 / scale

    def to_dict(self) -> dict:
        """Return the fields as a JSON-serialisable dict."""
        return dataclasses.asdict(self)


def _check_layers(layers: Any) -> tuple[Layer, ...]:
    if isinstance(layers, Layer):
        return (layers,)
    if isinstance(layers, dict):
        return (Layer(**layers),)
    if not isinstance(layers, Sequence) or isinstance(layers, str) or len(layers) == 0:
        raise TypeError(
            f"`layers` must be a Layer or a non-empty sequence of Layer; got {layers!r}."
        )
    out = []
    for i, layer in enumerate(layers):
        if isinstance(layer, dict):
            layer = Layer(**layer)
        if not isinstance(layer, Layer):
            raise TypeError(f"`layers[{i}]` must be a Layer; got {layer!r}.")
        out.append(layer)
    return tuple(out)


def _check_modes(modes: Any) -> list[int]:
    if isinstance(modes, numbers.Integral) and not isinstance(modes, bool):
        modes = [modes]
    try:
        mode_list = [m for m in modes]
    except TypeError:
        raise TypeError(f"`modes` must be a sequence of Noll indices; got {modes!r}.") from None
    if not mode_list:
        raise ValueError("`modes` must hold at least one Noll index; got an empty sequence.")
    out = []
    for m in mode_list:
        if isinstance(m, bool) or not isinstance(m, numbers.Integral):
            raise TypeError(f"`modes` must hold int Noll indices; got {m!r}.")
        if m < 2:
            raise ValueError(
                f"`modes` must be Noll indices >= 2 (piston is not generated); got {int(m)}."
            )
        out.append(int(m))
    if len(set(out)) != len(out):
        raise ValueError(f"`modes` must not repeat a mode; got {out}.")
    return out


# ------------------------------------------------------------------ temporal spectra
def _psd_shape(freqs: np.ndarray, radial_order: int, wind_speed: float, diameter: float,
               outer_scale: float) -> np.ndarray:
    """Un-normalised asymptotic PSD shape of a radial order (Conan et al. 1995).

    Preconditions: ``freqs > 0`` [Hz]; returns the shape, 1 at the cutoff.
    """
    f_c = _CUTOFF_FACTOR * (radial_order + 1) * wind_speed / diameter
    x = freqs / f_c
    out = np.where(x > 1.0, x**_HIGH_SLOPE, 1.0)
    if radial_order == 1:
        f_0 = wind_speed / outer_scale if np.isfinite(outer_scale) else 0.0
        low = np.maximum(freqs, min(f_0, f_c)) / f_c
        out = np.where(x > 1.0, out, low**_LOW_SLOPE_TILT)
    return out


def _unit_filters(n_fft: int, sample_rate: float, radial_orders: Sequence[int],
                  wind_speed: float, diameter: float, outer_scale: float) -> dict[int, np.ndarray]:
    """Amplitude responses ``H`` (rfft grid) giving unit-variance series, per radial order.

    The circular filter ``x = irfft(H rfft(w))`` of unit white noise has
    ``Var x_t = sum over the full spectrum of H**2 / n_fft``; ``H`` is scaled so that it
    is exactly 1. The zero-frequency bin is 0.
    """
    freqs = sfft.rfftfreq(n_fft, d=1.0 / sample_rate)
    weights = np.full(freqs.size, 2.0)
    weights[0] = 1.0
    if n_fft % 2 == 0:
        weights[-1] = 1.0
    out = {}
    for n in sorted(set(radial_orders)):
        power = np.zeros(freqs.size)
        power[1:] = _psd_shape(freqs[1:], n, wind_speed, diameter, outer_scale)
        power *= n_fft / np.sum(weights * power)
        out[n] = np.sqrt(power)
    return out


def _mode_model(modes: list[int], outer_scale: float,
                diameter: float) -> tuple[np.ndarray, list[int], np.ndarray]:
    """Spatial model of a mode set, shared by the generator and its PSD.

    Returns the sort order of ``modes`` by Noll index, the radial orders of the sorted
    modes and the Cholesky factor of their Zernike covariance (sorted), in units of
    ``(D/r0)**(5/6) rad``.
    """
    order = np.argsort(modes, kind="stable")
    sorted_modes = [modes[i] for i in order]
    n_radial = [int(n) for n in np.atleast_1d(noll_to_zernike(np.array(sorted_modes)))[0]]
    cov = zernike_covariance(sorted_modes, outer_scale=outer_scale, diameter=diameter)
    return order, n_radial, np.linalg.cholesky(cov)


def _open_loop_array(modes: list[int], n_samples: int, sample_rate: float, diameter: float,
                     layers: tuple[Layer, ...], outer_scale: float, wavelength: float,
                     rng: np.random.Generator) -> np.ndarray:
    """Open-loop coefficients ``(n_samples, M)`` in rad at ``wavelength``.

    Preconditions: arguments validated. Draws ``len(layers) * M * n_fft`` normals from
    ``rng`` in that order (layer, mode sorted by Noll index, time).
    """
    order, n_radial, chol = _mode_model(modes, outer_scale, diameter)
    n_fft = sfft.next_fast_len(2 * n_samples, real=True)
    out = np.zeros((n_samples, len(modes)))
    for layer in layers:
        white = rng.standard_normal((len(modes), n_fft))
        filters = _unit_filters(n_fft, sample_rate, n_radial, layer.wind_speed, diameter,
                                outer_scale)
        spec = sfft.rfft(white, axis=1)
        for i, n in enumerate(n_radial):
            spec[i] *= filters[n]
        unit = sfft.irfft(spec, n=n_fft, axis=1)[:, :n_samples]
        amplitude = layer.d_over_r0_at(diameter, wavelength) ** (5.0 / 6.0)
        out += amplitude * (unit.T @ chol.T)
    result = np.empty_like(out)
    result[:, order] = out
    return result


def _continuous_integral(radial_order: int, wind_speed: float, diameter: float,
                         outer_scale: float) -> float:
    """``integral_0^inf`` of :func:`_psd_shape` [Hz], in closed form."""
    f_c = _CUTOFF_FACTOR * (radial_order + 1) * wind_speed / diameter
    high = 3.0 * f_c / 14.0  # integral_fc^inf (f / fc)**(-17/3) df
    if radial_order != 1:
        return f_c + high
    f_0 = min(wind_speed / outer_scale, f_c) if np.isfinite(outer_scale) else 0.0
    flat = f_0 * (f_0 / f_c) ** _LOW_SLOPE_TILT if f_0 > 0 else 0.0
    return flat + 3.0 * f_c * (1.0 - (f_0 / f_c) ** (1.0 / 3.0)) + high


def open_loop_psd(
    freqs,
    modes: Sequence[int] = range(2, 29),
    *,
    diameter: float,
    layers: Layer | Sequence[Layer],
    outer_scale: float = np.inf,
    wavelength: float = _R0_WAVELENGTH,
    n_frames: int | None = None,
    rate: float | None = None,
) -> np.ndarray:
    """One-sided PSD of the open-loop model of :func:`open_loop_log` [rad^2/Hz].

    ``PSD_j(f) = sum_l (D/r0_l)**(5/3) sum_k L[j, k]**2 S_{n_k, l}(f)`` with ``L`` the
    Cholesky factor of the Zernike covariance (modes sorted by Noll index) and
    ``S_{n, l}`` the unit-variance asymptotic spectrum of radial order ``n`` for the wind
    of layer ``l`` (module docstring).

    Parameters
    ----------
    freqs : array_like, shape (F,)
        Frequencies [Hz], > 0.
    modes, diameter, layers, outer_scale, wavelength
        As in :func:`open_loop_log`.
    n_frames, rate : int and float, optional
        Give both to get the expected spectrum of a record generated with these values:
        the unit spectra are then normalised over the resolved band, as the generator
        does (module docstring), instead of over ``(0, inf)``, and are 0 above
        ``rate / 2``.

    Returns
    -------
    numpy.ndarray, shape (F, M)
        PSD per mode; its integral over ``f > 0`` is the mode's variance.
    """
    f = np.atleast_1d(np.asarray(freqs, dtype=np.float64))
    if f.ndim != 1 or not np.all(np.isfinite(f)) or np.any(f <= 0):
        raise ValueError("`freqs` must be a 1-D array of finite frequencies > 0 Hz.")
    mode_list = _check_modes(modes)
    diameter, outer_scale, wavelength = _check_geometry(diameter, outer_scale, wavelength)
    layer_tuple = _check_layers(layers)
    if (n_frames is None) != (rate is None):
        raise ValueError("`n_frames` and `rate` must be given together (or neither).")
    if n_frames is not None:
        n_frames = check_int(n_frames, "n_frames", minimum=2)
        rate = check_rate(rate)
    order, n_radial, chol = _mode_model(mode_list, outer_scale, diameter)
    weights2 = chol**2
    if n_frames is not None:
        n_fft = sfft.next_fast_len(2 * n_frames, real=True)
        first_bin = sfft.rfftfreq(n_fft, d=1.0 / rate)[1:2]
    out = np.zeros((f.size, len(mode_list)))
    for layer in layer_tuple:
        unit = np.empty((f.size, len(mode_list)))
        if n_frames is not None:
            filters = _unit_filters(n_fft, rate, n_radial, layer.wind_speed, diameter,
                                    outer_scale)
        for i, n in enumerate(n_radial):
            shape = _psd_shape(f, n, layer.wind_speed, diameter, outer_scale)
            if n_frames is None:
                unit[:, i] = shape / _continuous_integral(n, layer.wind_speed, diameter,
                                                          outer_scale)
            else:
                scale = filters[n][1] ** 2 / _psd_shape(first_bin, n, layer.wind_speed,
                                                        diameter, outer_scale)[0]
                unit[:, i] = np.where(f <= rate / 2.0, 2.0 * scale * shape / rate, 0.0)
        strength = layer.d_over_r0_at(diameter, wavelength) ** (5.0 / 3.0)
        out += strength * (unit @ weights2.T)
    result = np.empty_like(out)
    result[:, order] = out
    return result


def _check_geometry(diameter, outer_scale, wavelength):
    diameter = check_telescope_diameter(diameter)  # <= 100 m: m13, diameter=800 (cm)
    outer_scale = check_real(outer_scale, "outer_scale", minimum=0.0, strict_min=True,
                             allow_inf=True)
    wavelength = check_wavelength(wavelength)
    check_outer_scale(outer_scale, diameter)  # closedloop's rule: L0 beyond the pupil
    return diameter, outer_scale, wavelength


def _layers_metadata(layers: tuple[Layer, ...], diameter: float, wavelength: float) -> dict:
    d_over = [layer.d_over_r0_at(diameter, wavelength) for layer in layers]
    total = sum(d**(5.0 / 3.0) for d in d_over) ** (3.0 / 5.0)
    return {
        "layers": [layer.to_dict() for layer in layers],
        "d_over_r0_per_layer": d_over,
        "d_over_r0": total,
        "r0_m": diameter / total,
    }


def open_loop_log(
    modes: Sequence[int] = range(2, 29),
    *,
    n_frames: int,
    rate: float,
    diameter: float,
    layers: Layer | Sequence[Layer],
    outer_scale: float = np.inf,
    wavelength: float = _R0_WAVELENGTH,
    seed: int | np.random.Generator | None = None,
) -> ModalLog:
    """Synthetic open-loop Zernike coefficients of multi-layer frozen-flow turbulence.

    Spatial statistics are exact in expectation (Kolmogorov or von Karman Zernike
    covariance); temporal spectra follow the asymptotes of Conan et al. (1995). The
    construction and what is approximate are described in the module docstring.

    Parameters
    ----------
    modes : sequence of int
        Noll indices (>= 2) of the columns, in the order wanted. Default Z2..Z28.
    n_frames : int
        Number of samples T (>= 2).
    rate : float
        Sample rate [Hz], within 1 mHz - 1 MHz; below 1 Hz or above 100 kHz (no
        wavefront sensor) the log's ``UserWarning`` (see ``ModalLog``).
    diameter : float
        Pupil diameter D [m], in (0, 100] (the ELT is 39 m; a larger value is
        centimetres typed as metres).
    layers : Layer or sequence of Layer
        Turbulent layers, each with its own ``r0`` and wind speed.
    outer_scale : float
        von Karman outer scale L0 [m]; ``np.inf`` for Kolmogorov.
    wavelength : float
        Wavelength [m] at which the phase coefficients are given (rad).
    seed : None, int or numpy.random.Generator
        Randomness; same seed, same numbers.

    Returns
    -------
    ModalLog
        Coefficients ``(T, M)`` in rad at ``wavelength``, Noll convention, with the
        generator parameters in ``metadata``.

    Raises
    ------
    TypeError, ValueError
        Invalid argument (the message names it).
    """
    mode_list = _check_modes(modes)
    n_frames = check_int(n_frames, "n_frames", minimum=2)
    rate = check_rate(rate, warn=False)  # refused here; warned once, by the ModalLog
    diameter, outer_scale, wavelength = _check_geometry(diameter, outer_scale, wavelength)
    layer_tuple = _check_layers(layers)
    # white noise, its spectrum and the filtered series, ~ 2 T x M floats each; without
    # this n_frames = 2**70 raised OverflowError in numpy (adversarial round 18, q63)
    check_memory(FFT_BYTES_PER_SAMPLE * n_frames * len(mode_list), "n_frames", n_frames,
                 "the open-loop series and their spectra")
    generator_seed = seed_record(seed)  # np.int64, a 0-d array: their int (JSON)
    rng = check_rng(seed)
    coeffs = _open_loop_array(mode_list, n_frames, rate, diameter, layer_tuple, outer_scale,
                              wavelength, rng)
    metadata = {
        "source": "modalinfo.telemetry.synthetic.open_loop_log",
        "synthetic": True,
        "loop": "open",
        "diameter_m": diameter,
        "outer_scale_m": None if not np.isfinite(outer_scale) else outer_scale,
        "wavelength_m": wavelength,
        "rate_hz": rate,
        "seed": generator_seed,
        **_layers_metadata(layer_tuple, diameter, wavelength),
    }
    return ModalLog(coeffs, rate=rate, modes=mode_list, convention="noll", units="rad",
                    wavelength=wavelength, metadata=metadata)


