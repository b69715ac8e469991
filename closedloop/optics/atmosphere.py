"""Frozen-flow atmosphere: layers of Kolmogorov / von Karman phase moving with the wind.

Each :class:`AtmosphericLayer` owns one square phase screen drawn once at construction
by :func:`closedloop.optics.phase_screen.fft_phase_screen` (FFT synthesis with the aliased
spectrum, split cells next to DC, Lane et al. 1992 subharmonics and a tilt tail; see
that module for the method and the sources) and returns, at any time ``t``, the phase
on its output grid (the layer's meta-pupil) translated by the wind::

    phase(x, y; t) = screen(x - v_x t, y - v_y t)      [rad at the wavelength of r0]

so the pattern moves *with* the wind. Output pixel ``(i, j)`` sits at
``x = (j - (n - 1) / 2) dx``, ``y = (i - (n - 1) / 2) dx`` (x along columns, axis 1;
y along rows, axis 0), which is also the pixel grid of
``modalinfo.bases.Pupil(n, diameter=n dx)``.

Screen size and what happens after ``duration_hint``
----------------------------------------------------
The screen is square, ``G = max(4 n, n + 3 + max(|v_x|, |v_y|) T / dx)`` pixels rounded up
to an FFT-friendly size, with ``T = duration_hint``: ``4 n`` keeps the structure function
close to theory up to lags of ``n`` pixels (the screen's expected structure function is
0.999 of the theory up to ``G / 16`` and 0.993 / 0.992 / 0.983 at ``G / 4`` for
L0 = inf / 1e4 m / 25 m, see :func:`closedloop.optics.phase_screen.expected_structure_function`),
and the second term lets the
output grid travel ``|v| T`` without ever reading a pixel twice. The start position is
chosen so that during ``[0, T]`` the grid never crosses the screen's edge. ``G`` is capped
at ``max_screen_pixels`` (4096 by default: 128 MB per layer, ~0.5 GB transient while
drawing). Beyond the covered time (or if the cap cut the screen short, which is warned
about at construction) the screen wraps periodically: the FFT part of the screen is
periodic and continuous across the edge, its low-frequency part (split cells,
subharmonics, tilt tail) is not, so once per wrap a step in the low orders crosses the
grid and the high-frequency pattern repeats. ``covered_time`` says how long a layer runs
before that. For example 70 m/s for 1 s at 6.25 cm pixels is 1120 pixels of travel: a
1296-pixel screen (13 MB) for a 160-pixel grid; a 10 s run needs 11360 pixels and, with
the default cap, wraps twice (or pass a larger ``max_screen_pixels``).

Sub-pixel shifts
----------------
The shift ``v t / dx`` is the same for every output pixel, so the resampling is a
separable filter applied to the screen (numba kernel
:func:`closedloop.optics._atmosphere_kernels.shift_separable`): Keys cubic convolution (4 taps,
``a = -1/2``; Keys 1981, IEEE TASSP 29, 1153; the default) or bilinear (2 taps). At an
integer shift both reduce to an exact copy. Interpolation smooths the phase at the
pixel scale. Predicted from the Kolmogorov structure function of the point samples and
measured by the tests (``tests/closedloop/test_atmosphere.py``), the structure function
along the shift at a lag of 1 / 2 / 4 pixels is multiplied by

- bilinear:   0.794 / 0.913 / 0.968 at a half-pixel shift, 0.862 / 0.942 / 0.979 on
  average over uniformly distributed fractions;
- Keys cubic: 0.870 / 0.968 / 0.991 at a half-pixel shift, 0.933 / 0.983 / 0.995 on
  average

(bilinear at half a pixel: the difference of two half-pixel averages is half the 2-pixel
difference, ``2^(5/3) / 4 = 0.794``). In spectral terms a half-pixel bilinear shift keeps
``cos^2(pi f dx)`` of the power, half of it at a 4-pixel period, where Keys keeps 78%:
that is power the DMs cannot fit anyway, so it would bias the fitting error low; hence
cubic by default, for ~15 us more per 160 x 160 layer.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

import numpy as np
from scipy import fft as sfft

from closedloop.optics._atmosphere_kernels import shift_separable
from closedloop.optics.phase_screen import fft_phase_screen
from modalinfo.common.quiet import warn
from modalinfo.common.validation import (
    as_float_array,
    check_choice,
    check_int,
    check_real,
    check_rng,
)

__all__ = ["AtmosphericLayer", "Atmosphere", "screen_size"]

_INTERPOLATIONS = ("bilinear", "cubic")


def screen_size(n_pixels: int, pixel_scale: float, velocity, duration: float,
                max_screen_pixels: int = 4096) -> int:
    """Side ``G`` [pixels] of the square screen of a layer (see the module docstring).

    Parameters
    ----------
    n_pixels : int
        Output grid side ``n``.
    pixel_scale : float
        Pixel size [m].
    velocity : (2,) array_like
        Wind ``(v_x, v_y)`` [m/s].
    duration : float
        Time [s] the grid must travel without wrapping.
    max_screen_pixels : int
        Cap on ``G``.

    Returns
    -------
    int
        ``min(cap, next_fast_len(max(4 n, n + 3 + ceil(max|v| T / dx))))``.
    """
    travel = max(abs(float(velocity[0])), abs(float(velocity[1]))) * duration / pixel_scale
    need = max(4 * n_pixels, n_pixels + 3 + math.ceil(travel - 1e-9))
    return int(min(max_screen_pixels, sfft.next_fast_len(need, real=False)))


def _keys_weights(frac: float) -> np.ndarray:
    """Keys (1981) cubic-convolution weights (a = -1/2) of taps at -1, 0, 1, 2."""
    t = frac
    t2 = t * t
    t3 = t2 * t
    return np.array([
        -0.5 * t3 + t2 - 0.5 * t,
        1.5 * t3 - 2.5 * t2 + 1.0,
        -1.5 * t3 + 2.0 * t2 + 0.5 * t,
        0.5 * t3 - 0.5 * t2,
    ])


class AtmosphericLayer:
    """One frozen-flow turbulent layer seen on a square output grid.

    Parameters
    ----------
    n_pixels : int
        Output grid side ``n`` (``>= 2``); the grid is centred on the optical axis at
        this layer's altitude (the layer's meta-pupil).
    pixel_scale : float
        Pixel size ``dx`` [m], ``> 0``.
    r0 : float
        Fried parameter of this layer [m], ``> 0``, at the wavelength of the phase.
    velocity : (2,) array_like
        Wind ``(v_x, v_y)`` [m/s]; x along columns (axis 1), y along rows (axis 0).
    outer_scale : float
        Von Karman outer scale ``L0`` [m], ``> 0``; ``inf`` for Kolmogorov.
    altitude : float
        Altitude [m], ``>= 0``; stored for the simulator, it does not change the screen.
    duration_hint : float
        Run length [s], ``> 0``, that the screen must cover without wrapping.
    seed : None, int or numpy.random.Generator
        Randomness of the screen; the same seed gives the same bits.
    interpolation : {"cubic", "bilinear"}
        Sub-pixel resampling filter: Keys cubic convolution (default) or bilinear.
    max_screen_pixels : int, optional
        Cap on the screen side ``G`` (memory: ``8 G^2`` bytes), ``>= n + 8``; default
        ``max(4096, 4 n)``.

    Attributes
    ----------
    screen : numpy.ndarray
        ``(G, G)`` read-only phase screen [rad].
    covered_time : float
        Time [s] during which the grid travels without wrapping (``inf`` without wind).
    t : float
        Current time [s].

    Notes
    -----
    :meth:`phase` at time ``t`` samples the screen at row ``row_start + i - v_y t / dx``
    and column ``col_start + j - v_x t / dx`` (modulo ``G``) with the chosen filter;
    ``row_start`` and ``col_start`` are attributes. It uses a scratch buffer of the
    layer: do not call it on the same layer from two threads at once.
    """

    def __init__(
        self,
        n_pixels: int,
        pixel_scale: float,
        r0: float,
        velocity=(0.0, 0.0),
        outer_scale: float = np.inf,
        altitude: float = 0.0,
        duration_hint: float = 1.0,
        seed=None,
        *,
        interpolation: str = "cubic",
        max_screen_pixels: int | None = None,
    ) -> None:
        self.n_pixels = check_int(n_pixels, "n_pixels", minimum=2)
        self.pixel_scale = check_real(pixel_scale, "pixel_scale", minimum=0.0, strict_min=True)
        self.r0 = check_real(r0, "r0", minimum=0.0, strict_min=True)
        vel = as_float_array(velocity, "velocity", shape=(2,))
        self.velocity = (float(vel[0]), float(vel[1]))
        self.outer_scale = check_real(outer_scale, "outer_scale", minimum=0.0, strict_min=True,
                                      allow_inf=True)
        self.altitude = check_real(altitude, "altitude", minimum=0.0)
        self.duration_hint = check_real(duration_hint, "duration_hint", minimum=0.0,
                                        strict_min=True)
        self.interpolation = check_choice(interpolation, "interpolation", _INTERPOLATIONS)
        if max_screen_pixels is None:
            max_screen_pixels = max(4096, 4 * self.n_pixels)
        cap = check_int(max_screen_pixels, "max_screen_pixels", minimum=self.n_pixels + 8)
        rng = check_rng(seed)

        g = screen_size(self.n_pixels, self.pixel_scale, self.velocity, self.duration_hint, cap)
        screen = fft_phase_screen(g, self.pixel_scale, self.r0, outer_scale=self.outer_scale,
                                  seed=rng)
        screen.flags.writeable = False
        self.screen = screen
        n = self.n_pixels
        vx, vy = self.velocity
        # start at the edge the wind moves away from, so [0, covered_time] never wraps
        # (one spare pixel on each side for the cubic filter's outer taps)
        self.col_start = g - n - 2 if vx > 0 else 1
        self.row_start = g - n - 2 if vy > 0 else 1
        vmax = max(abs(vx), abs(vy))
        self.covered_time = math.inf if vmax == 0 else (g - n - 3) * self.pixel_scale / vmax
        if self.covered_time < self.duration_hint:
            warn(
                f"AtmosphericLayer: the {g}-pixel screen (max_screen_pixels={cap}) covers "
                f"{self.covered_time:.3g} s of wind at {vmax:g} m/s, less than "
                f"duration_hint={self.duration_hint:g} s; the screen wraps after that "
                "(periodic, with a step in the low orders at each wrap that crosses the "
                "pupil; with an infinite outer scale the tip/tilt and focus variance after "
                "the first wrap were 50 and 80 times the turbulence's in adversarial round "
                f"23): statistics are right up to {self.covered_time:.3g} s only; give a "
                "finite outer_scale, a shorter duration or a larger max_screen_pixels.",
                RuntimeWarning,
                stacklevel=2,
            )
        taps = 2 if self.interpolation == "bilinear" else 4
        self._taps = taps
        self._work = np.empty((taps, n))
        self._t = 0.0

    # -- clock -----------------------------------------------------------------------
    @property
    def t(self) -> float:
        """Current time [s]."""
        return self._t

    @t.setter
    def t(self, value: float) -> None:
        self.evolve_until(value)

    @property
    def screen_pixels(self) -> int:
        """Screen side ``G`` [pixels]."""
        return self.screen.shape[0]

    def reset(self) -> None:
        """Go back to ``t = 0`` (the same screen: the same phase as after construction)."""
        self._t = 0.0

    def evolve_until(self, t: float) -> None:
        """Move the layer to time ``t`` [s] (``>= 0``; frozen flow, any order of calls)."""
        self._t = check_real(t, "t", minimum=0.0)

    # -- sampling --------------------------------------------------------------------
    def _offsets(self, start: int, shift_pixels: float) -> tuple[int, float]:
        """Integer base (mod G) and fraction of the sampling position ``start - shift``."""
        pos = start - shift_pixels
        base = math.floor(pos)
        return base % self.screen.shape[0], pos - base

    def phase(self, out: np.ndarray | None = None) -> np.ndarray:
        """Phase [rad] on the output grid at the current time.

        Parameters
        ----------
        out : numpy.ndarray, optional
            ``(n, n)`` float64 C-contiguous writeable array to write into.

        Returns
        -------
        numpy.ndarray
            ``(n, n)`` phase, ``out`` if given.
        """
        n = self.n_pixels
        if out is None:
            out = np.empty((n, n))
        elif not isinstance(out, np.ndarray):
            raise TypeError(f"`out` must be a numpy.ndarray; got {type(out).__name__}.")
        elif (out.shape != (n, n) or out.dtype != np.float64 or not out.flags.c_contiguous
              or not out.flags.writeable):
            raise ValueError(
                f"`out` must be a writeable C-contiguous float64 array of shape ({n}, {n}); "
                f"got shape {out.shape}, dtype {out.dtype}, "
                f"C-contiguous={out.flags.c_contiguous}, writeable={out.flags.writeable}."
            )
        return self._phase_into(out)

    def _phase_into(self, out: np.ndarray) -> np.ndarray:
        """:meth:`phase` into a checked ``out`` (the simulator's hot loop: no validation)."""
        vx, vy = self.velocity
        row0, fy = self._offsets(self.row_start, vy * self._t / self.pixel_scale)
        col0, fx = self._offsets(self.col_start, vx * self._t / self.pixel_scale)
        if self._taps == 2:
            wy = np.array([1.0 - fy, fy])
            wx = np.array([1.0 - fx, fx])
        else:
            g = self.screen.shape[0]
            wy, wx = _keys_weights(fy), _keys_weights(fx)
            row0, col0 = (row0 - 1) % g, (col0 - 1) % g
        shift_separable(self.screen, row0, col0, wy, wx, self._work, out)
        return out

    def __repr__(self) -> str:
        return (f"AtmosphericLayer(n_pixels={self.n_pixels}, pixel_scale={self.pixel_scale:g}, "
                f"r0={self.r0:g}, velocity={self.velocity}, outer_scale={self.outer_scale:g}, "
                f"altitude={self.altitude:g}, screen={self.screen_pixels}^2)")


class Atmosphere:
    """Layers that share one clock.

    Parameters
    ----------
    layers : iterable of AtmosphericLayer
        At least one layer.

    Attributes
    ----------
    layers : tuple of AtmosphericLayer
    """

    def __init__(self, layers: Iterable[AtmosphericLayer]) -> None:
        if isinstance(layers, AtmosphericLayer):
            layers = [layers]
        try:
            layers = tuple(layers)
        except TypeError as exc:
            raise TypeError(
                f"`layers` must be an iterable of AtmosphericLayer; got {type(layers).__name__}."
            ) from exc
        if not layers:
            raise ValueError("`layers` must hold at least one AtmosphericLayer; got none.")
        for k, layer in enumerate(layers):
            if not isinstance(layer, AtmosphericLayer):
                raise TypeError(
                    f"`layers[{k}]` must be an AtmosphericLayer; got {type(layer).__name__}."
                )
        self.layers = layers
        self._t = 0.0
        for layer in layers:
            layer.evolve_until(0.0)

    @property
    def t(self) -> float:
        """Current time [s]."""
        return self._t

    @t.setter
    def t(self, value: float) -> None:
        self.evolve_until(value)

    @property
    def covered_time(self) -> float:
        """Time [s] before the first layer's screen wraps (``inf`` without wind)."""
        return min(layer.covered_time for layer in self.layers)

    def reset(self) -> None:
        """Every layer back to ``t = 0``."""
        self._t = 0.0
        for layer in self.layers:
            layer.reset()

    def evolve_until(self, t: float) -> None:
        """Move every layer to time ``t`` [s]."""
        t = check_real(t, "t", minimum=0.0)
        for layer in self.layers:
            layer._t = t  # checked once above, not once per layer
        self._t = t

    def forward(self, out: np.ndarray, layers: Sequence[int],
                work: np.ndarray | None = None) -> np.ndarray:
        """Sum of the phases [rad] of ``layers`` (indices) at the current time, into ``out``.

        The loop's hot path: ``out`` (and ``work``, needed for more than one layer) must be
        writeable C-contiguous float64 arrays of the layers' ``(n, n)`` grid, which every
        layer of the sum shares; nothing is checked here (:meth:`AtmosphericLayer.phase`
        checks). The first layer is written into ``out``, the next ones into ``work`` and
        added. Returns ``out``.
        """
        self.layers[layers[0]]._phase_into(out)
        for li in layers[1:]:
            self.layers[li]._phase_into(work)
            out += work
        return out

    def __len__(self) -> int:
        return len(self.layers)

    def __iter__(self):
        return iter(self.layers)

    def __getitem__(self, index):
        return self.layers[index]

    def __repr__(self) -> str:
        return f"Atmosphere({len(self.layers)} layers, t={self._t:g} s)"
