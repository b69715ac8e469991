"""The servo model of a per-mode integrator loop: one model for every part of the package.

A wavefront sensor (WFS) integrates the residual over ``integration_frames`` frame
periods ending at ``t_k = (k + 1) T``; the integrator ``c[k] = c[k-1] + g m[k]`` (with an
optional leak) computes a command that the deformable mirror holds (zero-order hold)
from ``t_k + delay_frames T`` until the next one replaces it. Because the command is
piecewise constant, the WFS sees a fixed combination of past commands,
``(W c)_k = sum_j w_j c[k-j]`` with ``w_j`` (:func:`command_weights`) the fraction of the
integration window during which ``c[k-j]`` is applied, and the sampled loop is exactly

    m = (y + n) (1 - z**-1) / (1 - z**-1 + g W(z)),   W(z) = sum_j w_j z**-j,

with ``y`` the open-loop WFS measurement and ``n`` the WFS noise. From it:

- :func:`rejection_transfer_function` ``E = (1 - z**-1) / (1 - z**-1 + g W)``
  (measured residual over open-loop turbulence);
- :func:`noise_transfer_function` ``N = g / (1 - z**-1 + g W)`` (command over WFS
  noise), and :func:`noise_propagation` its mean square over the band;
- :func:`max_stable_gain`, :func:`closed_loop_bandwidth`, :func:`gain_for_bandwidth`.

:mod:`modalinfo.telemetry.synthetic` (spectral telemetry) and the MCAO simulator
``closedloop`` both use these functions, so the loop they simulate is the loop analysed
here. Reference: Madec, P.-Y. 1999, in *Adaptive Optics in Astronomy* (Roddier ed.), ch. 6.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize, signal

from modalinfo._validation import as_float_array, check_choice, check_real

__all__ = [
    "LoopBandwidth",
    "check_loop",
    "command_weights",
    "loop_denominator",
    "check_stable",
    "max_stable_gain",
    "rejection_transfer_function",
    "noise_transfer_function",
    "noise_propagation",
    "closed_loop_bandwidth",
    "gain_for_bandwidth",
]

_MODELS = ("sampled", "continuous")
_DEFINITIONS = ("rejection_0db", "closed_loop_3db")


def check_loop(gain, delay_frames, integration_frames) -> tuple[float, float, float]:
    """Validate the loop parameters and return them as floats.

    ``gain`` > 0, ``delay_frames`` >= 0 and ``integration_frames`` in (0, 1]; a bad
    value raises ``ValueError`` naming it.
    """
    gain = check_real(gain, "gain", minimum=0.0, strict_min=True)
    delay_frames = check_real(delay_frames, "delay_frames", minimum=0.0)
    integration_frames = check_real(integration_frames, "integration_frames", minimum=0.0,
                                    maximum=1.0, strict_min=True)
    return gain, delay_frames, integration_frames


def command_weights(delay_frames: float, integration_frames: float) -> np.ndarray:
    """``w_j``: fraction of frame k's integration window during which ``c[k-j]`` is applied.

    Frame ``k`` integrates over ``[-iota, 0]`` (frame units, relative to its end);
    command ``c[k-j]`` is applied on ``[delta - j, delta - j + 1)``. ``w[0] = 0`` since
    ``delta >= 0``; the weights sum to 1.
    """
    delta, iota = delay_frames, integration_frames
    n = int(math.floor(delta + iota)) + 2
    j = np.arange(n, dtype=np.float64)
    lo = np.maximum(delta - j, -iota)
    hi = np.minimum(delta - j + 1.0, 0.0)
    w = np.clip(hi - lo, 0.0, None) / iota
    w[np.abs(w) < 1e-15] = 0.0
    last = np.flatnonzero(w)[-1]
    return w[: last + 1]


def loop_denominator(gain: float, weights: np.ndarray) -> np.ndarray:
    """Coefficients ``a`` of ``1 - z**-1 + g W(z)`` in powers of ``z**-1``."""
    a = gain * np.concatenate([weights, np.zeros(max(0, 2 - weights.size))])
    a[0] += 1.0
    a[1] -= 1.0
    return a


def _pole_radius(gain: float, delay_frames: float, integration_frames: float) -> float:
    a = loop_denominator(gain, command_weights(delay_frames, integration_frames))
    a = np.trim_zeros(a, "b")
    if a.size < 2:
        return 0.0
    return float(np.max(np.abs(np.roots(a))))


def max_stable_gain(delay_frames: float = 1.0, integration_frames: float = 1.0) -> float:
    """Largest integrator gain for which the sampled loop is stable.

    Parameters
    ----------
    delay_frames : float
        Delay between the end of the WFS integration and the command update [frames].
    integration_frames : float
        WFS integration time [frames], in (0, 1].

    Returns
    -------
    float
        Gain at which the largest closed-loop pole reaches the unit circle (to 1e-10).
    """
    _, delay_frames, integration_frames = check_loop(1.0, delay_frames, integration_frames)

    def excess(g):
        return _pole_radius(g, delay_frames, integration_frames) - 1.0

    hi = 1.0
    while excess(hi) < 0.0:
        hi *= 2.0
    lo = 1e-9
    return float(optimize.brentq(excess, lo, hi, xtol=1e-12))


def check_stable(gain: float, delay_frames: float, integration_frames: float) -> None:
    """Raise ``ValueError`` (with the stability limit) if the sampled loop is unstable."""
    radius = _pole_radius(gain, delay_frames, integration_frames)
    if radius >= 1.0 - 1e-12:
        limit = max_stable_gain(delay_frames, integration_frames)
        raise ValueError(
            f"`gain` = {gain} makes the loop unstable (largest closed-loop pole modulus "
            f"{radius:.4f} >= 1) for delay_frames={delay_frames}, "
            f"integration_frames={integration_frames}; the loop is stable for gain < "
            f"{limit:.4f}."
        )


def rejection_transfer_function(
    freqs,
    *,
    rate: float,
    gain: float,
    delay_frames: float,
    integration_frames: float = 1.0,
    model: str = "sampled",
) -> np.ndarray:
    """Rejection transfer function of the modal integrator loop.

    ``E(f) = 1 / (1 + g W(z) / (1 - z**-1))`` with ``z = exp(2 i pi f / rate)``: residual
    over open-loop turbulence. The closed-loop transfer function (correction over
    turbulence) is ``1 - E``.

    Parameters
    ----------
    freqs : array_like
        Frequencies [Hz].
    rate : float
        Loop frame rate [Hz]; frame period ``T = 1 / rate``.
    gain : float
        Integrator gain ``g`` (> 0).
    delay_frames : float
        Delay ``tau / T`` from the end of the WFS integration to the command update
        (fractional allowed, >= 0).
    integration_frames : float
        WFS integration time ``T_i / T`` in (0, 1].
    model : {"sampled", "continuous"}
        ``"sampled"``: the exact discrete-time function from the open-loop WFS
        measurement sequence to the closed-loop one, ``W(z) = sum_j w_j z**-j`` with
        ``w_j`` the fraction of the integration window during which the command of
        ``j`` frames earlier is applied (zero-order hold, delay and box integration,
        exact for fractional values). ``"continuous"``: the usual continuous-time
        approximation ``W = sinc(f T_i) e**(-i pi f T_i) sinc(f T) e**(-i pi f T)
        e**(-2 i pi f tau)`` (WFS box, zero-order hold, delay), without aliasing: within
        ~1 % of the sampled model below ``rate / 10`` for ``integration_frames = 1``, up
        to ~10 % off for shorter integrations.

    Returns
    -------
    numpy.ndarray of complex
        ``E(f)``, same shape as ``freqs``. ``E(0) = 0``.
    """
    f = as_float_array(freqs, "freqs").reshape(np.shape(freqs))
    rate = check_real(rate, "rate", minimum=0.0, strict_min=True)
    gain, delay_frames, integration_frames = check_loop(gain, delay_frames, integration_frames)
    check_choice(model, "model", _MODELS)
    period = 1.0 / rate
    zinv = np.exp(-2j * np.pi * f * period)
    if model == "sampled":
        weights = command_weights(delay_frames, integration_frames)
        wz = np.polyval(weights[::-1], zinv)
    else:
        t_i = integration_frames * period
        wz = (np.sinc(f * t_i) * np.exp(-1j * np.pi * f * t_i)
              * np.sinc(f * period) * np.exp(-1j * np.pi * f * period)
              * np.exp(-2j * np.pi * f * delay_frames * period))
    one_minus = 1.0 - zinv
    with np.errstate(divide="ignore", invalid="ignore"):
        out = one_minus / (one_minus + gain * wz)
    return np.where(np.abs(one_minus) == 0.0, 0.0 + 0.0j, out)


def noise_transfer_function(
    freqs,
    *,
    rate: float,
    gain: float,
    delay_frames: float,
    integration_frames: float = 1.0,
) -> np.ndarray:
    """Transfer function from WFS noise to the integrator command (sampled model).

    ``N(f) = g / (1 - z**-1 + g W(z))`` with ``z = exp(2 i pi f / rate)`` and ``W`` from
    :func:`command_weights`: white WFS noise of variance ``s**2`` per frame gives a
    command (and so a mirror) noise of variance ``s**2 * mean |N|**2`` over the band
    (:func:`noise_propagation`). ``N(0) = 1``: a constant bias is fully applied.

    Parameters
    ----------
    freqs : array_like
        Frequencies [Hz].
    rate, gain, delay_frames, integration_frames
        As in :func:`rejection_transfer_function`.

    Returns
    -------
    numpy.ndarray of complex
        ``N(f)``, same shape as ``freqs``.
    """
    f = as_float_array(freqs, "freqs").reshape(np.shape(freqs))
    rate = check_real(rate, "rate", minimum=0.0, strict_min=True)
    gain, delay_frames, integration_frames = check_loop(gain, delay_frames, integration_frames)
    zinv = np.exp(-2j * np.pi * f / rate)
    weights = command_weights(delay_frames, integration_frames)
    wz = np.polyval(weights[::-1], zinv)
    return gain / (1.0 - zinv + gain * wz)


def noise_propagation(*, gain: float, delay_frames: float,
                      integration_frames: float = 1.0) -> float:
    """Mean square of :func:`noise_transfer_function` over the band: command / noise variance.

    ``(1 / pi) int_0^pi |N(e**(i w))|**2 dw``, computed exactly as the sum of the squared
    impulse response of ``N`` (Parseval), which converges geometrically for a stable loop.

    Parameters
    ----------
    gain, delay_frames, integration_frames
        As in :func:`rejection_transfer_function`.

    Returns
    -------
    float
        Variance of the command per unit variance of white WFS noise (per mode).
    """
    gain, delay_frames, integration_frames = check_loop(gain, delay_frames, integration_frames)
    check_stable(gain, delay_frames, integration_frames)
    a = loop_denominator(gain, command_weights(delay_frames, integration_frames))
    radius = _pole_radius(gain, delay_frames, integration_frames)
    # enough samples for the slowest pole to decay below 1e-17 of its start
    n = int(min(10_000_000, max(1000, math.ceil(-40.0 / math.log(max(radius, 1e-12))))))
    impulse = np.zeros(n)
    impulse[0] = gain
    h = signal.lfilter([1.0], a, impulse)
    return float(np.dot(h, h))


@dataclass(frozen=True)
class LoopBandwidth:
    """Bandwidths of a modal integrator loop.

    Attributes
    ----------
    rejection_0db : float
        Lowest frequency [Hz] where ``|E(f)| = 1`` (0 dB crossing of the rejection
        transfer function): below it turbulence is attenuated.
    closed_loop_3db : float
        Lowest frequency [Hz] where the closed-loop transfer function ``|1 - E(f)|``
        falls to ``1 / sqrt(2)`` (-3 dB).
    max_amplification : float
        ``max_f |E(f)|`` up to the Nyquist frequency (noise and turbulence amplification
        above the bandwidth; 1 means none).
    """

    rejection_0db: float
    closed_loop_3db: float
    max_amplification: float


def _first_crossing(func, nyquist: float) -> float:
    grid = np.linspace(0.0, nyquist, 4097)[1:]
    values = func(grid)
    idx = np.flatnonzero(values >= 0.0)
    if idx.size == 0:
        return float("nan")
    i = int(idx[0])
    if i == 0:
        return float(optimize.brentq(func, 1e-9 * nyquist, grid[0], xtol=1e-10))
    return float(optimize.brentq(func, grid[i - 1], grid[i], xtol=1e-10))


def closed_loop_bandwidth(
    *,
    rate: float,
    gain: float,
    delay_frames: float,
    integration_frames: float = 1.0,
    model: str = "sampled",
) -> LoopBandwidth:
    """Bandwidths of the loop from :func:`rejection_transfer_function`.

    Parameters are those of :func:`rejection_transfer_function`. Crossings are searched
    on a 4096-point grid up to ``rate / 2`` and refined with Brent's method (NaN if
    there is none below Nyquist).

    Returns
    -------
    LoopBandwidth
        0 dB crossing of ``|E|``, -3 dB point of ``|1 - E|`` and the peak of ``|E|``.
    """
    rate = check_real(rate, "rate", minimum=0.0, strict_min=True)
    kwargs = dict(rate=rate, gain=gain, delay_frames=delay_frames,
                  integration_frames=integration_frames, model=model)
    nyquist = rate / 2.0

    def rejection(f):
        return np.abs(rejection_transfer_function(f, **kwargs)) - 1.0

    def closed(f):
        return 1.0 / np.sqrt(2.0) - np.abs(1.0 - rejection_transfer_function(f, **kwargs))

    grid = np.linspace(0.0, nyquist, 4097)
    peak = float(np.max(np.abs(rejection_transfer_function(grid, **kwargs))))
    return LoopBandwidth(
        rejection_0db=_first_crossing(rejection, nyquist),
        closed_loop_3db=_first_crossing(closed, nyquist),
        max_amplification=peak,
    )


def gain_for_bandwidth(
    bandwidth: float,
    *,
    rate: float,
    delay_frames: float,
    integration_frames: float = 1.0,
    definition: str = "rejection_0db",
    model: str = "sampled",
) -> float:
    """Integrator gain giving a loop bandwidth (by ``definition``), among stable gains.

    Parameters
    ----------
    bandwidth : float
        Wanted bandwidth [Hz], below ``rate / 2``.
    rate, delay_frames, integration_frames, model
        As in :func:`rejection_transfer_function`.
    definition : {"rejection_0db", "closed_loop_3db"}
        Which bandwidth of :class:`LoopBandwidth` to match.

    Returns
    -------
    float
        The gain (Brent's method, to 1e-12).

    Raises
    ------
    ValueError
        If no stable gain reaches ``bandwidth``.
    """
    rate = check_real(rate, "rate", minimum=0.0, strict_min=True)
    bandwidth = check_real(bandwidth, "bandwidth", minimum=0.0, maximum=rate / 2.0,
                           strict_min=True, strict_max=True)
    check_choice(definition, "definition", _DEFINITIONS)
    limit = max_stable_gain(delay_frames, integration_frames)

    def excess(g):
        bw = closed_loop_bandwidth(rate=rate, gain=g, delay_frames=delay_frames,
                                   integration_frames=integration_frames, model=model)
        value = getattr(bw, definition)
        return (value if np.isfinite(value) else rate) - bandwidth

    lo, hi = 1e-6 * limit, (1.0 - 1e-6) * limit
    if excess(hi) < 0.0:
        raise ValueError(
            f"`bandwidth` = {bandwidth} Hz ({definition}) is out of reach of a stable "
            f"integrator at rate={rate} Hz, delay_frames={delay_frames}, "
            f"integration_frames={integration_frames} (stable gains < {limit:.4f})."
        )
    return float(optimize.brentq(excess, lo, hi, xtol=1e-12))
