"""Kolmogorov / von Karman phase screens: FFT synthesis with subharmonics and a tilt tail.

Method
------
A square screen of ``G x G`` pixels of size ``dx`` [m] is the real part of a random
Fourier sum over three sets of frequencies (``f`` in cycles per metre)::

    phi(x) = Re sum_k c_k exp(2 pi i f_k . x),   c_k = sqrt(W(f_k) dA_k) (a_k + i b_k)

with ``a_k, b_k`` independent standard normals, so that every term has variance
``W(f_k) dA_k`` and the structure function is ``2 sum_k W dA (1 - cos 2 pi f_k . r)``,
a Riemann sum of the exact ``D(r) = 2 int W(f) (1 - cos 2 pi f . r) d^2 f``.

1. The FFT lattice ``f = (p, q) df`` with ``df = 1 / (G dx)``, ``dA = df^2``, DC left
   out; one inverse FFT. This part alone is periodic with period ``G dx``. Its power is
   the *aliased* spectrum ``sum_{m,n} W(f + (m, n) / dx)``: the screen is a grid of
   point samples of the continuous phase, whose discrete spectrum is that sum, so the
   samples have the exact structure function at integer lags (an alias-free FFT screen
   misses the ~10% of ``D(dx)`` that lies beyond the Nyquist frequency).
2. The cells next to DC. Point sampling ``W(f_c) dA`` is poor where ``W`` varies a lot
   across a cell: ``W |f|^2 ~ f^(-5/3)`` varies 6-fold across the first ring, which then
   carries ~20% too little tilt. The 8 cells of the first ring are each replaced by
   3 x 3 terms at the centres of their sub-cells, and every term within 8 rings of DC
   gets the cell-integrated power ``int_cell W |f|^2 d^2f / |f_c|^2`` (16 x 16
   Gauss-Legendre nodes), which gives each cell its exact share of the small-lag
   structure function and of the gradient.
3. Subharmonics (Lane, Glindemann & Dainty 1992, Waves in Random Media 2, 209; the
   3 x 3 recursive form used by Johansson & Gavel 1994, Proc. SPIE 2200, 372, and by
   Schmidt 2010, "Numerical simulation of optical wave propagation", listing 9.3):
   the DC cell ``|f_x|, |f_y| < df / 2`` that the FFT cannot represent is split into
   3 x 3 cells of side ``df / 3``; the 8 outer cells become 8 Fourier terms at their
   centres (with the power of item 2), and the centre cell is split again, ``levels``
   times. All the extra terms are evaluated on the screen grid as a sum of separable
   outer products, grouped by their distinct ``f_x`` (a numba kernel, independent of any
   BLAS thread count).
4. The tilt tail (ours): Lane's method leaves the last centre cell
   ``|f_x|, |f_y| < df / (2 3^levels)`` empty. Over a screen much smaller than
   ``3^levels G dx`` a Fourier term of that cell is, to first order, a random gradient,
   so the cell is replaced by ``g_x x + g_y y`` with ``g_x, g_y ~ N(0, s^2)`` and
   ``s^2 = int_cell (2 pi f_x)^2 W(f) d^2 f`` (numerical quadrature). For Kolmogorov
   turbulence this matters: the tilt over a pupil ``D`` gathers power from all
   frequencies below ``1 / D`` with a density ``f^(-2/3)``, and the share of Noll's tip
   variance coming from ``|f| < f_c`` is ``0.81 (pi D f_c)^(1/3)`` (e.g. 17% for a
   16 m screen with 5 levels and D = 4 m), which Lane's method alone would lose. The
   neglected second-order (curvature) term has a relative weight ``~ (pi / 3^levels)^2``
   over the screen.

:func:`expected_structure_function` sums ``2 P_k (1 - cos 2 pi f_k r)`` over all these
terms: the ensemble structure function the method delivers is 0.993-0.9998 of
Kolmogorov's from 1 pixel to a quarter of the screen, and 0.989 at half of it
(von Karman L0 = 25 m, 16 m screen: 0.983 at a quarter).

The phase power spectrum is von Karman,
``W(f) = c r0^(-5/3) (f^2 + 1/L0^2)^(-11/6)`` [rad^2 m^2] with
``c = 0.022896`` (:data:`modalinfo.bases.turbulence.KOLMOGOROV_PSD_CONSTANT`), which
gives ``D(r) = 6.8839 (r / r0)^(5/3)`` for ``L0 = inf``. Phase is in radians at the
wavelength where ``r0`` is given.

Why a finite FFT screen and not an extruded "infinite" one: row extrusion (Assemat et al.
2006) needs the phase covariance, which does not exist for Kolmogorov turbulence and is
numerically ill-conditioned for very large L0 (hcipy and aotools fail there); the FFT
screen needs only the spectrum, which is well defined for every L0, and subharmonics plus
the tilt tail give the low orders their power at any L0. The cost is memory: the screen
must be long enough for the wind to cross it (see :mod:`closedloop.optics.atmosphere`).
"""

from __future__ import annotations

import functools
from typing import NamedTuple

import numpy as np
from scipy import fft as sfft
from scipy import integrate

from closedloop.optics._atmosphere_kernels import add_separable_terms, aliased_power
from modalinfo.bases.turbulence import KOLMOGOROV_PSD_CONSTANT
from modalinfo.common.validation import check_int, check_real, check_rng

__all__ = [
    "phase_psd",
    "fft_phase_screen",
    "expected_structure_function",
    "DEFAULT_SUBHARMONIC_LEVELS",
]

#: Subharmonic levels by default: the last centre cell is 3^5 = 243 times smaller than
#: the screen's frequency step, so the tilt tail's neglected curvature is ~1.7e-4.
DEFAULT_SUBHARMONIC_LEVELS: int = 5


def phase_psd(f, r0: float, outer_scale: float = np.inf):
    """Von Karman phase power spectral density ``W(f)`` [rad^2 m^2].

    Parameters
    ----------
    f : array_like
        Spatial frequency magnitude [cycles / m].
    r0 : float
        Fried parameter [m] at the phase wavelength.
    outer_scale : float
        Outer scale ``L0`` [m]; ``inf`` for Kolmogorov.

    Returns
    -------
    numpy.ndarray
        ``0.022896 r0^(-5/3) (f^2 + 1/L0^2)^(-11/6)``; ``inf`` at ``f = 0`` for
        Kolmogorov turbulence.
    """
    f = np.asarray(f, dtype=float)
    k0sq = 0.0 if np.isinf(outer_scale) else 1.0 / outer_scale**2
    with np.errstate(divide="ignore"):
        return KOLMOGOROV_PSD_CONSTANT * r0 ** (-5 / 3) * (f * f + k0sq) ** (-11 / 6)


_GL_X, _GL_W = np.polynomial.legendre.leggauss(16)


def _cell_power(fx, fy, side, r0: float, outer_scale: float) -> np.ndarray:
    """Power of the Fourier term standing for square cells centred at ``(fx, fy)``.

    ``int_cell W(f) |f|^2 d^2f / |f_c|^2`` (16 x 16 Gauss-Legendre nodes per cell): the
    term then carries the cell's exact contribution to the small-lag structure function
    and to the gradient (tilt), ``2 pi^2 int W (f . r)^2``, where the point value
    ``W(f_c) side^2`` underestimates it by ~20% in the cells next to the origin
    (``W |f|^2 ~ f^(-5/3)`` varies 6-fold across them). Far from the origin the two agree.
    """
    fx, fy, side = (np.asarray(v, dtype=float) for v in (fx, fy, side))
    u = 0.5 * _GL_X
    w = 0.5 * _GL_W
    px = fx[..., None, None] + side[..., None, None] * u[:, None]
    py = fy[..., None, None] + side[..., None, None] * u[None, :]
    f2 = px * px + py * py
    integrand = phase_psd(np.sqrt(f2), r0, outer_scale) * f2
    integral = np.sum(integrand * (w[:, None] * w[None, :]), axis=(-2, -1)) * side**2
    return integral / (fx * fx + fy * fy)


#: FFT cells with ``max(|p|, |q|) <= _SPLIT_RINGS`` are each replaced by 3 x 3 terms.
_SPLIT_RINGS = 1

#: FFT cells with ``max(|p|, |q|) <= _NEAR_RINGS`` get the cell-integrated power.
_NEAR_RINGS = 8
#: Alias orders summed explicitly; the rest of the spectrum beyond is added as an integral.
_ALIAS_ORDERS = 2


@functools.lru_cache(maxsize=8)
def _lattice_amplitude_cached(g: int, dx: float, outer_scale: float) -> np.ndarray:
    """Amplitudes ``sqrt(W_eff dA)`` for ``r0 = 1`` on the quarter lattice ``|p|, |q| <= G/2``.

    ``W_eff`` is the aliased spectrum ``sum_{m,n} W(f + (m, n) / dx)``: the screen is a
    grid of point samples of the continuous phase, whose discrete spectrum is the sum of
    the aliases, so the samples have the exact structure function at integer lags,
    including the ~10% of ``D(dx)`` that lies beyond the Nyquist frequency (an
    alias-free FFT screen misses it). Orders ``|m|, |n| <= 2`` are summed; the rest is
    ``dx^2`` times the integral of ``W`` outside the square of half-width ``2.5 / dx``
    (approximated by the disc of equal area). The cells next to DC use
    :func:`_cell_power` instead of the point value.
    """
    freqs = sfft.fftfreq(g, d=dx)
    half = g // 2 + 1  # |p| = 0 .. g // 2 ; the lattice is symmetric in |p|, |q|
    fq = np.abs(freqs[:half])
    fxq, fyq = np.meshgrid(fq, fq)
    power = np.zeros((half, half))
    k = 1.0 / dx
    k0sq = 0.0 if np.isinf(outer_scale) else 1.0 / outer_scale**2
    aliased_power(np.ascontiguousarray(fq), k, k0sq, _ALIAS_ORDERS, power)
    power *= KOLMOGOROV_PSD_CONSTANT  # phase_psd with r0 = 1
    radius = (2 * _ALIAS_ORDERS + 1) * k / np.sqrt(np.pi)
    tail = 2 * np.pi * KOLMOGOROV_PSD_CONSTANT * 0.6 * (radius**2 + k0sq) ** (-5 / 6)
    power += tail * dx**2  # integral over f outside the box, per lattice cell of area k^2
    df = 1.0 / (g * dx)
    near = min(_NEAR_RINGS, half - 1)
    idx = np.arange(near + 1) * df
    cx, cy = np.meshgrid(idx, idx)
    cx[0, 0] = np.nan  # DC: no term
    with np.errstate(invalid="ignore"):
        centre = _cell_power(cx, cy, np.full_like(cx, df), 1.0, outer_scale) / df**2
    power[: near + 1, : near + 1] += np.nan_to_num(centre, nan=0.0)
    power[near + 1 :, :] += phase_psd(np.hypot(fxq, fyq)[near + 1 :, :], 1.0, outer_scale)
    power[: near + 1, near + 1 :] += phase_psd(np.hypot(fxq, fyq)[: near + 1, near + 1 :], 1.0,
                                               outer_scale)
    power[0, 0] = 0.0
    quarter = np.sqrt(power) * df
    quarter.flags.writeable = False
    return quarter


def _lattice_amplitude(g: int, dx: float, r0: float, outer_scale: float) -> np.ndarray:
    """Lattice amplitudes for Fried parameter ``r0`` (``W`` scales as ``r0^(-5/3)``)."""
    quarter = _lattice_amplitude_cached(g, dx, outer_scale)
    # unfold |p|, |q| onto the FFT order 0, 1, ..., g//2, ..., -1
    index = np.abs(np.round(sfft.fftfreq(g) * g).astype(np.int64))
    return quarter[np.ix_(index, index)] * r0 ** (-5 / 6)


@functools.lru_cache(maxsize=64)
def _tail_gradient_variance(half_width: float, r0: float, outer_scale: float) -> float:
    """``int_{|fx|,|fy| < h} (2 pi fx)^2 W(f) d^2 f`` [rad^2 / m^2] in polar coordinates.

    ``(2 pi fx)^2 W`` is ``4 pi^2 cos^2(phi) f^2 W(f)``; the radial integral
    ``int_0^R f^3 W(f) df`` is ``3 R^(1/3) c r0^(-5/3)`` for Kolmogorov turbulence; for
    von Karman it is the antiderivative's difference where the knee ``1/L0 < R`` and is
    integrated numerically below (where that difference cancels);
    ``R(phi) = h / max(|cos phi|, |sin phi|)``. By the
    8-fold symmetry of the square the angular integral is 8 times the one over
    ``[0, pi/4]`` of the symmetrised ``(cos^2 + sin^2) / 2 = 1/2`` weight.
    """
    c = KOLMOGOROV_PSD_CONSTANT * r0 ** (-5 / 3)
    k0sq = 0.0 if np.isinf(outer_scale) else 1.0 / outer_scale**2

    def radial(big_r: float) -> float:
        if k0sq == 0.0:
            return 3.0 * big_r ** (1 / 3) * c
        if k0sq < big_r * big_r:
            # the knee f = 1/L0 inside [0, R]: quad missed it (L0 = 1e6 m: 0.6 % off without
            # a word; 1e9 m: IntegrationWarning). Exact antiderivative in u = f^2 + k0^2,
            # 3 u^(1/6) + (3/5) k0^2 u^(-5/6), free of cancellation here (k0 < R)
            u = big_r * big_r + k0sq
            return c * (3.0 * u ** (1 / 6) + 0.6 * k0sq * u ** (-5 / 6) - 3.6 * k0sq ** (1 / 6))
        value, _ = integrate.quad(lambda f: f**3 * c * (f * f + k0sq) ** (-11 / 6), 0.0, big_r,
                                  limit=200, epsabs=0.0, epsrel=1e-10)
        return value

    # over [0, pi/4] both cos^2 and sin^2 appear in the 8 octants: weight 1/2 each on average
    value, _ = integrate.quad(lambda phi: 0.5 * radial(half_width / np.cos(phi)), 0.0, np.pi / 4,
                              limit=200, epsabs=0.0, epsrel=1e-10)
    return float(4 * np.pi**2 * 8 * value)


class _Spectrum(NamedTuple):
    amplitude: np.ndarray  # (G, G) lattice amplitudes sqrt(W_eff dA), zero where replaced
    fx: np.ndarray  # (K,) frequencies of the extra terms [1/m]
    fy: np.ndarray
    power: np.ndarray  # (K,) variance of each extra term [rad^2]
    tail_variance: float  # variance of each tilt-tail gradient component [rad^2 / m^2]


def _spectral_terms(g: int, dx: float, r0: float, outer_scale: float, levels: int,
                    tilt_tail: bool) -> _Spectrum:
    """Every Fourier term of a screen and its variance (no random numbers)."""
    df = 1.0 / (g * dx)
    amp = _lattice_amplitude(g, dx, r0, outer_scale)
    terms = []
    split = min(_SPLIT_RINGS, (g - 1) // 2)
    for p in range(-split, split + 1):  # FFT cells next to DC: 3 x 3 terms each
        for q in range(-split, split + 1):
            if p or q:
                amp[q % g, p % g] = 0.0
                for a in (-1, 0, 1):
                    for b in (-1, 0, 1):
                        terms.append(((p + a / 3) * df, (q + b / 3) * df, df / 3))
    for p in range(1, levels + 1):  # Lane's subharmonics of the DC cell
        dfp = df / 3**p
        for a in (-1, 0, 1):
            for b in (-1, 0, 1):
                if a or b:
                    terms.append((a * dfp, b * dfp, dfp))
    if terms:
        fx, fy, side = (np.array(v) for v in zip(*terms, strict=True))
        power = _cell_power(fx, fy, side, r0, outer_scale)
    else:
        fx = fy = power = np.zeros(0)
    tail = _tail_gradient_variance(df / (2 * 3**levels), r0, outer_scale) if tilt_tail else 0.0
    return _Spectrum(amp, fx, fy, power, tail)


def expected_structure_function(
    lags,
    n_pixels: int,
    pixel_scale: float,
    r0: float,
    *,
    outer_scale: float = np.inf,
    levels: int = DEFAULT_SUBHARMONIC_LEVELS,
    tilt_tail: bool = True,
) -> np.ndarray:
    """Ensemble structure function of :func:`fft_phase_screen` screens along x [rad^2].

    ``D(r) = sum_k 2 P_k (1 - cos(2 pi f_x,k r)) + s^2 r^2`` over every term of the
    synthesis (lattice, split cells, subharmonics) and the tilt tail: what the method
    delivers, to compare with the theory (``6.8839 (r / r0)^(5/3)`` or von Karman).
    With the defaults it is 0.993-0.9998 of Kolmogorov's from 1 pixel to ``G / 4``
    and 0.989 at ``G / 2``.

    Parameters
    ----------
    lags : array_like
        Lags [m] along x.
    n_pixels, pixel_scale, r0, outer_scale, levels, tilt_tail
        As :func:`fft_phase_screen`.

    Returns
    -------
    numpy.ndarray
        ``D`` at each lag [rad^2].
    """
    g = check_int(n_pixels, "n_pixels", minimum=8)
    dx = check_real(pixel_scale, "pixel_scale", minimum=0.0, strict_min=True)
    r0 = check_real(r0, "r0", minimum=0.0, strict_min=True)
    outer_scale = check_real(outer_scale, "outer_scale", minimum=0.0, strict_min=True,
                             allow_inf=True)
    levels = check_int(levels, "levels", minimum=0, maximum=30)
    spec = _spectral_terms(g, dx, r0, outer_scale, levels, bool(tilt_tail))
    freqs = sfft.fftfreq(g, d=dx)
    lattice_power = np.sum(spec.amplitude**2, axis=0)  # marginal over f_y, per f_x
    out = []
    for r in np.atleast_1d(np.asarray(lags, dtype=float)):
        d = np.sum(2 * lattice_power * (1 - np.cos(2 * np.pi * freqs * r)))
        d += np.sum(2 * spec.power * (1 - np.cos(2 * np.pi * spec.fx * r)))
        d += spec.tail_variance * r * r
        out.append(d)
    return np.array(out)


def fft_phase_screen(
    n_pixels: int,
    pixel_scale: float,
    r0: float,
    *,
    outer_scale: float = np.inf,
    levels: int = DEFAULT_SUBHARMONIC_LEVELS,
    tilt_tail: bool = True,
    seed=None,
) -> np.ndarray:
    """Draw a square Kolmogorov / von Karman phase screen (module docstring for the method).

    Parameters
    ----------
    n_pixels : int
        Screen side ``G`` [pixels], ``>= 8``. FFT-friendly sizes
        (``scipy.fft.next_fast_len``) are fastest.
    pixel_scale : float
        Pixel size [m], ``> 0``.
    r0 : float
        Fried parameter [m] at the phase wavelength, ``> 0``.
    outer_scale : float
        Outer scale ``L0`` [m], ``> 0``; ``inf`` (default) for Kolmogorov.
    levels : int
        Subharmonic levels, ``>= 0`` (0: the FFT lattice only).
    tilt_tail : bool
        Add the random gradient standing for the last, empty centre cell.
    seed : None, int or numpy.random.Generator
        Randomness; the same seed gives the same bits.

    Returns
    -------
    numpy.ndarray
        ``(G, G)`` float64 phase [rad]; row index along ``y``, column index along ``x``.
        Its mean is removed (piston is arbitrary).

    Notes
    -----
    The random numbers are drawn in a fixed order: ``2 G^2`` normals for the FFT
    lattice, then ``16`` per subharmonic level, then ``2`` for the tilt tail.
    """
    g = check_int(n_pixels, "n_pixels", minimum=8)
    dx = check_real(pixel_scale, "pixel_scale", minimum=0.0, strict_min=True)
    r0 = check_real(r0, "r0", minimum=0.0, strict_min=True)
    outer_scale = check_real(outer_scale, "outer_scale", minimum=0.0, strict_min=True,
                             allow_inf=True)
    levels = check_int(levels, "levels", minimum=0, maximum=30)
    rng = check_rng(seed)

    spec = _spectral_terms(g, dx, r0, outer_scale, levels, tilt_tail)
    # complex normals filled in place (the same stream as standard_normal((2, G, G)));
    # peak memory ~ 32 G^2 bytes, 0.5 GB at G = 4096
    coeffs = np.empty((g, g), dtype=complex)
    buffer = np.empty((g, g))
    coeffs.real = rng.standard_normal(out=buffer)
    coeffs.imag = rng.standard_normal(out=buffer)
    del buffer
    coeffs *= spec.amplitude
    spectrum = sfft.ifft2(coeffs, norm="forward", overwrite_x=True)
    del coeffs
    screen = spectrum.real.copy()
    del spectrum
    coords = (np.arange(g) - g / 2) * dx  # centred, keeps the low-order terms small
    if spec.fx.size:
        z = rng.standard_normal((2, spec.fx.size))
        c = (z[0] + 1j * z[1]) * np.sqrt(spec.power)
        # The K terms use few distinct f_x and f_y values (19 each with the defaults), so
        # sum_k c_k e^(2 pi i fy_k y) e^(2 pi i fx_k x) = EY @ C @ EX with C the (n_y, n_x)
        # matrix of summed coefficients: rank n_x instead of K (~6x fewer operations).
        unit = (1.0 / (g * dx)) / 3 ** max(levels, 1)
        kx, ix = np.unique(np.round(spec.fx / unit).astype(np.int64), return_inverse=True)
        ky, iy = np.unique(np.round(spec.fy / unit).astype(np.int64), return_inverse=True)
        cmat = np.zeros((ky.size, kx.size), dtype=complex)
        np.add.at(cmat, (iy, ix), c)
        ey = np.exp(2j * np.pi * np.outer(coords, ky * unit))  # (G, n_y)
        ex = np.exp(2j * np.pi * np.outer(kx * unit, coords))  # (n_x, G)
        left = np.einsum("gv,vu->gu", ey, cmat)  # (G, n_x), no BLAS: same bits everywhere
        # Re(left @ ex) = Re(left) Re(ex) - Im(left) Im(ex): 2 n_x separable real terms
        add_separable_terms(screen, np.ascontiguousarray(np.hstack([left.real, -left.imag])),
                            np.ascontiguousarray(np.vstack([ex.real, ex.imag])))
    if tilt_tail:
        gx, gy = rng.standard_normal(2) * np.sqrt(spec.tail_variance)
        screen += gx * coords[None, :] + gy * coords[:, None]
    screen -= screen.mean()
    return screen
