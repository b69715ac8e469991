"""Influence functions of a deformable mirror of actuators on a square grid.

Pure geometry (no loop, no turbulence): actuators on a square grid of pitch ``p``
centred on the optical axis, each with a Gaussian influence function

    IF(x, y) = c ** (((x - x_a)**2 + (y - y_a)**2) / p**2)
             = exp(-((x - x_a)**2 + (y - y_a)**2) / (2 sigma**2)),
    sigma = p / sqrt(-2 ln c),

so that ``IF = 1`` on the actuator and ``IF = c`` (the *coupling*, or crosstalk) on its
nearest neighbour. This is the shape and the parametrisation of hcipy
(``make_gaussian_influence_functions``: ``sigma = spacing / sqrt(-2 ln crosstalk)``,
default crosstalk 0.15, "representative for Boston Micromachines DMs") and of OOPAO
(``DeformableMirror``: ``mechCoupling``, default 0.35). The default here is OOPAO's
**c = 0.35**, the coupling of the continuous-facesheet piezo-stack mirrors of 4-m
telescopes (the 30-35 % of the project's design notes; hcipy's 0.15 is a MEMS value).

Truncation and sparsity. The Gaussian is the product of two 1-D factors
``f(u) = c ** ((u / p)**2)``. Each factor is cut to zero where it falls below
``truncation`` (default 1e-3), i.e. for ``|u| > R = p sqrt(ln(truncation) / ln c)``
(2.56 pitches at ``c = 0.35``, 1.91 at 0.15). The support is the square
``|x - x_a|, |y - y_a| <= R``, so the truncated function is *still exactly separable*,
and the operator (pixels x actuators) is

* sparse: :attr:`InfluenceFunctions.matrix` (``scipy.sparse`` CSR, ``(2R/dx)**2``
  non-zeros per actuator), used to build Gram matrices, fits and K-L modes;
* separable: :meth:`InfluenceFunctions.surface` applies ``F_y C F_x^T`` with banded
  1-D factors (numba kernel), ``n_act n w + P w`` multiply-adds for ``P`` pixels and a
  band of ``w`` actuators per pixel: what a loop pays every frame (never a dense
  pixels x actuators product).

hcipy truncates the 2-D Gaussian at ``cutoff = 3`` pitches on a disc and subtracts the
value there; OOPAO keeps the full Gaussian. With ``truncation = 1e-3`` the dropped 1-D
tail is ``erfc(sqrt(ln 1000)) = 2.1e-4`` of the factor's integral on each side.

Valid actuators are chosen by illumination, as COMPASS's (and yao's) ``thresh`` does
(an actuator is kept when its response over the pupil is a large enough fraction of a
fully illuminated one's): the *illumination* of actuator ``a`` is
``sum over the pupil of IF_a / sum over the whole plane of IF_a``, and actuators with
illumination ``>= threshold`` (default **0.05**) are kept. The rim needs the actuators
just outside it. Measured on 20 Kolmogorov screens (64-pixel pupil, 16 actuators
across, the fitting error of ``tests/bases/test_influence.py``): with ``threshold``
0.25 the fitting error is 2.4x hcipy's DM of all 16 x 16 actuators at coupling 0.15
(1.12x at 0.35), with 0.05 it is 1.04x (1.04x) and the Gram matrix's condition
number stays ~1e4 (5.8e4 at 0.02).

Any plane: the pupil is any :class:`~modalinfo.bases.Pupil` (or
:class:`~modalinfo.bases.MaskedPupil`, e.g. the disc of a meta-pupil on a larger
altitude plane); pixel ``(i, j)`` has its centre at ``((j + 0.5 - N/2) dx,
(i + 0.5 - N/2) dx)``, ``dx = diameter / N``, ``x`` along columns.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import linalg, sparse

from modalinfo.bases import _influence_kernels
from modalinfo.bases.pupil import Pupil
from modalinfo.common.validation import as_float_array, check_int, check_memory, check_real

__all__ = ["InfluenceFunctions", "DEFAULT_COUPLING", "DEFAULT_TRUNCATION",
           "DEFAULT_THRESHOLD", "gaussian_factor"]

#: coupling at the nearest neighbour: OOPAO's default ``mechCoupling``
DEFAULT_COUPLING = 0.35
#: relative level of a 1-D factor at the edge of its support
DEFAULT_TRUNCATION = 1e-3
#: minimum illuminated fraction of an actuator's influence (COMPASS/yao ``thresh`` rule)
DEFAULT_THRESHOLD = 0.05


def support_radius(pitch: float, coupling: float, truncation: float) -> float:
    """Half-side ``R`` [m] of an influence function's square support.

    ``R = pitch sqrt(ln(truncation) / ln(coupling))``: the 1-D factor
    ``coupling ** ((u / pitch)**2)`` equals ``truncation`` at ``|u| = R``.
    """
    return pitch * math.sqrt(math.log(truncation) / math.log(coupling))


def gaussian_factor(coords, centres, pitch: float, coupling: float,
                    radius: float) -> np.ndarray:
    """1-D factor of the Gaussian influence functions, dense ``(n_coords, n_centres)``.

    ``f[i, a] = coupling ** (((coords[i] - centres[a]) / pitch)**2)`` where
    ``|coords[i] - centres[a]| <= radius``, else 0.

    Parameters
    ----------
    coords : (n,) array_like
        Pixel-centre coordinates [m].
    centres : (n_act,) array_like
        Actuator coordinates [m] along the same axis.
    pitch : float
        Actuator pitch [m].
    coupling : float
        Influence at the nearest neighbour, in (0, 1).
    radius : float
        Support half-width [m].
    """
    u = np.asarray(coords, dtype=np.float64)[:, None] - np.asarray(centres, np.float64)[None]
    out = np.exp(math.log(coupling) * (u / pitch) ** 2)
    out[np.abs(u) > radius] = 0.0
    return out


def _band(factor: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Banded form ``(first, values)`` of a 1-D factor (see ``separable_surface``)."""
    n, n_act = factor.shape
    nonzero = factor != 0.0
    any_ = nonzero.any(axis=1)
    lo = np.where(any_, np.argmax(nonzero, axis=1), 0)
    hi = np.where(any_, n_act - 1 - np.argmax(nonzero[:, ::-1], axis=1), 0)
    width = int(max(1, (hi - lo + 1)[any_].max() if any_.any() else 1))
    first = np.minimum(lo, n_act - width).astype(np.int64)
    cols = first[:, None] + np.arange(width)[None, :]
    values = np.ascontiguousarray(np.take_along_axis(factor, cols, axis=1))
    return np.ascontiguousarray(first), values


class InfluenceFunctions:
    """Gaussian influence functions of a square actuator grid, sampled on a pupil.

    Parameters
    ----------
    pupil : Pupil
        Where the surface is sampled (its ``mask`` pixels, row-major); ``MaskedPupil``
        for an arbitrary illuminated region (a meta-pupil disc on an altitude plane).
    n_actuators : int
        Actuators across the grid, ``>= 2``; the grid has ``n_actuators**2`` sites at
        ``(k - (n_actuators - 1) / 2) pitch``, ``k = 0 .. n_actuators - 1``, on each axis.
    pitch : float, optional
        Actuator pitch [m], ``> 0``; default ``pupil.diameter / (n_actuators - 1)``
        (Fried geometry: the outermost actuators on the rim of the grid's diameter).
    coupling : float
        Influence at the nearest neighbour, ``0 < coupling < 1`` (default 0.35, OOPAO).
    truncation : float
        Level of a 1-D factor at the edge of its support, ``0 < truncation < coupling``
        (default 1e-3).
    threshold : float
        Minimum illumination of a valid actuator, ``0 < threshold <= 1`` (default 0.05).

    Attributes
    ----------
    positions : (n_actuators**2, 2) float64
        ``(x, y)`` [m] of every grid site, row-major (site ``iy * n_actuators + ix``).
    illumination : (n_actuators**2,) float64
        Fraction of each site's influence on the pupil's pixels.
    valid : (n_actuators**2,) bool
        Sites kept (``illumination >= threshold``).
    n_valid : int
        Number of valid actuators (the command length).
    radius : float
        Support half-side ``R`` [m].
    """

    def __init__(self, pupil: Pupil, n_actuators: int, pitch: float | None = None, *,
                 coupling: float = DEFAULT_COUPLING, truncation: float = DEFAULT_TRUNCATION,
                 threshold: float = DEFAULT_THRESHOLD) -> None:
        if not isinstance(pupil, Pupil):
            raise TypeError(f"`pupil` must be a modalinfo.bases.Pupil; got {type(pupil).__name__}.")
        self.n_actuators = check_int(n_actuators, "n_actuators", minimum=2)
        # about five (n_actuators, n_actuators) float64 grids (positions, illumination)
        check_memory(40.0 * self.n_actuators**2, "n_actuators", self.n_actuators,
                     "its actuator grids")
        if pitch is None:
            pitch = pupil.diameter / (self.n_actuators - 1)
        self.pitch = check_real(pitch, "pitch", minimum=0.0, strict_min=True)
        self.coupling = check_real(coupling, "coupling", minimum=0.0, maximum=1.0,
                                   strict_min=True, strict_max=True)
        self.truncation = check_real(truncation, "truncation", minimum=0.0,
                                     maximum=self.coupling, strict_min=True, strict_max=True)
        self.threshold = check_real(threshold, "threshold", minimum=0.0, maximum=1.0,
                                    strict_min=True)
        self.pupil = pupil
        self.radius = support_radius(self.pitch, self.coupling, self.truncation)
        n = pupil.n_pixels
        dx = pupil.diameter / n
        self.pixel_scale = dx
        self.coords = (np.arange(n) + 0.5 - n / 2) * dx
        self.centres = (np.arange(self.n_actuators) - (self.n_actuators - 1) / 2) * self.pitch
        cy, cx = np.meshgrid(self.centres, self.centres, indexing="ij")
        self.positions = np.column_stack([cx.ravel(), cy.ravel()])
        # the 1-D factor on the pupil grid (x and y share it: square grids, same centre)
        self.factor = gaussian_factor(self.coords, self.centres, self.pitch, self.coupling,
                                      self.radius)
        mask = np.asarray(pupil.mask)
        inside = self.factor.T @ mask.astype(np.float64) @ self.factor  # (iy, ix)
        # whole-plane volume: the same factor summed over pixel centres extended past the
        # grid by the support (every pixel an influence function can reach)
        m = int(math.ceil(self.radius / dx)) + 1
        ext = (np.arange(-m, n + m) + 0.5 - n / 2) * dx
        total_1d = gaussian_factor(ext, self.centres, self.pitch, self.coupling,
                                   self.radius).sum(axis=0)
        total = np.outer(total_1d, total_1d)
        self.illumination = (inside / total).ravel()
        self.valid = self.illumination >= self.threshold
        if not self.valid.any():
            raise ValueError(
                f"`threshold` keeps no actuator: the best-illuminated one has "
                f"{self.illumination.max():.3g} of its influence on the pupil; got "
                f"threshold={self.threshold}.")
        self.valid_index = np.flatnonzero(self.valid).astype(np.int64)
        self.n_valid = int(self.valid_index.size)
        self.valid_positions = self.positions[self.valid]
        flat = np.flatnonzero(mask.ravel())
        self._rows = (flat // n).astype(np.int64)
        self._cols = (flat % n).astype(np.int64)
        self._first, self._values = _band(self.factor)
        # read-only: surface(), fit() and the DM-space K-L modes read these arrays at every
        # call, so a caller writing into ``valid_index`` or ``factor`` silently changed
        # every later surface (audit 10-state, row ret-influence)
        for arr in (self.coords, self.centres, self.positions, self.factor,
                    self.illumination, self.valid, self.valid_index, self.valid_positions,
                    self._rows, self._cols, self._first, self._values):
            arr.flags.writeable = False
        self._matrix = None
        self._gram = None
        self._gram_factor = None

    def __repr__(self) -> str:
        return (f"InfluenceFunctions(n_actuators={self.n_actuators}, pitch={self.pitch!r}, "
                f"coupling={self.coupling!r}, n_valid={self.n_valid}, pupil={self.pupil!r})")

    # ------------------------------------------------------------------ operators
    @property
    def matrix(self) -> sparse.csr_matrix:
        """Sparse operator ``(n_pupil_pixels, n_valid)`` [surface per unit stroke] (CSR)."""
        if self._matrix is None:
            f = sparse.csr_matrix(self.factor)
            full = sparse.kron(f, f, format="csr")  # rows iy*n + ix, columns ay*na + ax
            flat = np.flatnonzero(np.asarray(self.pupil.mask).ravel())
            mat = full[flat][:, self.valid_index].tocsr()
            mat.eliminate_zeros()
            mat.sort_indices()
            self._matrix = mat
        return self._matrix

    def surface(self, commands) -> np.ndarray:
        """Mirror surface on the pupil pixels for actuator strokes.

        Parameters
        ----------
        commands : array_like
            ``(n_valid,)`` strokes [surface units, e.g. rad of phase] of the valid
            actuators (order of :attr:`valid_index`), or ``(T, n_valid)``.

        Returns
        -------
        numpy.ndarray
            ``(n_pupil_pixels,)`` or ``(T, n_pupil_pixels)``: ``sum_a commands[a] IF_a``.
        """
        c = as_float_array(commands, "commands", ndim=(1, 2))
        if c.shape[-1] != self.n_valid:
            raise ValueError(f"`commands` must have last axis of length n_valid={self.n_valid}; "
                             f"got shape {c.shape}.")
        if c.ndim == 2:
            return np.stack([self._surface(row) for row in c])
        return self._surface(c)

    def _surface(self, c: np.ndarray) -> np.ndarray:
        """Separable banded product for one validated command vector."""
        # scratch arrays of this call: the kernel releases the GIL, and grids shared by
        # the object made threads calling surface() on one mirror mix each other's
        # commands (audit 10-state, row thr-influence-surface); the allocation is small
        # beside the product
        grid = np.zeros((self.n_actuators, self.n_actuators))
        grid.ravel()[self.valid_index] = c
        work = np.empty((self._first.shape[0], self.n_actuators))
        out = np.empty(self._rows.size)
        _influence_kernels.separable_surface(grid, self._first, self._values, self._rows,
                                             self._cols, work, out)
        return out

    def gram(self) -> np.ndarray:
        """DM metric: ``matrix.T @ matrix / n_pupil_pixels``, dense ``(n_valid, n_valid)``.

        The pupil-mean inner product of the influence functions (``ModalBasis.gram``'s
        convention).
        """
        if self._gram is None:
            m = self.matrix
            g = (m.T @ m).toarray() / m.shape[0]
            g = 0.5 * (g + g.T)
            g.flags.writeable = False
            self._gram = g
        return self._gram

    def fit(self, phase) -> np.ndarray:
        """Least-squares strokes of a phase on the pupil pixels (DM metric).

        Parameters
        ----------
        phase : array_like
            ``(n_pupil_pixels,)`` or ``(T, n_pupil_pixels)`` [rad].

        Returns
        -------
        numpy.ndarray
            ``(n_valid,)`` or ``(T, n_valid)`` strokes minimising the pupil residual.
        """
        ph = as_float_array(phase, "phase", ndim=(1, 2))
        if ph.shape[-1] != self.pupil.n_valid:
            raise ValueError(f"`phase` must have last axis of length n_valid="
                             f"{self.pupil.n_valid} (pupil pixels); got shape {ph.shape}.")
        if self._gram_factor is None:
            self._gram_factor = linalg.cho_factor(self.gram(), lower=True)
        rhs = (self.matrix.T @ ph.T) / self.pupil.n_valid
        return np.ascontiguousarray(linalg.cho_solve(self._gram_factor, rhs).T)

    def to_image(self, values) -> np.ndarray:
        """Scatter pupil-pixel values into ``(..., N, N)`` images (NaN outside)."""
        return self.pupil.to_image(values)
