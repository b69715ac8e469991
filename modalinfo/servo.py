"""The servo model of a per-mode integrator loop: one model for every part of the package.

A wavefront sensor (WFS) integrates the residual over ``integration_frames`` frame
periods ending at ``t_k = (k + 1) T``; the integrator ``c[k] = c[k-1] + g m[k]`` (with an
optional leak, ``c[k] = (1 - leak) c[k-1] + g m[k]``) computes a command that the
deformable mirror holds (zero-order hold) from ``t_k + delay_frames T`` until the next
one replaces it. Because the command is piecewise constant, the WFS sees a fixed
combination of past commands,
``(W c)_k = sum_j w_j c[k-j]`` with ``w_j`` (:func:`command_weights`) the fraction of the
integration window during which ``c[k-j]`` is applied, and the sampled loop is exactly

    m = (y + n) L(z) / (L(z) + g W(z)),   L(z) = 1 - (1 - leak) z**-1,
    W(z) = sum_j w_j z**-j,

with ``y`` the open-loop WFS measurement and ``n`` the WFS noise (``L = 1 - z**-1`` for the
pure integrator, ``leak = 0``, the default everywhere). From it:

- :func:`rejection_transfer_function` ``E = L / (L + g W)`` (measured residual over
  open-loop turbulence);
- :func:`noise_transfer_function` ``N = g / (L + g W)`` (command over WFS noise), and
  :func:`noise_propagation` its mean square over the band;
- :func:`max_stable_gain`, :func:`closed_loop_bandwidth`, :func:`gain_for_bandwidth`.

Every one of them takes the ``leak`` (fix54-e: the rejection, the bandwidths and the
synthetic closed loop were the pure integrator's whatever the loop's leak), and both
transfer functions come from one helper, ``_loop_terms``.

Every function here is bounded in time: delays are limited to :data:`MAX_DELAY_FRAMES`
frames (a loop whose command arrives seconds after its measurement is not an AO
loop, and the characteristic polynomial's degree grows with the delay), the stability
limit is found on the unit circle (cost linear in the delay, not the cubic cost of
polynomial roots) and the noise propagation by FFTs of bounded size.

:mod:`modalinfo.telemetry.synthetic` (spectral telemetry) and the MCAO simulator
``closedloop`` both use these functions, so the loop they simulate is the loop analysed
here. Reference: Madec, P.-Y. 1999, in *Adaptive Optics in Astronomy* (Roddier ed.), ch. 6.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize

from modalinfo.common.records import array_fields_eq
from modalinfo.common.validation import as_float_array, check_choice, check_real

__all__ = [
    "MAX_DELAY_FRAMES",
    "LoopBandwidth",
    "check_loop",
    "command_weights",
    "loop_denominator",
    "check_leak",
    "check_stable",
    "max_stable_gain",
    "rejection_transfer_function",
    "noise_transfer_function",
    "noise_propagation",
    "closed_loop_bandwidth",
    "closed_loop_time_constant",
    "gain_for_bandwidth",
]

#: Longest loop delay [frames] the servo model accepts: beyond it every computation
#: would still be bounded but slow (the loop polynomial has degree ~ delay), and the
#: largest stable integrator gain is below 2e-3 (pi / (2 delay)), no AO loop.
MAX_DELAY_FRAMES = 1000.0
#: Largest polynomial degree for which pole moduli come from ``np.roots`` (cubic cost).
_MAX_ROOTS_DEGREE = 64
#: Largest FFT in :func:`noise_propagation` (2**22 points, 0.1 s).
_MAX_FFT = 2 ** 22

_MODELS = ("sampled", "continuous")
_DEFINITIONS = ("rejection_0db", "closed_loop_3db")


def check_loop(gain, delay_frames, integration_frames) -> tuple[float, float, float]:
    """Validate the loop parameters and return them as floats.

    ``gain`` > 0, ``delay_frames`` in [0, :data:`MAX_DELAY_FRAMES`] and
    ``integration_frames`` in (0, 1]; a bad value raises ``ValueError`` naming it.
    """
    gain = check_real(gain, "gain", minimum=0.0, strict_min=True)
    delay_frames = check_real(delay_frames, "delay_frames", minimum=0.0)
    if delay_frames > MAX_DELAY_FRAMES:
        raise ValueError(
            f"`delay_frames` must be <= {MAX_DELAY_FRAMES:g} frames (the longest delay the "
            f"servo model accepts: the stable gain there is below 2e-3); got "
            f"{delay_frames:g}.")
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


def loop_denominator(gain: float, weights: np.ndarray, leak: float = 0.0) -> np.ndarray:
    """Coefficients ``a`` of ``1 - (1 - leak) z**-1 + g W(z)`` in powers of ``z**-1``.

    ``leak`` is the integrator's leak, ``c[k] = (1 - leak) c[k-1] + g m[k]`` (0: the
    pure integrator).
    """
    a = gain * np.concatenate([weights, np.zeros(max(0, 2 - weights.size))])
    a[0] += 1.0
    a[1] -= 1.0 - leak
    return a


def _loop_terms(f: np.ndarray, rate: float, delay_frames: float, integration_frames: float,
                leak: float, model: str = "sampled") -> tuple[np.ndarray, np.ndarray]:
    """``L(z) = 1 - (1 - leak) z**-1`` and ``W(z)`` at ``z = exp(2 i pi f / rate)``.

    The two factors of every transfer function of the loop (the rejection ``L / (L + g
    W)``, the noise ``g / (L + g W)``): one place for the leaky integrator's ``L`` and for
    both models of ``W`` (:func:`rejection_transfer_function`). Arguments are checked by
    the callers.
    """
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
    return 1.0 - (1.0 - leak) * zinv, wz


def _pole_radius(gain: float, delay_frames: float, integration_frames: float,
                 leak: float = 0.0) -> float | None:
    """Largest closed-loop pole modulus; None when the polynomial is too long for roots."""
    a = loop_denominator(gain, command_weights(delay_frames, integration_frames), leak)
    a = np.trim_zeros(a, "b")
    if a.size < 2:
        return 0.0
    if a.size - 1 > _MAX_ROOTS_DEGREE:
        return None
    return float(np.max(np.abs(np.roots(a))))


def _crossing_gain(weights: np.ndarray, leak: float = 0.0) -> float:
    """Smallest gain > 0 that puts a pole of ``1 - r z**-1 + g W(z)`` on the unit circle.

    ``r = 1 - leak``. A pole sits at ``z = exp(i w)`` for the gain
    ``G(w) = -(1 - r exp(-i w)) / W(exp(i w))`` when ``G(w)`` is real and positive; for
    small gains every pole is inside (the integrator's at ``r - g``, the others at 0),
    so the smallest such ``G`` is the
    stability limit (the gain margin of the Nyquist criterion). ``Im G`` changes sign
    at most once per ``pi / len(W)`` in ``w``, so a grid 16 times finer than that
    brackets every crossing; each is refined by Brent's method. ``W`` has at most three
    non-zero taps, so the cost is linear in the delay.
    """
    taps = np.flatnonzero(weights)
    tw = weights[taps]

    def g_of(w):
        w = np.asarray(w, dtype=np.float64)
        wz = np.exp(-1j * np.multiply.outer(w, taps)) @ tw
        with np.errstate(divide="ignore", invalid="ignore"):
            return -(1.0 - (1.0 - leak) * np.exp(-1j * w)) / wz

    n = max(4096, 16 * weights.size)
    grid = np.linspace(0.0, np.pi, n + 1)[1:-1]  # w = pi apart, below
    with np.errstate(over="ignore"):
        values = g_of(grid)
    candidates = []
    # w = pi: G = -(2 - leak) / W(-1) is real (real coefficients); none if W(-1) = 0
    w_pi = float(np.sum(tw * (-1.0) ** taps))
    if w_pi < -1e-12:
        candidates.append(-(2.0 - leak) / w_pi)
    im = values.imag
    hits = np.abs(im) <= 1e-12 * np.abs(values)  # a crossing on a grid point
    candidates.extend(values.real[hits & (values.real > 0.0)].tolist())
    change = np.flatnonzero(np.sign(im[:-1]) * np.sign(im[1:]) < 0)
    change = change[(values.real[change] > 0.0) | (values.real[change + 1] > 0.0)]
    if change.size:
        coarse = np.minimum(np.abs(values[change]), np.abs(values[change + 1]))
        # refine only the brackets that can hold the smallest gain
        for i in change[coarse <= 2.0 * coarse.min()]:
            w0 = float(optimize.brentq(lambda w: g_of(w).imag, grid[i], grid[i + 1],
                                       xtol=1e-15, rtol=4 * np.finfo(float).eps))
            value = g_of(w0)
            if np.isfinite(value.real) and value.real > 0.0 and abs(value.imag) <= (
                    1e-8 * abs(value)):
                candidates.append(float(value.real))
    if not candidates:  # pragma: no cover - an integrator with a delay always has one
        return math.inf
    return min(candidates)


def max_stable_gain(delay_frames: float = 1.0, integration_frames: float = 1.0, *,
                    leak: float = 0.0) -> float:
    """Largest integrator gain for which the sampled loop is stable.

    Parameters
    ----------
    delay_frames : float
        Delay between the end of the WFS integration and the command update [frames],
        at most :data:`MAX_DELAY_FRAMES`.
    integration_frames : float
        WFS integration time [frames], in (0, 1].
    leak : float
        Integrator leak in [0, 1), ``c[k] = (1 - leak) c[k-1] + g m[k]``. The leak
        moves the limit either way: 2 - leak with no delay and a whole-frame exposure,
        unchanged at one frame of delay, higher for longer delays
        (0.618 -> 0.781 at two frames and leak 0.5; adversarial round 20 c01-c04).

    Returns
    -------
    float
        Gain at which a closed-loop pole reaches the unit circle (relative accuracy
        ~1e-12): the smallest positive real value of ``-(1 - (1 - leak) z**-1) / W(z)``
        on the unit circle. Cost linear in the delay (no polynomial roots).
    """
    _, delay_frames, integration_frames = check_loop(1.0, delay_frames, integration_frames)
    leak = check_leak(leak)
    return _crossing_gain(command_weights(delay_frames, integration_frames), leak)


def check_leak(leak: float) -> float:
    """Return ``leak`` as a float in [0, 1), or raise ``ValueError`` naming it."""
    return check_real(leak, "leak", minimum=0.0, maximum=1.0, strict_max=True)


def closed_loop_time_constant(gain: float, delay_frames: float = 1.0,
                              integration_frames: float = 1.0, *,
                              leak: float = 0.0) -> float | None:
    """Time constant of the sampled closed loop [frames]: ``-1 / ln r``.

    ``r`` is the largest modulus of the poles of ``1 - (1 - leak) z**-1 + g W(z)``
    (:func:`loop_denominator`): every error the loop corrects (a step, the open-loop
    turbulence at closure) decays at least as ``r**k`` after ``k`` frames, so its
    amplitude falls by ``e`` per time constant and its variance by ``e**2``.

    Parameters
    ----------
    gain : float
        Integrator gain, below :func:`max_stable_gain`.
    delay_frames, integration_frames : float
        Delay and exposure in frames (:func:`command_weights`).
    leak : float
        Integrator leak in [0, 1).

    Returns
    -------
    float or None
        The time constant [frames] (0 when every pole is at 0); None when the delay makes
        the polynomial too long for its roots (over 64 frames).

    Raises
    ------
    ValueError
        An argument out of range, or an unstable loop (:func:`check_stable`).
    """
    check_stable(gain, delay_frames, integration_frames, leak=leak)
    gain, delay_frames, integration_frames = check_loop(gain, delay_frames, integration_frames)
    radius = _pole_radius(gain, delay_frames, integration_frames, check_leak(leak))
    if radius is None:
        return None
    return 0.0 if radius <= 0.0 else -1.0 / math.log(radius)


def check_stable(gain: float, delay_frames: float, integration_frames: float, *,
                 leak: float = 0.0) -> None:
    """Raise ``ValueError`` (with the stability limit) if the sampled loop is unstable.

    ``leak`` is the integrator's leak (:func:`max_stable_gain`).
    """
    gain, delay_frames, integration_frames = check_loop(gain, delay_frames, integration_frames)
    leak = check_leak(leak)
    radius = _pole_radius(gain, delay_frames, integration_frames, leak)
    limit = max_stable_gain(delay_frames, integration_frames, leak=leak)
    # the gain margin decides (relative accuracy ~1e-12): a pole-modulus test alone called
    # a tiny gain unstable, since the integrator's pole 1 - g is within rounding of 1 for
    # g ~ 1e-12, and then printed "stable for gain < limit" with gain far below the limit
    bound = limit * (1.0 - 1e-12)
    unstable = gain >= bound or (radius is not None and radius > 1.0 + 1e-9)
    if unstable:
        pole = ("" if radius is None
                else f" (largest closed-loop pole modulus {radius:.4f} >= 1)" if radius >= 1.0
                else f" (largest closed-loop pole modulus {radius!r}, 1 within the limit's "
                     "1e-12 accuracy)")
        raise ValueError(
            f"`gain` = {gain} makes the loop unstable{pole} for delay_frames="
            f"{delay_frames}, integration_frames={integration_frames}"
            f"{f', leak={leak:g}' if leak else ''}; the loop is stable "
            f"for gain < {_shown_bound(bound, limit, gain)}."
        )


def _shown_bound(bound: float, limit: float, gain: float) -> str:
    """Return the bound ``gain >= bound`` refused, with the digits that put ``gain`` above it.

    4 decimals where they do (round 3's form); else as many as it takes, with the rule
    (fixes 45-c, round 45 PART b T90 / T104: 1 - 1 ulp was refused as "stable for gain <
    1.0000", the limit rounded, not the bound applied).
    """
    for digits in range(4, 18):
        shown = f"{bound:.{digits}f}"
        if float(shown) <= gain or gain < bound:
            break
    if digits == 4:
        return shown
    return f"{shown} (the limit {limit!r} less its 1e-12 relative accuracy)"


def rejection_transfer_function(
    freqs,
    *,
    rate: float,
    gain: float,
    delay_frames: float,
    integration_frames: float = 1.0,
    model: str = "sampled",
    leak: float = 0.0,
) -> np.ndarray:
    """Rejection transfer function of the modal integrator loop.

    ``E(f) = 1 / (1 + g W(z) / (1 - (1 - leak) z**-1))`` with ``z = exp(2 i pi f /
    rate)``: residual over open-loop turbulence. The closed-loop transfer function
    (correction over turbulence) is ``1 - E``.

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
        e**(-2 i pi f tau)`` (WFS box, zero-order hold, delay), without aliasing. Below
        ``rate / 10``, ``|E|`` is within 3.5 % of the sampled model's for
        ``integration_frames = 1``, delays up to 3 frames and gains up to half the
        stability limit (within 4.5 % up to 0.9 of the limit for delays up to 1 frame),
        and within 30 % for shorter integrations at gains up to half the limit. Nearer
        the limit the two differ far more (24 % at 2 frames of delay and 0.9 of the
        limit, 5x at integration 0.5, delay 2.5; measured by adversarial round 42 PART
        a, whose S02, S04, S06 found the "~1 % / ~10 %" once stated here untrue): use
        the sampled model there.
    leak : float
        Integrator leak in [0, 1), ``c[k] = (1 - leak) c[k-1] + g m[k]`` (0: the pure
        integrator), as :func:`max_stable_gain`. A leak keeps part of the lowest
        frequencies: ``E(0) = leak / (leak + g)`` (0.3 at gain 0.4664 and leak 0.2, the
        servo-lag residual of a slow mode x10 the pure integrator's; fix54-e).

    Returns
    -------
    numpy.ndarray of complex
        ``E(f)``, same shape as ``freqs``. ``E(0) = 0`` without a leak.

    Raises
    ------
    ValueError
        If the loop is unstable (:func:`check_stable`; also for
        :func:`noise_transfer_function` and :func:`closed_loop_bandwidth`).
    """
    f = as_float_array(freqs, "freqs").reshape(np.shape(freqs))
    rate = check_real(rate, "rate", minimum=0.0, strict_min=True)
    gain, delay_frames, integration_frames = check_loop(gain, delay_frames, integration_frames)
    # an unstable loop has no frequency response (its output grows without bound): the
    # formula's finite values, and the bandwidths read from them, were silent nonsense
    # (adversarial round 9, rows sv-rtf-unstable, sv-clbw-unstable)
    leak = check_leak(leak)
    # with the leak: it moves the limit (round 20)
    check_stable(gain, delay_frames, integration_frames, leak=leak)
    check_choice(model, "model", _MODELS)
    integrator, wz = _loop_terms(f, rate, delay_frames, integration_frames, leak, model)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = integrator / (integrator + gain * wz)
    return np.where(np.abs(integrator) == 0.0, 0.0 + 0.0j, out)


def noise_transfer_function(
    freqs,
    *,
    rate: float,
    gain: float,
    delay_frames: float,
    integration_frames: float = 1.0,
    leak: float = 0.0,
) -> np.ndarray:
    """Transfer function from WFS noise to the integrator command (sampled model).

    ``N(f) = g / (1 - (1 - leak) z**-1 + g W(z))`` with ``z = exp(2 i pi f / rate)`` and
    ``W`` from :func:`command_weights`: white WFS noise of variance ``s**2`` per frame
    gives a command (and so a mirror) noise of variance ``s**2 * mean |N|**2`` over the
    band (:func:`noise_propagation`). ``N(0) = 1`` without a leak: a constant bias is
    fully applied (``g / (leak + g)`` with one).

    Parameters
    ----------
    freqs : array_like
        Frequencies [Hz].
    rate, gain, delay_frames, integration_frames
        As in :func:`rejection_transfer_function`.
    leak : float
        Integrator leak in [0, 1), ``c[k] = (1 - leak) c[k-1] + g m[k]`` (0: the pure
        integrator), as :func:`max_stable_gain`.

    Returns
    -------
    numpy.ndarray of complex
        ``N(f)``, same shape as ``freqs``.
    """
    f = as_float_array(freqs, "freqs").reshape(np.shape(freqs))
    rate = check_real(rate, "rate", minimum=0.0, strict_min=True)
    gain, delay_frames, integration_frames = check_loop(gain, delay_frames, integration_frames)
    leak = check_leak(leak)
    # as the rejection (round 9), with the leak: it moves the limit (round 20)
    check_stable(gain, delay_frames, integration_frames, leak=leak)
    integrator, wz = _loop_terms(f, rate, delay_frames, integration_frames, leak)
    return gain / (integrator + gain * wz)


def noise_propagation(*, gain: float, delay_frames: float,
                      integration_frames: float = 1.0, leak: float = 0.0) -> float:
    """Mean square of :func:`noise_transfer_function` over the band: command / noise variance.

    ``(1 / pi) int_0^pi |N(e**(i w))|**2 dw``, computed exactly as the sum of the squared
    impulse response of ``N`` (Parseval), from FFTs of growing size until it settles.

    Parameters
    ----------
    gain, delay_frames, integration_frames
        As in :func:`rejection_transfer_function`.
    leak : float
        Integrator leak in [0, 1) (:func:`noise_transfer_function`). A leak lowers the
        command noise (0.520 -> 0.396 -> 0.315 at gain 0.4664, one frame of delay, leak
        0 / 0.2 / 0.5); the closed loop's budget and noise floor pass the loop's
        (adversarial round 54 PART a: they ignored it, x1.31-x1.65 too high).

    Returns
    -------
    float
        Variance of the command per unit variance of white WFS noise (per mode).
    """
    gain, delay_frames, integration_frames = check_loop(gain, delay_frames, integration_frames)
    leak = check_leak(leak)
    check_stable(gain, delay_frames, integration_frames, leak=leak)
    a = loop_denominator(gain, command_weights(delay_frames, integration_frames), leak)
    # the mean of |g / D|**2 over n points of the unit circle is the sum of squares of
    # the impulse response aliased modulo n, exact to O(r**n) for the slowest pole r:
    # double n until it settles (bounded by _MAX_FFT; each FFT is a Ctrl-C point)
    n = 1 << max(10, int(a.size - 1).bit_length() + 2)
    previous = math.nan
    while True:
        power = gain ** 2 / np.abs(np.fft.rfft(a, n)) ** 2  # bins 0 .. n/2 of n
        value = float((power[0] + power[-1] + 2.0 * power[1:-1].sum()) / n)
        if abs(value - previous) <= 1e-13 * value:
            return value
        if n >= _MAX_FFT:
            raise ValueError(
                f"`gain` = {gain} is too close to the stability limit for the noise "
                f"propagation to converge (delay_frames={delay_frames}, "
                f"integration_frames={integration_frames}"
                f"{f', leak={leak:g}' if leak else ''}; limit "
                f"{max_stable_gain(delay_frames, integration_frames, leak=leak):.6g}).")
        previous = value
        n *= 2


@array_fields_eq  # NaN fields equal after a round trip (audit 10-state)
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
        # below the first grid point: bracket down by factors of 1000 (a gain of 1e-9 puts
        # the crossing under 1e-9 Nyquist, where brentq's "f(a) and f(b) must have
        # different signs" was the answer: adversarial round 9, row se-servo-tiny-gain)
        lo, hi = 1e-9 * nyquist, grid[0]
        while func(lo) >= 0.0:
            if lo < 1e-290 * nyquist:
                return 0.0
            lo, hi = lo * 1e-3, lo
        xtol = 1e-10 if hi == grid[0] else min(1e-10, 1e-6 * lo)
        return float(optimize.brentq(func, lo, hi, xtol=xtol))
    return float(optimize.brentq(func, grid[i - 1], grid[i], xtol=1e-10))


def _peak(func, nyquist: float) -> float:
    """``max func`` on ``[0, nyquist]``: a 4097-point grid, each local maximum refined.

    Near the stability limit the resonance of ``|E|`` is far narrower than the grid
    step (its width ~ (1 - pole modulus) rate / (2 pi)), so the grid's largest value
    fell 4.6x below the peak at 0.9999 of the limit and 50x at 0.99999 (adversarial
    round 42 PART a, T22-T24). The grid point nearest a resonance is its local maximum,
    so the peak lies within one step of it: bounded Brent refines each local maximum
    (the 8 largest), down to a step of 1e-13 Nyquist.
    """
    grid = np.linspace(0.0, nyquist, 4097)
    values = func(grid)
    padded = np.concatenate([[-np.inf], values, [-np.inf]])
    local = np.flatnonzero((padded[1:-1] >= padded[:-2]) & (padded[1:-1] >= padded[2:]))
    best = float(np.max(values))
    for k in local[np.argsort(values[local])[::-1][:8]]:
        lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
        found = optimize.minimize_scalar(
            lambda f: -float(func(np.array([f]))[0]), bounds=(lo, hi), method="bounded",
            options={"xatol": 1e-13 * nyquist, "maxiter": 500})
        best = max(best, -float(found.fun))
    return best


def closed_loop_bandwidth(
    *,
    rate: float,
    gain: float,
    delay_frames: float,
    integration_frames: float = 1.0,
    model: str = "sampled",
    leak: float = 0.0,
) -> LoopBandwidth:
    """Bandwidths of the loop from :func:`rejection_transfer_function`.

    Parameters are those of :func:`rejection_transfer_function` (``leak`` too: a leaky
    loop's bandwidths are its own, fix54-e). Crossings are searched on a 4096-point grid
    up to ``rate / 2`` and refined with Brent's method (NaN if there is none below
    Nyquist); so is the peak of ``|E|`` (each local maximum of the grid refined, since a
    loop near its stability limit resonates within one step). A leak above ``(sqrt(2) -
    1) g`` keeps ``|1 - E|`` below ``1 / sqrt(2)`` from 0 Hz on (``|1 - E(0)| = g / (g +
    leak)``): ``closed_loop_3db`` is then 0.

    Returns
    -------
    LoopBandwidth
        0 dB crossing of ``|E|``, -3 dB point of ``|1 - E|`` and the peak of ``|E|``.
    """
    rate = check_real(rate, "rate", minimum=0.0, strict_min=True)
    kwargs = dict(rate=rate, gain=gain, delay_frames=delay_frames,
                  integration_frames=integration_frames, model=model, leak=leak)
    nyquist = rate / 2.0

    def rejection(f):
        return np.abs(rejection_transfer_function(f, **kwargs)) - 1.0

    def closed(f):
        return 1.0 / np.sqrt(2.0) - np.abs(1.0 - rejection_transfer_function(f, **kwargs))

    peak = _peak(lambda f: np.abs(rejection_transfer_function(f, **kwargs)), nyquist)
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
    leak: float = 0.0,
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
    leak : float
        Integrator leak in [0, 1) (:func:`rejection_transfer_function`).

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
    limit = max_stable_gain(delay_frames, integration_frames, leak=leak)

    def excess(g):
        bw = closed_loop_bandwidth(rate=rate, gain=g, delay_frames=delay_frames,
                                   integration_frames=integration_frames, model=model,
                                   leak=leak)
        value = getattr(bw, definition)
        return (value if np.isfinite(value) else rate) - bandwidth

    lo, hi = 1e-6 * limit, (1.0 - 1e-6) * limit
    if excess(hi) < 0.0:
        raise ValueError(
            f"`bandwidth` = {bandwidth} Hz ({definition}) is out of reach of a stable "
            f"integrator at rate={rate} Hz, delay_frames={delay_frames}, "
            f"integration_frames={integration_frames}{f', leak={leak:g}' if leak else ''} "
            f"(stable gains < {limit:.4f})."
        )
    return float(optimize.brentq(excess, lo, hi, xtol=1e-12))
